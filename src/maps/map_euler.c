/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The explicit map phi_T(mu, mu+) = q0(mu): order 1, no Newton. */
#include "map.h"
#include "model/model.h"

static int euler_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                     double *out) {
  (void)T;
  (void)mu_next;
  return sdae__eval_q0(c->model, t, mu, out);
}

static const sdae_map_type euler_type = {
    .name = "euler",
    .order = 1,
    .implicit = 0,
    .phi = euler_phi,
};

const sdae_map_type *const sdae_map_euler = &euler_type;
