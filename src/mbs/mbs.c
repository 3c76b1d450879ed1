/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanical front-end's stepper: one block holding the front-end's arrays and the stepper
 * of the normal form; a step maps (q, v) to (xi, mu) in the best chart, takes one step of
 * scheme 11 or 15, and maps back. Nothing is allocated per step and a failed step leaves q, v,
 * the chart and the statistics as they were. */
#include <math.h>
#include <stdalign.h>
#include <stdint.h>
#include <string.h>

#include "maps/map.h"
#include "mbs_impl.h"
#include "stepper/stepper.h"

static int validate(const sdae_mbs *sys, const sdae_options *o) {
  if (!sys || !o) return SDAE_ERR_NULL;
  if (!sys->mass || !sys->force || !sys->constraint) return SDAE_ERR_NULL;
  if (sys->n_c == 0 || sys->n_c >= sys->n_q) return SDAE_ERR_DIM;
  return SDAE_OK;
}

static void carve_point(sdae_mbs_point *p, size_t n_q, size_t n_c, size_t n_f, sdae_arena *a) {
  p->q = sdae__take(a, n_q, 1);
  p->v = sdae__take(a, n_q, 1);
  p->c = sdae__take(a, n_c, 1);
  p->ct = sdae__take(a, n_c, 1);
  p->G = sdae__take(a, n_c, n_q);
  p->GD = sdae__take(a, n_c, n_c <= SDAE_SMALL_DENSE ? n_c : sdae__lu_band_cols(n_c - 1, n_c - 1));
  p->piv = sdae__take_pivots(a, n_c);
  p->A = sdae__take(a, n_c, n_f);
  p->W = sdae__take(a, n_q, n_f);
  p->M = sdae__take(a, n_q, n_q);
}

/* the front-end's arrays, then the normal form's stepper (its bytes counted by its own rule) */
static void carve(sdae_mbs_stepper *s, sdae_arena *a, size_t inner_bytes) {
  size_t n_q = s->n_q, n_c = s->n_c, n_f = s->n_f;
  s->dep = sdae__take_indices(a, n_c);
  s->ind = sdae__take_indices(a, n_f);
  s->perm = sdae__take_indices(a, n_q);
  s->cand_dep = sdae__take_indices(a, n_c);
  s->cand_ind = sdae__take_indices(a, n_f);
  s->saved = sdae__take_indices(a, n_q);
  s->qr = sdae__take(a, n_c, n_q);
  s->tau = sdae__take(a, n_c, 1);
  s->norm = sdae__take(a, n_q, 1);
  carve_point(&s->pt, n_q, n_c, n_f, a);
  s->pt_key = sdae__take(a, 2 * n_q, 1);
  s->q_base = sdae__take(a, n_q, 1);
  s->xi = sdae__take(a, 2 * n_c, 1);
  s->mu = sdae__take(a, 2 * n_f, 1);
  s->zero = sdae__take(a, 2 * n_c, 1);
  s->Mr = sdae__take(a, n_f, n_f);
  s->R = sdae__take(a, n_f, n_f);
  s->rf = sdae__take(a, n_f, 1);
  s->fd_q = sdae__take(a, n_q, 1);
  s->fd_qj = sdae__take(a, n_q, 1);
  s->fd_G = sdae__take(a, n_c, n_q);
  s->fd_M = sdae__take(a, n_q, n_q);
  s->fd_c = sdae__take(a, n_c, 1);
  s->fd_ct = sdae__take(a, n_c, 1);
  s->Gdot = sdae__take(a, n_c, n_q);
  s->Mdv = sdae__take(a, n_q, 1);
  s->gdot = sdae__take(a, n_c, 1);
  s->fd_Gt = sdae__take(a, n_c, n_q);
  s->fd_Mdvt = sdae__take(a, n_q, 1);
  s->fd_gdott = sdae__take(a, n_c, 1);
  s->r1 = sdae__take(a, n_q, 1);
  s->r2 = sdae__take(a, n_q, 1);
  s->r3 = sdae__take(a, n_q, 1);
  s->X = sdae__take(a, n_c, n_f);
  s->LY = sdae__take(a, n_c, n_q);
  s->LA = sdae__take(a, n_c, n_c);
  s->query_xi = sdae__take(a, 2 * n_c, 1);
  sdae__mbs_derive_carve(s, a);
  s->inner = sdae__take_array(a, inner_bytes, 1, alignof(max_align_t));
}

