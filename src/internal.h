/* Internal declarations shared by the modules of the library; not installed.
 * Data flows one way: model -> map -> newton -> stabilizer/stepper -> integrate. */
#ifndef STABDAE_INTERNAL_H
#define STABDAE_INTERNAL_H

#include <math.h>
#include <string.h>

#include <stabdae/stabdae.h>

/* ---- maps: one static table per map type, one file per map (map_*.c) ---- */

struct sdae_map_type {
  const char *name;
  int implicit;    /* phi depends on mu+: the step solves for mu+ by Newton */
  int uses_newton; /* the map or the step needs the Newton workspace */
  /* SDAE_OK when the options give every callback the map needs, SDAE_ERR_MAP otherwise */
  int (*check)(const sdae_model *m, const sdae_options *o);
  /* doubles of scratch the map needs */
  size_t (*scratch)(const sdae_model *m, const sdae_options *o);
  /* phi_T(mu, mu+): n_mu values */
  int (*phi)(sdae_stepper *s, double t, double T, const double *mu, const double *mu_next,
             double *out);
  /* d phi_T / d mu+ (n_mu x n_mu), or NULL; used only when jac_given says so. Newton calls it
   * right after phi at the same arguments (as IDA hands its Jacobian the residual just
   * computed), so it may reuse what that call left in the map's scratch. */
  int (*jac)(sdae_stepper *s, double t, double T, const double *mu, const double *mu_next,
             double *out);
  int (*jac_given)(const sdae_model *m, const sdae_options *o);
};

/* A model with a declared bandwidth below n_mu - 1: Newton works on a band (GSL's banded LU,
 * finite differences); a dense one keeps a full matrix and can take an analytic Jacobian. */
static inline int sdae__banded(const sdae_model *m) {
  return m->bandwidth > 0 && m->bandwidth < m->n_mu - 1;
}

/* ---- the stepper: one block, the struct followed by its work arrays ---- */

struct sdae_stepper {
  sdae_model model;
  sdae_options opt;
  void *block;     /* what sdae_stepper_alloc_with allocated, NULL for a caller's block */
  size_t block_bytes;
  sdae_allocator allocator; /* block's, and sdae_certify_box's (zero: malloc and free) */
  size_t band;     /* Newton's band: lb = ub = band (n_mu - 1 when dense) */
  sdae_stats stats;

  double *Q;      /* n_mu x n_xi (dense models only) */
  double *Qxi;    /* n_mu: Q(xi, mu) xi */
  double *qnorm2; /* n_xi: ||q_i||^2 */
  double *k;      /* n_xi: the gains (eq. 6) */
  double *xi_new, *mu_new; /* n_xi, n_mu: the step's result before it is accepted */
  double *phi;    /* n_mu */
  double *map_work; /* the map's scratch */

  /* Newton (implicit maps only) */
  double *R, *dy, *fd_y, *fd_plus, *fd_minus; /* n_mu each */
  double *J;      /* n_mu x n_mu, dense models: an analytic dphi/dmu+, then I - T dphi/dmu+ */
  double *LU;     /* n_mu x (3 band + 1): I - T dphi/dmu+ in band format, then its factors */
  unsigned *piv;  /* n_mu */

  /* baselines (none, Baumgarte): one r x r block at a time */
  double *blk, *blk_LU;   /* SDAE_MAX_REL_DEGREE^2 and SDAE_MAX_REL_DEGREE (3 MAX - 2) */
  unsigned *blk_piv;      /* SDAE_MAX_REL_DEGREE */
};

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
 * (the chain's euler step at N = 100 is 7% slower with the loop). */
enum { SDAE_COPY_BY_LOOP = 8 };
static inline void sdae__copy(double *dst, const double *src, size_t n) {
  if (n > SDAE_COPY_BY_LOOP) {
    memcpy(dst, src, n * sizeof *dst);
    return;
  }
  for (size_t i = 0; i < n; i++) dst[i] = src[i];
}
int sdae__eval_q0(sdae_stepper *s, double t, const double *mu, double *out);
int sdae__eval_q0_jac(sdae_stepper *s, double t, const double *mu, double *out);
/* Q(xi, mu) xi into s->Qxi and ||q_i||^2 into s->qnorm2 */
int sdae__eval_Q(sdae_stepper *s, double t, const double *xi, const double *mu);
/* calls a user callback of the (t, mu, out) form through the model's params, then checks it;
 * inline: the discrete gradient makes four such calls per evaluation */
static inline int sdae__call_checked(int (*cb)(double, const double *, double *, void *),
                                     sdae_stepper *s, double t, const double *mu, double *out,
                                     size_t n_out) {
  int rc = sdae__status_of_callback(cb(t, mu, out, s->model.params));
  if (rc != SDAE_OK) return rc;
  return sdae__all_finite(out, n_out) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

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

/* newton.c: solves y = x + h (map's phi(x, y) + shift) for y (shift may be NULL), starting
 * from y; adds its iterations to the stats' newton_iters_last */
int sdae__newton(sdae_stepper *s, const sdae_map_type *map, double t, double h, const double *x,
                 const double *shift, double *y);

/* stabilizer.c: the xi update of the chosen stabilizer and scheme, into s->xi_new */
int sdae__stabilizer_check(const sdae_model *m, const sdae_options *o);
void sdae__gains(const sdae_stepper *s, double *k);
int sdae__xi_update(sdae_stepper *s, double T, const double *xi);

#endif /* STABDAE_INTERNAL_H */
