/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The quantities at a state of a sparse mechanism (mbs_sparse_query.c, behind sdae_mbs_xi,
 * sdae_mbs_energy and sdae_mbs_lambda when the coordinates are mbs_sparse's): as mbs_query.c,
 * on the query's own scratch (but lambda's, lent by the step), through the patterns. lambda from
 * the saddle-point system
 *
 *   [M G^T; G 0] [a; lambda] = [F; -gamma],   gamma = Gdot v + d/ds dc/dt,
 *
 * factored afresh in the step's factorization, lent (sdae_mbs_sparse_lent): the step's factors
 * are then the query's, and the step refactors at its own point before it solves again. */
#ifndef STABDAE_SRC_MBS_MBS_SPARSE_QUERY_H
#define STABDAE_SRC_MBS_MBS_SPARSE_QUERY_H

#include "core/arena.h"
#include "core/sparse_ldl.h"
#include "mbs_sparse_layout.h"

typedef struct sdae_mbs_sparse_query {
  const sdae_mbs_sparse_layout *ly; /* the patterns and the saddle-point system's */
  double *c, *ct, *gamma, *xi;      /* n_c, n_c, n_c, 2 n_c */
  double *G, *Gd, *M;               /* nnz(G), nnz(G), nnz(M) */
  double *F, *Mv;                   /* n_q each */
  sdae_mbs_sparse_lent lent;        /* the step's, for lambda */
} sdae_mbs_sparse_query;

void sdae__mbs_sparse_query_carve(sdae_mbs_sparse_query *qy, const sdae_mbs_sparse_layout *ly,
                                  const sdae_mbs_sparse_lent *lent, sdae_arena *a);
int sdae__mbs_sparse_query_xi(sdae_mbs_sparse_query *qy, double t, const double *q, const double *v,
                              double *xi);
int sdae__mbs_sparse_query_energy(sdae_mbs_sparse_query *qy, double t, const double *q,
                                  const double *v, double *E);
/* lambda, in what the step lent: its factors are the query's after it, failed or not */
int sdae__mbs_sparse_query_lambda(sdae_mbs_sparse_query *qy, double t, const double *q,
                                  const double *v, double *lambda);

#endif /* STABDAE_SRC_MBS_MBS_SPARSE_QUERY_H */
