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

#include "mbs_impl.h"

int sdae__mbs_xi_at(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                    double *xi) {
  sdae_mbs_point *p = &s->pt;
  int rc;
  s->pt_valid = 0;
  if ((rc = sdae__mbs_constraint(s, t, q, p->c)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian(s, t, q, p->G)) != SDAE_OK ||
      (rc = sdae__mbs_constraint_t(s, t, q, p->ct)) != SDAE_OK)
    return rc;
  for (size_t j = 0; j < s->n_c; j++) {
    double cdot = p->ct[j];
    for (size_t i = 0; i < s->n_q; i++) cdot += p->G[j * s->n_q + i] * v[i];
    xi[2 * j] = p->c[j];
    xi[2 * j + 1] = cdot;
  }
  return SDAE_OK;
}

static void mat_vec(const double *M, size_t n, const double *x, double *y) {
  for (size_t i = 0; i < n; i++) {
    double acc = 0.0;
    for (size_t j = 0; j < n; j++) acc += M[i * n + j] * x[j];
    y[i] = acc;
  }
}

void sdae__mbs_mu_at(sdae_mbs_stepper *s, const double *q, const double *v, double *mu) {
  mat_vec(s->pt.M, s->n_q, v, s->r1);
  for (size_t k = 0; k < s->n_f; k++) mu[k] = q[s->ind[k]];
  sdae__mbs_Wt(s, s->r1, mu + s->n_f);
}

void sdae__mbs_forget(sdae_mbs_stepper *s) {
  s->pt_valid = 0;
  sdae__derive_forget(&s->derive);
}

/* Newton on c(t, q_D, q_I) = xi's c-part from the step's q; stops once an update is below
 * 1e-10 of q_D's size: Newton's quadratic convergence puts the iterate at rounding then */
static int solve_q(sdae_mbs_stepper *s, double t, const double *xi, const double *mu) {
  sdae_mbs_point *p = &s->pt;
  size_t n_c = s->n_c;
  memcpy(p->q, s->q_base, s->n_q * sizeof *p->q);
  for (size_t k = 0; k < s->n_f; k++) p->q[s->ind[k]] = mu[k];
  for (unsigned it = 0; it < s->opt.newton_max_iter; it++) {
    double step = 0.0, size = 0.0;
    int rc;
    if ((rc = sdae__mbs_constraint(s, t, p->q, p->c)) != SDAE_OK ||
        (rc = sdae__mbs_jacobian(s, t, p->q, p->G)) != SDAE_OK)
      return rc;
    if (sdae__mbs_gd_factor(s) != SDAE_OK) return SDAE_ERR_PHI_INV;
    for (size_t j = 0; j < n_c; j++) s->r3[j] = p->c[j] - xi[2 * j];
    sdae__mbs_gd_solve(s, s->r3, s->r2);
    s->stats.phi_inv_iters++;
    for (size_t j = 0; j < n_c; j++) {
      double *qd = &p->q[s->dep[j]];
      *qd -= s->r2[j];
      step = fabs(s->r2[j]) > step ? fabs(s->r2[j]) : step;
      size = fabs(*qd) > size ? fabs(*qd) : size;
    }
    if (!sdae__all_finite(p->q, s->n_q)) return SDAE_ERR_PHI_INV;
    if (step <= 1e-10 * (1.0 + size)) return SDAE_OK;
  }
  return SDAE_ERR_PHI_INV;
}

/* the reduced mass W^T M W (n_f x n_f) into s->Mr, factored: symmetric by construction (DESIGN,
 * the price of zero drift), Y = M W column by column, then the upper triangle of W^T Y, mirrored.
 * Formed entry by entry, its two triangles would round differently by up to eps times M's
 * largest entries, which W^T M W need not have (a heavy direction across the constraints):
 * Cholesky would then see a non-symmetric matrix. */
static int reduced_mass(sdae_mbs_stepper *s) {
  size_t n_q = s->n_q, n_f = s->n_f;
  const double *W = s->pt.W;
  for (size_t b = 0; b < n_f; b++) {
    for (size_t i = 0; i < n_q; i++) {
      double acc = 0.0;
      for (size_t j = 0; j < n_q; j++) acc += s->pt.M[i * n_q + j] * W[j * n_f + b];
      s->r1[i] = acc;
    }
    for (size_t a = 0; a <= b; a++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += W[i * n_f + a] * s->r1[i];
      s->Mr[a * n_f + b] = s->Mr[b * n_f + a] = acc;
    }
  }
  return sdae__cholesky_factor(s->Mr, n_f);
}

