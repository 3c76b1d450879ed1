/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The dense back-end (mbs_dense.h): the chart by pivoted QR of G (mbs_chart.c), with
 * W = P [-A; I], A = G_D^-1 G_I formed; the velocity v = z + W v_I with G_D z_D = g and the
 * reduced mass W^T M W v_I = p - W^T M z; the momentum rate with
 * dW/dt = P [-G_D^-1 (dG/dt) W; 0], so that (dW/dt)^T M v = -(G_D^-1 (dG/dt) W)^T (M v)_D. */
#include <math.h>
#include <string.h>

#include "core/callback.h"
#include "core/lu.h"
#include "mbs_dense.h"

static int init(void *p, sdae_mbs_eval *eval, const sdae_options *o) {
  sdae_mbs_dense *d = p;
  (void)o;
  d->eval = eval;
  eval->matrices = 1;
  d->n_q = eval->n_q, d->n_c = eval->n_c, d->n_f = eval->n_q - eval->n_c;
  sdae__mbs_chart_init(&d->chart, eval->n_q, eval->n_c);
  return SDAE_OK;
}

static int carve(void *p, sdae_arena *a) {
  sdae_mbs_dense *d = p;
  size_t n_q = d->n_q, n_c = d->n_c, n_f = d->n_f;
  sdae__mbs_chart_carve(&d->chart, a);
  sdae__mbs_query_carve(&d->query, n_q, n_c, d->eval->n_rows, a);
  d->G = sdae__take(a, n_c, n_q);
  d->M = sdae__take(a, n_q, n_q);
  d->Mr = sdae__take(a, n_f, n_f);
  d->Y = sdae__take(a, n_q, 1);
  d->z_D = sdae__take(a, n_c, 1);
  d->Mz = sdae__take(a, n_q, 1);
  d->v_I = sdae__take(a, n_f, 1);
  d->Gdot = sdae__take(a, n_c, n_q);
  d->Mdv = sdae__take(a, n_q, 1);
  d->Mv = sdae__take(a, n_q, 1);
  d->GdW = sdae__take(a, n_c, 1);
  d->X = sdae__take(a, n_c, 1);
  d->dW = sdae__take(a, n_f, 1);
  d->D = sdae__take(a, n_q, n_q);
  return SDAE_OK;
}

/* ---- G and M, and products with them ---- */

static int jacobian(void *p, double t, const double *q) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_jacobian(d->eval, t, q, d->G);
}

static int mass(void *p, double t, const double *q) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_mass(d->eval, t, q, d->M);
}

static int mass_symmetric(const void *p) {
  const sdae_mbs_dense *d = p;
  return sdae__symmetric(d->M, d->n_q) ? SDAE_OK : SDAE_ERR_MASS;
}

static void g_times(const void *p, const double *x, const double *add, double *out) {
  const sdae_mbs_dense *d = p;
  for (size_t j = 0; j < d->n_c; j++) {
    double s = add ? add[j] : 0.0;
    for (size_t i = 0; i < d->n_q; i++) s += d->G[j * d->n_q + i] * x[i];
    out[j] = s;
  }
}

static void mat_vec(const double *M, size_t n, const double *x, double *y) {
  for (size_t i = 0; i < n; i++) {
    double acc = 0.0;
    for (size_t j = 0; j < n; j++) acc += M[i * n + j] * x[j];
    y[i] = acc;
  }
}

static void m_times(const void *p, const double *x, double *out) {
  const sdae_mbs_dense *d = p;
  mat_vec(d->M, d->n_q, x, out);
}

static double row_size(const void *p, size_t j) {
  const sdae_mbs_dense *d = p;
  double g = 0.0;
  for (size_t i = 0; i < d->n_q; i++) g += fabs(d->G[j * d->n_q + i]);
  return g;
}

/* ---- the chart (mbs_chart.c) ---- */

static int choose(void *p, int force_best, int reuse, sdae_mbs_choice *choice) {
  sdae_mbs_dense *d = p;
  int rc = sdae__mbs_chart_choose(&d->chart, d->G, force_best);
  (void)reuse; /* the best chart is sought at every start */
  choice->independence = d->chart.independence;
  if (rc == SDAE_OK) choice->switched = d->chart.switched, choice->kept = d->chart.kept;
  return rc;
}

