/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A sparse mechanism's matrices through their patterns (mbs_sparse_layout.c): G, M and the
 * saddle-point system K = [M G^T; G 0] as nonzeros, where M's and G's values go in K, K's
 * order and structure (analysed when the stepper is built), and the products. What the sparse
 * back-end (mbs_sparse.c) and the quantities at a state (mbs_sparse_query.c) share. */
#ifndef STABDAE_SRC_MBS_MBS_SPARSE_LAYOUT_H
#define STABDAE_SRC_MBS_MBS_SPARSE_LAYOUT_H

#include "core/arena.h"
#include "core/pattern.h"
#include "core/sparse_ldl.h"
#include "mbs_eval.h"

typedef struct sdae_mbs_sparse_layout {
  sdae_mbs_eval *eval;
  size_t n_q, n_c, n_k;        /* n_k = n_q + n_c: the saddle-point system's size */
  const sdae_pattern *Gp, *Mp; /* the mechanism's, the eval's copies */
  size_t *m_mirror;            /* nnz(M): where M's entry (j, i) is for its entry (i, j) */
  size_t knz;                  /* K's entries, both triangles */
  size_t *k_of_m, *k_of_g, *k_of_gt;
  size_t *k_of_d; /* n_c: each multiplier's diagonal entry (zero in K) */
  /* K's pattern (ksym.Ap, ksym.Ai: compressed rows, columns ascending), order and structure */
  sdae_sparse_ldl_symbolic ksym;
} sdae_mbs_sparse_layout;

/* what the step lends lambda's query and the projection step (mbs_project_linalg.h), which
 * run between its solves, never inside one: K's values, a right-hand side, a solution, a
 * residual and a correction (n_k each), and the saddle-point factorization */
typedef struct sdae_mbs_sparse_lent {
  double *K, *rhs, *sol, *res, *dx;
  sdae_sparse_ldl *kkt;
} sdae_mbs_sparse_lent;

/* the sizes of the mechanism's patterns; SDAE_ERR_OVERFLOW for a K whose indices the
 * factorization cannot hold */
int sdae__mbs_sparse_layout_init(sdae_mbs_sparse_layout *ly, sdae_mbs_eval *eval);
/* the arrays, counted or handed out; handed out, K's pattern built */
void sdae__mbs_sparse_layout_carve(sdae_mbs_sparse_layout *ly, sdae_arena *a);
/* the entries of the analysis' workspace, and K analysed in it (ksym.lnz, what the
 * factorizations carved after it hold), once K's pattern is built */
size_t sdae__mbs_sparse_layout_work_len(const sdae_mbs_sparse_layout *ly);
void sdae__mbs_sparse_layout_analyse(sdae_mbs_sparse_layout *ly, SuiteSparse_long *work);

/* out (n_c) = G x + add (add may be NULL), out (n_q) = M x, for G's and M's values; M
 * symmetric to rounding (SDAE_ERR_MASS otherwise); K's values from M's and G's */
void sdae__mbs_sparse_g_times(const sdae_mbs_sparse_layout *ly, const double *vals, const double *x,
                              const double *add, double *out);
void sdae__mbs_sparse_m_times(const sdae_mbs_sparse_layout *ly, const double *vals, const double *x,
                              double *out);
int sdae__mbs_sparse_mass_symmetric(const sdae_mbs_sparse_layout *ly, const double *M);
void sdae__mbs_sparse_kkt_values(const sdae_mbs_sparse_layout *ly, const double *M, const double *G,
                                 double *K);
/* K's values with constraint j softened: its diagonal entry -delta_j, delta_j = rho |G_j|^2 /
 * ||M||_inf (the scale of its multiplier's pivot, sdae__sparse_ldl_factor's), so that no pivot
 * of the multipliers falls below rho of its scale whatever G's rank (a Tikhonov
 * regularization of the constraints; delta n_c); ||M||_inf returned */
double sdae__mbs_sparse_kkt_soften(const sdae_mbs_sparse_layout *ly, const double *M,
                                   const double *G, double rho, double *K, double *delta);

#endif /* STABDAE_SRC_MBS_MBS_SPARSE_LAYOUT_H */
