/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Newton on R(mu+) = mu+ - mu - T (phi_T + Q xi): quadratic convergence with the analytic
 * Jacobian, the same root with finite differences, and the singular and capped cases. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "core/arena.h"
#include "core/lu.h"
#include "maps/map.h"
#include "stepper/stepper.h"
#include "testmodels.h"

/* The midpoint map of x'' = -x^3 as a user map that records every mu+ it is called with. */
typedef struct trace {
  quartic q;
  int n;
  double y[64][2];
  int singular; /* the Jacobian callback makes I - T dphi/dmu+ = 0 */
} trace;

static int traced_phi(double t, double T, const double *mu, const double *y, double *out,
                      void *params) {
  trace *tr = params;
  double mid[2] = {0.5 * (mu[0] + y[0]), 0.5 * (mu[1] + y[1])};
  (void)t, (void)T;
  if (tr->n < 64) memcpy(tr->y[tr->n++], y, sizeof tr->y[0]);
  out[0] = mid[1];
  out[1] = -mid[0] * mid[0] * mid[0];
  return 0;
}

static int traced_jac(double t, double T, const double *mu, const double *y, double *out,
                      void *params) {
  trace *tr = params;
  double m0 = 0.5 * (mu[0] + y[0]);
  (void)t;
  if (tr->singular) {
    out[0] = 1.0 / T, out[1] = 0.0, out[2] = 0.0, out[3] = 1.0 / T;
    return 0;
  }
  out[0] = 0.0, out[1] = 0.5, out[2] = -1.5 * m0 * m0, out[3] = 0.0;
  return 0;
}

static int run(trace *tr, int analytic, unsigned max_iter, double T, double *mu, int *status) {
  sdae_model m = quartic_model(&tr->q);
  sdae_options o = quartic_options(sdae_map_user, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.0, 0.0};
  m.params = tr;
  m.user_phi = traced_phi;
  m.user_phi_jac = analytic ? traced_jac : NULL;
  o.newton_max_iter = max_iter;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  *status = sdae_step(s, 0.0, T, xi, mu);
  int iters = (int)sdae_stepper_stats(s)->newton_iters_last;
  sdae_stepper_free(s);
  return iters;
}

/* A large step (T = 0.8 from (1.5, 0.5)) so that the predictor is far from the root: the
 * errors e_k = |y_k - y*| must satisfy e_{k+1} <= C e_k^2. */
START_TEST(quadratic_convergence_analytic) {
  trace tr = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0};
  double mu[2] = {1.5, 0.5};
  int status, iters = run(&tr, 1, 20, 0.8, mu, &status);
  ck_assert_int_eq(status, SDAE_OK);
  ck_assert_int_ge(iters, 3);
  ck_assert_int_le(iters, 8);
  /* tr.y[0] is the predictor's phi(mu, mu); tr.y[1..] the Newton iterates */
  double e[64];
  int n = tr.n - 1;
  for (int k = 0; k < n; k++)
    e[k] = fmax(fabs(tr.y[k + 1][0] - mu[0]), fabs(tr.y[k + 1][1] - mu[1]));
  ck_assert_double_gt(e[0], 1e-2);
  int checked = 0;
  for (int k = 0; k + 1 < n; k++)
    if (e[k] > 1e-7) {
      ck_assert_double_le(e[k + 1], 5.0 * e[k] * e[k]);
      checked++;
    }
  ck_assert_int_ge(checked, 2);
}
END_TEST

/* The same for the midpoint map with q0_jac on x'' = -x^3: the errors of the iterates
 * y_k = 2 m_k - mu, read from the midpoints m_k that q0 is called at, satisfy
 * e_{k+1} <= C e_k^2. C = (T/2) sup|d2 phi/dy2| ||M^-1|| = 0.4 (1.5 |m_1|) ||M^-1||, below 2
 * on this step: 5 leaves room. A chord iteration (M kept from the first iterate) converges
 * only linearly. */
static int traced_q0(double t, const double *mu, double *out, void *params) {
  trace *tr = params;
  (void)t;
  if (tr->n < 64) memcpy(tr->y[tr->n++], mu, sizeof tr->y[0]);
  out[0] = mu[1];
  out[1] = -mu[0] * mu[0] * mu[0];
  return 0;
}

START_TEST(quadratic_convergence_midpoint_q0_jac) {
  trace tr = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0};
  sdae_model m = quartic_model(&tr.q);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.0, 0.0}, mu[2] = {1.5, 0.5}, e[64];
  int checked = 0;
  m.params = &tr, m.q0 = traced_q0; /* q0_jac reads the quartic at the head of the trace */
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.8, xi, mu), SDAE_OK);
  sdae_stepper_free(s);
  /* tr.y[0] is the predictor's midpoint (mu itself); tr.y[1..] those of the Newton iterates */
  for (int k = 1; k < tr.n; k++)
    e[k] = fmax(fabs(2.0 * tr.y[k][0] - 1.5 - mu[0]), fabs(2.0 * tr.y[k][1] - 0.5 - mu[1]));
  ck_assert_double_gt(e[1], 1e-2);
  for (int k = 1; k + 1 < tr.n; k++)
    if (e[k] > 1e-7) {
      ck_assert_double_le(e[k + 1], 5.0 * e[k] * e[k]);
      checked++;
    }
  ck_assert_int_ge(checked, 2);
}
END_TEST

START_TEST(finite_differences_same_root) {
  trace ta = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0}, tf = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0};
  double a[2] = {1.5, 0.5}, f[2] = {1.5, 0.5};
  int sa, sf;
  run(&ta, 1, 20, 0.8, a, &sa);
  run(&tf, 0, 20, 0.8, f, &sf);
  ck_assert_int_eq(sa, SDAE_OK);
  ck_assert_int_eq(sf, SDAE_OK);
  ck_assert_double_le(rel_diff(a[0], f[0]), 1e-14);
  ck_assert_double_le(rel_diff(a[1], f[1]), 1e-14);
}
END_TEST

static int gsl_handler_calls;
static void counting_handler(const char *reason, const char *file, int line, int gsl_errno) {
  (void)reason, (void)file, (void)line, (void)gsl_errno;
  gsl_handler_calls++;
}

