/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The wide sparse LU that chooses a sparse mechanism's chart (core/sparse_lu.c), against dense
 * linear algebra (GSL's LU of the chosen columns) and the mathematics: A_D x = b and
 * A_D^T y = c solved to rounding, B = A_D^-1 A_I applied as the dense B, Hager's estimate a
 * lower bound of ||B||_1 and on the rope its value, dependent rows refused, the pivots kept by a
 * refactorization, and on a rope of 4096 links factors of the size of G. */
#include <float.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sparse_lu.h"
#include "rope.h"
#include "testmodels.h"
#include "truss.h"

/* a factorization of A with its own block (malloc'd: the test's, not the library's) */
typedef struct factored {
  sdae_sparse_lu lu;
  void *mem;
} factored;

/* A's orders (sdae__sparse_lu_orders), its block (malloc'd: the test's, not the library's) */
static size_t *orders_of(const sdae_pattern *p, size_t m, size_t n) {
  size_t len = sdae__sparse_lu_orders_min(m, n, p->nnz) + 9 * p->nnz; /* the hubs' whole graph */
  SuiteSparse_long *work = malloc(len * sizeof *work);
  size_t *orders = malloc(SDAE_SPARSE_LU_ORDERS * (m ? m : 1) * sizeof *orders);
  ck_assert_ptr_nonnull(work);
  ck_assert_ptr_nonnull(orders);
  ck_assert_int_eq(sdae__sparse_lu_orders(p, m, n, work, len, orders), SDAE_OK);
  free(work);
  return orders;
}

/* a factorization of A with its own block and L's reserve l_cap, in the order which */
static void factored_with(factored *f, const sdae_pattern *p, size_t m, size_t n, size_t l_cap,
                          int which) {
  sdae_arena a = {0};
  size_t *orders = orders_of(p, m, n);
  sdae__sparse_lu_carve(&f->lu, m, n, p->nnz, l_cap, &a);
  ck_assert(!a.overflow);
  f->mem = calloc(1, a.used + 64);
  ck_assert_ptr_nonnull(f->mem);
  a = (sdae_arena){.base = f->mem};
  sdae__sparse_lu_carve(&f->lu, m, n, p->nnz, l_cap, &a);
  memcpy(f->lu.order, orders + (size_t)which * m, m * sizeof *orders);
  free(orders);
}

/* the same, L's reserve U's, in the leaves' order */
static void factored_init(factored *f, const sdae_pattern *p, size_t m, size_t n) {
  factored_with(f, p, m, n, sdae__sparse_lu_reserve(m, p->nnz), SDAE_SPARSE_LU_LEAVES);
}

/* max_i |(A_D x - b)_i| over max_i sum |terms| for x = A_D^-1 b, b random: the solve's backward
 * error, over A's rows */
static double solve_residual(sdae_sparse_lu *lu, const sdae_pattern *p, const double *A,
                             gsl_rng *rng) {
  size_t m = lu->m;
  double *b = calloc(m, sizeof *b), *x = calloc(m, sizeof *x), worst = 0.0, size = 0.0;
  for (size_t i = 0; i < m; i++) b[i] = gsl_rng_uniform(rng) - 0.5;
  sdae__sparse_lu_solve(lu, b, x);
  for (size_t i = 0; i < m; i++) {
    double r = -b[i], s = fabs(b[i]);
    for (size_t e = p->row_start[i]; e < p->row_start[i + 1]; e++) {
      size_t k = lu->row_of[p->col[e]];
      if (k < m) r += A[e] * x[k], s += fabs(A[e] * x[k]);
    }
    worst = fmax(worst, fabs(r)), size = fmax(size, s);
  }
  free(b), free(x);
  return worst / size;
}

/* a rope of N links (closed: N + 1) at a random configuration, its G's values */
typedef struct rope_g {
  mech_rope r;
  sdae_mbs sys;
  double *q, *G;
} rope_g;

static void rope_g_at(rope_g *g, size_t N, int closed, gsl_rng *rng) {
  g->r = mech_rope_unit(N, closed, 1);
  ck_assert_int_eq(mech_rope_system(&g->sys, &g->r), 0);
  g->q = malloc(2 * N * sizeof *g->q);
  g->G = malloc(g->r.jacobian_pattern.nnz * sizeof *g->G);
  for (size_t i = 0; i < 2 * N; i++) g->q[i] = 4.0 * (gsl_rng_uniform(rng) - 0.5);
  ck_assert_int_eq(g->sys.jacobian(0.0, g->q, g->G, g->sys.params), 0);
}

static void rope_g_free(rope_g *g) {
  free(g->q), free(g->G);
  mech_rope_free(&g->r);
}

/* A dense (m x n, row-major) from its pattern */
static double *dense(const sdae_pattern *p, const double *values, size_t m, size_t n) {
  double *A = calloc(m * n, sizeof *A);
  for (size_t i = 0; i < m; i++)
    for (size_t e = p->row_start[i]; e < p->row_start[i + 1]; e++) A[i * n + p->col[e]] = values[e];
  return A;
}

/* max |a - b| over max |b| */
static double rel_err(const double *a, const double *b, size_t n) {
  double d = 0.0, s = DBL_MIN;
  for (size_t i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i])), s = fmax(s, fabs(b[i]));
  return d / s;
}