/* the stepper's fields that do not live in the arrays */
static void wire(sdae_mbs_stepper *s, const sdae_mbs *sys, const sdae_options *o) {
  memset(s, 0, sizeof *s);
  s->sys = *sys;
  s->opt = *o;
  /* the noise of the differences (SDAE_MBS_NEWTON_TOL); an invalid tolerance stays, for the
   * validation to refuse */
  double least = sys->jacobian ? SDAE_MBS_NEWTON_TOL : SDAE_MBS_FD_NEWTON_TOL;
  if (o->newton_tol > 0.0 && o->newton_tol < least) s->opt.newton_tol = least;
  s->n_q = sys->n_q;
  s->n_c = sys->n_c;
  s->n_f = sys->n_q - sys->n_c;
  s->energy_map = o->map && sdae__map_uses_H(o->map); /* no map: refused by the validation */
  sdae__mbs_model(s);
}

/* the block's bytes (with room to align a caller's block) and the normal form's stepper's */
static int measure(const sdae_mbs *sys, const sdae_options *o, size_t *bytes, size_t *inner) {
  sdae_mbs_stepper probe;
  sdae_arena a = {0};
  int rc = validate(sys, o);
  if (rc != SDAE_OK) return rc;
  wire(&probe, sys, o);
  if ((rc = sdae__stepper_validate(&probe.model, &probe.opt)) != SDAE_OK) return rc;
  if ((*inner = sdae_stepper_size(&probe.model, &probe.opt)) == 0) return SDAE_ERR_OVERFLOW;
  carve(&probe, &a, *inner);
  return sdae__block_bytes(&a, sizeof(sdae_mbs_stepper), bytes);
}

size_t sdae_mbs_stepper_size(const sdae_mbs *sys, const sdae_options *o) {
  size_t bytes, inner;
  return measure(sys, o, &bytes, &inner) == SDAE_OK ? bytes : 0;
}

static sdae_mbs_stepper *build(void *mem, const sdae_mbs *sys, const sdae_options *o,
                               size_t inner) {
  sdae_arena a;
  sdae_mbs_stepper *s = sdae__block_start(mem, sizeof(sdae_mbs_stepper), &a);
  void *inner_mem;
  wire(s, sys, o);
  carve(s, &a, inner);
  inner_mem = s->inner;
  memset(s->zero, 0, 2 * s->n_c * sizeof *s->zero);
  /* measured with the same model and options: cannot fail */
  sdae_stepper_init(&s->inner, inner_mem, inner, &s->model, &s->opt);
  return s;
}

int sdae_mbs_stepper_init(sdae_mbs_stepper **s, void *mem, size_t len, const sdae_mbs *sys,
                          const sdae_options *o) {
  size_t bytes, inner;
  int rc;
  if (!s || !mem) return SDAE_ERR_NULL;
  if ((rc = measure(sys, o, &bytes, &inner)) != SDAE_OK) return rc;
  if (len < bytes) return SDAE_ERR_BUFFER;
  *s = build(mem, sys, o, inner);
  return SDAE_OK;
}

int sdae_mbs_stepper_alloc_with(sdae_mbs_stepper **s, const sdae_mbs *sys,
                                const sdae_options *o, const sdae_allocator *a) {
  sdae_block block;
  size_t bytes, inner;
  void *mem;
  int rc;
  if (!s) return SDAE_ERR_NULL;
  if ((rc = measure(sys, o, &bytes, &inner)) != SDAE_OK) return rc;
  if (!(mem = sdae__block_alloc(&block, a, bytes))) return SDAE_ERR_NOMEM;
  *s = build(mem, sys, o, inner);
  (*s)->block = block;
  return SDAE_OK;
}

int sdae_mbs_stepper_alloc(sdae_mbs_stepper **s, const sdae_mbs *sys, const sdae_options *o) {
  return sdae_mbs_stepper_alloc_with(s, sys, o, NULL);
}

void sdae_mbs_stepper_free(sdae_mbs_stepper *s) {
  if (s) sdae__block_free(&s->block);
}

/* ---- the step ---- */

static int state_ok(const sdae_mbs_stepper *s, double t, const double *q, const double *v) {
  if (!isfinite(t)) return SDAE_ERR_PARAM;
  return sdae__all_finite(q, s->n_q) && sdae__all_finite(v, s->n_q) ? SDAE_OK : SDAE_ERR_STATE;
}

/* M at (t, q) into the point, and its Cholesky factor in scratch: SDAE_ERR_MASS unless SPD */
static int mass_at(sdae_mbs_stepper *s, double t, const double *q) {
  int rc = sdae__mbs_mass(s, t, q, s->pt.M);
  if (rc != SDAE_OK) return rc;
  memcpy(s->fd_M, s->pt.M, s->n_q * s->n_q * sizeof *s->fd_M);
  return sdae__cholesky_factor(s->fd_M, s->n_q);
}

