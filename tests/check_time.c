/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Time: every model callback of the rotation fixture (tests/fixtures/rotation.h) depends on t,
 * with a(t) = 1 + t, so a map, the stepper or sdae_integrate handing a callback the wrong time
 * changes the numbers. Checked three ways: one step against its closed form, the order of
 * every map against the exact solution, and the decay of xi under a time-dependent gain. */
#include <math.h>
#include <string.h>

#include "core/arena.h"
#include "core/lu.h"
#include "maps/map.h"
#include "stepper/stepper.h"
#include "testmodels.h"

static sdae_options options(const sdae_map_type *map, sdae_scheme scheme) {
  sdae_options o;
  sdae_options_default(&o);
  o.map = map;
  o.scheme = scheme;
  return o;
}

/* one step of the map from (t, xi, mu) */
static void one_step(const sdae_model *m, const sdae_map_type *map, double t, double T, double *xi,
                     double *mu) {
  sdae_options o = options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  ck_assert_int_eq(sdae_stepper_alloc(&s, m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, t, T, xi, mu), SDAE_OK);
  sdae_stepper_free(s);
}

/* ---- one step against its closed form ---- */

/* Euler from t with xi != 0: mu+ = mu + T (a(t) J mu + b(t) xi e1), b(t) = 1 + t, and
 * xi+ = xi / (1 - T k(t)) (eq. 15): the time of q0, of Q in the mu row and of Q in the gain.
 * The formulas are evaluated here as the definitions read; 4 ulps of rounding allowed. */
START_TEST(euler_step_uses_t) {
  sdae_model m = rotation_model(NULL);
  double t = 0.7, T = 0.25, xi[1] = {0.3}, mu[2] = {0.6, -0.8}, a = 1.0 + t, b = 1.0 + t;
  double want_mu[2] = {0.6 + T * (a * -0.8 + b * 0.3), -0.8 + T * (-a * 0.6)};
  double want_xi = 0.3 / (1.0 - T * rotation_gain(t, 1.0, 1.0));
  one_step(&m, sdae_map_euler, t, T, xi, mu);
  for (int i = 0; i < 2; i++) ck_assert_double_le(fabs(mu[i] - want_mu[i]), 4 * DBL_EPSILON);
  ck_assert_double_le(fabs(xi[0] - want_xi), 4 * DBL_EPSILON * fabs(want_xi));
}
END_TEST

/* The midpoint rule on the linear q0 = a J mu solves (I - (T a/2) J) mu+ = (I + (T a/2) J) mu,
 * a = a(t + T/2): its Cayley transform turns mu by 2 atan(T a / 2). Gonzalez's discrete
 * gradient of H = |mu|^2/2 is exactly the midpoint, so dgrad with S = a(t + T/2) J is the same
 * map; so is the user map of the fixture. On the manifold (xi = 0), to 1e-14: a wrong time
 * (t, or t - T/2) changes the angle by T^2/2 or T^2 = 0.03 here. */
static void cayley_step(const sdae_map_type *map, int with_S_apply) {
  sdae_model m = rotation_model(NULL);
  double t = 0.7, T = 0.25, xi[1] = {0.0}, mu[2] = {0.6, -0.8}, want[2];
  if (with_S_apply) m.S = NULL, m.S_apply = rotation_S_apply;
  rotation_turn(2.0 * atan(0.5 * T * rotation_rate(t + 0.5 * T)), mu, want);
  one_step(&m, map, t, T, xi, mu);
  for (int i = 0; i < 2; i++) ck_assert_double_le(fabs(mu[i] - want[i]), 1e-14);
}

START_TEST(midpoint_step_uses_half_time) { cayley_step(sdae_map_midpoint, 0); }
END_TEST

START_TEST(dgrad_step_uses_half_time) {
  cayley_step(sdae_map_dgrad, 0);
  cayley_step(sdae_map_dgrad, 1);
}
END_TEST

START_TEST(user_map_gets_step_time) { cayley_step(sdae_map_user, 0); }
END_TEST

/* dg4 and dg6: stage k is the Cayley step of length h_k = gamma_k T from the time
 * t_k = t + (gamma_1 + ... + gamma_{k-1}) T, turning by 2 atan(h_k a(t_k + h_k/2) / 2); the
 * rotations commute, so one step turns mu by the sum. (A stage clock running backwards, or
 * standing still, changes the sum by O(T^2).) */
static void composed_step(const sdae_map_type *map) {
  sdae_model m = rotation_model(NULL);
  double t = 0.7, T = 0.25, xi[1] = {0.0}, mu[2] = {0.6, -0.8}, want[2], angle = 0.0, tk = t;
  for (size_t k = 0; k < map->stages; k++) {
    double h = map->gamma[k] * T;
    angle += 2.0 * atan(0.5 * h * rotation_rate(tk + 0.5 * h));
    tk += h;
  }
  rotation_turn(angle, mu, want);
  one_step(&m, map, t, T, xi, mu);
  for (int i = 0; i < 2; i++) ck_assert_double_le(fabs(mu[i] - want[i]), 1e-14);
}

