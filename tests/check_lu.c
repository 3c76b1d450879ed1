/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The small dense LU of Newton (n <= SDAE_SMALL_DENSE) against GSL's banded LU on the same
 * matrices: the same solution to rounding, pivoting where the first pivot is zero, and the same
 * singularity verdicts. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_rng.h>

#include "core/arena.h"
#include "core/lu.h"
#include "maps/map.h"
#include "stepper/stepper.h"
#include "testmodels.h"

enum { NMAX = SDAE_SMALL_DENSE };

/* x = A^-1 b through GSL's banded LU with the band lb = ub = n - 1 */
static int gsl_solve(const double *A, size_t n, const double *b, double *x) {
  double AB[NMAX * (4 * NMAX)];
  unsigned piv[NMAX];
  sdae__lu_pack(A, n, n - 1, n - 1, AB);
  return sdae__lu_solve(AB, piv, n, n - 1, n - 1, b, x);
}

static int small_solve(const double *A, size_t n, const double *b, double *x) {
  double LU[NMAX * NMAX];
  unsigned piv[NMAX];
  memcpy(LU, A, n * n * sizeof *A);
  int rc = sdae__lu_small_factor(LU, piv, n);
  if (rc == SDAE_OK) sdae__lu_small_solve(LU, piv, n, b, x);
  return rc;
}

/* A x = b holds to rounding: ||A x - b|| <= 64 n eps ||A|| ||x|| */
static void check_residual(const double *A, size_t n, const double *b, const double *x) {
  double An = 0.0, xn = 0.0, r = 0.0;
  for (size_t i = 0; i < n; i++) {
    double acc = -b[i];
    for (size_t j = 0; j < n; j++) acc += A[i * n + j] * x[j], An = fmax(An, fabs(A[i * n + j]));
    r = fmax(r, fabs(acc));
    xn = fmax(xn, fabs(x[i]));
  }
  ck_assert_double_le(r, 64.0 * (double)n * 2.2e-16 * An * xn);
}

START_TEST(same_solution_as_gsl) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  for (size_t n = 1; n <= NMAX; n++)
    for (int trial = 0; trial < 200; trial++) {
      double A[NMAX * NMAX], b[NMAX], x[NMAX], y[NMAX];
      for (size_t i = 0; i < n * n; i++) A[i] = 2.0 * gsl_rng_uniform(rng) - 1.0;
      for (size_t i = 0; i < n; i++) b[i] = 2.0 * gsl_rng_uniform(rng) - 1.0;
      if (trial % 4 == 0) A[0] = 0.0; /* the first pivot must come from another row */
      int rs = small_solve(A, n, b, x), rg = gsl_solve(A, n, b, y);
      ck_assert_int_eq(rs, rg);
      if (rs != SDAE_OK) continue;
      check_residual(A, n, b, x);
      for (size_t i = 0; i < n; i++)
        ck_assert_double_le(fabs(x[i] - y[i]), 1e-9 * (1.0 + fabs(y[i])));
    }
  gsl_rng_free(rng);
}
END_TEST

START_TEST(singular_is_reported) {
  /* rank 1, a zero matrix, and a NaN: refused by both, without a division by zero */
  const double rank1[9] = {1, 2, 3, 2, 4, 6, -1, -2, -3}, zero[4] = {0}, nan[4] = {1, NAN, 0, 1};
  const double b[3] = {1, 1, 1};
  double x[3];
  ck_assert_int_eq(small_solve(rank1, 3, b, x), SDAE_ERR_SINGULAR);
  ck_assert_int_eq(gsl_solve(rank1, 3, b, x), SDAE_ERR_SINGULAR);
  ck_assert_int_eq(small_solve(zero, 2, b, x), SDAE_ERR_SINGULAR);
  ck_assert_int_eq(small_solve(nan, 2, b, x), SDAE_ERR_SINGULAR);
}
END_TEST

