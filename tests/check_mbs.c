/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanical front-end (<stabdae/mbs.h>) against the mathematics of its mechanisms
 * (examples/models/mechanisms.h, tests/fixtures/wire.h): orders of convergence against exact
 * solutions (the pendulum's Jacobi elliptic swing, the bead on a rotating wire), multipliers
 * against the exact rod tension and wire reaction, the energy kept by the discrete gradient
 * through chart switches, the decay of xi by the gains of eq. 6, dissipation with damping, the
 * chart rule, and the wire's derivatives along the motion by sdae_mbs_check. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "mechanisms.h"
#include "testmodels.h"
#include "wire.h"

static sdae_options options(const sdae_map_type *map, sdae_scheme scheme) {
  sdae_options o;
  sdae_options_default(&o);
  o.map = map;
  o.scheme = scheme;
  return o;
}

static sdae_mbs_stepper *stepper(const sdae_mbs *sys, const sdae_options *o) {
  sdae_mbs_stepper *s = NULL;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, sys, o), SDAE_OK);
  return s;
}

/* ---- orders: the pendulum against its exact swing ---- */

static const mech_pendulum PENDULUM = {.L = 1.0, .m = 1.0, .ga = 9.81};

/* Max-norm error in (q, v) at tf of the swing from rest at theta0, n = tf/T steps. */
static double pendulum_error(const sdae_mbs *sys, const sdae_options *o, double theta0, double tf,
                             double T) {
  const mech_pendulum *p = sys->params;
  sdae_mbs_stepper *s = stepper(sys, o);
  double q[2], v[2], qe[2], ve[2], th, om;
  size_t n = (size_t)lround(tf / T);
  mech_pendulum_state(p, theta0, 0.0, q, v);
  ck_assert_int_eq(sdae_mbs_integrate(s, 0.0, T, n, n, q, v, NULL, NULL, NULL), SDAE_OK);
  sdae_mbs_stepper_free(s);
  mech_pendulum_exact(p, theta0, tf, &th, &om);
  mech_pendulum_state(p, th, om, qe, ve);
  return fmax(max_abs_diff(q, qe, 2), max_abs_diff(v, ve, 2));
}

/* The error divides by 2^p when T halves, within 10 %: p = 1 (euler), 2 (midpoint, dgrad),
 * 4 (dg4, midpoint4, rk4), 6 (midpoint6), 8 (rk8). The chart of the pendulum is q_D = y
 * while |x/y| = tan theta is below 1.5 times |y/x| = cot theta, i.e. tan theta < 1.22: a
 * swing of theta0 = 0.5 (tan 0.55) never switches, one of theta0 = 1 switches four times in
 * 2 s. tf = 2 s is past a half-period (about 1.0 s). The errors stay far above the front-end's
 * difference quotients (about 1e-12): asserted above 1e-9. */
static void expect_pendulum_order_from(const sdae_mbs *sys, const sdae_map_type *map, unsigned p,
                                       double theta0, double T) {
  sdae_options o = options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  double e1 = pendulum_error(sys, &o, theta0, 2.0, T);
  double e2 = pendulum_error(sys, &o, theta0, 2.0, T / 2);
  double ratio = e1 / e2, want = ldexp(1.0, (int)p);
  ck_assert_double_gt(e2, 1e-9);
  ck_assert_msg(fabs(ratio / want - 1.0) <= 0.1, "%s: error %g -> %g, ratio %g, want %g",
                sdae_map_name(map), e1, e2, ratio, want);
}

static void expect_pendulum_order(const sdae_mbs *sys, const sdae_map_type *map, unsigned p,
                                  double T) {
  expect_pendulum_order_from(sys, map, p, 0.5, T);
}

START_TEST(pendulum_order_euler) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order(&sys, sdae_map_euler, 1, 2e-3);
}
END_TEST

START_TEST(pendulum_order_midpoint) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order(&sys, sdae_map_midpoint, 2, 0.02);
}
END_TEST

/* G from fourth-order differences of c: the same order */
START_TEST(pendulum_order_midpoint_no_jacobian) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sys.jacobian = NULL, sys.jacobian_dot = NULL; /* differences: Gdot needs G */
  expect_pendulum_order(&sys, sdae_map_midpoint, 2, 0.02);
}
END_TEST

START_TEST(pendulum_order_dgrad) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order(&sys, sdae_map_dgrad, 2, 0.02);
}
END_TEST

START_TEST(pendulum_order_dg4) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order(&sys, sdae_map_dg4, 4, 0.05);
}
END_TEST

/* the midpoint map composed (q0 only, so any forces): orders 4 and 6 through the front-end */
START_TEST(pendulum_order_midpoint4) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order(&sys, sdae_map_midpoint4, 4, 0.05);
}
END_TEST

START_TEST(pendulum_order_midpoint6) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order(&sys, sdae_map_midpoint6, 6, 0.1);
}
END_TEST

/* the explicit Runge-Kutta maps through the front-end: every stage is a q0 of the chart, a
 * Phi^-1 and the mechanism's forces */
START_TEST(pendulum_order_rk4) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order(&sys, sdae_map_rk4, 4, 0.05);
}
END_TEST

