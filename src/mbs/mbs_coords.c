/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a mechanism in a chart (DESIGN.md, the mechanical front-end):
 *
 *   xi = per constraint (c_j, G_j v + dc_j/dt),   mu = (q_I, W^T M v),
 *
 * L_g mu = 0 because G W = 0, and on the manifold (q_I, W^T M v) are canonical. Phi^-1 solves
 * c(t, q) = xi's c-part for q_D by Newton from the step's q, then
 * [G; W^T M] v = [xi's velocity part - dc/dt; W^T M v] by the reduced mass W^T M W. The
 * mu-dynamics are (q_I', d/dt(W^T M v)) = (v_I, W^T (F + (dM/dt) v) - (dW/dt)^T M v), lambda
 * dropping out as W^T G^T = 0, with (dW/dt)^T M v = (G_D^-1 (dG/dt) W)^T (M v)_D. */
#include <math.h>
#include <string.h>

#include "core/callback.h"
#include "core/lu.h"
#include "mbs_coords.h"

void sdae__mbs_coords_init(sdae_mbs_coords *co, sdae_mbs_eval *eval, sdae_mbs_atlas *chart,
                           unsigned newton_max_iter) {
  co->eval = eval;
  co->chart = chart;
  co->n_q = chart->n_q;
  co->n_c = chart->n_c;
  co->n_f = chart->n_f;
  co->newton_max_iter = newton_max_iter;
}

void sdae__mbs_coords_carve(sdae_mbs_coords *co, sdae_arena *a) {
  size_t n_q = co->n_q, n_c = co->n_c, n_f = co->n_f;
  co->q = sdae__take(a, n_q, 1);
  co->v = sdae__take(a, n_q, 1);
  co->c = sdae__take(a, n_c, 1);
  co->ct = sdae__take(a, n_c, 1);
  co->G = sdae__take(a, n_c, n_q);
  co->M = sdae__take(a, n_q, n_q);
  co->Mr = sdae__take(a, n_f, n_f);
  co->key = sdae__take(a, 2 * n_q, 1);
  co->q_base = sdae__take(a, n_q, 1);
  co->M_spd = sdae__take(a, n_q, n_q);
  co->Mv = sdae__take(a, n_q, 1);
  co->res = sdae__take(a, n_c, 1);
  co->dq_D = sdae__take(a, n_c, 1);
  co->Y = sdae__take(a, n_q, 1);
  co->rhs = sdae__take(a, n_c, 1);
  co->z_D = sdae__take(a, n_c, 1);
  co->Mz = sdae__take(a, n_q, 1);
  co->v_I = sdae__take(a, n_f, 1);
  co->F = sdae__take(a, n_q, 1);
  co->Gdot = sdae__take(a, n_c, n_q);
  co->Mdv = sdae__take(a, n_q, 1);
  co->GdW = sdae__take(a, n_c, 1);
  co->X = sdae__take(a, n_c, 1);
  co->dW = sdae__take(a, n_f, 1);
}

void sdae__mbs_coords_forget(sdae_mbs_coords *co) { co->valid = 0; }

int sdae__mbs_coords_xi(sdae_mbs_coords *co, double t, const double *q, const double *v,
                        double *xi) {
  co->valid = 0; /* the point's c, G and dc/dt are about to be another configuration's */
  return sdae__mbs_xi_of(co->eval, t, q, v, co->c, co->G, co->ct, xi);
}

static void mat_vec(const double *M, size_t n, const double *x, double *y) {
  for (size_t i = 0; i < n; i++) {
    double acc = 0.0;
    for (size_t j = 0; j < n; j++) acc += M[i * n + j] * x[j];
    y[i] = acc;
  }
}

int sdae__mbs_coords_begin(sdae_mbs_coords *co, double t, const double *q, const double *v,
                           double *mu) {
  const sdae_mbs_atlas *ch = co->chart;
  int rc;
  co->valid = 0; /* the point's M is about to be the start's */
  if ((rc = sdae__mbs_mass(co->eval, t, q, co->M)) != SDAE_OK) return rc;
  memcpy(co->M_spd, co->M, co->n_q * co->n_q * sizeof *co->M);
  if ((rc = sdae__cholesky_factor(co->M_spd, co->n_q)) != SDAE_OK) return rc;
  mat_vec(co->M, co->n_q, v, co->Mv);
  for (size_t k = 0; k < co->n_f; k++) mu[k] = q[ch->ind[k]];
  sdae__mbs_Wt(ch, co->Mv, mu + co->n_f);
  memcpy(co->q_base, q, co->n_q * sizeof *q);
  return SDAE_OK;
}

/* Newton on c(t, q_D, q_I) = xi's c-part from the step's q; stops once an update is below
 * 1e-10 of q_D's size: Newton's quadratic convergence puts the iterate at rounding then */
static int solve_q(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_c = co->n_c;
  memcpy(co->q, co->q_base, co->n_q * sizeof *co->q);
  for (size_t k = 0; k < co->n_f; k++) co->q[ch->ind[k]] = mu[k];
  for (unsigned it = 0; it < co->newton_max_iter; it++) {
    double step = 0.0, size = 0.0;
    int rc;
    if ((rc = sdae__mbs_constraint(co->eval, t, co->q, co->c)) != SDAE_OK ||
        (rc = sdae__mbs_jacobian(co->eval, t, co->q, co->G)) != SDAE_OK)
      return rc;
    if (sdae__mbs_gd_factor(co->chart, co->G) != SDAE_OK) return SDAE_ERR_PHI_INV;
    for (size_t j = 0; j < n_c; j++) co->res[j] = co->c[j] - xi[2 * j];
    sdae__mbs_gd_solve(ch, co->res, co->dq_D);
    co->phi_inv_iters++;
    for (size_t j = 0; j < n_c; j++) {
      double *qd = &co->q[ch->dep[j]];
      *qd -= co->dq_D[j];
      step = fabs(co->dq_D[j]) > step ? fabs(co->dq_D[j]) : step;
      size = fabs(*qd) > size ? fabs(*qd) : size;
    }
    if (!sdae__all_finite(co->q, co->n_q)) return SDAE_ERR_PHI_INV;
    if (step <= 1e-10 * (1.0 + size)) return SDAE_OK;
  }
  return SDAE_ERR_PHI_INV;
}

/* the reduced mass W^T M W (n_f x n_f) into co->Mr, factored: symmetric by construction (DESIGN,
 * the price of zero drift), Y = M W column by column, then the upper triangle of W^T Y, mirrored.
 * Formed entry by entry, its two triangles would round differently by up to eps times M's
 * largest entries, which W^T M W need not have (a heavy direction across the constraints):
 * Cholesky would then see a non-symmetric matrix. */
static int reduced_mass(sdae_mbs_coords *co) {
  size_t n_q = co->n_q, n_f = co->n_f;
  const double *W = co->chart->W;
  for (size_t b = 0; b < n_f; b++) {
    for (size_t i = 0; i < n_q; i++) {
      double acc = 0.0;
      for (size_t j = 0; j < n_q; j++) acc += co->M[i * n_q + j] * W[j * n_f + b];
      co->Y[i] = acc;
    }
    for (size_t a = 0; a <= b; a++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += W[i * n_f + a] * co->Y[i];
      co->Mr[a * n_f + b] = co->Mr[b * n_f + a] = acc;
    }
  }
  return sdae__cholesky_factor(co->Mr, n_f);
}

/* v = z + W v_I with G z = xi's velocity part - dc/dt (z_I = 0) and W^T M v = mu's p-part */
static int solve_v(sdae_mbs_coords *co, const double *xi, const double *mu) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_q = co->n_q, n_c = co->n_c, n_f = co->n_f;
  int rc = reduced_mass(co);
  if (rc != SDAE_OK) return rc;
  for (size_t j = 0; j < n_c; j++) co->rhs[j] = xi[2 * j + 1] - co->ct[j];
  sdae__mbs_gd_solve(ch, co->rhs, co->z_D);
  memset(co->v, 0, n_q * sizeof *co->v);
  for (size_t j = 0; j < n_c; j++) co->v[ch->dep[j]] = co->z_D[j];
  mat_vec(co->M, n_q, co->v, co->Mz);
  sdae__mbs_Wt(ch, co->Mz, co->v_I);
  for (size_t k = 0; k < n_f; k++) co->v_I[k] = mu[n_f + k] - co->v_I[k];
  sdae__cholesky_solve(co->Mr, n_f, co->v_I);
  for (size_t i = 0; i < n_q; i++)
    for (size_t k = 0; k < n_f; k++) co->v[i] += ch->W[i * n_f + k] * co->v_I[k];
  return sdae__all_finite(co->v, n_q) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int same_point(const sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  return co->valid && co->key_t == t &&
         memcmp(co->key, xi, 2 * co->n_c * sizeof *xi) == 0 &&
         memcmp(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu) == 0;
}

int sdae__mbs_phi_inv(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  int rc;
  if (same_point(co, t, xi, mu)) return SDAE_OK;
  co->valid = 0;
  if ((rc = solve_q(co, t, xi, mu)) != SDAE_OK) return rc;
  /* G, W and M where q ended, for v and for the mu-dynamics there */
  if ((rc = sdae__mbs_jacobian(co->eval, t, co->q, co->G)) != SDAE_OK) return rc;
  if (sdae__mbs_chart_factor(co->chart, co->G, NULL) != SDAE_OK) return SDAE_ERR_PHI_INV;
  if ((rc = sdae__mbs_constraint_t(co->eval, t, co->q, co->ct)) != SDAE_OK ||
      (rc = sdae__mbs_mass(co->eval, t, co->q, co->M)) != SDAE_OK ||
      (rc = solve_v(co, xi, mu)) != SDAE_OK)
    return rc;
  memcpy(co->key, xi, 2 * co->n_c * sizeof *xi);
  memcpy(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu);
  co->key_t = t;
  co->valid = 1;
  return SDAE_OK;
}

/* co->dW = X^T (M v)_D with X = G_D^-1 (dG/dt) W: the term (dW/dt)^T M v */
static void dW_term(sdae_mbs_coords *co) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_q = co->n_q, n_c = co->n_c, n_f = co->n_f;
  for (size_t k = 0; k < n_f; k++) {
    for (size_t j = 0; j < n_c; j++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += co->Gdot[j * n_q + i] * ch->W[i * n_f + k];
      co->GdW[j] = acc;
    }
    sdae__mbs_gd_solve(ch, co->GdW, co->X);
    co->dW[k] = 0.0;
    for (size_t j = 0; j < n_c; j++) co->dW[k] += co->X[j] * co->Mv[ch->dep[j]];
  }
}

int sdae__mbs_mu_dot(sdae_mbs_coords *co, double t, double *out) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_q = co->n_q, n_f = co->n_f;
  int rc;
  if ((rc = sdae__mbs_force(co->eval, t, co->q, co->v, co->F)) != SDAE_OK ||
      (rc = sdae__mbs_along(co->eval, t, co->q, co->v, co->Gdot, co->Mdv, NULL)) != SDAE_OK)
    return rc;
  for (size_t i = 0; i < n_q; i++) co->F[i] += co->Mdv[i];
  sdae__mbs_Wt(ch, co->F, out + n_f);
  mat_vec(co->M, n_q, co->v, co->Mv);
  dW_term(co);
  for (size_t k = 0; k < n_f; k++) {
    out[k] = co->v[ch->ind[k]];
    out[n_f + k] -= co->dW[k];
  }
  return SDAE_OK;
}
