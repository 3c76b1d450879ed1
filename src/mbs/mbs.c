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
  /* redundant constraints: rank independent ones among n_c, n_q - rank >= 1 degrees of
   * freedom */
  if (sys->n_c == 0 || sys->rank > sys->n_c || sdae__mbs_rank(sys) >= sys->n_q) return SDAE_ERR_DIM;
  return sdae__mbs_patterns_check(sys);
}

/* the parts' arrays, the step's own, then the normal form's stepper (its bytes counted by its
 * own rule); handed out, what the coordinates analyse of the mechanism when built (the sparse
 * saddle-point system's order and structure) may refuse it */
static int carve(sdae_mbs_stepper *s, sdae_arena *a, size_t inner_bytes) {
  int rc;
  sdae__mbs_eval_carve(&s->eval, a);
  rc = sdae__mbs_coords_carve(&s->coords, a);
  sdae__mbs_model_carve(&s->nf, a);
  sdae__mbs_project_carve(&s->project, a);
  s->xi = sdae__take(a, 2 * s->n_c, 1);
  s->mu = sdae__take(a, 2 * s->n_f, 1);
  s->rollback = sdae__take_array(a, sdae__mbs_parts_bytes(s), 1, 1);
  s->inner = sdae__take_array(a, inner_bytes, 1, alignof(max_align_t));
  return rc;
}

/* the stepper's parts wired to each other, arrays not yet handed out: the coordinates over the
 * sparse back-end for a mechanism with both patterns stepped by an explicit map, else over the
 * dense one */
static int wire(sdae_mbs_stepper *s, const sdae_mbs *sys, const sdae_options *o) {
  int rc, sparse = sdae__mbs_sparse_applies(sys, o);
  memset(s, 0, sizeof *s);
  s->opt = *o;
  /* the noise of the differences (SDAE_MBS_NEWTON_TOL); an invalid tolerance stays, for the
   * validation to refuse */
  double least = sys->jacobian ? SDAE_MBS_NEWTON_TOL : SDAE_MBS_FD_NEWTON_TOL;
  if (o->newton_tol > 0.0 && o->newton_tol < least) s->opt.newton_tol = least;
  s->n_q = sys->n_q;
  s->n_c = sdae__mbs_rank(sys);
  s->n_f = sys->n_q - s->n_c;
  sdae__mbs_eval_init(&s->eval, sys);
  if (sparse)
    rc = sdae__mbs_coords_init(&s->coords, &s->eval, &sdae__mbs_sparse_linalg, &s->sparse, o);
  else
    rc = sdae__mbs_coords_init(&s->coords, &s->eval, &sdae__mbs_dense_linalg, &s->dense, o);
  sdae__mbs_model_init(&s->nf, &s->eval, &s->coords);
  sdae__mbs_project_init(&s->project, &s->eval, &s->opt, sparse ? &s->sparse.ly : NULL,
                         sparse ? &s->sparse.lend : NULL, !sdae__mbs_redundant(&s->eval));
  return rc;
}

typedef struct args {
  const sdae_mbs *sys;
  const sdae_options *o;
} args;

/* the block's bytes (with room to align a caller's block): the parts' (as the coordinates'
 * analysis in scratch sizes them) and the normal form's stepper's */
static int measure(const void *p, const sdae_scratch *scratch, size_t *bytes) {
  const args *g = p;
  sdae_mbs_stepper probe;
  sdae_arena a = {0};
  size_t inner;
  int rc = validate(g->sys, g->o);
  if (rc != SDAE_OK || (rc = wire(&probe, g->sys, g->o)) != SDAE_OK) return rc;
  if ((rc = sdae__stepper_validate(&probe.nf.model, &probe.opt)) != SDAE_OK) return rc;
  if ((inner = sdae_stepper_size(&probe.nf.model, &probe.opt)) == 0) return SDAE_ERR_OVERFLOW;
  if ((rc = sdae__mbs_coords_analyse(&probe.coords, scratch)) != SDAE_OK) return rc;
  carve(&probe, &a, inner);
  return sdae__block_bytes(&a, sizeof(sdae_mbs_stepper), bytes);
}