/* rk8 on the swing from theta0 = 0.1. From 0.5 the nonlinearity's part of the error (as on
 * the quartic of check_maps.c, still led by its T^9 term) competes with the linearized
 * oscillator's: the two-point ratio wanders between 165 and 500 for T from 0.4 to 0.1, where
 * the error reaches the front-end's 1e-12. From 0.1 the nonlinear part is 25 times smaller
 * relative to the linear one, and the ratio from T = 0.4 (5 steps of 1.25 rad of the linear
 * swing, errors 7e-7 and 3e-9) is asymptotic. */
START_TEST(pendulum_order_rk8) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order_from(&sys, sdae_map_rk8, 8, 0.1, 0.4);
}
END_TEST

/* Order 2 through the four chart switches of the swing from theta0 = 1. The switch falls on the
 * first step boundary past the crossing, so its phase within a step differs between T and T/2;
 * that moves the error by O(T^3) only, but the pieces before and after the switches partly
 * cancel, so the two-point ratio is asymptotic only for small T (4.8 at T = 0.025, 4.2 at
 * 0.005): T = 0.0025. */
START_TEST(pendulum_order_midpoint_through_switches) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_order_from(&sys, sdae_map_midpoint, 2, 1.0, 2.5e-3);
}
END_TEST

/* ---- the bead on a rotating wire: a time-dependent constraint ---- */

static const wire WIRE = {2.0, 1.0};
static const double R0 = 1.0, RDOT0 = 0.3;

static double wire_error(const sdae_mbs *sys, double tf, double T, unsigned long *switches) {
  const wire *p = sys->params;
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(sys, &o);
  double q[2], v[2], qe[2], ve[2], lambda;
  size_t n = (size_t)lround(tf / T);
  wire_exact(p, R0, RDOT0, 0.0, q, v, &lambda);
  ck_assert_int_eq(sdae_mbs_integrate(s, 0.0, T, n, n, q, v, NULL, NULL, NULL), SDAE_OK);
  *switches = sdae_mbs_stepper_stats(s)->chart_switches;
  sdae_mbs_stepper_free(s);
  wire_exact(p, R0, RDOT0, tf, qe, ve, &lambda);
  return fmax(max_abs_diff(q, qe, 2), max_abs_diff(v, ve, 2));
}

/* Order 2 with the midpoint map (ratio 4 within 10 %) over a turn of 2 rad, through a chart
 * switch: G = (-sin w t, cos w t) starts with q_D = y (measure |tan w t| = 0) and at w t = 2
 * that chart's measure |tan 2| = 2.19 is 4.8 times the other's |cot 2| = 0.46, so at least one
 * switch must have happened. With the callbacks and with the differences of c in q and t. */
static void expect_wire_order(const sdae_mbs *sys) {
  unsigned long sw1, sw2;
  double e1 = wire_error(sys, 2.0, 0.02, &sw1), e2 = wire_error(sys, 2.0, 0.01, &sw2);
  ck_assert_double_gt(e2, 1e-9);
  ck_assert_msg(fabs(e1 / e2 / 4.0 - 1.0) <= 0.1, "error %g -> %g, ratio %g", e1, e2, e1 / e2);
  ck_assert_uint_ge(sw1, 1);
  ck_assert_uint_ge(sw2, 1);
}

START_TEST(wire_order_midpoint) {
  wire p = WIRE;
  sdae_mbs sys = wire_mbs(&p);
  expect_wire_order(&sys);
}
END_TEST

START_TEST(wire_order_midpoint_differences) {
  wire p = WIRE;
  sdae_mbs sys = wire_mbs(&p);
  sys.jacobian = NULL, sys.constraint_t = NULL;
  sys.jacobian_dot = NULL, sys.constraint_t_dot = NULL; /* differences: these need those */
  expect_wire_order(&sys);
}
END_TEST

/* lambda = -2 m w r' at the exact state (fixture: along n = G^T, m q'' = -lambda n and
 * q'' . n = 2 w r'). gamma comes from fourth-order differences: 1e-10 of the size of the terms,
 * m w (2 |r'| + w r) (the Coriolis and the centripetal scale). */
static void expect_wire_lambda(const sdae_mbs *sys) {
  const wire *p = sys->params;
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(sys, &o);
  for (int i = 0; i <= 8; i++) {
    double t = 0.25 * i, q[2], v[2], want, got = NAN, w = p->w;
    double r = R0 * cosh(w * t) + RDOT0 / w * sinh(w * t);
    double rdot = R0 * w * sinh(w * t) + RDOT0 * cosh(w * t);
    wire_exact(p, R0, RDOT0, t, q, v, &want);
    ck_assert_double_eq_tol(want, -2.0 * p->m * w * rdot, 1e-15 * fabs(want));
    ck_assert_int_eq(sdae_mbs_lambda(s, t, q, v, &got), SDAE_OK);
    ck_assert_msg(fabs(got - want) <= 1e-10 * p->m * w * (2.0 * fabs(rdot) + w * r),
                  "t = %g: lambda %.17g, want %.17g", t, got, want);
  }
  sdae_mbs_stepper_free(s);
}

