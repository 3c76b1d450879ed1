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
  /* a derivative of a callback left out: what it derives from is differenced, and it with it */
  if ((sys->jacobian_dot && !sys->jacobian) || (sys->constraint_t_dot && !sys->constraint_t))
    return SDAE_ERR_NULL;
  if (sys->n_c == 0 || sys->n_c >= sys->n_q) return SDAE_ERR_DIM;
  return sdae__mbs_patterns_check(sys);
}

/* the parts' arrays, the step's own, then the normal form's stepper (its bytes counted by its
 * own rule); handed out, what the parts analyse of the mechanism when built (the sparse
 * saddle-point system's order and structure) may refuse it */
static int carve(sdae_mbs_stepper *s, sdae_arena *a, size_t inner_bytes) {
  int rc = SDAE_OK;
  sdae__mbs_eval_carve(&s->eval, a);
  if (s->sparse) { /* the dense parts not carved: their arrays grow with n_q^2 */
    rc = sdae__mbs_sparse_carve(&s->sp, a);
    sdae__mbs_sparse_query_carve(&s->sq, &s->sp, a);
  } else {
    sdae__mbs_chart_carve(&s->chart, a);
    sdae__mbs_coords_carve(&s->coords, a);
    sdae__mbs_query_carve(&s->query, s->n_q, s->n_c, a);
  }
  sdae__mbs_model_carve(&s->nf, a);
  s->xi = sdae__take(a, 2 * s->n_c, 1);
  s->mu = sdae__take(a, 2 * s->n_f, 1);
  s->rollback = sdae__take_array(a, sdae__mbs_parts_bytes(s), 1, 1);
  s->inner = sdae__take_array(a, inner_bytes, 1, alignof(max_align_t));
  return rc;
}

/* the stepper's parts wired to each other, arrays not yet handed out */
static void wire(sdae_mbs_stepper *s, const sdae_mbs *sys, const sdae_options *o) {
  memset(s, 0, sizeof *s);
  s->opt = *o;
  /* the noise of the differences (SDAE_MBS_NEWTON_TOL); an invalid tolerance stays, for the
   * validation to refuse */
  double least = sys->jacobian ? SDAE_MBS_NEWTON_TOL : SDAE_MBS_FD_NEWTON_TOL;
  if (o->newton_tol > 0.0 && o->newton_tol < least) s->opt.newton_tol = least;
  s->n_q = sys->n_q;
  s->n_c = sys->n_c;
  s->n_f = sys->n_q - sys->n_c;
  s->energy_map = o->map && sdae__map_uses_H(o->map); /* no map: refused by the validation */
  sdae__mbs_eval_init(&s->eval, sys);
  sdae__mbs_chart_init(&s->chart, s->n_q, s->n_c);
  sdae__mbs_coords_init(&s->coords, &s->eval, &s->chart, o->newton_max_iter);
  s->sparse = sdae__mbs_sparse_applies(sys, o);
  s->eval.matrices = !s->sparse;
  if (s->sparse) sdae__mbs_sparse_init(&s->sp, &s->eval, o->newton_max_iter);
  sdae__mbs_model_init(&s->nf, &s->eval, &s->coords, s->sparse ? &s->sp : NULL);
}

/* the block's bytes (with room to align a caller's block) and the normal form's stepper's */
static int measure(const sdae_mbs *sys, const sdae_options *o, size_t *bytes, size_t *inner) {
  sdae_mbs_stepper probe;
  sdae_arena a = {0};
  int rc = validate(sys, o);
  if (rc != SDAE_OK) return rc;
  wire(&probe, sys, o);
  if (probe.sparse && !sdae__mbs_sparse_fits(&probe.sp)) return SDAE_ERR_OVERFLOW;
  if ((rc = sdae__stepper_validate(&probe.nf.model, &probe.opt)) != SDAE_OK) return rc;
  if ((*inner = sdae_stepper_size(&probe.nf.model, &probe.opt)) == 0) return SDAE_ERR_OVERFLOW;
  carve(&probe, &a, *inner);
  return sdae__block_bytes(&a, sizeof(sdae_mbs_stepper), bytes);
}

