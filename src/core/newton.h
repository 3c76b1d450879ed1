/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Newton's method on a system R(y) = 0 of n equations given as a residual, an optional
 * Jacobian dR/dy and a context: nothing else is known of the problem. */
#ifndef STABDAE_SRC_CORE_NEWTON_H
#define STABDAE_SRC_CORE_NEWTON_H

#include <stddef.h>

#include "arena.h"
#include "bytes.h"

typedef struct sdae_newton_system {
  /* R(y) into R (n values): an sdae_status */
  int (*residual)(void *ctx, const double *y, double *R);
  /* optional, used by a dense Newton only: dR/dy at y (n x n, row-major), called right after
   * residual at the same y (so it may reuse what residual left in ctx); NULL: differences */
  int (*jacobian)(void *ctx, const double *y, double *J);
  void *ctx;
} sdae_newton_system;

typedef struct sdae_newton {
  size_t n, band; /* the band of dR/dy: n - 1 when dense */
  double tol;
  unsigned max_iter;
  double *R, *dy, *fd_y, *fd_plus, *fd_minus; /* n each */
  double *J;                                  /* n x n, dense only: dR/dy */
  double *LU;           /* n x (3 band + 1): dR/dy in band format, then its factors */
  unsigned *piv;        /* n */
  unsigned iters;       /* iterations, counted here alone; the owner reads and clears them */
  double residual_last; /* ||R||_inf at the last iterate evaluated */
  /* the matrix kept across solves by sdae__newton_solve_kept (when the owner sets keep):
   * factored, for the coefficient kept_coeff, solves since it was built */
  int keep, kept;
  double kept_coeff;
  unsigned kept_age;
  unsigned long refreshes; /* matrices built by sdae__newton_solve_kept */
} sdae_newton;

/* its workspace for n unknowns and a Jacobian of bandwidth band (n - 1: dense), counted or
 * handed out; tol bounds the last update relative to 1 + ||y||, max_iter the iterations */
void sdae__newton_carve(sdae_newton *nw, size_t n, size_t band, double tol, unsigned max_iter,
                        sdae_arena *a);
/* y such that R(y) = 0, from the y given: SDAE_ERR_NEWTON when max_iter iterations do not
 * converge, the residual's or Jacobian's status when they fail, SDAE_ERR_SINGULAR,
 * SDAE_ERR_NONFINITE */
int sdae__newton_solve(sdae_newton *nw, const sdae_newton_system *sys, double *y);
/* The same, for a system whose matrix dR/dy is built by differences (sys->jacobian unused) and
 * has the form I - coeff J: the factored matrix of an earlier solve is used while it serves
 * (docs/front-ends.md, the cost of a step; CVODE's rules), rebuilt at the iterate when the
 * estimated rate of convergence is slow, when coeff differs from the one it was built for by more
 * than 30 %, after NEWTON_KEEP_SOLVES solves, after a failed solve and after sdae__newton_forget.
 * With a kept matrix the iteration is a chord: it stops when the update is below tol
 * (1 + ||y||) and at rounding of y, or when the rate predicts what is left far below rounding,
 * so that what the chord leaves (of one sign solve after solve) does not accumulate. */
int sdae__newton_solve_kept(sdae_newton *nw, const sdae_newton_system *sys, double coeff,
                            double *y);
/* the kept matrix is no longer the system's (the owner changed it: a chart switch) */
void sdae__newton_forget(sdae_newton *nw);
/* what the next solve depends on (the kept matrix: its factors, coefficient and age), counted,
 * written or read (core/bytes.h) */
void sdae__newton_state(sdae_newton *nw, sdae_bytes *b);
/* the kept factors' pivots index rows of the matrix (what bytes read may not hold) */
int sdae__newton_state_valid(const sdae_newton *nw);

#endif /* STABDAE_SRC_CORE_NEWTON_H */
