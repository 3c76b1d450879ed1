/* Newton's method for the implicit maps: solves
 *
 *   R(y) = y - mu - T (phi_T(mu, y) + Q(xi, mu) xi) = 0,   dR/dy = I - T dphi_T/dy
 *
 * with an LU solve (lu.c) on the n_mu x n_mu matrix; dphi_T/dy is the map's own Jacobian when
 * it has one and central finite differences otherwise. */
#include <float.h>
#include <math.h>

#include "internal.h"

static double norm_inf(const double *v, size_t n) {
  double r = 0.0;
  for (size_t i = 0; i < n; i++) r = fmax(r, fabs(v[i]));
  return r;
}

static int residual(sdae_stepper *s, double t, double T, const double *mu, const double *y) {
  size_t n = s->model.n_mu;
  int rc = s->opt.map->phi(s, t, T, mu, y, s->phi);
  s->stats.phi_evals++;
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) s->R[i] = y[i] - mu[i] - T * (s->phi[i] + s->Qxi[i]);
  return SDAE_OK;
}

/* Central differences, column by column: dphi/dy_j ~ (phi(y + h e_j) - phi(y - h e_j)) / 2h,
 * with h ~ eps^(1/3) scaled to y_j (the step that balances truncation and rounding). */
static int fd_jacobian(sdae_stepper *s, double t, double T, const double *mu, const double *y) {
  size_t n = s->model.n_mu;
  const sdae_map_type *map = s->opt.map;
  for (size_t i = 0; i < n; i++) s->fd_y[i] = y[i];
  for (size_t j = 0; j < n; j++) {
    double h = cbrt(DBL_EPSILON) * fmax(1.0, fabs(y[j]));
    int rc;
    s->fd_y[j] = y[j] + h;
    h = s->fd_y[j] - y[j]; /* the step actually taken, exactly representable */
    rc = map->phi(s, t, T, mu, s->fd_y, s->fd_plus);
    s->fd_y[j] = y[j] - h;
    if (rc == SDAE_OK) rc = map->phi(s, t, T, mu, s->fd_y, s->fd_minus);
    s->fd_y[j] = y[j];
    s->stats.phi_evals += 2;
    if (rc != SDAE_OK) return rc;
    for (size_t i = 0; i < n; i++) s->J[i * n + j] = (s->fd_plus[i] - s->fd_minus[i]) / (2.0 * h);
  }
  return SDAE_OK;
}

/* J = I - T dphi/dy in s->J */
static int newton_matrix(sdae_stepper *s, double t, double T, const double *mu, const double *y) {
  size_t n = s->model.n_mu;
  int rc = s->analytic_jac ? s->opt.map->jac(s, t, T, mu, y, s->J)
                           : fd_jacobian(s, t, T, mu, y);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n * n; i++) s->J[i] = -T * s->J[i];
  for (size_t i = 0; i < n; i++) s->J[i * n + i] += 1.0;
  return sdae__all_finite(s->J, n * n) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int solve(sdae_stepper *s) {
  size_t n = s->model.n_mu;
  sdae__lu_pack(s->J, n, n - 1, n - 1, s->LU);
  return sdae__lu_solve(s->LU, s->piv, n, n - 1, n - 1, s->R, s->dy);
}

/* One Newton iteration from y; *done when the update is below tolerance or R(y) = 0. */
static int iterate(sdae_stepper *s, double t, double T, const double *mu, double *y, int *done) {
  size_t n = s->model.n_mu;
  int rc = residual(s, t, T, mu, y);
  if (rc != SDAE_OK) return rc;
  s->stats.newton_residual_last = norm_inf(s->R, n);
  if (s->stats.newton_residual_last == 0.0) {
    *done = 1;
    return SDAE_OK;
  }
  rc = newton_matrix(s, t, T, mu, y);
  if (rc == SDAE_OK) rc = solve(s);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) y[i] -= s->dy[i];
  if (!sdae__all_finite(y, n)) return SDAE_ERR_NONFINITE;
  *done = norm_inf(s->dy, n) <= s->opt.newton_tol * (1.0 + norm_inf(y, n));
  return SDAE_OK;
}

int sdae__newton(sdae_stepper *s, double t, double T, const double *mu, double *y) {
  int done = 0, rc = SDAE_OK;
  unsigned it = 0;
  while (!done && rc == SDAE_OK && it < s->opt.newton_max_iter) {
    it++;
    rc = iterate(s, t, T, mu, y, &done);
  }
  s->stats.newton_iters_last = it;
  if (rc != SDAE_OK) return rc;
  return done ? SDAE_OK : SDAE_ERR_NEWTON;
}
