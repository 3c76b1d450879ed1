/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The saddle-point factorization of sparse mechanisms (core/sparse_ldl.c: SuiteSparse's AMD
 * and LDL) against dense linear algebra and the mathematics: K x = b solved as GSL's dense LU
 * solves it and backward stable, the coordinates ordered before the multipliers, a mass not
 * positive definite and dependent constraints refused by the pivots' signs, and L's size that
 * of the elimination: a coordinate that every constraint holds (a cart under k pendulums)
 * couples all k multipliers, k (k - 1) / 2 entries of fill, unless it is a hub taken after
 * them; a coordinate with no mass of its own taken after them too. */
#include <float.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sparse_ldl.h"
#include "testmodels.h"

/* K = [M G^T; G 0] in compressed rows, its dense copy, and its factorization's block */
typedef struct saddle {
  size_t n_q, n_c, n, nnz;
  size_t *row_start, *col;
  double *values, *dense;
  sdae_sparse_ldl_symbolic sym;
  sdae_sparse_ldl f;
  void *mem, *factors;
} saddle;

/* entry (i, j) of K appended to row i (the rows written in order, columns ascending) */
static void put(saddle *k, size_t i, size_t j, double v) {
  k->col[k->nnz] = j, k->values[k->nnz++] = v;
  k->dense[i * k->n + j] = v;
  k->row_start[i + 1] = k->nnz;
}

/* K from dense M (n_q x n_q) and G (n_c x n_q), their zeros left out of the pattern */
static void saddle_init(saddle *k, size_t n_q, size_t n_c, const double *M, const double *G) {
  size_t n = n_q + n_c;
  *k = (saddle){.n_q = n_q, .n_c = n_c, .n = n};
  k->row_start = calloc(n + 1, sizeof *k->row_start);
  k->col = malloc(n * n * sizeof *k->col);
  k->values = malloc(n * n * sizeof *k->values);
  k->dense = calloc(n * n, sizeof *k->dense);
  for (size_t i = 0; i < n; i++) {
    k->row_start[i + 1] = k->nnz;
    for (size_t j = 0; j < n; j++) {
      double v = i < n_q ? (j < n_q ? M[i * n_q + j] : G[(j - n_q) * n_q + i])
                         : (j < n_q ? G[(i - n_q) * n_q + j] : 0.0);
      if (v != 0.0) put(k, i, j, v);
    }
  }
}

/* the analysis of K's pattern in a block of the test's (its workspace apart), then the
 * factorization's arrays, as many entries of L as it counted, in another */
static void saddle_analyse(saddle *k) {
  sdae_arena a = {0};
  sdae__sparse_ldl_symbolic_carve(&k->sym, k->n, k->n_q, k->nnz, &a);
  ck_assert(!a.overflow);
  k->mem = calloc(1, a.used + 64);
  a = (sdae_arena){.base = k->mem};
  sdae__sparse_ldl_symbolic_carve(&k->sym, k->n, k->n_q, k->nnz, &a);
  SuiteSparse_long *work = malloc(sdae__sparse_ldl_work_len(k->n, k->nnz) * sizeof *work);
  for (size_t i = 0; i <= k->n; i++) k->sym.Ap[i] = (SuiteSparse_long)k->row_start[i];
  for (size_t e = 0; e < k->nnz; e++) k->sym.Ai[e] = (SuiteSparse_long)k->col[e];
  sdae__sparse_ldl_analyse(&k->sym, work);
  free(work);
  ck_assert_uint_le(k->sym.lnz, k->n * (k->n - 1) / 2); /* L strictly lower */
  a = (sdae_arena){0};
  sdae__sparse_ldl_carve(&k->f, &k->sym, &a);
  ck_assert(!a.overflow);
  k->factors = calloc(1, a.used + 64);
  a = (sdae_arena){.base = k->factors};
  sdae__sparse_ldl_carve(&k->f, &k->sym, &a);
}

static void saddle_free(saddle *k) {
  free(k->row_start), free(k->col), free(k->values), free(k->dense);
  free(k->mem), free(k->factors);
}

