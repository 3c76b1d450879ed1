/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Newton's method on R(y) = 0 (core/newton.h), the library's one nonlinear solver. Its
 * adapters: the maps' step equation (maps/map_solve.c)
 *
 *   R(y) = y - x - h (phi(x, y) + shift),   dR/dy = I - h dphi/dy,
 *
 * Phi^-1's chord iteration on c(t, q) = xi_c for q_D (mbs/mbs_coords.c, G_D's factors its
 * setup) and a DAE's coordinates Phi(t, x) = z (dae/coords.c). Newton's own matrix is the
 * system's Jacobian when it has one and Newton is dense, central differences of R otherwise:
 * columns 2b + 1 apart do not share a row of a band-b matrix, so each colour group of columns
 * costs two residuals. It is factored by LU (lu.c): written out for small dense systems, GSL's
 * banded LU otherwise (dense is the band n - 1).
 *
 * Two ways to use the matrix, the owner's choice (keep). Newton: rebuilt at every iterate
 * (quadratic convergence) except after an update below reuse_below; the steps that contract
 * keep a fresh matrix (a chord there leaves errors of a few ulps that are not random: H then
 * drifts under the discrete gradient). Kept (CVODE's and IDA's rules): the factored matrix of an
 * earlier solve serves while the coefficient in front of the Jacobian stays within DGMAX and for
 * MSBP solves, as a chord iteration that rebuilds at the iterate when its rate is slow. A kept
 * matrix that does not converge is rebuilt at the solve's start and the same solve retried,
 * with its own iteration cap (CVODE's cvNls recovery); only a fresh matrix's failure is one.
 * The convergence test (converged, judge) and its constants are the same for every adapter. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "callback.h"
#include "lu.h"
#include "newton.h"

void sdae__newton_carve(sdae_newton *nw, size_t n, size_t band, double tol, unsigned max_iter,
                        sdae_arena *a) {
  nw->n = n;
  nw->band = band;
  nw->tol = tol;
  nw->max_iter = max_iter;
  sdae__newton_carve_hooks(nw, n, tol, max_iter, a);
  nw->band = band;
  nw->own_matrix = 1;
  nw->fd_y = sdae__take(a, n, 1);
  nw->fd_plus = sdae__take(a, n, 1);
  nw->fd_minus = sdae__take(a, n, 1);
  nw->J = band == n - 1 ? sdae__take(a, n, n) : NULL; /* dense: analytic Jacobians */
  nw->LU = sdae__take(a, n, sdae__lu_band_cols(band, band));
  nw->piv = sdae__take_pivots(a, n);
}

void sdae__newton_carve_hooks(sdae_newton *nw, size_t n, double tol, unsigned max_iter,
                              sdae_arena *a) {
  nw->n = n;
  nw->band = n - 1;
  nw->tol = tol;
  nw->max_iter = max_iter;
  nw->R = sdae__take(a, n, 1);
  nw->dy = sdae__take(a, n, 1);
  nw->y0 = sdae__take(a, n, 1);
  nw->fd_y = nw->fd_plus = nw->fd_minus = nw->J = nw->LU = NULL;
  nw->piv = NULL;
  nw->own_matrix = 0;
  nw->iters = 0;
  nw->residual_last = 0.0;
  nw->keep = nw->kept = 0;
  nw->coeff = nw->kept_coeff = 0.0;
  nw->kept_age = 0;
  nw->refreshes = nw->retries = 0;
  nw->krylov = NULL;
  nw->krylov_iters = 0;
}

void sdae__newton_carve_krylov(sdae_newton *nw, size_t n, size_t m, double rtol, double tol,
                               unsigned max_iter, sdae_arena *a) {
  sdae__newton_carve_hooks(nw, n, tol, max_iter, a);
  nw->fd_y = sdae__take(a, n, 1);
  nw->fd_plus = sdae__take(a, n, 1);
  sdae__gmres_carve(&nw->gmres, n, m, a);
  nw->krylov = &nw->gmres;
  nw->krylov_rtol = rtol;
}

void sdae__newton_forget(sdae_newton *nw) { nw->kept = 0; }

static int small_dense(const sdae_newton *nw);
static size_t band_cols(const sdae_newton *nw);

/* Newton's own factors live in J (small dense) or in LU, with the pivots; an owner's (a Newton
 * of hooks) are the owner's to write */
void sdae__newton_state(sdae_newton *nw, sdae_bytes *b) {
  size_t n = nw->n;
  sdae__bytes_flag(b, &nw->kept);
  sdae__bytes_doubles(b, &nw->kept_coeff, 1);
  sdae__bytes(b, &nw->kept_age, sizeof nw->kept_age);
  sdae__bytes(b, &nw->refreshes, sizeof nw->refreshes);
  sdae__bytes(b, &nw->retries, sizeof nw->retries);
  if (!nw->own_matrix) return;
  if (small_dense(nw))
    sdae__bytes_doubles(b, nw->J, n * n);
  else
    sdae__bytes_doubles(b, nw->LU, n * band_cols(nw));
  sdae__bytes(b, nw->piv, n * sizeof *nw->piv);
}

int sdae__newton_state_valid(const sdae_newton *nw) {
  for (size_t i = 0; nw->kept && nw->own_matrix && i < nw->n; i++)
    if (nw->piv[i] >= nw->n) return 0;
  return 1;
}

void sdae__newton_adopt(sdae_newton *nw, double coeff) {
  nw->kept = 1, nw->kept_coeff = coeff, nw->kept_age = 0;
}

/* max(r, |v|) written out: fmax is a call (NaN rules); the values here are finite */
static double max_abs(double r, double v) { return fabs(v) > r ? fabs(v) : r; }

/* the sum of v_i - v_i: 0 when every v_i is finite, NaN otherwise (Inf - Inf is NaN); in the
 * loop that measures v, a finiteness test without a pass of its own */
static double nan_probe(double probe, double v) { return probe + (v - v); }

/* one entry of the implicit form R(y) = y - x - coeff (f(y) + shift) (CVODE's, of a step) */
static double implicit_r(double y, double x, double h, double f, double shift) {
  return y - x - h * (f + shift);
}

/* R from f(y) in place, in the implicit form */
static void implicit_form(const sdae_newton *nw, const sdae_newton_system *sys, const double *y,
                          double *R) {
  for (size_t i = 0; i < nw->n; i++)
    R[i] = implicit_r(y[i], sys->x[i], nw->coeff, R[i], sys->shift ? sys->shift[i] : 0.0);
}

/* R(y) into out: the system's residual, or its f in the implicit form */
static int system_R(const sdae_newton *nw, const sdae_newton_system *sys, const double *y,
                    double *out) {
  int rc;
  if (!sys->f) return sys->residual(sys->ctx, y, out);
  if ((rc = sys->f(sys->ctx, y, out)) == SDAE_OK) implicit_form(nw, sys, y, out);
  return rc;
}

/* R(y) into nw->R, and ||R||_inf into residual_last; a NaN or Inf in R is SDAE_ERR_NONFINITE
 * (max_abs would pass over a NaN, and R = 0 would then read as converged) */
static int residual(sdae_newton *nw, const sdae_newton_system *sys, const double *y) {
  double *R = nw->R, norm = 0.0, probe = 0.0;
  size_t n = nw->n;
  int rc;
  if (!sys->f) {
    if ((rc = sys->residual(sys->ctx, y, R)) != SDAE_OK) return rc;
    for (size_t i = 0; i < n; i++) {
      norm = max_abs(norm, R[i]);
      probe = nan_probe(probe, R[i]);
    }
  } else { /* the implicit form, measured in the pass that forms it */
    const double *x = sys->x, *shift = sys->shift, h = nw->coeff;
    if ((rc = sys->f(sys->ctx, y, R)) != SDAE_OK) return rc;
    for (size_t i = 0; i < n; i++) {
      R[i] = implicit_r(y[i], x[i], h, R[i], shift ? shift[i] : 0.0);
      norm = max_abs(norm, R[i]);
      probe = nan_probe(probe, R[i]);
    }
  }
  if (probe != 0.0) return SDAE_ERR_NONFINITE;
  nw->residual_last = norm;
  return SDAE_OK;
}

static size_t band_cols(const sdae_newton *nw) { return sdae__lu_band_cols(nw->band, nw->band); }

/* a dense Newton keeps dR/dy in nw->J (and factors it there when small); a banded one builds it
 * directly in GSL's band storage nw->LU */
static int small_dense(const sdae_newton *nw) {
  return nw->band + 1 == nw->n && nw->n <= SDAE_SMALL_DENSE; /* J exists exactly when dense */
}

static void set_entry(sdae_newton *nw, size_t i, size_t j, double v) {
  if (nw->J)
    nw->J[i * nw->n + j] = v;
  else
    nw->LU[j * band_cols(nw) + 2 * nw->band + i - j] = v;
}

/* one colour group: columns first, first + w, ...; h_j (kept in nw->dy) ~ eps^(1/3) |y_j|, the
 * step that balances truncation and rounding, made exactly representable */
static int fd_group(sdae_newton *nw, const sdae_newton_system *sys, const double *y, size_t first,
                    size_t w) {
  size_t n = nw->n, b = nw->band;
  int rc;
  memcpy(nw->fd_y, y, n * sizeof *y);
  for (size_t j = first; j < n; j += w) {
    nw->fd_y[j] = y[j] + cbrt(DBL_EPSILON) * fmax(1.0, fabs(y[j]));
    nw->dy[j] = nw->fd_y[j] - y[j];
  }
  rc = system_R(nw, sys, nw->fd_y, nw->fd_plus);
  for (size_t j = first; j < n; j += w) nw->fd_y[j] = y[j] - nw->dy[j];
  if (rc == SDAE_OK) rc = system_R(nw, sys, nw->fd_y, nw->fd_minus);
  if (rc != SDAE_OK) return rc;
  for (size_t j = first; j < n; j += w) {
    size_t i0 = j > b ? j - b : 0, i1 = j + b < n ? j + b : n - 1;
    for (size_t i = i0; i <= i1; i++)
      set_entry(nw, i, j, (nw->fd_plus[i] - nw->fd_minus[i]) / (2.0 * nw->dy[j]));
  }
  return SDAE_OK;
}

static int finite_differences(sdae_newton *nw, const sdae_newton_system *sys, const double *y) {
  size_t n = nw->n, w = 2 * nw->band + 1 < n ? 2 * nw->band + 1 : n;
  int rc = SDAE_OK;
  if (!nw->J) memset(nw->LU, 0, n * band_cols(nw) * sizeof *nw->LU); /* the band's fill-in */
  for (size_t g = 0; g < w && rc == SDAE_OK; g++) rc = fd_group(nw, sys, y, g, w);
  return rc;
}

/* dR/dy at y, factored: Newton's own linear setup */
/* dR/dy = I - coeff J from the system's J in place, in the pass that tests it is finite */
static int from_jacobian(sdae_newton *nw) {
  size_t n = nw->n;
  double *J = nw->J, h = -nw->coeff, probe = 0.0;
  for (size_t k = 0; k < n * n; k++) {
    J[k] *= h;
    probe = nan_probe(probe, J[k]);
  }
  for (size_t i = 0; i < n; i++) J[i * n + i] += 1.0;
  return probe == 0.0 ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int newton_matrix(sdae_newton *nw, const sdae_newton_system *sys, const double *y) {
  size_t n = nw->n, b = nw->band;
  int analytic = nw->J && sys->jacobian;
  int rc = analytic ? sys->jacobian(sys->ctx, y, nw->J) : finite_differences(nw, sys, y);
  if (rc != SDAE_OK) return rc;
  if (nw->J) {
    rc = analytic                         ? from_jacobian(nw)
         : sdae__all_finite(nw->J, n * n) ? SDAE_OK
                                          : SDAE_ERR_NONFINITE;
    if (rc != SDAE_OK) return rc;
    if (small_dense(nw)) return sdae__lu_small_factor(nw->J, nw->piv, n);
    sdae__lu_pack(nw->J, n, b, b, nw->LU);
  } else if (!sdae__all_finite(nw->LU, n * band_cols(nw))) {
    return SDAE_ERR_NONFINITE;
  }
  return sdae__lu_factor(nw->LU, nw->piv, n, b, b);
}

/* dy = (dR/dy)^-1 R with the factors: Newton's own linear solve */
static void newton_solve(sdae_newton *nw) {
  size_t n = nw->n, b = nw->band;
  if (small_dense(nw))
    sdae__lu_small_solve(nw->J, nw->piv, n, nw->R, nw->dy);
  else
    sdae__lu_factored_solve(nw->LU, nw->piv, n, b, b, nw->R, nw->dy);
}

/* ---- the linear setup and solve: the system's, or Newton's own ---- */

static int setup(sdae_newton *nw, const sdae_newton_system *sys, const double *y, int chord) {
  int rc;
  nw->kept = 0; /* the kept matrix, if any, is being replaced */
  if (chord) nw->refreshes++;
  rc = sys->setup ? sys->setup(sys->ctx, y) : newton_matrix(nw, sys, y);
  nw->built = rc == SDAE_OK;
  return rc;
}

/* Newton-Krylov's product dR/dy x ~ (R(y + s x) - R(y)) / s, s balancing truncation and
 * rounding (sqrt(eps) of y's size over x's, as KINSOL's), R(y) in nw->R */
typedef struct krylov_ctx {
  sdae_newton *nw;
  const sdae_newton_system *sys;
  const double *y;
} krylov_ctx;

static int krylov_apply(void *ctx, const double *x, double *out) {
  const krylov_ctx *k = ctx;
  sdae_newton *nw = k->nw;
  size_t n = nw->n;
  double xs = 0.0, ys = 0.0, s;
  int rc;
  for (size_t i = 0; i < n; i++) {
    xs = fmax(xs, fabs(x[i]));
    ys = fmax(ys, fabs(k->y[i]));
  }
  if (xs == 0.0) {
    memset(out, 0, n * sizeof *out);
    return SDAE_OK;
  }
  s = 0x1p-26 * (1.0 + ys) / xs;
  for (size_t i = 0; i < n; i++) nw->fd_y[i] = k->y[i] + s * x[i];
  if ((rc = system_R(nw, k->sys, nw->fd_y, nw->fd_plus)) != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) out[i] = (nw->fd_plus[i] - nw->R[i]) / s;
  return SDAE_OK;
}

static int krylov_precond(void *ctx, const double *r, double *z) {
  const krylov_ctx *k = ctx;
  return k->sys->solve(k->sys->ctx, r, z);
}

static int solve(sdae_newton *nw, const sdae_newton_system *sys, const double *y) {
  if (nw->krylov && sys->solve) {
    krylov_ctx k = {nw, sys, y};
    sdae_gmres_ops ops = {krylov_apply, krylov_precond, &k};
    int rc = sdae__gmres_solve(nw->krylov, &ops, nw->R, nw->dy, nw->krylov_rtol);
    nw->krylov_iters += nw->krylov->iters;
    return rc;
  }
  if (sys->solve) return sys->solve(sys->ctx, nw->R, nw->dy);
  newton_solve(nw);
  return SDAE_OK;
}

/* ---- the convergence test, one for every solve (SUNDIALS' fourth hook), and its constants ---- */

/* Newton rebuilds the matrix at every iterate whose update was above this (relative): below it
 * the iterate is within about L 1e-10 of the root (L = h times the second derivative of phi,
 * Newton's constant) and the matrix of the iterate before differs by about L 1e-5, so the step
 * with it lands within L^2 1e-15 of the root: the last iterations only confirm convergence */
static const double reuse_below = 1e-5;
/* a chord (keep = 1) whose estimated rate exceeds this rebuilds the matrix at the iterate: each
 * further iteration would gain less than a digit */
static const double rate_slow = 0.1;
/* a chord whose update shrinks by less than this factor does not converge (IDA's RATEMAX): a
 * kept matrix is given up and the solve retried from its start with a fresh one (rebuilt at
 * such an iterate, Newton may go on to another root: Phi^-1's other sheet) */
static const double rate_diverging = 0.9;
/* the rate estimate keeps this fraction of the last one (CVODE's CRDOWN) */
static const double rate_memory = 0.3;
/* a chord has converged when its update is at rounding of y (two ulps of 1 + ||y||), or what
 * the rate predicts is left is below a thousandth of an ulp: what a chord leaves has one sign
 * solve after solve (it approaches from one side along the motion), and the discrete
 * gradient's H or Phi^-1's xi_c sums it over many steps */
static const double chord_moved = 2.0 * DBL_EPSILON;
static const double chord_left = 1e-3 * DBL_EPSILON;
/* Newton at the noise of its residual: with a matrix built within reuse_below of the root, an
 * exact residual would make the next update about Newton's constant times the square of the
 * last; an update that does not shrink (by rate_diverging) is the residual's own noise (a
 * mechanism's ill-conditioned mass amplifies its rounding), and no iteration improves on the
 * iterate. It is accepted there when at most this (relative): the noise of a difference
 * quotient of step sqrt(eps), the noisiest residual the library forms */
static const double noise_most = 0x1p-26; /* sqrt(DBL_EPSILON) */
/* the kept matrix is rebuilt once coeff differs from its own by more than this (CVODE's
 * DGMAX) */
static const double keep_coeff_change = 0.3;
/* and after this many solves (CVODE's MSBP: 20 steps) */
#define NEWTON_KEEP_SOLVES 20

/* one attempt's progress: m updates since the matrix was built (fresh: at the iterate of
 * update 0; near: and that update was within reuse_below), the last update, the rate */
typedef struct attempt_state {
  int chord, fresh, near;
  int short_solve; /* the last update's GMRES stopped short of its tolerance: neither
                    * convergence nor the residual's noise */
  unsigned m;
  double prev, rate;
} attempt_state;

/* the updates stopped shrinking with a matrix from within reuse_below: the residual's noise */
static int at_noise(const attempt_state *st, double del, double scale) {
  return st->near && !st->short_solve && st->m > 0 && del > rate_diverging * st->prev &&
         del <= noise_most * scale;
}

/* converged after an update del (scale: 1 + ||y||): below tol, and for a chord at rounding or
 * predicted to leave nothing; a step of Newton (the matrix at its own iterate, or without
 * chord the last iterate's within reuse_below) leaves its square times Newton's constant */
static int converged(const sdae_newton *nw, const attempt_state *st, double del, double scale) {
  /* a small update from a GMRES that stopped short says nothing of the residual (a singular
   * preconditioner gives none at all) */
  if (del > nw->tol * scale || st->short_solve) return 0;
  if (!st->chord || (st->fresh && st->m == 0)) return 1;
  return del <= chord_moved * scale ||
         (st->m >= 2 && st->rate < 1.0 && st->rate / (1.0 - st->rate) * del <= chord_left * scale);
}

typedef enum { GO_ON, CONVERGED, REBUILD, DIVERGED } verdict;

/* the test after an update del; a chord's rate as CVODE estimates it, rate = max(CRDOWN rate,
 * del_m / del_m-1) */
static verdict judge(const sdae_newton *nw, attempt_state *st, double del, double scale) {
  if (st->fresh && st->m == 0) st->near = del <= reuse_below * scale;
  if (!st->chord) {
    if (del <= nw->tol * scale || at_noise(st, del, scale)) return CONVERGED;
    return del > reuse_below * scale ? REBUILD : GO_ON;
  }
  if (st->m > 0) st->rate = max_abs(rate_memory * st->rate, del / st->prev); /* both >= 0 */
  if (converged(nw, st, del, scale) || at_noise(st, del, scale)) return CONVERGED;
  if (st->m > 0 && del > rate_diverging * st->prev) return DIVERGED;
  /* far from the root a matrix from the iterate is Newton's: rebuilt as without chord */
  if (st->fresh && st->m == 0) return del > reuse_below * scale ? REBUILD : GO_ON;
  return st->m > 0 && st->rate > rate_slow ? REBUILD : GO_ON;
}

/* y -= dy; the update's and the new iterate's sizes */
static int update(sdae_newton *nw, double *y, double *del, double *scale) {
  size_t n = nw->n;
  const double *dy = nw->dy;
  double dy_norm = 0.0, y_norm = 0.0, probe = 0.0;
  for (size_t i = 0; i < n; i++) {
    y[i] -= dy[i];
    dy_norm = max_abs(dy_norm, dy[i]);
    y_norm = max_abs(y_norm, y[i]);
    probe = nan_probe(probe, y[i]);
  }
  *del = dy_norm;
  *scale = 1.0 + y_norm; /* multiplied, not divided: Newton's chain waits on this test */
  return probe == 0.0 ? SDAE_OK : SDAE_ERR_NONFINITE;
}

/* ---- one attempt: at most max_iter iterations from y, the matrix built first when build ---- */
static int attempt(sdae_newton *nw, const sdae_newton_system *sys, double *y, int chord,
                   int build) {
  attempt_state st = {chord, 0, 0, 0, 0, 0.0, 0.0};
  int kept = !build; /* the attempt starts with a kept matrix */
  for (unsigned it = 0; it < nw->max_iter; it++) {
    double del, scale;
    verdict v;
    int rc;
    nw->iters++;
    if ((rc = residual(nw, sys, y)) != SDAE_OK) return rc;
    if (nw->residual_last == 0.0) return SDAE_OK;
    if (build) {
      if ((rc = setup(nw, sys, y, chord)) != SDAE_OK) return rc;
      st.fresh = 1, st.near = 0, st.m = 0, st.rate = 0.0;
    }
    if ((rc = solve(nw, sys, y)) != SDAE_OK) return rc;
    st.short_solve = nw->krylov && sys->solve && !nw->krylov->reached;
    if ((rc = update(nw, y, &del, &scale)) != SDAE_OK) return kept ? SDAE_ERR_NEWTON : rc;
    v = judge(nw, &st, del, scale);
    if (v == CONVERGED) return SDAE_OK;
    if (v == DIVERGED && kept) return SDAE_ERR_NEWTON; /* retried from the start */
    build = v == REBUILD || v == DIVERGED;
    st.prev = del;
    st.m++;
  }
  return SDAE_ERR_NEWTON;
}

/* a failure of a kept matrix that a matrix built at the start may cure: no convergence (an
 * iterate that is not finite among them), an iterate outside Phi^-1's domain, a singular matrix
 * at an iterate; a callback's own failure is the step's */
static int curable(int rc) {
  return rc == SDAE_ERR_NEWTON || rc == SDAE_ERR_PHI_INV || rc == SDAE_ERR_SINGULAR;
}

static int keep_serves(const sdae_newton *nw, double coeff) {
  return nw->kept && nw->kept_age < NEWTON_KEEP_SOLVES &&
         fabs(coeff - nw->kept_coeff) <= keep_coeff_change * fabs(nw->kept_coeff);
}

int sdae__newton_solve(sdae_newton *nw, const sdae_newton_system *sys, double coeff, double *y) {
  /* a matrix from the system's own Jacobian costs one call: rebuilt as Newton needs it */
  int chord = nw->keep && !(sys->jacobian && nw->J && !sys->setup);
  int kept = chord && keep_serves(nw, coeff), rc;
  nw->coeff = coeff;
  nw->built = 0;
  if (kept) {
    sdae__copy(nw->y0, y, nw->n);
    nw->kept_age++;
  }
  for (;;) {
    rc = attempt(nw, sys, y, chord, !kept);
    if (rc == SDAE_OK || !kept || !curable(rc)) break;
    sdae__copy(y, nw->y0, nw->n); /* CVODE's recovery: the same solve, a fresh matrix */
    nw->retries++;
    kept = 0;
  }
  if (rc != SDAE_OK) {
    nw->kept = 0; /* a failed solve: the next one builds its own */
    return rc;
  }
  /* a matrix built by this solve is kept; one that converged at once (R = 0 at the start, as at
   * an equilibrium) built none, and no matrix is kept */
  if (chord && !nw->kept && nw->built) nw->kept = 1, nw->kept_coeff = coeff, nw->kept_age = 0;
  return SDAE_OK;
}
