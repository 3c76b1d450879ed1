/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Internal declarations shared by the modules of the library; not installed.
 * Data flows one way: model -> map -> newton -> stabilizer/stepper -> integrate. */
#ifndef STABDAE_INTERNAL_H
#define STABDAE_INTERNAL_H

#include <math.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "alloc.h"
#include "map.h"

/* Newton on a band narrower than the matrix (the options' bandwidth): GSL's banded LU and
 * finite differences; a dense Newton keeps a full matrix and can take an analytic Jacobian. */
static inline int sdae__banded(const sdae_model *m, const sdae_options *o) {
  return o->bandwidth > 0 && o->bandwidth < m->n_mu - 1;
}

/* ---- arena.c: one block handed out array by array; the same walk, without a base, only
 * counts (overflow-checked) ---- */
typedef struct sdae_arena {
  char *base; /* NULL: count only; else aligned for any type */
  size_t used;
  int overflow;
} sdae_arena;
/* n elements of size bytes, aligned to align (a power of two) */
void *sdae__take_array(sdae_arena *a, size_t n, size_t size, size_t align);
double *sdae__take(sdae_arena *a, size_t n1, size_t n2); /* n1 x n2 doubles */
unsigned *sdae__take_pivots(sdae_arena *a, size_t n);
/* header + the arrays counted, in bytes; SDAE_ERR_OVERFLOW when that does not fit in size_t */
int sdae__arena_bytes(const sdae_arena *a, size_t header, size_t *bytes);
/* a block of an object (header bytes) and the arrays counted in a, in memory of any alignment:
 * its bytes (with room to align the caller's memory); and, in mem, where the object goes, with
 * a set to hand out the arrays after it */
int sdae__block_bytes(const sdae_arena *a, size_t header, size_t *bytes);
void *sdae__block_start(void *mem, size_t header, sdae_arena *a);

/* ---- newton.c: solves y = x + h (phi(x, y) + shift) for y (shift may be NULL), from y ---- */
typedef struct sdae_newton {
  size_t n, band;     /* the band of the Newton matrix: n - 1 when dense */
  double tol;
  unsigned max_iter;
  double *R, *dy, *phi, *fd_y, *fd_plus, *fd_minus; /* n each */
  double *J;          /* n x n, dense only: an analytic dphi/dy, then I - h dphi/dy */
  double *LU;         /* n x (3 band + 1): I - h dphi/dy in band format, then its factors */
  unsigned *piv;      /* n */
  unsigned iters;     /* iterations, counted here alone; the stepper reads and clears them */
  double residual_last; /* ||R||_inf at the last iterate evaluated */
} sdae_newton;
/* its workspace for the model and options (counted, or handed out) */
void sdae__newton_carve(sdae_newton *nw, const sdae_model *m, const sdae_options *o,
                        sdae_arena *a);
int sdae__newton_solve(sdae_newton *nw, const sdae_map_type *map, sdae_map_ctx *c, double t,
                       double h, const double *x, const double *shift, double *y);

/* ---- stabilizer.c: the xi update of the paper's stabilizer or a baseline; a table each ---- */
typedef struct sdae_stab_ctx {
  const sdae_model *model;
  const sdae_options *opt;
  const double *qnorm2;     /* ||q_i||^2 at (xi, mu), n_xi */
  double *k;                /* the paper's: the gains (eq. 6), n_xi */
  double *blk, *blk_LU;     /* the baselines': one chain's (I - T A) and its factors */
  unsigned *blk_piv;
} sdae_stab_ctx;
typedef struct sdae_stabilizer_type {
  const char *name;
  int (*validate)(const sdae_model *m, const sdae_options *o); /* optional */
  void (*carve)(sdae_stab_ctx *c, sdae_arena *a);           /* optional: its workspace */
  int (*xi_update)(sdae_stab_ctx *c, double T, const double *xi, double *xi_new);
} sdae_stabilizer_type;
/* the table of a stabilizer, NULL for an unknown one */
const sdae_stabilizer_type *sdae__stabilizer_type(sdae_stabilizer which);
/* SDAE_OK when the model's rel_degree gives n_constraints degrees in 1..max summing to n_xi,
 * SDAE_ERR_REL_DEGREE otherwise */
int sdae__rel_degree_check(const sdae_model *m, unsigned max);
/* k_i = -(delta^2/2) ||q_i||^2 - epsilon (eq. 6), n values */
void sdae__gains(const sdae_options *o, const double *qnorm2, size_t n, double *k);

/* ---- the stepper: one block, the struct followed by its work arrays ---- */
struct sdae_stepper {
  sdae_model model;
  sdae_options opt;
  const sdae_stabilizer_type *stabilizer;
  void *block;              /* what sdae_stepper_alloc_with allocated, NULL for a caller's */
  size_t block_bytes;
  sdae_allocator allocator; /* block's, and sdae_certify_box's (zero: malloc and free) */
  sdae_stats stats;
  sdae_map_ctx map;         /* the map's context: model, scratch, Newton */
  sdae_newton newton;
  sdae_stab_ctx stab;
  double *Q;      /* n_mu x n_xi (dense Q only) */
  double *Qxi;    /* n_mu: Q(xi, mu) xi */
  double *qnorm2; /* n_xi: ||q_i||^2 */
  double *xi_new, *mu_new; /* n_xi, n_mu: the step's result before it is accepted */
  double *phi;    /* n_mu: the map's value at the predictor */
};