START_TEST(dg4_stage_times_advance) { composed_step(sdae_map_dg4); }
END_TEST

START_TEST(dg6_stage_times_advance) { composed_step(sdae_map_dg6); }
END_TEST

/* ---- orders against the exact solution ---- */

/* max-norm error at tf = t0 + n T on the manifold from mu(t0) = (1, 0), by sdae_integrate */
static double rotation_error(const sdae_model *m, const sdae_map_type *map, double t0, double tf,
                             double T) {
  sdae_options o = options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[1] = {0.0}, mu[2] = {1.0, 0.0}, mu0[2] = {1.0, 0.0}, exact[2];
  size_t n = (size_t)lround((tf - t0) / T);
  ck_assert_int_eq(sdae_stepper_alloc(&s, m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, t0, T, n, n, xi, mu, NULL, NULL, NULL), SDAE_OK);
  sdae_stepper_free(s);
  rotation_exact(t0, mu0, tf, exact);
  return fmax(fabs(mu[0] - exact[0]), fabs(mu[1] - exact[1]));
}

/* The error divides by 2^p when T halves, p = sdae_map_order(map) = the order theory gives
 * (euler 1, midpoint and dgrad 2, dg4 and rk4 4, dg6 6, rk8 8), within 5 %; T large enough
 * that the error stays far above rounding (asserted: above 1e-11; dg6's is 9e-10 at T = 0.05,
 * rk8's 4e-11 at T = 0.125), small enough to be asymptotic (dg6 at T = 0.2 is still at 60).
 * With the wrong time in a symmetric map the quadrature of a(t) is off by O(T): ratio 2; a
 * Runge-Kutta stage at a wrong node c_i breaks an order condition of order 2 (sum b_i c_i =
 * 1/2, with c the node of a(t)) or higher. */
static void expect_order(const sdae_model *m, const sdae_map_type *map, unsigned order, double T) {
  double e1 = rotation_error(m, map, 0.0, 2.0, T), e2 = rotation_error(m, map, 0.0, 2.0, T / 2);
  ck_assert_uint_eq(sdae_map_order(map), order);
  ck_assert_double_gt(e2, 1e-11);
  ck_assert_double_gt(e1 / e2, 0.95 * pow(2.0, order));
  ck_assert_double_lt(e1 / e2, 1.05 * pow(2.0, order));
}

START_TEST(order_euler_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_euler, 1, 0.0025);
}
END_TEST

START_TEST(order_midpoint_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_midpoint, 2, 0.02);
}
END_TEST

START_TEST(order_dgrad_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_dgrad, 2, 0.02);
}
END_TEST

START_TEST(order_dg4_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_dg4, 4, 0.025);
}
END_TEST

START_TEST(order_dg6_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_dg6, 6, 0.1);
}
END_TEST

/* the midpoint map composed: the stages' times tile the step as dg4's and dg6's do */
START_TEST(order_midpoint4_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_midpoint4, 4, 0.025);
}
END_TEST

START_TEST(order_midpoint6_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_midpoint6, 6, 0.1);
}
END_TEST

/* the explicit Runge-Kutta maps: their stages at t + c_i T */
START_TEST(order_rk4_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_rk4, 4, 0.025);
}
END_TEST

START_TEST(order_rk8_time_dependent) {
  sdae_model m = rotation_model(NULL);
  expect_order(&m, sdae_map_rk8, 8, 0.25);
}
END_TEST

/* ---- time in Q: the gain k_1(t_n) of every step ---- */

/* From t0 = 0.3, n steps of T: xi_N = xi_0 prod_n 1/(1 - T k(t_n)) (scheme 15) or
 * prod_n (1 + T k(t_n)) (scheme 11), t_n = t0 + n T, computed here from k's closed form; to
 * 64 ulps relative over 40 steps. A Q evaluated at t + T (or 0) gives another product. */
static double xi_product(sdae_scheme scheme, double t0, double T, size_t n, double delta) {
  double xi = 1.0;
  for (size_t i = 0; i < n; i++) {
    double k = rotation_gain(t0 + (double)i * T, delta, 1.0);
    xi = scheme == SDAE_SCHEME_EXPLICIT ? xi * (1.0 + T * k) : xi / (1.0 - T * k);
  }
  return xi;
}

static void xi_follows_gain(int use_Q_apply, sdae_scheme scheme) {
  sdae_model m = rotation_model(NULL);
  sdae_options o = options(sdae_map_midpoint, scheme);
  sdae_stepper *s;
  double t0 = 0.3, T = 0.02, xi[1] = {1.0}, mu[2] = {0.6, -0.8};
  size_t n = 40;
  if (use_Q_apply) m.Q = NULL, m.Q_apply = rotation_Q_apply;
  o.delta = 2.0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, t0, T, n, 1, xi, mu, NULL, NULL, NULL), SDAE_OK);
  sdae_stepper_free(s);
  double want = xi_product(scheme, t0, T, n, 2.0);
  ck_assert_double_le(fabs(xi[0] - want), 64 * DBL_EPSILON * fabs(want));
}