START_TEST(wire_lambda_exact) {
  wire p = WIRE;
  sdae_mbs sys = wire_mbs(&p);
  expect_wire_lambda(&sys);
  sys.jacobian = NULL, sys.constraint_t = NULL;
  sys.jacobian_dot = NULL, sys.constraint_t_dot = NULL; /* differences: these need those */
  expect_wire_lambda(&sys);
}
END_TEST

/* xi = (c, G v + dc/dt): zero at the exact states; off them, the closed forms
 * c = -sin(w t) x + cos(w t) y and G v + dc/dt = n.v - w e.q. */
START_TEST(wire_xi) {
  wire p = WIRE;
  sdae_mbs sys = wire_mbs(&p);
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  double t = 0.7, q[2], v[2], lambda, xi[2];
  wire_exact(&p, R0, RDOT0, t, q, v, &lambda);
  ck_assert_int_eq(sdae_mbs_xi(s, t, q, v, xi), SDAE_OK);
  ck_assert_double_le(fabs(xi[0]), 1e-15);
  ck_assert_double_le(fabs(xi[1]), 1e-14);
  q[0] = 0.4, q[1] = 1.3, v[0] = -0.2, v[1] = 0.9;
  ck_assert_int_eq(sdae_mbs_xi(s, t, q, v, xi), SDAE_OK);
  double e[2] = {cos(t), sin(t)}, n[2] = {-sin(t), cos(t)};
  ck_assert_double_eq_tol(xi[0], n[0] * q[0] + n[1] * q[1], 1e-15);
  ck_assert_double_eq_tol(xi[1], n[0] * v[0] + n[1] * v[1] - (e[0] * q[0] + e[1] * q[1]), 1e-15);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* The wire's derivatives along the motion agree with sdae_mbs_check's differences (about 1e-9
 * relative for smooth callbacks; measured <= 4.7e-12), at two times of its turn. */
static const double WIRE_T[2] = {0.37, 2.9}, WIRE_Q[2][2] = {{0.8, -0.3}, {-1.2, 0.5}};
static const double WIRE_V[2][2] = {{0.4, 1.1}, {-0.6, 0.25}};

START_TEST(wire_derivatives_checked) {
  wire p = WIRE;
  sdae_mbs sys = wire_mbs(&p);
  sdae_mbs_check_report r;
  const unsigned given = 1u << SDAE_MBS_JACOBIAN | 1u << SDAE_MBS_CONSTRAINT_T |
                         1u << SDAE_MBS_MASS_DOT_V | 1u << SDAE_MBS_JACOBIAN_DOT |
                         1u << SDAE_MBS_CONSTRAINT_T_DOT;
  for (int k = 0; k < 2; k++) {
    ck_assert_int_eq(sdae_mbs_check(&sys, WIRE_T[k], WIRE_Q[k], WIRE_V[k], 1e-6, &r), SDAE_OK);
    ck_assert_uint_eq(r.checked, given);
    ck_assert_int_eq(r.consistent, 1);
    for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++) ck_assert_double_lt(r.mismatch[d], 1e-7);
  }
}
END_TEST

/* A wrong sign in the wire's derivatives is found where it is: in the constraint's time term
 * w^2 (sin(w t) x - cos(w t) y) of d/ds dc/dt, and in the second entry of the turning G'. */
static int (*true_constraint_t_dot)(double t, const double *q, const double *v, double *out,
                                    void *params);

static int wrong_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                  void *params) {
  const wire *p = params;
  int rc = true_constraint_t_dot(t, q, v, out, params);
  /* the time term's sign flipped: subtract it twice */
  out[0] -= 2 * p->w * p->w * (sin(p->w * t) * q[0] - cos(p->w * t) * q[1]);
  return rc;
}

static int wrong_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                              void *params) {
  const wire *p = params;
  (void)q, (void)v;
  Gdot[0] = -p->w * cos(p->w * t), Gdot[1] = p->w * sin(p->w * t); /* entry 1's sign */
  return 0;
}

