/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a sparse mechanism at the cost of its nonzeros (mbs_sparse.h): the steps
 * of mbs_coords.c (docs/front-ends.md, the mechanical front-end) with every product through the
 * patterns, the chart's solves through core/sparse_lu.c and the saddle-point system's through
 * core/sparse_ldl.c. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/callback.h"
#include "core/lu.h"
#include "maps/map.h"
#include "mbs_sparse.h"

/* as mbs_coords.c's: a step of Newton from factors at its own iterate below this of 1 + |q_D|
 * has converged; xi_i at or below this times its terms is rounding; the state's q_D finished
 * from this far */
#define NEWTON_SMALL 1e-10
#define XI_ROUNDING (2.0 * DBL_EPSILON)
#define DITHER 0x1p-40

int sdae__mbs_sparse_applies(const sdae_mbs *sys, const sdae_options *o) {
  return sys->mass_pattern && sys->jacobian_pattern && sys->jacobian_dot && sys->mass_dot_v &&
         o->map && !sdae__map_uses_newton(o->map);
}

void sdae__mbs_sparse_init(sdae_mbs_sparse *sp, sdae_mbs_eval *eval, unsigned newton_max_iter) {
  sp->eval = eval;
  sp->n_q = eval->n_q;
  sp->n_c = eval->n_c;
  sp->n_f = sp->n_q - sp->n_c;
  sp->n_k = sp->n_q + sp->n_c;
  sp->newton_max_iter = newton_max_iter;
}

int sdae__mbs_sparse_fits(const sdae_mbs_sparse *sp) {
  const sdae_mbs *sys = &sp->eval->sys;
  size_t gnz = sys->jacobian_pattern->nnz, mnz = sys->mass_pattern->nnz;
  return gnz < SIZE_MAX / 4 && sdae__sparse_ldl_fits(sp->n_k, mnz + 2 * gnz);
}

/* ---- the saddle-point system's pattern ---- */

/* position of (i, j) in a pattern's row i, (size_t)-1 if none */
static size_t find(const sdae_pattern *p, size_t i, size_t j) {
  for (size_t e = p->row_start[i]; e < p->row_start[i + 1]; e++)
    if (p->col[e] == j) return e;
  return (size_t)-1;
}

/* K = [M G^T; G 0] in compressed rows, columns ascending: row i < n_q holds M's row i, then the
 * constraints whose rows hold column i; row n_q + j holds G's row j. start (n_k + 1) is G^T's
 * row counts first. */
static void build_k(sdae_mbs_sparse *sp, size_t *start, size_t *col) {
  const sdae_pattern *M = sp->Mp, *G = sp->Gp;
  size_t n_q = sp->n_q, *fill = sp->lu[0].count; /* n_q: the elimination's, free here */
  memset(fill, 0, n_q * sizeof *fill);
  for (size_t e = 0; e < G->nnz; e++) fill[G->col[e]]++;
  start[0] = 0;
  for (size_t i = 0; i < n_q; i++)
    start[i + 1] = start[i] + (M->row_start[i + 1] - M->row_start[i]) + fill[i];
  for (size_t j = 0; j < sp->n_c; j++)
    start[n_q + j + 1] = start[n_q + j] + (G->row_start[j + 1] - G->row_start[j]);
  for (size_t i = 0; i < n_q; i++) { /* M's row, then G^T's entries appended below */
    fill[i] = start[i];
    for (size_t e = M->row_start[i]; e < M->row_start[i + 1]; e++) {
      sp->k_of_m[e] = fill[i];
      col[fill[i]++] = M->col[e];
    }
  }
  for (size_t j = 0; j < sp->n_c; j++) /* rows j ascending: G^T's columns ascending */
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++) {
      size_t i = G->col[e];
      sp->k_of_gt[e] = fill[i];
      col[fill[i]++] = n_q + j;
      size_t k = start[n_q + j] + (e - G->row_start[j]);
      sp->k_of_g[e] = k;
      col[k] = i;
    }
  for (size_t i = 0; i < n_q; i++) /* the mirror of each mass entry (i, j): (j, i) */
    for (size_t e = M->row_start[i]; e < M->row_start[i + 1]; e++)
      sp->m_mirror[e] = find(M, M->col[e], i);
}