/* the parts wired and carved, then the normal form's stepper in its part of the block; what
 * the coordinates analyse when built may refuse the mechanism */
static int build(void *mem, const void *p, void **obj, sdae_block **block) {
  const args *g = p;
  sdae_arena a;
  sdae_mbs_stepper *s = sdae__block_start(mem, sizeof(sdae_mbs_stepper), &a);
  size_t inner;
  void *inner_mem;
  int rc = wire(s, g->sys, g->o);
  if (rc != SDAE_OK) return rc;
  inner = sdae_stepper_size(&s->nf.model, &s->opt); /* measured: not 0 */
  if ((rc = carve(s, &a, inner)) != SDAE_OK) return rc;
  inner_mem = s->inner;
  /* measured with the same model and options: cannot fail */
  sdae_stepper_init(&s->inner, inner_mem, inner, &s->nf.model, &s->opt);
  sdae__stepper_keep_newton(s->inner); /* each residual a Phi^-1: the matrix is kept */
  *obj = s, *block = &s->block;
  return SDAE_OK;
}

static const sdae_block_type mbs_block = {measure, build};

size_t sdae_mbs_stepper_size_with(const sdae_mbs *sys, const sdae_options *o,
                                  const sdae_allocator *a) {
  const args g = {sys, o};
  return sdae__block_size(&mbs_block, &g, a);
}

size_t sdae_mbs_stepper_size(const sdae_mbs *sys, const sdae_options *o) {
  return sdae_mbs_stepper_size_with(sys, o, NULL);
}

int sdae_mbs_stepper_init(sdae_mbs_stepper **s, void *mem, size_t len, const sdae_mbs *sys,
                          const sdae_options *o) {
  const args g = {sys, o};
  void *obj;
  int rc;
  if (!s) return SDAE_ERR_NULL;
  if ((rc = sdae__block_init(&mbs_block, &g, mem, len, &obj)) == SDAE_OK) *s = obj;
  return rc;
}

int sdae_mbs_stepper_alloc_with(sdae_mbs_stepper **s, const sdae_mbs *sys, const sdae_options *o,
                                const sdae_allocator *a) {
  const args g = {sys, o};
  void *obj;
  int rc;
  if (!s) return SDAE_ERR_NULL;
  if ((rc = sdae__block_new(&mbs_block, &g, a, &obj)) == SDAE_OK) *s = obj;
  return rc;
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
  s->stats.chart_measure = s->coords.linalg->measure(s->coords.la);
}

/* the normal form's step; a failing callback of it reports the front-end's own status */
static int normal_step(sdae_mbs_stepper *s, double t, double T) {
  int rc = sdae_step(s->inner, t, T, s->xi, s->mu);
  if ((rc == SDAE_ERR_CALLBACK_FATAL || rc == SDAE_ERR_CALLBACK_RECOVERABLE) &&
      s->nf.status != SDAE_OK)
    rc = s->nf.status;
  return rc;
}

/* (q, v) -> one start of the coordinates (the chart, the best one with force_best; xi, mu) ->
 * one step -> Phi^-1 at t + T. What the normal form kept (q0 at a (t, mu)) came from an
 * earlier start, and after a chart switch from another chart, as the Newton matrix its stepper
 * keeps (a function of mu). A start near a singular configuration stops there with *project
 * set: the step is the projection's (mbs_project.h). */
static int try_step(sdae_mbs_stepper *s, double t, double T, const double *q, const double *v,
                    int force_best, sdae_mbs_start *st, int *project) {
  int rc;
  s->nf.status = SDAE_OK;
  sdae__mbs_model_forget(&s->nf);
  rc = sdae__mbs_coords_start(&s->coords, t, q, v, force_best, st);
  if ((*project = sdae__mbs_project_wanted(&s->project, rc, st->choice.independence)) ||
      rc != SDAE_OK)
    return rc;
  if (st->choice.switched) sdae__stepper_newton_forget(s->inner);
  if ((rc = normal_step(s, t, T)) != SDAE_OK) return rc;
  return sdae__mbs_phi_inv_state(&s->coords, t + T, s->xi, s->mu);
}