/* The factors against dense algebra: A_D (the chosen columns, in pivot order) by GSL's LU,
 * then b = A_D x for a random x solved back, A_D^T y likewise, and B = A_D^-1 A_I column by
 * column against times_b and (its rows) times_bt; the estimate against the exact ||B||_1.
 * Returns the estimate over ||B||_1. */
static double against_dense(sdae_sparse_lu *lu, const double *A, gsl_rng *rng) {
  size_t m = lu->m, n = lu->n;
  gsl_matrix *AD = gsl_matrix_alloc(m, m);
  gsl_permutation *perm = gsl_permutation_alloc(m);
  gsl_vector *col = gsl_vector_alloc(m), *sol = gsl_vector_alloc(m);
  double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *b = malloc(m * sizeof *b);
  double *z = malloc(n * sizeof *z), *Bd = calloc(m * n, sizeof *Bd), exact = 0.0;
  int sign;
  for (size_t k = 0; k < m; k++) { /* the pivots are distinct columns */
    ck_assert_uint_lt(lu->pivot[k], n);
    ck_assert_uint_eq(lu->row_of[lu->pivot[k]], k);
    for (size_t i = 0; i < m; i++) gsl_matrix_set(AD, i, k, A[i * n + lu->pivot[k]]);
  }
  /* A_D x = b: b formed from a known x, solved back */
  for (size_t k = 0; k < m; k++) x[k] = gsl_rng_uniform(rng) - 0.5;
  for (size_t i = 0; i < m; i++) {
    b[i] = 0.0;
    for (size_t k = 0; k < m; k++) b[i] += gsl_matrix_get(AD, i, k) * x[k];
  }
  sdae__sparse_lu_solve(lu, b, y);
  ck_assert_double_le(rel_err(y, x, m), 1e-10);
  /* A_D^T y = c, c formed from a known y */
  for (size_t k = 0; k < m; k++) {
    b[k] = 0.0;
    for (size_t i = 0; i < m; i++) b[k] += gsl_matrix_get(AD, i, k) * x[i];
  }
  sdae__sparse_lu_solve_t(lu, b, y);
  ck_assert_double_le(rel_err(y, x, m), 1e-10);
  /* B = A_D^-1 A_I densely, column by column of A_I */
  gsl_linalg_LU_decomp(AD, perm, &sign);
  for (size_t c = 0; c < n; c++) {
    double colsum = 0.0;
    if (lu->row_of[c] != m) continue;
    for (size_t i = 0; i < m; i++) gsl_vector_set(col, i, A[i * n + c]);
    gsl_linalg_LU_solve(AD, perm, col, sol);
    for (size_t k = 0; k < m; k++) Bd[k * n + c] = gsl_vector_get(sol, k);
    for (size_t k = 0; k < m; k++) colsum += fabs(Bd[k * n + c]);
    exact = fmax(exact, colsum);
    memset(x, 0, n * sizeof *x);
    x[c] = 1.0;
    sdae__sparse_lu_times_b(lu, x, y);
    for (size_t k = 0; k < m; k++) b[k] = Bd[k * n + c];
    ck_assert_double_le(rel_err(y, b, m), 1e-10);
  }
  for (size_t k = 0; k < m; k++) { /* row k of B by B^T e_k */
    memset(b, 0, m * sizeof *b);
    b[k] = 1.0;
    sdae__sparse_lu_times_bt(lu, b, y);
    for (size_t c = 0; c < n; c++) ck_assert_double_le(fabs(y[c] - Bd[k * n + c]), 1e-10 * exact);
  }
  double est = sdae__sparse_lu_norm1(lu, x, z);
  ck_assert_double_le(est, exact * (1.0 + 1e-12)); /* ||B x||_1 with ||x||_1 = 1 */
  gsl_matrix_free(AD), gsl_permutation_free(perm), gsl_vector_free(col), gsl_vector_free(sol);
  free(x), free(y), free(b), free(z), free(Bd);
  return est / exact;
}

