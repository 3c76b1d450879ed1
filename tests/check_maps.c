/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mu-maps: order on the manifold against the exact solution x = A cn(A t | 1/2) of
 * x'' = -x^3, exact energy conservation of the discrete gradient, its dissipation with
 * S = J - R, and its small-increment branch. */
#include <float.h>
#include <math.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "core/arena.h"
#include "core/lu.h"
#include "maps/map.h"
#include "stepper/stepper.h"
#include "testmodels.h"

/* The error at t = 2 divides by 2^order when T halves (from T to T/2); within 5%. */
static void expect_order(const sdae_options *o, int order, double T) {
  double e1 = quartic_error(o, 1.0, 2.0, T), e2 = quartic_error(o, 1.0, 2.0, T / 2);
  ck_assert_double_gt(e1 / e2, 0.95 * pow(2.0, order));
  ck_assert_double_lt(e1 / e2, 1.05 * pow(2.0, order));
}

START_TEST(order_euler_is_1) {
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 1, 0.02);
}
END_TEST

START_TEST(order_midpoint_is_2) {
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 2, 0.02);
}
END_TEST

START_TEST(order_dgrad_is_2) {
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_EXPLICIT);
  expect_order(&o, 2, 0.02);
}
END_TEST

/* Yoshida's triple jump of the symmetric discrete gradient: order 4 */
START_TEST(order_dg4_is_4) {
  sdae_options o = quartic_options(sdae_map_dg4, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 4, 0.04);
}
END_TEST

/* Kahan and Li's s9odr6a composition of the same: order 6 */
START_TEST(order_dg6_is_6) {
  sdae_options o = quartic_options(sdae_map_dg6, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 6, 0.2);
}
END_TEST

/* the same compositions of the implicit midpoint map (q0 only): orders 4 and 6 */
START_TEST(order_midpoint4_is_4) {
  sdae_options o = quartic_options(sdae_map_midpoint4, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 4, 0.04);
}
END_TEST

START_TEST(order_midpoint6_is_6) {
  sdae_options o = quartic_options(sdae_map_midpoint6, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 6, 0.2);
}
END_TEST

/* The classical Runge-Kutta method: order 4 (its order conditions are checked in multiple
 * precision by tools/stabdae_ref/tests/test_rk_order_conditions.py; here its implementation) */
START_TEST(order_rk4_is_4) {
  sdae_options o = quartic_options(sdae_map_rk4, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 4, 0.05);
}
END_TEST

/* DOP853's eighth-order solution on the quartic. Its principal error coefficients are so small
 * that on this problem the next term, C9 T^9, outweighs C8 T^8 at every step size whose error
 * double precision resolves: the global error is C8 T^8 (1 + x), x = (C9/C8) T, and the
 * two-point ratio 256 (1 + x)/(1 + x/2) lies between 256 and 512, reaching 256 only as T -> 0
 * (the same tableau in 50-digit arithmetic: 297 from T = 0.4, 315 from 0.2, 281 from 0.025,
 * 260 from 0.00625, where the error is 2e-23). So here the ratio from T = 0.4 (errors 1e-8
 * and 4e-11, far above rounding) is asserted between 256 and 512, within 10 %: a broken order
 * condition of order <= 8 gives at most 128. The ratio within 10 % of 256 is measured on the
 * rotation (check_time.c) and on the pendulum's small swing (check_mbs.c), whose errors are
 * those of a linear oscillator. */
START_TEST(order_rk8_is_8) {
  sdae_options o = quartic_options(sdae_map_rk8, SDAE_SCHEME_SEMI_IMPLICIT);
  double e1 = quartic_error(&o, 1.0, 2.0, 0.4), e2 = quartic_error(&o, 1.0, 2.0, 0.2);
  ck_assert_double_gt(e2, 1e-11);
  ck_assert_msg(e1 / e2 > 0.9 * 256.0 && e1 / e2 < 1.1 * 512.0, "error %g -> %g, ratio %g", e1, e2,
                e1 / e2);
}
END_TEST

