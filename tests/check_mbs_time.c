/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanical front-end with time everywhere: a bead of mass m(t) = 1 + 0.3 sin 2t on a wire
 * that turns at rate w and shifts, c(t, q) = -sin(w t) x + cos(w t) y - a sin t, pulled to the
 * origin by a spring k and by a force -g0 (1 + sin t / 2) along y. A wrong time in the mass, the
 * constraint, its derivatives or the step changes the trajectory; the reference is the index-1
 * ODE M v' = F - G^T lambda with lambda from G v' + gamma = 0 (gamma in closed form here),
 * integrated by GSL's rk8pd to 1e-13. */
#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <stabdae/mbs.h>

#include "testmodels.h"

static const double w = 1.5, a = 0.2, k = 2.0, g0 = 1.0;

static double mass_of(double t) { return 1.0 + 0.3 * sin(2.0 * t); }

static int mass(double t, const double *q, double *M, void *p) {
  (void)q, (void)p;
  M[0] = M[3] = mass_of(t);
  M[1] = M[2] = 0.0;
  return 0;
}

static int force(double t, const double *q, const double *v, double *F, void *p) {
  (void)v, (void)p;
  F[0] = -k * q[0];
  F[1] = -k * q[1] - g0 * (1.0 + 0.5 * sin(t));
  return 0;
}

static int constraint(double t, const double *q, double *c, void *p) {
  (void)p;
  c[0] = -sin(w * t) * q[0] + cos(w * t) * q[1] - a * sin(t);
  return 0;
}

static int jacobian(double t, const double *q, double *G, void *p) {
  (void)q, (void)p;
  G[0] = -sin(w * t);
  G[1] = cos(w * t);
  return 0;
}

static int constraint_t(double t, const double *q, double *ct, void *p) {
  (void)p;
  ct[0] = -w * cos(w * t) * q[0] - w * sin(w * t) * q[1] - a * cos(t);
  return 0;
}

static int potential(double t, const double *q, double *V, void *p) {
  (void)t, (void)p;
  *V = 0.5 * k * (q[0] * q[0] + q[1] * q[1]) + g0 * q[1];
  return 0;
}

/* lambda = G F + m gamma (M = m I, |G| = 1), gamma = d/dt (G v + dc/dt) with v fixed */
static double lambda_exact(double t, const double *q, const double *v) {
  double cw = cos(w * t), sw = sin(w * t);
  double gamma = 2.0 * (-w * cw * v[0] - w * sw * v[1]) + w * w * (sw * q[0] - cw * q[1]) +
                 a * sin(t);
  double F[2];
  force(t, q, v, F, NULL);
  return -sw * F[0] + cw * F[1] + mass_of(t) * gamma;
}

static int ode(double t, const double y[], double dy[], void *p) {
  double G[2], F[2], lam = lambda_exact(t, y, y + 2), m = mass_of(t);
  (void)p;
  jacobian(t, y, G, NULL);
  force(t, y, y + 2, F, NULL);
  dy[0] = y[2], dy[1] = y[3];
  dy[2] = (F[0] - G[0] * lam) / m;
  dy[3] = (F[1] - G[1] * lam) / m;
  return GSL_SUCCESS;
}

/* on the constraints at t = 0: y = 0, and G v + dc/dt = v_y - w x - a = 0 */
static const double q_start[2] = {0.5, 0.0}, v_start[2] = {0.3, 1.5 * 0.5 + 0.2};

static void reference(double tf, double *y) {
  gsl_odeiv2_system sys = {ode, NULL, 4, NULL};
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-3, 1e-14, 1e-14);
  double t = 0.0;
  memcpy(y, q_start, sizeof q_start);
  memcpy(y + 2, v_start, sizeof v_start);
  ck_assert_int_eq(gsl_odeiv2_driver_apply(d, &t, tf, y), GSL_SUCCESS);
  gsl_odeiv2_driver_free(d);
}

static sdae_mbs bead(int derivatives) {
  sdae_mbs sys = {.n_q = 2, .n_c = 1, .mass = mass, .force = force, .constraint = constraint};
  if (derivatives) sys.jacobian = jacobian, sys.constraint_t = constraint_t;
  return sys;
}

