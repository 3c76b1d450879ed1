/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A user's program against the installed stabdae: a linear model with one constraint
 * coordinate and one coordinate of the constrained motion,
 *
 *     xi' = k xi,  k = -(delta^2/2) c^2 - epsilon,     mu' = a mu + c xi,
 *
 * stepped with scheme 15 and the euler map. Then xi+ = xi / (1 - T k) (eq. 15) and
 * mu+ = (1 + T a) mu + T c xi, whose closed forms after n steps are
 *
 *     xi_n = s^n xi_0,   mu_n = r^n mu_0 + T c xi_0 (r^n - s^n) / (r - s),
 *     s = 1 / (1 - T k),  r = 1 + T a;
 *
 * the program checks both, and that a bad step size is refused with the state untouched; and it
 * sizes a mechanism with no callbacks (0), which links the mechanical front-end, and with it,
 * in a static link, SuiteSparse's LDL and AMD. Exit status 0 when everything holds. */
#include <math.h>
#include <stdio.h>

#include <stabdae/mbs.h>
#include <stabdae/stabdae.h>

#ifndef STABDAE_VIA
#define STABDAE_VIA "?"
#endif

typedef struct linear {
  double a, c;
} linear;

static int q0(double t, const double *mu, double *out, void *params) {
  const linear *p = params;
  (void)t;
  out[0] = p->a * mu[0];
  return 0;
}

static int Q(double t, const double *xi, const double *mu, double *out, void *params) {
  const linear *p = params;
  (void)t, (void)xi, (void)mu;
  out[0] = p->c;
  return 0;
}

static int fail(const char *what, int rc) {
  fprintf(stderr, "consumer (%s): %s: %s\n", STABDAE_VIA, what, sdae_strerror(rc));
  return 1;
}

static double rel_err(double x, double ref) { return fabs(x - ref) / fabs(ref); }

int main(void) {
  linear p = {-0.5, 2.0};
  sdae_model model = {.n_xi = 1, .n_mu = 1, .q0 = q0, .Q = Q, .params = &p};
  sdae_options opt;
  sdae_stepper *s;
  const double T = 0.1, xi0 = 0.3, mu0 = 1.0;
  const int n = 50;
  double xi = xi0, mu = mu0;
  int rc;

  sdae_options_default(&opt); /* scheme 15, euler map, delta = epsilon = 1 */
  opt.delta = 1.5;
  opt.epsilon = 0.25;
  if ((rc = sdae_stepper_alloc(&s, &model, &opt)) != SDAE_OK) return fail("alloc", rc);
  for (int i = 0; i < n; i++)
    if ((rc = sdae_step(s, i * T, T, &xi, &mu)) != SDAE_OK) return fail("step", rc);

  double k = -0.5 * opt.delta * opt.delta * p.c * p.c - opt.epsilon; /* eq. 6 */
  double sf = 1.0 / (1.0 - T * k), r = 1.0 + T * p.a;
  double xi_ref = pow(sf, n) * xi0;
  double mu_ref = pow(r, n) * mu0 + T * p.c * xi0 * (pow(r, n) - pow(sf, n)) / (r - sf);
  int ok = rel_err(xi, xi_ref) <= 1e-13 && rel_err(mu, mu_ref) <= 1e-13;
  printf("consumer (%s, stabdae %d.%d.%d): xi_%d = %.17g (closed form %.17g), "
         "mu_%d = %.17g (closed form %.17g)\n",
         STABDAE_VIA, SDAE_VERSION_MAJOR, SDAE_VERSION_MINOR, SDAE_VERSION_PATCH, n, xi, xi_ref, n,
         mu, mu_ref);

  double xi_before = xi, mu_before = mu;
  rc = sdae_step(s, n * T, -T, &xi, &mu);
  ok = ok && rc == SDAE_ERR_STEP && xi == xi_before && mu == mu_before;
  printf("consumer (%s): T = %g refused: %s\n", STABDAE_VIA, -T, sdae_strerror(rc));
  const sdae_mbs empty = {0};
  ok = ok && sdae_mbs_stepper_size(&empty, &opt) == 0;
  sdae_stepper_free(s);
  if (!ok) fprintf(stderr, "consumer (%s): FAILED\n", STABDAE_VIA);
  return ok ? 0 : 1;
}
