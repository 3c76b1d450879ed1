/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Linear solves for Newton and the Baumgarte baseline: LU with partial pivoting through GSL's
 * banded LU, a dense matrix being the band lb = ub = n - 1; Newton's small dense matrices
 * (n <= SDAE_SMALL_DENSE) by the same elimination, written out here. The banded routines work
 * entirely in the caller's memory (gsl_linalg_LU_decomp allocates its pivots on every call), and
 * the pivots are checked here before the solve, so a singular matrix is a status, never a
 * division by zero inside GSL. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_linalg.h>

#include <stabdae/stabdae.h>

#include "lu.h"

size_t sdae__lu_band_cols(size_t lb, size_t ub) { return 2 * lb + ub + 1; }

/* GSL's band format: row j holds column j of A, AB[j][lb + ub + i - j] = A[i][j]; the cells
 * outside A (first and last rows) are zeroed, since the pivot scale reads the whole band. */
void sdae__lu_pack(const double *A, size_t n, size_t lb, size_t ub, double *AB) {
  size_t ld = sdae__lu_band_cols(lb, ub);
  memset(AB, 0, n * ld * sizeof *AB);
  for (size_t j = 0; j < n; j++) {
    size_t i0 = j > ub ? j - ub : 0, i1 = j + lb < n ? j + lb : n - 1;
    for (size_t i = i0; i <= i1; i++) AB[j * ld + lb + ub + i - j] = A[i * n + j];
  }
}

/* The largest |entry| of the band: the scale of the singularity test, which is normwise. A pivot
 * |u_kk| <= n eps max|a_ij| is zero to working precision: A is then within a relative
 * perturbation of n eps of a singular matrix (its condition number is above about 1/(n eps)),
 * however its rows are scaled. Written out rather than with fmax, which the compiler must call
 * (NaN rules); NaN entries are skipped as fmax does. */
static double band_scale(const double *AB, size_t n, size_t lb, size_t ld) {
  double scale = 0.0;
  for (size_t j = 0; j < n; j++)
    for (size_t c = lb; c < ld; c++) {
      double a = fabs(AB[j * ld + c]);
      scale = a > scale ? a : scale;
    }
  return scale;
}

int sdae__lu_factor(double *AB, unsigned *piv, size_t n, size_t lb, size_t ub) {
  size_t ld = sdae__lu_band_cols(lb, ub);
  gsl_matrix_view M = gsl_matrix_view_array(AB, n, ld);
  gsl_vector_uint_view P = gsl_vector_uint_view_array(piv, n);
  double scale = band_scale(AB, n, lb, ld);
  gsl_linalg_LU_band_decomp(n, lb, ub, &M.matrix, &P.vector);
  /* U's diagonal sits in column lb + ub; NaN (after a zero pivot) fails the test too */
  for (size_t j = 0; j < n; j++)
    if (!(fabs(AB[j * ld + lb + ub]) > (double)n * DBL_EPSILON * scale)) return SDAE_ERR_SINGULAR;
  return SDAE_OK;
}

void sdae__lu_factored_solve(const double *AB, const unsigned *piv, size_t n, size_t lb, size_t ub,
                             const double *b, double *x) {
  size_t ld = sdae__lu_band_cols(lb, ub);
  gsl_matrix_const_view M = gsl_matrix_const_view_array(AB, n, ld);
  gsl_vector_uint_const_view P = gsl_vector_uint_const_view_array(piv, n);
  gsl_vector_const_view B = gsl_vector_const_view_array(b, n);
  gsl_vector_view X = gsl_vector_view_array(x, n);
  gsl_linalg_LU_band_solve(lb, ub, &M.matrix, &P.vector, &B.vector, &X.vector);
}

int sdae__lu_solve(double *AB, unsigned *piv, size_t n, size_t lb, size_t ub, const double *b,
                   double *x) {
  int rc = sdae__lu_factor(AB, piv, n, lb, ub);
  if (rc == SDAE_OK) sdae__lu_factored_solve(AB, piv, n, lb, ub, b, x);
  return rc;
}