/* I - T dphi/dmu+ = 0: a named status, the state untouched, GSL's handler never called. */
START_TEST(singular_matrix_is_reported) {
  trace tr = {{1.0, 0.0, 0, 0}, 0, {{0}}, 1};
  double mu[2] = {1.5, 0.5};
  int status;
  gsl_error_handler_t *old = gsl_set_error_handler(counting_handler);
  run(&tr, 1, 20, 0.8, mu, &status);
  gsl_set_error_handler(old);
  ck_assert_int_eq(status, SDAE_ERR_SINGULAR);
  ck_assert_double_eq(mu[0], 1.5);
  ck_assert_double_eq(mu[1], 0.5);
  ck_assert_int_eq(gsl_handler_calls, 0);
}
END_TEST

/* Quadratic convergence from an O(1) start needs more than two iterations at T = 0.8: the cap
 * of 2 is reached from the predictor, then from the step's start (map_solve.c), each attempt
 * counted to its own cap. */
START_TEST(iteration_cap_is_reported) {
  trace tr = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0};
  double mu[2] = {1.5, 0.5};
  int status, iters = run(&tr, 1, 2, 0.8, mu, &status);
  ck_assert_int_eq(status, SDAE_ERR_NEWTON);
  ck_assert_int_eq(iters, 2 + 2);
  ck_assert_double_eq(mu[0], 1.5);
  ck_assert_double_eq(mu[1], 0.5);
}
END_TEST

/* Statistics: the totals add up and the last residual is at rounding level. */
START_TEST(statistics_add_up) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.1, 0.0}, mu[2] = {1.0, 0.0};
  unsigned long sum = 0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  for (int n = 0; n < 50; n++) {
    ck_assert_int_eq(sdae_step(s, n * 0.05, 0.05, xi, mu), SDAE_OK);
    sum += sdae_stepper_stats(s)->newton_iters_last;
    ck_assert_double_le(sdae_stepper_stats(s)->newton_residual_last, 1e-8);
  }
  ck_assert_uint_eq(sdae_stepper_stats(s)->newton_iters_total, sum);
  ck_assert_uint_eq(sdae_stepper_stats(s)->steps, 50);
  sdae_stepper_reset_stats(s);
  ck_assert_uint_eq(sdae_stepper_stats(s)->steps, 0);
  sdae_stepper_free(s);
}
END_TEST

/* The LU reads only what the packing writes: a caller's block full of stale huge numbers
 * (the bytes 0x7f make doubles near 1.4e306) gives the same steps, bit for bit, as a zeroed
 * one, through Newton's matrix (midpoint map) and Baumgarte's chain (scheme 15). */
static void steps_in_block(unsigned char fill, sdae_stabilizer stabilizer, double *xi, double *mu) {
  static max_align_t mem[256];
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  o.stabilizer = stabilizer;
  memset(mem, fill, sizeof mem);
  ck_assert_int_eq(sdae_stepper_init(&s, mem, sizeof mem, &m, &o), SDAE_OK);
  for (int n = 0; n < 10; n++) ck_assert_int_eq(sdae_step(s, n * 0.1, 0.1, xi, mu), SDAE_OK);
  sdae_stepper_free(s); /* the block the caller's again, to be filled anew */
}

START_TEST(stale_memory_is_never_read) {
  const sdae_stabilizer st[2] = {SDAE_STAB_PAPER, SDAE_STAB_BAUMGARTE};
  for (int i = 0; i < 2; i++) {
    double xi0[2] = {0.1, 0.2}, mu0[2] = {1.0, 0.0}, xi1[2] = {0.1, 0.2}, mu1[2] = {1.0, 0.0};
    steps_in_block(0x00, st[i], xi0, mu0);
    steps_in_block(0x7f, st[i], xi1, mu1);
    ck_assert_int_eq(memcmp(xi0, xi1, sizeof xi0), 0);
    ck_assert_int_eq(memcmp(mu0, mu1, sizeof mu0), 0);
  }
}
END_TEST

/* ---- Newton's cost, fixed by its definition (src/core/newton.c) ----
 * A step of an implicit map costs one evaluation of phi for the predictor mu + T (phi(mu, mu) +
 * Q xi); each Newton iteration one for the residual R(y), plus, when M = I - T dphi/dmu+ is
 * rebuilt, 2 per colour group of columns with finite differences (n groups dense, 2b + 1 for a
 * band b) or none with an analytic Jacobian. An iteration stops at once when R(y) = 0 exactly,
 * else after the update that is below newton_tol (1 + ||y||). */

/* The step count of a stepper over n steps of the rotation fixture (linear in mu, a(t) = 1 + t)
 * from t = 0.3 with xi = 0.3 != 0 (the shift Q xi in Newton's right-hand side). */
static void per_step_cost(const sdae_map_type *map, const sdae_model *m, unsigned iters,
                          unsigned long evals) {
  sdae_options o = quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[1] = {0.3}, mu[2] = {0.6, -0.8};
  ck_assert_int_eq(sdae_stepper_alloc(&s, m, &o), SDAE_OK);
  for (int n = 0; n < 20; n++) {
    unsigned long before = sdae_stepper_stats(s)->phi_evals;
    ck_assert_int_eq(sdae_step(s, 0.3 + 0.1 * n, 0.1, xi, mu), SDAE_OK);
    ck_assert_uint_eq(sdae_stepper_stats(s)->newton_iters_last, iters);
    ck_assert_uint_eq(sdae_stepper_stats(s)->phi_evals - before, evals);
  }
  sdae_stepper_free(s);
}

/* q0 = a(t) J mu is linear in mu, so with the exact Jacobian (q0_jac) the first Newton update
 * lands on the root to rounding and the second, of a few ulps, confirms it: 2 iterations, and
 * 3 evaluations of phi (predictor and two residuals). A Jacobian off by any factor makes
 * Newton linear: more iterations. */
START_TEST(linear_midpoint_one_iteration_plus_confirm) {
  sdae_model m = rotation_model(NULL);
  per_step_cost(sdae_map_midpoint, &m, 2, 3);
}
END_TEST

/* The same for the discrete gradient of H = |mu|^2/2 with hess_H (exact: S depends on t only),
 * with S and with S_apply, and the user map with user_phi_jac. */
START_TEST(linear_dgrad_and_user_one_iteration_plus_confirm) {
  sdae_model m = rotation_model(NULL);
  per_step_cost(sdae_map_dgrad, &m, 2, 3);
  m.S = NULL, m.S_apply = rotation_S_apply;
  per_step_cost(sdae_map_dgrad, &m, 2, 3);
  m = rotation_model(NULL);
  m.user_phi_jac = rotation_user_phi_jac;
  per_step_cost(sdae_map_user, &m, 2, 3);
}
END_TEST

