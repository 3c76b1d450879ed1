/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A parent project's program that links stabdae built inside its own tree (add_subdirectory or
 * FetchContent, tests/subproject/CMakeLists.txt), written only against the public API.
 *
 * The model has two constraint coordinates and one coordinate of the constrained motion, with
 * a constant Q = [c1 c2]:
 *
 *     xi_i' = k_i xi_i,  k_i = -(delta^2/2) c_i^2 - epsilon  (eq. 6: ||q_i||^2 = c_i^2),
 *     mu'   = a mu + c1 xi1 + c2 xi2.
 *
 * Scheme 15 with the euler map gives xi_i+ = xi_i / (1 - T k_i) and
 * mu+ = (1 + T a) mu + T (c1 xi1 + c2 xi2), whose closed forms after n steps are
 *
 *     xi_i,n = xi_i,0 / (1 - T k_i)^n,
 *     mu_n   = r^n mu_0 + T sum_i c_i xi_i,0 (r^n - s_i^n) / (r - s_i),
 *     s_i = 1 / (1 - T k_i),  r = 1 + T a.
 *
 * The program checks both, that each constraint coordinate has its own gain, and that
 * sdae_version() is the version of the headers it was compiled with. Exit status 0 when
 * everything holds. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <stabdae/stabdae.h>

#ifndef SUBPROJECT_HOW
#define SUBPROJECT_HOW "?"
#endif

typedef struct linear2 {
  double a, c[2];
} linear2;

static int q0(double t, const double *mu, double *out, void *params) {
  const linear2 *p = params;
  (void)t;
  out[0] = p->a * mu[0];
  return 0;
}

/* Q is 1 x 2, row-major: column i is q_i = c_i */
static int Q(double t, const double *xi, const double *mu, double *out, void *params) {
  const linear2 *p = params;
  (void)t, (void)xi, (void)mu;
  out[0] = p->c[0];
  out[1] = p->c[1];
  return 0;
}

static double rel_err(double x, double ref) { return fabs(x - ref) / fabs(ref); }

int main(void) {
  linear2 p = {-0.5, {2.0, 0.5}};
  sdae_model model = {.n_xi = 2, .n_mu = 1, .q0 = q0, .Q = Q, .params = &p};
  sdae_options opt;
  sdae_stepper *s;
  const double T = 0.05, xi0[2] = {0.3, -0.2}, mu0 = 1.0;
  const int n = 80;
  double xi[2] = {xi0[0], xi0[1]}, mu = mu0;
  int rc, ok = 1;

  sdae_options_default(&opt); /* scheme 15, euler map */
  opt.scheme = SDAE_SCHEME_SEMI_IMPLICIT;
  opt.map = sdae_map_euler;
  opt.delta = 1.5;
  opt.epsilon = 0.25;
  if ((rc = sdae_stepper_alloc(&s, &model, &opt)) != SDAE_OK) {
    fprintf(stderr, "subproject (%s): alloc: %s\n", SUBPROJECT_HOW, sdae_strerror(rc));
    return 1;
  }
  for (int i = 0; i < n && rc == SDAE_OK; i++) rc = sdae_step(s, i * T, T, xi, &mu);
  sdae_stepper_free(s);
  if (rc != SDAE_OK) {
    fprintf(stderr, "subproject (%s): step: %s\n", SUBPROJECT_HOW, sdae_strerror(rc));
    return 1;
  }

  double r = 1.0 + T * p.a, mu_ref = pow(r, n) * mu0;
  for (int i = 0; i < 2; i++) {
    double k = -0.5 * opt.delta * opt.delta * p.c[i] * p.c[i] - opt.epsilon; /* eq. 6 */
    double si = 1.0 / (1.0 - T * k);
    double xi_ref = xi0[i] / pow(1.0 - T * k, n);
    mu_ref += T * p.c[i] * xi0[i] * (pow(r, n) - pow(si, n)) / (r - si);
    printf("subproject (%s): xi%d_%d = %.17g, closed form %.17g (k%d = %g)\n", SUBPROJECT_HOW,
           i + 1, n, xi[i], xi_ref, i + 1, k);
    ok = ok && rel_err(xi[i], xi_ref) <= 1e-13;
  }
  printf("subproject (%s): mu_%d = %.17g, closed form %.17g\n", SUBPROJECT_HOW, n, mu, mu_ref);
  ok = ok && rel_err(mu, mu_ref) <= 1e-13;

  printf("subproject (%s): sdae_version() = %s, headers %s\n", SUBPROJECT_HOW, sdae_version(),
         SDAE_VERSION_STRING);
  ok = ok && strcmp(sdae_version(), SDAE_VERSION_STRING) == 0;

  if (!ok) fprintf(stderr, "subproject (%s): FAILED\n", SUBPROJECT_HOW);
  return ok ? 0 : 1;
}