/* The harmonic oscillator mu' = J mu, J = [[0, 1], [-1, 0]] (J^2 = -I), with one constraint
 * coordinate whose column of Q is e1 (unused on the manifold). */
static int harmonic_q0(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  out[0] = mu[1];
  out[1] = -mu[0];
  return 0;
}

static int harmonic_Q(double t, const double *xi, const double *mu, double *out, void *params) {
  (void)t, (void)xi, (void)mu, (void)params;
  out[0] = 1.0;
  out[1] = 0.0;
  return 0;
}

static sdae_model harmonic_model(void) {
  sdae_model m = {.n_xi = 1, .n_mu = 2, .q0 = harmonic_q0, .Q = harmonic_Q};
  return m;
}

/* Past its stability limit an explicit map is still the method: no status, the method's
 * number. RK4 on mu' = J mu multiplies by its stability polynomial R(TJ) = (1 - T^2/2 +
 * T^4/24) I + (T - T^3/6) J, |R(iT)| <= 1 only up to T = 2 sqrt(2). With T = 3, mu = (1, 0):
 * mu+ = (1 - 4.5 + 3.375, -(3 - 4.5)) = (-0.125, 1.5), |mu+| = 1.505 > 1. The intermediate
 * values are exact in binary but for the weights 1/6 and 1/3: 8 ulps allowed. DOP853's
 * polynomial has |R(iT)| <= 1 up to T = 5.96; at T = 8 one step grows the state (by 37, its
 * |R(8i)|), still with SDAE_OK. */
START_TEST(rk_past_stability_limit_is_the_method) {
  sdae_model m = harmonic_model();
  sdae_options o = quartic_options(sdae_map_rk4, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[1] = {0.0}, mu[2] = {1.0, 0.0};
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 3.0, xi, mu), SDAE_OK);
  ck_assert_double_le(fabs(mu[0] + 0.125), 8 * DBL_EPSILON);
  ck_assert_double_le(fabs(mu[1] - 1.5), 8 * DBL_EPSILON);
  sdae_stepper_free(s);

  o.map = sdae_map_rk8;
  mu[0] = 1.0, mu[1] = 0.0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 8.0, xi, mu), SDAE_OK);
  ck_assert_double_gt(hypot(mu[0], mu[1]), 10.0);
  sdae_stepper_free(s);
}
END_TEST

/* the quartic's q0, recording whether it was ever handed a non-finite state */
static int finite_args_only = 1;

static int watched_q0(double t, const double *mu, double *out, void *params) {
  if (!isfinite(mu[0]) || !isfinite(mu[1])) finite_args_only = 0;
  out[0] = mu[1];
  out[1] = -((quartic *)params)->k * mu[0] * mu[0] * mu[0];
  (void)t;
  return 0;
}

/* A step whose stages overflow: the cubic force makes each stage about the cube of the last,
 * so with T = 1e3 (rk8) or 1e100 (rk4) the values pass DBL_MAX within the step. The step
 * fails with SDAE_ERR_NONFINITE, xi and mu stay as they were bit for bit, and q0 is never
 * handed an Inf or NaN state. */
START_TEST(rk_overflow_is_nonfinite) {
  const sdae_map_type *maps[2] = {sdae_map_rk8, sdae_map_rk4};
  const double T[2] = {1e3, 1e100};
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  m.q0 = watched_q0;
  for (int i = 0; i < 2; i++) {
    sdae_options o = quartic_options(maps[i], SDAE_SCHEME_SEMI_IMPLICIT);
    sdae_stepper *s;
    double xi[2] = {0.0, 0.0}, mu[2] = {1.0, 0.0};
    finite_args_only = 1;
    ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
    ck_assert_int_eq(sdae_step(s, 0.0, T[i], xi, mu), SDAE_ERR_NONFINITE);
    ck_assert(xi[0] == 0.0 && xi[1] == 0.0 && mu[0] == 1.0 && mu[1] == 0.0);
    ck_assert(finite_args_only);
    sdae_stepper_free(s);
  }
}
END_TEST