START_TEST(wire_derivative_errors_found) {
  wire p = WIRE;
  sdae_mbs sys = wire_mbs(&p), wrong = sys;
  sdae_mbs_check_report r;
  true_constraint_t_dot = sys.constraint_t_dot;
  wrong.constraint_t_dot = wrong_constraint_t_dot;
  ck_assert_int_eq(sdae_mbs_check(&wrong, WIRE_T[0], WIRE_Q[0], WIRE_V[0], 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_int_eq(r.worst, SDAE_MBS_CONSTRAINT_T_DOT);
  ck_assert_uint_eq(r.worst_index, 0);
  wrong = sys;
  wrong.jacobian_dot = wrong_jacobian_dot;
  ck_assert_int_eq(sdae_mbs_check(&wrong, WIRE_T[0], WIRE_Q[0], WIRE_V[0], 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_int_eq(r.worst, SDAE_MBS_JACOBIAN_DOT);
  ck_assert_uint_eq(r.worst_index, 1);
}
END_TEST

/* ---- the pendulum's multiplier, xi and energy ---- */

/* lambda = m (L omega^2 + ga cos theta) / L on the circle (mechanisms.c: -G^T lambda = -lambda q is
 * the rod's pull of magnitude lambda L). Here gamma = d/ds G(q + s v) v = |v|^2 with G linear
 * in q, so the fourth-order difference of the given jacobian is exact but for rounding,
 * eps |q| |v| / s with s ~ eps^(1/5): 1e-12 of m (L omega^2 + ga) / L. Without the jacobian, G is
 * itself a difference of c (rounding eps |c| / s) and gamma its difference again: the rounding
 * eps |c| / s^2 ~ 4e-10 |c|, so 1e-9. */
static void expect_pendulum_lambda(const sdae_mbs *sys, double tol) {
  const mech_pendulum *p = sys->params;
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(sys, &o);
  const double theta[5] = {0.0, 0.4, 1.2, 2.0, -2.9}, omega[5] = {0.0, -1.5, 2.5, 0.7, 3.0};
  for (int i = 0; i < 5; i++) {
    double q[2], v[2], got = NAN, want = mech_pendulum_lambda(p, theta[i], omega[i]);
    double scale = p->m * (p->L * omega[i] * omega[i] + p->ga) / p->L;
    mech_pendulum_state(p, theta[i], omega[i], q, v);
    ck_assert_int_eq(sdae_mbs_lambda(s, 0.3, q, v, &got), SDAE_OK);
    ck_assert_msg(fabs(got - want) <= tol * scale, "theta %g omega %g: lambda %.17g, want %.17g",
                  theta[i], omega[i], got, want);
  }
  sdae_mbs_stepper_free(s);
}

START_TEST(pendulum_lambda_tension) {
  mech_pendulum p = {.L = 1.3, .m = 0.7, .ga = 9.81};
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  expect_pendulum_lambda(&sys, 1e-12);
  sys.jacobian = NULL, sys.jacobian_dot = NULL; /* differences: Gdot needs G */
  expect_pendulum_lambda(&sys, 1e-9);
}
END_TEST

/* xi = ((x^2 + y^2 - L^2)/2, x vx + y vy) and E = m |v|^2 / 2 + m g y, by the definitions */
START_TEST(pendulum_xi_and_energy) {
  mech_pendulum p = {.L = 1.3, .m = 0.7, .ga = 9.81};
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  double q[2] = {0.3, -1.2}, v[2] = {0.5, 0.7}, xi[2], E;
  ck_assert_int_eq(sdae_mbs_xi(s, 0.0, q, v, xi), SDAE_OK);
  ck_assert_double_eq_tol(xi[0], 0.5 * (0.09 + 1.44 - 1.69), 1e-15);
  ck_assert_double_eq_tol(xi[1], 0.3 * 0.5 - 1.2 * 0.7, 1e-15);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E), SDAE_OK);
  ck_assert_double_eq_tol(E, 0.5 * 0.7 * (0.25 + 0.49) + 0.7 * 9.81 * -1.2, 1e-14);
  sdae_mbs_stepper_free(s);
  /* without potential: the kinetic energy alone */
  wire w = WIRE;
  sys = wire_mbs(&w);
  s = stepper(&sys, &o);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E), SDAE_OK);
  ck_assert_double_eq_tol(E, 0.5 * 2.0 * (0.25 + 0.49), 1e-15);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* ---- the chart rule ---- */

/* For the pendulum G = (x, y): the chart q_D = y has measure |x/y| = |tan theta|, q_D = x has
 * |cot theta|. The first step takes the best; later a chart is replaced only when the best is
 * better by SDAE_MBS_CHART_FACTOR = 1.5: from theta = 0.85 (tan 1.139, cot 0.878: 1.30 times
 * better) the chart stays, from theta = 0.95 (tan 1.398, cot 0.715: 1.96 times) it switches.
 * chart_measure is the chosen chart's measure at the state where it was chosen. */
START_TEST(pendulum_chart_hysteresis) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  const sdae_mbs_stats *st = sdae_mbs_stepper_stats(s);
  size_t dep[1] = {99};
  double q[2], v[2];
  ck_assert_int_eq(sdae_mbs_chart(s, dep), SDAE_ERR_CHART); /* no chart before a step */
  ck_assert_uint_eq(dep[0], 99);
  mech_pendulum_state(&p, 0.7, 0.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_chart(s, dep), SDAE_OK);
  ck_assert_uint_eq(dep[0], 1);
  ck_assert_uint_eq(st->chart_switches, 0);
  ck_assert_double_eq_tol(st->chart_measure, tan(0.7), 1e-14);
  mech_pendulum_state(&p, 0.85, 0.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_chart(s, dep), SDAE_OK);
  ck_assert_uint_eq(dep[0], 1);
  ck_assert_uint_eq(st->chart_switches, 0);
  mech_pendulum_state(&p, 0.95, 0.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_chart(s, dep), SDAE_OK);
  ck_assert_uint_eq(dep[0], 0);
  ck_assert_uint_eq(st->chart_switches, 1);
  ck_assert_double_eq_tol(st->chart_measure, 1.0 / tan(0.95), 1e-14);
  ck_assert_uint_eq(st->step.steps, 3);
  sdae_mbs_stepper_reset_stats(s);
  ck_assert_uint_eq(st->chart_switches, 0);
  ck_assert_uint_eq(st->step.steps, 0);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* ---- the double pendulum: energy through chart switches ---- */

typedef struct dp_watch {
  const mech_double_pendulum *p;
  sdae_mbs_stepper *s;
  double E0, E_prev, worst_drift, worst_switch_jump, worst_c;
  unsigned long switches_prev, switch_steps;
  unsigned long unordered; /* steps after which the chart's q_D were not ascending */
} dp_watch;

/* the energy by its definition, not by the library */
static double dp_energy(const mech_double_pendulum *p, const double *q, const double *v) {
  return 0.5 * p->m1 * (v[0] * v[0] + v[1] * v[1]) + 0.5 * p->m2 * (v[2] * v[2] + v[3] * v[3]) +
         p->ga * (p->m1 * q[1] + p->m2 * q[3]);
}

static int dp_observe(size_t step, double t, const double *q, const double *v, void *data) {
  dp_watch *w = data;
  double E = dp_energy(w->p, q, v), dx = q[2] - q[0], dy = q[3] - q[1];
  unsigned long sw = sdae_mbs_stepper_stats(w->s)->chart_switches;
  (void)t;
  if (step == 0) w->E0 = E;
  w->worst_drift = fmax(w->worst_drift, fabs(E - w->E0));
  if (step > 0 && sw > w->switches_prev) {
    w->worst_switch_jump = fmax(w->worst_switch_jump, fabs(E - w->E_prev));
    w->switch_steps++;
  }
  w->worst_c = fmax(w->worst_c, fabs(0.5 * (q[0] * q[0] + q[1] * q[1] - w->p->L1 * w->p->L1)));
  w->worst_c = fmax(w->worst_c, fabs(0.5 * (dx * dx + dy * dy - w->p->L2 * w->p->L2)));
  w->E_prev = E, w->switches_prev = sw;
  if (step > 0) { /* the chart's dependent coordinates, ascending as sdae_mbs_chart promises */
    size_t dep[2];
    if (sdae_mbs_chart(w->s, dep) != SDAE_OK || !(dep[0] < dep[1])) w->unordered++;
  }
  return 0;
}

/* From both arms raised (theta = 2.2, 2.7 rad, at rest; E0 = g (m1 y1 + m2 y2) = 20.4 J), a
 * chaotic motion; 4e4 steps of T = 2e-3 (80 s) with dgrad (1e5 steps take 9 s). The discrete
 * gradient conserves H = v^T M v / 2 + V exactly but for Newton's tolerance and rounding: |E - E0|
 * <= 1e-12 |E0|. The constraints at rounding: |c_j| <= 1e-13 L^2 (L = 1). The chart switches (the
 * arms turn over, so no chart is best throughout), and a step that switches changes E by rounding
 * only: 1e-14 |E0|. */
START_TEST(double_pendulum_energy_through_switches) {
  mech_double_pendulum p = {.L1 = 1.0, .L2 = 1.0, .m1 = 1.0, .m2 = 1.0, .ga = 9.81};
  sdae_mbs sys;
  mech_double_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  dp_watch w = {&p, s, 0, 0, 0, 0, 0, 0, 0, 0};
  const double theta[2] = {2.2, 2.7}, omega[2] = {0.0, 0.0};
  double q[4], v[4], E;
  size_t n = 40000, done = 0;
  mech_double_pendulum_state(&p, theta, omega, q, v);
  ck_assert_int_eq(sdae_mbs_integrate(s, 0.0, 2e-3, n, 1, q, v, dp_observe, &w, &done), SDAE_OK);
  ck_assert_uint_eq(done, n);
  ck_assert_double_eq_tol(w.E0, 9.81 * (-2.0 * cos(2.2) - cos(2.7)), 1e-13);
  ck_assert_msg(w.worst_drift <= 1e-12 * fabs(w.E0), "energy drift %g of %g", w.worst_drift, w.E0);
  ck_assert_msg(w.worst_c <= 1e-13, "max |c| %g", w.worst_c);
  ck_assert_uint_ge(sdae_mbs_stepper_stats(s)->chart_switches, 1);
  ck_assert_uint_eq(w.switch_steps, sdae_mbs_stepper_stats(s)->chart_switches);
  ck_assert_uint_eq(w.unordered, 0);
  ck_assert_msg(w.worst_switch_jump <= 1e-14 * fabs(w.E0), "jump %g at a switch",
                w.worst_switch_jump);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E), SDAE_OK);
  ck_assert_double_eq_tol(E, dp_energy(&p, q, v), 1e-14 * fabs(w.E0));
  sdae_mbs_stepper_free(s);
}
END_TEST

