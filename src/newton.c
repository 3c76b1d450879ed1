/* Newton's method for the implicit maps and for the stages of composed maps: solves
 *
 *   R(y) = y - x - h (phi(x, y) + shift) = 0,   M = dR/dy = I - h dphi/dy
 *
 * (for a step of eq. 11/15: x = mu, h = T, shift = Q(xi, mu) xi). dphi/dy is the map's own
 * Jacobian when it has one and the model is dense, central finite differences otherwise: columns
 * 2b + 1 apart do not share a row of a band-b matrix, so each colour group of columns costs two
 * evaluations of phi. M is factored by LU (lu.c): written out for small dense models, GSL's
 * banded LU otherwise (dense is the band n - 1).
 *
 * M is rebuilt at every iterate (Newton, quadratic convergence) except after an update below
 * reuse_below (1 + ||y||): by then the iterate is within about L 1e-10 of the root (L = h times
 * the second derivative of phi, Newton's constant) and the kept M, from the previous iterate,
 * differs by about L 1e-5, so the step with it lands within L^2 1e-15 of the root: far below
 * rounding for any L < 0.1 (at T = 0.001, L is about 1e-2 for the chain). Those last iterations
 * only confirm convergence; keeping M spares them a finite-difference Jacobian (2 (2b + 1)
 * evaluations of phi) or an analytic one, and a factorization. The steps that contract, with
 * larger updates, keep a fresh M (a chord iteration there leaves errors of a few ulps that are
 * not random: H then drifts under the discrete gradient). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "internal.h"

/* M is kept for the next iteration when the last update was at most this (relative) */
static const double reuse_below = 1e-5;

typedef struct problem {
  const sdae_map_type *map;
  double t, h;
  const double *x, *shift;
  int analytic; /* dphi/dy from the map's Jacobian */
} problem;


/* max(r, |v|) written out: fmax is a call (NaN rules); the values here are finite */
static double max_abs(double r, double v) { return fabs(v) > r ? fabs(v) : r; }

static int phi(sdae_stepper *s, const problem *P, const double *y, double *out) {
  s->stats.phi_evals++;
  return P->map->phi(s, P->t, P->h, P->x, y, out);
}

/* R(y) into s->R, and ||R||_inf into the statistics */
static int residual(sdae_stepper *s, const problem *P, const double *y) {
  size_t n = s->model.n_mu;
  double norm = 0.0;
  int rc = phi(s, P, y, s->phi);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) {
    s->R[i] = y[i] - P->x[i] - P->h * (s->phi[i] + (P->shift ? P->shift[i] : 0.0));
    norm = max_abs(norm, s->R[i]);
  }
  s->stats.newton_residual_last = norm;
  return SDAE_OK;
}

static size_t band_cols(const sdae_stepper *s) { return sdae__lu_band_cols(s->band, s->band); }

/* a dense model keeps M in s->J (and factors it there when small); a banded one builds it
 * directly in GSL's band storage s->LU */
static int small_dense(const sdae_stepper *s) {
  return s->J && s->model.n_mu <= SDAE_SMALL_DENSE;
}

static void set_entry(sdae_stepper *s, size_t i, size_t j, double v) {
  if (s->J)
    s->J[i * s->model.n_mu + j] = v;
  else
    s->LU[j * band_cols(s) + 2 * s->band + i - j] = v;
}

/* one colour group: columns first, first + w, ...; h_j (kept in s->dy) ~ eps^(1/3) |y_j|, the
 * step that balances truncation and rounding, made exactly representable */
static int fd_group(sdae_stepper *s, const problem *P, const double *y, size_t first, size_t w) {
  size_t n = s->model.n_mu, b = s->band;
  int rc;
  memcpy(s->fd_y, y, n * sizeof *y);
  for (size_t j = first; j < n; j += w) {
    s->fd_y[j] = y[j] + cbrt(DBL_EPSILON) * fmax(1.0, fabs(y[j]));
    s->dy[j] = s->fd_y[j] - y[j];
  }
  rc = phi(s, P, s->fd_y, s->fd_plus);
  for (size_t j = first; j < n; j += w) s->fd_y[j] = y[j] - s->dy[j];
  if (rc == SDAE_OK) rc = phi(s, P, s->fd_y, s->fd_minus);
  if (rc != SDAE_OK) return rc;
  for (size_t j = first; j < n; j += w) {
    size_t i0 = j > b ? j - b : 0, i1 = j + b < n ? j + b : n - 1;
    for (size_t i = i0; i <= i1; i++) {
      double d = (s->fd_plus[i] - s->fd_minus[i]) / (2.0 * s->dy[j]);
      set_entry(s, i, j, (i == j ? 1.0 : 0.0) - P->h * d);
    }
  }
  return SDAE_OK;
}

