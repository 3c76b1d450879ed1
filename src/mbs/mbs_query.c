/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The quantities at a state: xi, the energy and the multipliers. Each query
 * computes into its own scratch and hands out its result only when it is finite: a finite state
 * may still overflow (G v, v^T M v, the multipliers' gamma ~ |v|^2). A query leaves the step's
 * arrays, its chart and its statistics alone. */
#include <math.h>
#include <string.h>

#include "core/callback.h"
#include "core/lu.h"
#include "mbs_query.h"

void sdae__mbs_query_carve(sdae_mbs_query *qy, size_t n_q, size_t n_c, sdae_arena *a) {
  qy->c = sdae__take(a, n_c, 1);
  qy->G = sdae__take(a, n_c, n_q);
  qy->ct = sdae__take(a, n_c, 1);
  qy->xi = sdae__take(a, 2 * n_c, 1);
  qy->M = sdae__take(a, n_q, n_q);
  qy->lam_G = sdae__take(a, n_c, n_q);
  qy->gamma = sdae__take(a, n_c, 1);
  qy->F = sdae__take(a, n_q, 1);
  qy->M_chol = sdae__take(a, n_q, n_q);
  qy->Y = sdae__take(a, n_c, n_q);
  qy->GY = sdae__take(a, n_c, n_c);
  qy->lambda = sdae__take(a, n_c, 1);
}

int sdae__mbs_query_xi(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                       const double *v, double *xi) {
  int rc;
  if ((rc = sdae__mbs_state_ok(ev, t, q, v)) != SDAE_OK ||
      (rc = sdae__mbs_xi_of(ev, t, q, v, qy->c, qy->G, qy->ct, qy->xi)) != SDAE_OK)
    return rc;
  if (!sdae__all_finite(qy->xi, 2 * ev->n_c)) return SDAE_ERR_NONFINITE;
  memcpy(xi, qy->xi, 2 * ev->n_c * sizeof *xi);
  return SDAE_OK;
}

int sdae__mbs_query_energy(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                           const double *v, double *E) {
  double energy;
  int rc;
  if ((rc = sdae__mbs_state_ok(ev, t, q, v)) != SDAE_OK ||
      (rc = sdae__mbs_mass(ev, t, q, qy->M)) != SDAE_OK ||
      (rc = sdae__mbs_energy_of(ev, t, q, v, qy->M, &energy)) != SDAE_OK)
    return rc;
  if (!isfinite(energy)) return SDAE_ERR_NONFINITE;
  *E = energy;
  return SDAE_OK;
}

/* (G M^-1 G^T) lambda = G M^-1 F + gamma: Y = G M^-1 row by row (M symmetric), then the
 * n_c x n_c system, singular only when the constraints are dependent; G Y^T symmetric by
 * construction (its upper triangle, mirrored), as Cholesky requires */
int sdae__mbs_query_lambda(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                           const double *v, double *lambda) {
  size_t n_q = ev->n_q, n_c = ev->n_c;
  int rc;
  if ((rc = sdae__mbs_state_ok(ev, t, q, v)) != SDAE_OK) return rc;
  if ((rc = sdae__mbs_along(ev, t, q, v, NULL, NULL, qy->gamma)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian(ev, t, q, qy->lam_G)) != SDAE_OK ||
      (rc = sdae__mbs_force(ev, t, q, v, qy->F)) != SDAE_OK ||
      (rc = sdae__mbs_mass(ev, t, q, qy->M_chol)) != SDAE_OK ||
      (rc = sdae__cholesky_factor(qy->M_chol, n_q)) != SDAE_OK)
    return rc;
  for (size_t j = 0; j < n_c; j++) {
    memcpy(qy->Y + j * n_q, qy->lam_G + j * n_q, n_q * sizeof *qy->Y);
    sdae__cholesky_solve(qy->M_chol, n_q, qy->Y + j * n_q);
  }
  for (size_t i = 0; i < n_c; i++) {
    double b = qy->gamma[i];
    for (size_t k = 0; k < n_q; k++) b += qy->Y[i * n_q + k] * qy->F[k];
    qy->lambda[i] = b;
    for (size_t j = i; j < n_c; j++) {
      double acc = 0.0;
      for (size_t k = 0; k < n_q; k++) acc += qy->lam_G[i * n_q + k] * qy->Y[j * n_q + k];
      qy->GY[i * n_c + j] = qy->GY[j * n_c + i] = acc;
    }
  }
  if (sdae__cholesky_factor(qy->GY, n_c) != SDAE_OK) return SDAE_ERR_RANK;
  sdae__cholesky_solve(qy->GY, n_c, qy->lambda);
  if (!sdae__all_finite(qy->lambda, n_c)) return SDAE_ERR_NONFINITE;
  memcpy(lambda, qy->lambda, n_c * sizeof *lambda);
  return SDAE_OK;
}