/* dg4 and dg6: explicit to the stepper (no predictor, no Newton of its own: one evaluation of
 * the composed phi), each of the s stages a dgrad solve of 2 iterations and 3 evaluations:
 * iterations 2 s, evaluations 1 + 3 s (s = 3: 6 and 10; s = 9: 18 and 28). */
START_TEST(linear_composed_stages_cost) {
  sdae_model m = rotation_model(NULL);
  per_step_cost(sdae_map_dg4, &m, 6, 10);
  per_step_cost(sdae_map_dg6, &m, 18, 28);
}
END_TEST

/* An explicit map: one evaluation of phi per step and no Newton iteration. */
START_TEST(explicit_map_one_evaluation) {
  sdae_model m = rotation_model(NULL);
  per_step_cost(sdae_map_euler, &m, 0, 1);
}
END_TEST

/* A user map independent of mu+ with dyadic numbers (mu, T, phi, Q xi exact in binary): the
 * predictor is the root exactly, R = 0 at the first iterate, and Newton stops there without a
 * Jacobian: 1 iteration, 2 evaluations (predictor, residual). Computing M anyway would cost
 * 2 n = 4 more by finite differences; a predictor off the root, an iteration and 5 more. */
static int constant_phi(double t, double T, const double *mu, const double *y, double *out,
                        void *params) {
  (void)t, (void)T, (void)mu, (void)y, (void)params;
  out[0] = 0.5, out[1] = -0.25;
  return 0;
}

START_TEST(exact_predictor_stops_at_zero_residual) {
  sdae_model m = rotation_model(NULL);
  sdae_options o = quartic_options(sdae_map_user, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[1] = {0.5}, mu[2] = {1.0, 0.5};
  m.user_phi = constant_phi;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.25, xi, mu), SDAE_OK); /* Q xi = (1 + 0) 0.5 */
  ck_assert_uint_eq(sdae_stepper_stats(s)->newton_iters_last, 1);
  ck_assert_uint_eq(sdae_stepper_stats(s)->phi_evals, 2);
  ck_assert_double_eq(mu[0], 1.0 + 0.25 * (0.5 + 0.5)); /* exact in binary */
  ck_assert_double_eq(mu[1], 0.5 + 0.25 * -0.25);
  sdae_stepper_free(s);
}
END_TEST

/* ---- the finite-difference Jacobian's cost, through sdae__newton_solve itself ---- */

typedef struct fd_case {
  size_t n, band; /* band 0: dense */
} fd_case;

/* phi = (1/2, -1/4, 1/2, ...): independent of y, so its differences are exactly 0 and M = I. */
static int const_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                     double *out) {
  (void)t, (void)T, (void)mu, (void)mu_next;
  for (size_t i = 0; i < c->model->n_mu; i++) out[i] = i % 2 ? -0.25 : 0.5;
  return SDAE_OK;
}

static const sdae_map_type const_map = {
    .name = "const", .order = 1, .implicit = 1, .phi = const_phi};

/* Newton from y = x = (1, 1, ...) with h = 1/4: R(x) = -h phi != 0, so iteration 1 evaluates R
 * (1), builds M by finite differences (2 w, w the colour groups) and lands exactly (dyadic) on
 * y = x + h phi; iteration 2 finds R = 0 exactly and stops (1). Total 2 + 2 w, 2 iterations,
 * with w = n dense and w = 2b + 1 for a band b < n - 1. */
static void fd_cost(fd_case fc, unsigned long groups) {
  sdae_model m = {.n_xi = 1, .n_mu = fc.n};
  sdae_options o;
  sdae_newton nw;
  sdae_arena count = {0}, a = {0};
  sdae_options_default(&o);
  o.bandwidth = fc.band;
  sdae__newton_carve(&nw, fc.n, fc.band ? fc.band : fc.n - 1, o.newton_tol, o.newton_max_iter,
                     &count);
  a.base = calloc(count.used, 1); /* calloc: aligned for any type */
  sdae__newton_carve(&nw, fc.n, fc.band ? fc.band : fc.n - 1, o.newton_tol, o.newton_max_iter, &a);
  nw.iters = 0;
  sdae_map_ctx c = {&m, NULL, &nw, 0, NULL};
  double x[16], y[16];
  for (size_t i = 0; i < fc.n; i++) x[i] = y[i] = 1.0;
  ck_assert_int_eq(sdae__map_solve(&const_map, &c, 0.0, 0.25, x, NULL, y), SDAE_OK);
  ck_assert_uint_eq(c.phi_evals, 2 + 2 * groups);
  ck_assert_uint_eq(nw.iters, 2);
  for (size_t i = 0; i < fc.n; i++) ck_assert_double_eq(y[i], 1.0 + 0.25 * (i % 2 ? -0.25 : 0.5));
  free(a.base);
}

START_TEST(fd_jacobian_costs_2n_dense) {
  fd_cost((fd_case){2, 0}, 2); /* the small dense LU */
  fd_cost((fd_case){4, 0}, 4);
  fd_cost((fd_case){6, 0}, 6); /* GSL's LU on the full band */
}
END_TEST

START_TEST(fd_jacobian_costs_2_times_2b_plus_1_banded) {
  fd_cost((fd_case){12, 1}, 3);
  fd_cost((fd_case){12, 2}, 5);
  fd_cost((fd_case){16, 4}, 9);
}
END_TEST

/* ---- Newton's definition at its boundaries, through sdae__newton_solve itself ----
 * A map of the test's own (the table of src/maps/map.h) and a workspace for n unknowns. */

static sdae_model ws_model;

/* a Newton workspace for n unknowns (band 0: dense) with tolerance tol; returns its block */
static void *newton_ws(sdae_newton *nw, size_t n, size_t band, double tol) {
  sdae_options o;
  sdae_arena count = {0}, a = {0};
  ws_model = (sdae_model){.n_xi = 1, .n_mu = n};
  sdae_options_default(&o);
  o.bandwidth = band, o.newton_tol = tol;
  sdae__newton_carve(nw, n, band ? band : n - 1, o.newton_tol, o.newton_max_iter, &count);
  a.base = calloc(count.used, 1);
  sdae__newton_carve(nw, n, band ? band : n - 1, o.newton_tol, o.newton_max_iter, &a);
  nw->iters = 0;
  return a.base;
}

