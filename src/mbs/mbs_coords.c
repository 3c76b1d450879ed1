/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a mechanism in a chart (docs/front-ends.md, the mechanical front-end):
 *
 *   xi = per constraint (c_j, G_j v + dc_j/dt),   mu = (q_I, W^T M v),
 *
 * L_g mu = 0 because G W = 0, and on the manifold (q_I, W^T M v) are canonical. Phi^-1 solves
 * c(t, q) = xi's c-part for q_D by a chord iteration from the last point's linearization, then
 * [G; W^T M] v = [xi's velocity part - dc/dt; W^T M v] by the reduced mass W^T M W. The
 * mu-dynamics are (q_I', d/dt(W^T M v)) = (v_I, W^T (F + (dM/dt) v) + (dW/dt)^T M v), lambda
 * dropping out as W^T G^T = 0, with dW/dt = P [-G_D^-1 (dG/dt) W; 0], so that
 * (dW/dt)^T M v = -(G_D^-1 (dG/dt) W)^T (M v)_D. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/callback.h"
#include "core/lu.h"
#include "mbs_coords.h"

/* Phi^-1's Newton (core/newton.h, keep: a chord with G_D's factors from the base) accepts a
 * step of Newton from factors at its own iterate below this times 1 + |q_D|: it leaves an
 * error of its square times the curvature, rounding (a chord's corrections must reach the
 * rounding of q_D: what they leave has one sign, and the scheme's xi_c sums it) */
#define NEWTON_SMALL 1e-10

void sdae__mbs_coords_init(sdae_mbs_coords *co, sdae_mbs_eval *eval, sdae_mbs_atlas *chart,
                           unsigned newton_max_iter) {
  co->eval = eval;
  co->chart = chart;
  co->n_q = chart->n_q;
  co->n_c = chart->n_c;
  co->n_f = chart->n_f;
  co->newton_max_iter = newton_max_iter;
}

void sdae__mbs_coords_carve(sdae_mbs_coords *co, sdae_arena *a) {
  size_t n_q = co->n_q, n_c = co->n_c, n_f = co->n_f;
  co->q = sdae__take(a, n_q, 1);
  co->v = sdae__take(a, n_q, 1);
  co->c = sdae__take(a, n_c, 1);
  co->ct = sdae__take(a, n_c, 1);
  co->G = sdae__take(a, n_c, n_q);
  co->M = sdae__take(a, n_q, n_q);
  co->Mr = sdae__take(a, n_f, n_f);
  co->key = sdae__take(a, 2 * n_q, 1);
  co->base_q = sdae__take(a, n_q, 1);
  co->base_c = sdae__take(a, n_c, 1);
  co->base_ct = sdae__take(a, n_c, 1);
  co->dq_I = sdae__take(a, n_f, 1);
  co->Mv = sdae__take(a, n_q, 1);
  co->res = sdae__take(a, n_c, 1);
  co->dq_D = sdae__take(a, n_c, 1);
  co->q_D = sdae__take(a, n_c, 1);
  co->Y = sdae__take(a, n_q, 1);
  co->rhs = sdae__take(a, n_c, 1);
  co->z_D = sdae__take(a, n_c, 1);
  co->Mz = sdae__take(a, n_q, 1);
  co->v_I = sdae__take(a, n_f, 1);
  co->F = sdae__take(a, n_q, 1);
  co->Gdot = sdae__take(a, n_c, n_q);
  co->Mdv = sdae__take(a, n_q, 1);
  co->GdW = sdae__take(a, n_c, 1);
  co->X = sdae__take(a, n_c, 1);
  co->dW = sdae__take(a, n_f, 1);
  sdae__newton_carve_hooks(&co->newton, n_c, NEWTON_SMALL, co->newton_max_iter, a);
  co->newton.keep = 1;
}

/* (t, q, v) is the point Phi^-1 left (the last step's end): t within rounding of its time
 * (t0 + (i + 1) T and t0 + i T + T differ by an ulp), q and v the same doubles */
static int at_point(const sdae_mbs_coords *co, double t, const double *q, const double *v) {
  double dt = fabs(t - co->key_t), size = fmax(fabs(t), fabs(co->key_t));
  return co->valid && (dt == 0.0 || dt <= 4.0 * DBL_EPSILON * size) &&
         memcmp(q, co->q, co->n_q * sizeof *q) == 0 && memcmp(v, co->v, co->n_q * sizeof *v) == 0;
}

int sdae__mbs_coords_xi(sdae_mbs_coords *co, double t, const double *q, const double *v,
                        double *xi) {
  int rc;
  co->at_start = at_point(co, t, q, v);
  co->valid = 0; /* the point becomes the step's start */
  co->phi_inv_iters = 0;
  if (!co->at_start) return sdae__mbs_xi_of(co->eval, t, q, v, co->c, co->G, co->ct, xi);
  /* docs/front-ends.md, the cost of a step: the last step's end, G, dc/dt and M there kept; c is
   * evaluated where Phi^-1 converged (its iteration evaluated it one correction before) */
  if ((rc = sdae__mbs_constraint(co->eval, t, q, co->c)) != SDAE_OK) return rc;
  sdae__mbs_xi_compose(co->eval, v, co->c, co->G, co->ct, xi);
  return SDAE_OK;
}

/* xi_i at rounding: at most XI_ROUNDING times the size of its terms, the rounding that
 * Phi^-1 and the evaluation of c and G v + dc/dt leave in it at every step. Two ulps: under
 * the floor the gain is -epsilon, and xi_i walks up to the floor before the paper's gain takes
 * it back, so the floor is where xi stays on the manifold; at 4 and 8 ulps the double
 * pendulum's max |c| over 5e4 steps grew from 3.0e-15 to 4.6e-15 and 8.3e-15, and a particle on
 * a sphere with a heavy direction of M left G v above 4 n eps |v| */
#define XI_ROUNDING (2.0 * DBL_EPSILON)

static double max_abs_of(const double *x, size_t n) {
  double m = 0.0;
  for (size_t i = 0; i < n; i++) m = fabs(x[i]) > m ? fabs(x[i]) : m;
  return m;
}

/* the size of c_j's terms ~ |G_j|_1 |q|_inf (c of degree one or more in q), of G_j v +
 * dc_j/dt's |G_j|_1 |v|_inf + |dc_j/dt| */
void sdae__mbs_coords_floors(const sdae_mbs_coords *co, const double *q, const double *v,
                             double *floor) {
  size_t n_q = co->n_q;
  double nq = max_abs_of(q, n_q), nv = max_abs_of(v, n_q);
  for (size_t j = 0; j < co->n_c; j++) {
    double g = 0.0;
    for (size_t i = 0; i < n_q; i++) g += fabs(co->G[j * n_q + i]);
    floor[2 * j] = XI_ROUNDING * g * nq;
    floor[2 * j + 1] = XI_ROUNDING * (g * nv + fabs(co->ct[j]));
  }
}

static void mat_vec(const double *M, size_t n, const double *x, double *y) {
  for (size_t i = 0; i < n; i++) {
    double acc = 0.0;
    for (size_t j = 0; j < n; j++) acc += M[i * n + j] * x[j];
    y[i] = acc;
  }
}

int sdae__mbs_coords_begin(sdae_mbs_coords *co, double t, const double *q, const double *v,
                           double *mu) {
  const sdae_mbs_atlas *ch = co->chart;
  int rc;
  co->valid = 0; /* the point's M is about to be the start's */
  /* at the last step's end, M was checked there */
  if (!co->at_start && (rc = sdae__mbs_mass_symmetric(co->eval, t, q, co->M)) != SDAE_OK) return rc;
  mat_vec(co->M, co->n_q, v, co->Mv);
  for (size_t k = 0; k < co->n_f; k++) mu[k] = q[ch->ind[k]];
  sdae__mbs_Wt(ch, co->Mv, mu + co->n_f);
  /* the step's start is the first solve's base, the chart factored there */
  memcpy(co->base_q, q, co->n_q * sizeof *q);
  memcpy(co->base_c, co->c, co->n_c * sizeof *co->c);
  memcpy(co->base_ct, co->ct, co->n_c * sizeof *co->ct);
  co->base_t = t;
  co->base_here = 0;
  return SDAE_OK;
}

/* The linearization of the chart at the base (docs/front-ends.md, the cost of a step): q_I from mu,
 * and G_D dq_D = dxi_c - G_I dq_I - dc/dt dt, i.e. q = q_b + W_b dq_I + P_D G_D^-1 (dxi_c -
 * ct_b dt) with the factors of the base (or kept since). */
static void predict(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_c = co->n_c, n_f = co->n_f;
  memcpy(co->q, co->base_q, co->n_q * sizeof *co->q);
  for (size_t j = 0; j < n_c; j++)
    co->res[j] = (xi[2 * j] - co->base_c[j]) - co->base_ct[j] * (t - co->base_t);
  sdae__mbs_gd_solve(ch, co->res, co->dq_D);
  for (size_t k = 0; k < n_f; k++) co->dq_I[k] = mu[k] - co->base_q[ch->ind[k]];
  for (size_t j = 0; j < n_c; j++) {
    double acc = co->dq_D[j];
    for (size_t k = 0; k < n_f; k++) acc -= ch->A[j * n_f + k] * co->dq_I[k];
    co->q[ch->dep[j]] += acc;
  }
  for (size_t k = 0; k < n_f; k++) co->q[ch->ind[k]] = mu[k];
}

/* ---- q_D from c(t, q) = xi's c-part, an adapter of Newton (core/newton.h) ---- */

typedef struct q_eq {
  sdae_mbs_coords *co;
  double t;
  const double *xi;
} q_eq;

static void set_q_D(sdae_mbs_coords *co, const double *q_D) {
  double *q = co->q; /* in locals: a write through q could alias co */
  const size_t *dep = co->chart->dep;
  for (size_t j = 0, n = co->n_c; j < n; j++) q[dep[j]] = q_D[j];
}

/* residual: c(t, q) - xi's c-part at q with q_D = y */
static int q_residual(void *ctx, const double *y, double *R) {
  const q_eq *e = ctx;
  sdae_mbs_coords *co = e->co;
  int rc;
  set_q_D(co, y);
  if ((rc = sdae__mbs_constraint(co->eval, e->t, co->q, co->c)) != SDAE_OK) return rc;
  const double *c = co->c, *xi = e->xi;
  for (size_t j = 0, n = co->n_c; j < n; j++) R[j] = c[j] - xi[2 * j];
  return SDAE_OK;
}

/* linear setup: G_D's factors at q with q_D = y (the chart's, refactored) */
static int q_setup(void *ctx, const double *y) {
  const q_eq *e = ctx;
  sdae_mbs_coords *co = e->co;
  int rc;
  set_q_D(co, y);
  if ((rc = sdae__mbs_jacobian(co->eval, e->t, co->q, co->G)) != SDAE_OK) return rc;
  return sdae__mbs_gd_factor(co->chart, co->G) == SDAE_OK ? SDAE_OK : SDAE_ERR_PHI_INV;
}

/* linear solve with G_D's factors */
static void q_solve(void *ctx, const double *R, double *dy) {
  const q_eq *e = ctx;
  sdae__mbs_gd_solve(e->co->chart, R, dy);
}

/* q_D from c(t, q) = xi's c-part (docs/front-ends.md, the cost of a step): predicted by the
 * chart's linearization at the base, then Newton's chord with G_D's factors kept from there
 * (adopted: the chart factored them at the base), refreshed at the iterate when slow and, when
 * the chord fails, at the prediction, the solve retried from there (core/newton.h). */
static int solve_q(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  q_eq e = {co, t, xi};
  const sdae_newton_system sys = {
      .residual = q_residual, .setup = q_setup, .solve = q_solve, .ctx = &e};
  int rc;
  predict(co, t, xi, mu);
  for (size_t j = 0; j < co->n_c; j++) co->q_D[j] = co->q[co->chart->dep[j]];
  sdae__newton_adopt(&co->newton, 1.0);
  rc = sdae__newton_solve(&co->newton, &sys, 1.0, co->q_D);
  co->phi_inv_iters += co->newton.iters;
  co->newton.iters = 0;
  set_q_D(co, co->q_D);
  if (rc == SDAE_ERR_NEWTON || rc == SDAE_ERR_SINGULAR) return SDAE_ERR_PHI_INV;
  return rc;
}

/* the reduced mass W^T M W (n_f x n_f) into co->Mr, factored: symmetric by construction
 * (docs/front-ends.md, the price of zero drift), Y = M W column by column, then the upper triangle
 * of W^T Y, mirrored. Formed entry by entry, its two triangles would round differently by up to eps
 * times M's largest entries, which W^T M W need not have (a heavy direction across the
 * constraints): Cholesky would then see a non-symmetric matrix. */
static int reduced_mass(sdae_mbs_coords *co) {
  size_t n_q = co->n_q, n_f = co->n_f;
  const double *W = co->chart->W;
  for (size_t b = 0; b < n_f; b++) {
    for (size_t i = 0; i < n_q; i++) {
      double acc = 0.0;
      for (size_t j = 0; j < n_q; j++) acc += co->M[i * n_q + j] * W[j * n_f + b];
      co->Y[i] = acc;
    }
    for (size_t a = 0; a <= b; a++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += W[i * n_f + a] * co->Y[i];
      co->Mr[a * n_f + b] = co->Mr[b * n_f + a] = acc;
    }
  }
  return sdae__cholesky_factor(co->Mr, n_f);
}

/* v = z + W v_I with G z = xi's velocity part - dc/dt (z_I = 0) and W^T M v = mu's p-part */
static int solve_v(sdae_mbs_coords *co, const double *xi, const double *mu) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_q = co->n_q, n_c = co->n_c, n_f = co->n_f;
  for (size_t j = 0; j < n_c; j++) co->rhs[j] = xi[2 * j + 1] - co->ct[j];
  sdae__mbs_gd_solve(ch, co->rhs, co->z_D);
  memset(co->v, 0, n_q * sizeof *co->v);
  for (size_t j = 0; j < n_c; j++) co->v[ch->dep[j]] = co->z_D[j];
  mat_vec(co->M, n_q, co->v, co->Mz);
  sdae__mbs_Wt(ch, co->Mz, co->v_I);
  for (size_t k = 0; k < n_f; k++) co->v_I[k] = mu[n_f + k] - co->v_I[k];
  sdae__cholesky_solve(co->Mr, n_f, co->v_I);
  for (size_t i = 0; i < n_q; i++)
    for (size_t k = 0; k < n_f; k++) co->v[i] += ch->W[i * n_f + k] * co->v_I[k];
  return sdae__all_finite(co->v, n_q) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int same_point(const sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  return co->valid && co->key_t == t && memcmp(co->key, xi, 2 * co->n_c * sizeof *xi) == 0 &&
         memcmp(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu) == 0;
}

/* the base's configuration again (t, xi's c-part and q_I the same): its q, G, dc/dt, M, W and
 * reduced mass hold, v alone changes (the velocity columns of Q, a Newton matrix's momentum
 * columns) */
static int same_configuration(const sdae_mbs_coords *co, double t, const double *xi,
                              const double *mu) {
  if (!co->base_here || co->base_t != t) return 0;
  for (size_t j = 0; j < co->n_c; j++)
    if (xi[2 * j] != co->base_c[j]) return 0;
  for (size_t k = 0; k < co->n_f; k++)
    if (mu[k] != co->base_q[co->chart->ind[k]]) return 0;
  return 1;
}

/* q where the chord iteration converged, and there G (once), the chart's factors and W, dc/dt,
 * M and the reduced mass; the point becomes the next solve's base */
/* The state's configuration (the step's end, whose c the next step measures as xi_c) is
 * finished by one step of Newton from q_D moved by DITHER of 1 + |q_D|, with G_D's factors at
 * the converged q. The chord's last corrections are computed within an ulp or two of the root,
 * where the rounding of c is set by the root's place among the doubles: of one sign step after
 * step as xi_c moves slowly, and xi_c sums it (the double pendulum's max |c| reached 1.4e-13 at
 * T = 1e-5, against 1.1e-14 with Newton from the step's start). From 1e-12 away the rounding
 * of c is unrelated to the root's, and the step of Newton leaves (K/2) 1e-24; it lands within
 * an ulp of the converged q, so G, W and the factors there serve to rounding. One call of c. */
#define DITHER 0x1p-40
static int finish(sdae_mbs_coords *co, double t, const double *xi) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_c = co->n_c;
  int rc;
  for (size_t j = 0; j < n_c; j++) {
    double *qd = &co->q[ch->dep[j]];
    *qd += DITHER * (1.0 + fabs(*qd));
  }
  if ((rc = sdae__mbs_constraint(co->eval, t, co->q, co->c)) != SDAE_OK) return rc;
  for (size_t j = 0; j < n_c; j++) co->res[j] = co->c[j] - xi[2 * j];
  sdae__mbs_gd_solve(ch, co->res, co->dq_D);
  co->phi_inv_iters++;
  for (size_t j = 0; j < n_c; j++) co->q[ch->dep[j]] -= co->dq_D[j];
  return sdae__all_finite(co->q, co->n_q) ? SDAE_OK : SDAE_ERR_PHI_INV;
}

static int configuration(sdae_mbs_coords *co, double t, const double *xi, const double *mu,
                         int state) {
  int rc;
  co->base_here = 0;
  if ((rc = solve_q(co, t, xi, mu)) != SDAE_OK) return rc;
  if ((rc = sdae__mbs_jacobian(co->eval, t, co->q, co->G)) != SDAE_OK) return rc;
  if (sdae__mbs_chart_factor(co->chart, co->G, NULL) != SDAE_OK) return SDAE_ERR_PHI_INV;
  if (state && (rc = finish(co, t, xi)) != SDAE_OK) return rc;
  if ((rc = sdae__mbs_constraint_t(co->eval, t, co->q, co->ct)) != SDAE_OK ||
      (rc = sdae__mbs_mass(co->eval, t, co->q, co->M)) != SDAE_OK ||
      (rc = reduced_mass(co)) != SDAE_OK)
    return rc;
  memcpy(co->base_q, co->q, co->n_q * sizeof *co->q);
  for (size_t j = 0; j < co->n_c; j++) co->base_c[j] = xi[2 * j];
  memcpy(co->base_ct, co->ct, co->n_c * sizeof *co->ct);
  co->base_t = t;
  co->base_here = 1;
  return SDAE_OK;
}

int sdae__mbs_coords_seed(sdae_mbs_coords *co, double t, const double *q, const double *v,
                          const double *mu) {
  int rc;
  memcpy(co->q, q, co->n_q * sizeof *q);
  memcpy(co->v, v, co->n_q * sizeof *v);
  if ((rc = reduced_mass(co)) != SDAE_OK) return rc; /* in the chart just chosen */
  memset(co->key, 0, 2 * co->n_c * sizeof *co->key);
  memcpy(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu);
  co->key_t = t;
  co->valid = 1;
  memset(co->base_c, 0, co->n_c * sizeof *co->base_c); /* the configuration of xi's c-part 0 */
  co->base_here = 1;
  return SDAE_OK;
}

static int phi_inv(sdae_mbs_coords *co, double t, const double *xi, const double *mu, int state) {
  int rc;
  if (same_point(co, t, xi, mu)) return SDAE_OK;
  co->valid = 0;
  if (!same_configuration(co, t, xi, mu) && (rc = configuration(co, t, xi, mu, state)) != SDAE_OK)
    return rc;
  if ((rc = solve_v(co, xi, mu)) != SDAE_OK) return rc;
  memcpy(co->key, xi, 2 * co->n_c * sizeof *xi);
  memcpy(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu);
  co->key_t = t;
  co->valid = 1;
  return SDAE_OK;
}

int sdae__mbs_phi_inv(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  return phi_inv(co, t, xi, mu, 0);
}

/* M symmetric at the state handed out, as at every start (sdae__mbs_mass_symmetric) */
int sdae__mbs_phi_inv_state(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  int rc = phi_inv(co, t, xi, mu, 1);
  if (rc == SDAE_OK && !sdae__symmetric(co->M, co->n_q)) return SDAE_ERR_MASS;
  return rc;
}

/* co->dW = X^T (M v)_D with X = G_D^-1 (dG/dt) W: minus the term (dW/dt)^T M v */
static void dW_term(sdae_mbs_coords *co) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_q = co->n_q, n_c = co->n_c, n_f = co->n_f;
  for (size_t k = 0; k < n_f; k++) {
    for (size_t j = 0; j < n_c; j++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += co->Gdot[j * n_q + i] * ch->W[i * n_f + k];
      co->GdW[j] = acc;
    }
    sdae__mbs_gd_solve(ch, co->GdW, co->X);
    co->dW[k] = 0.0;
    for (size_t j = 0; j < n_c; j++) co->dW[k] += co->X[j] * co->Mv[ch->dep[j]];
  }
}