size_t sdae_mbs_stepper_size(const sdae_mbs *sys, const sdae_options *o) {
  size_t bytes, inner;
  return measure(sys, o, &bytes, &inner) == SDAE_OK ? bytes : 0;
}

static int build(sdae_mbs_stepper **out, void *mem, const sdae_mbs *sys, const sdae_options *o,
                 size_t inner) {
  sdae_arena a;
  sdae_mbs_stepper *s = sdae__block_start(mem, sizeof(sdae_mbs_stepper), &a);
  void *inner_mem;
  int rc;
  wire(s, sys, o);
  if ((rc = carve(s, &a, inner)) != SDAE_OK) return rc;
  inner_mem = s->inner;
  /* measured with the same model and options: cannot fail */
  sdae_stepper_init(&s->inner, inner_mem, inner, &s->nf.model, &s->opt);
  sdae__stepper_keep_newton(s->inner); /* each residual a Phi^-1: the matrix is kept */
  *out = s;
  return SDAE_OK;
}

int sdae_mbs_stepper_init(sdae_mbs_stepper **s, void *mem, size_t len, const sdae_mbs *sys,
                          const sdae_options *o) {
  size_t bytes, inner;
  int rc;
  if (!s || !mem) return SDAE_ERR_NULL;
  if ((rc = measure(sys, o, &bytes, &inner)) != SDAE_OK) return rc;
  if (len < bytes) return SDAE_ERR_BUFFER;
  return build(s, mem, sys, o, inner);
}