/* ---- the decay of xi from an off-manifold start ---- */

/* Each constraint coordinate obeys xi+ = xi / (1 - T k) (scheme 15) or (1 + T k) xi (scheme 11)
 * with k = -(delta^2/2) ||q_i||^2 - epsilon <= -epsilon (eq. 6): every step shrinks |xi_j| by
 * 1/(1 + T epsilon) at least (scheme 15), or by (1 - T epsilon) when T |k| <= 2 - T epsilon
 * (scheme 11, T small). Measured with sdae_mbs_xi after each step, from q off the circle
 * (c = 0.15) and v with a radial part (G v = -0.14); 1e-14 allowed for rounding. */
typedef struct decay_watch {
  sdae_mbs_stepper *s;
  double factor, prev[2], first[2], worst_excess;
  size_t steps;
} decay_watch;

static int decay_observe(size_t step, double t, const double *q, const double *v, void *data) {
  decay_watch *w = data;
  double xi[2];
  ck_assert_int_eq(sdae_mbs_xi(w->s, t, q, v, xi), SDAE_OK);
  if (step == 0) memcpy(w->first, xi, sizeof xi);
  for (int j = 0; step > 0 && j < 2; j++)
    w->worst_excess = fmax(w->worst_excess, fabs(xi[j]) - (w->factor * fabs(w->prev[j]) + 1e-14));
  memcpy(w->prev, xi, sizeof xi);
  w->steps = step;
  return 0;
}

