/* SPDX-License-Identifier: GPL-3.0-or-later */
/* GMRES (Saad and Schultz) on A x = b from x = 0, right-preconditioned, A and the
 * preconditioner given as functions, as SUNDIALS' SPGMR takes them (ATimes, Psolve): at most m
 * Arnoldi steps by modified Gram-Schmidt, the least-squares problem by Givens rotations, no
 * restart. Flexible (Saad's FGMRES): the preconditioned vectors are kept, so the preconditioner
 * may itself be inexact. Every array is the caller's (carved from its block). */
#ifndef STABDAE_SRC_CORE_GMRES_H
#define STABDAE_SRC_CORE_GMRES_H

#include <stddef.h>

#include "arena.h"

typedef struct sdae_gmres {
  size_t n, m;
  double *V;               /* (m + 1) x n: the Arnoldi basis */
  double *Z;               /* m x n: the preconditioned basis */
  double *H;               /* (m + 1) x m: the Hessenberg matrix, rotated to triangular */
  double *cs, *sn, *g, *y; /* m, m, m + 1, m: the rotations, the rotated residual, the solution */
  unsigned iters;          /* Arnoldi steps of the last solve */
  int reached;             /* the last solve reached rtol (not stopped at m steps) */
} sdae_gmres;

typedef struct sdae_gmres_ops {
  /* out = A x, and z = P^-1 r (P ~ A): sdae_status each */
  int (*apply)(void *ctx, const double *x, double *out);
  int (*precond)(void *ctx, const double *r, double *z);
  void *ctx;
} sdae_gmres_ops;

/* the arrays for n unknowns and at most m steps, counted or handed out */
void sdae__gmres_carve(sdae_gmres *g, size_t n, size_t m, sdae_arena *a);
/* x with ||b - A x||_2 <= rtol ||b||_2 (reached), or the best of m steps or of an invariant
 * Krylov space (not reached): SDAE_OK; or the status of an apply or precond that failed, x then
 * 0; x = 0 for b = 0 */
int sdae__gmres_solve(sdae_gmres *g, const sdae_gmres_ops *ops, const double *b, double *x,
                      double rtol);

#endif /* STABDAE_SRC_CORE_GMRES_H */