/* Newton on y = x + h phi(x, y) from y; the status, with the iterations and evaluations */
static int solve_with(const sdae_map_type *map, size_t n, size_t band, double tol, double h,
                      const double *x, double *y, unsigned *iters, unsigned long *evals) {
  sdae_newton nw;
  void *mem = newton_ws(&nw, n, band, tol);
  sdae_map_ctx c = {&ws_model, NULL, &nw, 0, NULL};
  int rc = sdae__map_solve(map, &c, 0.0, h, x, NULL, y);
  *iters = nw.iters;
  *evals = c.phi_evals;
  free(mem);
  return rc;
}

/* phi = the constant vector phi_value (independent of y: its differences are exactly 0, M = I) */
static double phi_value[8];
static int value_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                     double *out) {
  (void)t, (void)T, (void)mu, (void)mu_next;
  for (size_t i = 0; i < c->model->n_mu; i++) out[i] = phi_value[i];
  return SDAE_OK;
}
static const sdae_map_type value_map = {.name = "value", .implicit = 1, .phi = value_phi};

/* a Jacobian that overflows: the Newton matrix I - h J is not finite */
static int inf_jac(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                   double *out) {
  size_t n = c->model->n_mu;
  (void)t, (void)T, (void)mu, (void)mu_next;
  for (size_t i = 0; i < n * n; i++) out[i] = i == 0 ? INFINITY : 0.0;
  return SDAE_OK;
}
static const sdae_map_type inf_jac_map = {
    .name = "infjac", .implicit = 1, .phi = value_phi, .jac = inf_jac};

/* An analytic Jacobian holding Inf: SDAE_ERR_NONFINITE (not a singular verdict on Inf), for the
 * small dense LU (n = 2) and GSL's (n = 6). R(x) = -h phi != 0, so M is built at once. */
START_TEST(infinite_jacobian_is_nonfinite) {
  const size_t ns[2] = {2, 6};
  for (int k = 0; k < 2; k++) {
    double x[6], y[6];
    unsigned iters;
    unsigned long evals;
    for (size_t i = 0; i < 6; i++) x[i] = y[i] = 1.0, phi_value[i] = 0.5;
    ck_assert_int_eq(solve_with(&inf_jac_map, ns[k], 0, 1e-14, 0.25, x, y, &iters, &evals),
                     SDAE_ERR_NONFINITE);
    ck_assert_uint_eq(iters, 1);
  }
}
END_TEST

/* phi_i = +1e308 where y_i >= x_i, -1e308 below: finite everywhere, but the central difference
 * of column i, (1e308 - (-1e308)) / (2 h_i), overflows (2e308 > DBL_MAX = 1.8e308) */
static int cliff_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                     double *out) {
  (void)t, (void)T;
  for (size_t i = 0; i < c->model->n_mu; i++) out[i] = mu_next[i] >= mu[i] ? 1e308 : -1e308;
  return SDAE_OK;
}
static const sdae_map_type cliff_map = {.name = "cliff", .implicit = 1, .phi = cliff_phi};

/* A finite-difference matrix that overflows: SDAE_ERR_NONFINITE, dense (small: n = 2, GSL's:
 * n = 6) and banded (n = 6, b = 1, built in the band storage). The residual at y = x is
 * -h 1e308, finite. */
START_TEST(overflowing_differences_are_nonfinite) {
  const fd_case cs[3] = {{2, 0}, {6, 0}, {6, 1}};
  for (int k = 0; k < 3; k++) {
    double x[6], y[6];
    unsigned iters;
    unsigned long evals;
    for (size_t i = 0; i < 6; i++) x[i] = y[i] = 1.0;
    ck_assert_int_eq(solve_with(&cliff_map, cs[k].n, cs[k].band, 1e-14, 0.25, x, y, &iters, &evals),
                     SDAE_ERR_NONFINITE);
    ck_assert_uint_eq(iters, 1);
  }
}
END_TEST

/* An iterate that overflows: phi = 1.6e308 constant, h = 1, from y = x = 1e308. M = I, so the
 * first update lands on x + h phi = 2.6e308 > DBL_MAX: the root is not representable, and the
 * iterate is refused at once (1 iteration), not taken as converged. */
START_TEST(overflowing_iterate_is_nonfinite) {
  double x[2] = {1e308, 1e308}, y[2] = {1e308, 1e308};
  unsigned iters;
  unsigned long evals;
  phi_value[0] = phi_value[1] = 1.6e308;
  ck_assert_int_eq(solve_with(&value_map, 2, 0, 1e-14, 1.0, x, y, &iters, &evals),
                   SDAE_ERR_NONFINITE);
  ck_assert_uint_eq(iters, 1);
}
END_TEST

/* The stopping test dy <= tol (1 + ||y||) at its boundary, in exact binary arithmetic:
 * phi = (2, -2), h = 1/4, x = (1/2, 1/2): the root is y* = (1, 0), ||y*|| = 1. From
 * y0 = (1 + 2^-20, 0) the first update (M = I exactly) is dy = (2^-20, 0) and lands on y*.
 * With tol = 2^-21, tol (1 + ||y*||) = 2^-20 = dy: done after 1 iteration (1 residual + 2 n = 4
 * evaluations for M). With tol one ulp below, not done: iteration 2 finds R(y*) = 0 exactly and
 * stops (1 more evaluation). */
START_TEST(stopping_test_boundary) {
  const double tols[2] = {0x1p-21, nextafter(0x1p-21, 0.0)};
  const unsigned want_iters[2] = {1, 2};
  const unsigned long want_evals[2] = {5, 6};
  for (int k = 0; k < 2; k++) {
    double x[2] = {0.5, 0.5}, y[2] = {1.0 + 0x1p-20, 0.0};
    unsigned iters;
    unsigned long evals;
    phi_value[0] = 2.0, phi_value[1] = -2.0;
    ck_assert_int_eq(solve_with(&value_map, 2, 0, tols[k], 0.25, x, y, &iters, &evals), SDAE_OK);
    ck_assert_uint_eq(iters, want_iters[k]);
    ck_assert_uint_eq(evals, want_evals[k]);
    ck_assert_double_eq(y[0], 1.0); /* the root, exactly */
    ck_assert_double_eq(y[1], 0.0);
  }
}
END_TEST

/* phi = (0, p(y_1)), p = 2^-30 below 1 and 0 above: piecewise constant, so every central
 * difference here is exactly 0 and M = I (Newton is then y+ = x + h phi(y)). */