/* On ropes open and closed at random configurations (their G's rows the links' directions):
 * a chart, its solves and B as the dense algebra's. Hager's estimate of ||B||_1 is a lower bound
 * (a theorem, checked in against_dense); how far below is not bounded in general, so here it is
 * held to a factor 3 and to being exact on at least half of the ropes (measured: 15 of 20
 * exact, the least 0.52) */
START_TEST(rope_charts_solve_as_dense_algebra) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  int exact = 0;
  gsl_rng_set(rng, 7);
  for (int trial = 0; trial < 20; trial++) {
    rope_g g;
    factored f;
    rope_g_at(&g, 3 + (size_t)trial % 9, trial % 2, rng);
    size_t m = g.sys.n_c, n = g.sys.n_q;
    double *A = dense(&g.r.jacobian_pattern, g.G, m, n);
    factored_init(&f, &g.r.jacobian_pattern, m, n);
    ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, &g.r.jacobian_pattern, g.G), SDAE_OK);
    double ratio = against_dense(&f.lu, A, rng);
    ck_assert_double_ge(ratio, 1.0 / 3.0);
    exact += ratio >= 1.0 - 1e-12;
    free(A), free(f.mem);
    rope_g_free(&g);
  }
  ck_assert_int_ge(exact, 10);
  gsl_rng_free(rng);
}
END_TEST

/* random wide sparse matrices, 4 nonzeros a row: the same against dense algebra */
START_TEST(random_wide_matrices_solve_as_dense_algebra) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  for (int trial = 0; trial < 20; trial++) {
    size_t m = 10 + (size_t)trial, n = 2 * m + 3, start[64], col[256], k = 0;
    double values[256];
    factored f;
    start[0] = 0;
    for (size_t i = 0; i < m; i++) { /* columns i, and three others ascending and distinct */
      unsigned char used[64] = {0};
      used[i] = 1;
      for (int c = 0; c < 3; c++) used[gsl_rng_uniform_int(rng, n)] = 1;
      for (size_t c = 0; c < n; c++)
        if (used[c]) col[k] = c, values[k++] = gsl_rng_uniform(rng) - 0.5;
      start[i + 1] = k;
    }
    sdae_pattern p = {k, start, col};
    double *A = dense(&p, values, m, n);
    ck_assert_int_eq(sdae__pattern_check(&p, m, n, 0), SDAE_OK);
    factored_init(&f, &p, m, n);
    ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, &p, values), SDAE_OK);
    ck_assert_double_ge(against_dense(&f.lu, A, rng), 1.0 / 3.0);
    free(A), free(f.mem);
  }
  gsl_rng_free(rng);
}
END_TEST

/* a row that is a combination of the others has no pivot: SDAE_ERR_RANK, in every order */
START_TEST(dependent_rows_are_rank) {
  static const size_t start[] = {0, 2, 4, 7}, col[] = {0, 1, 1, 2, 0, 1, 2};
  static const double values[] = {1.0, 2.0, 3.0, -1.0, 1.0, 5.0, -1.0}; /* row 2 = row 0 + 1 */
  sdae_pattern p = {7, start, col};
  factored f;
  size_t *orders = orders_of(&p, 3, 5);
  double x[5], z[5];
  factored_init(&f, &p, 3, 5);
  ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, &p, values), SDAE_ERR_RANK);
  /* in every order: the rank is the matrix's */
  ck_assert_int_eq(
      sdae__sparse_lu_choose_best(&f.lu, &p, values, orders, SDAE_SPARSE_LU_ORDERS, 1.5, x, z),
      SDAE_ERR_RANK);
  free(orders), free(f.mem);
}
END_TEST

