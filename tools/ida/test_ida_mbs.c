/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Check suite of IDA for mechanisms (ida_mbs.h): the pendulum against its elliptic solution,
 * the double pendulum and a pendulum with a moving pivot against GSL's rk8pd on their angle
 * equations, the four-bar's energy, the rod tension, and the work at two tolerances; the KLU path
 * on the rope of examples/models/rope.h against the dense one, its iteration matrix against the
 * exact one, and what it refuses. Every bound comes from the mathematics or the requested
 * tolerance. */
#include "ida_mbs.h"

#include <check.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_sf_ellint.h>
#include <gsl/gsl_sf_elljac.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "benchmarks.h"
#include "mechanisms.h"
#include "rope.h"

static const char *form_name(idambs_form form) { return form == IDAMBS_GGL ? "ggl" : "index1"; }

static idaref_options options(double rtol, double tf, double dt) {
  return (idaref_options){
      .rtol = rtol, .atol = rtol / 100.0, .tf = tf, .dt = dt, .max_steps = 100000};
}

static void solve_ok(const sdae_mbs *sys, idambs_form form, const double *q0, const double *v0,
                     const idaref_options *o, idambs_row_fn row, void *ctx, idaref_result *res) {
  int status = idambs_solve(sys, form, 0.0, q0, v0, o, row, ctx, res);
  ck_assert_msg(status == IDAREF_OK, "%s failed with %s at t = %g: %s", res->function,
                res->flag_name, res->t_reached, res->message);
}

static void print_stats(const char *what, idambs_form form, const idaref_result *res) {
  const idaref_stats *s = &res->stats;
  printf("  %-6s steps %ld, res %ld, jac %ld, nonlinear iterations %ld, etf %ld, ncf %ld (%s)\n",
         form_name(form), s->steps, s->res_evals, s->jac_evals, s->nonlin_iters, s->err_test_fails,
         s->nonlin_conv_fails, what);
}

/* IDA keeps each step's local error near rtol |y| (atol = rtol/100), and on these bounded,
 * non-chaotic motions the local errors add up at most linearly, so the global error of a
 * quantity of size `scale` stays below steps * rtol * scale. */
static double global_bound(const idaref_options *o, const idaref_result *res, double scale) {
  return (double)res->stats.steps * o->rtol * scale;
}

/* ---- the pendulum: elliptic solution and rod tension --------------------------------------- */

/* From rest at theta0: sin(theta/2) = s sn(K(s) - w t; s), s = sin(theta0/2), w = sqrt(ga/L);
 * GSL's ellint_Kcomp takes the modulus s, elljac the parameter s^2;
 * theta' = -2 s w cn dn / cos(theta/2). */
static void pendulum_exact(const mech_pendulum *p, double theta0, double t, double *theta,
                           double *thetadot) {
  double s = sin(0.5 * theta0), w = sqrt(p->ga / p->L), sn, cn, dn;
  double K = gsl_sf_ellint_Kcomp(s, GSL_PREC_DOUBLE);
  ck_assert_int_eq(gsl_sf_elljac_e(K - w * t, s * s, &sn, &cn, &dn), GSL_SUCCESS);
  *theta = 2.0 * asin(s * sn);
  *thetadot = -2.0 * s * w * cn * dn / cos(0.5 * *theta);
}

/* The rod tension of c = (|q|^2 - L^2)/2, M = m I, F = (0, -m ga): twice differentiating
 * |q|^2 = L^2 gives q.v' + |v|^2 = 0 with m v' = F - lambda q, so lambda = m (|v|^2 - ga y)/L^2. */
static double tension(const mech_pendulum *p, const double *q, const double *v) {
  return p->m * (v[0] * v[0] + v[1] * v[1] - p->ga * q[1]) / (p->L * p->L);
}

typedef struct pendulum_rec {
  const mech_pendulum *p;
  double theta0;
  double err_q, err_v, err_lambda, lambda_vs_state, max_c;
} pendulum_rec;

static int pendulum_row(double t, const double *q, const double *v, const double *lambda,
                        void *ctx) {
  pendulum_rec *r = ctx;
  const mech_pendulum *p = r->p;
  double th, thd;
  pendulum_exact(p, r->theta0, t, &th, &thd);
  r->err_q = fmax(r->err_q, fmax(fabs(q[0] - p->L * sin(th)), fabs(q[1] + p->L * cos(th))));
  r->err_v =
      fmax(r->err_v, fmax(fabs(v[0] - p->L * cos(th) * thd), fabs(v[1] - p->L * sin(th) * thd)));
  /* lambda L^2 = m (L^2 theta'^2 + ga L cos theta), theta'^2 = 2 (ga/L)(cos th - cos th0) */
  r->err_lambda = fmax(r->err_lambda, fabs(lambda[0] - p->m * p->ga / p->L *
                                                           (3.0 * cos(th) - 2.0 * cos(r->theta0))));
  r->lambda_vs_state = fmax(r->lambda_vs_state, fabs(lambda[0] - tension(p, q, v)));
  r->max_c = fmax(r->max_c, fabs(q[0] * q[0] + q[1] * q[1] - p->L * p->L) / 2.0);
  return 0;
}

