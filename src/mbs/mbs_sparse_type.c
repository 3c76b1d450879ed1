/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A sparse mechanism's coordinates as a type (mbs_sparse_type.h): a step starts as the dense
 * one does (mbs_dense_type.c), with the chart kept or chosen by mbs_sparse.c's sparse LU at the
 * G evaluated there. */
#include <string.h>

#include "mbs_sparse_type.h"

static int init(void *p, sdae_mbs_eval *eval, const sdae_options *o) {
  sdae_mbs_sparse_parts *s = p;
  eval->matrices = 0; /* the stencils' dense matrices grow with n_q^2 */
  sdae__mbs_sparse_init(&s->sp, eval, o->newton_max_iter);
  return sdae__mbs_sparse_fits(&s->sp) ? SDAE_OK : SDAE_ERR_OVERFLOW;
}

static int carve(void *p, sdae_arena *a) {
  sdae_mbs_sparse_parts *s = p;
  int rc = sdae__mbs_sparse_carve(&s->sp, a);
  sdae__mbs_sparse_query_carve(&s->query, &s->sp, a);
  return rc;
}

static int start(void *p, double t, const double *q, const double *v, int force_best,
                 sdae_mbs_start *st) {
  sdae_mbs_sparse *sp = &((sdae_mbs_sparse_parts *)p)->sp;
  int rc;
  if ((rc = sdae__mbs_sparse_xi(sp, t, q, v, st->xi)) != SDAE_OK ||
      (rc = sdae__mbs_sparse_choose(sp, force_best)) != SDAE_OK)
    return rc;
  st->switched = sp->switched, st->kept = sp->kept;
  if ((rc = sdae__mbs_sparse_begin(sp, t, q, v, st->mu)) != SDAE_OK) return rc;
  sdae__mbs_sparse_floors(sp, q, v, st->floor);
  if (!sdae__mbs_at_floors(st->xi, st->floor, 2 * sp->n_c)) return SDAE_OK;
  return sdae__mbs_sparse_seed(sp, t, q, v, st->mu);
}

static int phi_inv(void *p, double t, const double *xi, const double *mu) {
  return sdae__mbs_sparse_phi_inv(&((sdae_mbs_sparse_parts *)p)->sp, t, xi, mu);
}

static int phi_inv_state(void *p, double t, const double *xi, const double *mu) {
  return sdae__mbs_sparse_phi_inv_state(&((sdae_mbs_sparse_parts *)p)->sp, t, xi, mu);
}

static int mu_dot(void *p, double t, double *out) {
  return sdae__mbs_sparse_mu_dot(&((sdae_mbs_sparse_parts *)p)->sp, t, out);
}

static void point(const void *p, double *q, double *v) {
  const sdae_mbs_sparse *sp = &((const sdae_mbs_sparse_parts *)p)->sp;
  memcpy(q, sp->q, sp->n_q * sizeof *q);
  memcpy(v, sp->v, sp->n_q * sizeof *v);
}

static void report(const void *p, sdae_mbs_report *r) {
  const sdae_mbs_sparse *sp = &((const sdae_mbs_sparse_parts *)p)->sp;
  r->phi_inv_iters = sp->phi_inv_iters;
  r->measure = sp->measure;
}

static int chart(const void *p, size_t *dependent) {
  const sdae_mbs_sparse *sp = &((const sdae_mbs_sparse_parts *)p)->sp;
  if (!sp->have) return SDAE_ERR_CHART;
  sdae__mbs_sparse_chart(sp, dependent);
  return SDAE_OK;
}

static void state(void *p, sdae_bytes *b) {
  sdae__mbs_sparse_state(&((sdae_mbs_sparse_parts *)p)->sp, b);
}

/* the factors are not in the bytes: made anew at the next step's start, once the bytes read
 * are whole (a refused state leaves the stepper as it was, its factors' flag too) */
static int state_read(void *p) {
  sdae_mbs_sparse *sp = &((sdae_mbs_sparse_parts *)p)->sp;
  if (!sdae__mbs_sparse_valid(sp)) return 0;
  sdae__mbs_sparse_stale(sp);
  return 1;
}

static int xi(void *p, double t, const double *q, const double *v, double *out) {
  return sdae__mbs_sparse_query_xi(&((sdae_mbs_sparse_parts *)p)->query, t, q, v, out);
}

static int energy(void *p, double t, const double *q, const double *v, double *E) {
  return sdae__mbs_sparse_query_energy(&((sdae_mbs_sparse_parts *)p)->query, t, q, v, E);
}

static int lambda(void *p, double t, const double *q, const double *v, double *out) {
  return sdae__mbs_sparse_query_lambda(&((sdae_mbs_sparse_parts *)p)->query, t, q, v, out);
}

const sdae_mbs_type sdae__mbs_sparse_type = {
    .name = "sparse",
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
};
