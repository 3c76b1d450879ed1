/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The dense coordinates as a type (mbs_dense_type.h): a step starts by evaluating at q (c, G and
 * dc/dt), choosing or keeping the chart at that G, forming mu and xi's floors, and on the
 * manifold seeding Phi^-1 with the start itself; the rest is mbs_coords.c's and mbs_query.c's,
 * and the energy structure on the manifold (docs/front-ends.md, the mechanical front-end). */
#include <string.h>

#include "maps/map.h"
#include "mbs_dense_type.h"

static int init(void *p, sdae_mbs_eval *eval, const sdae_options *o) {
  sdae_mbs_dense_parts *d = p;
  d->eval = eval;
  eval->matrices = 1;
  d->energy_map = o->map && sdae__map_uses_H(o->map); /* no map: refused by the validation */
  sdae__mbs_chart_init(&d->chart, eval->n_q, eval->n_c);
  sdae__mbs_coords_init(&d->coords, eval, &d->chart, o->newton_max_iter);
  return SDAE_OK;
}

static int carve(void *p, sdae_arena *a) {
  sdae_mbs_dense_parts *d = p;
  size_t n_q = d->eval->n_q, n_c = d->eval->n_c;
  sdae__mbs_chart_carve(&d->chart, a);
  sdae__mbs_coords_carve(&d->coords, a);
  sdae__mbs_query_carve(&d->query, n_q, n_c, a);
  d->zero = sdae__take(a, 2 * n_c, 1);
  if (d->zero) /* NULL while the block is only counted */
    memset(d->zero, 0, 2 * n_c * sizeof *d->zero);
  d->D = sdae__take(a, n_q, n_q);
  d->F_in = sdae__take(a, n_q, 1);
  return SDAE_OK;
}

/* the energy-conserving maps need time-independent constraints */
static int energy_map_ok(const sdae_mbs_dense_parts *d) {
  if (!d->energy_map) return SDAE_OK;
  for (size_t j = 0; j < d->eval->n_c; j++)
    if (d->coords.ct[j] != 0.0) return SDAE_ERR_MAP;
  return SDAE_OK;
}

static int start(void *p, double t, const double *q, const double *v, int force_best,
                 sdae_mbs_start *st) {
  sdae_mbs_dense_parts *d = p;
  sdae_mbs_coords *co = &d->coords;
  int rc;
  if ((rc = sdae__mbs_coords_xi(co, t, q, v, st->xi)) != SDAE_OK ||
      (rc = energy_map_ok(d)) != SDAE_OK ||
      (rc = sdae__mbs_chart_choose(&d->chart, co->G, force_best)) != SDAE_OK)
    return rc;
  st->switched = d->chart.switched, st->kept = d->chart.kept;
  if ((rc = sdae__mbs_coords_begin(co, t, q, v, st->mu)) != SDAE_OK) return rc;
  sdae__mbs_coords_floors(co, q, v, st->floor);
  if (!sdae__mbs_at_floors(st->xi, st->floor, 2 * d->eval->n_c)) return SDAE_OK;
  return sdae__mbs_coords_seed(co, t, q, v, st->mu);
}

static int phi_inv(void *p, double t, const double *xi, const double *mu) {
  return sdae__mbs_phi_inv(&((sdae_mbs_dense_parts *)p)->coords, t, xi, mu);
}

static int phi_inv_state(void *p, double t, const double *xi, const double *mu) {
  return sdae__mbs_phi_inv_state(&((sdae_mbs_dense_parts *)p)->coords, t, xi, mu);
}

static int mu_dot(void *p, double t, double *out) {
  return sdae__mbs_mu_dot(&((sdae_mbs_dense_parts *)p)->coords, t, out);
}

static void point(const void *p, double *q, double *v) {
  const sdae_mbs_coords *co = &((const sdae_mbs_dense_parts *)p)->coords;
  memcpy(q, co->q, co->n_q * sizeof *q);
  memcpy(v, co->v, co->n_q * sizeof *v);
}

static void report(const void *p, sdae_mbs_report *r) {
  const sdae_mbs_dense_parts *d = p;
  r->phi_inv_iters = d->coords.phi_inv_iters;
  r->measure = d->chart.measure;
}