START_TEST(pendulum_matches_elliptic_solution) {
  idambs_form form = _i ? IDAMBS_GGL : IDAMBS_INDEX1;
  mech_pendulum p = {.L = 1.3, .m = 0.7, .ga = 9.81};
  const double theta0 = 0.8, q0[2] = {p.L * sin(theta0), -p.L * cos(theta0)}, v0[2] = {0, 0};
  idaref_options o = options(1e-10, 5.0, 0.05);
  pendulum_rec r = {.p = &p, .theta0 = theta0};
  idaref_result res;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  solve_ok(&sys, form, q0, v0, &o, pendulum_row, &r, &res);
  double vscale = sqrt(p.ga * p.L), lscale = p.m * p.ga / p.L;
  printf("pendulum: |q - exact| %.2e, |v - exact| %.2e, |lambda - exact| %.2e, "
         "|lambda - m(|v|^2 - ga y)/L^2| %.2e, max |c| %.2e\n",
         r.err_q, r.err_v, r.err_lambda, r.lambda_vs_state, r.max_c);
  print_stats("pendulum rtol 1e-10", form, &res);
  ck_assert_double_le(r.err_q, global_bound(&o, &res, p.L));
  ck_assert_double_le(r.err_v, global_bound(&o, &res, vscale));
  /* lambda is a smooth function of (q, v) (tension): its error is that of the state, times
   * the tension's derivatives m |v| / L^2 ~ lscale / vscale and m ga / L^2 */
  ck_assert_double_le(r.err_lambda, 3.0 * global_bound(&o, &res, lscale));
  if (form == IDAMBS_GGL) /* c = 0 is an equation of GGL, solved to Newton's tolerance */
    ck_assert_double_le(r.max_c, o.rtol * p.L * p.L);
  else /* index 1 drifts: |c| = |(|q|^2 - L^2)/2| <= L |dq| + |dq|^2 / 2 */
    ck_assert_double_le(r.max_c, p.L * global_bound(&o, &res, p.L));
}
END_TEST

/* The tension at arbitrary states on the manifold, from the callbacks with the jacobian and by
 * differences of c alone (fourth order: about 1e-10 relative). */
START_TEST(lambda_is_the_rod_tension) {
  mech_pendulum p = {.L = 1.7, .m = 2.3, .ga = 9.81};
  sdae_mbs sys;
  mech_pendulum_system(&sys, &p);
  if (_i) sys.jacobian = NULL, sys.jacobian_dot = NULL; /* differences: Gdot needs G */
  for (double th = -2.9; th < 3.0; th += 0.7) {
    const double q[2] = {p.L * sin(th), -p.L * cos(th)};
    const double w = 1.5 - th, v[2] = {p.L * w * cos(th), p.L * w * sin(th)};
    double lambda, vdot[2], expect = tension(&p, q, v);
    ck_assert_int_eq(idambs_lambda(&sys, 0.0, q, v, &lambda, vdot), 0);
    ck_assert_msg(fabs(lambda - expect) <= 1e-9 * fabs(expect) + 1e-12, "theta %g: %.17g vs %.17g",
                  th, lambda, expect);
    /* v' = (F - G^T lambda)/m: the gravity plus the pull towards the pivot */
    ck_assert_double_le(fabs(vdot[0] + lambda * q[0] / p.m), 1e-9 * p.ga);
    ck_assert_double_le(fabs(vdot[1] + p.ga + lambda * q[1] / p.m), 1e-9 * p.ga);
  }
}
END_TEST

/* ---- the double pendulum against its angle equations ---------------------------------------- */

/* Lagrange's equations in the angles a_i from the downward vertical (d = a1 - a2):
 * (m1 + m2) L1 a1'' + m2 L2 cos d a2'' = -m2 L2 a2'^2 sin d - (m1 + m2) ga sin a1,
 * L1 cos d a1'' + L2 a2'' = L1 a1'^2 sin d - ga sin a2. */
static int double_pendulum_ode(double t, const double *y, double *dy, void *params) {
  const mech_double_pendulum *p = params;
  double d = y[0] - y[1], m = p->m1 + p->m2;
  double a11 = m * p->L1, a12 = p->m2 * p->L2 * cos(d), a21 = p->L1 * cos(d), a22 = p->L2;
  double b1 = -p->m2 * p->L2 * y[3] * y[3] * sin(d) - m * p->ga * sin(y[0]);
  double b2 = p->L1 * y[2] * y[2] * sin(d) - p->ga * sin(y[1]);
  double det = a11 * a22 - a12 * a21;
  (void)t;
  dy[0] = y[2];
  dy[1] = y[3];
  dy[2] = (b1 * a22 - a12 * b2) / det;
  dy[3] = (a11 * b2 - a21 * b1) / det;
  return GSL_SUCCESS;
}

/* y (n values) from t = 0 to t1 by rk8pd at 1e-13 */
static void rk8pd(int (*f)(double, const double *, double *, void *), void *params, size_t n,
                  double t1, double *y) {
  gsl_odeiv2_system ode = {f, NULL, n, params};
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(&ode, gsl_odeiv2_step_rk8pd, 1e-3, 1e-13, 1e-13);
  double t = 0.0;
  ck_assert_ptr_nonnull(d);
  ck_assert_int_eq(gsl_odeiv2_driver_apply(d, &t, t1, y), GSL_SUCCESS);
  gsl_odeiv2_driver_free(d);
}

typedef struct last_row {
  size_t n_q, n_c;
  double t, q[8], v[8], lambda[8];
} last_row;

static int keep_last(double t, const double *q, const double *v, const double *lambda, void *ctx) {
  last_row *r = ctx;
  r->t = t;
  memcpy(r->q, q, r->n_q * sizeof *q);
  memcpy(r->v, v, r->n_q * sizeof *v);
  memcpy(r->lambda, lambda, r->n_c * sizeof *lambda);
  return 0;
}