/* A refactorization keeps the pivots and solves at the new values; one whose pivot vanishes
 * there is SDAE_ERR_RANK (a rope link whose pivot coordinate's component turns to 0) */
START_TEST(refactor_keeps_the_pivots) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  rope_g g, h;
  factored f;
  gsl_rng_set(rng, 3);
  rope_g_at(&g, 7, 0, rng);
  rope_g_at(&h, 7, 0, rng);
  size_t m = g.sys.n_c, n = g.sys.n_q, pivots[8];
  factored_init(&f, &g.r.jacobian_pattern, m, n);
  ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, &g.r.jacobian_pattern, g.G), SDAE_OK);
  memcpy(pivots, f.lu.pivot, m * sizeof *pivots);
  ck_assert_int_eq(sdae__sparse_lu_refactor(&f.lu, &h.r.jacobian_pattern, h.G), SDAE_OK);
  ck_assert_mem_eq(pivots, f.lu.pivot, m * sizeof *pivots);
  double *A = dense(&h.r.jacobian_pattern, h.G, m, n);
  against_dense(&f.lu, A, rng);
  /* the first link's row (G's row 0 = (x_1, y_1), the coordinates themselves): zero its pivot's */
  for (size_t k = 0; k < m; k++)
    if (f.lu.order[k] == 0) h.q[pivots[k]] = 0.0;
  ck_assert_int_eq(h.sys.jacobian(0.0, h.q, h.G, h.sys.params), 0);
  ck_assert_int_eq(sdae__sparse_lu_refactor(&f.lu, &h.r.jacobian_pattern, h.G), SDAE_ERR_RANK);
  free(A), free(f.mem);
  rope_g_free(&g), rope_g_free(&h);
  gsl_rng_free(rng);
}
END_TEST

/* A rope of 4096 links: a chart in its reserve, factors of at most three times G's nonzeros
 * (Markowitz's count takes the link's far end, which no later link holds, whenever its value
 * passes the threshold, and fill then stops), and a solve to rounding (residual) */
START_TEST(a_rope_of_4096_links_factors_in_its_nonzeros) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  for (int closed = 0; closed <= 1; closed++) {
    rope_g g;
    factored f;
    rope_g_at(&g, 4095, closed, rng);
    const sdae_pattern *p = &g.r.jacobian_pattern;
    size_t m = g.sys.n_c, n = g.sys.n_q;
    factored_init(&f, p, m, n);
    ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, p, g.G), SDAE_OK);
    ck_assert_uint_le(f.lu.u_start[m] + f.lu.l_start[m], 3 * p->nnz);
    ck_assert_double_le(solve_residual(&f.lu, p, g.G, rng), 1e-12);
    free(f.mem);
    rope_g_free(&g);
  }
  gsl_rng_free(rng);
}
END_TEST

/* The closed rope of 4095 links at its start, two straight runs (a V): no column is held by one
 * row, and along a straight run the coordinate a leaf would pivot on cancels, so taking the
 * loop's rows in turn grew a row longer at each link, past the reserve. The first row set
 * aside opens the loop: every other row a leaf, no fill, L's entries all in the last row (the
 * one set aside, eliminating through the loop) */
START_TEST(a_closed_rope_in_straight_runs_opens_its_loop) {
  mech_rope r = mech_rope_unit(4095, 1, 1);
  sdae_mbs sys;
  factored f;
  ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
  const sdae_pattern *p = &r.jacobian_pattern;
  size_t m = sys.n_c, n = sys.n_q;
  double *q = malloc(n * sizeof *q), *v = malloc(n * sizeof *v), *G = malloc(p->nnz * sizeof *G);
  ck_assert_int_eq(mech_rope_start(&r, 0.3, q, v), 0);
  ck_assert_int_eq(sys.jacobian(0.0, q, G, sys.params), 0);
  factored_init(&f, p, m, n);
  ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, p, G), SDAE_OK);
  ck_assert_uint_eq(f.lu.l_start[m - 1], 0);
  ck_assert_uint_le(f.lu.l_start[m], m - 1);
  ck_assert_uint_le(f.lu.u_start[m - 1], p->nnz - (p->row_start[1] - p->row_start[0]));
  free(q), free(v), free(G), free(f.mem);
  mech_rope_free(&r);
}
END_TEST