/* The paper's Section IV map (the model's user map) for k = 1, d = 0 is the coordinate discrete
 * gradient of H: symmetric, so order 2. */
START_TEST(order_user_paper_map_is_2) {
  sdae_options o = quartic_options(sdae_map_user, SDAE_SCHEME_SEMI_IMPLICIT);
  expect_order(&o, 2, 0.02);
}
END_TEST

static double H_of(quartic *p, const double *mu) {
  double h;
  quartic_H(0.0, mu, &h, p);
  return h;
}

/* S skew: H(mu+) - H(mu) = T gradbar^T S gradbar = 0 up to rounding, over 1e5 steps; for dg4
 * and dg6 in each of their stages. Rounding accumulates per stage solve: at most 1e-13 per
 * 1e5 of them. (The midpoint map, which only approximates H, is off by 1.7e-5 here.) */
static void conserves_H(const sdae_map_type *map, int stages) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0, 0}, mu[2] = {1.0, 0.0}, H0 = H_of(&p, mu), worst = 0.0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  for (int n = 0; n < 100000; n++) {
    ck_assert_int_eq(sdae_step(s, n * 0.01, 0.01, xi, mu), SDAE_OK);
    worst = fmax(worst, rel_diff(H_of(&p, mu), H0));
  }
  ck_assert_double_le(worst, 1e-13 * stages);
  sdae_stepper_free(s);
}

START_TEST(dgrad_conserves_H) { conserves_H(sdae_map_dgrad, 1); }
END_TEST

START_TEST(dg4_conserves_H) { conserves_H(sdae_map_dg4, 3); }
END_TEST

START_TEST(dg6_conserves_H) { conserves_H(sdae_map_dg6, 9); }
END_TEST

/* Reference for the damped oscillator: GSL's rk8pd at tight tolerance. */
static int damped_rhs(double t, const double y[], double f[], void *params) {
  const quartic *p = params;
  (void)t;
  f[0] = y[1];
  f[1] = -p->k * y[0] * y[0] * y[0] - p->d * y[1];
  return GSL_SUCCESS;
}

/* S = J - R, R = diag(0, d) >= 0: H(mu+) - H(mu) = -T d gradbar_2^2 <= 0 every step; and H
 * follows the continuous decay to the map's second order. */
START_TEST(dgrad_dissipates_monotonically) {
  quartic p = {1.0, 0.1, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  gsl_odeiv2_system sys = {damped_rhs, NULL, 2, &p};
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-3, 1e-13, 0.0);
  sdae_stepper *s;
  double xi[2] = {0, 0}, mu[2] = {1.0, 0.0}, y[2] = {1.0, 0.0}, t = 0.0, T = 0.01;
  double H = H_of(&p, mu), H0 = H;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  for (int n = 0; n < 1000; n++) {
    ck_assert_int_eq(sdae_step(s, n * T, T, xi, mu), SDAE_OK);
    double Hn = H_of(&p, mu);
    ck_assert_double_le(Hn, H + 4e-16 * H0);
    H = Hn;
  }
  ck_assert_int_eq(gsl_odeiv2_driver_apply(d, &t, 10.0, y), GSL_SUCCESS);
  ck_assert_double_lt(H, 0.5 * H0);
  ck_assert_double_le(rel_diff(H, H_of(&p, y)), 1e-3);
  gsl_odeiv2_driver_free(d);
  sdae_stepper_free(s);
}
END_TEST

/* A map's context as the stepper hands it over, with scratch for a model of n_mu = 2. */
static sdae_map_ctx map_ctx(const sdae_model *m, const sdae_options *o) {
  static double work[64];
  ck_assert_uint_le(o->map->scratch(m, o), sizeof work / sizeof *work);
  return (sdae_map_ctx){m, work, NULL, 0, NULL};
}