START_TEST(double_pendulum_matches_angle_equations) {
  idambs_form form = _i ? IDAMBS_GGL : IDAMBS_INDEX1;
  mech_double_pendulum p = {.L1 = 1.0, .L2 = 0.8, .m1 = 1.0, .m2 = 0.6, .ga = 9.81};
  double a[4] = {0.9, -0.4, 0.0, 1.5}, q0[4], v0[4], q[4], v[4], err_q = 0.0, err_v = 0.0;
  idaref_options o = options(1e-10, 2.0, 0.5);
  last_row r = {.n_q = 4, .n_c = 2};
  idaref_result res;
  sdae_mbs sys;
  mech_double_pendulum_system(&sys, &p);
  mech_double_pendulum_state(&p, a, a + 2, q0, v0);
  solve_ok(&sys, form, q0, v0, &o, keep_last, &r, &res);
  rk8pd(double_pendulum_ode, &p, 4, 2.0, a);
  mech_double_pendulum_state(&p, a, a + 2, q, v);
  for (int i = 0; i < 4; i++) {
    err_q = fmax(err_q, fabs(r.q[i] - q[i]));
    err_v = fmax(err_v, fabs(r.v[i] - v[i]));
  }
  printf("double pendulum at t = 2: |q - rk8pd| %.2e, |v - rk8pd| %.2e\n", err_q, err_v);
  print_stats("double pendulum rtol 1e-10", form, &res);
  ck_assert_double_eq(r.t, 2.0);
  ck_assert_double_le(err_q, global_bound(&o, &res, p.L1 + p.L2));
  ck_assert_double_le(err_v, global_bound(&o, &res, sqrt(p.ga * (p.L1 + p.L2))));
}
END_TEST

/* ---- the four-bar: energy and constraints --------------------------------------------------- */

typedef struct fourbar_rec {
  const sdae_mbs *sys;
  const mech_fourbar *p;
  double E0, max_dE, max_c;
  size_t rows;
} fourbar_rec;

static int fourbar_row(double t, const double *q, const double *v, const double *lambda,
                       void *ctx) {
  fourbar_rec *r = ctx;
  const mech_fourbar *p = r->p;
  double V, E;
  (void)lambda;
  ck_assert_int_eq(r->sys->potential(t, q, &V, r->sys->params), 0);
  E = 0.5 * (p->mB * (v[0] * v[0] + v[1] * v[1]) + p->mC * (v[2] * v[2] + v[3] * v[3])) + V;
  if (r->rows++ == 0) r->E0 = E;
  r->max_dE = fmax(r->max_dE, fabs(E - r->E0));
  r->max_c = fmax(r->max_c, mech_max_abs_c(r->sys, t, q));
  return 0;
}

static mech_fourbar fourbar_default(void) {
  return (mech_fourbar){.a = 1.0, .b = 4.0, .e = 3.0, .d = 4.5, .mB = 1.0, .mC = 1.0, .ga = 9.81};
}

/* Conservative (gravity, ideal joints): the energy is constant; 3 s are about two crank turns. */
START_TEST(fourbar_conserves_energy) {
  idambs_form form = _i ? IDAMBS_GGL : IDAMBS_INDEX1;
  mech_fourbar p = fourbar_default();
  double q0[4], v0[4];
  idaref_options o = options(1e-10, 3.0, 0.01);
  idaref_result res;
  sdae_mbs sys;
  fourbar_rec r = {.sys = &sys, .p = &p};
  mech_fourbar_system(&sys, &p);
  ck_assert_int_eq(mech_fourbar_state(&p, 0.0, 5.0, q0, v0), 0);
  solve_ok(&sys, form, q0, v0, &o, fourbar_row, &r, &res);
  printf("fourbar: E0 %.6f, relative energy drift %.2e, max |c| %.2e\n", r.E0, r.max_dE / r.E0,
         r.max_c);
  print_stats("fourbar rtol 1e-10", form, &res);
  ck_assert_double_le(r.max_dE, 1e-8 * r.E0);
  if (form == IDAMBS_GGL)
    ck_assert_double_le(r.max_c, o.rtol * p.d * p.d);
  else
    ck_assert_double_le(r.max_c, p.d * global_bound(&o, &res, p.d));
}
END_TEST

/* The work of BDF orders 1 to 5: a tolerance 1000 times tighter costs 1000^(1/(k+1)) times the
 * steps at order k, at most 1000^(1/2) ~ 32 (order 1), and at least more steps; one output at
 * tf, so the count is IDA's own. (Measured: about 2.5 to 2.9, below order 5's 3.2: at rtol 1e-6
 * the steps are limited by Newton and error test failures as much as by accuracy.) */
START_TEST(fourbar_work_follows_tolerance) {
  idambs_form form = _i ? IDAMBS_GGL : IDAMBS_INDEX1;
  mech_fourbar p = fourbar_default();
  double q0[4], v0[4], rtol[2] = {1e-6, 1e-9};
  long steps[2];
  sdae_mbs sys;
  mech_fourbar_system(&sys, &p);
  ck_assert_int_eq(mech_fourbar_state(&p, 0.0, 5.0, q0, v0), 0);
  for (int i = 0; i < 2; i++) {
    idaref_options o = options(rtol[i], 3.0, 3.0);
    fourbar_rec r = {.sys = &sys, .p = &p};
    idaref_result res;
    char what[64];
    solve_ok(&sys, form, q0, v0, &o, fourbar_row, &r, &res);
    snprintf(what, sizeof what, "fourbar rtol %.0e, energy drift %.1e", rtol[i], r.max_dE / r.E0);
    print_stats(what, form, &res);
    steps[i] = res.stats.steps;
  }
  ck_assert_int_gt(steps[1], steps[0]);
  ck_assert_double_le((double)steps[1], pow(1000.0, 1.0 / 2.0) * (double)steps[0]);
}
END_TEST

/* ---- a time-dependent constraint: the pendulum on a moving pivot ---------------------------- */

/* q = (x, y) on a rod L from the pivot p(t) = (a sin w t, 0): c = (|q - p(t)|^2 - L^2)/2,
 * G = (q - p)^T, dc/dt = -(q - p).p'(t); M = m I, F = (0, -m ga). */
typedef struct moving_pivot {
  double L, m, ga, a, w;
} moving_pivot;

static void pivot(const moving_pivot *p, double t, double *P, double *Pdot) {
  P[0] = p->a * sin(p->w * t), P[1] = 0.0;
  Pdot[0] = p->a * p->w * cos(p->w * t), Pdot[1] = 0.0;
}

