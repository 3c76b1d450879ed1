/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanisms of models/mechanisms.c: their callbacks against the mathematics (jacobian =
 * dc/dq and force = -dV/dq by central differences, the mass matrix), their derivatives along
 * the motion by sdae_mbs_check (and a wrong sign in one of them caught), their start states on
 * the constraints, Grashof's condition, and integrated through <stabdae/mbs.h>: the pendulum's
 * order against its exact solution, lambda in closed form, the energy kept by the discrete
 * gradient through chart switches, the four-bar's full turns, the double pendulum's chaos. */
#include <check.h>
#include <math.h>
#include <stdlib.h>

#include "mechanisms.h"
#include "test_util.h"

typedef struct mechanisms {
  mech_pendulum pend;
  mech_double_pendulum dpend;
  mech_fourbar fourbar;
  sdae_mbs sys[3];
} mechanisms;

/* parameters away from 1 so that a swapped length or mass shows */
static void all_mechanisms(mechanisms *m) {
  m->pend = (mech_pendulum){.L = 1.3, .m = 0.7, .ga = 9.81};
  m->dpend = (mech_double_pendulum){1.1, 0.8, 0.6, 1.7, 9.81};
  m->fourbar = (mech_fourbar){1.0, 4.0, 3.0, 4.5, 0.9, 1.6, 9.81};
  mech_pendulum_system(&m->sys[0], &m->pend);
  mech_double_pendulum_system(&m->sys[1], &m->dpend);
  mech_fourbar_system(&m->sys[2], &m->fourbar);
}

/* G = dc/dq by central differences at random points (c is quadratic: exact up to rounding) */
START_TEST(test_jacobian) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  mechanisms m;
  all_mechanisms(&m);
  for (int k = 0; k < 3; k++) {
    const sdae_mbs *s = &m.sys[k];
    for (int n = 0; n < 50; n++) {
      double q[4], G[12], cp[3], cm[3], h = 1e-5;
      for (size_t i = 0; i < s->n_q; i++) q[i] = tu_flat(r, -3, 3);
      ck_assert_int_eq(s->jacobian(0, q, G, s->params), 0);
      for (size_t i = 0; i < s->n_q; i++) {
        double qi = q[i];
        q[i] = qi + h;
        s->constraint(0, q, cp, s->params);
        q[i] = qi - h;
        s->constraint(0, q, cm, s->params);
        q[i] = qi;
        for (size_t j = 0; j < s->n_c; j++)
          ck_assert_double_eq_tol(G[j * s->n_q + i], (cp[j] - cm[j]) / (2 * h), 1e-9);
      }
    }
  }
  gsl_rng_free(r);
}
END_TEST

/* F = -dV/dq (the potential declares the forces conservative) and M = diag of the masses */
START_TEST(test_force_mass) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  mechanisms m;
  all_mechanisms(&m);
  const double masses[3][4] = {{0.7, 0.7}, {0.6, 0.6, 1.7, 1.7}, {0.9, 0.9, 1.6, 1.6}};
  for (int k = 0; k < 3; k++) {
    const sdae_mbs *s = &m.sys[k];
    double q[4], v[4], F[4], M[16], Vp, Vm, h = 1e-4;
    for (size_t i = 0; i < s->n_q; i++) q[i] = tu_flat(r, -3, 3), v[i] = tu_flat(r, -3, 3);
    ck_assert_int_eq(s->force(0, q, v, F, s->params), 0);
    ck_assert_int_eq(s->mass(0, q, M, s->params), 0);
    for (size_t i = 0; i < s->n_q; i++) {
      double qi = q[i];
      q[i] = qi + h;
      s->potential(0, q, &Vp, s->params);
      q[i] = qi - h;
      s->potential(0, q, &Vm, s->params);
      q[i] = qi;
      ck_assert_double_eq_tol(F[i], -(Vp - Vm) / (2 * h), 1e-9);
      for (size_t j = 0; j < s->n_q; j++)
        ck_assert_double_eq(M[i * s->n_q + j], i == j ? masses[k][i] : 0.0);
    }
  }
  gsl_rng_free(r);
}
END_TEST

