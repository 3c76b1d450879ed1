/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The quantities at a state of a sparse mechanism (mbs_sparse_query.h). */
#include <string.h>

#include "core/callback.h"
#include "mbs_sparse_query.h"

void sdae__mbs_sparse_query_carve(sdae_mbs_sparse_query *qy, const sdae_mbs_sparse_layout *ly,
                                  const sdae_mbs_sparse_lent *lent, sdae_arena *a) {
  size_t n_q = ly->n_q, n_c = ly->n_c, gnz = ly->Gp->nnz;
  qy->ly = ly;
  qy->c = sdae__take(a, n_c, 1), qy->ct = sdae__take(a, n_c, 1);
  qy->gamma = sdae__take(a, n_c, 1), qy->xi = sdae__take(a, 2 * n_c, 1);
  qy->G = sdae__take(a, gnz, 1), qy->Gd = sdae__take(a, gnz, 1);
  qy->M = sdae__take(a, ly->Mp->nnz, 1);
  qy->F = sdae__take(a, n_q, 1), qy->Mv = sdae__take(a, n_q, 1);
  qy->lent = *lent;
}

int sdae__mbs_sparse_query_xi(sdae_mbs_sparse_query *qy, double t, const double *q, const double *v,
                              double *xi) {
  const sdae_mbs_sparse_layout *ly = qy->ly;
  sdae_mbs_eval *e = ly->eval;
  int rc;
  if ((rc = sdae__mbs_constraint(e, t, q, qy->c)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian_values(e, t, q, qy->G)) != SDAE_OK ||
      (rc = sdae__mbs_constraint_t(e, t, q, qy->ct)) != SDAE_OK)
    return rc;
  sdae__mbs_sparse_g_times(ly, qy->G, v, qy->ct, qy->gamma); /* G v + dc/dt */
  for (size_t j = 0; j < ly->n_c; j++) qy->xi[2 * j] = qy->c[j], qy->xi[2 * j + 1] = qy->gamma[j];
  if (!sdae__all_finite(qy->xi, 2 * ly->n_c)) return SDAE_ERR_NONFINITE;
  memcpy(xi, qy->xi, 2 * ly->n_c * sizeof *xi);
  return SDAE_OK;
}

int sdae__mbs_sparse_query_energy(sdae_mbs_sparse_query *qy, double t, const double *q,
                                  const double *v, double *E) {
  const sdae_mbs_sparse_layout *ly = qy->ly;
  double V = 0.0, kinetic = 0.0;
  int rc;
  if ((rc = sdae__mbs_mass_values(ly->eval, t, q, qy->M)) != SDAE_OK ||
      (rc = sdae__mbs_sparse_mass_symmetric(ly, qy->M)) != SDAE_OK ||
      (ly->eval->sys.potential && (rc = sdae__mbs_potential(ly->eval, t, q, &V)) != SDAE_OK))
    return rc;
  sdae__mbs_sparse_m_times(ly, qy->M, v, qy->Mv);
  for (size_t i = 0; i < ly->n_q; i++) kinetic += v[i] * qy->Mv[i];
  kinetic = 0.5 * kinetic + V;
  if (!sdae__all_finite(&kinetic, 1)) return SDAE_ERR_NONFINITE;
  *E = kinetic;
  return SDAE_OK;
}

/* gamma = Gdot v + d/ds dc/dt at the state */
static int gamma_at(sdae_mbs_sparse_query *qy, double t, const double *q, const double *v) {
  const sdae_mbs_sparse_layout *ly = qy->ly;
  int rc;
  if ((rc = sdae__mbs_jacobian_dot_values(ly->eval, t, q, v, qy->Gd)) != SDAE_OK ||
      (rc = sdae__mbs_ct_dot(ly->eval, t, q, v, qy->ct)) != SDAE_OK)
    return rc;
  sdae__mbs_sparse_g_times(ly, qy->Gd, v, qy->ct, qy->gamma);
  return SDAE_OK;
}

int sdae__mbs_sparse_query_lambda(sdae_mbs_sparse_query *qy, double t, const double *q,
                                  const double *v, double *lambda) {
  const sdae_mbs_sparse_layout *ly = qy->ly;
  size_t n_q = ly->n_q, n_c = ly->n_c;
  int rc;
  if ((rc = sdae__mbs_mass_values(ly->eval, t, q, qy->M)) != SDAE_OK ||
      (rc = sdae__mbs_sparse_mass_symmetric(ly, qy->M)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian_values(ly->eval, t, q, qy->G)) != SDAE_OK ||
      (rc = sdae__mbs_force(ly->eval, t, q, v, qy->F)) != SDAE_OK ||
      (rc = gamma_at(qy, t, q, v)) != SDAE_OK)
    return rc;
  const sdae_mbs_sparse_lent *w = &qy->lent;
  sdae__mbs_sparse_kkt_values(ly, qy->M, qy->G, w->K);
  if ((rc = sdae__sparse_ldl_factor(w->kkt, w->K)) != SDAE_OK) return rc;
  memcpy(w->rhs, qy->F, n_q * sizeof *w->rhs);
  for (size_t j = 0; j < n_c; j++) w->rhs[n_q + j] = -qy->gamma[j];
  sdae__sparse_ldl_solve(w->kkt, w->rhs, w->sol);
  if (!sdae__all_finite(w->sol + n_q, n_c)) return SDAE_ERR_NONFINITE;
  memcpy(lambda, w->sol + n_q, n_c * sizeof *lambda);
  return SDAE_OK;
}