int sdae__mbs_sparse_carve(sdae_mbs_sparse *sp, sdae_arena *a) {
  size_t n_q = sp->n_q, n_c = sp->n_c, n_k = sp->n_k, *start, *col;
  const sdae_mbs *sys = &sp->eval->sys;
  size_t gnz = sys->jacobian_pattern->nnz, mnz = sys->mass_pattern->nnz, knz = mnz + 2 * gnz;
  sp->Gp = sys->jacobian_pattern, sp->Mp = sys->mass_pattern;
  sp->m_mirror = sdae__take_indices(a, mnz);
  sdae__sparse_lu_carve(&sp->lu[0], n_c, n_q, gnz, a);
  sdae__sparse_lu_carve(&sp->lu[1], n_c, n_q, gnz, a);
  sp->ind = sdae__take_indices(a, sp->n_f);
  start = sdae__take_indices(a, n_k + 1);
  col = sdae__take_indices(a, knz);
  sp->k_of_m = sdae__take_indices(a, mnz);
  sp->k_of_g = sdae__take_indices(a, gnz);
  sp->k_of_gt = sdae__take_indices(a, gnz);
  sp->K = sdae__take(a, knz, 1);
  sdae__sparse_ldl_symbolic_carve(&sp->ksym, n_k, n_q, knz, a);
  sdae__sparse_ldl_carve(&sp->kkt, &sp->ksym, a);
  sp->q = sdae__take(a, n_q, 1), sp->v = sdae__take(a, n_q, 1);
  sp->c = sdae__take(a, n_c, 1), sp->ct = sdae__take(a, n_c, 1);
  sp->G = sdae__take(a, gnz, 1), sp->M = sdae__take(a, mnz, 1), sp->Gd = sdae__take(a, gnz, 1);
  sp->nu = sdae__take(a, n_c, 1);
  sp->key = sdae__take(a, 2 * n_q, 1);
  sp->base_q = sdae__take(a, n_q, 1);
  sp->base_c = sdae__take(a, n_c, 1), sp->base_ct = sdae__take(a, n_c, 1);
  sp->Mv = sdae__take(a, n_q, 1), sp->F = sdae__take(a, n_q, 1), sp->Mdv = sdae__take(a, n_q, 1);
  sp->y = sdae__take(a, n_q, 1), sp->rhs = sdae__take(a, n_k, 1), sp->sol = sdae__take(a, n_k, 1);
  sp->zc = sdae__take(a, n_c, 1), sp->yd = sdae__take(a, n_c, 1);
  sp->q_D = sdae__take(a, n_c, 1), sp->res = sdae__take(a, n_c, 1);
  sp->est_x = sdae__take(a, n_q, 1), sp->est_z = sdae__take(a, n_q, 1);
  sdae__newton_carve_hooks(&sp->newton, n_c, NEWTON_SMALL, sp->newton_max_iter, a);
  sp->newton.keep = 1;
  sp->Kp = (sdae_pattern){knz, start, col};
  if (!start) return SDAE_OK; /* counted, not handed out */
  build_k(sp, start, col);
  return sdae__sparse_ldl_analyse(&sp->ksym, &sp->Kp);
}

void sdae__mbs_sparse_stale(sdae_mbs_sparse *sp) { sp->fresh = 0; }

/* ---- products through the patterns ---- */

static const sdae_sparse_lu *chart(const sdae_mbs_sparse *sp) { return &sp->lu[sp->cur]; }

void sdae__mbs_sparse_g_times(const sdae_mbs_sparse *sp, const double *vals, const double *x,
                              const double *add, double *out) {
  const sdae_pattern *G = sp->Gp;
  for (size_t j = 0; j < sp->n_c; j++) {
    double s = add ? add[j] : 0.0;
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++) s += vals[e] * x[G->col[e]];
    out[j] = s;
  }
}