/* the energy-conserving maps need time-independent constraints */
static int energy_map_ok(const sdae_mbs_stepper *s) {
  if (!s->energy_map) return SDAE_OK;
  for (size_t j = 0; j < s->n_c; j++)
    if (s->pt.ct[j] != 0.0) return SDAE_ERR_MAP;
  return SDAE_OK;
}

/* the normal form's step; a failing callback of it reports the front-end's own status */
static int normal_step(sdae_mbs_stepper *s, double t, double T) {
  int rc = sdae_step(s->inner, t, T, s->xi, s->mu);
  if ((rc == SDAE_ERR_CALLBACK_FATAL || rc == SDAE_ERR_CALLBACK_RECOVERABLE) &&
      s->status != SDAE_OK)
    rc = s->status;
  return rc;
}

static int try_step(sdae_mbs_stepper *s, double t, double T, const double *q, const double *v) {
  int rc;
  s->status = SDAE_OK;
  if ((rc = sdae__mbs_xi_at(s, t, q, v, s->xi)) != SDAE_OK || (rc = energy_map_ok(s)) != SDAE_OK ||
      (rc = sdae__mbs_choose_chart(s)) != SDAE_OK || (rc = mass_at(s, t, q)) != SDAE_OK)
    return rc;
  sdae__mbs_mu_at(s, q, v, s->mu);
  memcpy(s->q_base, q, s->n_q * sizeof *q);
  sdae__mbs_forget(s);
  if ((rc = normal_step(s, t, T)) != SDAE_OK) return rc;
  return sdae__mbs_phi_inv(s, t + T, s->xi, s->mu);
}

int sdae_mbs_step(sdae_mbs_stepper *s, double t, double T, double *q, double *v) {
  sdae_mbs_stats stats;
  sdae_stats inner;
  int had_chart, rc;
  if (!s || !q || !v) return SDAE_ERR_NULL;
  if (!(isfinite(T) && T > 0.0)) return SDAE_ERR_STEP;
  if ((rc = state_ok(s, t, q, v)) != SDAE_OK) return rc;
  stats = s->stats;
  inner = *sdae_stepper_stats(s->inner);
  had_chart = s->have_chart;
  memcpy(s->saved, s->dep, s->n_c * sizeof *s->dep);
  memcpy(s->saved + s->n_c, s->ind, s->n_f * sizeof *s->ind);
  rc = try_step(s, t, T, q, v);
  if (rc == SDAE_ERR_PHI_INV && s->kept) {
    /* the chart kept by hysteresis folds within the step: once more in the best one */
    s->force_best = 1;
    rc = try_step(s, t, T, q, v);
    s->force_best = 0;
  }
  if (rc != SDAE_OK) { /* the chart and every count (the normal form's stepper's too) as before */
    memcpy(s->dep, s->saved, s->n_c * sizeof *s->dep);
    memcpy(s->ind, s->saved + s->n_c, s->n_f * sizeof *s->ind);
    s->have_chart = had_chart;
    s->stats = stats;
    sdae__stepper_restore_stats(s->inner, &inner);
    sdae__mbs_forget(s);
    return rc;
  }
  memcpy(q, s->pt.q, s->n_q * sizeof *q);
  memcpy(v, s->pt.v, s->n_q * sizeof *v);
  s->stats.step = *sdae_stepper_stats(s->inner);
  return SDAE_OK;
}

/* ---- integrate ---- */

typedef struct run {
  sdae_mbs_stepper *s;
  double *q, *v;
  sdae_mbs_observer obs;
  void *data;
} run;

static int step(void *ctx, double t, double T) {
  run *r = ctx;
  return sdae_mbs_step(r->s, t, T, r->q, r->v);
}

static int observe(void *ctx, size_t i, double t) {
  run *r = ctx;
  return r->obs(i, t, r->q, r->v, r->data);
}

int sdae_mbs_integrate(sdae_mbs_stepper *s, double t0, double T, size_t nsteps, size_t every,
                       double *q, double *v, sdae_mbs_observer obs, void *data,
                       size_t *steps_done) {
  run r = {s, q, v, obs, data};
  sdae_drive d = {step, obs ? observe : NULL, &r};
  if (steps_done) *steps_done = 0;
  if (!s || !q || !v) return SDAE_ERR_NULL;
  return sdae__drive(&d, t0, T, nsteps, every, steps_done);
}

/* ---- quantities at a state ---- */