START_TEST(permutation_case_exact) {
  /* [[0, 1], [1, 0]] x = (3, 5): x = (5, 3) exactly, through one row swap */
  const double A[4] = {0, 1, 1, 0}, b[2] = {3, 5};
  double x[2];
  ck_assert_int_eq(small_solve(A, 2, b, x), SDAE_OK);
  ck_assert_double_eq(x[0], 5.0);
  ck_assert_double_eq(x[1], 3.0);
}
END_TEST

/* Partial pivoting takes the largest entry of the column, not the last one above the
 * diagonal: A = [[1, 0, 0], [4, 1, 0], [3, 0, 1]]. Step 1 takes row 1 (4), leaving rows
 * (0, -1/4, 0) and (0, -3/4, 1); step 2 takes the second of them (3/4 > 1/4): the factors' rows
 * are A's rows 1, 2, 0, and U = [[4, 1, 0], [0, -3/4, 1], [0, 0, -1/3]] (exact but for the
 * last entry, 0 - (1/3) 1, one rounding). */
START_TEST(pivot_is_the_largest_of_the_column) {
  double A[9] = {1, 0, 0, 4, 1, 0, 3, 0, 1};
  unsigned piv[3];
  ck_assert_int_eq(sdae__lu_small_factor(A, piv, 3), SDAE_OK);
  ck_assert_uint_eq(piv[0], 1);
  ck_assert_uint_eq(piv[1], 2);
  ck_assert_uint_eq(piv[2], 0);
  ck_assert_double_eq(A[0], 0.25); /* U's diagonal is kept as its reciprocal */
  ck_assert_double_eq(A[4], -4.0 / 3.0);
  ck_assert_double_eq_tol(A[8], -3.0, 4 * DBL_EPSILON);
}
END_TEST

START_TEST(four_cycle_exact) {
  /* row i of A is row (i + 1) mod 4 of I: A x = b gives x[(i + 1) % 4] = b[i] exactly, through
   * three row swaps composed into one permutation */
  double A[16] = {0}, b[4] = {3, 5, 7, 11}, x[4];
  for (int i = 0; i < 4; i++) A[i * 4 + (i + 1) % 4] = 1.0;
  ck_assert_int_eq(small_solve(A, 4, b, x), SDAE_OK);
  for (int i = 0; i < 4; i++) ck_assert_double_eq(x[(i + 1) % 4], b[i]);
}
END_TEST

START_TEST(larger_than_small_is_refused) {
  double A[25] = {0};
  unsigned piv[5];
  for (int i = 0; i < 5; i++) A[i * 5 + i] = 1.0;
  ck_assert_int_eq(sdae__lu_small_factor(A, piv, 5), SDAE_ERR_DIM);
}
END_TEST

/* Badly scaled: A = [[1, 1], [s, 0]], det = -s, normwise condition number about s. Partial
 * pivoting gives U = [[s, 0], [0, 1]] with every operation exact. The singularity test is
 * normwise (a pivot below n eps max|a_ij| is zero to working precision: A is then within a
 * relative perturbation n eps of a singular matrix), so A is solved exactly, x = (1, 1) from
 * b = (2, s), while s < 1/(2 eps) = 2.3e15, and refused beyond, on both paths alike. On a target
 * with a fused multiply-add GSL as built for it may fuse (Debian's arm64 build does): one
 * rounding where two cancel here, 1 - 2^-53 at 1e15, so its path is held to one unit in the last
 * place there; the library's own is exact everywhere (it fuses nothing, -ffp-contract=off). */
#ifdef __FP_FAST_FMA
#define GSL_FUSED_ULP DBL_EPSILON
#else
#define GSL_FUSED_ULP 0.0
#endif
START_TEST(badly_scaled_solves_exactly) {
  const double s[4] = {1e10, 1e15, 1e16, 1e20};
  const int solved[4] = {1, 1, 0, 0};
  for (int k = 0; k < 4; k++) {
    const double A[4] = {1, 1, s[k], 0}, b[2] = {2, s[k]};
    double x[2] = {0, 0}, y[2] = {0, 0};
    int want = solved[k] ? SDAE_OK : SDAE_ERR_SINGULAR;
    ck_assert_int_eq(small_solve(A, 2, b, x), want);
    ck_assert_int_eq(gsl_solve(A, 2, b, y), want);
    for (int i = 0; i < 2 && solved[k]; i++) {
      ck_assert_double_eq(x[i], 1.0);
      ck_assert_double_le(fabs(y[i] - 1.0), GSL_FUSED_ULP);
    }
  }
}
END_TEST

