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

#include "mechanisms.h"
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
  double gamma =
      2.0 * (-w * cw * v[0] - w * sw * v[1]) + w * w * (sw * q[0] - cw * q[1]) + a * sin(t);
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
static double error_at(const sdae_mbs *sys, const sdae_map_type *map, sdae_scheme scheme, double T,
                       double tf, double *max_c) {
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
static void expect_order(int derivatives, const sdae_map_type *map, sdae_scheme scheme, double T,
                         unsigned p) {
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

/* Every map that evaluates H (the discrete gradient and its compositions) is refused on the
 * moving wire; the midpoint maps, which need q0 only, are not. */
START_TEST(every_energy_map_refused_on_moving_constraint) {
  const sdae_map_type *maps[5] = {sdae_map_dgrad, sdae_map_dg4, sdae_map_dg6, sdae_map_midpoint,
                                  sdae_map_midpoint4};
  const int want[5] = {SDAE_ERR_MAP, SDAE_ERR_MAP, SDAE_ERR_MAP, SDAE_OK, SDAE_OK};
  for (int i = 0; i < 5; i++) {
    sdae_mbs sys = bead(1);
    sdae_options o;
    sdae_mbs_stepper *s;
    double q[2], v[2];
    sys.potential = potential;
    sdae_options_default(&o);
    o.map = maps[i];
    memcpy(q, q_start, sizeof q), memcpy(v, v_start, sizeof v);
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_step(s, 0.0, 0.01, q, v), want[i]);
    sdae_mbs_stepper_free(s);
  }
}
END_TEST

/* ---- late times: the differences in t scale with max(1, |t|) ---- */

static const mech_pendulum PENDULUM = {.L = 1.0, .m = 1.0, .ga = 9.81, .d = 0.0};

/* The pendulum does not depend on t, so its xi, its multiplier and a step are the same at
 * t = 1e15 as at t = 0 (dc/dt = 0 exactly). At 1e15 the spacing of the doubles is 0.125: a
 * difference step in t below that vanishes. */
START_TEST(time_independent_at_late_time) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  sdae_options o;
  sdae_mbs_stepper *s;
  const double late = 1e15;
  double q[2], v[2], q0[2], v0[2], q1[2], v1[2], xi0[2], xi1[2], lam0, lam1;
  mech_pendulum_system(&sys, &p);
  sdae_options_default(&o);
  o.map = sdae_map_midpoint;
  mech_pendulum_state(&p, 0.4, 0.7, q, v);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_xi(s, 0.0, q, v, xi0), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_xi(s, late, q, v, xi1), SDAE_OK);
  for (int i = 0; i < 2; i++) ck_assert_double_le(fabs(xi1[i] - xi0[i]), 1e-15);
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.0, q, v, &lam0), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_lambda(s, late, q, v, &lam1), SDAE_OK);
  ck_assert_double_le(fabs(lam1 - lam0), 1e-12 * fabs(lam0));
  ck_assert_double_le(fabs(lam0 - mech_pendulum_lambda(&p, 0.4, 0.7)), 1e-10);
  memcpy(q0, q, sizeof q), memcpy(v0, v, sizeof v);
  memcpy(q1, q, sizeof q), memcpy(v1, v, sizeof v);
  for (int n = 0; n < 10; n++) {
    ck_assert_int_eq(sdae_mbs_step(s, 0.01 * n, 0.01, q0, v0), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_step(s, late + 0.01 * n, 0.01, q1, v1), SDAE_OK);
  }
  for (int i = 0; i < 2; i++) {
    ck_assert_double_le(fabs(q1[i] - q0[i]), 1e-13);
    ck_assert_double_le(fabs(v1[i] - v0[i]), 1e-13);
  }
  ck_assert_double_le(fabs(q1[0] * q1[0] + q1[1] * q1[1] - 1.0), 1e-15);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* the same from the largest times: 20 steps from t0 = 1.7e308 as from t0 = 0 */
START_TEST(integrate_from_the_largest_times) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  sdae_options o;
  sdae_mbs_stepper *s;
  double q0[2], v0[2], q1[2], v1[2];
  size_t done = 0;
  mech_pendulum_system(&sys, &p);
  sdae_options_default(&o);
  o.map = sdae_map_dgrad;
  mech_pendulum_state(&p, 0.4, 0.7, q0, v0);
  memcpy(q1, q0, sizeof q0), memcpy(v1, v0, sizeof v0);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_integrate(s, 0.0, 0.01, 20, 20, q0, v0, NULL, NULL, NULL), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_integrate(s, 1.7e308, 0.01, 20, 20, q1, v1, NULL, NULL, &done),
                   SDAE_OK);
  ck_assert_uint_eq(done, 20);
  for (int i = 0; i < 2; i++) {
    ck_assert_double_le(fabs(q1[i] - q0[i]), 1e-13);
    ck_assert_double_le(fabs(v1[i] - v0[i]), 1e-13);
  }
  sdae_mbs_stepper_free(s);
}
END_TEST

