/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The sparse linear-algebra back-end of a mechanism's coordinates (mbs_linalg.h, mbs_sparse.c),
 * at the cost of its nonzeros: G, M and dG/ds as their nonzeros, the chart by
 * core/sparse_lu.c (G = L U, G_D = L U_D, no G_D^-1 G_I formed) and the velocity from the
 * saddle-point system [M G^T; G 0] [v; nu] = [P^T (0, p); g], factored by core/sparse_ldl.c
 * (SuiteSparse's AMD and LDL): W^T y = y_I - G_I^T G_D^-T y_D, and the multipliers give
 * G_D^-T (M v)_D = -nu, so that
 *
 *   p' = W^T (F + (dM/dt) v + (dG/dt)^T nu).
 *
 * Used for a mechanism with both patterns, jacobian_dot and mass_dot_v, stepped by an explicit
 * map or by one whose Newton the model's linear solve serves (sdae__mbs_sparse_applies: the
 * midpoint and discrete-gradient maps and their compositions), whose matrix is the velocity's
 * system at the midpoint (mbs_coords.c, the implicit maps' linear solve). */
#ifndef STABDAE_SRC_MBS_MBS_SPARSE_H
#define STABDAE_SRC_MBS_MBS_SPARSE_H

#include <stabdae/stabdae.h>

#include "core/arena.h"
#include "core/bytes.h"
#include "core/sparse_ldl.h"
#include "core/sparse_lu.h"
#include "mbs_eval.h"
#include "mbs_linalg.h"
#include "mbs_sparse_layout.h"
#include "mbs_sparse_query.h"

typedef struct sdae_mbs_sparse {
  sdae_mbs_eval *eval;
  size_t n_q, n_c, n_f;
  sdae_mbs_sparse_layout ly; /* the patterns, the saddle-point system's layout and analysis */
  const sdae_pattern *Gp;    /* ly's, for short */
  /* the chart: the current factorization and a candidate's, swapped on a switch */
  sdae_sparse_lu lu[2];
  int cur, have, kept;
  size_t *orders; /* the rows' orders the factorization tries (sdae__sparse_lu_orders) */
  /* L's reserve: the most entries L can hold in any of them (sdae__sparse_lu_l_bound), or U's
   * reserve where that is less */
  size_t l_cap;
  size_t *ind;    /* n_f: the current chart's q_I, ascending */
  int switched;   /* the last choice replaced the chart (the first one does not) */
  double measure; /* ||G_D^-1 G_I||_1 (estimated) of the current chart where chosen */
  /* the saddle-point system's values and factors; lent (with rhs, sol, k_res and k_dx, as
   * lend lists them) to lambda's query (sdae_mbs_lambda) or the projection step since they
   * were the point's: refactored before they serve again */
  double *K;
  sdae_sparse_ldl kkt;
  int lent;
  sdae_mbs_sparse_lent lend;
  /* an implicit map's: the factors kept for its Newton (sdae_mbs_linalg's newton_keep) */
  int implicit;
  sdae_sparse_ldl newton;
  double *Dv; /* nnz(M): the damping's values, with a damping */
  /* at the point */
  double *G, *M, *Gd; /* nnz(G), nnz(M), nnz(G) */
  double *nu;         /* n_c: the multipliers of the velocity's system */
  /* scratch */
  double *Mdv, *rhs, *sol;     /* n_q, n_k, n_k */
  double *k_res, *k_dx;        /* n_k each: the refinement's residual and correction */
  double *zc, *yd, *res;       /* n_c each */
  double *est_x, *est_z;       /* n_q each: the norm estimate's */
  sdae_mbs_sparse_query query; /* on ly */
} sdae_mbs_sparse;

/* the sparse back-end serves this mechanism and options: both patterns, jacobian_dot and
 * mass_dot_v given, an explicit map or one a model's linear solve serves */
int sdae__mbs_sparse_applies(const sdae_mbs *sys, const sdae_options *o);

extern const sdae_mbs_linalg sdae__mbs_sparse_linalg;

#endif /* STABDAE_SRC_MBS_MBS_SPARSE_H */