/* c = 0 and G v = 0 at a state; the largest |c_j| is mech_max_abs_c */
static void assert_consistent(const sdae_mbs *s, const double *q, const double *v) {
  double c[3], G[12], worst = 0.0;
  s->constraint(0, q, c, s->params);
  s->jacobian(0, q, G, s->params);
  for (size_t j = 0; j < s->n_c; j++) {
    double Gv = 0.0;
    for (size_t i = 0; i < s->n_q; i++) Gv += G[j * s->n_q + i] * v[i];
    ck_assert_double_lt(fabs(c[j]), 1e-13);
    ck_assert_double_lt(fabs(Gv), 1e-12);
    worst = fmax(worst, fabs(c[j]));
  }
  ck_assert_double_eq(mech_max_abs_c(s, 0, q), worst);
}

START_TEST(test_start_states) {
  mechanisms m;
  all_mechanisms(&m);
  double q[4], v[4], a[2] = {2.0, -0.7}, w[2] = {0.3, -1.2};
  mech_double_pendulum_state(&m.dpend, a, w, q, v);
  assert_consistent(&m.sys[1], q, v);
  /* the angles are those asked for, from the downward vertical; speeds L w */
  ck_assert_double_eq_tol(atan2(q[0], -q[1]), a[0], 1e-14);
  ck_assert_double_eq_tol(atan2(q[2] - q[0], q[1] - q[3]), a[1], 1e-14);
  ck_assert_double_eq_tol(hypot(v[0], v[1]), 1.1 * 0.3, 1e-14);
  for (double th = -3.0; th < 3.2; th += 0.5) {
    ck_assert_int_eq(mech_fourbar_state(&m.fourbar, th, 2.5, q, v), 0);
    assert_consistent(&m.sys[2], q, v);
    ck_assert_double_eq_tol(atan2(q[1], q[0]), th, 1e-14);
    ck_assert_double_eq_tol(q[0] * v[1] - q[1] * v[0], 2.5, 1e-13); /* a^2 omega, a = 1 */
    /* C on the side of B-D the header names: (D - B) x (C - B) > 0 */
    ck_assert_double_gt((4.5 - q[0]) * (q[3] - q[1]) + q[1] * (q[2] - q[0]), 0.0);
  }
  /* a ground link too long: at theta = 0, |B - D| = d - a = 7.5 > b + e = 7 */
  mech_fourbar open = m.fourbar;
  open.d = 8.5;
  ck_assert_int_eq(mech_fourbar_state(&open, 0.0, 1.0, q, v), -1);
}
END_TEST

/* s + l <= p + q with the crank shortest: (a, b, e, d) */
START_TEST(test_grashof) {
  const struct {
    double a, b, e, d;
    int crank_rocker;
  } cases[] = {
      {1, 4, 3, 4.5, 1},   /* 5.5 <= 7 */
      {2.5, 4, 3, 4.5, 1}, /* 7 <= 7: the change point still counts */
      {2.6, 4, 3, 4.5, 0}, /* 7.1 > 6.9 */
      {3, 4, 1, 4.5, 0},   /* Grashof (5.5 <= 7) but the rocker is the shortest */
      {1, 4.5, 3, 4, 1},   /* the longest link anywhere */
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    mech_fourbar p = {cases[i].a, cases[i].b, cases[i].e, cases[i].d, 1, 1, 0};
    ck_assert_int_eq(mech_fourbar_crank_rocker(&p), cases[i].crank_rocker);
  }
}
END_TEST

/* ---- the derivatives along the motion, against sdae_mbs_check's differences ------------------ */

/* what every one of these mechanisms gives: G, (d/ds M) v, d/ds G, and a potential (so the
 * force is checked against -dV/dq, the Lagrangian's velocity terms, 0 here, and -D v) */
static const unsigned point_masses_given =
    1u << SDAE_MBS_JACOBIAN | 1u << SDAE_MBS_MASS_DOT_V | 1u << SDAE_MBS_JACOBIAN_DOT |
    1u << SDAE_MBS_FORCE | 1u << SDAE_MBS_CONSTRAINT_T | 1u << SDAE_MBS_CONSTRAINT_T_DOT;

/* states away from symmetries: no angle a multiple of pi/4, every velocity non-zero, the
 * pendulum's also off its circle (the check needs no consistent state) */