/* the statistics of a step that succeeded: the one place they are counted */
static void commit(sdae_mbs_stepper *s, const sdae_mbs_start *st) {
  s->stats.phi_inv_iters += s->coords.phi_inv_iters;
  s->stats.chart_switches += (unsigned long)st->choice.switched;
  s->stats.row_switches += (unsigned long)st->rows_switched;
}

/* the projection step in (q, v) from the parts as they were before the start (the chart
 * unchanged); the normal form's Newton matrix, of a mu steps ago, is not kept */
static int projection_step(sdae_mbs_stepper *s, double t, double T, double *q, double *v) {
  int rc;
  sdae__mbs_rollback(s);
  if ((rc = sdae__mbs_project_step(&s->project, t, T, q, v)) != SDAE_OK) return rc;
  sdae__stepper_newton_forget(s->inner);
  s->stats.projected_steps++;
  return SDAE_OK;
}

int sdae_mbs_step(sdae_mbs_stepper *s, double t, double T, double *q, double *v) {
  sdae_mbs_start st = {0};
  int rc, project;
  double seen;
  if (!s || !q || !v) return SDAE_ERR_NULL;
  if (!(isfinite(T) && T > 0.0)) return SDAE_ERR_STEP;
  if ((rc = sdae__mbs_state_ok(&s->eval, t, q, v)) != SDAE_OK) return rc;
  st.xi = s->xi, st.mu = s->mu, st.floor = s->nf.floor;
  sdae__mbs_rollback_save(s);
  rc = try_step(s, t, T, q, v, 0, &st, &project);
  seen = st.choice.independence;
  if (!project && rc == SDAE_ERR_PHI_INV && st.choice.kept) {
    /* the chart kept by hysteresis folds within the step: once more in the best one, counted
     * as the one step it is (the first try's work is not kept, as a failed step's is not) */
    sdae__mbs_rollback(s);
    st.choice.switched = st.choice.kept = st.rows_switched = 0;
    rc = try_step(s, t, T, q, v, 1, &st, &project);
  }
  if (project) {
    rc = projection_step(s, t, T, q, v);
  } else if (rc == SDAE_OK) {
    sdae__mbs_coords_point(&s->coords, q, v);
    commit(s, &st);
  }
  if (rc == SDAE_OK)
    sdae__mbs_project_seen(&s->project, seen);
  else
    sdae__mbs_rollback(s);
  sdae__mbs_stepper_gather(s);
  return rc;
}

/* ---- integrate ---- */

static int step(void *s, double t, double T, double *q, double *v) {
  return sdae_mbs_step(s, t, T, q, v);
}

int sdae_mbs_integrate(sdae_mbs_stepper *s, double t0, double T, size_t nsteps, size_t every,
                       double *q, double *v, sdae_mbs_observer obs, void *data,
                       size_t *steps_done) {
  return sdae__run(s, step, t0, T, nsteps, every, q, v, obs, data, steps_done);
}

const sdae_mbs_stats *sdae_mbs_stepper_stats(const sdae_mbs_stepper *s) {
  return s ? &s->stats : NULL;
}

void sdae_mbs_stepper_reset_stats(sdae_mbs_stepper *s) {
  if (!s) return;
  s->stats.chart_switches = 0; /* the counters; the chart's measure is the current chart's */
  s->stats.row_switches = 0;
  s->stats.phi_inv_iters = 0;
  s->stats.projected_steps = 0;
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
  return s->coords.linalg->query_xi(s->coords.la, t, q, v, xi);
}

int sdae_mbs_energy(sdae_mbs_stepper *s, double t, const double *q, const double *v, double *E) {
  if (!s || !q || !v || !E) return SDAE_ERR_NULL;
  return s->coords.linalg->query_energy(s->coords.la, t, q, v, E);
}

int sdae_mbs_lambda(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                    double *lambda) {
  if (!s || !q || !v || !lambda) return SDAE_ERR_NULL;
  return s->coords.linalg->query_lambda(s->coords.la, t, q, v, lambda);
}

int sdae_mbs_chart(const sdae_mbs_stepper *s, size_t *dependent) {
  if (!s || !dependent) return SDAE_ERR_NULL;
  return s->coords.linalg->chart(s->coords.la, dependent);
}