START_TEST(gain_uses_step_time_dense_Q) {
  xi_follows_gain(0, SDAE_SCHEME_SEMI_IMPLICIT);
  xi_follows_gain(0, SDAE_SCHEME_EXPLICIT);
}
END_TEST

START_TEST(gain_uses_step_time_Q_apply) {
  xi_follows_gain(1, SDAE_SCHEME_SEMI_IMPLICIT);
  xi_follows_gain(1, SDAE_SCHEME_EXPLICIT);
}
END_TEST

/* sdae_stepper_gains at time t: k_1(t) of eq. 6 in closed form, to 2 ulps. */
START_TEST(gains_at_given_time) {
  sdae_model m = rotation_model(NULL);
  sdae_options o = options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[1] = {0.5}, mu[2] = {0.6, -0.8}, k[1];
  o.delta = 2.0, o.epsilon = 0.5;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  for (double t = 0.0; t < 3.0; t += 0.75) {
    double want = rotation_gain(t, 2.0, 0.5);
    ck_assert_int_eq(sdae_stepper_gains(s, t, xi, mu, k), SDAE_OK);
    ck_assert_double_le(fabs(k[0] - want), 2 * DBL_EPSILON * fabs(want));
  }
  sdae_stepper_free(s);
}
END_TEST

/* ---- sdae_integrate's clock: step i from t0 + (i - 1) T, observed at t0 + i T ---- */

typedef struct clock_log {
  size_t count;
  double t0, T, worst;
} clock_log;

static int watch_clock(size_t step, double t, const double *xi, const double *mu, void *data) {
  clock_log *c = data;
  (void)xi, (void)mu;
  c->worst = fmax(c->worst, fabs(t - (c->t0 + (double)step * c->T)));
  c->count++;
  return 0;
}

/* Over 1000 steps from t0 = 10.1 with T = 0.1: the observer's times are t0 + i T to 1 ulp of
 * 110 (an accumulated t += T drifts by 2e-12 here, over 100 ulps), and xi, whose gain depends
 * on the time of every step, is the product of 1/(1 - T k(t0 + i T)). The midpoint map keeps
 * |mu| (euler's would grow by sqrt(1 + (T a)^2) a step and overflow). */
START_TEST(integrate_times_are_t0_plus_iT) {
  sdae_model m = rotation_model(NULL);
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  clock_log c = {0, 10.1, 0.1, 0.0};
  double xi[1] = {1.0}, mu[2] = {0.6, -0.8};
  size_t n = 1000;
  o.epsilon = 1e-3, o.delta = 1e-2; /* small gains: xi stays far above underflow */
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, c.t0, c.T, n, 1, xi, mu, watch_clock, &c, NULL), SDAE_OK);
  sdae_stepper_free(s);
  ck_assert_uint_eq(c.count, n + 1);
  ck_assert_double_le(c.worst, 110.0 * DBL_EPSILON);
  double want = 1.0;
  for (size_t i = 0; i < n; i++) {
    double t = c.t0 + (double)i * c.T, b = 1.0 + t;
    want /= 1.0 - c.T * (-0.5 * 1e-4 * b * b - 1e-3);
  }
  ck_assert_double_le(fabs(xi[0] - want), 1e-12 * want);
}
END_TEST

int main(void) {
  Suite *s = suite_create("time");
  ADD_CASE(s, euler_step_uses_t);
  ADD_CASE(s, midpoint_step_uses_half_time);
  ADD_CASE(s, dgrad_step_uses_half_time);
  ADD_CASE(s, user_map_gets_step_time);
  ADD_CASE(s, dg4_stage_times_advance);
  ADD_CASE(s, dg6_stage_times_advance);
  ADD_CASE(s, order_euler_time_dependent);
  ADD_CASE(s, order_midpoint_time_dependent);
  ADD_CASE(s, order_dgrad_time_dependent);
  ADD_CASE(s, order_dg4_time_dependent);
  ADD_CASE(s, order_dg6_time_dependent);
  ADD_CASE(s, order_midpoint4_time_dependent);
  ADD_CASE(s, order_midpoint6_time_dependent);
  ADD_CASE(s, order_rk4_time_dependent);
  ADD_CASE(s, order_rk8_time_dependent);
  ADD_CASE(s, gain_uses_step_time_dense_Q);
  ADD_CASE(s, gain_uses_step_time_Q_apply);
  ADD_CASE(s, gains_at_given_time);
  ADD_CASE(s, integrate_times_are_t0_plus_iT);
  return run_suite(s);
}
