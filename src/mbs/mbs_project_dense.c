/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The projection's linear algebra on dense matrices (mbs_project_linalg.h): the null space of
 * G's pivoted QR, the rows below the floor dropped. */
#include <math.h>
#include <string.h>

#include "mbs_project_linalg.h"

void sdae__mbs_project_dense_init(sdae_mbs_project_dense *d, sdae_mbs_eval *eval) {
  memset(d, 0, sizeof *d);
  d->eval = eval;
  d->n_q = eval->n_q;
  d->n_c = eval->n_c;
}

static void carve(void *p, sdae_arena *a) {
  sdae_mbs_project_dense *d = p;
  sdae__mbs_nullspace_carve(&d->ns, d->n_q, d->n_c, a);
  d->M = sdae__take(a, d->n_q, d->n_q);
  d->G = sdae__take(a, d->n_c, d->n_q);
}

static int factor(void *p, double t, const double *q, double floor) {
  sdae_mbs_project_dense *d = p;
  int rc;
  if ((rc = sdae__mbs_jacobian(d->eval, t, q, d->G)) != SDAE_OK ||
      (rc = sdae__mbs_mass_symmetric(d->eval, t, q, d->M)) != SDAE_OK)
    return rc;
  return sdae__mbs_nullspace_factor(&d->ns, d->G, d->M, floor);
}

/* the same QR, its rank counted again: a higher floor only drops rows */
static int refactor(void *p, double floor) {
  sdae_mbs_project_dense *d = p;
  return sdae__mbs_nullspace_truncate(&d->ns, floor);
}

static void solve(void *p, const double *F, const double *g, double *x) {
  sdae_mbs_project_dense *d = p;
  sdae__mbs_nullspace_solve(&d->ns, F, g, x);
}

static int gamma_at(void *p, double t, const double *q, const double *v, double *gamma) {
  sdae_mbs_project_dense *d = p;
  return sdae__mbs_along(d->eval, t, q, v, NULL, NULL, gamma);
}

static void g_times(const void *p, const double *x, const double *add, double *out) {
  const sdae_mbs_project_dense *d = p;
  for (size_t j = 0; j < d->n_c; j++) {
    double s = add ? add[j] : 0.0;
    for (size_t i = 0; i < d->n_q; i++) s += d->G[j * d->n_q + i] * x[i];
    out[j] = s;
  }
}

static double row_size(const void *p, size_t j) {
  const sdae_mbs_project_dense *d = p;
  double s = 0.0;
  for (size_t i = 0; i < d->n_q; i++) s += fabs(d->G[j * d->n_q + i]);
  return s;
}

const sdae_mbs_project_linalg sdae__mbs_project_dense_linalg = {
    .carve = carve,
    .factor = factor,
    .refactor = refactor,
    .solve = solve,
    .gamma = gamma_at,
    .g_times = g_times,
    .row_size = row_size,
};