int sdae__mbs_mu_dot(sdae_mbs_coords *co, double t, double *out) {
  const sdae_mbs_atlas *ch = co->chart;
  size_t n_q = co->n_q, n_f = co->n_f;
  int rc;
  if ((rc = sdae__mbs_force(co->eval, t, co->q, co->v, co->F)) != SDAE_OK ||
      (rc = sdae__mbs_along(co->eval, t, co->q, co->v, co->Gdot, co->Mdv, NULL)) != SDAE_OK)
    return rc;
  for (size_t i = 0; i < n_q; i++) co->F[i] += co->Mdv[i];
  sdae__mbs_Wt(ch, co->F, out + n_f);
  mat_vec(co->M, n_q, co->v, co->Mv);
  dW_term(co);
  for (size_t k = 0; k < n_f; k++) {
    out[k] = co->v[ch->ind[k]];
    out[n_f + k] -= co->dW[k];
  }
  return SDAE_OK;
}

void sdae__mbs_coords_state(sdae_mbs_coords *co, sdae_bytes *b) {
  size_t n_q = co->n_q, n_c = co->n_c;
  sdae__bytes_flag(b, &co->valid);
  sdae__bytes_doubles(b, &co->key_t, 1);
  sdae__bytes_doubles(b, co->key, 2 * n_q);
  sdae__bytes_doubles(b, co->q, n_q);
  sdae__bytes_doubles(b, co->v, n_q);
  sdae__bytes_doubles(b, co->G, n_c * n_q);
  sdae__bytes_doubles(b, co->ct, n_c);
  sdae__bytes_doubles(b, co->M, n_q * n_q);
}