static int mp_mass(double t, const double *q, double *M, void *params) {
  const moving_pivot *p = params;
  (void)t, (void)q;
  M[0] = M[3] = p->m, M[1] = M[2] = 0.0;
  return 0;
}

static int mp_force(double t, const double *q, const double *v, double *F, void *params) {
  const moving_pivot *p = params;
  (void)t, (void)q, (void)v;
  F[0] = 0.0, F[1] = -p->m * p->ga;
  return 0;
}

static int mp_constraint(double t, const double *q, double *c, void *params) {
  const moving_pivot *p = params;
  double P[2], Pd[2];
  pivot(p, t, P, Pd);
  c[0] = ((q[0] - P[0]) * (q[0] - P[0]) + (q[1] - P[1]) * (q[1] - P[1]) - p->L * p->L) / 2.0;
  return 0;
}

static int mp_jacobian(double t, const double *q, double *G, void *params) {
  double P[2], Pd[2];
  pivot(params, t, P, Pd);
  G[0] = q[0] - P[0], G[1] = q[1] - P[1];
  return 0;
}

static int mp_constraint_t(double t, const double *q, double *ct, void *params) {
  double P[2], Pd[2];
  pivot(params, t, P, Pd);
  ct[0] = -(q[0] - P[0]) * Pd[0] - (q[1] - P[1]) * Pd[1];
  return 0;
}

/* theta from the downward vertical, q = p + L (sin th, -cos th): the tangential part of
 * m q'' = F - lambda (q - p), with p'' = (-a w^2 sin w t, 0), is
 * L theta'' = -ga sin theta + a w^2 sin(w t) cos theta. */
static int moving_pivot_ode(double t, const double *y, double *dy, void *params) {
  const moving_pivot *p = params;
  dy[0] = y[1];
  dy[1] = (-p->ga * sin(y[0]) + p->a * p->w * p->w * sin(p->w * t) * cos(y[0])) / p->L;
  return GSL_SUCCESS;
}

typedef struct pivot_rec {
  moving_pivot *p;
  double y[2], t; /* rk8pd's state at t */
  double err_q, err_v;
} pivot_rec;

static int pivot_row(double t, const double *q, const double *v, const double *lambda, void *ctx) {
  pivot_rec *r = ctx;
  const moving_pivot *p = r->p;
  double P[2], Pd[2], th = r->y[0], thd = r->y[1];
  (void)lambda;
  if (t > r->t) { /* rk8pd from the last row on: a restart from 0 each time would cost more */
    gsl_odeiv2_system ode = {moving_pivot_ode, NULL, 2, r->p};
    gsl_odeiv2_driver *d =
        gsl_odeiv2_driver_alloc_y_new(&ode, gsl_odeiv2_step_rk8pd, 1e-3, 1e-13, 1e-13);
    ck_assert_int_eq(gsl_odeiv2_driver_apply(d, &r->t, t, r->y), GSL_SUCCESS);
    gsl_odeiv2_driver_free(d);
    th = r->y[0], thd = r->y[1];
  }
  pivot(p, t, P, Pd);
  r->err_q =
      fmax(r->err_q, fmax(fabs(q[0] - P[0] - p->L * sin(th)), fabs(q[1] - P[1] + p->L * cos(th))));
  r->err_v = fmax(r->err_v, fmax(fabs(v[0] - Pd[0] - p->L * cos(th) * thd),
                                 fabs(v[1] - Pd[1] - p->L * sin(th) * thd)));
  return 0;
}

/* _i: bit 0 the form, bit 1 without jacobian and constraint_t (fourth-order differences).
 * GGL from differences runs at rtol 1e-8: its rows c = 0 and G v + dc/dt = 0 then carry
 * rounding noise of about 1e-13 relative (eps / step of the differences), which its index-2
 * Newton amplifies as 1/h^2; at rtol 1e-10 IDA fails at t = 0 (IDA_CONV_FAIL). */
START_TEST(moving_pivot_matches_angle_equation) {
  idambs_form form = _i & 1 ? IDAMBS_GGL : IDAMBS_INDEX1;
  moving_pivot p = {.L = 1.0, .m = 1.5, .ga = 9.81, .a = 0.1, .w = 5.0};
  sdae_mbs sys = {.n_q = 2,
                  .n_c = 1,
                  .mass = mp_mass,
                  .force = mp_force,
                  .constraint = mp_constraint,
                  .jacobian = mp_jacobian,
                  .constraint_t = mp_constraint_t,
                  .params = &p};
  const double theta0 = 0.3;
  /* at rest relative to the pivot, which starts at the origin moving at a w */
  const double q0[2] = {p.L * sin(theta0), -p.L * cos(theta0)}, v0[2] = {p.a * p.w, 0.0};
  idaref_options o = options(_i == 3 ? 1e-8 : 1e-10, 4.0, 0.1);
  pivot_rec r = {.p = &p, .y = {theta0, 0.0}};
  idaref_result res;
  if (_i & 2) sys.jacobian = NULL, sys.constraint_t = NULL;
  solve_ok(&sys, form, q0, v0, &o, pivot_row, &r, &res);
  printf("moving pivot%s: |q - rk8pd| %.2e, |v - rk8pd| %.2e\n", _i & 2 ? " (differences)" : "",
         r.err_q, r.err_v);
  print_stats(o.rtol == 1e-8 ? "moving pivot rtol 1e-8" : "moving pivot rtol 1e-10", form, &res);
  ck_assert_double_eq(r.t, 4.0);
  ck_assert_double_le(r.err_q, global_bound(&o, &res, p.L));
  ck_assert_double_le(r.err_v, global_bound(&o, &res, sqrt(p.ga * p.L) + p.a * p.w));
}
END_TEST

/* ---- the driver ----------------------------------------------------------------------------- */