void sdae__mbs_sparse_m_times(const sdae_mbs_sparse *sp, const double *vals, const double *x,
                              double *out) {
  const sdae_pattern *M = sp->Mp;
  for (size_t i = 0; i < sp->n_q; i++) {
    double s = 0.0;
    for (size_t e = M->row_start[i]; e < M->row_start[i + 1]; e++) s += vals[e] * x[M->col[e]];
    out[i] = s;
  }
}

/* out (n_f, by q_I) = W^T y = y_I - G_I^T G_D^-T y_D */
static void wt(sdae_mbs_sparse *sp, const double *y, double *out) {
  sdae_sparse_lu *lu = &sp->lu[sp->cur];
  const sdae_pattern *G = sp->Gp;
  double *acc = sp->est_x; /* n_q */
  for (size_t k = 0; k < sp->n_c; k++) sp->yd[k] = y[lu->pivot[k]];
  sdae__sparse_lu_solve_t(lu, sp->yd, sp->zc);
  for (size_t f = 0; f < sp->n_f; f++) acc[sp->ind[f]] = 0.0;
  for (size_t j = 0; j < sp->n_c; j++)
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++)
      if (lu->row_of[G->col[e]] == sp->n_c) acc[G->col[e]] += sp->G[e] * sp->zc[j];
  for (size_t f = 0; f < sp->n_f; f++) out[f] = y[sp->ind[f]] - acc[sp->ind[f]];
}

/* M symmetric to rounding, entry by its mirror (sdae__symmetric's rule on the nonzeros) */
int sdae__mbs_sparse_mass_symmetric(const sdae_mbs_sparse *sp, const double *M) {
  double asym = 0.0, big = 0.0;
  for (size_t e = 0; e < sp->Mp->nnz; e++) {
    double d = fabs(M[e] - M[sp->m_mirror[e]]);
    big = fmax(big, fabs(M[e]));
    asym = d > asym || d != d ? d : asym;
  }
  return asym <= 16.0 * (double)sp->n_q * DBL_EPSILON * big ? SDAE_OK : SDAE_ERR_MASS;
}

/* ---- the chart ---- */

/* the current chart's q_I: the columns no row pivots on */
static void independents(sdae_mbs_sparse *sp) {
  const sdae_sparse_lu *lu = chart(sp);
  for (size_t c = 0, f = 0; c < sp->n_q; c++)
    if (lu->row_of[c] == sp->n_c) sp->ind[f++] = c;
}

static double estimate(sdae_mbs_sparse *sp, int which) {
  return sdae__sparse_lu_norm1(&sp->lu[which], sp->est_x, sp->est_z);
}

/* the two factorizations split q alike (the same dependent coordinates) */
static int same_chart(const sdae_mbs_sparse *sp) {
  const size_t *a = sp->lu[0].row_of, *b = sp->lu[1].row_of, m = sp->n_c;
  for (size_t c = 0; c < sp->n_q; c++)
    if ((a[c] == m) != (b[c] == m)) return 0;
  return 1;
}

/* The current chart is refactored at the step's start and its ||G_D^-1 G_I||_1 estimated; a
 * new one is sought only when that grew past SDAE_MBS_CHART_FACTOR times its value where the
 * chart was chosen or last kept (or force_best), and taken when better by that factor, as the
 * dense hysteresis (mbs_chart.c), whose measure is the current chart's. A chart kept without a
 * search is kept too: a step that folds in it is retried in a chart chosen anew. */
int sdae__mbs_sparse_choose(sdae_mbs_sparse *sp, int force_best) {
  double now = HUGE_VAL, best;
  int other = 1 - sp->cur, rc;
  sp->kept = sp->switched = 0;
  if (sp->have &&
      (sp->reuse || sdae__sparse_lu_refactor(&sp->lu[sp->cur], sp->Gp, sp->G) == SDAE_OK)) {
    now = estimate(sp, sp->cur);
    sp->kept = 1;
    if (!force_best && now <= SDAE_MBS_CHART_FACTOR * sp->measure) return SDAE_OK;
  }
  if ((rc = sdae__sparse_lu_choose(&sp->lu[other], sp->Gp, sp->G)) != SDAE_OK)
    return now < HUGE_VAL ? SDAE_OK : rc; /* the current one serves */
  best = estimate(sp, other);
  if (sp->have && !force_best && now <= SDAE_MBS_CHART_FACTOR * best) {
    sp->measure = now; /* kept: its measure where it was kept */
    return SDAE_OK;
  }
  sp->kept = sp->switched = 0;
  sp->switched = sp->have && !same_chart(sp);
  sp->cur = other, sp->have = 1, sp->measure = best;
  independents(sp);
  return SDAE_OK;
}