/* a random sparse mechanism's M (banded, diagonally dominant: positive definite) and G (each
 * constraint on its own coordinate and two others near it, as joints couple neighbouring
 * bodies: full rank) */
static void random_mechanism(gsl_rng *rng, size_t n_q, size_t n_c, double *M, double *G) {
  memset(M, 0, n_q * n_q * sizeof *M);
  memset(G, 0, n_c * n_q * sizeof *G);
  for (size_t i = 0; i < n_q; i++) {
    M[i * n_q + i] = 3.0 + gsl_rng_uniform(rng);
    if (i + 1 < n_q) M[i * n_q + i + 1] = M[(i + 1) * n_q + i] = gsl_rng_uniform(rng) - 0.5;
  }
  for (size_t j = 0; j < n_c; j++) {
    G[j * n_q + j] = 2.0 + gsl_rng_uniform(rng);
    for (int e = 0; e < 2; e++) {
      size_t near = j + 1 + gsl_rng_uniform_int(rng, 6);
      G[j * n_q + (near < n_q ? near : j)] += gsl_rng_uniform(rng);
    }
  }
}

/* K factored and solved for a random b, against GSL's dense LU of the same K: x the same to
 * tol (1 + |x|) (K's dense copy is overwritten) */
static void solves_as_gsl(saddle *k, gsl_rng *rng, double tol) {
  size_t n = k->n;
  double *b = malloc(n * sizeof *b), *x = malloc(n * sizeof *x);
  ck_assert_int_eq(sdae__sparse_ldl_factor(&k->f, k->values), SDAE_OK);
  for (size_t i = 0; i < n; i++) b[i] = gsl_rng_uniform(rng) - 0.5;
  sdae__sparse_ldl_solve(&k->f, b, x);
  gsl_matrix_view K = gsl_matrix_view_array(k->dense, n, n);
  gsl_vector_view bv = gsl_vector_view_array(b, n);
  gsl_vector *xg = gsl_vector_alloc(n);
  gsl_permutation *perm = gsl_permutation_alloc(n);
  int sign;
  ck_assert_int_eq(gsl_linalg_LU_decomp(&K.matrix, perm, &sign), 0);
  ck_assert_int_eq(gsl_linalg_LU_solve(&K.matrix, perm, &bv.vector, xg), 0);
  ck_assert_double_le(max_abs_diff(x, xg->data, n), tol * (1.0 + gsl_blas_dnrm2(xg)));
  gsl_vector_free(xg), gsl_permutation_free(perm);
  free(b), free(x);
}

/* the status of K's factorization for dense M (n_q x n_q) and G (n_c x n_q), analysed first */
static int factor_status(size_t n_q, size_t n_c, const double *M, const double *G) {
  saddle k;
  int rc;
  saddle_init(&k, n_q, n_c, M, G);
  saddle_analyse(&k);
  rc = sdae__sparse_ldl_factor(&k.f, k.values);
  saddle_free(&k);
  return rc;
}