/* ---- small dense systems --------------------------------------------------------------------
 * Gaussian elimination with partial pivoting in place on the row-major matrix: unit-lower L
 * below the diagonal, U on and above, as LAPACK's getrf, but with
 *  - U's diagonal kept as its reciprocal: the solves, two per factorization in Newton, then
 *    multiply, and a division's latency is off their critical path;
 *  - the pivoting kept as the permutation itself: row i of the factors is row piv[i] of A, so
 *    the solve gathers b once and works in a local array, in registers once n is a constant (in
 *    x itself each substitution waited on the store of the one before);
 * with the band solve's singularity test, and a pivot below DBL_MIN (whose reciprocal would
 * overflow) counted singular too. GSL's elimination, up to the rounding of those reciprocals,
 * without its views, scaling and BLAS calls, which dominate a 2 x 2 solve (docs/performance.md). */

static void swap_rows(double *A, unsigned *piv, size_t n, size_t k, size_t p) {
  unsigned r = piv[k];
  piv[k] = piv[p];
  piv[p] = r;
  for (size_t j = 0; j < n; j++) {
    double tmp = A[k * n + j];
    A[k * n + j] = A[p * n + j];
    A[p * n + j] = tmp;
  }
}

static int small_factor(double *A, unsigned *piv, size_t n) {
  double scale = 0.0;
  for (size_t i = 0; i < n * n; i++) scale = fabs(A[i]) > scale ? fabs(A[i]) : scale;
  for (size_t i = 0; i < n; i++) piv[i] = (unsigned)i;
  for (size_t k = 0; k < n; k++) {
    size_t p = k;
    for (size_t i = k + 1; i < n; i++)
      if (fabs(A[i * n + k]) > fabs(A[p * n + k])) p = i;
    if (!(fabs(A[p * n + k]) > (double)n * DBL_EPSILON * scale) || fabs(A[p * n + k]) < DBL_MIN)
      return SDAE_ERR_SINGULAR;
    if (p != k) swap_rows(A, piv, n, k, p);
    A[k * n + k] = 1.0 / A[k * n + k];
    for (size_t i = k + 1; i < n; i++) {
      double l = A[i * n + k] *= A[k * n + k];
      for (size_t j = k + 1; j < n; j++) A[i * n + j] -= l * A[k * n + j];
    }
  }
  return SDAE_OK;
}

static void small_solve(const double *LU, const unsigned *piv, size_t n, const double *b,
                        double *x) {
  double w[SDAE_SMALL_DENSE];
  for (size_t i = 0; i < n; i++) w[i] = b[piv[i]];
  for (size_t i = 1; i < n; i++) /* L y = P b */
    for (size_t j = 0; j < i; j++) w[i] -= LU[i * n + j] * w[j];
  for (size_t i = n; i-- > 0;) { /* U x = y */
    for (size_t j = i + 1; j < n; j++) w[i] -= LU[i * n + j] * w[j];
    w[i] *= LU[i * n + i];
  }
  for (size_t i = 0; i < n; i++) x[i] = w[i];
}

/* The entry points call the loops above with n a constant for each size, so that the compiler
 * compiles each size with its loops unrolled: for 2 x 2 the generic loops cost half again. */
int sdae__lu_small_factor(double *A, unsigned *piv, size_t n) {
  switch (n) {
  case 1: return small_factor(A, piv, 1);
  case 2: return small_factor(A, piv, 2);
  case 3: return small_factor(A, piv, 3);
  case 4: return small_factor(A, piv, 4);
  default: return SDAE_ERR_DIM; /* not a small system: the solve's array holds 4 */
  }
}

void sdae__lu_small_solve(const double *LU, const unsigned *piv, size_t n, const double *b,
                          double *x) {
  switch (n) {
  case 1: small_solve(LU, piv, 1, b, x); break;
  case 2: small_solve(LU, piv, 2, b, x); break;
  case 3: small_solve(LU, piv, 3, b, x); break;
  case 4: small_solve(LU, piv, 4, b, x); break;
  default: break; /* refused by the factorization */
  }
}

