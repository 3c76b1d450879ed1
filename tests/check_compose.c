/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The composition coefficients of dg4 and dg6 (and midpoint4, midpoint6: the same ones), read
 * from the map tables themselves
 * (src/maps/map.h: gamma, stages, base), against the order conditions of a symmetric composition
 * Psi_T = Phi_{g_s T} o ... o Phi_{g_1 T} of the symmetric order-2 discrete gradient Phi
 * (Hairer, Lubich, Wanner, Geometric Numerical Integration, II.4 and V.3): consistency
 * sum g = 1, symmetry g_i = g_{s+1-i}, order 4 sum g^3 = 0, order 6 also sum g^5 = 0 and
 * sum g_i^3 c_i^2 = 0. An order test at moderate T cannot see a defect of 1e-10 in a
 * coefficient; these conditions, held to the rounding of the stored doubles, do. */
#include <float.h>
#include <math.h>

#include "core/arena.h"
#include "core/lu.h"
#include "maps/map.h"
#include "stepper/stepper.h"
#include "testmodels.h"

/* sum g_i^k, and in *bound the rounding it may carry: each g_i is stored to eps/2 relative,
 * which moves g_i^k by k eps/2 |g_i|^k, and the s-term sum in double adds at most s eps times
 * the sum of |terms|: (k/2 + s) eps sum |g_i|^k */
static double power_sum(const sdae_map_type *map, int k, double *bound) {
  double sum = 0.0, abs_sum = 0.0;
  for (size_t i = 0; i < map->stages; i++) {
    double p = pow(map->gamma[i], k);
    sum += p;
    abs_sum += fabs(p);
  }
  *bound = (0.5 * k + (double)map->stages) * DBL_EPSILON * abs_sum;
  return sum;
}

/* c_i = sum_{j<i} g_j - sum_{j>i} g_j: where stage i sits in the step, from its centre */
static double centre_offset(const sdae_map_type *map, size_t i) {
  double c = 0.0;
  for (size_t j = 0; j < map->stages; j++) {
    if (j < i) c += map->gamma[j];
    if (j > i) c -= map->gamma[j];
  }
  return c;
}

/* sum g_i^3 c_i^2: the coefficient of the order-5 commutator [A, [A, B]] of the composition
 * (Phi_h = exp(h A + h^3 B + ...)); zero is the fourth condition of order 6. Rounding bound as
 * above, with the c_i carrying s eps each. */
static double commutator_condition(const sdae_map_type *map, double *bound) {
  double sum = 0.0, abs_sum = 0.0;
  for (size_t i = 0; i < map->stages; i++) {
    double c = centre_offset(map, i), term = pow(map->gamma[i], 3) * c * c;
    sum += term;
    abs_sum += fabs(term);
  }
  *bound = (1.5 + 3.0 * (double)map->stages) * DBL_EPSILON * abs_sum;
  return sum;
}

static void expect_symmetric_consistent(const sdae_map_type *map, size_t stages) {
  double bound, sum;
  ck_assert_uint_eq(map->stages, stages);
  ck_assert_int_eq(map->implicit, 0); /* one scheme step: xi updated once per T */
  for (size_t i = 0; i < stages; i++)
    ck_assert_double_eq(map->gamma[i], map->gamma[stages - 1 - i]);
  sum = power_sum(map, 1, &bound);
  ck_assert_double_le(fabs(sum - 1.0), bound);
}

START_TEST(dg4_order_conditions) {
  const sdae_map_type *map = sdae_map_dg4;
  double bound, sum;
  expect_symmetric_consistent(map, 3);
  sum = power_sum(map, 3, &bound); /* about 4.4e-15 for |g|^3 summing to 9.9 */
  ck_assert_double_le(fabs(sum), bound);
  ck_assert_uint_eq(sdae_map_order(map), 4);
  /* order 4 only: the order-6 conditions fail by O(1) */
  ck_assert_double_gt(fabs(power_sum(map, 5, &bound)), 1.0);
  ck_assert_double_gt(fabs(commutator_condition(map, &bound)), 0.1);
}
END_TEST

/* Yoshida's triple jump in closed form: g1 = g3 = 1/(2 - 2^(1/3)), g2 = -2^(1/3)/(2 - 2^(1/3)),
 * to 4 eps relative (cbrt's ulp, amplified by 2^(1/3)/(2 - 2^(1/3)) = 1.7 in the difference,
 * one division, the table's own rounding). */
START_TEST(dg4_is_yoshida_triple_jump) {
  const double *g = sdae_map_dg4->gamma, c = cbrt(2.0);
  double g1 = 1.0 / (2.0 - c), g2 = -c / (2.0 - c);
  ck_assert_double_le(fabs(g[0] - g1), 4 * DBL_EPSILON * g1);
  ck_assert_double_le(fabs(g[1] - g2), 4 * DBL_EPSILON * fabs(g2));
}
END_TEST

START_TEST(dg6_order_conditions) {
  const sdae_map_type *map = sdae_map_dg6;
  double bound, sum;
  expect_symmetric_consistent(map, 9);
  sum = power_sum(map, 3, &bound);
  ck_assert_double_le(fabs(sum), bound);
  sum = power_sum(map, 5, &bound); /* about 1.8e-15 */
  ck_assert_double_le(fabs(sum), bound);
  sum = commutator_condition(map, &bound);
  ck_assert_double_le(fabs(sum), bound);
  ck_assert_uint_eq(sdae_map_order(map), 6);
}
END_TEST

/* Every map's declared order is the one theory gives it (the orders measured against exact
 * solutions are in check_time.c and check_maps.c), and the user's map declares none. */
/* The two families are the same compositions of two symmetric order-2 bases: the discrete
 * gradient and the implicit midpoint map. */
