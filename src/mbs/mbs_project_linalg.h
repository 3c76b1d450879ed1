/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The projection step's linear algebra (mbs_project.c) behind one table, over the mechanism's
 * matrices as the coordinates' back-end holds them: the saddle-point system
 * [M G^T; G 0] [x; lambda] = [F; -g] at a point, whatever the rank of G, its nearly dependent
 * rows (sine to the others below a floor) set aside:
 *
 *   dense  (mbs_project_dense.c): the null-space method on G's pivoted QR (mbs_nullspace.h),
 *          the rows past the floor dropped;
 *   sparse (mbs_project_sparse.c): the system with each constraint softened by floor^2 of its
 *          pivot's scale (sdae__mbs_sparse_kkt_soften), factored by LDL on the coordinates'
 *          own analysis, and refined against the exact system: a row of sine s is kept to
 *          (floor^2 / s^2)^3 of its part, one below the floor damped to s^2 / floor^2. */
#ifndef STABDAE_SRC_MBS_MBS_PROJECT_LINALG_H
#define STABDAE_SRC_MBS_MBS_PROJECT_LINALG_H

#include <stddef.h>

#include "core/arena.h"
#include "core/sparse_ldl.h"
#include "mbs_eval.h"
#include "mbs_nullspace.h"
#include "mbs_sparse_layout.h"

typedef struct sdae_mbs_project_dense {
  sdae_mbs_eval *eval;
  size_t n_q, n_c;
  double *M, *G; /* n_q x n_q, n_c x n_q */
  sdae_mbs_nullspace ns;
} sdae_mbs_project_dense;

typedef struct sdae_mbs_project_sparse {
  sdae_mbs_eval *eval;
  const sdae_mbs_sparse_layout *ly; /* the sparse back-end's: K's pattern and analysis */
  const sdae_mbs_sparse_lent *lent; /* its step's arrays, borrowed (K, the factors, vectors) */
  size_t n_q, n_c, n_k;
  double *G, *M, *delta; /* nnz(G), nnz(M), n_c: the softening's */
  double *Gd, *ctd;      /* nnz(G), n_c: gamma's parts */
} sdae_mbs_project_sparse;

typedef struct sdae_mbs_project_linalg {
  void (*carve)(void *la, sdae_arena *a);
  /* G and M at (t, q) (SDAE_ERR_MASS unless M is symmetric), then the system factored with
   * the rows below floor set aside; refactor: at the same G and M with another floor */
  int (*factor)(void *la, double t, const double *q, double floor);
  int (*refactor)(void *la, double floor);
  /* x (n_q) with G x = -g on the rows kept and M x = F - G^T lambda; F NULL: zero, x the least
   * M-norm correction onto G x = -g. x must not be F or g. */
  void (*solve)(void *la, const double *F, const double *g, double *x);
  /* gamma (n_c) = Gdot v + d/ds dc/dt at (t, q, v) */
  int (*gamma)(void *la, double t, const double *q, const double *v, double *gamma);
  /* out (n_c) = G x + add at the stored G; the 1-norm of its row j */
  void (*g_times)(const void *la, const double *x, const double *add, double *out);
  double (*row_size)(const void *la, size_t j);
} sdae_mbs_project_linalg;

/* wired to the callbacks (and, sparse, to the back-end's layout and what its step lends, both
 * carved before) */
void sdae__mbs_project_dense_init(sdae_mbs_project_dense *d, sdae_mbs_eval *eval);
void sdae__mbs_project_sparse_init(sdae_mbs_project_sparse *s, sdae_mbs_eval *eval,
                                   const sdae_mbs_sparse_layout *ly,
                                   const sdae_mbs_sparse_lent *lent);
extern const sdae_mbs_project_linalg sdae__mbs_project_dense_linalg;
extern const sdae_mbs_project_linalg sdae__mbs_project_sparse_linalg;

#endif /* STABDAE_SRC_MBS_MBS_PROJECT_LINALG_H */