static void expect_decay(sdae_scheme scheme, double T, size_t n) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_midpoint, scheme);
  decay_watch w = {NULL, 0, {0, 0}, {0, 0}, -1.0, 0};
  double q[2] = {0.3, -1.1}, v[2] = {1.0, 0.4};
  o.epsilon = 2.0;
  w.s = stepper(&sys, &o);
  w.factor =
      scheme == SDAE_SCHEME_SEMI_IMPLICIT ? 1.0 / (1.0 + T * o.epsilon) : 1.0 - T * o.epsilon;
  ck_assert_int_eq(sdae_mbs_integrate(w.s, 0.0, T, n, 1, q, v, decay_observe, &w, NULL), SDAE_OK);
  ck_assert_uint_eq(w.steps, n);
  ck_assert_double_eq_tol(w.first[0], 0.15, 1e-15);
  ck_assert_double_eq_tol(w.first[1], -0.14, 1e-15);
  ck_assert_msg(w.worst_excess <= 0.0, "xi above the bound by %g", w.worst_excess);
  /* and so over the run: |xi_n| <= |xi_0| factor^n (+ rounding) */
  for (int j = 0; j < 2; j++)
    ck_assert_double_le(fabs(w.prev[j]), fabs(w.first[j]) * pow(w.factor, (double)n) + 1e-13);
  sdae_mbs_stepper_free(w.s);
}

START_TEST(decay_scheme15) { expect_decay(SDAE_SCHEME_SEMI_IMPLICIT, 0.01, 300); }
END_TEST

START_TEST(decay_scheme11) { expect_decay(SDAE_SCHEME_EXPLICIT, 2e-3, 1000); }
END_TEST

/* ---- dissipation ---- */

typedef struct damp_watch {
  const mech_pendulum *p;
  double E_prev, worst_rise, dissipated, v_prev[2], E0, E_last;
} damp_watch;

static double pendulum_energy(const mech_pendulum *p, const double *q, const double *v) {
  return 0.5 * p->m * (v[0] * v[0] + v[1] * v[1]) + p->m * p->ga * q[1];
}

static int damp_observe(size_t step, double t, const double *q, const double *v, void *data) {
  damp_watch *w = data;
  double E = pendulum_energy(w->p, q, v), T = 0.01;
  (void)t;
  if (step == 0) w->E0 = E;
  if (step > 0) {
    double mx = 0.5 * (v[0] + w->v_prev[0]), my = 0.5 * (v[1] + w->v_prev[1]);
    w->worst_rise = fmax(w->worst_rise, E - w->E_prev);
    w->dissipated += T * w->p->d * (mx * mx + my * my); /* dE/dt = -v^T D v, midpoint rule */
  }
  w->E_prev = w->E_last = E;
  memcpy(w->v_prev, v, sizeof w->v_prev);
  return 0;
}

/* With damping D = d I, H+ - H = -T gradbar^T R gradbar <= 0 for the discrete gradient: the
 * energy never rises (1e-13 m g L for rounding), and over 10 s it falls by the work of the
 * damping force, the integral of d |v|^2, to 1 % (the quadrature and the map are order 2,
 * (omega T)^2 = 1e-3). */
START_TEST(damped_pendulum_dissipates) {
  mech_pendulum p = {.L = 1.0, .m = 1.0, .ga = 9.81, .d = 0.3};
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  damp_watch w = {&p, 0, -1.0, 0, {0, 0}, 0, 0};
  double q[2], v[2];
  mech_pendulum_state(&p, 1.0, 0.0, q, v);
  ck_assert_int_eq(sdae_mbs_integrate(s, 0.0, 0.01, 1000, 1, q, v, damp_observe, &w, NULL),
                   SDAE_OK);
  sdae_mbs_stepper_free(s);
  ck_assert_msg(w.worst_rise <= 1e-13 * p.m * p.ga * p.L, "energy rose by %g", w.worst_rise);
  ck_assert_double_gt(w.dissipated, 0.1 * (w.E0 + p.m * p.ga * p.L)); /* a real loss */
  ck_assert_msg(fabs((w.E0 - w.E_last) - w.dissipated) <= 0.01 * w.dissipated,
                "energy lost %g, damping work %g", w.E0 - w.E_last, w.dissipated);
}
END_TEST

/* ---- sdae_mbs_integrate: the observer's contract and the same steps as sdae_mbs_step ---- */

typedef struct count_watch {
  size_t seen[8], count, stop_at;
} count_watch;

