/* SPDX-License-Identifier: GPL-3.0-or-later */
/* GMRES (core/gmres.c) and Newton-Krylov (core/newton.c with sdae__newton_carve_krylov): GMRES
 * is exact in n steps on n unknowns and in one with the exact inverse as its preconditioner,
 * its rotated residual is the true residual, it stops short at m steps and says so; Newton with
 * GMRES as its linear solve converges where the chord on the same preconditioner cannot; and a
 * model's own linear solve serves the stepper's implicit maps. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_linalg.h>

#include "core/arena.h"
#include "core/gmres.h"
#include "core/newton.h"
#include "testmodels.h"

enum { N = 8 };

/* a nonsymmetric matrix with the eigenvalues of its diagonal spread over [1, 8] */
typedef struct linear {
  double A[N * N];
  double LU[N * N]; /* A's factors (GSL's), the exact preconditioner */
  size_t perm[N];
  int exact;   /* precondition by A^-1 (else by I) */
  int fail_at; /* apply fails at this call (0: never) */
  int calls;
} linear;

static linear linear_scaled(double scale) {
  linear L;
  memset(&L, 0, sizeof L);
  for (size_t i = 0; i < N; i++)
    for (size_t j = 0; j < N; j++)
      L.A[i * N + j] =
          scale * (i == j ? 1.0 + (double)i : 0.3 * sin(1.0 + (double)(3 * i + 7 * j)));
  memcpy(L.LU, L.A, sizeof L.A);
  gsl_matrix_view lu = gsl_matrix_view_array(L.LU, N, N);
  gsl_permutation p = {N, L.perm};
  int sign;
  ck_assert_int_eq(gsl_linalg_LU_decomp(&lu.matrix, &p, &sign), GSL_SUCCESS);
  return L;
}

static linear linear_case(void) { return linear_scaled(1.0); }

static void times(const double *A, const double *x, double *out) {
  for (size_t i = 0; i < N; i++) {
    out[i] = 0.0;
    for (size_t j = 0; j < N; j++) out[i] += A[i * N + j] * x[j];
  }
}

/* the call numbered fail_at (products and preconditioner solves counted together) fails, its
 * values written all the same */
static int apply(void *ctx, const double *x, double *out) {
  linear *L = ctx;
  times(L->A, x, out);
  return ++L->calls == L->fail_at ? SDAE_ERR_CALLBACK_RECOVERABLE : SDAE_OK;
}

/* x = A^-1 b by A's factors */
static void lu_solve(linear *L, const double *b_in, double *x) {
  gsl_matrix_view lu = gsl_matrix_view_array(L->LU, N, N);
  gsl_permutation p = {N, L->perm};
  gsl_vector_const_view bv = gsl_vector_const_view_array(b_in, N);
  gsl_vector_view xv = gsl_vector_view_array(x, N);
  ck_assert_int_eq(gsl_linalg_LU_solve(&lu.matrix, &p, &bv.vector, &xv.vector), GSL_SUCCESS);
}

static int precond(void *ctx, const double *r, double *z) {
  linear *L = ctx;
  if (L->exact)
    lu_solve(L, r, z);
  else
    memcpy(z, r, N * sizeof *z);
  return ++L->calls == L->fail_at ? SDAE_ERR_CALLBACK_FATAL : SDAE_OK;
}

static void *gmres_of(sdae_gmres *g, size_t m) {
  sdae_arena count = {0}, a = {0};
  sdae__gmres_carve(g, N, m, &count);
  a.base = calloc(count.used, 1);
  sdae__gmres_carve(g, N, m, &a);
  return a.base;
}

static double residual_norm(const double *A, const double *b, const double *x) {
  double Ax[N], s = 0.0;
  times(A, x, Ax);
  for (size_t i = 0; i < N; i++) s += (b[i] - Ax[i]) * (b[i] - Ax[i]);
  return sqrt(s);
}

static const double b[N] = {1.0, -2.0, 0.5, 3.0, -1.0, 0.25, 2.0, -0.75};