/* one row [2, 1, -3]: its pivot the largest (a tie of Markowitz's counts, 0 each), column 2;
 * B = A_D^-1 A_I = (2, 1) / -3, ||B||_1 = 2/3, which Hager's estimate finds exactly */
START_TEST(a_single_row_and_its_norm) {
  static const size_t start[] = {0, 3}, col[] = {0, 1, 2};
  static const double values[] = {2.0, 1.0, -3.0};
  sdae_pattern p = {3, start, col};
  factored f;
  double x[3], z[3];
  factored_init(&f, &p, 1, 3);
  ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, &p, values), SDAE_OK);
  ck_assert_uint_eq(f.lu.pivot[0], 2);
  ck_assert_double_eq_tol(sdae__sparse_lu_norm1(&f.lu, x, z), 2.0 / 3.0, 1e-15);
  free(f.mem);
}
END_TEST

/* a truss (examples/models/truss.h) at its start, its G's values */
typedef struct truss_g {
  mech_truss t;
  sdae_mbs sys;
  double *q, *G;
} truss_g;

static void truss_g_at(truss_g *g, int (*build)(mech_truss *, size_t, int), size_t size) {
  ck_assert_int_eq(build(&g->t, size, 1), 0);
  ck_assert_int_eq(mech_truss_system(&g->sys, &g->t), 0);
  g->q = malloc(2 * g->sys.n_q * sizeof *g->q);
  g->G = malloc(g->t.jacobian_pattern.nnz * sizeof *g->G);
  mech_truss_start(&g->t, g->q, g->q + g->sys.n_q);
  ck_assert_int_eq(g->sys.jacobian(0.0, g->q, g->G, g->sys.params), 0);
}

static void truss_g_free(truss_g *g) {
  free(g->q), free(g->G);
  mech_truss_free(&g->t);
}

/* every topology of a truss: a cart under 50 pendulums, ladders of 8 and 16 cells, a cloth of
 * 8 x 8, a binary tree of depth 6 */
static const struct {
  int (*build)(mech_truss *, size_t, int);
  size_t size;
} trusses[] = {{mech_truss_star, 50},
               {mech_truss_ladder, 8},
               {mech_truss_ladder, 16},
               {mech_truss_cloth, 8},
               {mech_truss_tree, 6}};
enum { TRUSSES = sizeof trusses / sizeof *trusses };

/* each order sdae__sparse_lu_orders finds takes every row once, on every topology of a truss,
 * with workspace at its least (the hubs' bound halved to fit) and with room; one entry less is
 * refused */
START_TEST(every_order_takes_each_row_once) {
  for (size_t c = 0; c < TRUSSES; c++)
    for (int room = 0; room < 2; room++) {
      truss_g g;
      truss_g_at(&g, trusses[c].build, trusses[c].size);
      const sdae_pattern *p = &g.t.jacobian_pattern;
      size_t m = g.sys.n_c, n = g.sys.n_q, len = sdae__sparse_lu_orders_min(m, n, p->nnz);
      size_t given = len + (size_t)room * 9 * p->nnz;
      SuiteSparse_long *work = malloc(given * sizeof *work); /* what it is told: no more */
      size_t *orders = malloc(SDAE_SPARSE_LU_ORDERS * m * sizeof *orders);
      unsigned char *seen = malloc(m);
      ck_assert_int_eq(sdae__sparse_lu_orders(p, m, n, work, len - 1, orders), SDAE_ERR_BUFFER);
      ck_assert_int_eq(sdae__sparse_lu_orders(p, m, n, work, given, orders), SDAE_OK);
      for (size_t o = 0; o < SDAE_SPARSE_LU_ORDERS; o++) {
        memset(seen, 0, m);
        for (size_t k = 0; k < m; k++) {
          ck_assert_uint_lt(orders[o * m + k], m);
          ck_assert(!seen[orders[o * m + k]]);
          seen[orders[o * m + k]] = 1;
        }
      }
      free(work), free(orders), free(seen);
      truss_g_free(&g);
    }
}
END_TEST