void sdae__mbs_sparse_chart(const sdae_mbs_sparse *sp, size_t *dep) {
  const sdae_sparse_lu *lu = chart(sp);
  for (size_t c = 0, k = 0; c < sp->n_q; c++)
    if (lu->row_of[c] != sp->n_c) dep[k++] = c;
}

/* ---- xi at a state, the step's start ---- */

static int at_point(const sdae_mbs_sparse *sp, double t, const double *q, const double *v) {
  double dt = fabs(t - sp->key_t), size = fmax(fabs(t), fabs(sp->key_t));
  return sp->valid && (dt == 0.0 || dt <= 4.0 * DBL_EPSILON * size) &&
         memcmp(q, sp->q, sp->n_q * sizeof *q) == 0 && memcmp(v, sp->v, sp->n_q * sizeof *v) == 0;
}

static void xi_compose(const sdae_mbs_sparse *sp, const double *v, double *xi) {
  sdae__mbs_sparse_g_times(sp, sp->G, v, sp->ct, sp->zc);
  for (size_t j = 0; j < sp->n_c; j++) xi[2 * j] = sp->c[j], xi[2 * j + 1] = sp->zc[j];
}

int sdae__mbs_sparse_xi(sdae_mbs_sparse *sp, double t, const double *q, const double *v,
                        double *xi) {
  int rc;
  sp->at_start = at_point(sp, t, q, v);
  sp->reuse = sp->at_start && sp->fresh;
  sp->valid = sp->fresh = 0;
  sp->phi_inv_iters = 0;
  if ((rc = sdae__mbs_constraint(sp->eval, t, q, sp->c)) != SDAE_OK) return rc;
  if (!sp->at_start && ((rc = sdae__mbs_jacobian_values(sp->eval, t, q, sp->G)) != SDAE_OK ||
                        (rc = sdae__mbs_constraint_t(sp->eval, t, q, sp->ct)) != SDAE_OK))
    return rc;
  xi_compose(sp, v, xi);
  return SDAE_OK;
}

int sdae__mbs_sparse_begin(sdae_mbs_sparse *sp, double t, const double *q, const double *v,
                           double *mu) {
  int rc;
  sp->valid = 0;
  if (!sp->at_start && ((rc = sdae__mbs_mass_values(sp->eval, t, q, sp->M)) != SDAE_OK ||
                        (rc = sdae__mbs_sparse_mass_symmetric(sp, sp->M)) != SDAE_OK))
    return rc;
  sdae__mbs_sparse_m_times(sp, sp->M, v, sp->Mv);
  for (size_t f = 0; f < sp->n_f; f++) mu[f] = q[sp->ind[f]];
  wt(sp, sp->Mv, mu + sp->n_f);
  memcpy(sp->base_q, q, sp->n_q * sizeof *q);
  memcpy(sp->base_c, sp->c, sp->n_c * sizeof *sp->c);
  memcpy(sp->base_ct, sp->ct, sp->n_c * sizeof *sp->ct);
  sp->base_t = t, sp->base_here = 0;
  return SDAE_OK;
}

void sdae__mbs_sparse_floors(const sdae_mbs_sparse *sp, const double *q, const double *v,
                             double *floor) {
  const sdae_pattern *G = sp->Gp;
  double nq = 0.0, nv = 0.0;
  for (size_t i = 0; i < sp->n_q; i++) nq = fmax(nq, fabs(q[i])), nv = fmax(nv, fabs(v[i]));
  for (size_t j = 0; j < sp->n_c; j++) {
    double g = 0.0;
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++) g += fabs(sp->G[e]);
    floor[2 * j] = XI_ROUNDING * g * nq;
    floor[2 * j + 1] = XI_ROUNDING * (g * nv + fabs(sp->ct[j]));
  }
}