/* The map itself, through the internal table: when |mu+ - mu| is below sqrt(eps), gradbar H
 * is grad H(mid) (H is not called, phi = S grad H(mid) = q0(mid)); otherwise the difference
 * quotient makes gradbar . v = H(mu+) - H(mu), with gradbar = S^-1 phi = J^T phi for S = J. */
START_TEST(dgrad_small_increment_branch) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  double x[2] = {0.8, 0.3}, near[2] = {0.8 + 1e-10, 0.3 - 1e-10}, far[2] = {0.9, 0.1};
  double phi[2], q0mid[2], Hx, Hy;
  sdae_map_ctx c = map_ctx(&m, &o);
  ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.0, 0.1, x, near, phi), SDAE_OK);
  ck_assert_int_eq(p.H_calls, 0);
  double mid[2] = {0.5 * (x[0] + near[0]), 0.5 * (x[1] + near[1])};
  ck_assert_int_eq(m.q0(0.0, mid, q0mid, &p), 0);
  ck_assert_double_eq(phi[0], q0mid[0]);
  ck_assert_double_eq(phi[1], q0mid[1]);

  ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.0, 0.1, x, far, phi), SDAE_OK);
  ck_assert_int_eq(p.H_calls, 2);
  double gradbar_v = -phi[1] * (far[0] - x[0]) + phi[0] * (far[1] - x[1]);
  quartic_H(0.0, x, &Hx, &p);
  quartic_H(0.0, far, &Hy, &p);
  ck_assert_double_le(fabs(gradbar_v - (Hy - Hx)), 1e-16);
}
END_TEST

/* An H with a coupling term and time in its Hessian, so that the Jacobian's index order and
 * time argument are exercised: H = mu2^2/2 + k mu1^4/4 + mu1^2 mu2/2 + t mu1^2/2. */
static int coupled_H(double t, const double *mu, double *out, void *params) {
  const quartic *p = params;
  double a = mu[0], b = mu[1];
  out[0] = 0.5 * b * b + 0.25 * p->k * a * a * a * a + 0.5 * a * a * b + 0.5 * t * a * a;
  return 0;
}

static int coupled_grad_H(double t, const double *mu, double *out, void *params) {
  const quartic *p = params;
  double a = mu[0], b = mu[1];
  out[0] = p->k * a * a * a + a * b + t * a;
  out[1] = b + 0.5 * a * a;
  return 0;
}

static int coupled_hess_H(double t, const double *mu, double *out, void *params) {
  const quartic *p = params;
  double a = mu[0], b = mu[1];
  out[0] = 3.0 * p->k * a * a + b + t;
  out[1] = out[2] = a;
  out[3] = 1.0;
  return 0;
}

/* The Jacobian from hess_H, called after phi at the same point as Newton does. Far from mu,
 * against central differences of phi with step h = 1e-6 (truncation h^2 phi''' about 1e-12,
 * rounding eps/h about 1e-10). Within the small-increment branch, where phi = S grad H(mid),
 * it is (1/2) S hess H(mid) exactly (differences there would see the rounding of the
 * quotient c, eps |H| / h^2). t = 0.3, T = 0.1: H, S and hess H at mid time 0.35. With S dense
 * and with S_apply. */