/* The best of the orders by the hysteresis rule (a later order's chart replaces the one kept
 * when its estimate of ||B||_1 is smaller by the factor, or the same with fewer entries): the
 * kept chart's estimate is then at most the factor times every fitting order's (to the tie's
 * rounding), it is the first fitting order's where none is smaller by the factor (the ladder of
 * 8 cells: 4.30 the leaves, 4.29 the others), its factors solve as dense algebra does, and on
 * each topology at least one order fits */
START_TEST(the_best_order_keeps_a_chart_within_the_factor_of_each) {
  const double by = 1.5, tie = 1e-9;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 13);
  for (size_t c = 0; c < TRUSSES; c++) {
    truss_g g;
    factored f;
    truss_g_at(&g, trusses[c].build, trusses[c].size);
    const sdae_pattern *p = &g.t.jacobian_pattern;
    size_t m = g.sys.n_c, n = g.sys.n_q, *orders = orders_of(p, m, n);
    double *x = malloc(2 * n * sizeof *x), *z = x + n, kept, first = 0.0, least = HUGE_VAL;
    double *A = dense(p, g.G, m, n);
    factored_init(&f, p, m, n);
    ck_assert_int_eq(
        sdae__sparse_lu_choose_best(&f.lu, p, g.G, orders, SDAE_SPARSE_LU_ORDERS, by, x, z),
        SDAE_OK);
    kept = sdae__sparse_lu_norm1(&f.lu, x, z);
    against_dense(&f.lu, A, rng);
    for (size_t o = 0; o < SDAE_SPARSE_LU_ORDERS; o++) {
      factored one;
      factored_init(&one, p, m, n);
      memcpy(one.lu.order, orders + o * m, m * sizeof *orders);
      if (sdae__sparse_lu_choose(&one.lu, p, g.G) == SDAE_OK) {
        double mu = sdae__sparse_lu_norm1(&one.lu, x, z);
        ck_assert_double_le(kept, by * mu * (1.0 + tie));
        if (first == 0.0)
          first = mu;
        else
          least = fmin(least, mu);
      }
      free(one.mem);
    }
    ck_assert_double_gt(first, 0.0);
    if (least * by >= first) ck_assert_double_le(fabs(kept - first), tie * first);
    free(x), free(A), free(orders), free(f.mem);
    truss_g_free(&g);
  }
  gsl_rng_free(rng);
}
END_TEST

/* A ladder of 64 four-bar cells, a long row of loops: the leaves first (each loop opened by a
 * row set aside, which eliminates through the rest of the ladder) fills L, and minimum degree
 * (whose elimination tree on a band is a path, every independent column carried through each
 * row above it) fills U, past the reserve both (4 nnz(G) + n_c for U and as much for L, one
 * array: minimum degree's U and L take 6691 entries of its 6532); nested dissection's tree, of
 * depth log n_c, fits, and its factors solve as dense algebra does */
START_TEST(a_long_row_of_loops_fits_by_dissection) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  truss_g g;
  factored f;
  gsl_rng_set(rng, 17);
  truss_g_at(&g, mech_truss_ladder, 64);
  const sdae_pattern *p = &g.t.jacobian_pattern;
  size_t m = g.sys.n_c, n = g.sys.n_q, *orders = orders_of(p, m, n);
  double *x = malloc(2 * n * sizeof *x), *A = dense(p, g.G, m, n);
  factored_init(&f, p, m, n);
  for (size_t o = 0; o < SDAE_SPARSE_LU_ORDERS; o++) {
    memcpy(f.lu.order, orders + o * m, m * sizeof *orders);
    ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, p, g.G),
                     o == SDAE_SPARSE_LU_DISSECTION ? SDAE_OK : SDAE_ERR_PATTERN);
  }
  ck_assert_int_eq(
      sdae__sparse_lu_choose_best(&f.lu, p, g.G, orders, SDAE_SPARSE_LU_ORDERS, 1.5, x, x + n),
      SDAE_OK);
  ck_assert_mem_eq(f.lu.order, orders + SDAE_SPARSE_LU_DISSECTION * m, m * sizeof *orders);
  against_dense(&f.lu, A, rng);
  free(x), free(A), free(orders), free(f.mem);
  truss_g_free(&g);
  gsl_rng_free(rng);
}
END_TEST

/* U takes the room L leaves: the cloth of 32 x 32 in minimum degree's order fills U past its own
 * reserve (4 nnz(G) + n_c), with an L far below L's (U's again); in the one array both fit, and
 * the solve's backward error is at rounding. A reserve of exactly the entries they took fits,
 * one fewer is SDAE_ERR_PATTERN */