/* ---- the velocity: [M G^T; G 0] [v; nu] = [P^T (0, p); xi_v - dc/dt] ---- */

void sdae__mbs_sparse_kkt_values(const sdae_mbs_sparse *sp, const double *M, const double *G,
                                 double *K) {
  for (size_t e = 0; e < sp->Mp->nnz; e++) K[sp->k_of_m[e]] = M[e];
  for (size_t e = 0; e < sp->Gp->nnz; e++) K[sp->k_of_g[e]] = K[sp->k_of_gt[e]] = G[e];
}

/* K at the point's M and G, factored */
static int kkt_factor(sdae_mbs_sparse *sp) {
  sdae__mbs_sparse_kkt_values(sp, sp->M, sp->G, sp->K);
  return sdae__sparse_ldl_factor(&sp->kkt, sp->K);
}

/* v and nu at the point from p (mu's momenta) and xi's velocity part. The saddle-point solve
 * leaves G v - g at its own accuracy, which the chain's condition makes grow with its length
 * (N^2): v_D is then moved by G_D^-1 (g - G v), as the dense coordinates form v = z + W v_I with
 * G_D z_D = g, so that xi's velocity part stays at rounding (and Q's columns are skipped) */
static int solve_v(sdae_mbs_sparse *sp, const double *xi, const double *p) {
  sdae_sparse_lu *lu = &sp->lu[sp->cur];
  memset(sp->rhs, 0, sp->n_q * sizeof *sp->rhs);
  for (size_t f = 0; f < sp->n_f; f++) sp->rhs[sp->ind[f]] = p[f];
  for (size_t j = 0; j < sp->n_c; j++) sp->rhs[sp->n_q + j] = xi[2 * j + 1] - sp->ct[j];
  sdae__sparse_ldl_solve(&sp->kkt, sp->rhs, sp->sol);
  memcpy(sp->v, sp->sol, sp->n_q * sizeof *sp->v);
  memcpy(sp->nu, sp->sol + sp->n_q, sp->n_c * sizeof *sp->nu);
  sdae__mbs_sparse_g_times(sp, sp->G, sp->v, NULL, sp->res);
  for (size_t j = 0; j < sp->n_c; j++) sp->res[j] = sp->rhs[sp->n_q + j] - sp->res[j];
  sdae__sparse_lu_solve(lu, sp->res, sp->zc);
  for (size_t k = 0; k < sp->n_c; k++) sp->v[lu->pivot[k]] += sp->zc[k];
  return sdae__all_finite(sp->sol, sp->n_k) && sdae__all_finite(sp->v, sp->n_q)
             ? SDAE_OK
             : SDAE_ERR_NONFINITE;
}

int sdae__mbs_sparse_seed(sdae_mbs_sparse *sp, double t, const double *q, const double *v,
                          const double *mu) {
  int rc;
  memcpy(sp->q, q, sp->n_q * sizeof *q);
  memset(sp->key, 0, 2 * sp->n_c * sizeof *sp->key);
  if ((!sp->reuse && (rc = kkt_factor(sp)) != SDAE_OK) ||
      (rc = solve_v(sp, sp->key, mu + sp->n_f)) != SDAE_OK)
    return rc;
  memcpy(sp->v, v, sp->n_q * sizeof *v); /* the start's v, to rounding the one solved for */
  memcpy(sp->key + 2 * sp->n_c, mu, 2 * sp->n_f * sizeof *mu);
  sp->key_t = t, sp->valid = 1;
  memset(sp->base_c, 0, sp->n_c * sizeof *sp->base_c);
  sp->base_here = 1;
  return SDAE_OK;
}

/* ---- q_D from c(t, q) = xi's c-part: Newton's chord with G_D's factors ---- */

typedef struct q_eq {
  sdae_mbs_sparse *sp;
  double t;
  const double *xi;
} q_eq;