/* [1e-310]: a subnormal pivot. The small LU keeps U's diagonal as its reciprocal, and
 * 1/1e-310 overflows (DBL_MAX is 1.8e308): by its DBL_MIN rule it is singular. GSL's path
 * divides instead, so there the matrix is what it is, invertible: x = b / a, one rounding
 * (about 1e10: the stored subnormal 1e-310 carries only 44 bits). */
START_TEST(subnormal_pivot) {
  const double A[1] = {1e-310}, b[1] = {1e-300};
  double x[1] = {0};
  ck_assert_int_eq(small_solve(A, 1, b, x), SDAE_ERR_SINGULAR);
  ck_assert_int_eq(gsl_solve(A, 1, b, x), SDAE_OK);
  ck_assert_double_eq(x[0], b[0] / A[0]);
}
END_TEST

/* Singular to rounding: A = s u v^T formed in floating point, u, v without exact binary
 * digits, so elimination leaves pivots of rounding size (about eps |A|), not exact zeros;
 * the test |u_kk| > n eps max|a_ij| must refuse them at every scale s, on both paths. */
START_TEST(rank_one_to_rounding_is_singular) {
  const double u[4] = {0.1, 0.7, 0.3, 0.9}, v[4] = {0.3, 0.9, 0.7, 0.1};
  const double scale[3] = {1e-150, 1.0, 1e150};
  const double b[4] = {1, 1, 1, 1};
  for (size_t n = 2; n <= NMAX; n++)
    for (int k = 0; k < 3; k++) {
      double A[NMAX * NMAX], x[NMAX];
      for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j < n; j++) A[i * n + j] = scale[k] * u[i] * v[j];
      ck_assert_int_eq(small_solve(A, n, b, x), SDAE_ERR_SINGULAR);
      ck_assert_int_eq(gsl_solve(A, n, b, x), SDAE_ERR_SINGULAR);
    }
}
END_TEST

/* The band path with a real band (lb = ub = 1 on n = 6): a tridiagonal matrix whose rows 2
 * and 3 (from 0) are equal to rounding (0.1 + 0.2 and 0.3) is refused; the same with row 3 made
 * [.., 2, 5, 1, ..] solves, to the residual bound of backward-stable LU. */
START_TEST(banded_singular_to_rounding) {
  enum { N = 6 };
  double A[N * N] = {0}, AB[N * 4], b[N] = {1, 2, 3, 4, 5, 6}, x[N];
  unsigned piv[N];
  for (int i = 0; i < N; i++) {
    A[i * N + i] = 4.0;
    if (i > 0) A[i * N + i - 1] = 1.0;
    if (i + 1 < N) A[i * N + i + 1] = 1.0;
  }
  /* rows 2 and 3 restricted to columns 2, 3: [a, c; a, c] up to rounding, zero elsewhere */
  A[2 * N + 1] = 0.0, A[2 * N + 2] = 0.1 + 0.2, A[2 * N + 3] = 0.7;
  A[3 * N + 2] = 0.3, A[3 * N + 3] = 0.7, A[3 * N + 4] = 0.0;
  sdae__lu_pack(A, N, 1, 1, AB);
  ck_assert_int_eq(sdae__lu_solve(AB, piv, N, 1, 1, b, x), SDAE_ERR_SINGULAR);
  A[3 * N + 2] = 2.0, A[3 * N + 3] = 5.0, A[3 * N + 4] = 1.0;
  sdae__lu_pack(A, N, 1, 1, AB);
  ck_assert_int_eq(sdae__lu_solve(AB, piv, N, 1, 1, b, x), SDAE_OK);
  check_residual(A, N, b, x);
}
END_TEST

