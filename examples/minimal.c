/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The smallest complete use of stabdae, written only against the public API: the paper's
 * nonlinear oscillator (Section IV, m = 1, k = 2, d = 0.03) from its off-manifold start
 * X = 0.1, Y = 0.6, integrated for 5 s with scheme 15 and the midpoint map. It prints the
 * constraint violation Y = xi1 as it is driven to zero. The full command-line program with
 * every option is examples/oscillator.c. */
#include <stdio.h>

#include <stabdae/stabdae.h>

typedef struct {
  double k, d;
} oscillator;

/* constrained motion (eq. 9): X'' = -k X^3 - d X' in mu = (X + Y, Y + X') */
static int q0(double t, const double *mu, double *out, void *params) {
  const oscillator *p = params;
  (void)t;
  out[0] = mu[1];
  out[1] = -p->k * mu[0] * mu[0] * mu[0] - p->d * mu[1];
  return 0;
}

/* Q(xi, mu), row-major 2 x 2, from eq. 22 (the corrected form: erratum 1 of docs/paper.md) */
static int Q(double t, const double *xi, const double *mu, double *out, void *params) {
  const oscillator *p = params;
  (void)t;
  out[0] = -1.0;
  out[1] = 1.0;
  out[2] = p->k * (3 * mu[0] * mu[0] - 3 * mu[0] * xi[0] + xi[0] * xi[0]) + p->d;
  out[3] = 1.0;
  return 0;
}

static int print_row(size_t step, double t, const double *xi, const double *mu, void *data) {
  (void)step, (void)data;
  printf("%6.2f  %+.6e  %+.6e  %+.6e\n", t, xi[0], mu[0] - xi[0], mu[1] - xi[0]);
  return 0;
}

int main(void) {
  oscillator p = {2.0, 0.03};
  sdae_model model = {.n_xi = 2, .n_mu = 2, .q0 = q0, .Q = Q, .params = &p};
  sdae_options opt;
  sdae_stepper *s;
  double X = 0.1, Y = 0.6, Xdot = 0.0, Ydot = 0.0;
  double xi[2] = {Y, Ydot}, mu[2] = {X + Y, Y + Xdot}; /* eq. 21 */
  int rc;

  sdae_options_default(&opt);
  opt.scheme = SDAE_SCHEME_SEMI_IMPLICIT; /* eq. 15: xi -> 0 for any T (Theorem 4) */
  opt.map = sdae_map_midpoint;
  opt.delta = 2.0;
  opt.epsilon = 1.0;
  if ((rc = sdae_stepper_alloc(&s, &model, &opt)) != SDAE_OK) {
    fprintf(stderr, "minimal: %s\n", sdae_strerror(rc));
    return 1;
  }
  printf("     t   Y (= xi1)      X              Xdot\n");
  rc = sdae_integrate(s, 0.0, 1e-3, 5000, 500, xi, mu, print_row, NULL, NULL);
  sdae_stepper_free(s);
  if (rc != SDAE_OK) {
    fprintf(stderr, "minimal: %s\n", sdae_strerror(rc));
    return 1;
  }
  return 0;
}
