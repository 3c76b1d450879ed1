/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The quantities at a state (mbs_query.c, behind sdae_mbs_xi, sdae_mbs_energy and
 * sdae_mbs_lambda of mbs.c): each computes into its own scratch (and the stencils' of mbs_eval,
 * which keep nothing between calls), never the step's arrays, and hands out its result only when it
 * is finite. */
#ifndef STABDAE_SRC_MBS_MBS_QUERY_H
#define STABDAE_SRC_MBS_MBS_QUERY_H

#include <stddef.h>

#include "core/arena.h"
#include "mbs_eval.h"
#include "mbs_nullspace.h"

typedef struct sdae_mbs_query {
  /* sdae_mbs_xi: c, G and dc/dt at q, and xi before it is checked */
  double *c, *G, *ct, *xi; /* n_c, n_c x n_q, n_c, 2 n_c */
  /* sdae_mbs_energy: M at q */
  double *M; /* n_q x n_q */
  /* sdae_mbs_lambda: G, gamma, F and M at the state, the saddle-point system's null-space
   * factors (mbs_nullspace.h), the acceleration */
  double *lam_G, *gamma, *F, *lam_M; /* n_c x n_q, n_c, n_q, n_q x n_q */
  sdae_mbs_nullspace ns;
  double *acc;    /* n_q */
  double *lambda; /* n_c */
  /* redundant constraints (n_rows > n_c): xi of every row; the rows chosen at the state, the
   * step's kept aside; G_D^T's QR (the chosen rows' G^T, n_q x n_c), each row's coefficients on
   * the chosen ones (n_rows x n_c), C^T C (n_c x n_c), a least-squares residual (n_q) */
  size_t n_rows;
  double *xi_all;
  size_t *rows;
  double *sel_T, *sel_tau, *coef, *ctc, *ls_res;
} sdae_mbs_query;

void sdae__mbs_query_carve(sdae_mbs_query *qy, size_t n_q, size_t n_c, size_t n_rows,
                           sdae_arena *a);
/* sdae_mbs_xi, sdae_mbs_energy and sdae_mbs_lambda on the query's scratch, the mechanism's
 * callbacks through ev; the output written only when the result is finite */
int sdae__mbs_query_xi(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                       const double *v, double *xi);
int sdae__mbs_query_energy(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                           const double *v, double *E);
int sdae__mbs_query_lambda(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                           const double *v, double *lambda);

#endif /* STABDAE_SRC_MBS_MBS_QUERY_H */
