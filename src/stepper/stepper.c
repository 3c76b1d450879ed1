/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The stepper: validation, one workspace block (caller's or allocated), and the step of
 * scheme 11 / 15. sdae_step allocates nothing and leaves xi, mu untouched on failure. */
#include <math.h>
#include <stdalign.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/arena.h"
#include "core/callback.h"
#include "model/model.h"
#include "stepper.h"
#include "stepper_impl.h"

void sdae_options_default(sdae_options *o) {
  if (!o) return;
  memset(o, 0, sizeof *o);
  o->scheme = SDAE_SCHEME_SEMI_IMPLICIT;
  o->delta = 1.0;
  o->epsilon = 1.0;
  o->map = sdae_map_euler;
  o->newton_tol = SDAE_NEWTON_TOL;
  o->newton_max_iter = SDAE_NEWTON_MAX_ITER;
  o->stabilizer = SDAE_STAB_PAPER;
  o->baumgarte_alpha[0] = 1.0; /* s^2 + 2 s + 1 = (s + 1)^2 */
  o->baumgarte_alpha[1] = 2.0;
}

static int positive_finite(double v) { return isfinite(v) && v > 0.0; }

int sdae__stepper_validate(const sdae_model *m, const sdae_options *o) {
  const sdae_stabilizer_type *stab;
  int rc;
  if (!m || !o) return SDAE_ERR_NULL;
  if (m->n_xi == 0 || m->n_mu == 0) return SDAE_ERR_DIM;
  if (!m->q0 || (!m->Q && !m->Q_apply)) return SDAE_ERR_NULL;
  if (!m->q0_lsetup != !m->q0_lsolve) return SDAE_ERR_NULL;
  if (o->scheme != SDAE_SCHEME_EXPLICIT && o->scheme != SDAE_SCHEME_SEMI_IMPLICIT)
    return SDAE_ERR_OPTION;
  if (!(stab = sdae__stabilizer_type(o->stabilizer))) return SDAE_ERR_OPTION;
  if (!positive_finite(o->delta) || !positive_finite(o->epsilon)) return SDAE_ERR_PARAM;
  if (!positive_finite(o->newton_tol) || o->newton_max_iter == 0) return SDAE_ERR_PARAM;
  if (!o->map) return SDAE_ERR_MAP;
  if (o->map->needs && (rc = o->map->needs(m)) != SDAE_OK) return rc;
  return stab->validate ? stab->validate(m, o) : SDAE_OK;
}

/* ---- workspace: the struct, then its arrays, one block; each part takes its own ---- */

static void carve(sdae_stepper *s, sdae_arena *a) {
  const sdae_model *m = &s->model;
  const sdae_map_type *map = s->opt.map;
  size_t n_mu = m->n_mu, n_xi = m->n_xi;
  s->Q = m->Q ? sdae__take(a, n_mu, n_xi) : NULL;
  s->Qxi = sdae__take(a, n_mu, 1);
  s->mu_new = sdae__take(a, n_mu, 1);
  s->phi = sdae__take(a, n_mu, 1);
  s->qnorm2 = sdae__take(a, n_xi, 1);
  s->xi_new = sdae__take(a, n_xi, 1);
  s->map.work = sdae__take(a, map->scratch ? map->scratch(m, &s->opt) : 0, 1);
  if (s->stabilizer->carve) s->stabilizer->carve(&s->stab, a);
  if (!sdae__map_uses_newton(map)) return;
  if (sdae__map_model_solves(map, m)) { /* Newton-Krylov on the model's linear solve */
    /* GMRES is exact in n_mu steps: no more are ever needed */
    sdae__newton_carve_krylov(&s->newton, n_mu, n_mu < SDAE_KRYLOV_DIM ? n_mu : SDAE_KRYLOV_DIM,
                              SDAE_KRYLOV_RTOL, s->opt.newton_tol, s->opt.newton_max_iter, a);
    s->map.mid = sdae__take(a, n_mu, 1);
    return;
  }
  sdae__newton_carve(&s->newton, n_mu, sdae__banded(m, &s->opt) ? s->opt.bandwidth : n_mu - 1,
                     s->opt.newton_tol, s->opt.newton_max_iter, a);
}

/* the stepper's parts wired to its model and options, arrays not yet handed out */
static void wire(sdae_stepper *s, const sdae_model *m, const sdae_options *o) {
  memset(s, 0, sizeof *s);
  s->model = *m;
  s->opt = *o;
  s->stabilizer = sdae__stabilizer_type(o->stabilizer);
  s->map.model = &s->model;
  s->map.newton = &s->newton;
  s->stab.model = &s->model;
  s->stab.opt = &s->opt;
}

typedef struct args {
  const sdae_model *m;
  const sdae_options *o;
} args;

/* Bytes for the block, with room to align a caller's block. */
static int measure(const void *p, const sdae_scratch *scratch, size_t *bytes) {
  (void)scratch; /* the sizes follow from the dimensions */
  const args *g = p;
  sdae_stepper probe;
  sdae_arena a = {0};
  int rc = sdae__stepper_validate(g->m, g->o);
  if (rc != SDAE_OK) return rc;
  wire(&probe, g->m, g->o);
  carve(&probe, &a);
  return sdae__block_bytes(&a, sizeof(sdae_stepper), bytes);
}

static int build(void *mem, const void *p, void **obj, sdae_block **block) {
  const args *g = p;
  sdae_arena a;
  sdae_stepper *s = sdae__block_start(mem, sizeof(sdae_stepper), &a);
  wire(s, g->m, g->o);
  carve(s, &a);
  s->stab.qnorm2 = s->qnorm2;
  *obj = s, *block = &s->block;
  return SDAE_OK;
}

static const sdae_block_type stepper_block = {measure, build};

size_t sdae_stepper_size(const sdae_model *m, const sdae_options *o) {
  const args g = {m, o};
  return sdae__block_size(&stepper_block, &g, NULL);
}

int sdae_stepper_init(sdae_stepper **s, void *mem, size_t len, const sdae_model *m,
                      const sdae_options *o) {
  const args g = {m, o};
  void *obj;
  int rc;
  if (!s) return SDAE_ERR_NULL;
  if ((rc = sdae__block_init(&stepper_block, &g, mem, len, &obj)) == SDAE_OK) *s = obj;
  return rc;
}

int sdae_stepper_alloc_with(sdae_stepper **s, const sdae_model *m, const sdae_options *o,
                            const sdae_allocator *a) {
  const args g = {m, o};
  void *obj;
  int rc;
  if (!s) return SDAE_ERR_NULL;
  if ((rc = sdae__block_new(&stepper_block, &g, a, &obj)) == SDAE_OK) *s = obj;
  return rc;
}

int sdae_stepper_alloc(sdae_stepper **s, const sdae_model *m, const sdae_options *o) {
  return sdae_stepper_alloc_with(s, m, o, NULL);
}

void sdae_stepper_free(sdae_stepper *s) {
  if (s) sdae__block_free(&s->block);
}

/* mu+ = mu + T (phi_T(mu, mu+) + Q xi) (eq. 11 and 15, mu row), from the explicit predictor
 * mu + T (phi_T(mu, mu) + Q xi), exact for the explicit maps */
static int mu_update(sdae_stepper *s, double t, double T, const double *mu) {
  const sdae_map_type *map = s->opt.map;
  size_t n = s->model.n_mu;
  int rc = sdae__map_phi(map, &s->map, t, T, mu, mu, s->phi);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) s->mu_new[i] = mu[i] + T * (s->phi[i] + s->Qxi[i]);
  if (map->implicit) rc = sdae__map_solve(map, &s->map, t, T, mu, s->Qxi, s->mu_new);
  return rc;
}