static int factor(void *p) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_chart_factor(&d->chart, d->G, NULL);
}

static int gd_factor(void *p) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_gd_factor(&d->chart, d->G);
}

static void split(const void *p, const size_t **dep, const size_t **ind) {
  const sdae_mbs_dense *d = p;
  *dep = d->chart.dep, *ind = d->chart.ind;
}

static void gd_solve(void *p, const double *rhs, double *x) {
  const sdae_mbs_dense *d = p;
  sdae__mbs_gd_solve(&d->chart, rhs, x);
}

static void move(void *p, const double *dxi, const double *dq, double *dq_D) {
  sdae_mbs_dense *d = p;
  const sdae_mbs_atlas *ch = &d->chart;
  size_t n_f = d->n_f;
  sdae__mbs_gd_solve(ch, dxi, dq_D);
  for (size_t j = 0; j < d->n_c; j++) {
    double acc = dq_D[j];
    for (size_t k = 0; k < n_f; k++) acc -= ch->A[j * n_f + k] * dq[ch->ind[k]];
    dq_D[j] = acc;
  }
}

static void wt(void *p, const double *y, double *out) {
  sdae_mbs_dense *d = p;
  sdae__mbs_Wt(&d->chart, y, out);
}

/* ---- the velocity ---- */

/* the reduced mass W^T M W (n_f x n_f) into d->Mr, factored: symmetric by construction
 * (docs/front-ends.md, the price of zero drift), Y = M W column by column, then the upper
 * triangle of W^T Y, mirrored. Formed entry by entry, its two triangles would round differently
 * by up to eps times M's largest entries, which W^T M W need not have (a heavy direction across
 * the constraints): Cholesky would then see a non-symmetric matrix. */
static int reduced_mass(sdae_mbs_dense *d) {
  size_t n_q = d->n_q, n_f = d->n_f;
  const double *W = d->chart.W;
  for (size_t b = 0; b < n_f; b++) {
    for (size_t i = 0; i < n_q; i++) {
      double acc = 0.0;
      for (size_t j = 0; j < n_q; j++) acc += d->M[i * n_q + j] * W[j * n_f + b];
      d->Y[i] = acc;
    }
    for (size_t a = 0; a <= b; a++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += W[i * n_f + a] * d->Y[i];
      d->Mr[a * n_f + b] = d->Mr[b * n_f + a] = acc;
    }
  }
  return sdae__cholesky_factor(d->Mr, n_f);
}

/* the reduced mass depends on the chart (W): formed whatever reuse says */
static int velocity_factor(void *p, int reuse) {
  (void)reuse;
  return reduced_mass(p);
}

/* v = z + W v_I with G z = g (z_I = 0) and W^T M v = p */
static int velocity(void *p, const double *g, const double *mom, double *v) {
  sdae_mbs_dense *d = p;
  const sdae_mbs_atlas *ch = &d->chart;
  size_t n_q = d->n_q, n_c = d->n_c, n_f = d->n_f;
  sdae__mbs_gd_solve(ch, g, d->z_D);
  memset(v, 0, n_q * sizeof *v);
  for (size_t j = 0; j < n_c; j++) v[ch->dep[j]] = d->z_D[j];
  mat_vec(d->M, n_q, v, d->Mz);
  sdae__mbs_Wt(ch, d->Mz, d->v_I);
  for (size_t k = 0; k < n_f; k++) d->v_I[k] = mom[k] - d->v_I[k];
  sdae__cholesky_solve(d->Mr, n_f, d->v_I);
  for (size_t i = 0; i < n_q; i++)
    for (size_t k = 0; k < n_f; k++) v[i] += ch->W[i * n_f + k] * d->v_I[k];
  return sdae__all_finite(v, n_q) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

/* the momentum rate reads M v and dG/dt at the point: nothing of a solve */
static int seed(void *p, int reuse, const double *g, const double *mom, double *v) {
  (void)g, (void)mom, (void)v;
  return velocity_factor(p, reuse);
}

/* ---- the momentum rate ---- */

/* d->dW = X^T (M v)_D with X = G_D^-1 (dG/dt) W: minus the term (dW/dt)^T M v */
static void dW_term(sdae_mbs_dense *d) {
  const sdae_mbs_atlas *ch = &d->chart;
  size_t n_q = d->n_q, n_c = d->n_c, n_f = d->n_f;
  for (size_t k = 0; k < n_f; k++) {
    for (size_t j = 0; j < n_c; j++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += d->Gdot[j * n_q + i] * ch->W[i * n_f + k];
      d->GdW[j] = acc;
    }
    sdae__mbs_gd_solve(ch, d->GdW, d->X);
    d->dW[k] = 0.0;
    for (size_t j = 0; j < n_c; j++) d->dW[k] += d->X[j] * d->Mv[ch->dep[j]];
  }
}

static int momentum_rate(void *p, double t, const double *q, const double *v, double *F,
                         double *out) {
  sdae_mbs_dense *d = p;
  size_t n_q = d->n_q;
  int rc = sdae__mbs_along(d->eval, t, q, v, d->Gdot, d->Mdv, NULL);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n_q; i++) F[i] += d->Mdv[i];
  sdae__mbs_Wt(&d->chart, F, out);
  mat_vec(d->M, n_q, v, d->Mv);
  dW_term(d);
  for (size_t k = 0; k < d->n_f; k++) out[k] -= d->dW[k];
  return SDAE_OK;
}

