/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The pendulum model: its coordinates (L_g mu = 0, the inverse map), the normal form against the
 * DAE, the energy structure, and integration against the exact solution on the manifold. */
#include <check.h>
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_sf_ellint.h>
#include <gsl/gsl_sf_elljac.h>

#include "pendulum_model.h"
#include "test_util.h"

static void random_state(gsl_rng *r, const pend_params *p, double *x) {
  double rho = p->L * tu_flat(r, 0.5, 1.5), th = tu_flat(r, -3.0, 3.0);
  x[0] = rho * sin(th);
  x[1] = -rho * cos(th);
  x[2] = tu_flat(r, -2.0, 2.0);
  x[3] = tu_flat(r, -2.0, 2.0);
}

static void phi_z(const double *x, double *z, const void *ctx) {
  ck_assert_int_eq(pend_to_coords(ctx, x, z, z + 2), 0);
}

START_TEST(test_coordinates_invert) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  pend_params p = {1.3, 0.7, 9.81};
  for (int n = 0; n < 100; n++) {
    double x[4], xi[2], mu[2], y[4];
    random_state(r, &p, x);
    ck_assert_int_eq(pend_to_coords(&p, x, xi, mu), 0);
    ck_assert_int_eq(pend_from_coords(&p, xi, mu, y), 0);
    for (int i = 0; i < 4; i++) ck_assert_double_eq_tol(y[i], x[i], 1e-13);
  }
  double xi[2] = {-p.L * p.L / 2, 0}, mu[2] = {0, 0}, y[4];
  ck_assert_int_eq(pend_from_coords(&p, xi, mu, y), -1); /* r = 0: outside the chart */
  gsl_rng_free(r);
}
END_TEST

/* L_g mu_j = 0 (mu does not see the constraint force), L_g xi1 = 0 and L_g xi2 = -r^2/m != 0
 * (relative degree 2), by central differences of Phi along g(x). */
START_TEST(test_lie_derivatives_along_g) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  pend_params p = {1.3, 0.7, 9.81};
  for (int n = 0; n < 100; n++) {
    double x[4], f[4], g[4], dz[4];
    random_state(r, &p, x);
    pend_dae(&p, x, f, g);
    tu_directional(phi_z, &p, x, g, 4, 4, 1e-5, dz);
    ck_assert_double_lt(fabs(dz[0]), 1e-9);
    ck_assert_double_eq_tol(dz[1], -(x[0] * x[0] + x[1] * x[1]) / p.m, 1e-8);
    ck_assert_double_lt(fabs(dz[2]), 1e-9);
    ck_assert_double_lt(fabs(dz[3]), 1e-9);
  }
  gsl_rng_free(r);
}
END_TEST

/* d/dt Phi along f + g lambda (any lambda) = (xi2, *, q0(mu) + Q(xi, mu) xi) */
START_TEST(test_normal_form) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  pend_params p = {1.3, 0.7, 9.81};
  sdae_model m;
  pend_model(&m, &p);
  for (int n = 0; n < 100; n++) {
    double x[4], f[4], g[4], v[4], dz[4], xi[2], mu[2], q0[2], Q[4];
    random_state(r, &p, x);
    double lambda = tu_flat(r, -30, 30);
    pend_dae(&p, x, f, g);
    for (int i = 0; i < 4; i++) v[i] = f[i] + lambda * g[i];
    tu_directional(phi_z, &p, x, v, 4, 4, 1e-5, dz);
    pend_to_coords(&p, x, xi, mu);
    ck_assert_int_eq(m.q0(0, mu, q0, &p), 0);
    ck_assert_int_eq(m.Q(0, xi, mu, Q, &p), 0);
    ck_assert_double_eq_tol(dz[0], xi[1], 1e-8);
    for (int i = 0; i < 2; i++) {
      double rhs = q0[i] + Q[2 * i] * xi[0] + Q[2 * i + 1] * xi[1];
      ck_assert_double_eq_tol(dz[2 + i], rhs, 1e-7 * (1 + fabs(rhs)));
    }
  }
  gsl_rng_free(r);
}
END_TEST

START_TEST(test_energy_structure) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  pend_params p = {1.3, 0.7, 9.81};
  sdae_model m;
  pend_model(&m, &p);
  for (int n = 0; n < 50; n++) {
    double mu[2] = {tu_flat(r, -3, 3), tu_flat(r, -3, 3)}, xi[2] = {0, 0}, x[4];
    double q0[2], gH[2], S[4], H;
    m.q0(0, mu, q0, &p);
    m.grad_H(0, mu, gH, &p);
    m.S(0, mu, S, &p);
    m.H(0, mu, &H, &p);
    for (int i = 0; i < 2; i++) /* S grad H = q0 */
      ck_assert_double_eq_tol(S[2 * i] * gH[0] + S[2 * i + 1] * gH[1], q0[i], 1e-13);
    pend_from_coords(&p, xi, mu, x); /* on the manifold H(mu) is the energy E(x) */
    ck_assert_double_eq_tol(H, pend_energy(&p, x), 1e-12);
  }
  gsl_rng_free(r);
}
END_TEST