/* The rows sit at t0 + k DT and tf exactly, from a t0 other than 0 (a time-dependent c). */
START_TEST(rows_hit_output_times_from_t0) {
  moving_pivot p = {.L = 1.0, .m = 1.0, .ga = 9.81, .a = 0.1, .w = 5.0};
  sdae_mbs sys = {.n_q = 2,
                  .n_c = 1,
                  .mass = mp_mass,
                  .force = mp_force,
                  .constraint = mp_constraint,
                  .params = &p};
  const double t0 = 0.7, P[2] = {p.a * sin(p.w * t0), 0.0}, Pd = p.a * p.w * cos(p.w * t0);
  const double q0[2] = {P[0], -p.L}, v0[2] = {Pd, 0.0}; /* hanging, moving with the pivot */
  idaref_options o = options(1e-8, 1.75, 0.25);
  last_row r = {.n_q = 2, .n_c = 1};
  idaref_result res;
  ck_assert_int_eq(idambs_solve(&sys, IDAMBS_INDEX1, t0, q0, v0, &o, keep_last, &r, &res),
                   IDAREF_OK);
  ck_assert_double_eq(r.t, 1.75);
  ck_assert_double_eq(res.t_reached, 1.75);
}
END_TEST

static int fail_on_second(double t, const double *q, const double *v, const double *l, void *ctx) {
  int *rows = ctx;
  (void)t, (void)q, (void)v, (void)l;
  return ++*rows == 2;
}

START_TEST(failures_are_reported) {
  mech_pendulum p = {.L = 1.0, .m = 1.0, .ga = 9.81};
  const double q0[2] = {sin(0.5), -cos(0.5)}, v0[2] = {0.0, 0.0}, origin[2] = {0.0, 0.0};
  idaref_options o = options(1e-10, 10.0, 1.0);
  idaref_result res;
  sdae_mbs sys;
  int rows = 0;
  mech_pendulum_system(&sys, &p);
  o.max_steps = 5;
  ck_assert_int_eq(idambs_solve(&sys, IDAMBS_GGL, 0.0, q0, v0, &o, fail_on_second, &rows, &res),
                   IDAREF_IDA_FAILED);
  ck_assert_str_eq(res.flag_name, "IDA_TOO_MUCH_WORK");
  ck_assert_int_eq(res.stats.steps, 5);
  ck_assert_int_eq(rows, 1);
  o.max_steps = 100000;
  rows = 0;
  ck_assert_int_eq(idambs_solve(&sys, IDAMBS_INDEX1, 0.0, q0, v0, &o, fail_on_second, &rows, &res),
                   IDAREF_OUTPUT_FAILED);
  ck_assert_double_eq(res.t_reached, 1.0);
  /* at the pivot G = q = 0: G M^-1 G^T is singular */
  ck_assert_int_eq(
      idambs_solve(&sys, IDAMBS_INDEX1, 0.0, origin, v0, &o, fail_on_second, &rows, &res),
      IDAMBS_START_FAILED);
  ck_assert_str_eq(res.function, "idambs_lambda");
}
END_TEST

/* ---- the slider crank: stabdae's front-end meets IDA ---------------------------------------- */

/* (q, v) at t = 10 by the front-end (scheme 15, dg4) from idaSlCrank_dns's start */
static void slider_crank_stabdae(double T, double *y) {
  bench_slider_crank p = bench_slider_crank_default();
  sdae_mbs sys;
  sdae_options o;
  sdae_mbs_stepper *s;
  bench_slider_crank_system(&sys, &p);
  bench_slider_crank_initial(&p, y, y + 3);
  sdae_options_default(&o);
  o.delta = 2.0, o.map = sdae_map_dg4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  size_t n = (size_t)lround(10.0 / T);
  ck_assert_int_eq(sdae_mbs_integrate(s, 0.0, T, n, n, y, y + 3, NULL, NULL, NULL), SDAE_OK);
  sdae_mbs_stepper_free(s);
}

static double max_diff(const double *a, const double *b, size_t n) {
  double d = 0.0;
  for (size_t i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i]));
  return d;
}

/* The slider crank's end state at t = 10 (the examples' program) against IDA at rtol 1e-12:
 * dg4 at T = 0.01 is off its limit by about |y_0.02 - y_0.01| / 15 (Richardson, order 4), IDA
 * by at most its global bound (steps times the tolerance, about 5e-9 here); the two must agree
 * within the sum (measured 1.5e-10 in q and v; the bound 3.3e-9). */
START_TEST(slider_crank_stabdae_meets_ida) {
  bench_slider_crank p = bench_slider_crank_default();
  sdae_mbs sys;
  double q0[3], v0[3], coarse[6], fine[6];
  idaref_options o = options(1e-12, 10.0, 10.0);
  idaref_result res;
  last_row ida = {.n_q = 3, .n_c = 2};
  bench_slider_crank_system(&sys, &p);
  bench_slider_crank_initial(&p, q0, v0);
  solve_ok(&sys, IDAMBS_INDEX1, q0, v0, &o, keep_last, &ida, &res);
  slider_crank_stabdae(0.02, coarse);
  slider_crank_stabdae(0.01, fine);
  double richardson = max_diff(coarse, fine, 6) / 15.0;
  double bound = 2.0 * richardson + global_bound(&o, &res, 1.3);
  double dq = max_diff(fine, ida.q, 3), dv = max_diff(fine + 3, ida.v, 3);
  printf("slider crank at t = 10: |stabdae - IDA| = %.2g (q), %.2g (v); bound %.2g\n", dq, dv,
         bound);
  ck_assert_double_lt(dq, bound);
  ck_assert_double_lt(dv, bound);
}
END_TEST

/* ---- the KLU path: the rope given by its patterns ---------------------------------------- */

/* every row of a run: (q, v, lambda) at the output times */
typedef struct rope_rows {
  size_t n_q, n_c, rows, room;
  double *y; /* rows x (2 n_q + n_c) */
} rope_rows;

