/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The implicit midpoint map phi_T(mu, mu+) = q0((mu + mu+)/2) at t + T/2: symmetric, order 2. */
#include "map.h"
#include "model/model.h"

static size_t midpoint_scratch(const sdae_model *m, const sdae_options *o) {
  (void)o;
  return m->n_mu; /* the midpoint */
}

static const double *midpoint(sdae_map_ctx *c, const double *mu, const double *mu_next) {
  double *mid = c->work;
  for (size_t i = 0; i < c->model->n_mu; i++) mid[i] = 0.5 * (mu[i] + mu_next[i]);
  return mid;
}

static int midpoint_phi(sdae_map_ctx *c, double t, double T, const double *mu,
                        const double *mu_next, double *out) {
  return sdae__eval_q0(c->model, t + 0.5 * T, midpoint(c, mu, mu_next), out);
}

/* d phi / d mu+ = q0'(mid) / 2 */
static int midpoint_jac(sdae_map_ctx *c, double t, double T, const double *mu,
                        const double *mu_next, double *out) {
  size_t n = c->model->n_mu;
  int rc = sdae__eval_q0_jac(c->model, t + 0.5 * T, midpoint(c, mu, mu_next), out);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n * n; i++) out[i] *= 0.5;
  return SDAE_OK;
}

static int midpoint_jac_given(const sdae_model *m) { return m->q0_jac != NULL; }

const sdae_map_type sdae__midpoint_type = {
    .name = "midpoint",
    .order = 2,
    .implicit = 1,
    .scratch = midpoint_scratch,
    .phi = midpoint_phi,
    .jac = midpoint_jac,
    .jac_given = midpoint_jac_given,
    .slope = 0.5, /* q0's derivative at the midpoint, halved */
};

const sdae_map_type *const sdae_map_midpoint = &sdae__midpoint_type;