/* ---- symmetric positive definite systems ----------------------------------------------------
 * Cholesky's factorization, written out because GSL's reports a matrix that is not positive
 * definite through its error handler, which aborts by default, and the library must return a
 * status instead. The factor is laid out as gsl_linalg_cholesky_decomp1 leaves it (L below the
 * diagonal, L^T above). A is taken as not symmetric positive definite when its triangles differ
 * by more than rounding (below) or a pivot falls to n eps of its largest entry.
 *
 * The rounding of a symmetric product (B^T D B, R diag R^T, a sum over bodies of J^T M_b J)
 * formed entry by entry: each entry of m terms is off by at most m eps times the sum of the
 * terms' sizes, which is at most max|A| when the terms are positive semidefinite (Cauchy-Schwarz
 * bounds them by the diagonal), and the two triangles round independently: 2 m eps max|A|. The
 * test allows m = SYM_TERMS n terms per entry (a rigid body's six per coordinate and more),
 * 3.6e-15 n of max|A|: an asymmetry of 1e-8 of it, a model's error and not rounding, is still
 * refused up to n = 2.8e6. */
#define SYM_TERMS 8.0
static double max_entry(const double *A, size_t n) {
  double scale = 0.0;
  for (size_t i = 0; i < n * n; i++) scale = fabs(A[i]) > scale ? fabs(A[i]) : scale;
  return scale;
}

/* one pass: the largest asymmetry and the largest entry (a front-end checks M at every state a
 * step starts from or hands out) */
int sdae__symmetric(const double *A, size_t n) {
  double asym = 0.0, big = 0.0;
  for (size_t i = 0; i < n; i++) {
    big = fabs(A[i * n + i]) > big ? fabs(A[i * n + i]) : big;
    for (size_t j = 0; j < i; j++) {
      double a = fabs(A[i * n + j]), b = fabs(A[j * n + i]), d = fabs(A[i * n + j] - A[j * n + i]);
      big = a > big ? a : big;
      big = b > big ? b : big;
      asym = d > asym || d != d ? d : asym; /* a NaN is no symmetry */
    }
  }
  return asym <= 2.0 * SYM_TERMS * (double)n * DBL_EPSILON * big;
}

int sdae__cholesky_factor(double *A, size_t n) {
  double tol = (double)n * DBL_EPSILON * max_entry(A, n);
  if (!sdae__symmetric(A, n)) return SDAE_ERR_MASS;
  for (size_t j = 0; j < n; j++) {
    double d = A[j * n + j];
    for (size_t k = 0; k < j; k++) d -= A[j * n + k] * A[j * n + k];
    if (!(d > tol)) return SDAE_ERR_MASS;
    A[j * n + j] = d = sqrt(d);
    for (size_t i = j + 1; i < n; i++) {
      double l = A[i * n + j];
      for (size_t k = 0; k < j; k++) l -= A[i * n + k] * A[j * n + k];
      A[i * n + j] = A[j * n + i] = l / d;
    }
  }
  return SDAE_OK;
}

/* L y = x, then L^T x = y: the substitutions written out, as for the small LU, since the
 * front-end solves a 1 x 1 to 4 x 4 system several times per evaluation and GSL's views and
 * BLAS calls would cost more than the arithmetic */
void sdae__cholesky_solve(const double *LLT, size_t n, double *x) {
  for (size_t i = 0; i < n; i++) {
    for (size_t k = 0; k < i; k++) x[i] -= LLT[i * n + k] * x[k];
    x[i] /= LLT[i * n + i];
  }
  for (size_t i = n; i-- > 0;) {
    for (size_t k = i + 1; k < n; k++) x[i] -= LLT[k * n + i] * x[k];
    x[i] /= LLT[i * n + i];
  }
}
