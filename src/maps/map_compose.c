/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Maps of higher order: a symmetric map Psi_h of order 2 (Psi_-h the inverse of Psi_h) composed
 * symmetrically,
 *
 *   Psi_T = Psi_{g_s T} o ... o Psi_{g_1 T},   g_i = g_{s+1-i},   sum g_i = 1,
 *
 * and phi_T(mu) = (Psi_T(mu) - mu)/T. The map is explicit in mu+ (its stages are solved
 * inside), so the step stays one scheme-11/15 step: xi is updated once per T, never by a
 * negative substep. Two symmetric bases:
 *
 *   the discrete gradient (Gonzalez's, with S at the midpoint): each stage conserves H when S
 *     is skew, so dg4 and dg6 do;
 *   the implicit midpoint map, which needs q0 only (any forces, time-dependent models):
 *     midpoint4 and midpoint6.
 *
 * and two compositions:
 *
 *   order 4: Yoshida's triple jump, g = (g1, 1 - 2 g1, g1), g1 = 1/(2 - 2^(1/3));
 *   order 6: Kahan and Li's s9odr6a (Hairer, Lubich, Wanner, Geometric Numerical Integration,
 *            V.3.2), 9 stages, with an error constant so much smaller than the triple jump's
 *            that it is the cheaper of the two for tight tolerances (docs/performance.md). */
#include "core/callback.h"
#include "map.h"

/* both satisfy sum g = 1 and sum g^3 = 0; s9odr6a also sum g^5 = 0 (to 1e-26) */
static const double triple_jump[3] = {1.3512071919596576340, -1.7024143839193152681,
                                      1.3512071919596576340};
static const double s9odr6a[9] = {
    0.39216144400731413928,  0.33259913678935943860, -0.70624617255763935981,
    0.08221359629355080023,  0.79854399093482996340, 0.08221359629355080023,
    -0.70624617255763935981, 0.33259913678935943860, 0.39216144400731413928};

static int dg_needs(const sdae_model *m) { return sdae__dgrad_type.needs(m); }

/* the stage's start and end, then the base map's scratch */
static size_t stage_scratch(const sdae_map_type *base, const sdae_model *m, const sdae_options *o) {
  return 2 * m->n_mu + base->scratch(m, o);
}

static size_t dg_scratch(const sdae_model *m, const sdae_options *o) {
  return stage_scratch(&sdae__dgrad_type, m, o);
}

static size_t midpoint_scratch(const sdae_model *m, const sdae_options *o) {
  return stage_scratch(&sdae__midpoint_type, m, o);
}

/* a new step: the base map forgets what it kept, in its part of the scratch */
static void compose_begin(sdae_map_ctx *c, const sdae_map_type *base) {
  sdae_map_ctx stage = *c;
  if (!base->begin) return;
  stage.work = c->work + 2 * c->model->n_mu;
  base->begin(&stage);
}

static void dg_begin(sdae_map_ctx *c) { compose_begin(c, &sdae__dgrad_type); }

/* Psi_T(mu) by the map's stages, each y = Psi_h(x): Newton on y = x + h phi(x, y) from the
 * predictor x + h phi(x, x); phi_T = (Psi_T(mu) - mu) / T. The stages see the context with
 * the base map's part of the scratch. */
static int compose(const sdae_map_type *map, sdae_map_ctx *c, double t, double T, const double *mu,
                   double *out) {
  const sdae_map_type *base = map->base;
  size_t n = c->model->n_mu;
  double *x = c->work, *y = x + n;
  sdae_map_ctx stage = *c;
  int rc = SDAE_OK;
  stage.work = y + n;
  sdae__copy(x, mu, n);
  for (size_t k = 0; k < map->stages && rc == SDAE_OK; k++) {
    double h = map->gamma[k] * T;
    rc = sdae__map_phi(base, &stage, t, h, x, x, y);
    for (size_t i = 0; i < n; i++) y[i] = x[i] + h * y[i];
    if (rc == SDAE_OK) rc = sdae__map_solve(base, &stage, t, h, x, NULL, y);
    t += h;
    sdae__copy(x, y, n);
  }
  c->phi_evals = stage.phi_evals;
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) out[i] = (x[i] - mu[i]) / T;
  return SDAE_OK;
}

static int dg4_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                   double *out) {
  (void)mu_next;
  return compose(sdae_map_dg4, c, t, T, mu, out);
}

static int dg6_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                   double *out) {
  (void)mu_next;
  return compose(sdae_map_dg6, c, t, T, mu, out);
}

static int midpoint4_phi(sdae_map_ctx *c, double t, double T, const double *mu,
                         const double *mu_next, double *out) {
  (void)mu_next;
  return compose(sdae_map_midpoint4, c, t, T, mu, out);
}

static int midpoint6_phi(sdae_map_ctx *c, double t, double T, const double *mu,
                         const double *mu_next, double *out) {
  (void)mu_next;
  return compose(sdae_map_midpoint6, c, t, T, mu, out);
}

#define STAGES(g) (sizeof(g) / sizeof *(g))

static const sdae_map_type dg4_type = {
    .name = "dg4",
    .order = 4,
    .implicit = 0,
    .needs = dg_needs,
    .scratch = dg_scratch,
    .begin = dg_begin,
    .phi = dg4_phi,
    .base = &sdae__dgrad_type,
    .gamma = triple_jump,
    .stages = STAGES(triple_jump),
};

static const sdae_map_type dg6_type = {
    .name = "dg6",
    .order = 6,
    .implicit = 0,
    .needs = dg_needs,
    .scratch = dg_scratch,
    .begin = dg_begin,
    .phi = dg6_phi,
    .base = &sdae__dgrad_type,
    .gamma = s9odr6a,
    .stages = STAGES(s9odr6a),
};

static const sdae_map_type midpoint4_type = {
    .name = "midpoint4",
    .order = 4,
    .implicit = 0,
    .scratch = midpoint_scratch,
    .phi = midpoint4_phi,
    .base = &sdae__midpoint_type,
    .gamma = triple_jump,
    .stages = STAGES(triple_jump),
};

static const sdae_map_type midpoint6_type = {
    .name = "midpoint6",
    .order = 6,
    .implicit = 0,
    .scratch = midpoint_scratch,
    .phi = midpoint6_phi,
    .base = &sdae__midpoint_type,
    .gamma = s9odr6a,
    .stages = STAGES(s9odr6a),
};

const sdae_map_type *const sdae_map_dg4 = &dg4_type;
const sdae_map_type *const sdae_map_dg6 = &dg6_type;
const sdae_map_type *const sdae_map_midpoint4 = &midpoint4_type;
const sdae_map_type *const sdae_map_midpoint6 = &midpoint6_type;