/* |q - q_ref| at tf after tf / T steps; the largest |c| on the way */
static double error_at(const sdae_mbs *sys, const sdae_map_type *map, sdae_scheme scheme,
                       double T, double tf, double *max_c) {
  sdae_options o;
  sdae_mbs_stepper *s;
  double q[2], v[2], ref[4], c;
  size_t n = (size_t)llround(tf / T);
  sdae_options_default(&o);
  o.map = map, o.scheme = scheme;
  memcpy(q, q_start, sizeof q), memcpy(v, v_start, sizeof v);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, sys, &o), SDAE_OK);
  *max_c = 0.0;
  for (size_t i = 0; i < n; i++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)i * T, T, q, v), SDAE_OK);
    constraint((double)(i + 1) * T, q, &c, NULL);
    *max_c = fmax(*max_c, fabs(c));
  }
  sdae_mbs_stepper_free(s);
  reference(tf, ref);
  return hypot(q[0] - ref[0], q[1] - ref[1]);
}

/* the error ratio for T and T/2 is 2^p within 10 %; the constraint at rounding throughout */
static void expect_order(int derivatives, const sdae_map_type *map, sdae_scheme scheme,
                         double T, unsigned p) {
  sdae_mbs sys = bead(derivatives);
  double c1, c2, e1 = error_at(&sys, map, scheme, T, 1.0, &c1);
  double e2 = error_at(&sys, map, scheme, 0.5 * T, 1.0, &c2), want = ldexp(1.0, (int)p);
  ck_assert_double_gt(e1 / e2, 0.9 * want);
  ck_assert_double_lt(e1 / e2, 1.1 * want);
  ck_assert_double_le(fmax(c1, c2), 1e-13);
}

START_TEST(euler_order_1) { expect_order(1, sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT, 0.005, 1); }
END_TEST

START_TEST(midpoint_order_2) {
  expect_order(1, sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT, 0.02, 2);
}
END_TEST

START_TEST(midpoint_order_2_scheme_11) {
  expect_order(1, sdae_map_midpoint, SDAE_SCHEME_EXPLICIT, 0.02, 2);
}
END_TEST

/* without jacobian and constraint_t: G and dc/dt by the library's differences */
START_TEST(midpoint_order_2_differences) {
  expect_order(0, sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT, 0.02, 2);
}
END_TEST

/* lambda at the reference's state at t = 1 against its closed form: exact derivatives leave
 * the rounding of the fourth-order difference along the motion (1e-12); without them the
 * differences are nested (dc/dt inside the derivative along the motion): 1e-9 */
static void expect_lambda(int derivatives, double tol) {
  sdae_mbs sys = bead(derivatives);
  sdae_options o;
  sdae_mbs_stepper *s;
  double y[4], lam, want;
  sdae_options_default(&o);
  reference(1.0, y);
  want = lambda_exact(1.0, y, y + 2);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_lambda(s, 1.0, y, y + 2, &lam), SDAE_OK);
  ck_assert_double_le(fabs(lam - want), tol * fabs(want));
  sdae_mbs_stepper_free(s);
}

START_TEST(lambda_exact_derivatives) { expect_lambda(1, 1e-12); }
END_TEST

START_TEST(lambda_differences) { expect_lambda(0, 1e-9); }
END_TEST

/* xi at the reference's state: c = 0 and G v + dc/dt = 0 along the exact motion */
START_TEST(xi_vanishes_on_the_motion) {
  sdae_mbs sys = bead(0);
  sdae_options o;
  sdae_mbs_stepper *s;
  double y[4], xi[2];
  sdae_options_default(&o);
  reference(0.8, y);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_xi(s, 0.8, y, y + 2, xi), SDAE_OK);
  ck_assert_double_le(fabs(xi[0]), 1e-13);
  ck_assert_double_le(fabs(xi[1]), 1e-10);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* the discrete gradients conserve an energy that a moving wire does not: refused at the step,
 * the state untouched */
START_TEST(energy_map_refused_on_moving_constraint) {
  sdae_mbs sys = bead(1);
  sdae_options o;
  sdae_mbs_stepper *s;
  double q[2], v[2];
  sys.potential = potential;
  sdae_options_default(&o);
  o.map = sdae_map_dgrad;
  memcpy(q, q_start, sizeof q), memcpy(v, v_start, sizeof v);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 0.01, q, v), SDAE_ERR_MAP);
  ck_assert_mem_eq(q, q_start, sizeof q);
  ck_assert_mem_eq(v, v_start, sizeof v);
  ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->step.steps, 0);
  sdae_mbs_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs_time");
  ADD_CASE(s, euler_order_1);
  ADD_CASE(s, midpoint_order_2);
  ADD_CASE(s, midpoint_order_2_scheme_11);
  ADD_CASE(s, midpoint_order_2_differences);
  ADD_CASE(s, lambda_exact_derivatives);
  ADD_CASE(s, lambda_differences);
  ADD_CASE(s, xi_vanishes_on_the_motion);
  ADD_CASE(s, energy_map_refused_on_moving_constraint);
  return run_suite(s);
}