static int keep_rows(double t, const double *q, const double *v, const double *lambda, void *ctx) {
  rope_rows *r = ctx;
  double *y = r->y + r->rows * (2 * r->n_q + r->n_c);
  (void)t;
  ck_assert_uint_lt(r->rows, r->room);
  memcpy(y, q, r->n_q * sizeof *q);
  memcpy(y + r->n_q, v, r->n_q * sizeof *v);
  memcpy(y + 2 * r->n_q, lambda, r->n_c * sizeof *lambda);
  r->rows++;
  return 0;
}

/* the largest difference of rows a and b over the components [from, from + n) */
static double rows_diff(const rope_rows *a, const rope_rows *b, size_t from, size_t n) {
  size_t len = 2 * a->n_q + a->n_c;
  double d = 0.0;
  for (size_t k = 0; k < a->rows; k++)
    for (size_t i = from; i < from + n; i++)
      d = fmax(d, fabs(a->y[k * len + i] - b->y[k * len + i]));
  return d;
}

/* The rope of 15 masses, open or closed (_i bit 0), given by its patterns, by KLU (bit 1 clear)
 * or by the dense solver reading the patterns (bit 1 set), against the dense solver on the same
 * rope given densely, every 0.1 s for 1 s. Each run is within its global bound of the motion
 * (steps times rtol times the quantity's scale, as above), so the two within the sum: for q the
 * rope's length N L, for v the speed of a fall through it, sqrt(2 ga N L), for lambda (the
 * tensions over L, G^T lambda = lambda (p_j - p_{j-1})) three times the rope's weight over L, as
 * the pendulum's. */
START_TEST(rope_klu_meets_dense) {
  int closed = _i & 1, klu = !(_i & 2);
  const size_t N = 15;
  mech_rope sp = mech_rope_unit(N, closed, 1), de = mech_rope_unit(N, closed, 0);
  sdae_mbs sparse, dense;
  size_t nq = 2 * N, nc = mech_rope_constraints(&sp), len = 2 * nq + nc;
  double q0[30], v0[30];
  idaref_options o = options(1e-8, 1.0, 0.1);
  idaref_result ra, rb;
  rope_rows a = {nq, nc, 0, 11, calloc(11 * len, sizeof(double))};
  rope_rows b = {nq, nc, 0, 11, calloc(11 * len, sizeof(double))};
  ck_assert_ptr_nonnull(a.y);
  ck_assert_ptr_nonnull(b.y);
  ck_assert_int_eq(mech_rope_system(&sparse, &sp), 0);
  ck_assert_int_eq(mech_rope_system(&dense, &de), 0);
  ck_assert_int_eq(mech_rope_start(&sp, 0.3, q0, v0), 0);
  ck_assert_int_eq(idambs_solve_with(&sparse, IDAMBS_INDEX1, klu ? IDAMBS_KLU : IDAMBS_DENSE, 0.0,
                                     q0, v0, &o, keep_rows, &a, &ra),
                   IDAREF_OK);
  solve_ok(&dense, IDAMBS_INDEX1, q0, v0, &o, keep_rows, &b, &rb);
  ck_assert_uint_eq(a.rows, 11);
  ck_assert_uint_eq(b.rows, 11);
  double L = (double)N * sp.L, vs = sqrt(2.0 * sp.ga * L),
         ls = 3.0 * sp.m * sp.ga * (double)N / sp.L;
  double dq = rows_diff(&a, &b, 0, nq), dv = rows_diff(&a, &b, nq, nq);
  double dl = rows_diff(&a, &b, 2 * nq, nc);
  printf("rope N = %zu %s, %s on the patterns vs dense: |dq| %.2e, |dv| %.2e, |dlambda| %.2e "
         "(bounds %.1e, %.1e, %.1e)\n",
         N, closed ? "closed" : "open", klu ? "KLU" : "dense solver", dq, dv, dl,
         global_bound(&o, &ra, L) + global_bound(&o, &rb, L),
         global_bound(&o, &ra, vs) + global_bound(&o, &rb, vs),
         global_bound(&o, &ra, ls) + global_bound(&o, &rb, ls));
  print_stats(klu ? "rope, KLU" : "rope, dense on patterns", IDAMBS_INDEX1, &ra);
  print_stats("rope, dense", IDAMBS_INDEX1, &rb);
  ck_assert_double_le(dq, global_bound(&o, &ra, L) + global_bound(&o, &rb, L));
  ck_assert_double_le(dv, global_bound(&o, &ra, vs) + global_bound(&o, &rb, vs));
  ck_assert_double_le(dl, global_bound(&o, &ra, ls) + global_bound(&o, &rb, ls));
  if (klu) /* the grouped differences are counted with IDA's own */
    ck_assert_int_gt(ra.stats.lin_res_evals, 0);
  free(a.y), free(b.y);
  mech_rope_free(&sp);
  mech_rope_free(&de);
}
END_TEST

/* The KLU path's iteration matrix at an arbitrary state of the rope (open or closed) against the
 * exact one. The rope's residual, y = (q, v, lambda): q' - v; m v' - F + G(q)^T lambda, F
 * constant; G(q) v' + gamma, gamma_c = v^T H_c v, H_c = d^2 c_c / dq^2 constant, and H_c x is
 * the rope's jacobian_dot at x (rows of x's differences). So dF/dy + cj dF/dy' is
 *   q rows:      cj I in q, -I in v;
 *   v rows:      column k of q: sum_c lambda_c H_c e_k = Gdot(e_k)^T lambda; cj m I in v; G^T;
 *   lambda rows: Gdot(v') in q, 2 Gdot(v) + cj G in v.
 * The forward differences (increments inc = sqrt(eps) max(|y_j|, 1)) are exact for the bilinear
 * terms, off by inc for gamma's quadratic one, and carry the rounding of gamma's own stencil
 * (step h about 7e-4 along (1, v)) over the increment, about eps / (h inc) = 2e-5 of the terms
 * G v; 1e-4 of the row's largest entry holds both, and an entry missing from the structure would
 * be of that row's size. */