START_TEST(test_derivatives_pendulum) {
  mechanisms m;
  all_mechanisms(&m);
  double q[2], v[2];
  mech_pendulum_state(&m.pend, 0.7, -1.9, q, v);
  tu_assert_derivatives_exact(&m.sys[0], 0.3, q, v, point_masses_given);
  const double q_off[2] = {0.93, -0.71}, v_off[2] = {0.37, 1.21};
  tu_assert_derivatives_exact(&m.sys[0], 0.3, q_off, v_off, point_masses_given);
  /* with damping the force gains -d v, checked against -D v */
  mech_pendulum damped = m.pend;
  sdae_mbs sys;
  damped.d = 0.4;
  mech_pendulum_system(&sys, &damped);
  tu_assert_derivatives_exact(&sys, 0.3, q_off, v_off, point_masses_given);
}
END_TEST

START_TEST(test_derivatives_double_pendulum) {
  mechanisms m;
  all_mechanisms(&m);
  const double a[2][2] = {{2.1, -0.6}, {-0.4, 1.3}}, w[2][2] = {{0.8, -1.7}, {-2.2, 0.9}};
  double q[4], v[4];
  for (int k = 0; k < 2; k++) {
    mech_double_pendulum_state(&m.dpend, a[k], w[k], q, v);
    tu_assert_derivatives_exact(&m.sys[1], 0.0, q, v, point_masses_given);
  }
}
END_TEST

START_TEST(test_derivatives_fourbar) {
  mechanisms m;
  all_mechanisms(&m);
  const double theta[2] = {0.9, -2.2}, omega[2] = {2.3, -4.1};
  double q[4], v[4];
  for (int k = 0; k < 2; k++) {
    ck_assert_int_eq(mech_fourbar_state(&m.fourbar, theta[k], omega[k], q, v), 0);
    tu_assert_derivatives_exact(&m.sys[2], 0.0, q, v, point_masses_given);
  }
}
END_TEST

/* A copy of a mechanism whose jacobian_dot has one entry of the wrong sign, the error a hand
 * derivation makes most easily ((d/ds M) v = 0 here has no sign to get wrong). */
static int (*true_jacobian_dot)(double t, const double *q, const double *v, double *Gdot,
                                void *params);
static size_t flipped_entry;

static int flipped_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                                void *params) {
  int rc = true_jacobian_dot(t, q, v, Gdot, params);
  Gdot[flipped_entry] = -Gdot[flipped_entry];
  return rc;
}