static int step_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                    double *out) {
  (void)c, (void)t, (void)T, (void)mu;
  out[0] = 0.0;
  out[1] = mu_next[1] < 1.0 ? 0x1p-30 : 0.0;
  return SDAE_OK;
}
static const sdae_map_type step_map = {.name = "step", .implicit = 1, .phi = step_phi};

/* M's reuse at its boundary: kept after an update dy <= 1e-5 (1 + ||y||), rebuilt above. With
 * x = (X, 0), X = 2^20, h = 1, from y0 = (X, a): update 1 is (0, a) (p(a) = 0 for a >= 1), to
 * y1 = (X, 0), where ||y1|| = X; update 2 is (0, -2^-30) to the root (X, 2^-30), below the
 * tolerance 1e-14 (1 + X) = 1.05e-8: 2 iterations. With a = 1e-5 (1 + X) exactly, M is kept
 * for iteration 2: 1 + 4 + 1 = 6 evaluations; with a one ulp above, rebuilt: 10. */
START_TEST(matrix_reuse_boundary) {
  const double X = 0x1p20, a = 1e-5 * (1.0 + X);
  const double as[2] = {a, nextafter(a, INFINITY)};
  const unsigned long want_evals[2] = {6, 10};
  for (int k = 0; k < 2; k++) {
    double x[2] = {X, 0.0}, y[2] = {X, as[k]};
    unsigned iters;
    unsigned long evals;
    ck_assert_int_eq(solve_with(&step_map, 2, 0, 1e-14, 1.0, x, y, &iters, &evals), SDAE_OK);
    ck_assert_uint_eq(iters, 2);
    ck_assert_uint_eq(evals, want_evals[k]);
    ck_assert_double_eq(y[0], X);
    ck_assert_double_eq(y[1], 0x1p-30);
  }
}
END_TEST

/* phi = -4 y with h = 1/4: R(y) = y - x - h phi = 2 y - x is linear, so the central difference
 * (R(y + h_j e_j) - R(y - h_j e_j)) / (2 h_j) has no truncation error, and at y_j = 1 (a power
 * of 2) and y_j = 0 with the step h_j = eps^(1/3) max(1, |y_j|) made exact, no rounding either:
 * with x = (1, 0), y_j +- h_j - x_j is exact (Sterbenz, or x_j = 0), and so is every R, so
 * dR/dy = 2 I exactly. From y0 = (1, 0): R = (1, 0), the update (1/2, 0) lands on the root
 * (1/2, 0) exactly and iteration 2 finds R = 0: 2 iterations, 1 + 2 n + 1 = 6 evaluations. (A
 * step that is not symmetric about y_j, or is zero at y_j = 0, gives another count or no
 * matrix.) */
static int linear_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                      double *out) {
  (void)t, (void)T, (void)mu;
  for (size_t i = 0; i < c->model->n_mu; i++) out[i] = -4.0 * mu_next[i];
  return SDAE_OK;
}
static const sdae_map_type linear_map = {.name = "linear", .implicit = 1, .phi = linear_phi};

START_TEST(fd_jacobian_exact_on_linear_map) {
  double x[2] = {1.0, 0.0}, y[2] = {1.0, 0.0};
  unsigned iters;
  unsigned long evals;
  ck_assert_int_eq(solve_with(&linear_map, 2, 0, 1e-14, 0.25, x, y, &iters, &evals), SDAE_OK);
  ck_assert_uint_eq(iters, 2);
  ck_assert_uint_eq(evals, 6);
  ck_assert_double_eq(y[0], 0.5); /* y = x / (1 + h 4) */
  ck_assert_double_eq(y[1], 0.0);
}
END_TEST

/* phi = A y with its exact Jacobian A (n = 4), recording every y phi is called at */
static const double A4[16] = {0.3,  -0.7, 0.1, 0.9,  1.1, 0.2,  -0.6, 0.4,
                              -0.8, 0.5,  0.7, -0.3, 0.6, -0.9, 0.35, 0.15};
static double seen4[8][4];
static int nseen4;
static int a4_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                  double *out) {
  (void)c, (void)t, (void)T, (void)mu;
  if (nseen4 < 8) memcpy(seen4[nseen4++], mu_next, sizeof seen4[0]);
  for (int i = 0; i < 4; i++) {
    double acc = 0.0;
    for (int j = 0; j < 4; j++) acc += A4[i * 4 + j] * mu_next[j];
    out[i] = acc;
  }
  return SDAE_OK;
}
static int a4_jac(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                  double *out) {
  (void)c, (void)t, (void)T, (void)mu, (void)mu_next;
  memcpy(out, A4, sizeof A4);
  return SDAE_OK;
}
static const sdae_map_type a4_map = {.name = "a4", .implicit = 1, .phi = a4_phi, .jac = a4_jac};

/* n = 4 = SDAE_SMALL_DENSE is a small system: Newton's first iterate from y0 = 0 is
 * y1 = 0 - M^-1 R(0), R(0) = -x (phi(0) = A 0 = 0), M = I - h A, and M^-1 R is the small LU's
 * solve, bit for bit; GSL's LU, which divides where the small one multiplies by reciprocals,
 * gives other last bits on this matrix (checked here too, so the comparison can tell the two
 * apart). */
START_TEST(four_unknowns_take_the_small_lu) {
  const double x[4] = {0.1, 0.2, 0.3, 0.4}, y0[4] = {0.0, 0.0, 0.0, 0.0}, h = 0.5;
  double y[4], M[16], AB[4 * 13], R[4], phi[4], dy_small[4], dy_gsl[4], want[4];
  unsigned piv[4], iters;
  unsigned long evals;
  memcpy(y, y0, sizeof y);
  nseen4 = 0;
  ck_assert_int_eq(solve_with(&a4_map, 4, 0, 1e-14, h, x, y, &iters, &evals), SDAE_OK);
  ck_assert_int_ge(nseen4, 2);
  sdae_map_ctx c = {&ws_model, NULL, NULL, 0, NULL};
  a4_phi(&c, 0.0, h, x, y0, phi);
  for (int i = 0; i < 4; i++) {
    R[i] = y0[i] - x[i] - h * phi[i];
    for (int j = 0; j < 4; j++) M[i * 4 + j] = (i == j ? 1.0 : 0.0) - h * A4[i * 4 + j];
  }
  sdae__lu_pack(M, 4, 3, 3, AB);
  ck_assert_int_eq(sdae__lu_solve(AB, piv, 4, 3, 3, R, dy_gsl), SDAE_OK);
  ck_assert_int_eq(sdae__lu_small_factor(M, piv, 4), SDAE_OK);
  sdae__lu_small_solve(M, piv, 4, R, dy_small);
  ck_assert_int_ne(memcmp(dy_small, dy_gsl, sizeof dy_gsl), 0);
  for (int i = 0; i < 4; i++) want[i] = y0[i] - dy_small[i];
  ck_assert_int_eq(memcmp(seen4[1], want, sizeof want), 0);
}
END_TEST

