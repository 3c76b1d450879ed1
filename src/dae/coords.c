/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Phi's Jacobian, Phi^-1 and mu's rate along f for a DAE's coordinates z = Phi(t, x) = (xi, mu)
 * (<stabdae/dae.h>). The finite differences are central: the Jacobian's with the step
 * cbrt(eps) max(1, |x_j|) (second order, about eps^(2/3) relative), mu's rate fourth order
 * (below). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "coords.h"
#include "core/callback.h"
#include "core/difference.h"
#include "core/lu.h"

void sdae__coords_carve(sdae_coords *c, const sdae_dae *dae, size_t n_xi, sdae_arena *a) {
  size_t n = dae->n;
  c->dae = dae;
  c->n = n;
  c->n_xi = n_xi;
  c->J = sdae__take(a, n, n);
  c->LU = sdae__take(a, n, sdae__lu_band_cols(n - 1, n - 1));
  c->piv = sdae__take_pivots(a, n);
  sdae__newton_carve_hooks(&c->newton, n, SDAE_NEWTON_TOL, SDAE_NEWTON_MAX_ITER, a);
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

/* ---- Phi^-1 by Newton on Phi(t, x) = z, an adapter of core/newton.h ---- */

typedef struct x_eq {
  sdae_coords *c;
  double t;
  const double *z;
} x_eq;

/* residual: Phi(t, x) - z */
static int x_residual(void *ctx, const double *x, double *R) {
  const x_eq *e = ctx;
  int rc = Phi_at(e->c, e->t, x, R);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < e->c->n; i++) R[i] -= e->z[i];
  return SDAE_OK;
}

/* linear setup: dPhi/dx at x, factored */
static int x_setup(void *ctx, const double *x) {
  const x_eq *e = ctx;
  sdae_coords *c = e->c;
  size_t n = c->n;
  int rc = sdae__coords_jacobian(c, e->t, x);
  if (rc != SDAE_OK) return rc;
  sdae__lu_pack(c->J, n, n - 1, n - 1, c->LU);
  return sdae__lu_factor(c->LU, c->piv, n, n - 1, n - 1);
}

static int x_solve(void *ctx, const double *R, double *dx) {
  const sdae_coords *c = ((const x_eq *)ctx)->c;
  sdae__lu_factored_solve(c->LU, c->piv, c->n, c->n - 1, c->n - 1, R, dx);
  return SDAE_OK;
}

int sdae__coords_invert(sdae_coords *c, double t, const double *z, double *x) {
  const sdae_dae *d = c->dae;
  x_eq e = {c, t, z};
  const sdae_newton_system sys = {
      .residual = x_residual, .setup = x_setup, .solve = x_solve, .ctx = &e};
  if (d->Phi_inv) return sdae__callback_checked(d->Phi_inv(t, z, x, d->params), x, c->n);
  return sdae__newton_solve(&c->newton, &sys, 1.0, x);
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
  const sdae_dae *d = c->dae;
  size_t n = c->n, n_xi = c->n_xi;
  int rc = sdae__callback_checked(d->f(t, x, c->fx, d->params), c->fx, n);
  if (rc != SDAE_OK) return rc;
  double s = pow(DBL_EPSILON, 0.2) * size_of(x, n) / size_of(c->fx, n);
  memset(out, 0, (n - n_xi) * sizeof *out);
  for (int k = 0; k < SDAE_FD_POINTS; k++) {
    for (size_t i = 0; i < n; i++) c->xa[i] = x[i] + sdae__fd_offset[k] * s * c->fx[i];
    if ((rc = Phi_at(c, t + sdae__fd_offset[k] * s, c->xa, c->za)) != SDAE_OK) return rc;
    sdae__fd_add(out, 1, c->za + n_xi, n - n_xi, k);
  }
  sdae__fd_finish(out, 1, n - n_xi, s);
  return SDAE_OK;
}