/* the check finds it: inconsistent, jacobian_dot the worst at that entry, the others exact */
static void assert_flip_found(const sdae_mbs *s, size_t entry, double t, const double *q,
                              const double *v) {
  sdae_mbs wrong = *s;
  sdae_mbs_check_report r;
  true_jacobian_dot = s->jacobian_dot, flipped_entry = entry;
  wrong.jacobian_dot = flipped_jacobian_dot;
  ck_assert_int_eq(sdae_mbs_check(&wrong, t, q, v, 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_int_eq(r.worst, SDAE_MBS_JACOBIAN_DOT);
  ck_assert_uint_eq(r.worst_index, entry);
  for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++)
    if (d != SDAE_MBS_JACOBIAN_DOT) ck_assert_double_lt(r.mismatch[d], 1e-7);
}

/* one entry each, non-zero at the state (a flipped 0 is no error) */
START_TEST(test_wrong_sign_found) {
  mechanisms m;
  all_mechanisms(&m);
  double q[4], v[4];
  /* the pendulum: Gdot = (v_x, v_y), entry 1 is v_y = 1.21 */
  const double q_off[2] = {0.93, -0.71}, v_off[2] = {0.37, 1.21};
  assert_flip_found(&m.sys[0], 1, 0.3, q_off, v_off);
  /* the double pendulum: entry 6, the second arm's row in x2, v_x2 - v_x1 = L2 w2 cos a2 =
   * 0.8 0.9 cos 1.3 = 0.19 */
  const double a[2] = {-0.4, 1.3}, w[2] = {-2.2, 0.9};
  mech_double_pendulum_state(&m.dpend, a, w, q, v);
  assert_flip_found(&m.sys[1], 6, 0.0, q, v);
  /* the four-bar: entry 11, the rocker's row in Cy, C's vertical velocity (D is fixed) */
  ck_assert_int_eq(mech_fourbar_state(&m.fourbar, -2.2, -4.1, q, v), 0);
  ck_assert_double_gt(fabs(v[3]), 0.1);
  assert_flip_found(&m.sys[2], 11, 0.0, q, v);
}
END_TEST

/* ---- integrated through the front-end ------------------------------------------------------- */

static const double two_pi = 6.283185307179586;

typedef struct run_result {
  double E0, E1, max_c; /* energy at the start and the end, max |c| over the run */
  double angle;         /* the angle of (q[0], q[1]) continued over the run */
  unsigned long switches;
} run_result;

static int run(const sdae_mbs *sys, const sdae_map_type *map, double T, size_t n, double *q,
               double *v, run_result *res) {
  sdae_options o;
  sdae_mbs_stepper *s = NULL;
  sdae_options_default(&o);
  o.map = map;
  o.delta = 2.0;
  int status = sdae_mbs_stepper_alloc(&s, sys, &o);
  ck_assert_int_eq(status, SDAE_OK);
  *res = (run_result){0};
  sdae_mbs_energy(s, 0, q, v, &res->E0);
  for (size_t i = 0; i < n && status == SDAE_OK; i++) {
    double before = atan2(q[1], q[0]);
    status = sdae_mbs_step(s, (double)i * T, T, q, v);
    res->angle += remainder(atan2(q[1], q[0]) - before, two_pi);
    res->max_c = fmax(res->max_c, mech_max_abs_c(sys, 0, q));
  }
  sdae_mbs_energy(s, 0, q, v, &res->E1);
  res->switches = sdae_mbs_stepper_stats(s)->chart_switches;
  sdae_mbs_stepper_free(s);
  return status;
}

static double pendulum_error(const sdae_map_type *map, double T) {
  mech_pendulum p = {.L = 1.3, .m = 0.7, .ga = 9.81};
  sdae_mbs sys;
  run_result res;
  mech_pendulum_system(&sys, &p);
  double q[2] = {1.3 * sin(1.0), -1.3 * cos(1.0)}, v[2] = {0, 0};
  ck_assert_int_eq(run(&sys, map, T, (size_t)lround(1.0 / T), q, v, &res), SDAE_OK);
  double theta, omega; /* the exact swing (Jacobi elliptic functions) */
  mech_pendulum_exact(&p, 1.0, 1.0, &theta, &omega);
  return fabs(atan2(q[0], -q[1]) - theta);
}

/* the angle at t = 1 from theta0 = 1 against the exact solution: order 2 for dgrad and
 * midpoint, 4 for dg4 (measured 1.9, 2.0, 4.0; dg4 at T = 0.0025, where the error, 3e-11, is
 * in the asymptotic range and above rounding) */
START_TEST(test_pendulum_order) {
  const sdae_map_type *maps[3] = {sdae_map_dgrad, sdae_map_midpoint, sdae_map_dg4};
  const double order[3] = {2, 2, 4}, T[3] = {0.004, 0.004, 0.0025};
  for (int k = 0; k < 3; k++) {
    double e1 = pendulum_error(maps[k], T[k]), e2 = pendulum_error(maps[k], T[k] / 2);
    ck_assert_double_eq_tol(log2(e1 / e2), order[k], 0.15);
  }
}
END_TEST

/* lambda = m (|v|^2 - ga y)/L^2: the rod's tension balances gravity's radial part and
 * supplies the centripetal force m |v|^2/L */
START_TEST(test_pendulum_lambda) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  mech_pendulum p = {.L = 1.3, .m = 0.7, .ga = 9.81};
  sdae_mbs sys;
  sdae_options o;
  sdae_mbs_stepper *s = NULL;
  mech_pendulum_system(&sys, &p);
  sdae_options_default(&o);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  for (int n = 0; n < 50; n++) {
    double th = tu_flat(r, -3, 3), w = tu_flat(r, -3, 3), lambda;
    double q[2] = {1.3 * sin(th), -1.3 * cos(th)}, v[2] = {1.3 * w * cos(th), 1.3 * w * sin(th)};
    ck_assert_int_eq(sdae_mbs_lambda(s, 0, q, v, &lambda), SDAE_OK);
    double want = 0.7 * (v[0] * v[0] + v[1] * v[1] - 9.81 * q[1]) / (1.3 * 1.3);
    ck_assert_double_eq_tol(lambda, want, 1e-12 * (1 + fabs(want)));
  }
  sdae_mbs_stepper_free(s);
  gsl_rng_free(r);
}
END_TEST

/* the default chaotic start: the discrete gradient keeps E = ga (m1 y1 + m2 y2) (at rest)
 * through the chart switches, the constraints stay at rounding */
