/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The dense linear-algebra back-end of a mechanism's coordinates (mbs_linalg.h, mbs_dense.c):
 * G and M as full matrices, the chart of mbs_chart.c (the best one by pivoted QR, G_D's LU,
 * A = G_D^-1 G_I and W), the velocity by the reduced mass W^T M W, the quantities at a state of
 * mbs_query.c, and the energy structure of the discrete gradients. Every implicit map, and
 * every mechanism without both patterns, is stepped on it. */
#ifndef STABDAE_SRC_MBS_MBS_DENSE_H
#define STABDAE_SRC_MBS_MBS_DENSE_H

#include "mbs_chart.h"
#include "mbs_linalg.h"
#include "mbs_query.h"

typedef struct sdae_mbs_dense {
  sdae_mbs_eval *eval;
  size_t n_q, n_c, n_f;
  sdae_mbs_atlas chart;
  sdae_mbs_query query;
  /* at the point */
  double *G;  /* n_c x n_q: dc/dq */
  double *M;  /* n_q x n_q */
  double *Mr; /* n_f x n_f: the reduced mass W^T M W, factored */
  /* scratch, one array a role */
  double *Y;          /* n_q: a column of M W */
  double *z_D;        /* n_c: G_D z_D = g */
  double *Mz;         /* n_q: M z */
  double *v_I;        /* n_f: v's independent part */
  double *Gdot, *Mdv; /* the momentum rate: dG/dt (n_c x n_q), (dM/dt) v (n_q) */
  double *Mv;         /* n_q: M v at the point */
  double *GdW, *X;    /* n_c each: a column of (dG/dt) W, G_D^-1 of it */
  double *dW;         /* n_f: X^T (M v)_D, minus (dW/dt)^T M v */
  double *D;          /* n_q x n_q: the damping D(q) */
} sdae_mbs_dense;

extern const sdae_mbs_linalg sdae__mbs_dense_linalg;

#endif /* STABDAE_SRC_MBS_MBS_DENSE_H */
