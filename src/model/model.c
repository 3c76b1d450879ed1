/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Calls into the user's model: every callback's status and every value it writes are checked
 * here, so the rest of the library works with finite numbers only. */
#include <math.h>

#include "model.h"

int sdae__eval_q0(const sdae_model *m, double t, const double *mu, double *out) {
  return sdae__call_checked(m->q0, m, t, mu, out, m->n_mu);
}

int sdae__eval_q0_jac(const sdae_model *m, double t, const double *mu, double *out) {
  return sdae__call_checked(m->q0_jac, m, t, mu, out, m->n_mu * m->n_mu);
}

/* Dense Q: the product Q xi and the squared column norms ||q_i||^2 (eq. 6's input). */
static void reduce_dense_Q(const sdae_model *m, const double *Q, const double *xi, double *Qxi,
                           double *qnorm2) {
  size_t n_mu = m->n_mu, n_xi = m->n_xi;
  for (size_t r = 0; r < n_mu; r++) {
    double acc = 0.0;
    for (size_t i = 0; i < n_xi; i++) acc += Q[r * n_xi + i] * xi[i];
    Qxi[r] = acc;
  }
  for (size_t i = 0; i < n_xi; i++) { /* column by column: no zeroing pass (a memset call) */
    double acc = 0.0;
    for (size_t r = 0; r < n_mu; r++) acc += Q[r * n_xi + i] * Q[r * n_xi + i];
    qnorm2[i] = acc;
  }
}

int sdae__eval_Q(const sdae_model *m, double *Q_dense, double t, const double *xi, const double *mu,
                 double *Qxi, double *qnorm2) {
  int rc;
  if (m->Q) {
    rc = sdae__status_of_callback(m->Q(t, xi, mu, Q_dense, m->params));
    if (rc != SDAE_OK) return rc;
    reduce_dense_Q(m, Q_dense, xi, Qxi, qnorm2);
  } else {
    rc = sdae__status_of_callback(m->Q_apply(t, xi, mu, Qxi, qnorm2, m->params));
    if (rc != SDAE_OK) return rc;
  }
  /* one test for a NaN or Inf in Q (it reaches its column's ||q_i||^2) and for an overflow in
   * Q xi or in the norms */
  if (!sdae__all_finite(Qxi, m->n_mu) || !sdae__all_finite(qnorm2, m->n_xi))
    return SDAE_ERR_NONFINITE;
  return SDAE_OK;
}