/* ---- the banded Newton's storage ----
 * A chain of n_mu = 6, q0 = K mu with K tridiagonal and skew (K_{i,i+1} = 1, K_{i+1,i} = -1),
 * the midpoint map with bandwidth 1: Newton builds M by finite differences directly in GSL's
 * band storage, which holds cells outside the matrix (above row 0, below row n - 1). */
enum { CHAIN = 6 };
static int chain_q0(double t, const double *mu, double *out, void *p) {
  (void)t, (void)p;
  for (int i = 0; i < CHAIN; i++)
    out[i] = 3.0 * ((i + 1 < CHAIN ? mu[i + 1] : 0.0) - (i > 0 ? mu[i - 1] : 0.0));
  return 0;
}
static int chain_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                         void *p) {
  (void)t, (void)mu, (void)p;
  for (int i = 0; i < CHAIN; i++) Qxi[i] = i == 0 ? xi[0] : 0.0;
  qnorm2[0] = 1.0;
  return 0;
}

static void chain_steps_in_block(unsigned char fill, double *xi, double *mu) {
  static max_align_t mem[512];
  sdae_model m = {.n_xi = 1, .n_mu = CHAIN, .q0 = chain_q0, .Q_apply = chain_Q_apply};
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  o.bandwidth = 1;
  memset(mem, fill, sizeof mem);
  ck_assert_int_eq(sdae_stepper_init(&s, mem, sizeof mem, &m, &o), SDAE_OK);
  for (int n = 0; n < 10; n++) ck_assert_int_eq(sdae_step(s, n * 0.5, 0.5, xi, mu), SDAE_OK);
  sdae_stepper_free(s); /* the block the caller's again, to be filled anew */
}

/* The band's cells outside the matrix and its fill-in are cleared before each matrix is
 * built: a caller's block full of stale huge numbers (0x7f bytes: doubles near 1.4e306, which
 * as the band's scale would make every pivot singular) steps exactly as a zeroed one. The
 * midpoint map conserves |mu| on this skew linear system (its Cayley transform is orthogonal):
 * to rounding, so the steps did move mu along the sphere. */
START_TEST(banded_storage_cleared_before_use) {
  double xi0[1] = {0.2}, mu0[CHAIN] = {0.6, -0.8, 0.3, 0.1, -0.2, 0.5};
  double xi1[1] = {0.2}, mu1[CHAIN] = {0.6, -0.8, 0.3, 0.1, -0.2, 0.5};
  double n0 = 0.0, n1 = 0.0;
  for (int i = 0; i < CHAIN; i++) n0 += mu0[i] * mu0[i];
  xi0[0] = xi1[0] = 0.0; /* on the manifold: mu alone moves */
  chain_steps_in_block(0x00, xi0, mu0);
  chain_steps_in_block(0x7f, xi1, mu1);
  ck_assert_int_eq(memcmp(mu0, mu1, sizeof mu0), 0);
  for (int i = 0; i < CHAIN; i++) n1 += mu0[i] * mu0[i];
  ck_assert_double_le(fabs(n1 - n0), 1e-14);
}
END_TEST

/* ---- the core's own interface: a residual, an optional Jacobian, a context, no map ----
 * R(y) = (y0^2 + y1^2 - 4, y0 - y1): the root (sqrt 2, sqrt 2). From (2, 1) Newton converges
 * quadratically, so within 8 iterations both with the Jacobian and with differences, to
 * rounding of the root. */
static int circle_residual(void *ctx, const double *y, double *R) {
  ++*(int *)ctx;
  R[0] = y[0] * y[0] + y[1] * y[1] - 4.0;
  R[1] = y[0] - y[1];
  return SDAE_OK;
}
static int circle_jacobian(void *ctx, const double *y, double *J) {
  (void)ctx;
  /* dR/dy = (2 y0, 2 y1; 1, -1) = I - J: the hook's J, with the coefficient 1 of the solve */
  J[0] = 1.0 - 2.0 * y[0], J[1] = -2.0 * y[1], J[2] = -1.0, J[3] = 2.0;
  return SDAE_OK;
}

/* a residual that is NaN: not converged but SDAE_ERR_NONFINITE, y untouched */
static int nan_residual(void *ctx, const double *y, double *R) {
  (void)ctx, (void)y;
  R[0] = R[1] = NAN;
  return SDAE_OK;
}

START_TEST(nan_residual_is_nonfinite) {
  sdae_newton nw;
  sdae_arena count = {0}, a = {0};
  sdae_newton_system sys = {.residual = nan_residual};
  double y[2] = {2.0, 1.0};
  sdae__newton_carve(&nw, 2, 1, 1e-14, 8, &count);
  a.base = calloc(count.used, 1);
  sdae__newton_carve(&nw, 2, 1, 1e-14, 8, &a);
  ck_assert_int_eq(sdae__newton_solve(&nw, &sys, 1.0, y), SDAE_ERR_NONFINITE);
  ck_assert_double_eq(y[0], 2.0);
  ck_assert_double_eq(y[1], 1.0);
  free(a.base);
}
END_TEST

START_TEST(plain_residual_system) {
  for (int with_jac = 0; with_jac < 2; with_jac++) {
    sdae_newton nw;
    sdae_arena count = {0}, a = {0};
    int calls = 0;
    sdae_newton_system sys = {
        .residual = circle_residual, .jacobian = with_jac ? circle_jacobian : NULL, .ctx = &calls};
    double y[2] = {2.0, 1.0};
    sdae__newton_carve(&nw, 2, 1, 1e-14, 8, &count);
    a.base = calloc(count.used, 1);
    sdae__newton_carve(&nw, 2, 1, 1e-14, 8, &a);
    nw.iters = 0;
    ck_assert_int_eq(sdae__newton_solve(&nw, &sys, 1.0, y), SDAE_OK);
    ck_assert_double_eq_tol(y[0], sqrt(2.0), 4e-16);
    ck_assert_double_eq_tol(y[1], sqrt(2.0), 4e-16);
    ck_assert_uint_le(nw.iters, 8);
    /* differences: two residuals a column on top of one an iteration */
    if (!with_jac) ck_assert_int_gt(calls, (int)nw.iters);
    free(a.base);
  }
}
END_TEST

