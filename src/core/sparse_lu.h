/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A wide sparse matrix A (m x n, m < n, its nonzeros in a pattern of compressed rows) factored
 * row by row, each row choosing its pivot column by the values: the chart of a sparse mechanism,
 * A = G and its pivot columns q_D, chosen without forming the dense G_D^-1 G_I.
 *
 * Row r of A, with the rows before it eliminated (their pivot columns taken out, smallest pivot
 * first), is row r of U; the multipliers are row r of L (unit lower triangular, m x m):
 *
 *   A = L U,   A_D = L U_D,   B = A_D^-1 A_I = U_D^-1 U_I,
 *
 * U_D (U's pivot columns, in pivot order) upper triangular; the rows are taken in an order
 * found from A's pattern (sdae__sparse_lu_orders: the leaves first, minimum degree, nested
 * dissection; the best chart of those that fit kept by sdae__sparse_lu_choose_best, by its
 * measure, then its fill). The pivot of row r is, among its
 * columns not yet pivots whose |value| is at least tau times the largest, the one fewest rows
 * still to come hold (Markowitz's count, which keeps the fill down: on a chain a link's far end,
 * which no later link holds but the next), the larger value on a tie. Nothing is dropped by its
 * value (nor is a zero kept out), so the factors' structure is set by A's pattern and the
 * pivots alone, and a
 * refactorization with the pivots kept fills the same places. Every array is carved when the
 * owner is built: L's reserve is the bound on it in the orders tried (sdae__sparse_lu_l_bound,
 * George and Ng's) where that is below U's (SDAE_SPARSE_LU_FILL), for which no static count
 * is useful. The two reserves are one array, U's entries taken from its front and L's from its
 * back, so the room an L below its bound leaves serves U; SDAE_ERR_PATTERN when the factors
 * together would need more. */
#ifndef STABDAE_SRC_CORE_SPARSE_LU_H
#define STABDAE_SRC_CORE_SPARSE_LU_H

#include <stddef.h>
#include <stdint.h>

#include <SuiteSparse_config.h>

#include "arena.h"
#include "pattern.h"

/* the entries U may hold (and L, where its bound is larger): this many times A's nonzeros,
 * plus one per row */
#define SDAE_SPARSE_LU_FILL 4
/* the threshold of the pivot choice: a candidate at least this fraction of the row's largest */
#define SDAE_SPARSE_LU_TAU 0.5
/* a column held by more rows than this is left out of the orders' graph (sparse_lu_order.c) */
#define SDAE_SPARSE_LU_HUB 8
/* the orders sdae__sparse_lu_orders finds, each m long, one after the other */
enum {
  SDAE_SPARSE_LU_LEAVES,
  SDAE_SPARSE_LU_AMD,
  SDAE_SPARSE_LU_DISSECTION,
  SDAE_SPARSE_LU_ORDERS
};

typedef struct sdae_sparse_lu {
  size_t m, n, cap, l_cap; /* the entries U and L hold together, and L's share of them */
  /* the order: A's row taken k-th; the pivots: step k's column, and a column's step (or m) */
  size_t *order, *pivot, *row_of;
  /* U's rows (entries u_start[k] .. u_start[k + 1] - 1, the pivot's at u_diag[k]) and L's
   * strictly lower rows (the multipliers l_rk, by k). Once factored, each row of U is its pivot,
   * then its entries in later pivots' columns (up to u_dend[k], u_step their steps), then those
   * in the other columns, each group in its order: the solves run over one group, no test per
   * entry */
  size_t *u_start, *u_diag, *u_dend;
  uint32_t *u_col, *u_step; /* 32 bits: n < 2^30 (the sizes above) */
  double *u_val;
  size_t *l_start;
  uint32_t *l_col; /* into u_col's and u_val's tail, where the last factorization left L */
  double *l_val;
  /* the elimination's workspace: the row (dense, n), its columns (a list and a mark), the pivot
   * rows to take out (a heap, smallest first, with a mark), the rows to come holding a column */
  double *x;
  size_t *list, *heap, *count;
  unsigned char *in_row, *pending;
  unsigned char *done; /* m: the owner's scratch, a mark per row */
  double *w, *v;       /* m each: the solves', the estimate's */
} sdae_sparse_lu;