START_TEST(bases_and_coefficients) {
  const sdae_map_type *dg[2] = {sdae_map_dg4, sdae_map_dg6};
  const sdae_map_type *mid[2] = {sdae_map_midpoint4, sdae_map_midpoint6};
  for (int k = 0; k < 2; k++) {
    ck_assert_ptr_eq(dg[k]->base, sdae_map_dgrad);
    ck_assert_ptr_eq(mid[k]->base, sdae_map_midpoint);
    ck_assert_uint_eq(mid[k]->stages, dg[k]->stages);
    for (size_t i = 0; i < dg[k]->stages; i++)
      ck_assert_double_eq(mid[k]->gamma[i], dg[k]->gamma[i]);
  }
}
END_TEST

START_TEST(declared_orders) {
  ck_assert_uint_eq(sdae_map_order(sdae_map_euler), 1);
  ck_assert_uint_eq(sdae_map_order(sdae_map_midpoint), 2);
  ck_assert_uint_eq(sdae_map_order(sdae_map_dgrad), 2);
  ck_assert_uint_eq(sdae_map_order(sdae_map_dg4), 4);
  ck_assert_uint_eq(sdae_map_order(sdae_map_dg6), 6);
  ck_assert_uint_eq(sdae_map_order(sdae_map_midpoint4), 4);
  ck_assert_uint_eq(sdae_map_order(sdae_map_midpoint6), 6);
  ck_assert_uint_eq(sdae_map_order(sdae_map_user), 0);
  ck_assert_uint_eq(sdae_map_order(NULL), 0);
  ck_assert_ptr_eq(sdae_map_by_name("dg6"), sdae_map_dg6);
  ck_assert_ptr_null(sdae_map_by_name("dg8"));
}
END_TEST

/* ---- the stages' predictor ----
 * H = mu_1 (linear), S = a(t) J with a(t) = 1 + t (the rotation fixture's S): gradbar H is
 * (1, 0) exactly for every increment (H(y) - H(x) - grad H . v = 0), so the stage map
 * phi(x, y) = S(t_k + h_k/2) (1, 0) = (0, -a(t_k + h_k/2)) does not depend on y, and the
 * predictor y = x + h_k phi(x, x) of stage k is its Newton root: the first iteration's update
 * is at rounding level and stops (1 iteration a stage, 2 evaluations: predictor and residual;
 * hess_H = 0 gives M without evaluations). A predictor from another time, or not x + h phi,
 * is off the root by O(h): a second iteration. The midpoint map's stage phi(x, y) = q0 at
 * t_k + h_k/2 is the same constant, with q0_jac = 0. */
static int linear_H(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  out[0] = mu[0];
  return 0;
}

static int linear_grad_H(double t, const double *mu, double *out, void *params) {
  (void)t, (void)mu, (void)params;
  out[0] = 1.0, out[1] = 0.0;
  return 0;
}

static int zero_matrix(double t, const double *mu, double *out, void *params) {
  (void)t, (void)mu, (void)params;
  out[0] = out[1] = out[2] = out[3] = 0.0;
  return 0;
}

static int linear_q0(double t, const double *mu, double *out, void *params) {
  (void)mu, (void)params;
  out[0] = 0.0, out[1] = -rotation_rate(t); /* S grad H */
  return 0;
}

/* One step from t = 0.7 with T = 0.25 on the manifold: 1 iteration and 2 evaluations per stage,
 * plus the stepper's one evaluation of the composed map; mu_1 unchanged and mu_2 decreased by
 * sum_k h_k a(t_k + h_k/2) = the integral of a over [t, t + T] (the midpoint rule is exact for
 * the linear a, and the stage times tile the step). */
static void predictor_is_root(const sdae_map_type *map) {
  sdae_model m = rotation_model(NULL);
  sdae_options o = quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double t = 0.7, T = 0.25, xi[1] = {0.0}, mu[2] = {0.6, -0.8};
  m.q0 = linear_q0, m.q0_jac = zero_matrix; /* the midpoint's Jacobian: q0 is constant */
  m.H = linear_H, m.grad_H = linear_grad_H, m.hess_H = zero_matrix;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, t, T, xi, mu), SDAE_OK);
  ck_assert_uint_eq(sdae_stepper_stats(s)->newton_iters_last, map->stages);
  ck_assert_uint_eq(sdae_stepper_stats(s)->phi_evals, 1 + 2 * map->stages);
  ck_assert_double_eq(mu[0], 0.6);
  ck_assert_double_le(fabs(mu[1] - (-0.8 - rotation_angle(t, t + T))), 1e-14);
  sdae_stepper_free(s);
}

START_TEST(dg4_stage_predictor_is_root) { predictor_is_root(sdae_map_dg4); }
END_TEST

START_TEST(dg6_stage_predictor_is_root) { predictor_is_root(sdae_map_dg6); }
END_TEST

START_TEST(midpoint4_stage_predictor_is_root) { predictor_is_root(sdae_map_midpoint4); }
END_TEST

START_TEST(midpoint6_stage_predictor_is_root) { predictor_is_root(sdae_map_midpoint6); }
END_TEST

int main(void) {
  Suite *s = suite_create("compose");
  ADD_CASE(s, dg4_order_conditions);
  ADD_CASE(s, dg4_is_yoshida_triple_jump);
  ADD_CASE(s, dg6_order_conditions);
  ADD_CASE(s, declared_orders);
  ADD_CASE(s, bases_and_coefficients);
  ADD_CASE(s, midpoint4_stage_predictor_is_root);
  ADD_CASE(s, midpoint6_stage_predictor_is_root);
  ADD_CASE(s, dg4_stage_predictor_is_root);
  ADD_CASE(s, dg6_stage_predictor_is_root);
  return run_suite(s);
}