static void set_q_D(sdae_mbs_sparse *sp, const double *q_D) {
  const size_t *pivot = chart(sp)->pivot;
  for (size_t k = 0; k < sp->n_c; k++) sp->q[pivot[k]] = q_D[k];
}

static int q_residual(void *ctx, const double *y, double *R) {
  const q_eq *e = ctx;
  sdae_mbs_sparse *sp = e->sp;
  int rc;
  set_q_D(sp, y);
  if ((rc = sdae__mbs_constraint(sp->eval, e->t, sp->q, sp->c)) != SDAE_OK) return rc;
  for (size_t j = 0; j < sp->n_c; j++) R[j] = sp->c[j] - e->xi[2 * j];
  return SDAE_OK;
}

static int q_setup(void *ctx, const double *y) {
  const q_eq *e = ctx;
  sdae_mbs_sparse *sp = e->sp;
  int rc;
  set_q_D(sp, y);
  if ((rc = sdae__mbs_jacobian_values(sp->eval, e->t, sp->q, sp->G)) != SDAE_OK) return rc;
  return sdae__sparse_lu_refactor(&sp->lu[sp->cur], sp->Gp, sp->G) == SDAE_OK ? SDAE_OK
                                                                              : SDAE_ERR_PHI_INV;
}

static void q_solve(void *ctx, const double *R, double *dy) {
  const q_eq *e = ctx;
  sdae__sparse_lu_solve(&e->sp->lu[e->sp->cur], R, dy);
}

/* the chart's linearization at the base: q_I from mu, G_D dq_D = dxi_c - dc/dt dt - G_I dq_I,
 * G_D^-1 G_I dq_I by the factors' B */
static void predict(sdae_mbs_sparse *sp, double t, const double *xi, const double *mu) {
  sdae_sparse_lu *lu = &sp->lu[sp->cur];
  double *dq = sp->y; /* n_q: q_I's move, zero at q_D */
  memset(dq, 0, sp->n_q * sizeof *dq);
  for (size_t f = 0; f < sp->n_f; f++) dq[sp->ind[f]] = mu[f] - sp->base_q[sp->ind[f]];
  for (size_t j = 0; j < sp->n_c; j++)
    sp->res[j] = (xi[2 * j] - sp->base_c[j]) - sp->base_ct[j] * (t - sp->base_t);
  sdae__sparse_lu_solve(lu, sp->res, sp->q_D);
  sdae__sparse_lu_times_b(lu, dq, sp->zc);
  memcpy(sp->q, sp->base_q, sp->n_q * sizeof *sp->q);
  for (size_t f = 0; f < sp->n_f; f++) sp->q[sp->ind[f]] = mu[f];
  for (size_t k = 0; k < sp->n_c; k++) sp->q[lu->pivot[k]] += sp->q_D[k] - sp->zc[k];
  for (size_t k = 0; k < sp->n_c; k++) sp->q_D[k] = sp->q[lu->pivot[k]];
}

static int solve_q(sdae_mbs_sparse *sp, double t, const double *xi, const double *mu) {
  q_eq e = {sp, t, xi};
  const sdae_newton_system sys = {
      .residual = q_residual, .setup = q_setup, .solve = q_solve, .ctx = &e};
  int rc;
  predict(sp, t, xi, mu);
  sdae__newton_adopt(&sp->newton, 1.0);
  rc = sdae__newton_solve(&sp->newton, &sys, 1.0, sp->q_D);
  sp->phi_inv_iters += sp->newton.iters;
  sp->newton.iters = 0;
  set_q_D(sp, sp->q_D);
  if (rc == SDAE_ERR_NEWTON || rc == SDAE_ERR_SINGULAR) return SDAE_ERR_PHI_INV;
  return rc;
}