static int finite_differences(sdae_stepper *s, const problem *P, const double *y) {
  size_t n = s->model.n_mu, w = 2 * s->band + 1 < n ? 2 * s->band + 1 : n;
  int rc = SDAE_OK;
  if (!s->J) memset(s->LU, 0, n * band_cols(s) * sizeof *s->LU); /* the band's fill-in too */
  for (size_t g = 0; g < w && rc == SDAE_OK; g++) rc = fd_group(s, P, y, g, w);
  return rc;
}

static int analytic_jacobian(sdae_stepper *s, const problem *P, const double *y) {
  size_t n = s->model.n_mu;
  int rc = P->map->jac(s, P->t, P->h, P->x, y, s->J);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) s->J[i * n + j] = (i == j ? 1.0 : 0.0) - P->h * s->J[i * n + j];
  return SDAE_OK;
}

/* M = I - h dphi/dy at y, factored */
static int newton_matrix(sdae_stepper *s, const problem *P, const double *y) {
  size_t n = s->model.n_mu, b = s->band;
  int rc = P->analytic ? analytic_jacobian(s, P, y) : finite_differences(s, P, y);
  if (rc != SDAE_OK) return rc;
  if (s->J) {
    if (!sdae__all_finite(s->J, n * n)) return SDAE_ERR_NONFINITE;
    if (small_dense(s)) return sdae__lu_small_factor(s->J, s->piv, n);
    sdae__lu_pack(s->J, n, b, b, s->LU);
  } else if (!sdae__all_finite(s->LU, n * band_cols(s))) {
    return SDAE_ERR_NONFINITE;
  }
  return sdae__lu_factor(s->LU, s->piv, n, b, b);
}

/* dy = M^-1 R with the factors */
static void newton_solve(sdae_stepper *s) {
  size_t n = s->model.n_mu, b = s->band;
  if (small_dense(s))
    sdae__lu_small_solve(s->J, s->piv, n, s->R, s->dy);
  else
    sdae__lu_factored_solve(s->LU, s->piv, n, b, b, s->R, s->dy);
}

/* One iteration from y; *done when the update is below tolerance or R(y) = 0. */
static int iterate(sdae_stepper *s, const problem *P, int *refresh, double *y, int *done) {
  size_t n = s->model.n_mu;
  double dy_norm = 0.0, y_norm = 0.0, scale; /* the update is measured against 1 + ||y|| */
  int rc = residual(s, P, y);
  if (rc != SDAE_OK) return rc;
  if (s->stats.newton_residual_last == 0.0) {
    *done = 1;
    return SDAE_OK;
  }
  if (*refresh && (rc = newton_matrix(s, P, y)) != SDAE_OK) return rc;
  newton_solve(s);
  for (size_t i = 0; i < n; i++) {
    y[i] -= s->dy[i];
    dy_norm = max_abs(dy_norm, s->dy[i]);
    y_norm = max_abs(y_norm, y[i]);
  }
  if (!sdae__all_finite(y, n)) return SDAE_ERR_NONFINITE;
  scale = 1.0 + y_norm; /* multiplied, not divided: Newton's chain waits on this test */
  *done = dy_norm <= s->opt.newton_tol * scale;
  *refresh = dy_norm > reuse_below * scale;
  return SDAE_OK;
}

static int analytic(const sdae_stepper *s, const sdae_map_type *map) {
  return s->J && map->jac && map->jac_given && map->jac_given(&s->model, &s->opt);
}

int sdae__newton(sdae_stepper *s, const sdae_map_type *map, double t, double h, const double *x,
                 const double *shift, double *y) {
  problem P = {map, t, h, x, shift, analytic(s, map)};
  int refresh = 1;
  int done = 0, rc = SDAE_OK;
  unsigned it = 0;
  while (!done && rc == SDAE_OK && it < s->opt.newton_max_iter) {
    it++;
    rc = iterate(s, &P, &refresh, y, &done);
  }
  s->stats.newton_iters_last += it;
  if (rc != SDAE_OK) return rc;
  return done ? SDAE_OK : SDAE_ERR_NEWTON;
}
