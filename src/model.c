/* Calls into the user's model: every callback's status and every value it writes are checked
 * here, so the rest of the library works with finite numbers only. */
#include <math.h>

#include "internal.h"

int sdae__eval_q0(sdae_stepper *s, double t, const double *mu, double *out) {
  return sdae__call_checked(s->model.q0, s, t, mu, out, s->model.n_mu);
}

int sdae__eval_q0_jac(sdae_stepper *s, double t, const double *mu, double *out) {
  size_t n = s->model.n_mu;
  return sdae__call_checked(s->model.q0_jac, s, t, mu, out, n * n);
}

/* Dense Q: the product Q xi and the squared column norms ||q_i||^2 (eq. 6's input). */
static void reduce_dense_Q(sdae_stepper *s, const double *xi) {
  size_t n_mu = s->model.n_mu, n_xi = s->model.n_xi;
  const double *Q = s->Q;
  for (size_t r = 0; r < n_mu; r++) {
    double acc = 0.0;
    for (size_t i = 0; i < n_xi; i++) acc += Q[r * n_xi + i] * xi[i];
    s->Qxi[r] = acc;
  }
  for (size_t i = 0; i < n_xi; i++) { /* column by column: no zeroing pass (a memset call) */
    double acc = 0.0;
    for (size_t r = 0; r < n_mu; r++) acc += Q[r * n_xi + i] * Q[r * n_xi + i];
    s->qnorm2[i] = acc;
  }
}

int sdae__eval_Q(sdae_stepper *s, double t, const double *xi, const double *mu) {
  const sdae_model *m = &s->model;
  int rc;
  if (m->Q) {
    rc = sdae__status_of_callback(m->Q(t, xi, mu, s->Q, m->params));
    if (rc != SDAE_OK) return rc;
    reduce_dense_Q(s, xi);
  } else {
    rc = sdae__status_of_callback(m->Q_apply(t, xi, mu, s->Qxi, s->qnorm2, m->params));
    if (rc != SDAE_OK) return rc;
  }
  /* one test for a NaN or Inf in Q (it reaches its column's ||q_i||^2) and for an overflow in
   * Q xi or in the norms */
  if (!sdae__all_finite(s->Qxi, m->n_mu) || !sdae__all_finite(s->qnorm2, m->n_xi))
    return SDAE_ERR_NONFINITE;
  return SDAE_OK;
}