/* Every query computes into its scratch and hands out its result only when it is finite: a
 * finite state may still overflow (G v, v^T M v, the multipliers' gamma ~ |v|^2). */
int sdae_mbs_xi(sdae_mbs_stepper *s, double t, const double *q, const double *v, double *xi) {
  int rc;
  if (!s || !q || !v || !xi) return SDAE_ERR_NULL;
  if ((rc = state_ok(s, t, q, v)) != SDAE_OK ||
      (rc = sdae__mbs_xi_at(s, t, q, v, s->query_xi)) != SDAE_OK)
    return rc;
  if (!sdae__all_finite(s->query_xi, 2 * s->n_c)) return SDAE_ERR_NONFINITE;
  memcpy(xi, s->query_xi, 2 * s->n_c * sizeof *xi);
  return SDAE_OK;
}

int sdae_mbs_energy(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                    double *E) {
  double V = 0.0, kinetic = 0.0, energy;
  size_t n = 0;
  int rc;
  if (!s || !q || !v || !E) return SDAE_ERR_NULL;
  if ((rc = state_ok(s, t, q, v)) != SDAE_OK) return rc;
  n = s->n_q;
  if ((rc = sdae__mbs_mass(s, t, q, s->fd_M)) != SDAE_OK) return rc;
  if (s->sys.potential && (rc = sdae__mbs_potential(s, t, q, &V)) != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) kinetic += v[i] * s->fd_M[i * n + j] * v[j];
  energy = 0.5 * kinetic + V;
  if (!isfinite(energy)) return SDAE_ERR_NONFINITE;
  *E = energy;
  return SDAE_OK;
}

/* (G M^-1 G^T) lambda = G M^-1 F + gamma: Y = G M^-1 row by row (M symmetric), then the
 * n_c x n_c system, singular only when the constraints are dependent; G Y^T symmetric by
 * construction (its upper triangle, mirrored), as Cholesky requires */
int sdae_mbs_lambda(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                    double *lambda) {
  size_t n_q, n_c;
  int rc;
  if (!s || !q || !v || !lambda) return SDAE_ERR_NULL;
  if ((rc = state_ok(s, t, q, v)) != SDAE_OK) return rc;
  n_q = s->n_q, n_c = s->n_c;
  if ((rc = sdae__mbs_along(s, t, q, v, s->Gdot, NULL, s->gdot)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian(s, t, q, s->Gdot)) != SDAE_OK ||
      (rc = sdae__mbs_force(s, t, q, v, s->r1)) != SDAE_OK ||
      (rc = sdae__mbs_mass(s, t, q, s->fd_M)) != SDAE_OK ||
      (rc = sdae__cholesky_factor(s->fd_M, n_q)) != SDAE_OK)
    return rc;
  for (size_t j = 0; j < n_c; j++) {
    memcpy(s->LY + j * n_q, s->Gdot + j * n_q, n_q * sizeof *s->LY);
    sdae__cholesky_solve(s->fd_M, n_q, s->LY + j * n_q);
  }
  for (size_t i = 0; i < n_c; i++) {
    double b = s->gdot[i];
    for (size_t k = 0; k < n_q; k++) b += s->LY[i * n_q + k] * s->r1[k];
    s->r2[i] = b;
    for (size_t j = i; j < n_c; j++) {
      double acc = 0.0;
      for (size_t k = 0; k < n_q; k++) acc += s->Gdot[i * n_q + k] * s->LY[j * n_q + k];
      s->LA[i * n_c + j] = s->LA[j * n_c + i] = acc;
    }
  }
  if (sdae__cholesky_factor(s->LA, n_c) != SDAE_OK) return SDAE_ERR_RANK;
  sdae__cholesky_solve(s->LA, n_c, s->r2);
  if (!sdae__all_finite(s->r2, n_c)) return SDAE_ERR_NONFINITE;
  memcpy(lambda, s->r2, n_c * sizeof *lambda);
  return SDAE_OK;
}

int sdae_mbs_chart(const sdae_mbs_stepper *s, size_t *dependent) {
  if (!s || !dependent) return SDAE_ERR_NULL;
  if (!s->have_chart) return SDAE_ERR_CHART;
  memcpy(dependent, s->dep, s->n_c * sizeof *dependent);
  return SDAE_OK;
}

const sdae_mbs_stats *sdae_mbs_stepper_stats(const sdae_mbs_stepper *s) {
  return s ? &s->stats : NULL;
}

void sdae_mbs_stepper_reset_stats(sdae_mbs_stepper *s) {
  if (!s) return;
  memset(&s->stats, 0, sizeof s->stats);
  sdae_stepper_reset_stats(s->inner);
}