/* SDAE_OK when the model and options make a stepper, the status saying why not otherwise */
int sdae__stepper_validate(const sdae_model *m, const sdae_options *o);

/* integrate.c: nsteps fixed steps of a stepper of either kind, the observer seeing step 0, every
 * `every`-th step and the last; step and observe receive ctx */
typedef struct sdae_drive {
  int (*step)(void *ctx, double t, double T);
  int (*observe)(void *ctx, size_t step, double t); /* NULL: none; non-zero stops */
  void *ctx;
} sdae_drive;
int sdae__drive(const sdae_drive *d, double t0, double T, size_t nsteps, size_t every,
                size_t *steps_done);

/* model.c: callbacks with their status and their outputs checked */
/* The SUNDIALS rule: 0 success, > 0 recoverable, < 0 fatal. Inline, as sdae__all_finite: both
 * run on every callback, a few values each for small models. */
static inline int sdae__status_of_callback(int rc) {
  if (rc == 0) return SDAE_OK;
  return rc > 0 ? SDAE_ERR_CALLBACK_RECOVERABLE : SDAE_ERR_CALLBACK_FATAL;
}
static inline int sdae__all_finite(const double *v, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (!isfinite(v[i])) return 0;
  return 1;
}
/* dst = src. A small model's state, just written a double at a time by the step, is read back
 * the same way: memcpy's 16-byte loads would wait for those stores to reach the cache (a load
 * spanning two stores is not forwarded). A large one goes to memcpy, whose wide loads then win
 * (docs/performance.md). */
enum { SDAE_COPY_BY_LOOP = 8 };
static inline void sdae__copy(double *dst, const double *src, size_t n) {
  if (n > SDAE_COPY_BY_LOOP) {
    memcpy(dst, src, n * sizeof *dst);
    return;
  }
  for (size_t i = 0; i < n; i++) dst[i] = src[i];
}
/* calls a user callback of the (t, mu, out) form with the model's params, then checks it;
 * inline: the discrete gradient makes four such calls per evaluation */
static inline int sdae__call_checked(int (*cb)(double, const double *, double *, void *),
                                     const sdae_model *m, double t, const double *mu,
                                     double *out, size_t n_out) {
  int rc = sdae__status_of_callback(cb(t, mu, out, m->params));
  if (rc != SDAE_OK) return rc;
  return sdae__all_finite(out, n_out) ? SDAE_OK : SDAE_ERR_NONFINITE;
}
int sdae__eval_q0(const sdae_model *m, double t, const double *mu, double *out);
int sdae__eval_q0_jac(const sdae_model *m, double t, const double *mu, double *out);
/* Q(xi, mu) xi into Qxi and ||q_i||^2 into qnorm2; Q_dense: n_mu x n_xi scratch for a dense Q */
int sdae__eval_Q(const sdae_model *m, double *Q_dense, double t, const double *xi,
                 const double *mu, double *Qxi, double *qnorm2);

/* lu.c: solves A x = b for a band matrix (lb = ub = n - 1: dense) with GSL's banded LU; AB is
 * n x sdae__lu_band_cols(lb, ub), filled by sdae__lu_pack, overwritten by the factors */
size_t sdae__lu_band_cols(size_t lb, size_t ub);
void sdae__lu_pack(const double *A, size_t n, size_t lb, size_t ub, double *AB);
int sdae__lu_solve(double *AB, unsigned *piv, size_t n, size_t lb, size_t ub, const double *b,
                   double *x);
/* the two halves of sdae__lu_solve, so that Newton can reuse the factors */
int sdae__lu_factor(double *AB, unsigned *piv, size_t n, size_t lb, size_t ub);
void sdae__lu_factored_solve(const double *AB, const unsigned *piv, size_t n, size_t lb,
                             size_t ub, const double *b, double *x);
/* Dense n x n (row-major) with n <= SDAE_SMALL_DENSE: LU with partial pivoting in place (piv:
 * row i of the factors is row piv[i] of A), same singularity test (SDAE_ERR_SINGULAR); then
 * solves with the factors. */
#define SDAE_SMALL_DENSE 4
int sdae__lu_small_factor(double *A, unsigned *piv, size_t n);
void sdae__lu_small_solve(const double *LU, const unsigned *piv, size_t n, const double *b,
                          double *x);

/* Symmetric positive definite A (n x n) in place: Cholesky's factor, SDAE_ERR_MASS when A is not
 * symmetric positive definite to working precision; then x = A^-1 x with the factor. */
int sdae__cholesky_factor(double *A, size_t n);
void sdae__cholesky_solve(const double *LLT, size_t n, double *x);

#endif /* STABDAE_INTERNAL_H */
