/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Phi's Jacobian, Phi^-1 and mu's rate along f for a DAE's coordinates z = Phi(t, x) = (xi, mu)
 * (<stabdae/check.h>). The finite differences are central: the Jacobian's with the step
 * cbrt(eps) max(1, |x_j|) (second order, about eps^(2/3) relative), mu's rate fourth order
 * (below). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "coords.h"
#include "core/callback.h"
#include "core/lu.h"

void sdae__coords_carve(sdae_coords *c, const sdae_dae *dae, size_t n_xi, sdae_arena *a) {
  size_t n = dae->n;
  c->dae = dae;
  c->n = n;
  c->n_xi = n_xi;
  c->J = sdae__take(a, n, n);
  c->LU = sdae__take(a, n, sdae__lu_band_cols(n - 1, n - 1));
  c->piv = sdae__take_pivots(a, n);
  c->r = sdae__take(a, n, 1), c->step = sdae__take(a, n, 1);
  c->xa = sdae__take(a, n, 1), c->za = sdae__take(a, n, 1), c->zb = sdae__take(a, n, 1);
  c->fx = sdae__take(a, n, 1);
}

static int Phi_at(const sdae_coords *c, double t, const double *x, double *z) {
  return sdae__callback_checked(c->dae->Phi(t, x, z, c->dae->params), z, c->n);
}

int sdae__coords_jacobian(sdae_coords *c, double t, const double *x) {
  const sdae_dae *d = c->dae;
  size_t n = c->n;
  if (d->Phi_jac) return sdae__callback_checked(d->Phi_jac(t, x, c->J, d->params), c->J, n * n);
  memcpy(c->xa, x, n * sizeof *x);
  for (size_t j = 0; j < n; j++) {
    double h = cbrt(DBL_EPSILON) * fmax(1.0, fabs(x[j]));
    int rc;
    c->xa[j] = x[j] + h;
    h = c->xa[j] - x[j]; /* the step as represented */
    rc = Phi_at(c, t, c->xa, c->za);
    c->xa[j] = x[j] - h;
    if (rc == SDAE_OK) rc = Phi_at(c, t, c->xa, c->zb);
    c->xa[j] = x[j];
    if (rc != SDAE_OK) return rc;
    for (size_t i = 0; i < n; i++) c->J[i * n + j] = (c->za[i] - c->zb[i]) / (2.0 * h);
  }
  return SDAE_OK;
}

int sdae__coords_invert(sdae_coords *c, double t, const double *z, double *x) {
  const sdae_dae *d = c->dae;
  size_t n = c->n;
  if (d->Phi_inv) return sdae__callback_checked(d->Phi_inv(t, z, x, d->params), x, n);
  for (int it = 0; it < 50; it++) {
    double step = 0.0, size = 0.0;
    int rc = Phi_at(c, t, x, c->r);
    if (rc == SDAE_OK) rc = sdae__coords_jacobian(c, t, x);
    if (rc != SDAE_OK) return rc;
    for (size_t i = 0; i < n; i++) c->r[i] -= z[i];
    sdae__lu_pack(c->J, n, n - 1, n - 1, c->LU);
    if ((rc = sdae__lu_solve(c->LU, c->piv, n, n - 1, n - 1, c->r, c->step)) != SDAE_OK) return rc;
    for (size_t i = 0; i < n; i++) {
      x[i] -= c->step[i];
      step = fmax(step, fabs(c->step[i]));
      size = fmax(size, fabs(x[i]));
    }
    if (step <= 1e-15 * (1.0 + size)) return SDAE_OK;
  }
  return SDAE_ERR_NEWTON;
}

/* max(1, |v|_inf): a size, the unit scale its floor */
static double size_of(const double *v, size_t n) {
  double m = 1.0;
  for (size_t i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
  return m;
}

/* m(s) = mu(t + s, x + s f(t, x)): m'(0) = [8 (m(s) - m(-s)) - (m(2s) - m(-2s))] / (12 s) with
 * an error of s^4 |m^(5)| / 30 + about 3 eps |m| / (2 s); s = eps^(1/5) (7.4e-4) balances the
 * two, both near 1e-13 relative for m of unit scale. s is eps^(1/5) of the time in which x
 * moves by its own scale, max(1, |x|) / max(1, |f|) (norms: x's components are taken to share
 * one scale; the unit scale, and the unit of time, below 1): x moves by eps^(1/5) of its size. */
int sdae__coords_mu_rate(sdae_coords *c, double t, const double *x, double *out) {
  static const double at[4] = {1.0, -1.0, 2.0, -2.0}, w[4] = {8.0, -8.0, -1.0, 1.0};
  const sdae_dae *d = c->dae;
  size_t n = c->n, n_xi = c->n_xi;
  int rc = sdae__callback_checked(d->f(t, x, c->fx, d->params), c->fx, n);
  if (rc != SDAE_OK) return rc;
  double s = pow(DBL_EPSILON, 0.2) * size_of(x, n) / size_of(c->fx, n);
  memset(out, 0, (n - n_xi) * sizeof *out);
  for (int k = 0; k < 4; k++) {
    for (size_t i = 0; i < n; i++) c->xa[i] = x[i] + at[k] * s * c->fx[i];
    if ((rc = Phi_at(c, t + at[k] * s, c->xa, c->za)) != SDAE_OK) return rc;
    for (size_t i = n_xi; i < n; i++) out[i - n_xi] += w[k] * c->za[i];
  }
  for (size_t i = 0; i < n - n_xi; i++) out[i] /= 12.0 * s;
  return SDAE_OK;
}
