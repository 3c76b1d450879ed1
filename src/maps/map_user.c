/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A user map phi_T(mu, mu+): the model's user_phi, with its optional Jacobian user_phi_jac
 * (e.g. the paper's Section IV map). */
#include "map.h"
#include "model/model.h"

static int user_needs(const sdae_model *m) { return m->user_phi ? SDAE_OK : SDAE_ERR_MAP; }

static int user_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                    double *out) {
  const sdae_model *m = c->model;
  return sdae__callback_checked(m->user_phi(t, T, mu, mu_next, out, m->params), out, m->n_mu);
}

static int user_jac(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                    double *out) {
  const sdae_model *m = c->model;
  return sdae__callback_checked(m->user_phi_jac(t, T, mu, mu_next, out, m->params), out,
                                m->n_mu * m->n_mu);
}

static int user_jac_given(const sdae_model *m) { return m->user_phi_jac != NULL; }

/* Implicit: a user map may depend on mu+; for one that does not, Newton converges in one
 * iteration. Its order is the user's. */
static const sdae_map_type user_type = {
    .name = "user",
    .order = 0,
    .implicit = 1,
    .needs = user_needs,
    .phi = user_phi,
    .jac = user_jac,
    .jac_given = user_jac_given,
};

const sdae_map_type *const sdae_map_user = &user_type;