/* A driven particle q = (x, y, z), c = (x - a t, y - sqrt(t)), dc/dt = (-a, -1/(2 sqrt t)),
 * left to the library's difference in t. At t = 1e15 its step, 7.4e-4 t, is as relative to t
 * as it is to 1 at t = 1: the difference of a t is exact but for the rounding of c (about
 * eps a t / step = 3e-13 a), that of sqrt(t) good to (step / t)^4 = 3e-13 relative. */
static const double drive_a = 0.5;

static int drive_mass(double t, const double *q, double *M, void *params) {
  (void)t, (void)q, (void)params;
  for (int i = 0; i < 9; i++) M[i] = i % 4 == 0 ? 1.0 : 0.0;
  return 0;
}

static int drive_force(double t, const double *q, const double *v, double *F, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  F[0] = F[1] = F[2] = 0.0;
  return 0;
}

static int drive_constraint(double t, const double *q, double *c, void *params) {
  (void)params;
  c[0] = q[0] - drive_a * t;
  c[1] = q[1] - sqrt(t);
  return 0;
}

START_TEST(moving_constraint_at_late_time) {
  sdae_mbs sys = {
      .n_q = 3, .n_c = 2, .mass = drive_mass, .force = drive_force, .constraint = drive_constraint};
  sdae_options o;
  sdae_mbs_stepper *s;
  const double late = 1e15;
  double q[3] = {drive_a * late, sqrt(late), 0.0}, v[3] = {0.0, 0.0, 0.0}, xi[4];
  double want = -0.5 / sqrt(late);
  sdae_options_default(&o);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_xi(s, late, q, v, xi), SDAE_OK);
  ck_assert_double_le(fabs(xi[1] + drive_a), 1e-11 * drive_a);
  ck_assert_double_le(fabs(xi[3] - want), 1e-11 * fabs(want));
  sdae_mbs_stepper_free(s);
}
END_TEST

/* A line through the origin turning at w = 3, c = x sin(w t) - y cos(w t), without constraint_t:
 * dc/dt = w (x cos(w t) + y sin(w t)) by differences in t, as accurate at t = 1e3 as at 1 (the
 * driver's period does not grow with t, so neither may the step): xi's velocity part
 * G v + dc/dt within 1e-9 of the closed form. */
static int turn_mass(double t, const double *q, double *M, void *params) {
  (void)t, (void)q, (void)params;
  M[0] = M[3] = 1.0, M[1] = M[2] = 0.0;
  return 0;
}
static int turn_force(double t, const double *q, const double *v, double *F, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  F[0] = F[1] = 0.0;
  return 0;
}
static int turn_constraint(double t, const double *q, double *c, void *params) {
  (void)params;
  c[0] = q[0] * sin(3.0 * t) - q[1] * cos(3.0 * t);
  return 0;
}
static int turn_jacobian(double t, const double *q, double *G, void *params) {
  (void)q, (void)params;
  G[0] = sin(3.0 * t), G[1] = -cos(3.0 * t);
  return 0;
}

START_TEST(turning_constraint_at_moderate_times) {
  sdae_mbs sys = {.n_q = 2,
                  .n_c = 1,
                  .mass = turn_mass,
                  .force = turn_force,
                  .constraint = turn_constraint,
                  .jacobian = turn_jacobian};
  sdae_options o;
  sdae_mbs_stepper *s;
  const double ts[4] = {1.0, 10.7, 100.7, 1000.7}, q[2] = {0.8, -0.35}, v[2] = {-1.3, 0.9};
  sdae_options_default(&o);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  for (int i = 0; i < 4; i++) {
    double xi[2], t = ts[i], w = 3.0;
    double exact =
        sin(w * t) * v[0] - cos(w * t) * v[1] + w * (q[0] * cos(w * t) + q[1] * sin(w * t));
    ck_assert_int_eq(sdae_mbs_xi(s, t, q, v, xi), SDAE_OK);
    ck_assert_double_eq_tol(xi[1], exact, 1e-9 * (1.0 + fabs(exact)));
  }
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
  ADD_CASE(s, every_energy_map_refused_on_moving_constraint);
  ADD_CASE(s, time_independent_at_late_time);
  ADD_CASE(s, integrate_from_the_largest_times);
  ADD_CASE(s, moving_constraint_at_late_time);
  ADD_CASE(s, turning_constraint_at_moderate_times);
  return run_suite(s);
}