START_TEST(u_takes_the_room_l_leaves) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  truss_g g;
  factored f;
  gsl_rng_set(rng, 19);
  truss_g_at(&g, mech_truss_cloth, 32);
  const sdae_pattern *p = &g.t.jacobian_pattern;
  size_t m = g.sys.n_c, n = g.sys.n_q, reserve = sdae__sparse_lu_reserve(m, p->nnz);
  factored_with(&f, p, m, n, reserve, SDAE_SPARSE_LU_AMD);
  ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, p, g.G), SDAE_OK);
  size_t u = f.lu.u_start[m], l = f.lu.l_start[m];
  ck_assert_uint_gt(u, reserve);
  ck_assert_double_le(solve_residual(&f.lu, p, g.G, rng), 1e-12);
  free(f.mem);
  for (int less = 0; less < 2; less++) {
    factored_with(&f, p, m, n, u + l - reserve - (size_t)less, SDAE_SPARSE_LU_AMD);
    ck_assert_int_eq(sdae__sparse_lu_choose(&f.lu, p, g.G), less ? SDAE_ERR_PATTERN : SDAE_OK);
    if (!less) ck_assert_double_le(solve_residual(&f.lu, p, g.G, rng), 1e-12);
    free(f.mem);
  }
  truss_g_free(&g);
  gsl_rng_free(rng);
}
END_TEST

/* the strictly lower entries of the Cholesky factor of A A^T with A's rows in order, by dense
 * symbolic elimination (an m x m boolean matrix: i and j adjacent when they share a column,
 * then each eliminated row joining its later neighbours) */
static size_t dense_cholesky_count(const sdae_pattern *p, size_t m, size_t n, const size_t *order) {
  unsigned char *B = calloc(m * m, 1), *in = calloc(m * n, 1);
  size_t count = 0;
  for (size_t k = 0; k < m; k++)
    for (size_t e = p->row_start[order[k]]; e < p->row_start[order[k] + 1]; e++)
      in[k * n + p->col[e]] = 1;
  for (size_t i = 0; i < m; i++)
    for (size_t j = 0; j < m; j++)
      for (size_t c = 0; c < n && !B[i * m + j]; c++) B[i * m + j] = in[i * n + c] && in[j * n + c];
  for (size_t k = 0; k < m; k++)
    for (size_t i = k + 1; i < m; i++) {
      if (!B[i * m + k]) continue;
      count++;
      for (size_t j = k + 1; j < m; j++)
        if (B[j * m + k]) B[i * m + j] = B[j * m + i] = 1;
    }
  free(B), free(in);
  return count;
}

/* the bound counted without forming A A^T is the dense symbolic count, in every order, on
 * random wide patterns (rows sharing single columns) and on every topology of a truss; told to
 * stop past a count, it returns one above it, at most the whole */
START_TEST(the_bound_on_l_is_the_cholesky_factors_count) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 23);
  for (size_t trial = 0; trial < 20 + TRUSSES; trial++) {
    size_t start[64], col[256], k = 0, m, n;
    sdae_pattern p;
    truss_g g;
    if (trial < 20) {
      m = 10 + trial, n = 2 * m + 3;
      start[0] = 0;
      for (size_t i = 0; i < m; i++) {
        unsigned char used[64] = {0};
        used[i] = 1;
        for (int c = 0; c < 3; c++) used[gsl_rng_uniform_int(rng, n)] = 1;
        for (size_t c = 0; c < n; c++)
          if (used[c]) col[k++] = c;
        start[i + 1] = k;
      }
      p = (sdae_pattern){k, start, col};
    } else {
      truss_g_at(&g, trusses[trial - 20].build, trusses[trial - 20].size);
      p = g.t.jacobian_pattern, m = g.sys.n_c, n = g.sys.n_q;
    }
    size_t *orders = orders_of(&p, m, n), len = sdae__sparse_lu_orders_min(m, n, p.nnz);
    SuiteSparse_long *work = malloc(len * sizeof *work);
    for (size_t o = 0; o < SDAE_SPARSE_LU_ORDERS; o++) {
      size_t full = dense_cholesky_count(&p, m, n, orders + o * m), half = full / 2;
      ck_assert_uint_eq(sdae__sparse_lu_l_bound(&p, m, n, orders + o * m, SIZE_MAX, work), full);
      ck_assert_uint_eq(sdae__sparse_lu_l_bound(&p, m, n, orders + o * m, full, work), full);
      size_t cut = sdae__sparse_lu_l_bound(&p, m, n, orders + o * m, half, work);
      ck_assert(full == half ? cut == full : (cut > half && cut <= full)); /* stopped past it */
    }
    free(work), free(orders);
    if (trial >= 20) truss_g_free(&g);
  }
  gsl_rng_free(rng);
}
END_TEST

