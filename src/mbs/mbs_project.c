/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The projection step across a singular configuration (mbs_project.h). The chart's coordinates
 * solve for q_D with G_D, whose least singular value vanishes with the configuration's distance
 * from the singular one while the chart's measure stays near 1: a chart step there loses
 * accuracy as 1 / sin^2 of the constraints' least angle (or the branch). The motion itself is
 * smooth through it, and so is the index-1 acceleration; rk8 in (q, v) with the projections
 * afterwards keeps its order there, at the cost of dense solves, for the few steps near it. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <stabdae/maps.h>
#include <stabdae/mbs.h>

#include "core/callback.h"
#include "mbs_project.h"

static int motion(double t, const double *y, double *out, void *params);

void sdae__mbs_project_init(sdae_mbs_project *p, sdae_mbs_eval *eval, const sdae_options *o,
                            const sdae_mbs_sparse_layout *sparse, const sdae_mbs_sparse_lent *lent,
                            int on) {
  memset(p, 0, sizeof *p);
  p->eval = eval;
  p->n_q = eval->n_q;
  p->n_c = eval->n_c;
  p->on = on;
  if (sparse) {
    sdae__mbs_project_sparse_init(&p->sparse, eval, sparse, lent);
    p->linalg = &sdae__mbs_project_sparse_linalg, p->la = &p->sparse;
  } else {
    sdae__mbs_project_dense_init(&p->dense, eval);
    p->linalg = &sdae__mbs_project_dense_linalg, p->la = &p->dense;
  }
  p->max_iter = o->newton_max_iter;
  p->map = sdae_map_rk8;
  p->model.n_mu = 2 * p->n_q;
  p->model.q0 = motion;
  p->model.params = p;
  p->last = p->largest = -1.0;
}

void sdae__mbs_project_carve(sdae_mbs_project *p, sdae_arena *a) {
  size_t n_q = p->n_q, n_c = p->n_c;
  if (!p->on) return;
  p->linalg->carve(p->la, a);
  p->ctx.model = &p->model;
  p->ctx.work = sdae__take(a, p->map->scratch(&p->model, NULL), 1);
  p->y = sdae__take(a, 2 * n_q, 1);
  p->ys = sdae__take(a, 2 * n_q, 1);
  p->phi = sdae__take(a, 2 * n_q, 1);
  p->F = sdae__take(a, n_q, 1);
  p->gamma = sdae__take(a, n_c, 1);
  p->c = sdae__take(a, n_c, 1);
  p->ct = sdae__take(a, n_c, 1);
  p->dx = sdae__take(a, n_q, 1);
}

int sdae__mbs_project_wanted(const sdae_mbs_project *p, int start, double s) {
  double near = SDAE_MBS_SINGULAR_NEAR * p->largest;
  if (!p->on || !(p->last >= 0.0)) return 0;
  if (start == SDAE_ERR_CHART || start == SDAE_ERR_RANK) return 1;
  return start == SDAE_OK && (s < near || 2.0 * s - p->last < near);
}

void sdae__mbs_project_seen(sdae_mbs_project *p, double s) {
  p->last = s;
  p->largest = fmax(p->largest, s);
}

static double inf_norm(const double *x, size_t n) {
  double m = 0.0;
  for (size_t i = 0; i < n; i++) m = fmax(m, fabs(x[i]));
  return m;
}

/* c at rounding: each |c_j| within a few eps of its terms' size, |G_j|_1 |q|_inf (the floors
 * of a chart step's xi) */
static int at_rounding(const sdae_mbs_project *p, const double *q) {
  double nq = fmax(1.0, inf_norm(q, p->n_q));
  for (size_t j = 0; j < p->n_c; j++)
    if (!(fabs(p->c[j]) <= 8.0 * DBL_EPSILON * p->linalg->row_size(p->la, j) * nq)) return 0;
  return 1;
}

/* The floors of the rows' sines below which a row is dropped from the projections and from the
 * acceleration, a row's sine being its angle to the span of those before it in G's pivoted QR.
 * A row kept at sine s amplifies rounding by 1 / s in the projections of q and v (the energy
 * off by eps / s) and by 1 / s^2 in the acceleration; a row dropped is left to the others,
 * its residual in the positions about s times the correction, and its force in the
 * acceleration, about s times the constraint force, left out. Measured on the N-four-bar (N =
 * 2, 10, 40, rk8 at T = 1e-4 to 1e-2 through a crossing from twelve phases of the steps'
 * grid; docs/performance.md): the energy's largest change below 5e-11 with these, up to
 * 4.7e-9 with the projections' rows kept down to SDAE_MBS_CHART_MIN. The acceleration's floor
 * is the higher: it truncates the projections' factorization, which can only drop rows. */
#define POSITION_FLOOR 1e-6
#define ACCELERATION_FLOOR 1e-4

/* q (in y) onto c(t, q) = 0 by Gauss-Newton with least M-norm corrections; G and M factored at
 * the q it ends at, but for the last correction, at rounding */
