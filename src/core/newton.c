/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Newton's method on R(y) = 0 (core/newton.h). The maps hand it
 *
 *   R(y) = y - x - h (phi(x, y) + shift),   dR/dy = I - h dphi/dy
 *
 * (maps/map_solve.c). dR/dy is the system's own Jacobian when it has one and Newton is dense,
 * central differences of R otherwise: columns 2b + 1 apart do not share a row of a band-b matrix,
 * so each colour group of columns costs two residuals. dR/dy is factored by LU (lu.c): written out
 * for small dense systems, GSL's banded LU otherwise (dense is the band n - 1).
 *
 * dR/dy is rebuilt at every iterate (Newton, quadratic convergence) except after an update below
 * reuse_below (1 + ||y||): by then the iterate is within about L 1e-10 of the root (L = h times
 * the second derivative of phi, Newton's constant) and the kept matrix, from the previous
 * iterate, differs by about L 1e-5, so the step with it lands within L^2 1e-15 of the root: far
 * below rounding for any L < 0.1 (at T = 0.001, L is about 1e-2 for the chain). Those last
 * iterations only confirm convergence; keeping the matrix spares them a difference Jacobian
 * (2 (2b + 1) residuals) or an analytic one, and a factorization. The steps that contract, with
 * larger updates, keep a fresh matrix (a chord iteration there leaves errors of a few ulps that
 * are not random: H then drifts under the discrete gradient). */
#include <float.h>
#include <math.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "callback.h"
#include "lu.h"
#include "newton.h"

/* dR/dy is kept for the next iteration when the last update was at most this (relative) */
static const double reuse_below = 1e-5;

void sdae__newton_carve(sdae_newton *nw, size_t n, size_t band, double tol, unsigned max_iter,
                        sdae_arena *a) {
  nw->n = n;
  nw->band = band;
  nw->tol = tol;
  nw->max_iter = max_iter;
  nw->R = sdae__take(a, n, 1);
  nw->dy = sdae__take(a, n, 1);
  nw->fd_y = sdae__take(a, n, 1);
  nw->fd_plus = sdae__take(a, n, 1);
  nw->fd_minus = sdae__take(a, n, 1);
  nw->J = band == n - 1 ? sdae__take(a, n, n) : NULL; /* dense: analytic Jacobians */
  nw->LU = sdae__take(a, n, sdae__lu_band_cols(band, band));
  nw->piv = sdae__take_pivots(a, n);
  nw->keep = nw->kept = 0;
  nw->kept_coeff = 0.0;
  nw->kept_age = 0;
  nw->refreshes = 0;
}

void sdae__newton_forget(sdae_newton *nw) { nw->kept = 0; }

static int small_dense(const sdae_newton *nw);
static size_t band_cols(const sdae_newton *nw);

/* the factors live in J (small dense) or in LU, with the pivots */
void sdae__newton_state(sdae_newton *nw, sdae_bytes *b) {
  size_t n = nw->n;
  sdae__bytes_flag(b, &nw->kept);
  sdae__bytes_doubles(b, &nw->kept_coeff, 1);
  sdae__bytes(b, &nw->kept_age, sizeof nw->kept_age);
  sdae__bytes(b, &nw->refreshes, sizeof nw->refreshes);
  if (small_dense(nw))
    sdae__bytes_doubles(b, nw->J, n * n);
  else
    sdae__bytes_doubles(b, nw->LU, n * band_cols(nw));
  sdae__bytes(b, nw->piv, n * sizeof *nw->piv);
}

int sdae__newton_state_valid(const sdae_newton *nw) {
  for (size_t i = 0; nw->kept && i < nw->n; i++)
    if (nw->piv[i] >= nw->n) return 0;
  return 1;
}

/* max(r, |v|) written out: fmax is a call (NaN rules); the values here are finite */
static double max_abs(double r, double v) { return fabs(v) > r ? fabs(v) : r; }

/* R(y) into nw->R, and ||R||_inf into residual_last; a NaN or Inf in R is SDAE_ERR_NONFINITE
 * (max_abs would pass over a NaN, and R = 0 would then read as converged) */
static int residual(sdae_newton *nw, const sdae_newton_system *sys, const double *y) {
  double norm = 0.0;
  int rc = sys->residual(sys->ctx, y, nw->R);
  if (rc != SDAE_OK) return rc;
  if (!sdae__all_finite(nw->R, nw->n)) return SDAE_ERR_NONFINITE;
  for (size_t i = 0; i < nw->n; i++) norm = max_abs(norm, nw->R[i]);
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
  rc = sys->residual(sys->ctx, nw->fd_y, nw->fd_plus);
  for (size_t j = first; j < n; j += w) nw->fd_y[j] = y[j] - nw->dy[j];
  if (rc == SDAE_OK) rc = sys->residual(sys->ctx, nw->fd_y, nw->fd_minus);
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

/* dR/dy at y, factored */
static int newton_matrix(sdae_newton *nw, const sdae_newton_system *sys, const double *y) {
  size_t n = nw->n, b = nw->band;
  int rc =
      nw->J && sys->jacobian ? sys->jacobian(sys->ctx, y, nw->J) : finite_differences(nw, sys, y);
  if (rc != SDAE_OK) return rc;
  if (nw->J) {
    if (!sdae__all_finite(nw->J, n * n)) return SDAE_ERR_NONFINITE;
    if (small_dense(nw)) return sdae__lu_small_factor(nw->J, nw->piv, n);
    sdae__lu_pack(nw->J, n, b, b, nw->LU);
  } else if (!sdae__all_finite(nw->LU, n * band_cols(nw))) {
    return SDAE_ERR_NONFINITE;
  }
  return sdae__lu_factor(nw->LU, nw->piv, n, b, b);
}

/* dy = (dR/dy)^-1 R with the factors */
static void newton_solve(sdae_newton *nw) {
  size_t n = nw->n, b = nw->band;
  if (small_dense(nw))
    sdae__lu_small_solve(nw->J, nw->piv, n, nw->R, nw->dy);
  else
    sdae__lu_factored_solve(nw->LU, nw->piv, n, b, b, nw->R, nw->dy);
}

/* One iteration from y; *done when the update is below tolerance or R(y) = 0. */
static int iterate(sdae_newton *nw, const sdae_newton_system *sys, int *refresh, double *y,
                   int *done) {
  size_t n = nw->n;
  double dy_norm = 0.0, y_norm = 0.0, scale; /* the update is measured against 1 + ||y|| */
  int rc = residual(nw, sys, y);
  if (rc != SDAE_OK) return rc;
  if (nw->residual_last == 0.0) {
    *done = 1;
    return SDAE_OK;
  }
  if (*refresh && (rc = newton_matrix(nw, sys, y)) != SDAE_OK) return rc;
  newton_solve(nw);
  for (size_t i = 0; i < n; i++) {
    y[i] -= nw->dy[i];
    dy_norm = max_abs(dy_norm, nw->dy[i]);
    y_norm = max_abs(y_norm, y[i]);
  }
  if (!sdae__all_finite(y, n)) return SDAE_ERR_NONFINITE;
  scale = 1.0 + y_norm; /* multiplied, not divided: Newton's chain waits on this test */
  *done = dy_norm <= nw->tol * scale;
  *refresh = dy_norm > reuse_below * scale;
  return SDAE_OK;
}

int sdae__newton_solve(sdae_newton *nw, const sdae_newton_system *sys, double *y) {
  int refresh = 1, done = 0, rc = SDAE_OK;
  unsigned it = 0;
  while (!done && rc == SDAE_OK && it < nw->max_iter) {
    it++;
    rc = iterate(nw, sys, &refresh, y, &done);
  }
  nw->iters += it;
  if (rc != SDAE_OK) return rc;
  return done ? SDAE_OK : SDAE_ERR_NEWTON;
}

/* ---- a matrix kept across solves (CVODE's rules: its DGMAX, MSBP and rate test) ---- */

/* the matrix is rebuilt once coeff differs from its own by more than this (CVODE's DGMAX) */
static const double keep_coeff_change = 0.3;
/* and after this many solves (CVODE's MSBP: 20 steps) */
#define NEWTON_KEEP_SOLVES 20
/* a chord whose estimated rate exceeds this rebuilds the matrix at the iterate */
static const double keep_rate_slow = 0.25;
/* the rate estimate keeps this fraction of the last one (CVODE's CRDOWN) */
static const double keep_rate_memory = 0.3;
/* converged with a kept matrix: the update at rounding of y (two ulps of 1 + ||y||), or what
 * the rate predicts is left below a thousandth of an ulp (the discrete gradient's H keeps the
 * sum of what is left, step after step) */
static const double keep_moved = 2.0 * DBL_EPSILON;
static const double keep_left = 1e-3 * DBL_EPSILON;

static int keep_serves(const sdae_newton *nw, double coeff) {
  return nw->kept && nw->kept_age < NEWTON_KEEP_SOLVES &&
         fabs(coeff - nw->kept_coeff) <= keep_coeff_change * fabs(nw->kept_coeff);
}

/* one chord iteration with the kept factors from y: *dy_norm the update, *scale 1 + ||y|| */
static int chord(sdae_newton *nw, const sdae_newton_system *sys, double *y, double *dy_norm,
                 double *scale, int *zero) {
  size_t n = nw->n;
  double y_norm = 0.0;
  int rc = residual(nw, sys, y);
  *dy_norm = 0.0;
  *zero = rc == SDAE_OK && nw->residual_last == 0.0;
  if (rc != SDAE_OK || *zero) return rc;
  newton_solve(nw);
  for (size_t i = 0; i < n; i++) {
    y[i] -= nw->dy[i];
    *dy_norm = max_abs(*dy_norm, nw->dy[i]);
    y_norm = max_abs(y_norm, y[i]);
  }
  *scale = 1.0 + y_norm;
  return sdae__all_finite(y, n) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

/* the chord iteration with the kept matrix, counting in *used; *slow when it no longer
 * serves (its rate), y then the last iterate, for the fresh Newton to go on from */
static int chord_solve(sdae_newton *nw, const sdae_newton_system *sys, double *y, unsigned *used,
                       int *slow) {
  double prev = 0.0, rate = 0.0;
  *slow = 0;
  for (unsigned k = 0; *used < nw->max_iter; k++) {
    double dy, scale;
    int zero, rc;
    (*used)++;
    rc = chord(nw, sys, y, &dy, &scale, &zero);
    if (rc != SDAE_OK || zero) return rc;
    if (k > 0) rate = fmax(keep_rate_memory * rate, dy / prev);
    if (dy <= nw->tol * scale &&
        (dy <= keep_moved * scale ||
         (k >= 2 && rate < 1.0 && rate / (1.0 - rate) * dy <= keep_left * scale)))
      return SDAE_OK;
    if (k > 0 && rate > keep_rate_slow) {
      *slow = 1;
      return SDAE_OK;
    }
    prev = dy;
  }
  return SDAE_ERR_NEWTON;
}

int sdae__newton_solve_kept(sdae_newton *nw, const sdae_newton_system *sys, double coeff,
                            double *y) {
  unsigned used = 0;
  int rc = SDAE_OK, slow = 1, refresh = 1, done = 0;
  if (keep_serves(nw, coeff)) {
    nw->kept_age++;
    rc = chord_solve(nw, sys, y, &used, &slow);
    if (rc == SDAE_ERR_NEWTON) /* no convergence with the kept matrix: a fresh one, a new cap */
      rc = SDAE_OK, slow = 1, nw->iters += used, used = 0;
    if (rc != SDAE_OK) nw->kept = 0; /* a failed solve: the next one builds its own */
    if (rc != SDAE_OK || !slow) {
      nw->iters += used;
      return rc;
    }
  }
  /* the matrix at the iterate, then Newton as sdae__newton_solve, within the same cap */
  nw->kept = 0;
  nw->refreshes++;
  while (!done && rc == SDAE_OK && used < nw->max_iter) {
    used++;
    rc = iterate(nw, sys, &refresh, y, &done);
  }
  nw->iters += used;
  if (rc != SDAE_OK) return rc;
  if (!done) return SDAE_ERR_NEWTON;
  nw->kept = 1, nw->kept_coeff = coeff, nw->kept_age = 0;
  return SDAE_OK;
}