/* v = z + W v_I with G z = xi's velocity part - dc/dt (z_I = 0) and W^T M v = mu's p-part */
static int solve_v(sdae_mbs_stepper *s, const double *xi, const double *mu) {
  sdae_mbs_point *p = &s->pt;
  size_t n_q = s->n_q, n_c = s->n_c, n_f = s->n_f;
  int rc = reduced_mass(s);
  if (rc != SDAE_OK) return rc;
  for (size_t j = 0; j < n_c; j++) s->r3[j] = xi[2 * j + 1] - p->ct[j];
  sdae__mbs_gd_solve(s, s->r3, s->r2);
  memset(p->v, 0, n_q * sizeof *p->v);
  for (size_t j = 0; j < n_c; j++) p->v[s->dep[j]] = s->r2[j];
  mat_vec(p->M, n_q, p->v, s->r1);
  sdae__mbs_Wt(s, s->r1, s->rf);
  for (size_t k = 0; k < n_f; k++) s->rf[k] = mu[n_f + k] - s->rf[k];
  sdae__cholesky_solve(s->Mr, n_f, s->rf);
  for (size_t i = 0; i < n_q; i++)
    for (size_t k = 0; k < n_f; k++) p->v[i] += p->W[i * n_f + k] * s->rf[k];
  return sdae__all_finite(p->v, n_q) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int same_point(const sdae_mbs_stepper *s, double t, const double *xi, const double *mu) {
  return s->pt_valid && s->pt_t == t &&
         memcmp(s->pt_key, xi, 2 * s->n_c * sizeof *xi) == 0 &&
         memcmp(s->pt_key + 2 * s->n_c, mu, 2 * s->n_f * sizeof *mu) == 0;
}

int sdae__mbs_phi_inv(sdae_mbs_stepper *s, double t, const double *xi, const double *mu) {
  sdae_mbs_point *p = &s->pt;
  int rc;
  if (same_point(s, t, xi, mu)) return SDAE_OK;
  s->pt_valid = 0;
  if ((rc = solve_q(s, t, xi, mu)) != SDAE_OK) return rc;
  /* G, W and M where q ended, for v and for the mu-dynamics there */
  if ((rc = sdae__mbs_jacobian(s, t, p->q, p->G)) != SDAE_OK) return rc;
  if (sdae__mbs_chart_factor(s, NULL) != SDAE_OK) return SDAE_ERR_PHI_INV;
  if ((rc = sdae__mbs_constraint_t(s, t, p->q, p->ct)) != SDAE_OK ||
      (rc = sdae__mbs_mass(s, t, p->q, p->M)) != SDAE_OK || (rc = solve_v(s, xi, mu)) != SDAE_OK)
    return rc;
  memcpy(s->pt_key, xi, 2 * s->n_c * sizeof *xi);
  memcpy(s->pt_key + 2 * s->n_c, mu, 2 * s->n_f * sizeof *mu);
  s->pt_t = t;
  s->pt_valid = 1;
  return SDAE_OK;
}

/* out = X^T (M v)_D with X = G_D^-1 (dG/dt) W: the term (dW/dt)^T M v */
static void dW_term(sdae_mbs_stepper *s, const double *Mv, double *out) {
  size_t n_q = s->n_q, n_c = s->n_c, n_f = s->n_f;
  for (size_t k = 0; k < n_f; k++) {
    for (size_t j = 0; j < n_c; j++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += s->Gdot[j * n_q + i] * s->pt.W[i * n_f + k];
      s->r3[j] = acc;
    }
    sdae__mbs_gd_solve(s, s->r3, s->gdot);
    out[k] = 0.0;
    for (size_t j = 0; j < n_c; j++) out[k] += s->gdot[j] * Mv[s->dep[j]];
  }
}

int sdae__mbs_mu_dot(sdae_mbs_stepper *s, double t, double *out) {
  sdae_mbs_point *p = &s->pt;
  size_t n_q = s->n_q, n_f = s->n_f;
  int rc;
  if ((rc = sdae__mbs_force(s, t, p->q, p->v, s->r1)) != SDAE_OK ||
      (rc = sdae__mbs_along(s, t, p->q, p->v, s->Gdot, s->Mdv, NULL)) != SDAE_OK)
    return rc;
  for (size_t i = 0; i < n_q; i++) s->r1[i] += s->Mdv[i];
  sdae__mbs_Wt(s, s->r1, out + n_f);
  mat_vec(p->M, n_q, p->v, s->r2);
  dW_term(s, s->r2, s->rf);
  for (size_t k = 0; k < n_f; k++) {
    out[k] = p->v[s->ind[k]];
    out[n_f + k] -= s->rf[k];
  }
  return SDAE_OK;
}