/* theta'' = -(ga/L) sin theta from rest at theta0: sin(theta/2) = s sn(K(s) - w t; s^2),
 * s = sin(theta0/2), w = sqrt(ga/L) */
static double exact_theta(const pend_params *p, double theta0, double t) {
  double s = sin(theta0 / 2), sn, cn, dn;
  double K = gsl_sf_ellint_Kcomp(s, GSL_PREC_DOUBLE);
  gsl_sf_elljac_e(K - sqrt(p->ga / p->L) * t, s * s, &sn, &cn, &dn);
  return 2 * asin(s * sn);
}

static double angle_error(pend_params *p, const sdae_map_type *map, double T, double tf,
                          double *H_drift) {
  sdae_model m;
  sdae_options o;
  pend_model(&m, p);
  sdae_options_default(&o);
  o.map = map;
  double theta0 = 1.0, xi[2] = {0, 0}, mu[2] = {theta0, 0};
  double H0 = pend_H(p, mu);
  size_t n = (size_t)lround(tf / T);
  ck_assert_int_eq(tu_integrate(&m, &o, T, n, xi, mu), SDAE_OK);
  *H_drift = fabs(pend_H(p, mu) - H0) / fabs(H0);
  return fabs(mu[0] - exact_theta(p, theta0, tf));
}

static double observed_order(const sdae_map_type *map, double *err_fine, double *H_drift) {
  pend_params p = {1.0, 1.0, 9.81};
  double e1 = angle_error(&p, map, 0.004, 1.0, H_drift);
  double e2 = angle_error(&p, map, 0.002, 1.0, H_drift);
  *err_fine = e2;
  return log2(e1 / e2);
}

START_TEST(test_exact_solution_euler) {
  double e, drift;
  double order = observed_order(sdae_map_euler, &e, &drift);
  ck_assert_double_eq_tol(order, 1.0, 0.1);
  ck_assert_double_lt(e, 5e-2);
}
END_TEST

START_TEST(test_exact_solution_midpoint) {
  double e, drift;
  double order = observed_order(sdae_map_midpoint, &e, &drift);
  ck_assert_double_eq_tol(order, 2.0, 0.1);
  ck_assert_double_lt(e, 1e-4);
}
END_TEST

START_TEST(test_exact_solution_dgrad) {
  double e, drift;
  double order = observed_order(sdae_map_dgrad, &e, &drift);
  ck_assert_double_eq_tol(order, 2.0, 0.1);
  ck_assert_double_lt(e, 1e-4);
  ck_assert_double_lt(drift, 1e-13); /* S skew: H conserved to round-off */
}
END_TEST

/* From off the circle the constraint h = xi1 decays: -k1 >= epsilon = 1, and by t = 5 the
 * residual |X^2 + Y^2 - L^2| = 2 |xi1| is below 1e-10 for every map */
START_TEST(test_constraint_restored) {
  const sdae_map_type *maps[3] = {sdae_map_euler, sdae_map_midpoint, sdae_map_dgrad};
  pend_params p = {1.0, 1.0, 9.81};
  sdae_model m;
  sdae_options o;
  pend_model(&m, &p);
  for (int k = 0; k < 3; k++) {
    sdae_options_default(&o);
    o.delta = 2.0;
    o.map = maps[k];
    double x0[4] = {0.5, -0.9, 0.1, 0.2}, xi[2], mu[2], x[4];
    pend_to_coords(&p, x0, xi, mu);
    ck_assert_int_eq(tu_integrate(&m, &o, 0.001, 5000, xi, mu), SDAE_OK);
    ck_assert_int_eq(pend_from_coords(&p, xi, mu, x), 0);
    ck_assert_double_lt(fabs(x[0] * x[0] + x[1] * x[1] - 1.0), 1e-10);
  }
}
END_TEST

static Suite *pendulum_suite(void) {
  Suite *s = suite_create("pendulum_model");
  TCase *tc = tcase_create("coordinates");
  tcase_add_test(tc, test_coordinates_invert);
  tcase_add_test(tc, test_lie_derivatives_along_g);
  tcase_add_test(tc, test_normal_form);
  tcase_add_test(tc, test_energy_structure);
  suite_add_tcase(s, tc);
  tc = tcase_create("exact_solution");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_exact_solution_euler);
  tcase_add_test(tc, test_exact_solution_midpoint);
  tcase_add_test(tc, test_exact_solution_dgrad);
  tcase_add_test(tc, test_constraint_restored);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(pendulum_suite());
  srunner_run_all(sr, CK_NORMAL);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