/* the counts of the map and Newton into the statistics, whatever the step's outcome */
static void count(sdae_stepper *s) {
  s->stats.phi_evals += s->map.phi_evals;
  s->stats.newton_iters_last = s->newton.iters; /* the map's own solves too (dg4's stages) */
  s->stats.newton_iters_total += s->newton.iters;
  s->stats.newton_residual_last = s->newton.residual_last;
  s->map.phi_evals = 0;
  s->newton.iters = 0;
}

static int call_status(const sdae_stepper *s, double t, const double *xi, const double *mu) {
  if (!s || !xi || !mu) return SDAE_ERR_NULL;
  if (!isfinite(t)) return SDAE_ERR_PARAM;
  if (!sdae__all_finite(xi, s->model.n_xi) || !sdae__all_finite(mu, s->model.n_mu))
    return SDAE_ERR_STATE;
  return SDAE_OK;
}

static int step(sdae_stepper *s, double t, double T, const double *xi, const double *mu) {
  const sdae_model *m = &s->model;
  int rc;
  if (s->opt.map->begin) s->opt.map->begin(&s->map);
  /* the model's factors are its own, not in the state's bytes: set up at the step's first solve */
  if (sdae__map_model_solves(s->opt.map, m)) sdae__newton_forget(&s->newton);
  rc = sdae__eval_Q(m, s->Q, t, xi, mu, s->Qxi, s->qnorm2);
  if (rc == SDAE_OK) rc = s->stabilizer->xi_update(&s->stab, T, xi, s->xi_new);
  if (rc == SDAE_OK) rc = mu_update(s, t, T, mu);
  if (rc != SDAE_OK) return rc;
  if (!sdae__all_finite(s->xi_new, m->n_xi) || !sdae__all_finite(s->mu_new, m->n_mu))
    return SDAE_ERR_NONFINITE;
  return SDAE_OK;
}