START_TEST(test_double_pendulum_energy) {
  mechanisms m;
  all_mechanisms(&m);
  double q[4], v[4], a[2] = {2.0, 2.5}, w[2] = {0, 0};
  run_result res;
  mech_double_pendulum_state(&m.dpend, a, w, q, v);
  double E = 9.81 * (0.6 * -1.1 * cos(2.0) + 1.7 * (-1.1 * cos(2.0) - 0.8 * cos(2.5)));
  ck_assert_int_eq(run(&m.sys[1], sdae_map_dgrad, 1e-3, 3000, q, v, &res), SDAE_OK);
  ck_assert_double_eq_tol(res.E0, E, 1e-13 * fabs(E));
  ck_assert_double_eq_tol(res.E1, E, 1e-11 * fabs(E));
  ck_assert_double_lt(res.max_c, 1e-13);
  ck_assert_uint_gt(res.switches, 0); /* the arms go over the top: no one chart serves */
}
END_TEST

/* the default crank-rocker from crank speed 5 under gravity: E - max V > 0 along the loop, so
 * the crank never stops: it turns at >= 3.69 rad/s (from the energy, by hand), more than
 * 2 pi in 2 s, with the energy kept */
START_TEST(test_fourbar_turns) {
  mech_fourbar p = {1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81};
  sdae_mbs sys;
  double q[4], v[4];
  run_result res;
  mech_fourbar_system(&sys, &p);
  ck_assert_int_eq(mech_fourbar_state(&p, 0.0, 5.0, q, v), 0);
  ck_assert_int_eq(run(&sys, sdae_map_dgrad, 1e-3, 2000, q, v, &res), SDAE_OK);
  ck_assert_double_gt(res.angle, 2 * 3.69);
  ck_assert_double_eq_tol(res.E1, res.E0, 1e-11 * fabs(res.E0));
  ck_assert_double_lt(res.max_c, 1e-13);
  ck_assert_uint_gt(res.switches, 0); /* B's dependent coordinate changes as the crank turns */
}
END_TEST

/* the separation of two starts 1e-9 apart after t = 8: amplified more than 1e4 times from the
 * default (a positive Lyapunov exponent; measured 2.7e-4), less than 10 times from small
 * swings (0.1, 0.1), where the double pendulum is close to its linearization, two normal
 * modes, and separations grow at most linearly (measured 7e-10) */
static double separation(double a1, double a2) {
  mech_double_pendulum p = {1.0, 1.0, 1.0, 1.0, 9.81}; /* the program's default */
  sdae_mbs sys;
  double q[2][4], v[2][4], w[2] = {0, 0};
  run_result res;
  mech_double_pendulum_system(&sys, &p);
  for (int k = 0; k < 2; k++) {
    double a[2] = {a1, a2 + 1e-9 * k};
    mech_double_pendulum_state(&p, a, w, q[k], v[k]);
    ck_assert_int_eq(run(&sys, sdae_map_dgrad, 1e-3, 8000, q[k], v[k], &res), SDAE_OK);
  }
  double d = 0.0;
  for (int i = 0; i < 4; i++) d = fmax(d, fabs(q[0][i] - q[1][i]));
  return d;
}

START_TEST(test_double_pendulum_chaos) {
  ck_assert_double_gt(separation(2.0, 2.5), 1e-5);
  ck_assert_double_lt(separation(0.1, 0.1), 1e-8);
}
END_TEST

static Suite *mechanisms_suite(void) {
  Suite *s = suite_create("mechanisms");
  TCase *tc = tcase_create("callbacks");
  tcase_add_test(tc, test_jacobian);
  tcase_add_test(tc, test_force_mass);
  tcase_add_test(tc, test_start_states);
  tcase_add_test(tc, test_grashof);
  suite_add_tcase(s, tc);
  tc = tcase_create("derivatives");
  tcase_add_test(tc, test_derivatives_pendulum);
  tcase_add_test(tc, test_derivatives_double_pendulum);
  tcase_add_test(tc, test_derivatives_fourbar);
  suite_add_tcase(s, tc);
  tc = tcase_create("derivative_errors");
  tcase_add_test(tc, test_wrong_sign_found);
  suite_add_tcase(s, tc);
  tc = tcase_create("integrated");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_pendulum_order);
  tcase_add_test(tc, test_pendulum_lambda);
  tcase_add_test(tc, test_double_pendulum_energy);
  tcase_add_test(tc, test_fourbar_turns);
  tcase_add_test(tc, test_double_pendulum_chaos);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(mechanisms_suite());
  srunner_run_all(sr, CK_NORMAL);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
