/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The chain model: coordinates, Q_apply against the DAE (normal form), the column norms of Q,
 * the banded Jacobian, the energy structure, one mass = the oscillator, and the constraints
 * restored from a random start. */
#include <check.h>
#include <math.h>
#include <stdlib.h>

#include "chain_model.h"
#include "oscillator_model.h"
#include "test_util.h"

#define NMAX 6

static chain_params params(size_t N) { return (chain_params){N, 2.0, 1.5, 0.03, 1.3, 9.81, NULL}; }

static void random_state(gsl_rng *r, size_t N, double *x) {
  for (size_t i = 0; i < 4 * N; i++) x[i] = tu_flat(r, -1.0, 1.0);
}

static void phi_z(const double *x, double *z, const void *ctx) {
  const chain_params *p = ctx;
  chain_to_coords(p, x, z, z + 2 * p->N);
}

START_TEST(test_coordinates_invert) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  chain_params p = params(NMAX);
  double x[4 * NMAX], xi[2 * NMAX], mu[2 * NMAX], y[4 * NMAX];
  random_state(r, NMAX, x);
  chain_to_coords(&p, x, xi, mu);
  chain_from_coords(&p, xi, mu, y);
  for (int i = 0; i < 4 * NMAX; i++) ck_assert_double_eq_tol(y[i], x[i], 1e-15);
  gsl_rng_free(r);
}
END_TEST

/* d/dt mu(x) along f + g lambda equals q0(mu) + Q(xi, mu) xi, for any lambda; xi_{i,1}' =
 * xi_{i,2}. Phi is linear, so the central difference is exact up to rounding. */
START_TEST(test_normal_form) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  for (size_t N = 1; N <= NMAX; N++) {
    chain_params p = params(N);
    sdae_model m;
    ck_assert_int_eq(chain_model(&m, &p), 0);
    ck_assert(m.Q == NULL); /* the chain is given through Q_apply */
    for (int n = 0; n < 30; n++) {
      double x[4 * NMAX], lambda[NMAX], v[4 * NMAX], dz[4 * NMAX];
      double xi[2 * NMAX], mu[2 * NMAX], q0[2 * NMAX], Qxi[2 * NMAX], qn[2 * NMAX];
      random_state(r, N, x);
      for (size_t i = 0; i < N; i++) lambda[i] = tu_flat(r, -20, 20);
      chain_dae_rhs(&p, x, lambda, v);
      tu_directional(phi_z, &p, x, v, 4 * N, 4 * N, 1e-4, dz);
      chain_to_coords(&p, x, xi, mu);
      m.q0(0, mu, q0, &p);
      m.Q_apply(0, xi, mu, Qxi, qn, &p);
      for (size_t i = 0; i < N; i++) ck_assert_double_eq_tol(dz[2 * i], xi[2 * i + 1], 1e-10);
      for (size_t i = 0; i < 2 * N; i++)
        ck_assert_double_eq_tol(dz[2 * N + i], q0[i] + Qxi[i], 1e-9 * (1 + fabs(q0[i])));
    }
    chain_model_free(&p);
  }
  gsl_rng_free(r);
}
END_TEST

/* With only xi_j non-zero, Q(xi, mu) xi = q_j(xi, mu) xi_j, so ||q_j||^2 is
 * ||(q(xi, mu) - q0(mu))||^2 / xi_j^2, from the DAE alone. */