START_TEST(rope_klu_matrix_is_exact) {
  int closed = _i;
  const size_t N = 7;
  mech_rope sp = mech_rope_unit(N, closed, 1), de = mech_rope_unit(N, closed, 0);
  sdae_mbs sparse, dense;
  size_t nq = 2 * N, nc = mech_rope_constraints(&sp), n = 2 * nq + nc;
  double y[40], yp[40], G[8 * 14], H[8 * 14], e[14], *J = calloc(n * n, sizeof *J);
  double *X = calloc(n * n, sizeof *X), cj = 10.0, outside = -1.0, worst = 0.0;
  ck_assert_ptr_nonnull(J);
  ck_assert_ptr_nonnull(X);
  ck_assert_int_eq(mech_rope_system(&sparse, &sp), 0);
  ck_assert_int_eq(mech_rope_system(&dense, &de), 0);
  ck_assert_int_eq(mech_rope_start(&sp, 0.3, y, y + nq), 0);
  for (size_t i = 0; i < n; i++) {
    if (i >= nq) y[i] = i < 2 * nq ? 0.3 * sin(1.0 + (double)i) : 4.0 + 0.5 * cos((double)i);
    yp[i] = 0.7 * cos(2.0 * (double)i);
  }
  ck_assert_int_eq(idambs_klu_matrix(&sparse, 0.0, y, yp, cj, J, &outside), 0);
  /* the exact matrix X */
  ck_assert_int_eq(dense.jacobian(0.0, y, G, dense.params), 0);
  for (size_t k = 0; k < nq; k++) {
    X[k * n + k] = cj, X[k * n + nq + k] = -1.0;
    X[(nq + k) * n + nq + k] = cj * sp.m;
    memset(e, 0, sizeof e);
    e[k] = 1.0;
    ck_assert_int_eq(dense.jacobian_dot(0.0, y, e, H, dense.params), 0);
    for (size_t c = 0; c < nc; c++)
      for (size_t i = 0; i < nq; i++) X[(nq + i) * n + k] += H[c * nq + i] * y[2 * nq + c];
  }
  for (size_t c = 0; c < nc; c++)
    for (size_t i = 0; i < nq; i++) X[(nq + i) * n + 2 * nq + c] = G[c * nq + i];
  ck_assert_int_eq(dense.jacobian_dot(0.0, y, yp + nq, H, dense.params), 0);
  for (size_t c = 0; c < nc; c++)
    for (size_t k = 0; k < nq; k++) X[(2 * nq + c) * n + k] = H[c * nq + k];
  ck_assert_int_eq(dense.jacobian_dot(0.0, y, y + nq, H, dense.params), 0);
  for (size_t c = 0; c < nc; c++)
    for (size_t k = 0; k < nq; k++)
      X[(2 * nq + c) * n + nq + k] = 2.0 * H[c * nq + k] + cj * G[c * nq + k];
  for (size_t i = 0; i < n; i++) {
    double row = 0.0;
    for (size_t j = 0; j < n; j++) row = fmax(row, fabs(X[i * n + j]));
    for (size_t j = 0; j < n; j++) {
      double d = fabs(J[i * n + j] - X[i * n + j]);
      worst = fmax(worst, d / row);
      ck_assert_msg(d <= 1e-4 * row, "%s rope: entry (%zu, %zu) %.17g, exact %.17g",
                    closed ? "closed" : "open", i, j, J[i * n + j], X[i * n + j]);
    }
  }
  printf("rope N = %zu %s: KLU matrix vs exact, largest difference %.1e of its row; the "
         "structure's check %.1e\n",
         N, closed ? "closed" : "open", worst, outside);
  /* the check's direction d (increments with factors in [0.5, 1)) against the matrix: the rope's
   * v rows are bilinear in (q, lambda), so they differ by the second-order term, the increment
   * (1.5e-8) relative, and by the rounding of their terms, eps |r| over |J d| ~ cj inc: 1e-6
   * is far above both and far below IDAMBS_KLU_OUTSIDE */
  ck_assert_double_le(outside, 1e-6);
  free(J), free(X);
  mech_rope_free(&sp);
  mech_rope_free(&de);
}
END_TEST

/* ---- the KLU path: what it refuses ----------------------------------------------------------- */

/* Two pendula of unit mass and length on pivots (0, 0) and (D, 0), their masses joined by a
 * spring of stiffness K and rest length D: q = (x1, y1, x2, y2), c_i = (|p_i - P_i|^2 - 1) / 2,
 * given by patterns (M diagonal, G's rows {0, 1} and {2, 3}). The spring couples coordinates
 * that share neither M nor a constraint: outside the KLU matrix's structure. */
enum { SPRING_D = 2, SPRING_K = 1000 };
static const size_t spring_m_start[] = {0, 1, 2, 3, 4}, spring_m_col[] = {0, 1, 2, 3};
static const size_t spring_g_start[] = {0, 2, 4}, spring_g_col[] = {0, 1, 2, 3};
static const sdae_pattern spring_m = {4, spring_m_start, spring_m_col};
static const sdae_pattern spring_g = {4, spring_g_start, spring_g_col};

static int spring_mass(double t, const double *q, double *M, void *params) {
  (void)t, (void)q, (void)params;
  M[0] = M[1] = M[2] = M[3] = 1.0;
  return 0;
}

static int spring_force(double t, const double *q, const double *v, double *F, void *params) {
  double fx = SPRING_K * (q[2] - q[0] - SPRING_D), fy = SPRING_K * (q[3] - q[1]);
  (void)t, (void)v, (void)params;
  F[0] = fx, F[1] = fy - 9.81, F[2] = -fx, F[3] = -fy - 9.81;
  return 0;
}