START_TEST(random_saddle_points_solve_as_dense_algebra) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  for (int trial = 0; trial < 40; trial++) {
    size_t n_q = 4 + gsl_rng_uniform_int(rng, 40), n_c = 1 + gsl_rng_uniform_int(rng, n_q - 1);
    size_t n = n_q + n_c;
    double *M = malloc(n_q * n_q * sizeof *M), *G = malloc(n_c * n_q * sizeof *G);
    double *b = malloc(n * sizeof *b), *x = malloc(n * sizeof *x), worst = 0.0, kx = 0.0;
    saddle k;
    random_mechanism(rng, n_q, n_c, M, G);
    saddle_init(&k, n_q, n_c, M, G);
    saddle_analyse(&k);
    for (size_t r = 0; r < n; r++) { /* the coordinates first: the order needing no pivoting */
      ck_assert_int_eq((size_t)k.sym.P[r] < n_q, r < n_q);
      ck_assert_int_eq(k.sym.Pinv[k.sym.P[r]], (long)r); /* and its inverse */
    }
    ck_assert_int_eq(sdae__sparse_ldl_factor(&k.f, k.values), SDAE_OK);
    for (size_t i = 0; i < n; i++) b[i] = gsl_rng_uniform(rng) - 0.5;
    sdae__sparse_ldl_solve(&k.f, b, x);
    /* backward stable: K x - b at the rounding of K x */
    for (size_t i = 0; i < n; i++) {
      double r = -b[i], s = 0.0;
      for (size_t j = 0; j < n; j++)
        r += k.dense[i * n + j] * x[j], s += fabs(k.dense[i * n + j] * x[j]);
      worst = fmax(worst, fabs(r)), kx = fmax(kx, s);
    }
    ck_assert_double_le(worst, 64.0 * (double)n * DBL_EPSILON * (kx + 1.0));
    /* and GSL's dense LU of the same K finds the same x */
    solves_as_gsl(&k, rng, 1e-10);
    free(M), free(G), free(b), free(x);
    saddle_free(&k);
  }
  gsl_rng_free(rng);
}
END_TEST

/* mechanisms whose constraints couple coordinates anywhere (each on its own coordinate and four
 * at random): AMD's elimination fills and uses the room it is given, which the order it returns
 * must not share. Analysed, each is a permutation with its inverse, and K x = b, in L's entries
 * as the analysis counts them, is solved as GSL's dense LU solves it */
START_TEST(coupled_anywhere_the_order_is_a_permutation) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  for (int trial = 0; trial < 60; trial++) {
    size_t n_q = 8 + gsl_rng_uniform_int(rng, 60),
           n_c = n_q / 2 + gsl_rng_uniform_int(rng, n_q / 2);
    size_t n = n_q + n_c;
    double *M = calloc(n_q * n_q, sizeof *M), *G = calloc(n_c * n_q, sizeof *G);
    saddle k;
    for (size_t i = 0; i < n_q; i++) M[i * n_q + i] = 1.0 + gsl_rng_uniform(rng);
    for (size_t j = 0; j < n_c; j++) {
      G[j * n_q + j] = 2.0 + gsl_rng_uniform(rng);
      for (int e = 0; e < 4; e++)
        G[j * n_q + gsl_rng_uniform_int(rng, n_q)] += gsl_rng_uniform(rng);
    }
    saddle_init(&k, n_q, n_c, M, G);
    saddle_analyse(&k);
    for (size_t r = 0; r < n; r++) {
      ck_assert(k.sym.P[r] >= 0 && (size_t)k.sym.P[r] < n);
      ck_assert_int_eq(k.sym.Pinv[k.sym.P[r]], (long)r);
    }
    solves_as_gsl(&k, rng, 1e-8);
    free(M), free(G);
    saddle_free(&k);
  }
  gsl_rng_free(rng);
}
END_TEST

/* a mass with a negative eigenvalue, a mass with a massless coordinate, and a constraint
 * repeated: the first two SDAE_ERR_MASS (a coordinate's pivot not positive), the third
 * SDAE_ERR_RANK (a multiplier's not negative) */
START_TEST(the_pivots_signs_refuse_what_has_no_solution) {
  double M[9] = {2, 0, 0, 0, 2, 0, 0, 0, 2}, G[6] = {1, 1, 0, 0, 1, 1};
  for (int which = 0; which < 3; which++) {
    double Mw[9], Gw[6];
    saddle k;
    memcpy(Mw, M, sizeof M), memcpy(Gw, G, sizeof G);
    if (which == 0) Mw[4] = -1.0;
    if (which == 1) Mw[8] = 1e-30 * DBL_EPSILON; /* at rounding, not zero */
    if (which == 2) memcpy(Gw + 3, Gw, 3 * sizeof *Gw);
    saddle_init(&k, 3, 2, Mw, Gw);
    saddle_analyse(&k);
    ck_assert_int_eq(sdae__sparse_ldl_factor(&k.f, k.values),
                     (which < 2 ? SDAE_ERR_MASS : SDAE_ERR_RANK));
    saddle_free(&k);
  }
}
END_TEST

