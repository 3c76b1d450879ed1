/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Calls into the user's normal form (sdae_model), every status and value checked, and the
 * model's facts the layers above share. */
#ifndef STABDAE_SRC_MODEL_MODEL_H
#define STABDAE_SRC_MODEL_MODEL_H

#include <stabdae/stabdae.h>

#include "core/callback.h"

/* Newton on a band narrower than the matrix (the options' bandwidth): GSL's banded LU and
 * finite differences; a dense Newton keeps a full matrix and can take an analytic Jacobian. */
static inline int sdae__banded(const sdae_model *m, const sdae_options *o) {
  return o->bandwidth > 0 && o->bandwidth < m->n_mu - 1;
}

/* calls a user callback of the (t, mu, out) form with the model's params, then checks it;
 * inline: the discrete gradient makes four such calls per evaluation */
static inline int sdae__call_checked(int (*cb)(double, const double *, double *, void *),
                                     const sdae_model *m, double t, const double *mu, double *out,
                                     size_t n_out) {
  return sdae__callback_checked(cb(t, mu, out, m->params), out, n_out);
}
int sdae__eval_q0(const sdae_model *m, double t, const double *mu, double *out);
int sdae__eval_q0_jac(const sdae_model *m, double t, const double *mu, double *out);
/* Q(xi, mu) xi into Qxi and ||q_i||^2 into qnorm2; Q_dense: n_mu x n_xi scratch for a dense Q */
int sdae__eval_Q(const sdae_model *m, double *Q_dense, double t, const double *xi, const double *mu,
                 double *Qxi, double *qnorm2);

#endif /* STABDAE_SRC_MODEL_MODEL_H */