/* George and Ng's bound: whatever the pivots (G's values scaled at random, entry by entry, so
 * that each trial pivots elsewhere), L holds at most the strictly lower entries of the Cholesky
 * factor of G G^T in the rows' order, on every topology of a truss and in every order; on an
 * open rope, whose G G^T is tridiagonal (two links share a mass), the leaves' order and
 * minimum degree, paths both, bound it at n_c - 1 */
START_TEST(l_stays_within_its_bound) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 19);
  for (size_t c = 0; c <= TRUSSES; c++) {
    truss_g g;
    rope_g r;
    const sdae_pattern *p;
    double *G;
    size_t m, n;
    if (c < TRUSSES) {
      truss_g_at(&g, trusses[c].build, trusses[c].size);
      p = &g.t.jacobian_pattern, G = g.G, m = g.sys.n_c, n = g.sys.n_q;
    } else {
      rope_g_at(&r, 64, 0, rng);
      p = &r.r.jacobian_pattern, G = r.G, m = r.sys.n_c, n = r.sys.n_q;
    }
    size_t *orders = orders_of(p, m, n), len = sdae__sparse_lu_orders_min(m, n, p->nnz);
    SuiteSparse_long *work = malloc(len * sizeof *work);
    double *scaled = malloc(p->nnz * sizeof *scaled);
    for (size_t o = 0; o < SDAE_SPARSE_LU_ORDERS; o++) {
      size_t most = sdae__sparse_lu_l_bound(p, m, n, orders + o * m, SIZE_MAX, work), fits = 0;
      if (c == TRUSSES && o != SDAE_SPARSE_LU_DISSECTION) ck_assert_uint_eq(most, m - 1);
      for (int trial = 0; trial < 8; trial++) {
        factored f;
        for (size_t e = 0; e < p->nnz; e++) scaled[e] = G[e] * (0.5 + 1.5 * gsl_rng_uniform(rng));
        factored_init(&f, p, m, n);
        memcpy(f.lu.order, orders + o * m, m * sizeof *orders);
        if (sdae__sparse_lu_choose(&f.lu, p, scaled) == SDAE_OK) {
          ck_assert_uint_le(f.lu.l_start[m], most);
          fits++;
        }
        free(f.mem);
      }
      ck_assert_uint_gt(fits + (o != SDAE_SPARSE_LU_DISSECTION), 0); /* dissection fits all */
    }
    free(work), free(scaled), free(orders);
    if (c < TRUSSES)
      truss_g_free(&g);
    else
      rope_g_free(&r);
  }
  gsl_rng_free(rng);
}
END_TEST

int main(void) {
  Suite *s = suite_create("sparse_lu");
  ADD_CASE(s, l_stays_within_its_bound);
  ADD_CASE(s, the_bound_on_l_is_the_cholesky_factors_count);
  ADD_CASE(s, a_closed_rope_in_straight_runs_opens_its_loop);
  ADD_CASE(s, a_single_row_and_its_norm);
  ADD_CASE(s, rope_charts_solve_as_dense_algebra);
  ADD_CASE(s, random_wide_matrices_solve_as_dense_algebra);
  ADD_CASE(s, dependent_rows_are_rank);
  ADD_CASE(s, refactor_keeps_the_pivots);
  ADD_CASE(s, a_rope_of_4096_links_factors_in_its_nonzeros);
  ADD_CASE(s, every_order_takes_each_row_once);
  ADD_CASE(s, the_best_order_keeps_a_chart_within_the_factor_of_each);
  ADD_CASE(s, a_long_row_of_loops_fits_by_dissection);
  ADD_CASE(s, u_takes_the_room_l_leaves);
  return run_suite(s);
}
