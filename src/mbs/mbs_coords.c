/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a mechanism in a chart (docs/front-ends.md, the mechanical front-end),
 * once for both linear-algebra back-ends (mbs_linalg.h):
 *
 *   xi = per constraint (c_j, G_j v + dc_j/dt),   mu = (q_I, W^T M v),
 *
 * L_g mu = 0 because G W = 0, and on the manifold (q_I, W^T M v) are canonical. Phi^-1 solves
 * c(t, q) = xi's c-part for q_D by a chord iteration from the last point's linearization, then
 * G v = xi's velocity part - dc/dt, W^T M v = mu's p-part by the back-end's velocity system.
 * The mu-dynamics are (q_I', d/dt(W^T M v)) = (v_I, W^T (F + (dM/dt) v) + (dW/dt)^T M v),
 * lambda dropping out as W^T G^T = 0. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/callback.h"
#include "maps/map.h"
#include "mbs_coords.h"

/* Phi^-1's Newton (core/newton.h, keep: a chord with G_D's factors from the base) accepts a
 * step of Newton from factors at its own iterate below this times 1 + |q_D|: it leaves an
 * error of its square times the curvature, rounding (a chord's corrections must reach the
 * rounding of q_D: what they leave has one sign, and the scheme's xi_c sums it) */
#define NEWTON_SMALL 1e-10

/* xi_i at rounding: at most XI_ROUNDING times the size of its terms, the rounding that
 * Phi^-1 and the evaluation of c and G v + dc/dt leave in it at every step. Two ulps: under
 * the floor the gain is -epsilon, and xi_i walks up to the floor before the paper's gain takes
 * it back, so the floor is where xi stays on the manifold; at 4 and 8 ulps the double
 * pendulum's max |c| over 5e4 steps grew from 3.0e-15 to 4.6e-15 and 8.3e-15, and a particle on
 * a sphere with a heavy direction of M left G v above 4 n eps |v| */
#define XI_ROUNDING (2.0 * DBL_EPSILON)

/* The state's configuration (the step's end, whose c the next step measures as xi_c) is
 * finished by one step of Newton from q_D moved by DITHER of 1 + |q_D|, with G_D's factors at
 * the converged q. The chord's last corrections are computed within an ulp or two of the root,
 * where the rounding of c is set by the root's place among the doubles: of one sign step after
 * step as xi_c moves slowly, and xi_c sums it (the double pendulum's max |c| reached 1.4e-13 at
 * T = 1e-5, against 1.1e-14 with Newton from the step's start). From 1e-12 away the rounding
 * of c is unrelated to the root's, and the step of Newton leaves (K/2) 1e-24; it lands within
 * an ulp of the converged q, so G, W and the factors there serve to rounding. One call of c. */
#define DITHER 0x1p-40

int sdae__mbs_coords_init(sdae_mbs_coords *co, sdae_mbs_eval *eval, const sdae_mbs_linalg *linalg,
                          void *la, const sdae_options *o) {
  co->eval = eval;
  co->linalg = linalg;
  co->la = la;
  co->n_q = eval->n_q;
  co->n_c = eval->n_c;
  co->n_f = eval->n_q - eval->n_c;
  co->newton_max_iter = o->newton_max_iter;
  co->energy_map = o->map && sdae__map_uses_H(o->map); /* no map: refused by the validation */
  return linalg->init(la, eval, o);
}

/* the chart's split as the back-end holds it, asked again wherever the chart may have changed:
 * a choice at the step's start and a state read (a set state, a roll-back) */
static void split(sdae_mbs_coords *co) { co->linalg->split(co->la, &co->dep, &co->ind); }

int sdae__mbs_coords_analyse(sdae_mbs_coords *co, const sdae_scratch *scratch) {
  return co->linalg->analyse ? co->linalg->analyse(co->la, scratch) : SDAE_OK;
}

int sdae__mbs_coords_carve(sdae_mbs_coords *co, sdae_arena *a) {
  size_t n_q = co->n_q, n_c = co->n_c;
  int rc = co->linalg->carve(co->la, a);
  co->q = sdae__take(a, n_q, 1);
  co->v = sdae__take(a, n_q, 1);
  co->c = sdae__take(a, n_c, 1);
  co->ct = sdae__take(a, n_c, 1);
  co->key = sdae__take(a, 2 * n_q, 1);
  co->base_q = sdae__take(a, n_q, 1);
  co->base_c = sdae__take(a, n_c, 1);
  co->base_ct = sdae__take(a, n_c, 1);
  co->Mv = sdae__take(a, n_q, 1);
  co->res = sdae__take(a, n_c, 1);
  co->dq_D = sdae__take(a, n_c, 1);
  co->q_D = sdae__take(a, n_c, 1);
  co->dq = sdae__take(a, n_q, 1);
  co->g = sdae__take(a, n_c, 1);
  co->F = sdae__take(a, n_q, 1);
  co->F_in = sdae__take(a, n_q, 1);
  co->w = sdae__take(a, n_q, 1);
  co->Dw = sdae__take(a, n_q, 1);
  co->zero = sdae__take(a, 2 * n_c, 1);
  if (co->zero) { /* NULL while the block is only counted */
    memset(co->zero, 0, 2 * n_c * sizeof *co->zero);
    split(co);
  }
  sdae__newton_carve_hooks(&co->newton, n_c, NEWTON_SMALL, co->newton_max_iter, a);
  co->newton.keep = 1;
  return rc;
}

/* ---- xi at a state, the step's start ---- */

/* (t, q, v) is the point Phi^-1 left (the last step's end): t within rounding of its time
 * (t0 + (i + 1) T and t0 + i T + T differ by an ulp), q and v the same doubles */
static int at_point(const sdae_mbs_coords *co, double t, const double *q, const double *v) {
  double dt = fabs(t - co->key_t), size = fmax(fabs(t), fabs(co->key_t));
  return co->valid && (dt == 0.0 || dt <= 4.0 * DBL_EPSILON * size) &&
         memcmp(q, co->q, co->n_q * sizeof *q) == 0 && memcmp(v, co->v, co->n_q * sizeof *v) == 0;
}

int sdae__mbs_coords_xi(sdae_mbs_coords *co, double t, const double *q, const double *v,
                        double *xi) {
  const sdae_mbs_linalg *la = co->linalg;
  int rc;
  co->at_start = at_point(co, t, q, v);
  co->reuse = co->at_start && co->fresh;
  co->valid = co->fresh = 0; /* the point becomes the step's start */
  co->phi_inv_iters = 0;
  /* docs/front-ends.md, the cost of a step: at the last step's end, G, dc/dt and M there kept;
   * c is evaluated where Phi^-1 converged (its iteration evaluated it one correction before) */
  if ((rc = sdae__mbs_constraint(co->eval, t, q, co->c)) != SDAE_OK) return rc;
  if (!co->at_start && ((rc = la->jacobian(co->la, t, q)) != SDAE_OK ||
                        (rc = sdae__mbs_constraint_t(co->eval, t, q, co->ct)) != SDAE_OK))
    return rc;
  la->g_times(co->la, v, co->ct, co->g);
  for (size_t j = 0; j < co->n_c; j++) xi[2 * j] = co->c[j], xi[2 * j + 1] = co->g[j];
  return SDAE_OK;
}

/* the size of c_j's terms ~ |G_j|_1 |q|_inf (c of degree one or more in q), of G_j v +
 * dc_j/dt's |G_j|_1 |v|_inf + |dc_j/dt| */
void sdae__mbs_coords_floors(const sdae_mbs_coords *co, const double *q, const double *v,
                             double *floor) {
  double nq = 0.0, nv = 0.0;
  for (size_t i = 0; i < co->n_q; i++) nq = fmax(nq, fabs(q[i])), nv = fmax(nv, fabs(v[i]));
  for (size_t j = 0; j < co->n_c; j++) {
    double g = co->linalg->row_size(co->la, j);
    floor[2 * j] = XI_ROUNDING * g * nq;
    floor[2 * j + 1] = XI_ROUNDING * (g * nv + fabs(co->ct[j]));
  }
}

/* every xi_i at its floor: on the manifold to rounding */
static int at_floors(const double *xi, const double *floor, size_t n_xi) {
  for (size_t i = 0; i < n_xi; i++)
    if (!(xi[i] >= -floor[i] && xi[i] <= floor[i])) return 0;
  return 1;
}

/* the energy-conserving maps need time-independent constraints */
static int energy_map_ok(const sdae_mbs_coords *co) {
  if (!co->energy_map) return SDAE_OK;
  for (size_t j = 0; j < co->n_c; j++)
    if (co->ct[j] != 0.0) return SDAE_ERR_MAP;
  return SDAE_OK;
}

/* M at q, before the chart is chosen (the sparse back-end measures the constraints'
 * independence on the velocity's system): SDAE_ERR_MASS unless symmetric; at the last step's
 * end it was checked there */
static int start_mass(sdae_mbs_coords *co, double t, const double *q) {
  const sdae_mbs_linalg *la = co->linalg;
  int rc;
  if (co->at_start) return SDAE_OK;
  if ((rc = la->mass(co->la, t, q)) != SDAE_OK) return rc;
  return la->mass_symmetric(co->la);
}

/* mu in the chart factored at q, and q as Phi^-1's first base */
static void begin(sdae_mbs_coords *co, double t, const double *q, const double *v, double *mu) {
  const sdae_mbs_linalg *la = co->linalg;
  const size_t *ind = co->ind;
  la->m_times(co->la, v, co->Mv);
  for (size_t k = 0; k < co->n_f; k++) mu[k] = q[ind[k]];
  la->wt(co->la, co->Mv, mu + co->n_f);
  memcpy(co->base_q, q, co->n_q * sizeof *q);
  memcpy(co->base_c, co->c, co->n_c * sizeof *co->c);
  memcpy(co->base_ct, co->ct, co->n_c * sizeof *co->ct);
  co->base_t = t;
  co->base_here = 0;
}

/* the step's start (t, q, v) taken as Phi^-1(t, 0, mu) (mu its coordinates), once every xi_i
 * is at its floor: the two differ by rounding (docs/front-ends.md, the cost of a step); the
 * velocity's system factored at q in the current chart */
static int seed(sdae_mbs_coords *co, double t, const double *q, const double *v, const double *mu) {
  int rc;
  memcpy(co->q, q, co->n_q * sizeof *q);
  for (size_t j = 0; j < co->n_c; j++) co->g[j] = 0.0 - co->ct[j];
  if ((rc = co->linalg->seed(co->la, co->reuse, co->g, mu + co->n_f, co->v)) != SDAE_OK) return rc;
  memcpy(co->v, v, co->n_q * sizeof *v); /* the start's v, to rounding the one solved for */
  memset(co->key, 0, 2 * co->n_c * sizeof *co->key);
  memcpy(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu);
  co->key_t = t;
  co->valid = 1;
  memset(co->base_c, 0, co->n_c * sizeof *co->base_c); /* the configuration of xi's c-part 0 */
  co->base_here = 1;
  return SDAE_OK;
}

int sdae__mbs_coords_start(sdae_mbs_coords *co, double t, const double *q, const double *v,
                           int force_best, sdae_mbs_start *st) {
  int rc, rows_changed, rows_kept, had = co->eval->have;
  /* redundant constraints: the rows first, and the point's G not theirs where they changed */
  if ((rc = sdae__mbs_select(co->eval, t, q, force_best, &rows_changed, &rows_kept)) != SDAE_OK)
    return rc;
  if (rows_changed) co->valid = 0;
  st->rows_switched = rows_changed && had;
  if ((rc = sdae__mbs_coords_xi(co, t, q, v, st->xi)) != SDAE_OK ||
      (rc = energy_map_ok(co)) != SDAE_OK || (rc = start_mass(co, t, q)) != SDAE_OK ||
      (rc = co->linalg->choose(co->la, force_best, co->reuse, &st->choice)) != SDAE_OK)
    return rc;
  st->choice.kept |= rows_kept; /* a step that folds is retried in the best rows and chart */
  split(co);
  begin(co, t, q, v, st->mu);
  sdae__mbs_coords_floors(co, q, v, st->floor);
  if (!at_floors(st->xi, st->floor, 2 * co->n_c)) return SDAE_OK;
  return seed(co, t, q, v, st->mu);
}

/* ---- q_D from c(t, q) = xi's c-part, an adapter of Newton (core/newton.h) ---- */

typedef struct q_eq {
  sdae_mbs_coords *co;
  double t;
  const double *xi;
} q_eq;

static void set_q_D(sdae_mbs_coords *co, const double *q_D) {
  double *q = co->q; /* in locals: a write through q could alias co */
  const size_t *dep = co->dep;
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
  if ((rc = co->linalg->jacobian(co->la, e->t, co->q)) != SDAE_OK) return rc;
  return co->linalg->gd_factor(co->la) == SDAE_OK ? SDAE_OK : SDAE_ERR_PHI_INV;
}

/* linear solve with G_D's factors */
static int q_solve(void *ctx, const double *R, double *dy) {
  const q_eq *e = ctx;
  e->co->linalg->gd_solve(e->co->la, R, dy);
  return SDAE_OK;
}

/* The linearization of the chart at the base (docs/front-ends.md, the cost of a step): q_I from
 * mu, and G_D dq_D = dxi_c - G_I dq_I - dc/dt dt, i.e. q = q_b + W_b dq_I + P_D G_D^-1 (dxi_c -
 * ct_b dt) with the factors of the base (or kept since). */
static void predict(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  const size_t *dep = co->dep, *ind = co->ind;
  for (size_t j = 0; j < co->n_c; j++)
    co->res[j] = (xi[2 * j] - co->base_c[j]) - co->base_ct[j] * (t - co->base_t);
  memset(co->dq, 0, co->n_q * sizeof *co->dq);
  for (size_t k = 0; k < co->n_f; k++) co->dq[ind[k]] = mu[k] - co->base_q[ind[k]];
  co->linalg->move(co->la, co->res, co->dq, co->dq_D);
  memcpy(co->q, co->base_q, co->n_q * sizeof *co->q);
  for (size_t j = 0; j < co->n_c; j++) co->q[dep[j]] += co->dq_D[j];
  for (size_t k = 0; k < co->n_f; k++) co->q[ind[k]] = mu[k];
}

/* q_D from c(t, q) = xi's c-part (docs/front-ends.md, the cost of a step): predicted by the
 * chart's linearization at the base, then Newton's chord with G_D's factors kept from there
 * (adopted: the chart factored them at the base), refreshed at the iterate when slow and, when
 * the chord fails, at the prediction, the solve retried from there (core/newton.h). */
static int solve_q(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  q_eq e = {co, t, xi};
  const sdae_newton_system sys = {
      .residual = q_residual, .setup = q_setup, .solve = q_solve, .ctx = &e};
  const size_t *dep = co->dep;
  int rc;
  predict(co, t, xi, mu);
  for (size_t j = 0; j < co->n_c; j++) co->q_D[j] = co->q[dep[j]];
  sdae__newton_adopt(&co->newton, 1.0);
  rc = sdae__newton_solve(&co->newton, &sys, 1.0, co->q_D);
  co->phi_inv_iters += co->newton.iters;
  co->newton.iters = 0;
  set_q_D(co, co->q_D);
  if (rc == SDAE_ERR_NEWTON || rc == SDAE_ERR_SINGULAR) return SDAE_ERR_PHI_INV;
  return rc;
}

/* the state's q_D finished by a step of Newton from DITHER away (above) */
static int finish(sdae_mbs_coords *co, double t, const double *xi) {
  const size_t *dep = co->dep;
  size_t n_c = co->n_c;
  int rc;
  for (size_t j = 0; j < n_c; j++) {
    double *qd = &co->q[dep[j]];
    *qd += DITHER * (1.0 + fabs(*qd));
  }
  if ((rc = sdae__mbs_constraint(co->eval, t, co->q, co->c)) != SDAE_OK) return rc;
  for (size_t j = 0; j < n_c; j++) co->res[j] = co->c[j] - xi[2 * j];
  co->linalg->gd_solve(co->la, co->res, co->dq_D);
  co->phi_inv_iters++;
  for (size_t j = 0; j < n_c; j++) co->q[dep[j]] -= co->dq_D[j];
  return sdae__all_finite(co->q, co->n_q) ? SDAE_OK : SDAE_ERR_PHI_INV;
}

/* q where the chord iteration converged, and there G (once), the chart's factors, dc/dt, M and
 * the velocity's system; the point becomes the next solve's base */
static int configuration(sdae_mbs_coords *co, double t, const double *xi, const double *mu,
                         int state) {
  const sdae_mbs_linalg *la = co->linalg;
  int rc;
  co->base_here = 0;
  if ((rc = solve_q(co, t, xi, mu)) != SDAE_OK) return rc;
  if ((rc = la->jacobian(co->la, t, co->q)) != SDAE_OK) return rc;
  if (la->factor(co->la) != SDAE_OK) return SDAE_ERR_PHI_INV;
  if (state && (rc = finish(co, t, xi)) != SDAE_OK) return rc;
  if ((rc = sdae__mbs_constraint_t(co->eval, t, co->q, co->ct)) != SDAE_OK ||
      (rc = la->mass(co->la, t, co->q)) != SDAE_OK ||
      (rc = la->velocity_factor(co->la, 0)) != SDAE_OK)
    return rc;
  memcpy(co->base_q, co->q, co->n_q * sizeof *co->q);
  for (size_t j = 0; j < co->n_c; j++) co->base_c[j] = xi[2 * j];
  memcpy(co->base_ct, co->ct, co->n_c * sizeof *co->ct);
  co->base_t = t;
  co->base_here = 1;
  return SDAE_OK;
}

static int same_point(const sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  return co->valid && co->key_t == t && memcmp(co->key, xi, 2 * co->n_c * sizeof *xi) == 0 &&
         memcmp(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu) == 0;
}

/* the base's configuration again (t, xi's c-part and q_I the same): its q, G, dc/dt, M and
 * factors hold, v alone changes (the velocity columns of Q, a Newton matrix's momentum
 * columns) */
static int same_configuration(const sdae_mbs_coords *co, double t, const double *xi,
                              const double *mu) {
  const size_t *ind = co->ind;
  if (!co->base_here || co->base_t != t) return 0;
  for (size_t j = 0; j < co->n_c; j++)
    if (xi[2 * j] != co->base_c[j]) return 0;
  for (size_t k = 0; k < co->n_f; k++)
    if (mu[k] != co->base_q[ind[k]]) return 0;
  return 1;
}

static int phi_inv(sdae_mbs_coords *co, double t, const double *xi, const double *mu, int state) {
  int rc;
  if (same_point(co, t, xi, mu)) return SDAE_OK;
  co->valid = 0;
  if (!same_configuration(co, t, xi, mu) && (rc = configuration(co, t, xi, mu, state)) != SDAE_OK)
    return rc;
  for (size_t j = 0; j < co->n_c; j++) co->g[j] = xi[2 * j + 1] - co->ct[j];
  if ((rc = co->linalg->velocity(co->la, co->g, mu + co->n_f, co->v)) != SDAE_OK) return rc;
  memcpy(co->key, xi, 2 * co->n_c * sizeof *xi);
  memcpy(co->key + 2 * co->n_c, mu, 2 * co->n_f * sizeof *mu);
  co->key_t = t;
  co->valid = 1;
  return SDAE_OK;
}

int sdae__mbs_phi_inv(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  return phi_inv(co, t, xi, mu, 0);
}

/* M symmetric at the state handed out, as at every start */
int sdae__mbs_phi_inv_state(sdae_mbs_coords *co, double t, const double *xi, const double *mu) {
  int rc = phi_inv(co, t, xi, mu, 1);
  if (rc == SDAE_OK) rc = co->linalg->mass_symmetric(co->la);
  co->fresh = rc == SDAE_OK; /* the next step's start, unless q or v are changed */
  return rc;
}

int sdae__mbs_mu_dot(sdae_mbs_coords *co, double t, double *out) {
  const size_t *ind = co->ind;
  int rc;
  if ((rc = sdae__mbs_force(co->eval, t, co->q, co->v, co->F)) != SDAE_OK ||
      (rc = co->linalg->momentum_rate(co->la, t, co->q, co->v, co->F, out + co->n_f)) != SDAE_OK)
    return rc;
  for (size_t k = 0; k < co->n_f; k++) out[k] = co->v[ind[k]];
  return SDAE_OK;
}

void sdae__mbs_coords_point(const sdae_mbs_coords *co, double *q, double *v) {
  memcpy(q, co->q, co->n_q * sizeof *q);
  memcpy(v, co->v, co->n_q * sizeof *v);
}

/* ---- the energy structure at Phi^-1(t, 0, mu) (mbs_model.c) ---- */

int sdae__mbs_energy_on(sdae_mbs_coords *co, double t, const double *mu, double *H) {
  int rc = sdae__mbs_phi_inv(co, t, co->zero, mu);
  return rc == SDAE_OK ? co->linalg->energy(co->la, t, co->q, co->v, H) : rc;
}

/* w = W x: x at q_I, G_D^-1 (-G_I x) at q_D */
static void w_times(sdae_mbs_coords *co, const double *x, double *w) {
  memset(w, 0, co->n_q * sizeof *w);
  for (size_t k = 0; k < co->n_f; k++) w[co->ind[k]] = x[k];
  co->linalg->move(co->la, co->zero, w, co->dq_D);
  for (size_t j = 0; j < co->n_c; j++) w[co->dep[j]] = co->dq_D[j];
}

/* R x = W^T D W x, by products */
int sdae__mbs_damping_on(sdae_mbs_coords *co, double t, const double *mu, const double *x,
                         double *out) {
  int rc;
  if (!co->eval->sys.damping) {
    memset(out, 0, co->n_f * sizeof *out);
    return SDAE_OK;
  }
  if ((rc = sdae__mbs_phi_inv(co, t, co->zero, mu)) != SDAE_OK) return rc;
  w_times(co, x, co->w);
  if ((rc = co->linalg->damping_times(co->la, t, co->q, co->w, co->Dw)) != SDAE_OK) return rc;
  co->linalg->wt(co->la, co->Dw, out);
  return SDAE_OK;
}

/* W^T F_in, the momentum part of B u */
int sdae__mbs_input_on(sdae_mbs_coords *co, double t, const double *mu, double *Bu) {
  int rc;
  if ((rc = sdae__mbs_phi_inv(co, t, co->zero, mu)) != SDAE_OK ||
      (rc = sdae__mbs_input_force(co->eval, t, co->q, co->v, co->F_in)) != SDAE_OK)
    return rc;
  co->linalg->wt(co->la, co->F_in, Bu);
  return SDAE_OK;
}

/* ---- the implicit maps' linear solve ---- */

int sdae__mbs_coords_solves(const sdae_mbs_coords *co) { return co->linalg->newton_keep != NULL; }

int sdae__mbs_lsetup(sdae_mbs_coords *co, double t, const double *mu, double a) {
  int rc = sdae__mbs_phi_inv(co, t, co->zero, mu);
  if (rc != SDAE_OK) return rc;
  co->linalg->newton_keep(co->la);
  co->newton_a = a;
  return SDAE_OK;
}

/* (I - a J) z = r with J = [[0, M_r^-1], [0, 0]]: u = M_r^-1 r_p from the kept velocity's
 * system (w = W u, G w = 0, W^T M w = r_p), z_q = r_q + a u, z_p = r_p */
int sdae__mbs_lsolve(sdae_mbs_coords *co, const double *r, double *z) {
  size_t n_f = co->n_f;
  int rc = co->linalg->newton_velocity(co->la, r + n_f, co->w);
  if (rc != SDAE_OK) return rc;
  for (size_t k = 0; k < n_f; k++) z[k] = r[k] + co->newton_a * co->w[co->ind[k]];
  memcpy(z + n_f, r + n_f, n_f * sizeof *z);
  return SDAE_OK;
}

/* ---- the state ---- */

/* the rows chosen among redundant constraints, the back-end's (the chart, G and M at the
 * point), then the point */
void sdae__mbs_coords_state(sdae_mbs_coords *co, sdae_bytes *b) {
  size_t n_q = co->n_q, n_c = co->n_c;
  sdae__mbs_eval_state(co->eval, b);
  co->linalg->state(co->la, b);
  if (b->in) split(co);
  sdae__bytes_flag(b, &co->valid);
  sdae__bytes_doubles(b, &co->key_t, 1);
  sdae__bytes_doubles(b, co->key, 2 * n_q);
  sdae__bytes_doubles(b, co->q, n_q);
  sdae__bytes_doubles(b, co->v, n_q);
  sdae__bytes_doubles(b, co->ct, n_c);
}

/* the factors are not in the bytes: made anew at the next step's start, once the bytes read
 * are whole (a refused state leaves the stepper as it was, its factors' flag too) */
int sdae__mbs_coords_state_read(sdae_mbs_coords *co) {
  if (!sdae__mbs_eval_valid(co->eval) || !co->linalg->state_read(co->la)) return 0;
  co->fresh = 0;
  return 1;
}