/* the Krylov space of an n x n matrix is the whole space after n steps: the solution to rounding
 * without a preconditioner, as A's own factors give it */
START_TEST(exact_in_n_steps) {
  for (int scaled = 0; scaled < 2; scaled++) { /* entries near 1, and near 1e-3 */
    linear L = linear_scaled(scaled ? 1e-3 : 1.0);
    sdae_gmres g;
    void *mem = gmres_of(&g, N);
    sdae_gmres_ops ops = {apply, precond, &L};
    double x[N], ref[N];
    ck_assert_int_eq(sdae__gmres_solve(&g, &ops, b, x, 1e-15), SDAE_OK);
    ck_assert_uint_le(g.iters, N);
    lu_solve(&L, b, ref);
    for (size_t i = 0; i < N; i++) ck_assert_double_le(fabs(x[i] - ref[i]), 1e-13 * fabs(ref[0]));
    free(mem);
  }
}
END_TEST

/* A = diag(1, ..., 1, last), no factors (the identity's preconditioner) */
static linear linear_diagonal(double last) {
  linear L;
  memset(&L, 0, sizeof L);
  for (size_t i = 0; i < N; i++) L.A[i * N + i] = i + 1 < N ? 1.0 : last;
  return L;
}

/* A = I: one step, x = b (the Hessenberg entry exactly 1); A = I + the shift down, b = e_1:
 * every step's new direction of length exactly 1, N steps, x = (1, -1, 1, ...) */
START_TEST(the_identity_in_one_step) {
  linear L = linear_diagonal(1.0);
  sdae_gmres g;
  void *mem = gmres_of(&g, N);
  sdae_gmres_ops ops = {apply, precond, &L};
  double x[N], e[N] = {1.0};
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, b, x, 1e-12), SDAE_OK);
  ck_assert_uint_eq(g.iters, 1);
  for (size_t i = 0; i < N; i++) ck_assert_double_le(fabs(x[i] - b[i]), 1e-15 * fabs(b[i]));
  for (size_t i = 1; i < N; i++) L.A[i * N + i - 1] = 1.0;
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, e, x, 1e-12), SDAE_OK);
  ck_assert_uint_eq(g.iters, N);
  for (size_t i = 0; i < N; i++) ck_assert_double_le(fabs(x[i] - (i % 2 ? -1.0 : 1.0)), 1e-12);
  free(mem);
}
END_TEST

/* A singular, b off its range (A = diag(1, ..., 1, 0), b = e_N): A b = 0, the Krylov space is
 * invariant at once and its best is x = 0, ||b - A x|| = ||b||: x = 0 exactly, not reached */
START_TEST(an_invariant_space_is_its_own_best) {
  linear L = linear_diagonal(0.0);
  sdae_gmres g;
  void *mem = gmres_of(&g, N);
  sdae_gmres_ops ops = {apply, precond, &L};
  double x[N], e[N] = {0};
  e[N - 1] = 1.0;
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, e, x, 1e-12), SDAE_OK);
  ck_assert_uint_eq(g.iters, 1);
  ck_assert_int_eq(g.reached, 0);
  for (size_t i = 0; i < N; i++) ck_assert_double_eq(x[i], 0.0);
  free(mem);
}
END_TEST

/* GMRES stops at the first step whose residual is within rtol ||b||: with ||b|| far from 1
 * (b times 1000), the steps one fewer leave more than that */
START_TEST(stops_at_the_first_step_within_rtol) {
  linear L = linear_case();
  sdae_gmres g;
  void *mem = gmres_of(&g, N);
  sdae_gmres_ops ops = {apply, precond, &L};
  double x[N], big[N], zero[N] = {0}, bn;
  unsigned k;
  for (size_t i = 0; i < N; i++) big[i] = 1e3 * b[i];
  bn = residual_norm(L.A, big, zero);
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, big, x, 1e-2), SDAE_OK);
  k = g.iters;
  ck_assert_int_eq(g.reached, 1);
  ck_assert_double_le(residual_norm(L.A, big, x), 1e-2 * bn * (1.0 + 1e-12));
  ck_assert_uint_ge(k, 2);
  free(mem);
  mem = gmres_of(&g, k - 1);
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, big, x, 1e-2), SDAE_OK);
  ck_assert_int_eq(g.reached, 0);
  ck_assert_double_gt(residual_norm(L.A, big, x), 1e-2 * bn);
  free(mem);
}
END_TEST