/* Sizes: n and nnz below 2^30 (2^16 and 2^26 on 32-bit targets), as sdae__sparse_ldl_fits
 * admits them for the owner's saddle-point system, so no count below overflows and the
 * factors' entries index by 32 bits (a fifth less memory than size_t's 64). */
/* the entries U's reserve holds for A of m rows and nnz nonzeros: SDAE_SPARSE_LU_FILL nnz + m,
 * and L's where the bound on it is not less */
size_t sdae__sparse_lu_reserve(size_t m, size_t nnz);
/* its arrays for A of m x n with nnz nonzeros and l_cap entries of L, counted or handed out */
void sdae__sparse_lu_carve(sdae_sparse_lu *lu, size_t m, size_t n, size_t nnz, size_t l_cap,
                           sdae_arena *a);
/* the entries of workspace sdae__sparse_lu_orders needs at least, for A of m x n with nnz
 * nonzeros; more lets it keep more columns in its graph (the hubs' bound halved until it fits) */
size_t sdae__sparse_lu_orders_min(size_t m, size_t n, size_t nnz);
/* orders (SDAE_SPARSE_LU_ORDERS x m): A's rows the leaves first, in AMD's minimum-degree order of
 * the graph of A A^T (two rows adjacent where they share a column; the columns held by more
 * than SDAE_SPARSE_LU_HUB rows left out), and in its nested dissection; work: len entries.
 * SDAE_ERR_BUFFER when len is below sdae__sparse_lu_orders_min. */
int sdae__sparse_lu_orders(const sdae_pattern *A, size_t m, size_t n, SuiteSparse_long *work,
                           size_t len, size_t *orders);
/* the most entries L can hold in the rows' order order (m), whatever the pivots: the strictly
 * lower entries of the Cholesky factor of A A^T in that order (sparse_lu_order.c), counted
 * until they pass most (a count above most then, a hub's rows costing the square of its
 * count); work: at least sdae__sparse_lu_orders_min entries */
size_t sdae__sparse_lu_l_bound(const sdae_pattern *A, size_t m, size_t n, const size_t *order,
                               size_t most, SuiteSparse_long *work);
/* the pivots chosen and A factored (values in A's pattern order) in the rows' order lu->order:
 * SDAE_OK; SDAE_ERR_RANK when a row is dependent on those before it (its largest remaining value
 * at rounding); SDAE_ERR_PATTERN when the factors outgrow their reserve */
int sdae__sparse_lu_choose(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values);
/* the pivots chosen in each of the k orders (k x m, as sdae__sparse_lu_orders gives them), the
 * factors of the best chart kept, its order in lu->order: the first that fits, replaced by a
 * later one whose estimate of ||B||_1 (sdae__sparse_lu_norm1, x and z its workspace) is smaller
 * by the factor by (the owner's hysteresis), or the same with fewer entries in L and U. SDAE_OK
 * when one fits; else SDAE_ERR_RANK if an order found a dependent row, SDAE_ERR_PATTERN if none
 * fits */
int sdae__sparse_lu_choose_best(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values,
                                const size_t *orders, size_t k, double by, double *x, double *z);
/* A factored again with the pivots kept (A's values changed, not its pattern): SDAE_ERR_RANK
 * when a pivot falls to rounding */
int sdae__sparse_lu_refactor(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values);
/* x = A_D^-1 b: b by A's rows, x by step (x[k] belongs to column pivot[k]) */
void sdae__sparse_lu_solve(sdae_sparse_lu *lu, const double *b, double *x);
/* y = A_D^-T c: c by pivot, y by A's rows */
void sdae__sparse_lu_solve_t(sdae_sparse_lu *lu, const double *c, double *y);
/* out = B x (m, by pivot) for x over A's n columns (its pivot columns not read) */
void sdae__sparse_lu_times_b(sdae_sparse_lu *lu, const double *x, double *out);
/* out = B^T y (n, over A's columns; 0 at the pivot columns) for y by pivot */
void sdae__sparse_lu_times_bt(sdae_sparse_lu *lu, const double *y, double *out);
/* Hager's estimate of ||B||_1 = max_j sum_i |B_ij| (Higham's form, LAPACK's dlacn2): a lower
 * bound, most often equal, from at most 5 products with B and with B^T, in O(nnz(L) + nnz(U))
 * each; x, z: n doubles of workspace */
double sdae__sparse_lu_norm1(sdae_sparse_lu *lu, double *x, double *z);

#endif /* STABDAE_SRC_CORE_SPARSE_LU_H */