int sdae_step(sdae_stepper *s, double t, double T, double *xi, double *mu) {
  int rc = call_status(s, t, xi, mu);
  if (rc != SDAE_OK) return rc;
  if (!positive_finite(T)) return SDAE_ERR_STEP;
  rc = step(s, t, T, xi, mu);
  count(s);
  if (rc != SDAE_OK) return rc;
  sdae__copy(xi, s->xi_new, s->model.n_xi);
  sdae__copy(mu, s->mu_new, s->model.n_mu);
  s->stats.steps++;
  return SDAE_OK;
}

int sdae_stepper_gains(sdae_stepper *s, double t, const double *xi, const double *mu, double *k) {
  int rc = call_status(s, t, xi, mu);
  if (rc != SDAE_OK) return rc;
  if (!k) return SDAE_ERR_NULL;
  if ((rc = sdae__eval_Q(&s->model, s->Q, t, xi, mu, s->Qxi, s->qnorm2)) != SDAE_OK) return rc;
  sdae__gains(&s->opt, s->qnorm2, s->model.n_xi, k);
  return sdae__all_finite(k, s->model.n_xi) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

const sdae_stats *sdae_stepper_stats(const sdae_stepper *s) { return s ? &s->stats : NULL; }

void sdae_stepper_reset_stats(sdae_stepper *s) {
  if (s) memset(&s->stats, 0, sizeof s->stats);
}

const sdae_model *sdae__stepper_model(const sdae_stepper *s) { return &s->model; }

const sdae_allocator *sdae__stepper_allocator(const sdae_stepper *s) { return &s->block.allocator; }

void sdae__stepper_keep_newton(sdae_stepper *s) {
  if (sdae__map_uses_newton(s->opt.map)) s->newton.keep = 1;
}

void sdae__stepper_newton_forget(sdae_stepper *s) {
  if (sdae__map_uses_newton(s->opt.map)) sdae__newton_forget(&s->newton);
}

/* field by field: the struct's padding is no part of the state */
void sdae__stepper_state(sdae_stepper *s, sdae_bytes *b) {
  sdae_stats *st = &s->stats;
  sdae__bytes(b, &st->steps, sizeof st->steps);
  sdae__bytes(b, &st->newton_iters_last, sizeof st->newton_iters_last);
  sdae__bytes(b, &st->newton_iters_total, sizeof st->newton_iters_total);
  sdae__bytes_doubles(b, &st->newton_residual_last, 1);
  sdae__bytes(b, &st->phi_evals, sizeof st->phi_evals);
  if (sdae__map_uses_newton(s->opt.map)) sdae__newton_state(&s->newton, b);
}

size_t sdae__stepper_state_bytes(const sdae_model *m, const sdae_options *o) {
  sdae_stepper probe;
  sdae_arena a = {0};
  sdae_bytes b = {NULL, NULL, 0};
  wire(&probe, m, o);
  carve(&probe, &a); /* counted: the sizes set, no array handed out */
  sdae__stepper_state(&probe, &b);
  return b.at;
}

int sdae__stepper_state_valid(const sdae_stepper *s) {
  return !sdae__map_uses_newton(s->opt.map) || sdae__newton_state_valid(&s->newton);
}