int sdae_mbs_stepper_alloc_with(sdae_mbs_stepper **s, const sdae_mbs *sys, const sdae_options *o,
                                const sdae_allocator *a) {
  sdae_block block;
  size_t bytes, inner;
  void *mem;
  int rc;
  if (!s) return SDAE_ERR_NULL;
  if ((rc = measure(sys, o, &bytes, &inner)) != SDAE_OK) return rc;
  if (!(mem = sdae__block_alloc(&block, a, bytes))) return SDAE_ERR_NOMEM;
  if ((rc = build(s, mem, sys, o, inner)) != SDAE_OK) {
    sdae__block_free(&block);
    return rc;
  }
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

void sdae__mbs_stepper_gather(sdae_mbs_stepper *s) {
  s->stats.step = *sdae_stepper_stats(s->inner);
  s->stats.chart_switches = s->sparse ? s->sp.switches : s->chart.switches;
  s->stats.phi_inv_iters = s->sparse ? s->sp.phi_inv_iters : s->coords.phi_inv_iters;
  s->stats.chart_measure = s->sparse ? s->sp.measure : s->chart.measure;
}

/* what coords and the normal form keep (Phi^-1's configuration, q0 at a (t, mu)) came from an
 * earlier start of Phi^-1's Newton, and after a chart switch from another chart: a step starts
 * without it, and a failed one leaves none of its own behind */
static void forget(sdae_mbs_stepper *s) {
  sdae__mbs_coords_forget(&s->coords);
  if (s->sparse) sdae__mbs_sparse_forget(&s->sp);
  sdae__mbs_model_forget(&s->nf);
}

/* the energy-conserving maps need time-independent constraints (implicit maps: never sparse) */
static int energy_map_ok(const sdae_mbs_stepper *s) {
  if (!s->energy_map) return SDAE_OK;
  for (size_t j = 0; j < s->n_c; j++)
    if (s->coords.ct[j] != 0.0) return SDAE_ERR_MAP;
  return SDAE_OK;
}

static unsigned long switches(const sdae_mbs_stepper *s) {
  return s->sparse ? s->sp.switches : s->chart.switches;
}

static int kept(const sdae_mbs_stepper *s) { return s->sparse ? s->sp.kept : s->chart.kept; }

/* the normal form's step; a failing callback of it reports the front-end's own status */
static int normal_step(sdae_mbs_stepper *s, double t, double T) {
  int rc = sdae_step(s->inner, t, T, s->xi, s->mu);
  if ((rc == SDAE_ERR_CALLBACK_FATAL || rc == SDAE_ERR_CALLBACK_RECOVERABLE) &&
      s->nf.status != SDAE_OK)
    rc = s->nf.status;
  return rc;
}

/* a new chart: mu is other coordinates, the Newton matrix kept by the normal form's stepper
 * (a function of mu) is not theirs */
static int chart_news(sdae_mbs_stepper *s, unsigned long before) {
  if (switches(s) != before) sdae__stepper_newton_forget(s->inner);
  return SDAE_OK;
}

/* every xi_i at its floor: the state is on the manifold to rounding */
static int at_floors(const sdae_mbs_stepper *s) {
  for (size_t i = 0; i < 2 * s->n_c; i++)
    if (!(fabs(s->xi[i]) <= s->nf.floor[i])) return 0;
  return 1;
}

/* try_step's start for a sparse mechanism: xi, the chart, mu and the floors by mbs_sparse */
static int sparse_start(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                        int force_best) {
  unsigned long before = s->sp.switches;
  int rc;
  if ((rc = sdae__mbs_sparse_xi(&s->sp, t, q, v, s->xi)) != SDAE_OK ||
      (rc = sdae__mbs_sparse_choose(&s->sp, force_best)) != SDAE_OK ||
      (rc = chart_news(s, before)) != SDAE_OK ||
      (rc = sdae__mbs_sparse_begin(&s->sp, t, q, v, s->mu)) != SDAE_OK)
    return rc;
  sdae__mbs_sparse_floors(&s->sp, q, v, s->nf.floor);
  forget(s);
  if (at_floors(s) && (rc = sdae__mbs_sparse_seed(&s->sp, t, q, v, s->mu)) != SDAE_OK) return rc;
  return SDAE_OK;
}

static int sparse_try_step(sdae_mbs_stepper *s, double t, double T, const double *q,
                           const double *v, int force_best) {
  int rc;
  s->nf.status = SDAE_OK;
  if ((rc = sparse_start(s, t, q, v, force_best)) != SDAE_OK ||
      (rc = normal_step(s, t, T)) != SDAE_OK)
    return rc;
  return sdae__mbs_sparse_phi_inv_state(&s->sp, t + T, s->xi, s->mu);
}

/* (q, v) -> xi, the chart (the best one with force_best), mu -> one step -> Phi^-1 at t + T;
 * on the manifold the state is the first evaluation's Phi^-1(t, 0, mu) */
static int try_step(sdae_mbs_stepper *s, double t, double T, const double *q, const double *v,
                    int force_best) {
  unsigned long before = s->chart.switches;
  int rc;
  if (s->sparse) return sparse_try_step(s, t, T, q, v, force_best);
  s->nf.status = SDAE_OK;
  if ((rc = sdae__mbs_coords_xi(&s->coords, t, q, v, s->xi)) != SDAE_OK ||
      (rc = energy_map_ok(s)) != SDAE_OK ||
      (rc = sdae__mbs_chart_choose(&s->chart, s->coords.G, force_best)) != SDAE_OK ||
      (rc = chart_news(s, before)) != SDAE_OK ||
      (rc = sdae__mbs_coords_begin(&s->coords, t, q, v, s->mu)) != SDAE_OK)
    return rc;
  sdae__mbs_coords_floors(&s->coords, q, v, s->nf.floor);
  forget(s);
  if (at_floors(s) && (rc = sdae__mbs_coords_seed(&s->coords, t, q, v, s->mu)) != SDAE_OK)
    return rc;
  if ((rc = normal_step(s, t, T)) != SDAE_OK) return rc;
  return sdae__mbs_phi_inv_state(&s->coords, t + T, s->xi, s->mu);
}

int sdae_mbs_step(sdae_mbs_stepper *s, double t, double T, double *q, double *v) {
  int rc;
  if (!s || !q || !v) return SDAE_ERR_NULL;
  if (!(isfinite(T) && T > 0.0)) return SDAE_ERR_STEP;
  if ((rc = sdae__mbs_state_ok(&s->eval, t, q, v)) != SDAE_OK) return rc;
  sdae__mbs_rollback_save(s);
  rc = try_step(s, t, T, q, v, 0);
  if (rc == SDAE_ERR_PHI_INV && kept(s)) {
    /* the chart kept by hysteresis folds within the step: once more in the best one, counted
     * as the one step it is (the first try's work is not kept, as a failed step's is not) */
    sdae__mbs_rollback(s);
    rc = try_step(s, t, T, q, v, 1);
  }
  if (rc == SDAE_OK) {
    memcpy(q, s->sparse ? s->sp.q : s->coords.q, s->n_q * sizeof *q);
    memcpy(v, s->sparse ? s->sp.v : s->coords.v, s->n_q * sizeof *v);
  } else {
    sdae__mbs_rollback(s);
  }
  sdae__mbs_stepper_gather(s);
  return rc;
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

const sdae_mbs_stats *sdae_mbs_stepper_stats(const sdae_mbs_stepper *s) {
  return s ? &s->stats : NULL;
}

void sdae_mbs_stepper_reset_stats(sdae_mbs_stepper *s) {
  if (!s) return;
  s->chart.switches = 0; /* the counters; the chart's measure is the current chart's */
  s->coords.phi_inv_iters = 0;
  s->sp.switches = 0, s->sp.phi_inv_iters = 0;
  sdae_stepper_reset_stats(s->inner);
  sdae__mbs_stepper_gather(s);
}

/* ---- the state as bytes (mbs_state.c) ---- */

size_t sdae_mbs_state_size(const sdae_mbs_stepper *s) { return s ? sdae__mbs_state_size(s) : 0; }

int sdae_mbs_get_state(const sdae_mbs_stepper *s, void *buf, size_t len) {
  if (!s || !buf) return SDAE_ERR_NULL;
  return sdae__mbs_state_get(s, buf, len);
}

int sdae_mbs_set_state(sdae_mbs_stepper *s, const void *buf, size_t len) {
  int rc;
  if (!s || !buf) return SDAE_ERR_NULL;
  if ((rc = sdae__mbs_state_set(s, buf, len)) == SDAE_OK) sdae__mbs_stepper_gather(s);
  return rc;
}

/* ---- quantities at a state (mbs_query.c) ---- */

int sdae_mbs_xi(sdae_mbs_stepper *s, double t, const double *q, const double *v, double *xi) {
  if (!s || !q || !v || !xi) return SDAE_ERR_NULL;
  if (s->sparse) return sdae__mbs_sparse_query_xi(&s->sq, t, q, v, xi);
  return sdae__mbs_query_xi(&s->query, &s->eval, t, q, v, xi);
}

int sdae_mbs_energy(sdae_mbs_stepper *s, double t, const double *q, const double *v, double *E) {
  if (!s || !q || !v || !E) return SDAE_ERR_NULL;
  if (s->sparse) return sdae__mbs_sparse_query_energy(&s->sq, t, q, v, E);
  return sdae__mbs_query_energy(&s->query, &s->eval, t, q, v, E);
}

int sdae_mbs_lambda(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                    double *lambda) {
  if (!s || !q || !v || !lambda) return SDAE_ERR_NULL;
  if (s->sparse) return sdae__mbs_sparse_query_lambda(&s->sq, t, q, v, lambda);
  return sdae__mbs_query_lambda(&s->query, &s->eval, t, q, v, lambda);
}

int sdae_mbs_chart(const sdae_mbs_stepper *s, size_t *dependent) {
  if (!s || !dependent) return SDAE_ERR_NULL;
  if (s->sparse) {
    if (!s->sp.have) return SDAE_ERR_CHART;
    sdae__mbs_sparse_chart(&s->sp, dependent);
    return SDAE_OK;
  }
  if (!s->chart.have) return SDAE_ERR_CHART;
  memcpy(dependent, s->chart.dep, s->n_c * sizeof *dependent);
  return SDAE_OK;
}