START_TEST(test_column_norms) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  chain_params p = params(NMAX);
  sdae_model m;
  ck_assert_int_eq(chain_model(&m, &p), 0);
  for (int n = 0; n < 20; n++)
    for (size_t j = 0; j < 2 * NMAX; j++) {
      double x[4 * NMAX], xi[2 * NMAX], mu[2 * NMAX], Qxi[2 * NMAX], qn[2 * NMAX];
      double q0[2 * NMAX], lambda[NMAX] = {0}, v[4 * NMAX], dz[4 * NMAX];
      random_state(r, NMAX, x);
      chain_to_coords(&p, x, xi, mu);
      for (size_t i = 0; i < 2 * NMAX; i++)
        if (i != j) xi[i] = 0.0;
      chain_from_coords(&p, xi, mu, x);
      chain_dae_rhs(&p, x, lambda, v);
      tu_directional(phi_z, &p, x, v, 4 * NMAX, 4 * NMAX, 1e-4, dz);
      m.q0(0, mu, q0, &p);
      m.Q_apply(0, xi, mu, Qxi, qn, &p);
      double norm2 = 0.0;
      for (size_t i = 0; i < 2 * NMAX; i++) {
        double qi = (dz[2 * NMAX + i] - q0[i]) / xi[j];
        norm2 += qi * qi;
      }
      ck_assert_double_eq_tol(qn[j], norm2, 1e-7 * norm2);
    }
  chain_model_free(&p);
  gsl_rng_free(r);
}
END_TEST

/* One mass is the oscillator of Section IV with the corrected Q */
START_TEST(test_one_mass_is_the_oscillator) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  chain_params p = params(1);
  osc_params po = {.k = p.k, .d = p.d, .m = p.m, .ga = p.ga, .q = OSC_Q_CORRECTED};
  sdae_model m;
  ck_assert_int_eq(chain_model(&m, &p), 0);
  for (int n = 0; n < 50; n++) {
    double xi[2] = {tu_flat(r, -1, 1), tu_flat(r, -1, 1)};
    double mu[2] = {tu_flat(r, -1, 1), tu_flat(r, -1, 1)}, Qxi[2], qn[2];
    m.Q_apply(0, xi, mu, Qxi, qn, &p);
    double c = osc_c(&po, xi, mu);
    ck_assert_double_eq_tol(qn[0], 1 + c * c, 1e-13 * (1 + c * c));
    ck_assert_double_eq(qn[1], 2.0);
    ck_assert_double_eq_tol(Qxi[1], c * xi[0] + xi[1], 1e-13);
  }
  chain_model_free(&p);
  gsl_rng_free(r);
}
END_TEST

START_TEST(test_banded_jacobian) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  chain_params p = params(NMAX);
  const size_t n = 2 * NMAX;
  sdae_model m;
  ck_assert_int_eq(chain_model(&m, &p), 0);
  double mu[2 * NMAX], J[4 * NMAX * NMAX], band[2 * NMAX * CHAIN_JAC_WIDTH];
  for (size_t i = 0; i < n; i++) mu[i] = tu_flat(r, -1, 1);
  m.q0_jac(0, mu, J, &p);
  chain_q0_jac_band(&p, mu, band);
  for (size_t c = 0; c < n; c++) {
    double a[2 * NMAX], b[2 * NMAX], qa[2 * NMAX], qb[2 * NMAX], h = 1e-6;
    for (size_t i = 0; i < n; i++) a[i] = b[i] = mu[i];
    a[c] += h;
    b[c] -= h;
    m.q0(0, a, qa, &p);
    m.q0(0, b, qb, &p);
    for (size_t row = 0; row < n; row++) {
      double fd = (qa[row] - qb[row]) / (2 * h);
      ck_assert_double_eq_tol(J[row * n + c], fd, 1e-7);
      long off = (long)c - (long)row;
      if (off < -CHAIN_JAC_LOWER || off > CHAIN_JAC_UPPER)
        ck_assert_double_eq_tol(fd, 0.0, 1e-9); /* the declared band holds the whole matrix */
      else
        ck_assert_double_eq_tol(band[row * CHAIN_JAC_WIDTH + (size_t)(off + CHAIN_JAC_LOWER)], fd,
                                1e-7);
    }
  }
  chain_model_free(&p);
  gsl_rng_free(r);
}
END_TEST