/* the state's q_D finished by a step of Newton from DITHER away (mbs_coords.c's finish) */
static int finish(sdae_mbs_sparse *sp, double t, const double *xi) {
  const sdae_sparse_lu *lu = chart(sp);
  int rc;
  for (size_t k = 0; k < sp->n_c; k++) {
    double *qd = &sp->q[lu->pivot[k]];
    *qd += DITHER * (1.0 + fabs(*qd));
  }
  if ((rc = sdae__mbs_constraint(sp->eval, t, sp->q, sp->c)) != SDAE_OK) return rc;
  for (size_t j = 0; j < sp->n_c; j++) sp->res[j] = sp->c[j] - xi[2 * j];
  sdae__sparse_lu_solve(&sp->lu[sp->cur], sp->res, sp->q_D);
  sp->phi_inv_iters++;
  for (size_t k = 0; k < sp->n_c; k++) sp->q[lu->pivot[k]] -= sp->q_D[k];
  return sdae__all_finite(sp->q, sp->n_q) ? SDAE_OK : SDAE_ERR_PHI_INV;
}

static int configuration(sdae_mbs_sparse *sp, double t, const double *xi, const double *mu,
                         int state) {
  int rc;
  sp->base_here = 0;
  if ((rc = solve_q(sp, t, xi, mu)) != SDAE_OK) return rc;
  if ((rc = sdae__mbs_jacobian_values(sp->eval, t, sp->q, sp->G)) != SDAE_OK) return rc;
  if (sdae__sparse_lu_refactor(&sp->lu[sp->cur], sp->Gp, sp->G) != SDAE_OK) return SDAE_ERR_PHI_INV;
  if (state && (rc = finish(sp, t, xi)) != SDAE_OK) return rc;
  if ((rc = sdae__mbs_constraint_t(sp->eval, t, sp->q, sp->ct)) != SDAE_OK ||
      (rc = sdae__mbs_mass_values(sp->eval, t, sp->q, sp->M)) != SDAE_OK ||
      (rc = kkt_factor(sp)) != SDAE_OK)
    return rc;
  memcpy(sp->base_q, sp->q, sp->n_q * sizeof *sp->q);
  for (size_t j = 0; j < sp->n_c; j++) sp->base_c[j] = xi[2 * j];
  memcpy(sp->base_ct, sp->ct, sp->n_c * sizeof *sp->ct);
  sp->base_t = t, sp->base_here = 1;
  return SDAE_OK;
}

static int same_point(const sdae_mbs_sparse *sp, double t, const double *xi, const double *mu) {
  return sp->valid && sp->key_t == t && memcmp(sp->key, xi, 2 * sp->n_c * sizeof *xi) == 0 &&
         memcmp(sp->key + 2 * sp->n_c, mu, 2 * sp->n_f * sizeof *mu) == 0;
}

static int same_configuration(const sdae_mbs_sparse *sp, double t, const double *xi,
                              const double *mu) {
  if (!sp->base_here || sp->base_t != t) return 0;
  for (size_t j = 0; j < sp->n_c; j++)
    if (xi[2 * j] != sp->base_c[j]) return 0;
  for (size_t f = 0; f < sp->n_f; f++)
    if (mu[f] != sp->base_q[sp->ind[f]]) return 0;
  return 1;
}

static int phi_inv(sdae_mbs_sparse *sp, double t, const double *xi, const double *mu, int state) {
  int rc;
  if (same_point(sp, t, xi, mu)) return SDAE_OK;
  sp->valid = 0;
  if (!same_configuration(sp, t, xi, mu) && (rc = configuration(sp, t, xi, mu, state)) != SDAE_OK)
    return rc;
  if ((rc = solve_v(sp, xi, mu + sp->n_f)) != SDAE_OK) return rc;
  memcpy(sp->key, xi, 2 * sp->n_c * sizeof *xi);
  memcpy(sp->key + 2 * sp->n_c, mu, 2 * sp->n_f * sizeof *mu);
  sp->key_t = t, sp->valid = 1;
  return SDAE_OK;
}

int sdae__mbs_sparse_phi_inv(sdae_mbs_sparse *sp, double t, const double *xi, const double *mu) {
  return phi_inv(sp, t, xi, mu, 0);
}

int sdae__mbs_sparse_phi_inv_state(sdae_mbs_sparse *sp, double t, const double *xi,
                                   const double *mu) {
  int rc = phi_inv(sp, t, xi, mu, 1);
  if (rc == SDAE_OK) rc = sdae__mbs_sparse_mass_symmetric(sp, sp->M);
  sp->fresh = rc == SDAE_OK; /* the next step's start, unless q or v are changed */
  return rc;
}