/* Partial pivoting takes the first largest entry of the column: A = [[1, 2], [-1, 3]] has a
 * tie |1| = |-1| in its first column, so no row is swapped (piv = identity), l21 = -1 and
 * U = [[1, 2], [0, 3 + 2]], U's diagonal kept as its reciprocal: factors {1, 2, -1, 1/5},
 * each exact or one rounding of 1/5. Taking the last largest would swap the rows. */
START_TEST(pivot_tie_takes_first_row) {
  double A[4] = {1, 2, -1, 3};
  unsigned piv[2];
  ck_assert_int_eq(sdae__lu_small_factor(A, piv, 2), SDAE_OK);
  ck_assert_uint_eq(piv[0], 0);
  ck_assert_uint_eq(piv[1], 1);
  ck_assert_double_eq(A[0], 1.0);
  ck_assert_double_eq(A[1], 2.0);
  ck_assert_double_eq(A[2], -1.0);
  ck_assert_double_eq(A[3], 1.0 / 5.0);
}
END_TEST

/* The singularity test |u_kk| > n eps max|a_ij| at its boundary: diag(2^-51, 1) (n = 2, max 1)
 * has the pivot u_11 = 2^-51 = 2 eps exactly: singular, on both paths; with the pivot one ulp
 * above, invertible, solved to the residual bound. */
START_TEST(singularity_threshold_is_strict) {
  const double at = 2.0 * DBL_EPSILON, above = nextafter(at, 1.0), b[2] = {1, 1};
  const double A_at[4] = {at, 0, 0, 1}, A_above[4] = {above, 0, 0, 1};
  double x[2];
  ck_assert_double_eq(at, 0x1p-51);
  ck_assert_int_eq(small_solve(A_at, 2, b, x), SDAE_ERR_SINGULAR);
  ck_assert_int_eq(gsl_solve(A_at, 2, b, x), SDAE_ERR_SINGULAR);
  ck_assert_int_eq(small_solve(A_above, 2, b, x), SDAE_OK);
  check_residual(A_above, 2, b, x);
  ck_assert_int_eq(gsl_solve(A_above, 2, b, x), SDAE_OK);
  check_residual(A_above, 2, b, x);
}
END_TEST

/* The scale is the largest entry of the whole matrix, here its last one: diag(1e-16, 1),
 * pivot 1e-16 < 2 eps 1 = 4.4e-16, is singular to working precision on both paths (for n = 3
 * and 4 likewise, the 1 last on the diagonal). */
START_TEST(scale_includes_last_entry) {
  const double b[4] = {1, 1, 1, 1};
  for (size_t n = 2; n <= NMAX; n++) {
    double A[NMAX * NMAX] = {0}, x[NMAX];
    for (size_t i = 0; i + 1 < n; i++) A[i * n + i] = 1e-16;
    A[n * n - 1] = 1.0;
    ck_assert_int_eq(small_solve(A, n, b, x), SDAE_ERR_SINGULAR);
    ck_assert_int_eq(gsl_solve(A, n, b, x), SDAE_ERR_SINGULAR);
  }
}
END_TEST

/* The test is relative to the matrix's own scale, however small: t [[0, 1], [1, 0]] with
 * t = 2^-100 solves exactly, x = (5, 3) / t from b = (3, 5), on both paths (every operation
 * on powers of 2 is exact). */
START_TEST(tiny_matrix_is_not_singular) {
  const double t = 0x1p-100, A[4] = {0, t, t, 0}, b[2] = {3, 5};
  double x[2], y[2];
  ck_assert_int_eq(small_solve(A, 2, b, x), SDAE_OK);
  ck_assert_int_eq(gsl_solve(A, 2, b, y), SDAE_OK);
  ck_assert_double_eq(x[0], 5.0 * 0x1p100);
  ck_assert_double_eq(x[1], 3.0 * 0x1p100);
  ck_assert_double_eq(y[0], 5.0 * 0x1p100);
  ck_assert_double_eq(y[1], 3.0 * 0x1p100);
}
END_TEST