START_TEST(test_energy_structure) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  chain_params p = params(NMAX);
  const size_t n = 2 * NMAX;
  sdae_model m;
  ck_assert_int_eq(chain_model(&m, &p), 0);
  double mu[2 * NMAX], xi[2 * NMAX] = {0}, x[4 * NMAX], q0[2 * NMAX], gH[2 * NMAX], H;
  double SgH[2 * NMAX];
  for (size_t i = 0; i < n; i++) mu[i] = tu_flat(r, -1, 1);
  m.q0(0, mu, q0, &p);
  m.grad_H(0, mu, gH, &p);
  m.S_apply(0, mu, gH, SgH, &p);
  m.H(0, mu, &H, &p);
  for (size_t i = 0; i < n; i++) {
    ck_assert_double_eq_tol(SgH[i], q0[i], 1e-13);
    double a[2 * NMAX], b[2 * NMAX], Ha, Hb, h = 1e-6; /* grad H against differences of H */
    for (size_t j = 0; j < n; j++) a[j] = b[j] = mu[j];
    a[i] += h;
    b[i] -= h;
    m.H(0, a, &Ha, &p);
    m.H(0, b, &Hb, &p);
    ck_assert_double_eq_tol(gH[i], (Ha - Hb) / (2 * h), 1e-8);
  }
  chain_from_coords(&p, xi, mu, x); /* H(mu) = E(x) on the manifold */
  ck_assert_double_eq_tol(H, chain_energy(&p, x), 1e-13);
  chain_model_free(&p);
  gsl_rng_free(r);
}
END_TEST

START_TEST(test_random_start_reproducible) {
  chain_params p = params(NMAX);
  double x[4 * NMAX], y[4 * NMAX];
  ck_assert_int_eq(chain_random_start(&p, 7, x), 0);
  ck_assert_int_eq(chain_random_start(&p, 7, y), 0);
  for (size_t i = 0; i < NMAX; i++) {
    ck_assert_double_eq(x[4 * i], y[4 * i]);
    ck_assert(fabs(x[4 * i]) <= 0.5 && fabs(x[4 * i + 1]) <= 0.2);
    ck_assert(fabs(x[4 * i + 2]) <= 0.1 && fabs(x[4 * i + 3]) <= 0.1);
  }
  ck_assert_int_eq(chain_random_start(&p, 8, y), 0);
  ck_assert(x[0] != y[0]);
}
END_TEST

/* With delta 2, epsilon 1: -k_{i,1} >= (delta^2/2) ||q_{i,1}||^2 + epsilon >= 3 and
 * -k_{i,2} = 5, so scheme 15 shrinks every xi at least by (1 + 3T)^(-t/T) ~ e^(-3t): from
 * |Y_i| <= 0.2, |Ydot_i| <= 0.1, below 1e-10 by t = 10 */
START_TEST(test_constraints_restored) {
  chain_params p = params(50);
  sdae_model m;
  sdae_options o;
  ck_assert_int_eq(chain_model(&m, &p), 0);
  sdae_options_default(&o);
  o.delta = 2.0;
  double *x = malloc(4 * p.N * sizeof *x), *xi = malloc(2 * p.N * sizeof *xi);
  double *mu = malloc(2 * p.N * sizeof *mu);
  ck_assert_int_eq(chain_random_start(&p, 3, x), 0);
  chain_to_coords(&p, x, xi, mu);
  ck_assert_int_eq(tu_integrate(&m, &o, 0.001, 10000, xi, mu), SDAE_OK);
  for (size_t i = 0; i < 2 * p.N; i++) ck_assert_double_lt(fabs(xi[i]), 1e-10);
  free(x);
  free(xi);
  free(mu);
  chain_model_free(&p);
}
END_TEST

static Suite *chain_suite(void) {
  Suite *s = suite_create("chain_model");
  TCase *tc = tcase_create("coordinates");
  tcase_add_test(tc, test_coordinates_invert);
  tcase_add_test(tc, test_normal_form);
  tcase_add_test(tc, test_column_norms);
  tcase_add_test(tc, test_one_mass_is_the_oscillator);
  tcase_add_test(tc, test_banded_jacobian);
  tcase_add_test(tc, test_energy_structure);
  tcase_add_test(tc, test_random_start_reproducible);
  suite_add_tcase(s, tc);
  tc = tcase_create("physics");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_constraints_restored);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(chain_suite());
  srunner_run_all(sr, CK_NORMAL);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
