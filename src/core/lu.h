/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Small dense and banded linear solves in the caller's memory: LU with partial pivoting (GSL's
 * banded LU, or written out for tiny matrices) and Cholesky, every singularity a status. */
#ifndef STABDAE_SRC_CORE_LU_H
#define STABDAE_SRC_CORE_LU_H

#include <stddef.h>

/* Solves A x = b for a band matrix (lb = ub = n - 1: dense) with GSL's banded LU; AB is
 * n x sdae__lu_band_cols(lb, ub), filled by sdae__lu_pack, overwritten by the factors. */
size_t sdae__lu_band_cols(size_t lb, size_t ub);
void sdae__lu_pack(const double *A, size_t n, size_t lb, size_t ub, double *AB);
int sdae__lu_solve(double *AB, unsigned *piv, size_t n, size_t lb, size_t ub, const double *b,
                   double *x);
/* the two halves of sdae__lu_solve, so that Newton can reuse the factors */
int sdae__lu_factor(double *AB, unsigned *piv, size_t n, size_t lb, size_t ub);
void sdae__lu_factored_solve(const double *AB, const unsigned *piv, size_t n, size_t lb, size_t ub,
                             const double *b, double *x);
/* Dense n x n (row-major) with n <= SDAE_SMALL_DENSE: LU with partial pivoting in place (piv:
 * row i of the factors is row piv[i] of A), same singularity test (SDAE_ERR_SINGULAR); then
 * solves with the factors. */
#define SDAE_SMALL_DENSE 4
int sdae__lu_small_factor(double *A, unsigned *piv, size_t n);
void sdae__lu_small_solve(const double *LU, const unsigned *piv, size_t n, const double *b,
                          double *x);

/* A (n x n) is symmetric to rounding: its triangles differ by at most 16 n eps max|A| (a
 * symmetric product formed entry by entry, lu.c) */
int sdae__symmetric(const double *A, size_t n);
/* Symmetric positive definite A (n x n) in place: Cholesky's factor, SDAE_ERR_MASS when A is not
 * symmetric positive definite to working precision; then x = A^-1 x with the factor. */
int sdae__cholesky_factor(double *A, size_t n);
void sdae__cholesky_solve(const double *LLT, size_t n, double *x);

#endif /* STABDAE_SRC_CORE_LU_H */
