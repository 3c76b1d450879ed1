/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The oscillator model against the paper's Section IV: the coordinates of eq. 21, the normal
 * form (eq. 22) against the DAE, the bound of eq. 24 (erratum 1), the maps, and the decay of
 * the constraint from the paper's start. */
#include <check.h>
#include <math.h>
#include <stdlib.h>

#include "oscillator_model.h"
#include "test_util.h"

static const osc_params paper = {.k = 2.0, .d = 0.03, .m = 1.0, .ga = 9.81, .q = OSC_Q_CORRECTED};

static void random_state(gsl_rng *r, double *x) {
  x[0] = tu_flat(r, -1.5, 1.5);
  x[1] = tu_flat(r, -1.0, 1.0);
  x[2] = tu_flat(r, -2.0, 2.0);
  x[3] = tu_flat(r, -2.0, 2.0);
}

static void phi_z(const double *x, double *z, const void *ctx) { osc_to_coords(ctx, x, z, z + 2); }

START_TEST(test_coordinates_invert) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  osc_params p = paper;
  for (int n = 0; n < 100; n++) {
    double x[4], xi[2], mu[2], y[4];
    random_state(r, x);
    osc_to_coords(&p, x, xi, mu);
    osc_from_coords(&p, xi, mu, y);
    for (int i = 0; i < 4; i++) ck_assert_double_eq_tol(y[i], x[i], 1e-15);
  }
  gsl_rng_free(r);
}
END_TEST

/* d/dt Phi(x) along f + g lambda, for any lambda, equals (xi2, *, q0 + Q xi): the derivation of
 * eq. 22 with the mass. Holds for the corrected Q only. */
static double normal_form_defect(osc_params *p, gsl_rng *r) {
  sdae_model m;
  osc_model(&m, p);
  double worst = 0.0;
  for (int n = 0; n < 100; n++) {
    double x[4], f[4], g[4], v[4], dz[4], xi[2], mu[2], q0[2], Q[4];
    random_state(r, x);
    double lambda = tu_flat(r, -20, 20);
    osc_dae(p, x, f, g);
    for (int i = 0; i < 4; i++) v[i] = f[i] + g[i] * lambda;
    tu_directional(phi_z, p, x, v, 4, 4, 1e-4, dz);
    osc_to_coords(p, x, xi, mu);
    m.q0(0, mu, q0, p);
    m.Q(0, xi, mu, Q, p);
    ck_assert_double_eq_tol(dz[0], xi[1], 1e-9); /* xi1' = xi2 */
    for (int i = 0; i < 2; i++) {
      double rhs = q0[i] + Q[2 * i] * xi[0] + Q[2 * i + 1] * xi[1];
      worst = fmax(worst, fabs(dz[2 + i] - rhs) / (1 + fabs(rhs)));
    }
  }
  return worst;
}

START_TEST(test_normal_form_corrected_q) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  osc_params p = paper;
  ck_assert_double_lt(normal_form_defect(&p, r), 1e-9);
  p.m = 2.5; /* erratum 3: the mass divides the accelerations and Q's second row */
  ck_assert_double_lt(normal_form_defect(&p, r), 1e-9);
  gsl_rng_free(r);
}
END_TEST

START_TEST(test_normal_form_fails_with_printed_q) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  osc_params p = paper;
  p.q = OSC_Q_PAPER;
  ck_assert_double_gt(normal_form_defect(&p, r), 1e-2); /* erratum 1 */
  gsl_rng_free(r);
}
END_TEST

/* eq. 24: max over B of -k_i with delta 2, epsilon 1. The printed Q gives the paper's 188.9 at
 * (xi1, mu1) = (-0.7, 0.9); the corrected one 189.245 at (0.7, -0.9) (erratum 1 of docs/paper.md).
 * Both c are even in (xi1, mu1) -> (-xi1, -mu1), so either corner of the pair is a maximizer. */
static double sup_minus_gain(osc_params *p, double *at_xi1, double *at_mu1) {
  sdae_model m;
  sdae_options o;
  sdae_stepper *s = NULL;
  osc_model(&m, p);
  sdae_options_default(&o);
  o.delta = 2.0;
  o.epsilon = 1.0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  double best = -INFINITY;
  for (int i = 0; i <= 140; i++)
    for (int j = 0; j <= 180; j++) {
      double xi[2] = {-0.7 + 0.01 * i, 0.0}, mu[2] = {-0.9 + 0.01 * j, 0.0}, k[2];
      ck_assert_int_eq(sdae_stepper_gains(s, 0, xi, mu, k), SDAE_OK);
      ck_assert_double_eq_tol(k[1], -5.0, 1e-12); /* -(delta^2/2) * 2 - epsilon */
      if (-k[0] > best) {
        best = -k[0];
        *at_xi1 = xi[0];
        *at_mu1 = mu[0];
      }
    }
  sdae_stepper_free(s);
  return best;
}

START_TEST(test_eq24_bound) {
  osc_params p = paper;
  double xi1, mu1;
  p.q = OSC_Q_PAPER;
  ck_assert_double_eq_tol(sup_minus_gain(&p, &xi1, &mu1), 188.9, 0.005);
  ck_assert_double_eq_tol(fabs(xi1), 0.7, 1e-9);
  ck_assert_double_eq_tol(xi1 * mu1, -0.63, 1e-9);
  p.q = OSC_Q_CORRECTED;
  ck_assert_double_eq_tol(sup_minus_gain(&p, &xi1, &mu1), 189.245, 1e-9);
  ck_assert_double_eq_tol(fabs(xi1), 0.7, 1e-9);
  ck_assert_double_eq_tol(xi1 * mu1, -0.63, 1e-9);
}
END_TEST