/* ---- the matrix kept across solves (CVODE's rules) ---- */

/* phi = -y^3 componentwise: y + h y^3 = x, a matrix I + 3 h diag(y^2) that changes with y */
static int cube_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                    double *out) {
  (void)t, (void)T, (void)mu;
  for (size_t i = 0; i < c->model->n_mu; i++) out[i] = -mu_next[i] * mu_next[i] * mu_next[i];
  return SDAE_OK;
}
static const sdae_map_type cube_map = {.name = "cube", .implicit = 1, .phi = cube_phi};

/* one solve of y + h y^3 = (x0, x0 / 2) from the last root (a stepper's predictor is as
 * near) with the kept matrix allowed: converged to rounding; the number of evaluations of phi
 * beyond one per iteration (2 n = 4 for a matrix by differences, 0 for the kept one) */
static double cube_y[2] = {1.0, 0.5};
static unsigned long cube_solve(sdae_newton *nw, double h, double x0) {
  sdae_map_ctx c = {&ws_model, NULL, nw, 0, NULL};
  double x[2] = {x0, 0.5 * x0}, *y = cube_y;
  unsigned iters = nw->iters;
  ck_assert_int_eq(sdae__map_solve(&cube_map, &c, 0.0, h, x, NULL, y), SDAE_OK);
  for (int i = 0; i < 2; i++)
    ck_assert_double_le(fabs(y[i] + h * y[i] * y[i] * y[i] - x[i]), 4.0 * DBL_EPSILON);
  return c.phi_evals - (nw->iters - iters);
}

/* the matrices one solve builds */
static unsigned long builds(sdae_newton *nw, double h, double x0, unsigned long *extra) {
  unsigned long before = nw->refreshes;
  *extra = cube_solve(nw, h, x0);
  return nw->refreshes - before;
}

/* Built by differences at the first solve (at each iterate that moves far, as Newton), then
 * kept for 20 solves, each a chord without differences; the 21st after it rebuilds. A
 * coefficient 25 % off keeps it, 50 % off rebuilds; so do a forget and a far jump (the chord's
 * rate slow: rebuilt at the iterate, within the same solve). Not asked for (keep = 0), it is
 * rebuilt at every solve, none counted as kept. */
START_TEST(kept_matrix_rules) {
  sdae_newton nw;
  void *mem = newton_ws(&nw, 2, 0, 1e-14);
  double x0 = 1.0;
  unsigned long extra;
  nw.keep = 1;
  ck_assert_uint_ge(builds(&nw, 0.25, x0, &extra), 1);
  ck_assert_uint_ge(extra, 4);
  for (int k = 0; k < 20; k++) {
    ck_assert_uint_eq(builds(&nw, 0.25, x0 += 1e-3, &extra), 0);
    ck_assert_uint_eq(extra, 0);
  }
  ck_assert_uint_ge(builds(&nw, 0.25, x0 += 1e-3, &extra), 1); /* 20 solves old */
  ck_assert_uint_ge(extra, 4);
  ck_assert_uint_eq(builds(&nw, 0.3125, x0 += 1e-3, &extra), 0); /* 25 % */
  ck_assert_uint_ge(builds(&nw, 0.375, x0 += 1e-3, &extra), 1);  /* 50 % */
  sdae__newton_forget(&nw);
  ck_assert_uint_ge(builds(&nw, 0.375, x0 += 1e-3, &extra), 1);
  ck_assert_uint_ge(builds(&nw, 0.375, x0 + 2.0, &extra), 1); /* y^2 from 0.67 to 2.5 */
  nw.keep = 0;
  ck_assert_uint_eq(builds(&nw, 0.375, x0, &extra), 0);
  ck_assert_uint_ge(extra, 4);
  ck_assert_uint_eq(nw.retries, 0); /* no kept matrix failed here */
  free(mem);
}
END_TEST

/* ---- CVODE's recovery (core/newton.h): a kept matrix that fails, the same solve retried ---- */

/* R(y) = y^p - a (p = 2 or 3) through the four hooks, the matrix p y^(p-1) at the setup's y:
 * each iterate evaluated and each setup's point recorded */
typedef struct power_sys {
  int p;
  double a, J;
  unsigned n_res, n_setup;
  double res_y[64], setup_y[64];
} power_sys;

static int power_residual(void *ctx, const double *y, double *R) {
  power_sys *s = ctx;
  if (s->n_res < 64) s->res_y[s->n_res] = y[0];
  s->n_res++;
  R[0] = (s->p == 2 ? y[0] * y[0] : y[0] * y[0] * y[0]) - s->a;
  return SDAE_OK;
}
static int power_setup(void *ctx, const double *y) {
  power_sys *s = ctx;
  if (s->n_setup < 64) s->setup_y[s->n_setup] = y[0];
  s->n_setup++;
  s->J = s->p == 2 ? 2.0 * y[0] : 3.0 * y[0] * y[0];
  return s->J == 0.0 ? SDAE_ERR_SINGULAR : SDAE_OK;
}
static int power_solve(void *ctx, const double *R, double *dy) {
  const power_sys *s = ctx;
  dy[0] = R[0] / s->J;
  return SDAE_OK;
}

/* a setup was made at y */
static int set_up_at(const power_sys *s, double y) {
  for (unsigned k = 0; k < s->n_setup && k < 64; k++)
    if (s->setup_y[k] == y) return 1;
  return 0;
}

/* a Newton that keeps its matrix, capped at 6 iterations an attempt */
enum { POWER_CAP = 6 };
static void *power_newton(sdae_newton *nw) {
  sdae_arena count = {0}, a = {0};
  sdae__newton_carve_hooks(nw, 1, 1e-14, POWER_CAP, &count);
  a.base = calloc(count.used, 1);
  sdae__newton_carve_hooks(nw, 1, 1e-14, POWER_CAP, &a);
  nw->keep = 1;
  return a.base;
}

static int power_solve_from(sdae_newton *nw, power_sys *s, double a, double *y) {
  const sdae_newton_system sys = {
      .residual = power_residual, .setup = power_setup, .solve = power_solve, .ctx = s};
  s->a = a, s->n_res = s->n_setup = 0;
  nw->iters = 0;
  return sdae__newton_solve(nw, &sys, 1.0, y);
}

