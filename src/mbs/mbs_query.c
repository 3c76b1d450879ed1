/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The quantities at a state: xi, the energy and the multipliers. Each query
 * computes into its own scratch and hands out its result only when it is finite: a finite state
 * may still overflow (G v, v^T M v, the multipliers' gamma ~ |v|^2). A query leaves the step's
 * arrays, its chart and its statistics alone. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_linalg.h>

#include "core/callback.h"
#include "mbs_query.h"

void sdae__mbs_query_carve(sdae_mbs_query *qy, size_t n_q, size_t n_c, size_t n_rows,
                           sdae_arena *a) {
  qy->c = sdae__take(a, n_c, 1);
  qy->G = sdae__take(a, n_c, n_q);
  qy->ct = sdae__take(a, n_c, 1);
  qy->xi = sdae__take(a, 2 * n_c, 1);
  qy->M = sdae__take(a, n_q, n_q);
  qy->lam_G = sdae__take(a, n_c, n_q);
  qy->gamma = sdae__take(a, n_c, 1);
  qy->F = sdae__take(a, n_q, 1);
  qy->lam_M = sdae__take(a, n_q, n_q);
  sdae__mbs_nullspace_carve(&qy->ns, n_q, n_c, a);
  qy->acc = sdae__take(a, n_q, 1);
  qy->lambda = sdae__take(a, n_c, 1);
  qy->n_rows = n_rows;
  if (n_rows == n_c) return;
  qy->xi_all = sdae__take(a, 2 * n_rows, 1);
  qy->rows = sdae__take_indices(a, n_c);
  qy->sel_T = sdae__take(a, n_q, n_c);
  qy->sel_tau = sdae__take(a, n_c, 1);
  qy->coef = sdae__take(a, n_rows, n_c);
  qy->ctc = sdae__take(a, n_c, n_c);
  qy->ls_res = sdae__take(a, n_q, 1);
}

int sdae__mbs_query_xi(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                       const double *v, double *xi) {
  int redundant = sdae__mbs_redundant(ev), rc;
  double *out = redundant ? qy->xi_all : qy->xi; /* every row's */
  if ((rc = sdae__mbs_state_ok(ev, t, q, v)) != SDAE_OK) return rc;
  rc = redundant ? sdae__mbs_xi_all(ev, t, q, v, out)
                 : sdae__mbs_xi_of(ev, t, q, v, qy->c, qy->G, qy->ct, out);
  if (rc != SDAE_OK) return rc;
  if (!sdae__all_finite(out, 2 * ev->n_rows)) return SDAE_ERR_NONFINITE;
  memcpy(xi, out, 2 * ev->n_rows * sizeof *xi);
  return SDAE_OK;
}

int sdae__mbs_query_energy(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                           const double *v, double *E) {
  double energy;
  int rc;
  if ((rc = sdae__mbs_state_ok(ev, t, q, v)) != SDAE_OK ||
      (rc = sdae__mbs_mass_symmetric(ev, t, q, qy->M)) != SDAE_OK ||
      (rc = sdae__mbs_energy_of(ev, t, q, v, qy->M, &energy)) != SDAE_OK)
    return rc;
  if (!isfinite(energy)) return SDAE_ERR_NONFINITE;
  *E = energy;
  return SDAE_OK;
}

/* From M a = F - G^T lambda with a from the acceleration-level constraint G a + gamma = 0:
 * G^T lambda = F - M a, i.e. R lambda = Y^T (F - M a). Needs of M what a step needs: M
 * symmetric and the reduced mass positive definite (a singular M may give one). */
static int chosen_lambda(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                         const double *v) {
  int rc;
  if ((rc = sdae__mbs_along(ev, t, q, v, NULL, NULL, qy->gamma)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian(ev, t, q, qy->lam_G)) != SDAE_OK ||
      (rc = sdae__mbs_force(ev, t, q, v, qy->F)) != SDAE_OK ||
      (rc = sdae__mbs_mass_symmetric(ev, t, q, qy->lam_M)) != SDAE_OK)
    return rc;
  /* a row within n_q eps of the span of the others: dependent (SDAE_ERR_RANK) */
  rc = sdae__mbs_nullspace_factor(&qy->ns, qy->lam_G, qy->lam_M, (double)ev->n_q * DBL_EPSILON);
  if (rc == SDAE_OK && qy->ns.rank < ev->n_c) rc = SDAE_ERR_RANK;
  if (rc != SDAE_OK) return rc;
  sdae__mbs_nullspace_solve(&qy->ns, qy->F, qy->gamma, qy->acc);
  sdae__mbs_nullspace_lambda(&qy->ns, qy->F, qy->acc, qy->lambda);
  return SDAE_OK;
}

/* The multipliers of every row from the chosen rows' (qy->lambda), G of every row at q in
 * ev->all_G: each row is C_j G_D-rows (C the rows' coefficients on the chosen ones, the
 * identity there, G_chosen^T C_j^T = G_j^T solved by least squares), so G^T lambda = G_chosen^T
 * C^T lambda, and the least-norm lambda with C^T lambda = lambda_chosen lies in range(C):
 * lambda = C (C^T C)^-1 lambda_chosen, the pseudo-inverse's (docs/front-ends.md) */
static int least_norm(sdae_mbs_query *qy, sdae_mbs_eval *ev, double *out) {
  size_t n_q = ev->n_q, n_c = ev->n_c, n_rows = ev->n_rows;
  gsl_matrix_view A = gsl_matrix_view_array(qy->sel_T, n_q, n_c);
  gsl_vector_view tau = gsl_vector_view_array(qy->sel_tau, n_c);
  gsl_matrix_view CtC = gsl_matrix_view_array(qy->ctc, n_c, n_c);
  gsl_vector_view z = gsl_vector_view_array(qy->lambda, n_c), res;
  for (size_t k = 0; k < n_c; k++)
    for (size_t i = 0; i < n_q; i++) qy->sel_T[i * n_c + k] = ev->all_G[ev->rows[k] * n_q + i];
  if (gsl_linalg_QR_decomp(&A.matrix, &tau.vector) != GSL_SUCCESS) return SDAE_ERR_RANK;
  res = gsl_vector_view_array(qy->ls_res, n_q);
  for (size_t j = 0, k = 0; j < n_rows; j++) {
    gsl_vector_view cj = gsl_vector_view_array(qy->coef + j * n_c, n_c);
    gsl_vector_const_view gj = gsl_vector_const_view_array(ev->all_G + j * n_q, n_q);
    if (k < n_c && ev->rows[k] == j) {
      gsl_vector_set_basis(&cj.vector, k++);
      continue;
    }
    gsl_linalg_QR_lssolve(&A.matrix, &tau.vector, &gj.vector, &cj.vector, &res.vector);
  }
  for (size_t a = 0; a < n_c; a++) /* C^T C */
    for (size_t b = 0; b < n_c; b++) {
      double acc = 0.0;
      for (size_t j = 0; j < n_rows; j++) acc += qy->coef[j * n_c + a] * qy->coef[j * n_c + b];
      qy->ctc[a * n_c + b] = acc;
    }
  if (gsl_linalg_cholesky_decomp1(&CtC.matrix) != GSL_SUCCESS) return SDAE_ERR_RANK;
  gsl_linalg_cholesky_svx(&CtC.matrix, &z.vector);
  for (size_t j = 0; j < n_rows; j++) {
    double acc = 0.0;
    for (size_t k = 0; k < n_c; k++) acc += qy->coef[j * n_c + k] * qy->lambda[k];
    out[j] = acc;
  }
  return SDAE_OK;
}

/* with redundant constraints the rows chosen at the state, the step's put back after */
static int redundant_lambda(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                            const double *v) {
  int have = ev->have, changed, kept, rc;
  memcpy(qy->rows, ev->rows, ev->n_c * sizeof *qy->rows);
  if ((rc = sdae__mbs_select(ev, t, q, 1, &changed, &kept)) == SDAE_OK &&
      (rc = chosen_lambda(qy, ev, t, q, v)) == SDAE_OK &&
      (rc = sdae__mbs_jacobian_all(ev, t, q)) == SDAE_OK)
    rc = least_norm(qy, ev, qy->xi_all); /* xi_all: n_rows values of scratch */
  memcpy(ev->rows, qy->rows, ev->n_c * sizeof *qy->rows);
  ev->have = have;
  return rc;
}

int sdae__mbs_query_lambda(sdae_mbs_query *qy, sdae_mbs_eval *ev, double t, const double *q,
                           const double *v, double *lambda) {
  int redundant = sdae__mbs_redundant(ev), rc;
  double *out = redundant ? qy->xi_all : qy->lambda;
  if ((rc = sdae__mbs_state_ok(ev, t, q, v)) != SDAE_OK) return rc;
  rc = redundant ? redundant_lambda(qy, ev, t, q, v) : chosen_lambda(qy, ev, t, q, v);
  if (rc != SDAE_OK) return rc;
  if (!sdae__all_finite(out, ev->n_rows)) return SDAE_ERR_NONFINITE;
  memcpy(lambda, out, ev->n_rows * sizeof *lambda);
  return SDAE_OK;
}