static int spring_constraint(double t, const double *q, double *c, void *params) {
  (void)t, (void)params;
  c[0] = (q[0] * q[0] + q[1] * q[1] - 1.0) / 2.0;
  c[1] = ((q[2] - SPRING_D) * (q[2] - SPRING_D) + q[3] * q[3] - 1.0) / 2.0;
  return 0;
}

static int spring_jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  G[0] = q[0], G[1] = q[1], G[2] = q[2] - SPRING_D, G[3] = q[3];
  return 0;
}

START_TEST(klu_refusals) {
  sdae_mbs spring = {.n_q = 4,
                     .n_c = 2,
                     .mass = spring_mass,
                     .force = spring_force,
                     .constraint = spring_constraint,
                     .jacobian = spring_jacobian,
                     .mass_pattern = &spring_m,
                     .jacobian_pattern = &spring_g};
  const double q0[4] = {sin(0.3), -cos(0.3), SPRING_D, -1.0}, v0[4] = {0};
  const size_t bad_col[] = {0, 4, 2, 3}; /* a column past n_q */
  const sdae_pattern bad = {4, spring_g_start, bad_col};
  idaref_options o = options(1e-6, 1.0, 0.5);
  mech_pendulum p = {.L = 1.0, .m = 1.0, .ga = 9.81};
  last_row r = {.n_q = 4, .n_c = 2};
  idaref_result res;
  sdae_mbs pendulum;
  mech_pendulum_system(&pendulum, &p);
  /* the GGL form, a mechanism without patterns, a pattern that is not one */
  ck_assert_int_eq(
      idambs_solve_with(&spring, IDAMBS_GGL, IDAMBS_KLU, 0.0, q0, v0, &o, keep_last, &r, &res),
      IDAMBS_UNSUPPORTED);
  ck_assert_ptr_nonnull(strstr(res.message, "index1 form only"));
  ck_assert_int_eq(
      idambs_solve_with(&pendulum, IDAMBS_INDEX1, IDAMBS_KLU, 0.0, q0, v0, &o, keep_last, &r, &res),
      IDAMBS_UNSUPPORTED);
  ck_assert_ptr_nonnull(strstr(res.message, "KLU needs mass_pattern and jacobian_pattern"));
  spring.jacobian_pattern = &bad;
  for (int solver = IDAMBS_DENSE; solver <= IDAMBS_KLU; solver++) {
    ck_assert_int_eq(idambs_solve_with(&spring, IDAMBS_INDEX1, (idambs_solver)solver, 0.0, q0, v0,
                                       &o, keep_last, &r, &res),
                     IDAMBS_UNSUPPORTED);
    ck_assert_ptr_nonnull(strstr(res.message, "jacobian_pattern is not a pattern"));
  }
  spring.jacobian_pattern = &spring_g;
  /* the spring, outside the structure: at cj = 10 its entries K dwarf the row's m cj, and the
   * check sees them; in the run KLU fails at its first matrix naming the row (cj = 1/h is a few
   * thousands on the first steps, K / (m cj) still above the check's 1e-2), while the dense
   * solver, whose matrix has every entry, runs */
  {
    double y[10] = {q0[0], q0[1], q0[2], q0[3], 0, 0, 0, 0, 1, 1}, yp[10] = {0}, J[100], outside;
    ck_assert_int_eq(idambs_klu_matrix(&spring, 0.0, y, yp, 10.0, J, &outside), 0);
    ck_assert_double_gt(outside, IDAMBS_KLU_OUTSIDE);
  }
  ck_assert_int_eq(
      idambs_solve_with(&spring, IDAMBS_INDEX1, IDAMBS_KLU, 0.0, q0, v0, &o, keep_last, &r, &res),
      IDAREF_IDA_FAILED);
  printf("spring: KLU refused: %s\n", res.message);
  ck_assert_str_eq(res.flag_name, "IDA_LSETUP_FAIL");
  ck_assert_ptr_nonnull(strstr(res.message, "outside its structure"));
  solve_ok(&spring, IDAMBS_INDEX1, q0, v0, &o, keep_last, &r, &res);
  ck_assert_double_eq(r.t, 1.0);
}
END_TEST

static Suite *ida_mbs_suite(void) {
  Suite *s = suite_create("ida_mbs");
  TCase *exact = tcase_create("exact");
  TCase *driver = tcase_create("driver");
  tcase_set_timeout(exact, 60);
  tcase_add_loop_test(exact, pendulum_matches_elliptic_solution, 0, 2);
  tcase_add_loop_test(exact, lambda_is_the_rod_tension, 0, 2);
  tcase_add_loop_test(exact, double_pendulum_matches_angle_equations, 0, 2);
  tcase_add_loop_test(exact, fourbar_conserves_energy, 0, 2);
  tcase_add_loop_test(exact, fourbar_work_follows_tolerance, 0, 2);
  tcase_add_loop_test(exact, moving_pivot_matches_angle_equation, 0, 4);
  tcase_add_test(exact, slider_crank_stabdae_meets_ida);
  tcase_add_loop_test(exact, rope_klu_meets_dense, 0, 4);
  tcase_add_loop_test(exact, rope_klu_matrix_is_exact, 0, 2);
  tcase_add_test(driver, klu_refusals);
  tcase_add_test(driver, rows_hit_output_times_from_t0);
  tcase_add_test(driver, failures_are_reported);
  suite_add_tcase(s, exact);
  suite_add_tcase(s, driver);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(ida_mbs_suite());
  int failed;
  gsl_set_error_handler_off();      /* GSL statuses are asserted instead of aborting */
  setvbuf(stdout, NULL, _IOLBF, 0); /* the measurements survive a failing (forked) test */
  srunner_run_all(sr, CK_NORMAL);
  failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