/* A singular matrix is refused before any solve: x is left as it was (no division by the
 * zero pivot inside GSL), for the zero matrix and a rank-1 one with exact zero pivots. */
START_TEST(singular_leaves_x_untouched) {
  const double zero[9] = {0}, rank1[9] = {1, 2, 4, 2, 4, 8, 4, 8, 16}, b[3] = {1, 1, 1};
  const double *As[2] = {zero, rank1};
  for (int k = 0; k < 2; k++) {
    double x[3] = {7.0, 7.0, 7.0};
    ck_assert_int_eq(gsl_solve(As[k], 3, b, x), SDAE_ERR_SINGULAR);
    for (int i = 0; i < 3; i++) ck_assert_double_eq(x[i], 7.0);
  }
}
END_TEST

/* ---- Cholesky of a symmetric positive definite matrix ---- */

enum { CMAX = 8 };

/* M = B^T D B + identity I (n x n, B m x n) as a user's code writes it, each entry its own sum:
 * the two triangles round differently, by up to about 2 (m + 1) eps max|M| */
static void gram(const double *B, const double *D, size_t m, size_t n, double identity, double *M) {
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) {
      double acc = i == j ? identity : 0.0;
      for (size_t k = 0; k < m; k++) acc += B[k * n + i] * D[k] * B[k * n + j];
      M[i * n + j] = acc;
    }
}

static double max_abs(const double *x, size_t n) {
  double m = 0.0;
  for (size_t i = 0; i < n; i++) m = fmax(m, fabs(x[i]));
  return m;
}

/* random B (m x n, entries in [-1, 1]) and D (log-uniform in [1e-2, 1e4]), seeded */
static void random_gram(gsl_rng *rng, size_t m, size_t n, double *M) {
  double B[8 * CMAX * CMAX], D[8 * CMAX];
  for (size_t i = 0; i < m * n; i++) B[i] = 2.0 * gsl_rng_uniform(rng) - 1.0;
  for (size_t k = 0; k < m; k++) D[k] = pow(10.0, -2.0 + 6.0 * gsl_rng_uniform(rng));
  gram(B, D, m, n, 1.0, M);
}

/* R diag(K, 1, 1) R^T, R the rotation by 0.7 about the axis (1, 2, 3) (Rodrigues' formula) */
static void rotated_diag(double K, double *M) {
  const double c = cos(0.7), s = sin(0.7), nrm = sqrt(14.0), D[3] = {K, 1.0, 1.0};
  const double u[3] = {1.0 / nrm, 2.0 / nrm, 3.0 / nrm};
  const double ux[9] = {0.0, -u[2], u[1], u[2], 0.0, -u[0], -u[1], u[0], 0.0};
  double Rt[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      Rt[j * 3 + i] = (i == j ? c : 0.0) + (1.0 - c) * u[i] * u[j] + s * ux[i * 3 + j];
  gram(Rt, D, 3, 3, 0.0, M);
}

/* Cholesky's factor solves M x = b backward stably: ||M x - b|| <= 64 n eps ||M|| ||x|| */
static void expect_cholesky_solves(const double *M, size_t n) {
  double LLT[CMAX * CMAX], b[CMAX], x[CMAX];
  memcpy(LLT, M, n * n * sizeof *M);
  ck_assert_int_eq(sdae__cholesky_factor(LLT, n), SDAE_OK);
  for (size_t i = 0; i < n; i++) b[i] = x[i] = 1.0 + (double)i;
  sdae__cholesky_solve(LLT, n, x);
  for (size_t i = 0; i < n; i++) {
    double acc = -b[i];
    for (size_t j = 0; j < n; j++) acc += M[i * n + j] * x[j];
    ck_assert_double_le(fabs(acc),
                        64.0 * (double)n * DBL_EPSILON * max_abs(M, n * n) * max_abs(x, n));
  }
}

/* Products that are symmetric positive definite in exact arithmetic, symmetric to their
 * rounding only: accepted, whatever their scale or conditioning (D up to 1e4, K up to 1e6),
 * with n terms per entry and with 8 n (a sum over many bodies). */
START_TEST(cholesky_takes_rounded_symmetric_products) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  double M[CMAX * CMAX];
  gsl_rng_set(rng, 20240611);
  for (size_t n = 2; n <= CMAX; n++)
    for (int trial = 0; trial < 500; trial++) {
      random_gram(rng, trial % 2 ? 8 * n : n, n, M);
      expect_cholesky_solves(M, n);
    }
  gsl_rng_free(rng);
  rotated_diag(100.0, M);
  expect_cholesky_solves(M, 3);
  rotated_diag(1e6, M);
  expect_cholesky_solves(M, 3);
}
END_TEST

