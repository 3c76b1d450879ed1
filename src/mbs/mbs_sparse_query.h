/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The quantities at a state of a sparse mechanism (mbs_sparse_query.c, behind sdae_mbs_xi,
 * sdae_mbs_energy and sdae_mbs_lambda when the coordinates are mbs_sparse's): as mbs_query.c,
 * on the query's own scratch, through the patterns. lambda from the saddle-point system
 *
 *   [M G^T; G 0] [a; lambda] = [F; -gamma],   gamma = Gdot v + d/ds dc/dt,
 *
 * factored afresh in the query's own factorization (the step's stays as it was). */
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
  double *K, *rhs, *sol;            /* nnz(K), n_k each */
  sdae_sparse_ldl kkt;              /* on the stepper's analysis of K */
} sdae_mbs_sparse_query;

void sdae__mbs_sparse_query_carve(sdae_mbs_sparse_query *qy, const sdae_mbs_sparse_layout *ly,
                                  sdae_arena *a);
int sdae__mbs_sparse_query_xi(sdae_mbs_sparse_query *qy, double t, const double *q, const double *v,
                              double *xi);
int sdae__mbs_sparse_query_energy(sdae_mbs_sparse_query *qy, double t, const double *q,
                                  const double *v, double *E);
int sdae__mbs_sparse_query_lambda(sdae_mbs_sparse_query *qy, double t, const double *q,
                                  const double *v, double *lambda);

#endif /* STABDAE_SRC_MBS_MBS_SPARSE_QUERY_H */