static int positions(sdae_mbs_project *p, double t, double *q) {
  sdae_mbs_eval *e = p->eval;
  for (unsigned it = 0;; it++) {
    int rc, done;
    if ((rc = sdae__mbs_constraint(e, t, q, p->c)) != SDAE_OK ||
        (rc = p->linalg->factor(p->la, t, q, POSITION_FLOOR)) != SDAE_OK)
      return rc;
    /* at rounding, one correction more: Gauss-Newton would stop on one side of the root, step
     * after step, and the steps near a singular configuration would sum it */
    done = at_rounding(p, q);
    if (!done && it == p->max_iter) return SDAE_ERR_NEWTON;
    p->linalg->solve(p->la, NULL, p->c, p->dx);
    for (size_t i = 0; i < p->n_q; i++) q[i] += p->dx[i];
    if (!sdae__all_finite(q, p->n_q)) return SDAE_ERR_NONFINITE;
    if (done) return SDAE_OK;
  }
}

/* v (in y) onto G v + dc/dt = 0, least M-norm, with the factors at q */
static int velocities(sdae_mbs_project *p, double t, const double *q, double *v) {
  int rc = sdae__mbs_constraint_t(p->eval, t, q, p->ct);
  if (rc != SDAE_OK) return rc;
  p->linalg->g_times(p->la, v, p->ct, p->c);
  p->linalg->solve(p->la, NULL, p->c, p->dx);
  for (size_t i = 0; i < p->n_q; i++) v[i] += p->dx[i];
  return sdae__all_finite(v, p->n_q) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

/* y' = (v, a) at y projected onto the constraints (q onto c = 0, v onto G v + dc/dt = 0): a
 * from M a = F - G^T lambda, G a + gamma = 0 there, G's rows below ACCELERATION_FLOOR from the
 * span of the others dropped. Off the constraints, near a singular configuration, the
 * acceleration would answer the stage's distance from them divided by the least sine. */
static int motion(double t, const double *y, double *out, void *params) {
  sdae_mbs_project *p = params;
  sdae_mbs_eval *e = p->eval;
  size_t n_q = p->n_q;
  double *q = p->ys, *v = p->ys + n_q;
  int rc;
  memcpy(p->ys, y, 2 * n_q * sizeof *y);
  if ((rc = positions(p, t, q)) != SDAE_OK || (rc = velocities(p, t, q, v)) != SDAE_OK ||
      (rc = sdae__mbs_force(e, t, q, v, p->F)) != SDAE_OK ||
      (rc = p->linalg->gamma(p->la, t, q, v, p->gamma)) != SDAE_OK ||
      (rc = p->linalg->refactor(p->la, ACCELERATION_FLOOR)) != SDAE_OK) {
    p->status = rc;
    return -1;
  }
  memcpy(out, v, n_q * sizeof *out);
  p->linalg->solve(p->la, p->F, p->gamma, out + n_q);
  return 0;
}

/* what the projection moved q (dx: q before it) against the step's own motion (from q0) */
static int accurate(const sdae_mbs_project *p, const double *q0, const double *q_rk,
                    const double *q) {
  double moved = 0.0, drift = 0.0;
  for (size_t i = 0; i < p->n_q; i++) {
    moved = fmax(moved, fabs(q_rk[i] - q0[i]));
    drift = fmax(drift, fabs(q[i] - q_rk[i]));
  }
  return drift <=
         SDAE_MBS_PROJECT_DRIFT * moved + 16.0 * DBL_EPSILON * fmax(1.0, inf_norm(q, p->n_q));
}

int sdae__mbs_project_step(sdae_mbs_project *p, double t, double T, double *q, double *v) {
  size_t n_q = p->n_q, n = 2 * n_q;
  double *y = p->y, *phi = p->phi;
  int rc;
  memcpy(y, q, n_q * sizeof *y);
  memcpy(y + n_q, v, n_q * sizeof *y);
  p->status = SDAE_OK;
  rc = sdae__map_phi(p->map, &p->ctx, t, T, y, NULL, phi);
  if (rc != SDAE_OK) return p->status != SDAE_OK ? p->status : rc;
  for (size_t i = 0; i < n; i++) y[i] += T * phi[i];
  if (!sdae__all_finite(y, n)) return SDAE_ERR_NONFINITE;
  memcpy(phi, y, n_q * sizeof *phi); /* q after the map, before the projection */
  if ((rc = positions(p, t + T, y)) != SDAE_OK) return rc;
  if (!accurate(p, q, phi, y)) return SDAE_ERR_CHART;
  if ((rc = velocities(p, t + T, y, y + n_q)) != SDAE_OK) return rc;
  memcpy(q, y, n_q * sizeof *q);
  memcpy(v, y + n_q, n_q * sizeof *v);
  return SDAE_OK;
}

void sdae__mbs_project_state(sdae_mbs_project *p, sdae_bytes *b) {
  sdae__bytes_doubles(b, &p->last, 1);
  sdae__bytes_doubles(b, &p->largest, 1);
}
