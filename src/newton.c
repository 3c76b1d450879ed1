/* Newton's method for the implicit maps and for the stages of composed maps: solves
 *
 *   R(y) = y - x - h (phi(x, y) + shift) = 0,   dR/dy = I - h dphi/dy
 *
 * (for a step of eq. 11/15: x = mu, h = T, shift = Q(xi, mu) xi) with an LU solve on a band
 * (lu.c; dense is the band n - 1). dphi/dy is the map's own Jacobian when it has one and the
 * model is dense, central finite differences otherwise: columns 2b + 1 apart do not share a
 * row of a band-b matrix, so each colour group of columns costs two evaluations of phi. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "internal.h"

typedef struct problem {
  const sdae_map_type *map;
  double t, h;
  const double *x, *shift;
} problem;

static double norm_inf(const double *v, size_t n) {
  double r = 0.0;
  for (size_t i = 0; i < n; i++) r = fmax(r, fabs(v[i]));
  return r;
}

static int phi(sdae_stepper *s, const problem *P, const double *y, double *out) {
  s->stats.phi_evals++;
  return P->map->phi(s, P->t, P->h, P->x, y, out);
}

static int residual(sdae_stepper *s, const problem *P, const double *y) {
  size_t n = s->model.n_mu;
  int rc = phi(s, P, y, s->phi);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++)
    s->R[i] = y[i] - P->x[i] - P->h * (s->phi[i] + (P->shift ? P->shift[i] : 0.0));
  return SDAE_OK;
}

static size_t band_cols(const sdae_stepper *s) { return sdae__lu_band_cols(s->band, s->band); }

/* one colour group: columns first, first + w, ...; h_j (kept in s->dy) ~ eps^(1/3) |y_j|, the
 * step that balances truncation and rounding, made exactly representable */
static int fd_group(sdae_stepper *s, const problem *P, const double *y, size_t first, size_t w) {
  size_t n = s->model.n_mu, b = s->band, ld = band_cols(s);
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
      s->LU[j * ld + 2 * b + i - j] = (i == j ? 1.0 : 0.0) - P->h * d;
    }
  }
  return SDAE_OK;
}

static int analytic(const sdae_stepper *s, const sdae_map_type *map) {
  return s->J && map->jac && map->jac_given && map->jac_given(&s->model, &s->opt);
}

/* I - h dphi/dy in band format in s->LU */
static int newton_matrix(sdae_stepper *s, const problem *P, const double *y) {
  size_t n = s->model.n_mu, w = 2 * s->band + 1 < n ? 2 * s->band + 1 : n;
  int rc = SDAE_OK;
  if (analytic(s, P->map)) {
    rc = P->map->jac(s, P->t, P->h, P->x, y, s->J);
    if (rc != SDAE_OK) return rc;
    for (size_t i = 0; i < n * n; i++) s->J[i] = (i % (n + 1) == 0 ? 1.0 : 0.0) - P->h * s->J[i];
    sdae__lu_pack(s->J, n, s->band, s->band, s->LU);
  } else {
    memset(s->LU, 0, n * band_cols(s) * sizeof *s->LU);
    for (size_t g = 0; g < w && rc == SDAE_OK; g++) rc = fd_group(s, P, y, g, w);
    if (rc != SDAE_OK) return rc;
  }
  return sdae__all_finite(s->LU, n * band_cols(s)) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

/* One Newton iteration from y; *done when the update is below tolerance or R(y) = 0. */
static int iterate(sdae_stepper *s, const problem *P, double *y, int *done) {
  size_t n = s->model.n_mu;
  int rc = residual(s, P, y);
  if (rc != SDAE_OK) return rc;
  s->stats.newton_residual_last = norm_inf(s->R, n);
  if (s->stats.newton_residual_last == 0.0) {
    *done = 1;
    return SDAE_OK;
  }
  rc = newton_matrix(s, P, y);
  if (rc == SDAE_OK) rc = sdae__lu_solve(s->LU, s->piv, n, s->band, s->band, s->R, s->dy);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) y[i] -= s->dy[i];
  if (!sdae__all_finite(y, n)) return SDAE_ERR_NONFINITE;
  *done = norm_inf(s->dy, n) <= s->opt.newton_tol * (1.0 + norm_inf(y, n));
  return SDAE_OK;
}

int sdae__newton(sdae_stepper *s, const sdae_map_type *map, double t, double h, const double *x,
                 const double *shift, double *y) {
  problem P = {map, t, h, x, shift};
  int done = 0, rc = SDAE_OK;
  unsigned it = 0;
  while (!done && rc == SDAE_OK && it < s->opt.newton_max_iter) {
    it++;
    rc = iterate(s, &P, y, &done);
  }
  s->stats.newton_iters_last += it;
  if (rc != SDAE_OK) return rc;
  return done ? SDAE_OK : SDAE_ERR_NEWTON;
}