static int count_observe(size_t step, double t, const double *q, const double *v, void *data) {
  count_watch *c = data;
  (void)t, (void)q, (void)v;
  if (c->count < 8) c->seen[c->count] = step;
  c->count++;
  return c->stop_at && step >= c->stop_at;
}

START_TEST(integrate_matches_steps) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *a = stepper(&sys, &o), *b = stepper(&sys, &o);
  count_watch c = {{0}, 0, 0};
  double q[2], v[2], q2[2], v2[2], t0 = 0.5, T = 0.01;
  size_t done = 0;
  mech_pendulum_state(&p, 1.0, 0.5, q, v);
  memcpy(q2, q, sizeof q), memcpy(v2, v, sizeof v);
  ck_assert_int_eq(sdae_mbs_integrate(a, t0, T, 7, 3, q, v, count_observe, &c, &done), SDAE_OK);
  for (size_t i = 0; i < 7; i++)
    ck_assert_int_eq(sdae_mbs_step(b, t0 + (double)i * T, T, q2, v2), SDAE_OK);
  ck_assert_uint_eq(done, 7);
  ck_assert_mem_eq(q, q2, sizeof q);
  ck_assert_mem_eq(v, v2, sizeof v);
  ck_assert_uint_eq(c.count, 4); /* steps 0, 3, 6 and the last, 7 */
  ck_assert_uint_eq(c.seen[0], 0);
  ck_assert_uint_eq(c.seen[1], 3);
  ck_assert_uint_eq(c.seen[2], 6);
  ck_assert_uint_eq(c.seen[3], 7);
  c = (count_watch){{0}, 0, 2};
  ck_assert_int_eq(sdae_mbs_integrate(a, t0, T, 7, 1, q, v, count_observe, &c, &done),
                   SDAE_STOPPED);
  ck_assert_uint_eq(done, 2);
  sdae_mbs_stepper_free(a);
  sdae_mbs_stepper_free(b);
}
END_TEST

/* A step past the kept chart's fold: the chart q_D = y, kept by hysteresis at theta = 0.85,
 * cannot hold x > L; from theta = 0.85 at omega = 8 a step of T = 0.1 carries x past L, so its
 * Phi^-1 fails and the step is taken once more in the best chart, q_D = x. It counts as one
 * step with one switch. */
START_TEST(step_past_a_kept_charts_fold_is_retried) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  const sdae_mbs_stats *st = sdae_mbs_stepper_stats(s);
  size_t dep[1];
  double q[2], v[2];
  mech_pendulum_state(&p, 0.7, 0.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  mech_pendulum_state(&p, 0.85, 8.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 0.1, q, v), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_chart(s, dep), SDAE_OK);
  ck_assert_uint_eq(dep[0], 0);
  ck_assert_uint_eq(st->chart_switches, 1);
  ck_assert_uint_eq(st->step.steps, 2);
  ck_assert_double_le(fabs(q[0] * q[0] + q[1] * q[1] - 1.0), 1e-14);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* ---- starts that only Newton's recovery steps from (core/newton.h) ---- */

/* The pendulum from q = (3, 0.5) at rest, far off |q| = 1 (xi_c = c = 4.125), by the midpoint
 * map at T = 0.05 (Theorem 4: a start off the manifold is brought onto it). Every step shrinks
 * |xi_j| by 1/(1 + T epsilon) at least (scheme 15, k <= -epsilon), up to the rounding of c's
 * terms (|q|^2 <= 9.25: a few ulps of 10, 1e-14 (1 + |xi|) allowed). Phi^-1's first solve is
 * predicted from the start's linearization 0.2 away in xi_c, where the kept factors' chord
 * does not converge: the solve is retried with factors at the prediction. At T = 0.05 the
 * state reaches (1.25, -0.89) with xi_c = 0.68 in 11 steps; the mu-dynamics are evaluated on
 * the manifold (xi = 0) at the same q_I, and the next y, below -1, has no point there in
 * either chart: 10 steps are asserted at T = 0.05, and 10 s at T = 0.025, where xi decays first
 * (then to rounding: |xi_n| <= |xi_0| / (1 + T epsilon)^n). */
static void expect_far_decay(double T, size_t n) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  sdae_options o = options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  double q[2] = {3.0, 0.5}, v[2] = {0.0, 0.0}, xi[2], prev[2], factor = 1.0 / (1.0 + T * o.epsilon);
  ck_assert_int_eq(sdae_mbs_xi(s, 0.0, q, v, prev), SDAE_OK);
  ck_assert_double_eq(prev[0], 4.125);
  for (size_t k = 0; k < n; k++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)k * T, T, q, v), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_xi(s, (double)(k + 1) * T, q, v, xi), SDAE_OK);
    for (int j = 0; j < 2; j++) {
      ck_assert_double_le(fabs(xi[j]), factor * fabs(prev[j]) + 1e-14 * (1.0 + fabs(prev[j])));
      prev[j] = xi[j];
    }
    if (k == 0) ck_assert_double_gt(q[0], 2.0); /* the start's side: Newton's root nearby */
  }
  ck_assert_double_le(fabs(xi[0]), 4.125 * pow(factor, (double)n) + 1e-13);
  sdae_mbs_stepper_free(s);
}