/* with A^-1 as the preconditioner A P^-1 = I: one step */
START_TEST(exact_preconditioner_one_step) {
  linear L = linear_case();
  sdae_gmres g;
  void *mem = gmres_of(&g, N);
  sdae_gmres_ops ops = {apply, precond, &L};
  double x[N];
  L.exact = 1;
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, b, x, 1e-12), SDAE_OK);
  ck_assert_uint_eq(g.iters, 1);
  ck_assert_int_eq(g.reached, 1);
  ck_assert_double_le(residual_norm(L.A, b, x), 1e-13);
  free(mem);
}
END_TEST

/* three steps of eight: short of the tolerance, said so (reached 0), and the residual the
 * rotations carry, |g_3|, is the true ||b - A x||, below ||b|| (GMRES minimizes it over the
 * Krylov space, which holds x = 0) */
START_TEST(short_at_m_steps) {
  linear L = linear_case();
  sdae_gmres g;
  void *mem = gmres_of(&g, 3);
  sdae_gmres_ops ops = {apply, precond, &L};
  double x[N], zero[N] = {0}, bn = residual_norm(L.A, b, zero);
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, b, x, 1e-12), SDAE_OK);
  ck_assert_uint_eq(g.iters, 3);
  ck_assert_int_eq(g.reached, 0);
  double r = residual_norm(L.A, b, x);
  ck_assert_double_lt(r, bn);
  ck_assert_double_gt(r, 1e-12 * bn);
  ck_assert_double_le(fabs(r - fabs(g.g[3])), 1e-12 * bn);
  free(mem);
}
END_TEST

/* a product or a preconditioner solve that fails (its values written) is the solve's status,
 * x left 0, whichever call it is; b = 0 is x = 0 without a call */
START_TEST(a_failing_product_and_a_zero_right_hand_side) {
  linear L = linear_case();
  sdae_gmres g;
  void *mem = gmres_of(&g, N);
  sdae_gmres_ops ops = {apply, precond, &L};
  double x[N], zero[N] = {0};
  for (int at = 1; at <= 6; at++) { /* odd: a preconditioner solve, even: a product */
    L.calls = 0, L.fail_at = at;
    ck_assert_int_eq(sdae__gmres_solve(&g, &ops, b, x, 1e-12),
                     at % 2 ? SDAE_ERR_CALLBACK_FATAL : SDAE_ERR_CALLBACK_RECOVERABLE);
    for (size_t i = 0; i < N; i++) ck_assert_double_eq(x[i], 0.0);
  }
  L.fail_at = 0;
  L.calls = 0;
  x[0] = 1.0;
  ck_assert_int_eq(sdae__gmres_solve(&g, &ops, zero, x, 1e-12), SDAE_OK);
  ck_assert_int_eq(L.calls, 0);
  for (size_t i = 0; i < N; i++) ck_assert_double_eq(x[i], 0.0);
  free(mem);
}
END_TEST

/* ---- Newton-Krylov ---- */

/* an implicit step y = x + h f(y), f_i(y) = -y_i^3 + (y_{i+1} - y_{i-1}), with the identity as
 * the "linear solve" of the hooks: its error is h f'(y), above 1 at h = 0.5 and y near 1.2, so
 * the chord on it does not contract, while GMRES on dR/dy by differences makes each update
 * Newton's, to GMRES's 1e-3 */
/* the cubic's f fails at this evaluation (0: never), and the hooks' solve is singular (z = 0) */
static unsigned cubic_fail_at, cubic_calls;
static int cubic_singular;