static void jacobian_matches_differences(int use_S_apply) {
  quartic p = {1.0, 0.1, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  double x[2] = {0.8, 0.3}, far[2] = {0.9, 0.1}, near[2] = {0.8 + 1e-10, 0.3 - 1e-10};
  double J[4], phi[2], plus[2], minus[2], y[2], h = 1e-6, mid[2], Hm[4];
  m.H = coupled_H, m.grad_H = coupled_grad_H, m.hess_H = coupled_hess_H;
  if (use_S_apply) m.S = NULL, m.S_apply = quartic_S_apply;
  sdae_map_ctx c = map_ctx(&m, &o);
  ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.3, 0.1, x, far, phi), SDAE_OK);
  ck_assert_int_eq(sdae_map_dgrad->jac(&c, 0.3, 0.1, x, far, J), SDAE_OK);
  for (int j = 0; j < 2; j++) {
    y[0] = far[0], y[1] = far[1];
    y[j] += h;
    ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.3, 0.1, x, y, plus), SDAE_OK);
    y[j] -= 2 * h;
    ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.3, 0.1, x, y, minus), SDAE_OK);
    for (int i = 0; i < 2; i++)
      ck_assert_double_le(fabs(J[i * 2 + j] - (plus[i] - minus[i]) / (2 * h)), 1e-8);
  }
  ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.3, 0.1, x, near, phi), SDAE_OK);
  ck_assert_int_eq(sdae_map_dgrad->jac(&c, 0.3, 0.1, x, near, J), SDAE_OK);
  mid[0] = 0.5 * (x[0] + near[0]), mid[1] = 0.5 * (x[1] + near[1]);
  coupled_hess_H(0.35, mid, Hm, &p);
  for (int j = 0; j < 2; j++) { /* S = [[0, 1], [-1, -d]] */
    ck_assert_double_eq_tol(J[j], 0.5 * Hm[2 + j], 1e-15);
    ck_assert_double_eq_tol(J[2 + j], 0.5 * (-Hm[j] - p.d * Hm[2 + j]), 1e-15);
  }
}

START_TEST(dgrad_jacobian_matches_differences) { jacobian_matches_differences(0); }
END_TEST

START_TEST(dgrad_jacobian_with_S_apply) { jacobian_matches_differences(1); }
END_TEST

/* Newton with the closed-form Jacobian reaches the same mu+ (to the Newton tolerance) with
 * fewer evaluations of phi: finite differences cost 2 n = 4 per Jacobian. */
START_TEST(dgrad_hessian_spares_evaluations) {
  quartic p = {1.0, 0.1, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *fd, *an;
  double xi[2] = {0.1, -0.2}, mu[2] = {0.8, 0.3}, xi2[2] = {0.1, -0.2}, mu2[2] = {0.8, 0.3};
  ck_assert_int_eq(sdae_stepper_alloc(&fd, &m, &o), SDAE_OK);
  m.hess_H = quartic_hess_H;
  ck_assert_int_eq(sdae_stepper_alloc(&an, &m, &o), SDAE_OK);
  for (int n = 0; n < 100; n++) {
    ck_assert_int_eq(sdae_step(fd, n * 0.05, 0.05, xi, mu), SDAE_OK);
    ck_assert_int_eq(sdae_step(an, n * 0.05, 0.05, xi2, mu2), SDAE_OK);
  }
  for (int i = 0; i < 2; i++) {
    ck_assert_double_le(fabs(mu[i] - mu2[i]), 1e-13);
    ck_assert_double_le(fabs(xi[i] - xi2[i]), 1e-13);
  }
  ck_assert_uint_lt(sdae_stepper_stats(an)->phi_evals, sdae_stepper_stats(fd)->phi_evals / 2);
  sdae_stepper_free(fd);
  sdae_stepper_free(an);
}
END_TEST

/* Every map is found by its own name, and declares the order of accuracy its construction gives
 * (euler 1; midpoint and Gonzalez's discrete gradient 2, both symmetric; the triple jump 4;
 * s9odr6a 6, with either base; the classical Runge-Kutta method 4, DOP853's solution 8); the
 * order tests above measure the same numbers. */
START_TEST(maps_by_name_and_order) {
  const sdae_map_type *maps[10] = {
      sdae_map_euler, sdae_map_midpoint,  sdae_map_dgrad,     sdae_map_user, sdae_map_dg4,
      sdae_map_dg6,   sdae_map_midpoint4, sdae_map_midpoint6, sdae_map_rk4,  sdae_map_rk8};
  const unsigned order[10] = {1, 2, 2, 0, 4, 6, 4, 6, 4, 8};
  for (int i = 0; i < 10; i++) {
    ck_assert_ptr_eq(sdae_map_by_name(sdae_map_name(maps[i])), maps[i]);
    ck_assert_uint_eq(sdae_map_order(maps[i]), order[i]);
  }
  ck_assert_ptr_null(sdae_map_by_name("dg"));
  ck_assert_ptr_null(sdae_map_by_name(NULL));
  ck_assert_str_eq(sdae_map_name(NULL), "(none)");
  ck_assert_uint_eq(sdae_map_order(NULL), 0);
}
END_TEST

/* The small-increment branch's threshold |v|^2 <= eps (1 + |m|^2), m the midpoint, at its
 * boundary, in exact binary (H is called twice, for H(mu) and H(mu+), outside the branch):
 *  - m = 0, v = (2^-26, 0): |v|^2 = 2^-52 = eps (1 + 0), on the boundary: not called;
 *  - m = 0, v = (2^-26, 2^-40): |v|^2 = 2^-52 + 2^-80, just above: called;
 *  - m = (1, 0), v = (2^-26, 2^-26): |v|^2 = 2^-51 = eps (1 + 1), on the boundary: not called. */
START_TEST(dgrad_small_increment_threshold) {
  const double x[3][2] = {{-0x1p-27, 0.0}, {-0x1p-27, -0x1p-41}, {1.0 - 0x1p-27, -0x1p-27}};
  const double y[3][2] = {{0x1p-27, 0.0}, {0x1p-27, 0x1p-41}, {1.0 + 0x1p-27, 0x1p-27}};
  const long calls[3] = {0, 2, 0};
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_map_ctx c = map_ctx(&m, &o);
  double phi[2];
  for (int k = 0; k < 3; k++) {
    p.H_calls = 0;
    ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.0, 0.1, x[k], y[k], phi), SDAE_OK);
    ck_assert_int_eq(p.H_calls, calls[k]);
  }
}
END_TEST