START_TEST(far_off_start_steps_and_decays) {
  expect_far_decay(0.05, 10);
  expect_far_decay(0.025, 400);
}
END_TEST

/* A point on the unit circle (c = (|q|^2 - 1)/2) with the SPD mass M = R diag(1e6, 1) R^T,
 * R the rotation by 30 degrees (condition number 1e6), under gravity V = g y, from the angle
 * 30 degrees, where the heavy direction is the circle's normal, at unit speed along it. The
 * momentum of the mu-dynamics carries M's rounding times 1e6: Newton's updates stop shrinking
 * near 1e-11 and are taken there (its noise). Each step is taken; the discrete gradient keeps
 * E = v^T M v / 2 + g y up to the rounding of its terms, eps ||M|| |v|^2 a step at most
 * (|v|^2 <= 2 (E + g) = 30.4, the light direction's mass 1), and c stays at rounding. */
static const double HEAVY_C = 0.86602540378443865, HEAVY_S = 0.5, HEAVY_M = 1e6, HEAVY_G = 9.81;

static int heavy_mass(double t, const double *q, double *M, void *params) {
  (void)t, (void)q, (void)params;
  M[0] = HEAVY_M * HEAVY_C * HEAVY_C + HEAVY_S * HEAVY_S;
  M[1] = M[2] = (HEAVY_M - 1.0) * HEAVY_C * HEAVY_S;
  M[3] = HEAVY_M * HEAVY_S * HEAVY_S + HEAVY_C * HEAVY_C;
  return 0;
}
static int heavy_force(double t, const double *q, const double *v, double *F, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  F[0] = 0.0, F[1] = -HEAVY_G;
  return 0;
}
static int heavy_potential(double t, const double *q, double *V, void *params) {
  (void)t, (void)params;
  V[0] = HEAVY_G * q[1];
  return 0;
}
static int heavy_constraint(double t, const double *q, double *c, void *params) {
  (void)t, (void)params;
  c[0] = 0.5 * (q[0] * q[0] + q[1] * q[1] - 1.0);
  return 0;
}
static int heavy_jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  G[0] = q[0], G[1] = q[1];
  return 0;
}

START_TEST(heavy_normal_mass_steps) {
  sdae_mbs sys = {.n_q = 2,
                  .n_c = 1,
                  .mass = heavy_mass,
                  .force = heavy_force,
                  .constraint = heavy_constraint,
                  .jacobian = heavy_jacobian,
                  .potential = heavy_potential};
  sdae_options o = options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  double th = acos(-1.0) / 6.0, T = 1e-3, E0, E;
  double q[2] = {cos(th), sin(th)}, v[2] = {-sin(th), cos(th)}; /* sin(th): 0.5 - eps/4 */
  const size_t n = 1000;
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E0), SDAE_OK);
  for (size_t k = 0; k < n; k++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)k * T, T, q, v), SDAE_OK);
    ck_assert_double_le(fabs(q[0] * q[0] + q[1] * q[1] - 1.0), 8.0 * DBL_EPSILON);
  }
  ck_assert_int_eq(sdae_mbs_energy(s, (double)n * T, q, v, &E), SDAE_OK);
  ck_assert_double_le(fabs(E - E0), (double)n * DBL_EPSILON * HEAVY_M * 2.0 * (E0 + HEAVY_G));
  ck_assert_double_gt(fabs(q[1] - sin(th)), 0.01); /* it moved off the light point */
  sdae_mbs_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs");
  ADD_CASE(s, pendulum_order_euler);
  ADD_CASE(s, pendulum_order_midpoint);
  ADD_CASE(s, pendulum_order_midpoint_no_jacobian);
  ADD_CASE(s, pendulum_order_dgrad);
  ADD_CASE(s, pendulum_order_dg4);
  ADD_CASE(s, pendulum_order_midpoint4);
  ADD_CASE(s, pendulum_order_midpoint6);
  ADD_CASE(s, pendulum_order_rk4);
  ADD_CASE(s, pendulum_order_rk8);
  ADD_CASE(s, pendulum_order_midpoint_through_switches);
  ADD_CASE(s, wire_order_midpoint);
  ADD_CASE(s, wire_order_midpoint_differences);
  ADD_CASE(s, wire_lambda_exact);
  ADD_CASE(s, wire_xi);
  ADD_CASE(s, wire_derivatives_checked);
  ADD_CASE(s, wire_derivative_errors_found);
  ADD_CASE(s, pendulum_lambda_tension);
  ADD_CASE(s, pendulum_xi_and_energy);
  ADD_CASE(s, pendulum_chart_hysteresis);
  ADD_CASE(s, step_past_a_kept_charts_fold_is_retried);
  ADD_CASE(s, double_pendulum_energy_through_switches);
  ADD_CASE(s, decay_scheme15);
  ADD_CASE(s, decay_scheme11);
  ADD_CASE(s, damped_pendulum_dissipates);
  ADD_CASE(s, integrate_matches_steps);
  ADD_CASE(s, far_off_start_steps_and_decays);
  ADD_CASE(s, heavy_normal_mass_steps);
  return run_suite(s);
}