static int cubic_f(void *ctx, const double *y, double *out) {
  (void)ctx;
  if (++cubic_calls == cubic_fail_at) return SDAE_ERR_CALLBACK_FATAL;
  for (size_t i = 0; i < N; i++)
    out[i] = -y[i] * y[i] * y[i] + (i + 1 < N ? y[i + 1] : 0.0) - (i > 0 ? y[i - 1] : 0.0);
  return SDAE_OK;
}
static int identity_setup(void *ctx, const double *y) {
  (void)ctx, (void)y;
  return SDAE_OK;
}
static int identity_solve(void *ctx, const double *R, double *dy) {
  (void)ctx;
  if (cubic_singular)
    memset(dy, 0, N * sizeof *dy);
  else
    memcpy(dy, R, N * sizeof *dy);
  return SDAE_OK;
}

static int cubic_solve(int krylov, double *y, unsigned *iters) {
  static const double x[N] = {1.2, -1.1, 1.3, 1.0, -1.25, 1.15, -1.0, 1.2};
  sdae_newton nw;
  sdae_arena count = {0}, a = {0};
  const sdae_newton_system sys = {
      .f = cubic_f, .x = x, .setup = identity_setup, .solve = identity_solve};
  int rc;
  if (krylov)
    sdae__newton_carve_krylov(&nw, N, N, 1e-3, 1e-13, 20, &count);
  else
    sdae__newton_carve_hooks(&nw, N, 1e-13, 20, &count);
  a.base = calloc(count.used, 1);
  if (krylov)
    sdae__newton_carve_krylov(&nw, N, N, 1e-3, 1e-13, 20, &a);
  else
    sdae__newton_carve_hooks(&nw, N, 1e-13, 20, &a);
  nw.keep = 1;
  memcpy(y, x, sizeof x);
  cubic_calls = 0;
  rc = sdae__newton_solve(&nw, &sys, 0.5, y);
  *iters = nw.iters;
  free(a.base);
  return rc;
}

START_TEST(newton_krylov_converges_where_the_chord_cannot) {
  double y[N], f[N];
  unsigned iters;
  int chord = cubic_solve(0, y, &iters); /* diverges: no root, or past the doubles */
  ck_assert(chord == SDAE_ERR_NEWTON || chord == SDAE_ERR_NONFINITE);
  ck_assert_int_eq(cubic_solve(1, y, &iters), SDAE_OK);
  ck_assert_uint_le(iters, 10); /* Newton's, each update to GMRES's 1e-3 */
  cubic_f(NULL, y, f);
  static const double x[N] = {1.2, -1.1, 1.3, 1.0, -1.25, 1.15, -1.0, 1.2};
  for (size_t i = 0; i < N; i++) ck_assert_double_le(fabs(y[i] - x[i] - 0.5 * f[i]), 1e-13);
}
END_TEST

/* ---- a model's own linear solve (sdae_model.q0_lsetup, q0_lsolve) ---- */

/* the quartic oscillator with the exact I - a dq0/dmu at the point set up, inverted: each
 * setup's t and a recorded */
typedef struct solved_quartic {
  quartic q; /* first: the quartic's callbacks read params as a quartic */
  double inv[4], t, a;
  int setups, solves;
} solved_quartic;

static int sq_setup(double t, const double *mu, double a, void *params) {
  solved_quartic *p = params;
  double J[4], A[4], det;
  quartic_q0_jac(t, mu, J, &p->q);
  for (int i = 0; i < 4; i++) A[i] = (i == 0 || i == 3 ? 1.0 : 0.0) - a * J[i];
  det = A[0] * A[3] - A[1] * A[2];
  p->inv[0] = A[3] / det, p->inv[1] = -A[1] / det, p->inv[2] = -A[2] / det, p->inv[3] = A[0] / det;
  p->t = t, p->a = a, p->setups++;
  return 0;
}