/* the same products with one entry off by 1e-8 of the largest: no longer symmetric (a model's
 * error, far above any rounding), refused */
START_TEST(cholesky_refuses_asymmetry) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  double M[CMAX * CMAX];
  gsl_rng_set(rng, 20240611);
  for (size_t n = 4; n <= CMAX; n++)
    for (int trial = 0; trial < 50; trial++) {
      random_gram(rng, n, n, M);
      M[(n - 1) * n + 1] += 1e-8 * max_abs(M, n * n);
      ck_assert_int_eq(sdae__cholesky_factor(M, n), SDAE_ERR_MASS);
    }
  gsl_rng_free(rng);
  rotated_diag(1e6, M);
  M[1] += 1e-8 * 1e6;
  ck_assert_int_eq(sdae__cholesky_factor(M, 3), SDAE_ERR_MASS);
}
END_TEST

/* A mass positive but singular to rounding: Cholesky refuses a pivot at or below n eps times
 * the largest entry (the rounding its elimination leaves), and takes one above it. diag(1, d)
 * at n = 2: d = 1.5 eps is refused (a tolerance of zero would take it), d = 3 eps is taken (a
 * tolerance twice as large would refuse it); a rank-one u u^T of exact binary entries leaves
 * a pivot of exactly zero. */
START_TEST(cholesky_refuses_a_mass_singular_to_rounding) {
  double M[4];
  const double eps = DBL_EPSILON;
  double below[4] = {1.0, 0.0, 0.0, 1.5 * eps}, above[4] = {1.0, 0.0, 0.0, 3.0 * eps};
  double rank_one[9] = {1.0, 0.5, 2.0, 0.5, 0.25, 1.0, 2.0, 1.0, 4.0};
  memcpy(M, below, sizeof M);
  ck_assert_int_eq(sdae__cholesky_factor(M, 2), SDAE_ERR_MASS);
  memcpy(M, above, sizeof M);
  ck_assert_int_eq(sdae__cholesky_factor(M, 2), SDAE_OK);
  ck_assert_double_eq(M[3], sqrt(3.0 * eps));
  ck_assert_int_eq(sdae__cholesky_factor(rank_one, 3), SDAE_ERR_MASS);
}
END_TEST

int main(void) {
  Suite *s = suite_create("lu");
  ADD_CASE(s, same_solution_as_gsl);
  ADD_CASE(s, singular_is_reported);
  ADD_CASE(s, permutation_case_exact);
  ADD_CASE(s, pivot_is_the_largest_of_the_column);
  ADD_CASE(s, four_cycle_exact);
  ADD_CASE(s, larger_than_small_is_refused);
  ADD_CASE(s, badly_scaled_solves_exactly);
  ADD_CASE(s, subnormal_pivot);
  ADD_CASE(s, rank_one_to_rounding_is_singular);
  ADD_CASE(s, banded_singular_to_rounding);
  ADD_CASE(s, pivot_tie_takes_first_row);
  ADD_CASE(s, singularity_threshold_is_strict);
  ADD_CASE(s, scale_includes_last_entry);
  ADD_CASE(s, tiny_matrix_is_not_singular);
  ADD_CASE(s, singular_leaves_x_untouched);
  ADD_CASE(s, cholesky_takes_rounded_symmetric_products);
  ADD_CASE(s, cholesky_refuses_asymmetry);
  ADD_CASE(s, cholesky_refuses_a_mass_singular_to_rounding);
  return run_suite(s);
}