/* H depending on t is evaluated at the map's one time, t + T/2 (as grad H and S): the discrete
 * gradient property gradbar . v = H(tm, mu+) - H(tm, mu) holds with tm = 0.35 for t = 0.3,
 * T = 0.1 (coupled_H's t mu1^2/2 term makes any other time of H(mu) or H(mu+) miss by
 * 0.32 or more here). S = J (d = 0), so gradbar = J^T phi. */
START_TEST(dgrad_time_dependent_H_at_mid_time) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  double x[2] = {0.8, 0.3}, far[2] = {0.9, 0.1}, phi[2], Hx, Hy;
  m.H = coupled_H, m.grad_H = coupled_grad_H;
  sdae_map_ctx c = map_ctx(&m, &o);
  ck_assert_int_eq(sdae_map_dgrad->phi(&c, 0.3, 0.1, x, far, phi), SDAE_OK);
  double gradbar_v = -phi[1] * (far[0] - x[0]) + phi[0] * (far[1] - x[1]);
  coupled_H(0.35, x, &Hx, &p);
  coupled_H(0.35, far, &Hy, &p);
  ck_assert_double_le(fabs(gradbar_v - (Hy - Hx)), 1e-15);
}
END_TEST

/* The midpoint map's Jacobian: d q0((mu + mu+)/2) / d mu+ = q0'(mid) / 2 (chain rule), every
 * entry halved exactly, here with the damping -d in the last entry (d = 0.1); and against
 * central differences of phi (h = 1e-6: truncation h^2 |d3 q0| / 6, rounding eps / h). */