static int sq_solve(const double *r, double *z, void *params) {
  solved_quartic *p = params;
  z[0] = p->inv[0] * r[0] + p->inv[1] * r[1];
  z[1] = p->inv[2] * r[0] + p->inv[3] * r[1];
  p->solves++;
  return 0;
}

/* 100 midpoint steps of T = 0.05 with the model's solve land where the dense Newton's do (the
 * same equation, solved to its tolerance), the solve set up at the midpoint's time with
 * a = T / 2 (the midpoint map's slope); one without the other is refused */
START_TEST(a_models_linear_solve_serves_the_midpoint_map) {
  solved_quartic sq = {.q = {.k = 1.0, .d = 0.1}};
  sdae_model plain = quartic_model(&sq.q), solved = plain;
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *a, *b;
  double xi[2] = {0.0, 0.0}, mu[2] = {1.0, 0.0}, xi2[2] = {0.0, 0.0}, mu2[2] = {1.0, 0.0};
  const double T = 0.05;
  solved.params = &sq;
  solved.q0_lsetup = sq_setup;
  ck_assert_int_eq(sdae_stepper_alloc(&b, &solved, &o), SDAE_ERR_NULL);
  solved.q0_lsetup = NULL, solved.q0_lsolve = sq_solve;
  ck_assert_int_eq(sdae_stepper_alloc(&b, &solved, &o), SDAE_ERR_NULL);
  solved.q0_lsetup = sq_setup;
  ck_assert_int_eq(sdae_stepper_alloc(&a, &plain, &o), SDAE_OK);
  ck_assert_int_eq(sdae_stepper_alloc(&b, &solved, &o), SDAE_OK);
  for (int k = 0; k < 100; k++) {
    ck_assert_int_eq(sdae_step(a, k * T, T, xi, mu), SDAE_OK);
    ck_assert_int_eq(sdae_step(b, k * T, T, xi2, mu2), SDAE_OK);
    ck_assert_double_eq(sq.a, 0.5 * T);
    ck_assert_double_eq(sq.t, k * T + 0.5 * T);
  }
  ck_assert_int_ge(sq.setups, 100); /* set up anew at each step's first solve */
  ck_assert_int_gt(sq.solves, sq.setups);
  for (int i = 0; i < 2; i++) ck_assert_double_le(fabs(mu[i] - mu2[i]), 1e-12);
  ck_assert_double_gt(fabs(mu[0] - 1.0), 0.1); /* it moved */
  sdae_stepper_free(a);
  sdae_stepper_free(b);
}
END_TEST

/* a residual that fails inside a GMRES product is the solve's status (fatal: not retried); a
 * preconditioner that maps everything to 0 gives GMRES no direction: no update is taken for
 * convergence, and the solve fails by name, never at y unchanged with SDAE_OK */
START_TEST(newton_krylov_failures_are_named) {
  double y[N];
  unsigned iters;
  cubic_fail_at = 3; /* the residual, then its first product's evaluation and the next */
  ck_assert_int_eq(cubic_solve(1, y, &iters), SDAE_ERR_CALLBACK_FATAL);
  cubic_fail_at = 0, cubic_singular = 1;
  ck_assert_int_eq(cubic_solve(1, y, &iters), SDAE_ERR_NEWTON);
  cubic_singular = 0;
}
END_TEST

int main(void) {
  Suite *s = suite_create("gmres");
  ADD_CASE(s, exact_in_n_steps);
  ADD_CASE(s, the_identity_in_one_step);
  ADD_CASE(s, an_invariant_space_is_its_own_best);
  ADD_CASE(s, stops_at_the_first_step_within_rtol);
  ADD_CASE(s, exact_preconditioner_one_step);
  ADD_CASE(s, short_at_m_steps);
  ADD_CASE(s, a_failing_product_and_a_zero_right_hand_side);
  ADD_CASE(s, newton_krylov_converges_where_the_chord_cannot);
  ADD_CASE(s, newton_krylov_failures_are_named);
  ADD_CASE(s, a_models_linear_solve_serves_the_midpoint_map);
  return run_suite(s);
}
