/* Linear solves for Newton and the Baumgarte baseline: LU with partial pivoting through GSL's
 * banded LU, a dense matrix being the band lb = ub = n - 1. The banded routines work entirely in
 * the caller's memory (gsl_linalg_LU_decomp allocates its pivots on every call), and the pivots
 * are checked here before the solve, so a singular matrix is a status, never a division by
 * zero inside GSL. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_linalg.h>

#include "internal.h"

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

int sdae__lu_solve(double *AB, unsigned *piv, size_t n, size_t lb, size_t ub, const double *b,
                   double *x) {
  size_t ld = sdae__lu_band_cols(lb, ub);
  gsl_matrix_view M = gsl_matrix_view_array(AB, n, ld);
  gsl_vector_uint_view P = gsl_vector_uint_view_array(piv, n);
  gsl_vector_const_view B = gsl_vector_const_view_array(b, n);
  gsl_vector_view X = gsl_vector_view_array(x, n);
  double scale = 0.0;
  for (size_t j = 0; j < n; j++)
    for (size_t c = lb; c < ld; c++) scale = fmax(scale, fabs(AB[j * ld + c]));
  gsl_linalg_LU_band_decomp(n, lb, ub, &M.matrix, &P.vector);
  /* U's diagonal sits in column lb + ub; NaN (after a zero pivot) fails the test too */
  for (size_t j = 0; j < n; j++)
    if (!(fabs(AB[j * ld + lb + ub]) > (double)n * DBL_EPSILON * scale)) return SDAE_ERR_SINGULAR;
  gsl_linalg_LU_band_solve(lb, ub, &M.matrix, &P.vector, &B.vector, &X.vector);
  return SDAE_OK;
}