static int chart(const void *p, size_t *dependent) {
  const sdae_mbs_atlas *ch = &((const sdae_mbs_dense_parts *)p)->chart;
  if (!ch->have) return SDAE_ERR_CHART;
  memcpy(dependent, ch->dep, ch->n_c * sizeof *dependent);
  return SDAE_OK;
}

static void state(void *p, sdae_bytes *b) {
  sdae_mbs_dense_parts *d = p;
  sdae__mbs_chart_state(&d->chart, b);
  sdae__mbs_coords_state(&d->coords, b);
}

static int state_read(void *p) {
  return sdae__mbs_chart_valid(&((sdae_mbs_dense_parts *)p)->chart);
}

static int xi(void *p, double t, const double *q, const double *v, double *out) {
  sdae_mbs_dense_parts *d = p;
  return sdae__mbs_query_xi(&d->query, d->eval, t, q, v, out);
}

static int energy(void *p, double t, const double *q, const double *v, double *E) {
  sdae_mbs_dense_parts *d = p;
  return sdae__mbs_query_energy(&d->query, d->eval, t, q, v, E);
}

static int lambda(void *p, double t, const double *q, const double *v, double *out) {
  sdae_mbs_dense_parts *d = p;
  return sdae__mbs_query_lambda(&d->query, d->eval, t, q, v, out);
}

/* ---- the energy structure at Phi^-1(t, 0, mu) (mbs_model.c) ---- */

static int energy_on(void *p, double t, const double *mu, double *H) {
  sdae_mbs_dense_parts *d = p;
  const sdae_mbs_coords *co = &d->coords;
  int rc = sdae__mbs_phi_inv(&d->coords, t, d->zero, mu);
  return rc == SDAE_OK ? sdae__mbs_energy_of(d->eval, t, co->q, co->v, co->M, H) : rc;
}

/* R = W^T D W; zero without damping */
static int damping_on(void *p, double t, const double *mu, double *R) {
  sdae_mbs_dense_parts *d = p;
  size_t n_q = d->chart.n_q, n_f = d->chart.n_f;
  const double *W = d->chart.W, *D = d->D;
  int rc;
  memset(R, 0, n_f * n_f * sizeof *R);
  if (!d->eval->sys.damping) return SDAE_OK;
  if ((rc = sdae__mbs_phi_inv(&d->coords, t, d->zero, mu)) != SDAE_OK ||
      (rc = sdae__mbs_damping(d->eval, t, d->coords.q, d->D)) != SDAE_OK)
    return rc;
  for (size_t a = 0; a < n_f; a++)
    for (size_t b = 0; b < n_f; b++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++)
        for (size_t j = 0; j < n_q; j++) acc += W[i * n_f + a] * D[i * n_q + j] * W[j * n_f + b];
      R[a * n_f + b] = acc;
    }
  return SDAE_OK;
}

/* W^T F_in, the momentum part of B u */
static int input_on(void *p, double t, const double *mu, double *Bu) {
  sdae_mbs_dense_parts *d = p;
  const sdae_mbs_coords *co = &d->coords;
  int rc;
  if ((rc = sdae__mbs_phi_inv(&d->coords, t, d->zero, mu)) != SDAE_OK ||
      (rc = sdae__mbs_input_force(d->eval, t, co->q, co->v, d->F_in)) != SDAE_OK)
    return rc;
  sdae__mbs_Wt(&d->chart, d->F_in, Bu);
  return SDAE_OK;
}

const sdae_mbs_type sdae__mbs_dense_type = {
    .name = "dense",
    .init = init,
    .carve = carve,
    .start = start,
    .phi_inv = phi_inv,
    .phi_inv_state = phi_inv_state,
    .mu_dot = mu_dot,
    .point = point,
    .report = report,
    .chart = chart,
    .state = state,
    .state_read = state_read,
    .xi = xi,
    .energy = energy,
    .lambda = lambda,
    .energy_on = energy_on,
    .damping_on = damping_on,
    .input_on = input_on,
};