/* y^3 = 1 is solved (the matrix 3 y^2 kept, built near y = 1), then y^3 = 1331 from y = 10:
 * the kept matrix (slope 3 where the root's is 363) sends the chord to 120, and the next update
 * is larger still: the chord does not contract, the kept matrix is given up after its second
 * update and the same solve starts again from y = 10 with a matrix built there, Newton's
 * quadratic convergence reaching y = 11 to rounding within its own cap: the two attempts
 * together take more iterations than one cap allows. */
START_TEST(stale_matrix_refreshed_and_retried) {
  sdae_newton nw;
  void *mem = power_newton(&nw);
  power_sys s = {.p = 3};
  double y = 1.1;
  ck_assert_int_eq(power_solve_from(&nw, &s, 1.0, &y), SDAE_OK);
  ck_assert_double_le(fabs(y - 1.0), 2.0 * DBL_EPSILON);
  ck_assert_int_eq(nw.kept, 1);
  ck_assert_uint_eq(nw.retries, 0);
  y = 10.0;
  ck_assert_int_eq(power_solve_from(&nw, &s, 1331.0, &y), SDAE_OK);
  ck_assert_double_le(fabs(y - 11.0), 4.0 * 11.0 * DBL_EPSILON);
  ck_assert_uint_eq(nw.retries, 1);
  ck_assert_uint_eq(s.n_res, nw.iters); /* one residual an iteration with a matrix of its own */
  ck_assert_double_eq(s.res_y[0], 10.0);
  ck_assert_double_gt(s.res_y[1], 100.0); /* the kept matrix's chord: 10 + 331 / 3 */
  ck_assert_uint_ge(s.n_setup, 1);
  ck_assert_double_eq(s.setup_y[0], 10.0); /* the retry's matrix: at the solve's start */
  ck_assert_double_eq(s.res_y[2], 10.0);   /* and its first iterate */
  ck_assert_uint_gt(nw.iters, POWER_CAP);  /* the cap counted anew */
  ck_assert_uint_le(nw.iters, 2 + POWER_CAP);
  ck_assert_int_eq(nw.kept, 1); /* the fresh matrix is kept for the next solve */
  free(mem);
}
END_TEST

/* y^2 = -1 has no root: from y = 0.7 with no matrix kept, Newton's own (fresh) attempt fails at
 * its cap, SDAE_ERR_NEWTON, nothing retried; after y^2 = 4 is solved (its matrix kept), the
 * same failure is first the kept matrix's, then the fresh retry's from the same start: both
 * attempts counted, and the failed solve keeps nothing: the next solve, y^2 = 4 again, builds
 * its matrix at its own start. */
START_TEST(fresh_failure_is_reported_and_nothing_kept) {
  sdae_newton nw;
  void *mem = power_newton(&nw);
  power_sys s = {.p = 2};
  double y = 0.7;
  ck_assert_int_eq(power_solve_from(&nw, &s, -1.0, &y), SDAE_ERR_NEWTON);
  ck_assert_uint_eq(nw.retries, 0);
  ck_assert_uint_eq(nw.iters, POWER_CAP);
  ck_assert_double_eq(s.setup_y[0], 0.7);
  ck_assert_int_eq(nw.kept, 0);
  y = 2.1;
  ck_assert_int_eq(power_solve_from(&nw, &s, 4.0, &y), SDAE_OK);
  ck_assert_double_le(fabs(y - 2.0), 4.0 * DBL_EPSILON);
  ck_assert_int_eq(nw.kept, 1);
  y = 0.7;
  ck_assert_int_eq(power_solve_from(&nw, &s, -1.0, &y), SDAE_ERR_NEWTON);
  ck_assert_uint_eq(nw.retries, 1);
  ck_assert_uint_gt(nw.iters, POWER_CAP); /* the kept attempt, then a whole fresh one */
  ck_assert_uint_le(nw.iters, 2 * POWER_CAP);
  ck_assert(set_up_at(&s, 0.7)); /* the retry from the same start */
  ck_assert_double_eq(s.res_y[nw.iters - POWER_CAP], 0.7);
  ck_assert_int_eq(nw.kept, 0);
  y = 2.1;
  ck_assert_int_eq(power_solve_from(&nw, &s, 4.0, &y), SDAE_OK);
  ck_assert_uint_ge(s.n_setup, 1);
  ck_assert_double_eq(s.setup_y[0], 2.1); /* nothing of the failed solve kept */
  ck_assert_uint_eq(nw.retries, 1);
  free(mem);
}
END_TEST

int main(void) {
  Suite *s = suite_create("newton");
  ADD_CASE(s, plain_residual_system);
  ADD_CASE(s, nan_residual_is_nonfinite);
  ADD_CASE(s, kept_matrix_rules);
  ADD_CASE(s, stale_matrix_refreshed_and_retried);
  ADD_CASE(s, fresh_failure_is_reported_and_nothing_kept);
  ADD_CASE(s, quadratic_convergence_analytic);
  ADD_CASE(s, quadratic_convergence_midpoint_q0_jac);
  ADD_CASE(s, finite_differences_same_root);
  ADD_CASE(s, singular_matrix_is_reported);
  ADD_CASE(s, iteration_cap_is_reported);
  ADD_CASE(s, statistics_add_up);
  ADD_CASE(s, stale_memory_is_never_read);
  ADD_CASE(s, linear_midpoint_one_iteration_plus_confirm);
  ADD_CASE(s, linear_dgrad_and_user_one_iteration_plus_confirm);
  ADD_CASE(s, linear_composed_stages_cost);
  ADD_CASE(s, explicit_map_one_evaluation);
  ADD_CASE(s, exact_predictor_stops_at_zero_residual);
  ADD_CASE(s, fd_jacobian_costs_2n_dense);
  ADD_CASE(s, fd_jacobian_costs_2_times_2b_plus_1_banded);
  ADD_CASE(s, infinite_jacobian_is_nonfinite);
  ADD_CASE(s, overflowing_differences_are_nonfinite);
  ADD_CASE(s, overflowing_iterate_is_nonfinite);
  ADD_CASE(s, stopping_test_boundary);
  ADD_CASE(s, matrix_reuse_boundary);
  ADD_CASE(s, fd_jacobian_exact_on_linear_map);
  ADD_CASE(s, four_unknowns_take_the_small_lu);
  ADD_CASE(s, banded_storage_cleared_before_use);
  return run_suite(s);
}