/* ---- the energy structure ---- */

static int energy(void *p, double t, const double *q, const double *v, double *E) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_energy_of(d->eval, t, q, v, d->M, E);
}

/* D x, D evaluated at q */
static int damping_times(void *p, double t, const double *q, const double *x, double *out) {
  sdae_mbs_dense *d = p;
  int rc = sdae__mbs_damping(d->eval, t, q, d->D);
  if (rc == SDAE_OK) mat_vec(d->D, d->n_q, x, out);
  return rc;
}

/* ---- the chart's and the state's ---- */

static int chart(const void *p, size_t *dependent) {
  const sdae_mbs_atlas *ch = &((const sdae_mbs_dense *)p)->chart;
  if (!ch->have) return SDAE_ERR_CHART;
  memcpy(dependent, ch->dep, ch->n_c * sizeof *dependent);
  return SDAE_OK;
}

static double measure(const void *p) { return ((const sdae_mbs_dense *)p)->chart.measure; }

static void state(void *p, sdae_bytes *b) {
  sdae_mbs_dense *d = p;
  sdae__mbs_chart_state(&d->chart, b);
  sdae__bytes_doubles(b, d->G, d->n_c * d->n_q);
  sdae__bytes_doubles(b, d->M, d->n_q * d->n_q);
}

static int state_read(void *p) { return sdae__mbs_chart_valid(&((sdae_mbs_dense *)p)->chart); }

static int query_xi(void *p, double t, const double *q, const double *v, double *out) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_query_xi(&d->query, d->eval, t, q, v, out);
}

static int query_energy(void *p, double t, const double *q, const double *v, double *E) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_query_energy(&d->query, d->eval, t, q, v, E);
}

static int query_lambda(void *p, double t, const double *q, const double *v, double *out) {
  sdae_mbs_dense *d = p;
  return sdae__mbs_query_lambda(&d->query, d->eval, t, q, v, out);
}

const sdae_mbs_linalg sdae__mbs_dense_linalg = {
    .name = "dense",
    .init = init,
    .carve = carve,
    .jacobian = jacobian,
    .mass = mass,
    .mass_symmetric = mass_symmetric,
    .g_times = g_times,
    .m_times = m_times,
    .row_size = row_size,
    .choose = choose,
    .factor = factor,
    .gd_factor = gd_factor,
    .split = split,
    .gd_solve = gd_solve,
    .move = move,
    .wt = wt,
    .velocity_factor = velocity_factor,
    .velocity = velocity,
    .seed = seed,
    .momentum_rate = momentum_rate,
    .energy = energy,
    .damping_times = damping_times,
    .chart = chart,
    .measure = measure,
    .state = state,
    .state_read = state_read,
    .query_xi = query_xi,
    .query_energy = query_energy,
    .query_lambda = query_lambda,
};
