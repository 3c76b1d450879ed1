/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Newton's method on a system R(y) = 0 of n equations, the one nonlinear solver of the library
 * (docs/architecture.md). As SUNDIALS' SUNNonlinSol, it sees the problem through four hooks:
 * the residual, a linear setup (the matrix at an iterate, factored), a linear solve with those
 * factors, and the convergence test, which is this file's own, one for every adapter (the
 * map's step equation, Phi^-1's chord iteration, a DAE's coordinates). */
#ifndef STABDAE_SRC_CORE_NEWTON_H
#define STABDAE_SRC_CORE_NEWTON_H

#include <stddef.h>

#include "arena.h"
#include "bytes.h"
#include "gmres.h"

/* the library's default tolerance and iteration cap (sdae_options_default, and the solves
 * that have no options: a DAE's coordinates) */
#define SDAE_NEWTON_TOL 1e-14
#define SDAE_NEWTON_MAX_ITER 20u
/* Newton-Krylov's GMRES (a model's linear solve its preconditioner): at most this many steps,
 * to this relative residual; Newton then gains about three digits an iteration, where the
 * preconditioner alone as a chord gained less than half of one on a long rope in motion (the
 * chart's terms it leaves out grow with the velocity's multipliers, docs/performance.md) */
#define SDAE_KRYLOV_DIM 40u
#define SDAE_KRYLOV_RTOL 1e-3

typedef struct sdae_newton_system {
  /* R(y) into R (n values): an sdae_status */
  int (*residual)(void *ctx, const double *y, double *R);
  /* or, for an implicit step R(y) = y - x - coeff (f(y) + shift) (CVODE's form; coeff the
   * solve's, shift optional): f(y) into out, and Newton forms R in the pass that measures it */
  int (*f)(void *ctx, const double *y, double *out);
  const double *x, *shift;
  /* the linear setup and solve of the owner (both or neither): the matrix at y factored, an
   * sdae_status; dy = A^-1 R with those factors, an sdae_status. NULL: Newton's own, dR/dy by
   * jacobian or by differences of residual, LU */
  int (*setup)(void *ctx, const double *y);
  int (*solve)(void *ctx, const double *R, double *dy);
  /* optional, with Newton's own setup when dense: J at y (n x n, row-major) such that
   * dR/dy = I - coeff J (coeff: the solve's), called right after residual at the same y (so it
   * may reuse what residual left in ctx); NULL: differences of R. A matrix from it costs one
   * call: Newton rebuilds it at every iterate that moved by more than a small step, never keeps
   * it across solves. */
  int (*jacobian)(void *ctx, const double *y, double *J);
  void *ctx;
} sdae_newton_system;

typedef struct sdae_newton {
  size_t n, band; /* the band of dR/dy: n - 1 when dense */
  double tol;
  unsigned max_iter;
  double coeff; /* the solve's: dR/dy = I - coeff J */
  /* the owner's choice: 0 rebuilds the matrix at every iterate until the update is small
   * (Newton); 1 keeps it across solves while it serves (a chord; CVODE's rules) */
  int keep;
  double *R, *dy, *y0;               /* n each: the residual, the update, the solve's start */
  double *fd_y, *fd_plus, *fd_minus; /* n each: Newton's own matrix by differences */
  int own_matrix;                    /* the matrix is Newton's (not the owner's hooks) */
  int built;                         /* the solve under way built a matrix */
  double *J;                         /* n x n, dense only: dR/dy */
  double *LU;                        /* n x (3 band + 1): dR/dy in band format, then its factors */
  unsigned *piv;                     /* n */
  unsigned iters;       /* iterations, counted here alone; the owner reads and clears them */
  double residual_last; /* ||R||_inf at the last iterate evaluated */
  /* what a solve leaves for the next (keep = 1), plain fields that a state written as bytes
   * carries: a factored matrix (in LU and piv, or the owner's), the coefficient it was built
   * for and the solves since */
  int kept;
  double kept_coeff;
  unsigned kept_age;
  /* Newton-Krylov (sdae__newton_carve_krylov): with the system's setup and solve, each linear
   * solve is GMRES on dR/dy, its products by differences of R at the iterate, the system's
   * solve its preconditioner */
  sdae_gmres *krylov;
  double krylov_rtol;
  sdae_gmres gmres;
  unsigned long krylov_iters; /* GMRES steps, counted here alone */
  unsigned long refreshes;    /* matrices built with keep = 1 */
  unsigned long retries;      /* solves retried from their start with a fresh matrix */
} sdae_newton;

/* its workspace for n unknowns and a Jacobian of bandwidth band (n - 1: dense), counted or
 * handed out; tol bounds the last update relative to 1 + ||y||, max_iter the iterations of
 * one attempt */
void sdae__newton_carve(sdae_newton *nw, size_t n, size_t band, double tol, unsigned max_iter,
                        sdae_arena *a);
/* the same without a matrix of its own: the system gives setup and solve */
void sdae__newton_carve_hooks(sdae_newton *nw, size_t n, double tol, unsigned max_iter,
                              sdae_arena *a);
/* the same, with GMRES of at most m steps to relative residual rtol as its linear solve */
void sdae__newton_carve_krylov(sdae_newton *nw, size_t n, size_t m, double rtol, double tol,
                               unsigned max_iter, sdae_arena *a);
/* y such that R(y) = 0, from the y given. The matrix, when it has the form I - coeff J, is kept
 * (keep = 1) while coeff stays within 30 % of the one it was built for and for at most 20
 * solves; a solve that does not converge with a kept matrix is retried from the same y with a
 * matrix built there and its own iteration cap (CVODE's recovery); only a failure with a fresh
 * matrix fails: SDAE_ERR_NEWTON when max_iter iterations do not converge, the residual's or the
 * setup's status when they fail, SDAE_ERR_SINGULAR, SDAE_ERR_NONFINITE. A failed solve keeps
 * nothing. */
int sdae__newton_solve(sdae_newton *nw, const sdae_newton_system *sys, double coeff, double *y);
/* the kept matrix is no longer the system's (the owner changed it: a chart switch, a failed
 * step) */
void sdae__newton_forget(sdae_newton *nw);
/* what the next solve depends on (the kept matrix: its factors, coefficient and age), counted,
 * written or read (core/bytes.h) */
void sdae__newton_state(sdae_newton *nw, sdae_bytes *b);
/* the kept factors' pivots index rows of the matrix (what bytes read may not hold) */
int sdae__newton_state_valid(const sdae_newton *nw);
/* the owner's factors (made by its own means, outside a solve) serve as the kept matrix of the
 * next solve: a failure with them is retried with the system's setup at the start */
void sdae__newton_adopt(sdae_newton *nw, double coeff);

#endif /* STABDAE_SRC_CORE_NEWTON_H */