/* the least pivot is n eps ||M||_inf, M's scale, not the entry's own nor G's: with M = diag(m0,
 * 1, 100) and one constraint on the first two coordinates, its coefficients 1e4 and 1 (n = 4:
 * 8.9e-14), m0 = 1e-14 is a mass at the rounding of M (SDAE_ERR_MASS) and m0 = 1e-12 is one
 * (SDAE_OK) */
START_TEST(the_least_pivot_is_at_the_rounding_of_the_mass) {
  for (int heavy = 0; heavy < 2; heavy++) {
    double M[9] = {heavy ? 1e-12 : 1e-14, 0, 0, 0, 1, 0, 0, 0, 100}, G[3] = {1e4, 1, 0};
    ck_assert_int_eq(factor_status(3, 1, M, G), heavy ? SDAE_OK : SDAE_ERR_MASS);
  }
}
END_TEST

/* the same at a small scale, ||M||_inf = 1e-3: m0 = 1e-19 under n eps ||M|| = 8.9e-19
 * (SDAE_ERR_MASS), 1e-17 above it; and two constraints [1, 1, 0], [1, 1, delta] with M = 1e-3 I,
 * whose Schur complement's second pivot is 1e3 delta^2, against n eps ||G_2||^2 / ||M|| =
 * 2.2e-12: delta = 1e-6 (1e-9) independent, delta = 1e-8 (1e-13) dependent to rounding
 * (SDAE_ERR_RANK) */
START_TEST(the_least_pivots_scale_with_m_and_g) {
  for (int heavy = 0; heavy < 2; heavy++) {
    double M[9] = {heavy ? 1e-17 : 1e-19, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3}, G[3] = {1e-3, 1e-3, 0};
    ck_assert_int_eq(factor_status(3, 1, M, G), heavy ? SDAE_OK : SDAE_ERR_MASS);
  }
  for (int apart = 0; apart < 2; apart++) {
    double M[9] = {1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3}, G[6] = {1, 1, 0, 1, 1, apart ? 1e-6 : 1e-8};
    ck_assert_int_eq(factor_status(3, 2, M, G), apart ? SDAE_OK : SDAE_ERR_RANK);
  }
}
END_TEST

/* a cart (coordinate 0) under k pendulums, constraint j on the cart and pendulum j's two
 * coordinates, M diagonal: eliminating the coordinates leaves G M^-1 G^T, whose every pair of
 * constraints shares the cart: L holds G's entries and k (k - 1) / 2 of fill, and no more */
static void cart(size_t k, saddle *s) {
  size_t n_q = 1 + 2 * k;
  double *M = calloc(n_q * n_q, sizeof *M), *G = calloc(k * n_q, sizeof *G);
  for (size_t i = 0; i < n_q; i++) M[i * n_q + i] = 1.0 + (double)i;
  for (size_t j = 0; j < k; j++) {
    G[j * n_q] = 1.0;
    G[j * n_q + 1 + 2 * j] = 0.5 + (double)j;
    G[j * n_q + 2 + 2 * j] = -1.0;
  }
  saddle_init(s, n_q, k, M, G);
  free(M), free(G);
}

/* up to SDAE_SPARSE_LDL_HUB constraints, the cart is taken with the coordinates: L holds G's
 * 3 k entries and the k (k - 1) / 2 of fill; one more and it is a hub, taken after the
 * multipliers: 3 k entries and no fill at k = 100 too (4950 of fill the other way); each
 * solves K x = b as GSL's dense LU does */
START_TEST(a_shared_coordinate_fills_only_below_the_hub_bound) {
  const size_t ks[] = {SDAE_SPARSE_LDL_HUB, SDAE_SPARSE_LDL_HUB + 1, 100};
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  for (size_t i = 0; i < 3; i++) {
    size_t k = ks[i], fill = k <= SDAE_SPARSE_LDL_HUB ? k * (k - 1) / 2 : 0;
    saddle s;
    cart(k, &s);
    saddle_analyse(&s);
    ck_assert_int_eq(s.sym.Lp[s.n], (long)(3 * k + fill));
    solves_as_gsl(&s, rng, 1e-12);
    saddle_free(&s);
  }
  gsl_rng_free(rng);
}
END_TEST