START_TEST(test_map_callbacks) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  osc_params p = paper;
  p.m = 1.7;
  sdae_model m;
  osc_model(&m, &p);
  for (int n = 0; n < 50; n++) {
    double mu[2] = {tu_flat(r, -1, 1), tu_flat(r, -1, 1)}, q0[2], gH[2], S[4], phi[2];
    m.q0(0, mu, q0, &p);
    m.grad_H(0, mu, gH, &p);
    m.S(0, mu, S, &p);
    for (int i = 0; i < 2; i++) /* S grad W = q0 */
      ck_assert_double_eq_tol(S[2 * i] * gH[0] + S[2 * i + 1] * gH[1], q0[i], 1e-14);
    m.user_phi(0, 0.01, mu, mu, phi, &p); /* the paper's map is consistent: phi(mu, mu) = q0 */
    for (int i = 0; i < 2; i++) ck_assert_double_eq_tol(phi[i], q0[i], 1e-14);
    double nx[2] = {tu_flat(r, -1, 1), tu_flat(r, -1, 1)}, J[4], pp[2], pm[2], h = 1e-6;
    m.user_phi_jac(0, 0.01, mu, nx, J, &p);
    for (int c = 0; c < 2; c++) { /* the Jacobian against central differences */
      double a[2] = {nx[0], nx[1]}, b[2] = {nx[0], nx[1]};
      a[c] += h;
      b[c] -= h;
      m.user_phi(0, 0.01, mu, a, pp, &p);
      m.user_phi(0, 0.01, mu, b, pm, &p);
      for (int i = 0; i < 2; i++)
        ck_assert_double_eq_tol(J[2 * i + c], (pp[i] - pm[i]) / (2 * h), 1e-8);
    }
  }
  gsl_rng_free(r);
}
END_TEST

/* On the manifold with d = 0 the paper's map and the discrete gradient conserve W exactly;
 * with d > 0 the discrete gradient dissipates it. */
static double step_W_change(osc_params *p, const sdae_map_type *map) {
  sdae_model m;
  sdae_options o;
  osc_model(&m, p);
  sdae_options_default(&o);
  o.map = map;
  double xi[2] = {0, 0}, mu[2] = {0.7, -0.4};
  double W0 = osc_W(p, mu);
  ck_assert_int_eq(tu_integrate(&m, &o, 0.05, 20, xi, mu), SDAE_OK);
  return (osc_W(p, mu) - W0) / W0;
}

START_TEST(test_energy_of_maps) {
  osc_params p = paper;
  p.d = 0.0;
  ck_assert_double_lt(fabs(step_W_change(&p, sdae_map_user)), 1e-13);
  ck_assert_double_lt(fabs(step_W_change(&p, sdae_map_dgrad)), 1e-13);
  p.d = 0.3;
  ck_assert_double_lt(step_W_change(&p, sdae_map_dgrad), -1e-3);
}
END_TEST

/* Theorem 4: from the paper's start (Y = 0.6 off the floor) the constraint decays; along the
 * solution -k1 = 2 (1 + c^2) + 1 >= 3 and c = 6 X^2 + 0.03 on the floor, so by t = 5 |Y| is far
 * below 1e-12. */
START_TEST(test_paper_run_constraint) {
  osc_params p = paper;
  sdae_model m;
  sdae_options o;
  osc_model(&m, &p);
  sdae_options_default(&o);
  o.delta = 2.0;
  o.epsilon = 1.0;
  o.map = sdae_map_user;
  double x0[4] = {0.1, 0.6, 0, 0}, xi[2], mu[2];
  osc_to_coords(&p, x0, xi, mu);
  ck_assert_int_eq(tu_integrate(&m, &o, 0.001, 5000, xi, mu), SDAE_OK);
  ck_assert_double_lt(fabs(xi[0]), 1e-12);
  ck_assert_double_lt(fabs(xi[1]), 1e-12);
  /* scheme 11 with T below 2/189.245 (Theorem 3) does the same */
  o.scheme = SDAE_SCHEME_EXPLICIT;
  osc_to_coords(&p, x0, xi, mu);
  ck_assert_int_eq(tu_integrate(&m, &o, 0.001, 5000, xi, mu), SDAE_OK);
  ck_assert_double_lt(fabs(xi[0]), 1e-12);
}
END_TEST

static Suite *oscillator_suite(void) {
  Suite *s = suite_create("oscillator_model");
  TCase *tc = tcase_create("coordinates");
  tcase_add_test(tc, test_coordinates_invert);
  tcase_add_test(tc, test_normal_form_corrected_q);
  tcase_add_test(tc, test_normal_form_fails_with_printed_q);
  suite_add_tcase(s, tc);
  tc = tcase_create("gains");
  tcase_add_test(tc, test_eq24_bound);
  suite_add_tcase(s, tc);
  tc = tcase_create("maps");
  tcase_add_test(tc, test_map_callbacks);
  tcase_add_test(tc, test_energy_of_maps);
  suite_add_tcase(s, tc);
  tc = tcase_create("physics");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_paper_run_constraint);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(oscillator_suite());
  srunner_run_all(sr, CK_NORMAL);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
