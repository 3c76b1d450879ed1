/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A CBLAS that computes nothing right, for the test that an FMU's GSL calls the CBLAS inside
 * its binary and never a cblas_* the importer's process loaded before it (test_fmus.py,
 * test_cblas_bound_inside): each routine GSL's linear algebra reaches counts its call in
 * poison_calls and writes NaN where it should write its result. Loaded with RTLD_GLOBAL before
 * the FMU, it comes first in the process's symbol lookup. */
#include <math.h>
#include <stddef.h>

#include <gsl/gsl_cblas.h>

/* read by the test through ctypes: a test program may keep a counter */
long poison_calls;

static void spoil(double *x, size_t n, size_t inc) {
  poison_calls++;
  for (size_t i = 0; x && i < n; i++) x[i * (inc ? inc : 1)] = NAN;
}

static size_t count(int n) { return n > 0 ? (size_t)n : 0; }

double cblas_ddot(const int N, const double *X, const int incX, const double *Y, const int incY) {
  (void)N, (void)X, (void)incX, (void)Y, (void)incY;
  poison_calls++;
  return NAN;
}

double cblas_dnrm2(const int N, const double *X, const int incX) {
  (void)N, (void)X, (void)incX;
  poison_calls++;
  return NAN;
}

double cblas_dasum(const int N, const double *X, const int incX) {
  (void)N, (void)X, (void)incX;
  poison_calls++;
  return NAN;
}

CBLAS_INDEX cblas_idamax(const int N, const double *X, const int incX) {
  (void)N, (void)X, (void)incX;
  poison_calls++;
  return 0;
}

void cblas_dswap(const int N, double *X, const int incX, double *Y, const int incY) {
  spoil(X, count(N), (size_t)incX);
  spoil(Y, count(N), (size_t)incY);
}

void cblas_dcopy(const int N, const double *X, const int incX, double *Y, const int incY) {
  (void)X, (void)incX;
  spoil(Y, count(N), (size_t)incY);
}

void cblas_daxpy(const int N, const double alpha, const double *X, const int incX, double *Y,
                 const int incY) {
  (void)alpha, (void)X, (void)incX;
  spoil(Y, count(N), (size_t)incY);
}

void cblas_dscal(const int N, const double alpha, double *X, const int incX) {
  (void)alpha;
  spoil(X, count(N), (size_t)incX);
}

void cblas_drot(const int N, double *X, const int incX, double *Y, const int incY, const double c,
                const double s) {
  (void)c, (void)s;
  spoil(X, count(N), (size_t)incX);
  spoil(Y, count(N), (size_t)incY);
}

void cblas_dgemv(const enum CBLAS_ORDER order, const enum CBLAS_TRANSPOSE TransA, const int M,
                 const int N, const double alpha, const double *A, const int lda, const double *X,
                 const int incX, const double beta, double *Y, const int incY) {
  (void)order, (void)alpha, (void)A, (void)lda, (void)X, (void)incX, (void)beta;
  spoil(Y, count(TransA == CblasNoTrans ? M : N), (size_t)incY);
}

void cblas_dsymv(const enum CBLAS_ORDER order, const enum CBLAS_UPLO Uplo, const int N,
                 const double alpha, const double *A, const int lda, const double *X,
                 const int incX, const double beta, double *Y, const int incY) {
  (void)order, (void)Uplo, (void)alpha, (void)A, (void)lda, (void)X, (void)incX, (void)beta;
  spoil(Y, count(N), (size_t)incY);
}

void cblas_dtrmv(const enum CBLAS_ORDER order, const enum CBLAS_UPLO Uplo,
                 const enum CBLAS_TRANSPOSE TransA, const enum CBLAS_DIAG Diag, const int N,
                 const double *A, const int lda, double *X, const int incX) {
  (void)order, (void)Uplo, (void)TransA, (void)Diag, (void)A, (void)lda;
  spoil(X, count(N), (size_t)incX);
}

void cblas_dtrsv(const enum CBLAS_ORDER order, const enum CBLAS_UPLO Uplo,
                 const enum CBLAS_TRANSPOSE TransA, const enum CBLAS_DIAG Diag, const int N,
                 const double *A, const int lda, double *X, const int incX) {
  (void)order, (void)Uplo, (void)TransA, (void)Diag, (void)A, (void)lda;
  spoil(X, count(N), (size_t)incX);
}

void cblas_dger(const enum CBLAS_ORDER order, const int M, const int N, const double alpha,
                const double *X, const int incX, const double *Y, const int incY, double *A,
                const int lda) {
  (void)order, (void)alpha, (void)X, (void)incX, (void)Y, (void)incY, (void)lda;
  spoil(A, count(M) * count(N) > 0 ? 1 : 0, 1);
}

void cblas_dgemm(const enum CBLAS_ORDER Order, const enum CBLAS_TRANSPOSE TransA,
                 const enum CBLAS_TRANSPOSE TransB, const int M, const int N, const int K,
                 const double alpha, const double *A, const int lda, const double *B, const int ldb,
                 const double beta, double *C, const int ldc) {
  (void)Order, (void)TransA, (void)TransB, (void)K, (void)alpha, (void)A, (void)lda, (void)B,
      (void)ldb, (void)beta, (void)ldc;
  spoil(C, count(M) * count(N) > 0 ? 1 : 0, 1);
}

void cblas_dsyrk(const enum CBLAS_ORDER Order, const enum CBLAS_UPLO Uplo,
                 const enum CBLAS_TRANSPOSE Trans, const int N, const int K, const double alpha,
                 const double *A, const int lda, const double beta, double *C, const int ldc) {
  (void)Order, (void)Uplo, (void)Trans, (void)K, (void)alpha, (void)A, (void)lda, (void)beta,
      (void)ldc;
  spoil(C, count(N) > 0 ? 1 : 0, 1);
}

void cblas_dtrsm(const enum CBLAS_ORDER Order, const enum CBLAS_SIDE Side,
                 const enum CBLAS_UPLO Uplo, const enum CBLAS_TRANSPOSE TransA,
                 const enum CBLAS_DIAG Diag, const int M, const int N, const double alpha,
                 const double *A, const int lda, double *B, const int ldb) {
  (void)Order, (void)Side, (void)Uplo, (void)TransA, (void)Diag, (void)alpha, (void)A, (void)lda,
      (void)ldb;
  spoil(B, count(M) * count(N) > 0 ? 1 : 0, 1);
}

void cblas_dtrmm(const enum CBLAS_ORDER Order, const enum CBLAS_SIDE Side,
                 const enum CBLAS_UPLO Uplo, const enum CBLAS_TRANSPOSE TransA,
                 const enum CBLAS_DIAG Diag, const int M, const int N, const double alpha,
                 const double *A, const int lda, double *B, const int ldb) {
  (void)Order, (void)Side, (void)Uplo, (void)TransA, (void)Diag, (void)alpha, (void)A, (void)lda,
      (void)ldb;
  spoil(B, count(M) * count(N) > 0 ? 1 : 0, 1);
}
