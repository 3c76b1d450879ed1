/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A sparse symmetric indefinite matrix, the saddle-point system K = [M G^T; G 0] of a sparse
 * mechanism (M positive definite, G of full rank), factored K = P^T L D L^T P by SuiteSparse:
 * the order P by AMD (minimum degree, against fill), its rows then taken by class (sparse_ldl.c:
 * the first n_pos rows, the coordinates, before the others, the multipliers, but for the
 * coordinates held by more than SDAE_SPARSE_LDL_HUB constraints or without a mass of their
 * own, taken after the multipliers matched to the others), an order in which LDL^T needs no
 * pivoting (D > 0 on the coordinates, D < 0 on the multipliers), and the factorization by LDL. Both
 * take every array from their caller, so all of it is carved from the owner's block:
 *
 *   analyse (once, when the owner is built): AMD's ordering (amd_l2, its workspace and the
 *            copy of the pattern it consumes lent by the owner) and LDL's symbolic factorization
 *            (ldl_l_symbolic: L's column counts and the elimination tree);
 *   factor  (each time the values change): ldl_l_numeric, O(nnz(L)) flops, no allocation;
 *   solve:  ldl_l_perm, ldl_l_lsolve, ldl_l_dsolve, ldl_l_ltsolve, ldl_l_permt.
 *
 * The symbolic part is shared by every numeric factorization of the same pattern (a stepper's
 * and its query's), and L's entries are what it counts: the factors are carved after it, their
 * owner measured by an analysis of its own in scratch (core/alloc.h). */
#ifndef STABDAE_SRC_CORE_SPARSE_LDL_H
#define STABDAE_SRC_CORE_SPARSE_LDL_H

#include <stddef.h>

#include <SuiteSparse_config.h>

#include "arena.h"

/* a coordinate held by more constraints than this is taken after the multipliers (a hub: the
 * k constraints of a cart under k pendulums would fill k (k - 1) / 2 entries the other way) */
#define SDAE_SPARSE_LDL_HUB 8

/* indices as SuiteSparse's long versions take them (amd_l2, ldl_l_*): 64 bits */
typedef struct sdae_sparse_ldl_symbolic {
  size_t n, n_pos, nnz;
  size_t lnz;                 /* L's entries, counted by the analysis (0 before it) */
  SuiteSparse_long *Ap, *Ai;  /* K's pattern, the owner's to write (symmetric: rows are columns) */
  SuiteSparse_long *P, *Pinv; /* the order: P[k] the row taken k-th */
  SuiteSparse_long *Lp, *Parent; /* L's column starts (n + 1) and the elimination tree */
  unsigned char *cls;            /* n: each row's class in the order (sparse_ldl.c) */
} sdae_sparse_ldl_symbolic;

typedef struct sdae_sparse_ldl {
  const sdae_sparse_ldl_symbolic *sym;
  SuiteSparse_long *Lnz, *Flag, *Pattern, *Li; /* LDL's workspace (n each), L's rows (cap) */
  double *Lx, *D, *Y;                          /* L's values (cap), D, LDL's workspace (n) */
  double *x;                                   /* n: a solve's permuted right-hand side */
} sdae_sparse_ldl;

/* the arrays of the analysis of a pattern of n rows (n_pos of them coordinates) and nnz entries,
 * counted or handed out */
void sdae__sparse_ldl_symbolic_carve(sdae_sparse_ldl_symbolic *s, size_t n, size_t n_pos,
                                     size_t nnz, sdae_arena *a);
/* the entries of the analysis' workspace (AMD's: the pattern it consumes, its workspace, the
 * order found), used once: the owner lends it (core/arena.h) */
size_t sdae__sparse_ldl_work_len(size_t n, size_t nnz);
/* the order and L's structure of K's pattern, as the owner wrote it in s->Ap and s->Ai
 * (symmetric, its multipliers' block empty as in [M G^T; G 0] or diagonal; its sizes fit,
 * sdae__sparse_ldl_fits, which the owner asks before it carves), and s->lnz; work:
 * sdae__sparse_ldl_work_len entries */
void sdae__sparse_ldl_analyse(sdae_sparse_ldl_symbolic *s, SuiteSparse_long *work);
/* whether a pattern of n rows and nnz entries keeps every count of AMD's and LDL's in range */
int sdae__sparse_ldl_fits(size_t n, size_t nnz);

/* a factorization's arrays, L's sym->lnz entries among them (sym analysed, or its lnz set as
 * an analysis of the same pattern counted it) */
void sdae__sparse_ldl_carve(sdae_sparse_ldl *f, const sdae_sparse_ldl_symbolic *sym, sdae_arena *a);
/* K's values (in the pattern's order) factored: SDAE_OK; SDAE_ERR_MASS when a coordinate's
 * pivot is not positive beyond n eps ||M||_inf (M not positive definite to its rounding),
 * SDAE_ERR_RANK when a multiplier's is not negative beyond n eps ||G_j||^2 / ||M||_inf, that
 * rounding carried to the diagonal of G M^-1 G^T (G not of full rank to rounding) */
int sdae__sparse_ldl_factor(sdae_sparse_ldl *f, const double *values);
/* dst's factors = src's (both of one analysis): dst then solves as src does now, whatever src
 * factors next */
void sdae__sparse_ldl_copy(sdae_sparse_ldl *dst, const sdae_sparse_ldl *src);
/* x = K^-1 b (x and b may not overlap) */
void sdae__sparse_ldl_solve(sdae_sparse_ldl *f, const double *b, double *x);

#endif /* STABDAE_SRC_CORE_SPARSE_LDL_H */
