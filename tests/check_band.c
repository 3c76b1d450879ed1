/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The banded Newton: on a chain of N quartic oscillators with quartic nearest-neighbour
 * springs, mu = (x_0, p_0, x_1, p_1, ...), the map's Jacobian has bandwidth 3 (p_i depends on
 * x_{i-1}, x_i, x_{i+1}); the banded solve must give the dense solve's steps, and keep H. */
#include <math.h>
#include <string.h>

#include "testmodels.h"

#define N 12

static double force(const double *mu, size_t i) {
  double x = mu[2 * i], f = -x * x * x;
  if (i + 1 < N) f += pow(mu[2 * i + 2] - x, 3);
  if (i > 0) f -= pow(x - mu[2 * i - 2], 3);
  return f;
}

static int q0(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  for (size_t i = 0; i < N; i++) out[2 * i] = mu[2 * i + 1], out[2 * i + 1] = force(mu, i);
  return 0;
}

/* one constraint with q_1 = 0: the stabilizer plays no part here */
static int Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                   void *params) {
  (void)t, (void)xi, (void)mu, (void)params;
  memset(Qxi, 0, 2 * N * sizeof *Qxi);
  qnorm2[0] = 0.0;
  return 0;
}

static int H(double t, const double *mu, double *out, void *params) {
  double h = 0.0;
  (void)t, (void)params;
  for (size_t i = 0; i < N; i++) {
    h += 0.5 * mu[2 * i + 1] * mu[2 * i + 1] + 0.25 * pow(mu[2 * i], 4);
    if (i + 1 < N) h += 0.25 * pow(mu[2 * i + 2] - mu[2 * i], 4);
  }
  *out = h;
  return 0;
}

static int grad_H(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  for (size_t i = 0; i < N; i++) out[2 * i] = -force(mu, i), out[2 * i + 1] = mu[2 * i + 1];
  return 0;
}

static int S(double t, const double *mu, double *out, void *params) {
  (void)t, (void)mu, (void)params;
  memset(out, 0, 4 * N * N * sizeof *out);
  for (size_t i = 0; i < N; i++) {
    out[(2 * i) * 2 * N + 2 * i + 1] = 1.0;
    out[(2 * i + 1) * 2 * N + 2 * i] = -1.0;
  }
  return 0;
}

static void run(const sdae_map_type *map, size_t bandwidth, double *mu, int steps) {
  sdae_model m = {
      .n_xi = 1, .n_mu = 2 * N, .q0 = q0, .Q_apply = Q_apply, .H = H, .grad_H = grad_H, .S = S};
  sdae_options o;
  sdae_stepper *s;
  double xi[1] = {0.0};
  sdae_options_default(&o);
  o.map = map, o.bandwidth = bandwidth;
  for (size_t i = 0; i < N; i++) mu[2 * i] = 0.5 * sin(1.0 + i), mu[2 * i + 1] = 0.1 * cos(2.0 * i);
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, 0.05, (size_t)steps, 1, xi, mu, NULL, NULL, NULL),
                   SDAE_OK);
  if (steps > 0) ck_assert_uint_gt(sdae_stepper_stats(s)->newton_iters_total, (unsigned long)steps);
  sdae_stepper_free(s);
}

static void banded_equals_dense(const sdae_map_type *map) {
  double dense[2 * N], band[2 * N];
  run(map, 0, dense, 200);
  run(map, 3, band, 200);
  for (size_t i = 0; i < 2 * N; i++) ck_assert_double_le(fabs(dense[i] - band[i]), 1e-12);
}

START_TEST(midpoint_banded_equals_dense) { banded_equals_dense(sdae_map_midpoint); }
END_TEST

START_TEST(dgrad_banded_equals_dense) { banded_equals_dense(sdae_map_dgrad); }
END_TEST

START_TEST(dg4_banded_keeps_H) {
  double mu0[2 * N], mu[2 * N], H0, H1;
  run(sdae_map_dg4, 3, mu0, 0);
  run(sdae_map_dg4, 3, mu, 400);
  H(0.0, mu0, &H0, NULL);
  H(0.0, mu, &H1, NULL);
  ck_assert_double_le(fabs(H1 - H0), 1e-14 * H0);
}
END_TEST

int main(void) {
  Suite *s = suite_create("band");
  ADD_CASE(s, midpoint_banded_equals_dense);
  ADD_CASE(s, dgrad_banded_equals_dense);
  ADD_CASE(s, dg4_banded_keeps_H);
  return run_suite(s);
}