/* a coordinate with no mass of its own (M's pattern without its diagonal entry), held to the
 * first by a constraint, on a particle on the unit circle: M = diag(1, 1, 0) semidefinite, the
 * reduced mass 1 > 0; taken after the multipliers, its pivot is the Schur complement's, and K
 * x = b is solved as GSL's dense LU does; the massless coordinate is refused (SDAE_ERR_MASS)
 * only when no constraint holds it (K singular) */
START_TEST(a_massless_coordinate_is_taken_after_the_multipliers) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  for (int held = 0; held < 2; held++) {
    double M[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0}, G[6] = {0.6, -0.8, 0, -1, 0, held ? 1 : 0};
    saddle s;
    if (!held) G[3] = 0, G[4] = 1; /* the second constraint on y: the massless s free */
    saddle_init(&s, 3, 2, M, G);
    saddle_analyse(&s);
    if (held)
      solves_as_gsl(&s, rng, 1e-12);
    else
      ck_assert_int_eq(sdae__sparse_ldl_factor(&s.f, s.values), SDAE_ERR_MASS);
    saddle_free(&s);
  }
  gsl_rng_free(rng);
}
END_TEST

/* L's entries reach n^2 / 2 (a cart under n - 1 pendulums): a size fits only where that count
 * fits SuiteSparse_long, 2^31 - 1 for a 32-bit long (32-bit targets), 2^63 - 1 for 64 bits */
START_TEST(a_size_fits_only_where_its_counts_fit_the_index) {
  const double most = ldexp(1.0, 8 * (int)sizeof(SuiteSparse_long) - 1); /* the index's range */
  const size_t n[] = {1000, 60000, 70000, 100000};
  for (size_t i = 0; i < sizeof n / sizeof n[0]; i++) {
    int counts_fit = 0.5 * (double)n[i] * (double)n[i] < most;
    ck_assert_int_eq(sdae__sparse_ldl_fits(n[i], 3 * n[i]), counts_fit);
  }
}
END_TEST

/* Two coordinates of no mass of their own, s held to x and u to y, on a particle on the unit
 * circle: q = (x, y, s, u), M = diag(1, 1, 0, 0), the reduced mass 1. Each massless coordinate
 * needs its constraint eliminated before it: the constraints that hold one are matched first
 * (x to s - x, y to u - y), the circle's left for the end. Matched in their order instead, the
 * circle took x, s - x was left, and s's pivot was exactly 0 (SDAE_ERR_MASS, from a review). */
START_TEST(massless_coordinates_have_their_constraints_first) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  double M[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  double G[12] = {0.6, -0.8, 0, 0, -1, 0, 1, 0, 0, -1, 0, 1};
  saddle s;
  saddle_init(&s, 4, 3, M, G);
  saddle_analyse(&s);
  solves_as_gsl(&s, rng, 1e-12);
  saddle_free(&s);
  gsl_rng_free(rng);
}
END_TEST

int main(void) {
  Suite *s = suite_create("sparse_ldl");
  ADD_CASE(s, random_saddle_points_solve_as_dense_algebra);
  ADD_CASE(s, coupled_anywhere_the_order_is_a_permutation);
  ADD_CASE(s, the_pivots_signs_refuse_what_has_no_solution);
  ADD_CASE(s, the_least_pivot_is_at_the_rounding_of_the_mass);
  ADD_CASE(s, the_least_pivots_scale_with_m_and_g);
  ADD_CASE(s, a_shared_coordinate_fills_only_below_the_hub_bound);
  ADD_CASE(s, a_massless_coordinate_is_taken_after_the_multipliers);
  ADD_CASE(s, massless_coordinates_have_their_constraints_first);
  ADD_CASE(s, a_size_fits_only_where_its_counts_fit_the_index);
  return run_suite(s);
}
