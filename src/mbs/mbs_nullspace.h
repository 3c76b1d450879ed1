/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The saddle-point system of a constrained mechanism, [M G^T; G 0] [x; lambda] = [F; -g], by the
 * null-space method on a rank-revealing factorization (mbs_nullspace.c): G's rows scaled to unit
 * length, G_s^T P = Q R by GSL's QR with column pivoting, the rank r the pivots down to the first
 * whose sine (R_kk / R_00, the angle of a row to the span of those before it) is below a floor,
 * Q = [Y Z] (Y: r columns, Z: n_q - r spanning the kernel of the rows kept; Q kept as GSL's
 * Householder vectors and applied by them, Z alone formed, for the reduced mass). Then
 * x = Y x_Y + Z x_Z with R_11^T x_Y = -(P^T D g)_r and (Z^T M Z) x_Z = Z^T (F - M Y x_Y): G x = -g,
 * and along ker G the motion M x = F. It serves the multipliers (mbs_query.c: the acceleration
 * and lambda, every row independent) and the projection step (mbs_project.c: the acceleration
 * and the M-orthogonal corrections of q and v, whatever the rank: the rows below the floor are
 * dropped, so that a configuration where G loses rank is solved as one with fewer constraints). */
#ifndef STABDAE_SRC_MBS_MBS_NULLSPACE_H
#define STABDAE_SRC_MBS_MBS_NULLSPACE_H

#include <stddef.h>

#include "core/arena.h"

typedef struct sdae_mbs_nullspace {
  size_t n_q, n_c, rank;
  const double *M;         /* n_q x n_q: the mass matrix factored with, the caller's */
  double *scale;           /* n_c: 1 / |G_j| */
  double *GT, *tau, *norm; /* n_q x n_c (G_s^T, then its QR: R above the diagonal), n_c, n_c */
  size_t *perm;            /* n_c */
  double *Z;               /* n_q x n_q (n_q - rank columns used) */
  double *MZ, *Mr;         /* n_q x n_q each (n_q - rank columns used): M Z, Z^T M Z */
  double *xZ, *res, *mu;   /* n_q (x_Z), n_q, n_c */
} sdae_mbs_nullspace;

void sdae__mbs_nullspace_carve(sdae_mbs_nullspace *ns, size_t n_q, size_t n_c, sdae_arena *a);
/* G (n_c x n_q) and M factored, the rank counted down to the first sine below floor; M is
 * read again by the solves and must stay. SDAE_ERR_RANK for a zero row of G, SDAE_ERR_MASS when
 * Z^T M Z is not positive definite. */
int sdae__mbs_nullspace_factor(sdae_mbs_nullspace *ns, const double *G, const double *M,
                               double floor);
/* the rank counted again with a higher floor (the rows past it dropped), the reduced mass
 * factored again */
int sdae__mbs_nullspace_truncate(sdae_mbs_nullspace *ns, double floor);
/* x (n_q) with G x = -g (the rows kept) and Z^T (M x - F) = 0; F NULL: zero, x the M-orthogonal
 * (least M-norm) solution, the correction that moves q or v onto G x = -g; x must not be F or
 * g (x_Y is formed in it while g is read) */
void sdae__mbs_nullspace_solve(sdae_mbs_nullspace *ns, const double *F, const double *g, double *x);
/* the multipliers of M x = F - G^T lambda at x solved for (every row kept: rank n_c), n_c */
void sdae__mbs_nullspace_lambda(sdae_mbs_nullspace *ns, const double *F, const double *x,
                                double *lambda);

#endif /* STABDAE_SRC_MBS_MBS_NULLSPACE_H */