START_TEST(midpoint_jacobian_is_half_q0_jac) {
  quartic p = {1.0, 0.1, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  const double x[2] = {0.8, 0.3}, y0[2] = {0.9, 0.1}, h = 1e-6;
  const double mid[2] = {0.5 * (x[0] + y0[0]), 0.5 * (x[1] + y0[1])};
  double J[4], Jq[4], plus[2], minus[2], y[2];
  sdae_map_ctx c = map_ctx(&m, &o);
  ck_assert_int_eq(sdae_map_midpoint->phi(&c, 0.0, 0.1, x, y0, plus), SDAE_OK);
  ck_assert_int_eq(sdae_map_midpoint->jac(&c, 0.0, 0.1, x, y0, J), SDAE_OK);
  quartic_q0_jac(0.05, mid, Jq, &p);
  for (int i = 0; i < 4; i++) ck_assert_double_eq(J[i], 0.5 * Jq[i]);
  ck_assert_double_eq(J[3], -0.05); /* -d / 2 */
  for (int j = 0; j < 2; j++) {
    y[0] = y0[0], y[1] = y0[1];
    y[j] += h;
    ck_assert_int_eq(sdae_map_midpoint->phi(&c, 0.0, 0.1, x, y, plus), SDAE_OK);
    y[j] -= 2 * h;
    ck_assert_int_eq(sdae_map_midpoint->phi(&c, 0.0, 0.1, x, y, minus), SDAE_OK);
    for (int i = 0; i < 2; i++)
      ck_assert_double_le(fabs(J[i * 2 + j] - (plus[i] - minus[i]) / (2 * h)), 1e-8);
  }
}
END_TEST

/* The user's map and its Jacobian writing NaN or Inf: the map itself reports
 * SDAE_ERR_NONFINITE (as for every callback), whatever Newton would make of the values. */
static int nan_user_phi(double t, double T, const double *mu, const double *y, double *out,
                        void *params) {
  (void)t, (void)T, (void)mu, (void)y, (void)params;
  out[0] = 0.5, out[1] = NAN;
  return 0;
}

static int inf_user_jac(double t, double T, const double *mu, const double *y, double *out,
                        void *params) {
  (void)t, (void)T, (void)mu, (void)y, (void)params;
  out[0] = out[1] = out[2] = 0.0, out[3] = INFINITY;
  return 0;
}

START_TEST(user_map_nonfinite_is_reported) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_map_ctx c = {&m, NULL, NULL, 0, NULL};
  const double x[2] = {0.8, 0.3}, y[2] = {0.9, 0.1};
  double out[4];
  ck_assert_int_eq(sdae_map_user->phi(&c, 0.0, 0.1, x, y, out), SDAE_OK); /* the paper's map */
  m.user_phi = nan_user_phi, m.user_phi_jac = inf_user_jac;
  ck_assert_int_eq(sdae_map_user->phi(&c, 0.0, 0.1, x, y, out), SDAE_ERR_NONFINITE);
  ck_assert_int_eq(sdae_map_user->jac(&c, 0.0, 0.1, x, y, out), SDAE_ERR_NONFINITE);
}
END_TEST

int main(void) {
  Suite *s = suite_create("maps");
  ADD_CASE(s, maps_by_name_and_order);
  ADD_CASE(s, order_euler_is_1);
  ADD_CASE(s, order_midpoint_is_2);
  ADD_CASE(s, order_dgrad_is_2);
  ADD_CASE(s, order_dg4_is_4);
  ADD_CASE(s, order_midpoint4_is_4);
  ADD_CASE(s, order_midpoint6_is_6);
  ADD_CASE(s, order_dg6_is_6);
  ADD_CASE(s, order_rk4_is_4);
  ADD_CASE(s, order_rk8_is_8);
  ADD_CASE(s, rk_past_stability_limit_is_the_method);
  ADD_CASE(s, rk_overflow_is_nonfinite);
  ADD_CASE(s, order_user_paper_map_is_2);
  ADD_CASE(s, dgrad_conserves_H);
  ADD_CASE(s, dg4_conserves_H);
  ADD_CASE(s, dg6_conserves_H);
  ADD_CASE(s, dgrad_dissipates_monotonically);
  ADD_CASE(s, dgrad_small_increment_branch);
  ADD_CASE(s, dgrad_jacobian_matches_differences);
  ADD_CASE(s, dgrad_jacobian_with_S_apply);
  ADD_CASE(s, dgrad_hessian_spares_evaluations);
  ADD_CASE(s, dgrad_small_increment_threshold);
  ADD_CASE(s, dgrad_time_dependent_H_at_mid_time);
  ADD_CASE(s, midpoint_jacobian_is_half_q0_jac);
  ADD_CASE(s, user_map_nonfinite_is_reported);
  return run_suite(s);
}