/* (v_I, W^T (F + (dM/dt) v + (dG/dt)^T nu)) at the point */
int sdae__mbs_sparse_mu_dot(sdae_mbs_sparse *sp, double t, double *out) {
  const sdae_pattern *G = sp->Gp;
  int rc;
  if ((rc = sdae__mbs_force(sp->eval, t, sp->q, sp->v, sp->F)) != SDAE_OK ||
      (rc = sdae__mbs_mass_dot_v(sp->eval, t, sp->q, sp->v, sp->Mdv)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian_dot_values(sp->eval, t, sp->q, sp->v, sp->Gd)) != SDAE_OK)
    return rc;
  for (size_t i = 0; i < sp->n_q; i++) sp->F[i] += sp->Mdv[i];
  for (size_t j = 0; j < sp->n_c; j++)
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++)
      sp->F[G->col[e]] += sp->Gd[e] * sp->nu[j];
  wt(sp, sp->F, out + sp->n_f);
  for (size_t f = 0; f < sp->n_f; f++) out[f] = sp->v[sp->ind[f]];
  return SDAE_OK;
}

/* ---- the state ---- */

static void lu_pivots(sdae_sparse_lu *lu, sdae_bytes *b) {
  sdae__bytes(b, lu->order, lu->m * sizeof *lu->order);
  sdae__bytes(b, lu->pivot, lu->m * sizeof *lu->pivot);
  sdae__bytes(b, lu->row_of, lu->n * sizeof *lu->row_of);
}

void sdae__mbs_sparse_state(sdae_mbs_sparse *sp, sdae_bytes *b) {
  size_t n_q = sp->n_q, n_c = sp->n_c;
  sdae__bytes_flag(b, &sp->have);
  sdae__bytes_flag(b, &sp->cur);
  sdae__bytes_doubles(b, &sp->measure, 1);
  sdae__bytes(b, sp->ind, sp->n_f * sizeof *sp->ind);
  lu_pivots(&sp->lu[0], b);
  lu_pivots(&sp->lu[1], b);
  sdae__bytes_flag(b, &sp->valid);
  sdae__bytes_doubles(b, &sp->key_t, 1);
  sdae__bytes_doubles(b, sp->key, 2 * n_q);
  sdae__bytes_doubles(b, sp->q, n_q);
  sdae__bytes_doubles(b, sp->v, n_q);
  sdae__bytes_doubles(b, sp->G, sp->Gp->nnz);
  sdae__bytes_doubles(b, sp->ct, n_c);
  sdae__bytes_doubles(b, sp->M, sp->Mp->nnz);
  sdae__bytes_doubles(b, sp->nu, n_c);
}

/* pivots that are a permutation's: pivot[k] a column whose row is k, every other column none;
 * the order a permutation of the rows */
static int lu_valid(sdae_sparse_lu *lu) {
  size_t rows = 0;
  memset(lu->done, 0, lu->m); /* the order's scratch: each row once */
  for (size_t k = 0; k < lu->m; k++) {
    if (lu->order[k] >= lu->m || lu->done[lu->order[k]]) return 0;
    lu->done[lu->order[k]] = 1;
  }
  for (size_t c = 0; c < lu->n; c++) {
    if (lu->row_of[c] == lu->m) continue;
    if (lu->row_of[c] > lu->m || lu->pivot[lu->row_of[c]] != c) return 0;
    rows++;
  }
  return rows == lu->m;
}

int sdae__mbs_sparse_valid(sdae_mbs_sparse *sp) {
  sdae_sparse_lu *lu = &sp->lu[sp->cur & 1];
  if (!sp->have) return 1;
  if (!lu_valid(lu)) return 0;
  for (size_t f = 0; f < sp->n_f; f++)
    if (sp->ind[f] >= sp->n_q || lu->row_of[sp->ind[f]] != sp->n_c) return 0;
  return 1;
}
