/* The stepper: validation, one workspace block (caller's or malloc'ed), and the step of
 * scheme 11 / 15. sdae_step allocates nothing and leaves xi, mu untouched on failure. */
#include <math.h>
#include <stdalign.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "alloc.h"
#include "internal.h"

void sdae_options_default(sdae_options *o) {
  if (!o) return;
  memset(o, 0, sizeof *o);
  o->scheme = SDAE_SCHEME_SEMI_IMPLICIT;
  o->delta = 1.0;
  o->epsilon = 1.0;
  o->map = sdae_map_euler;
  o->newton_tol = 1e-14;
  o->newton_max_iter = 20;
  o->stabilizer = SDAE_STAB_PAPER;
  o->baumgarte_alpha[0] = 1.0; /* s^2 + 2 s + 1 = (s + 1)^2 */
  o->baumgarte_alpha[1] = 2.0;
}

const char *sdae_map_name(const sdae_map_type *map) { return map ? map->name : "(none)"; }

static int positive_finite(double v) { return isfinite(v) && v > 0.0; }

static int validate(const sdae_model *m, const sdae_options *o) {
  int rc;
  if (!m || !o) return SDAE_ERR_NULL;
  if (m->n_xi == 0 || m->n_mu == 0) return SDAE_ERR_DIM;
  if (!m->q0 || (!m->Q && !m->Q_apply)) return SDAE_ERR_NULL;
  if (o->scheme != SDAE_SCHEME_EXPLICIT && o->scheme != SDAE_SCHEME_SEMI_IMPLICIT)
    return SDAE_ERR_OPTION;
  if (!positive_finite(o->delta) || !positive_finite(o->epsilon)) return SDAE_ERR_PARAM;
  if (!positive_finite(o->newton_tol) || o->newton_max_iter == 0) return SDAE_ERR_PARAM;
  if (!o->map) return SDAE_ERR_MAP;
  if ((rc = o->map->check(m, o)) != SDAE_OK) return rc;
  return sdae__stabilizer_check(m, o);
}

/* ---- workspace: [struct][doubles][unsigned pivots], one block ---- */

/* One walk over the arrays serves twice: with no base it only counts (overflow-checked) for
 * sdae_stepper_size; with a base it hands out the pointers. */
typedef struct arena {
  double *dbase;
  unsigned *ubase;
  size_t nd, nu;
  int overflow;
} arena;

static int add_ok(size_t *acc, size_t a) {
  if (a > SIZE_MAX - *acc) return 0;
  *acc += a;
  return 1;
}

static int mul_ok(size_t a, size_t b, size_t *out) {
  if (a != 0 && b > SIZE_MAX / a) return 0;
  *out = a * b;
  return 1;
}

static double *take(arena *a, size_t n1, size_t n2) {
  size_t n;
  if (!mul_ok(n1, n2, &n) || !add_ok(&a->nd, n)) {
    a->overflow = 1;
    return NULL;
  }
  return a->dbase ? a->dbase + (a->nd - n) : NULL;
}

static unsigned *take_pivots(arena *a, size_t n) {
  if (!add_ok(&a->nu, n)) {
    a->overflow = 1;
    return NULL;
  }
  return a->ubase ? a->ubase + (a->nu - n) : NULL;
}

/* the band Newton factors: the model's, or all of it (dense) */
static size_t newton_band(const sdae_model *m) {
  return sdae__banded(m) ? m->bandwidth : m->n_mu - 1;
}

static void carve(sdae_stepper *s, arena *a) {
  size_t n_mu = s->model.n_mu, n_xi = s->model.n_xi, r = SDAE_MAX_REL_DEGREE;
  s->Q = s->model.Q ? take(a, n_mu, n_xi) : NULL;
  s->Qxi = take(a, n_mu, 1);
  s->mu_new = take(a, n_mu, 1);
  s->phi = take(a, n_mu, 1);
  s->qnorm2 = take(a, n_xi, 1);
  s->k = take(a, n_xi, 1);
  s->xi_new = take(a, n_xi, 1);
  s->map_work = take(a, s->opt.map->scratch(&s->model, &s->opt), 1);
  s->blk = take(a, r, r);
  s->blk_LU = take(a, r, sdae__lu_band_cols(r - 1, r - 1));
  s->blk_piv = take_pivots(a, r);
  if (!s->opt.map->uses_newton) return;
  s->R = take(a, n_mu, 1);
  s->dy = take(a, n_mu, 1);
  s->fd_y = take(a, n_mu, 1);
  s->fd_plus = take(a, n_mu, 1);
  s->fd_minus = take(a, n_mu, 1);
  s->J = s->band == n_mu - 1 ? take(a, n_mu, n_mu) : NULL; /* dense: analytic Jacobians */
  s->LU = take(a, n_mu, sdae__lu_band_cols(s->band, s->band));
  s->piv = take_pivots(a, n_mu);
}

static size_t round_up(size_t v, size_t a) { return (v + a - 1) / a * a; }

static size_t header_bytes(void) { return round_up(sizeof(sdae_stepper), alignof(max_align_t)); }

/* Bytes for the block, with room to align a caller's block. */
static int measure(const sdae_model *m, const sdae_options *o, size_t *bytes) {
  sdae_stepper probe;
  arena a = {0};
  size_t db, ub;
  memset(&probe, 0, sizeof probe);
  probe.model = *m;
  probe.opt = *o;
  probe.band = newton_band(m);
  carve(&probe, &a);
  *bytes = header_bytes() + alignof(max_align_t) - 1;
  if (a.overflow || !mul_ok(a.nd, sizeof(double), &db) || !add_ok(bytes, db) ||
      !mul_ok(a.nu, sizeof(unsigned), &ub) || !add_ok(bytes, ub))
    return SDAE_ERR_OVERFLOW;
  return SDAE_OK;
}

size_t sdae_stepper_size(const sdae_model *m, const sdae_options *o) {
  size_t bytes;
  if (validate(m, o) != SDAE_OK || measure(m, o, &bytes) != SDAE_OK) return 0;
  return bytes;
}

static sdae_stepper *build(void *mem, const sdae_model *m, const sdae_options *o) {
  uintptr_t al = alignof(max_align_t), p = ((uintptr_t)mem + al - 1) / al * al;
  sdae_stepper *s = (sdae_stepper *)p;
  arena count = {0}, a = {0};
  memset(s, 0, sizeof *s);
  s->model = *m;
  s->opt = *o;
  s->band = newton_band(m);
  carve(s, &count);
  a.dbase = (double *)((char *)s + header_bytes());
  a.ubase = (unsigned *)(a.dbase + count.nd);
  carve(s, &a);
  return s;
}

int sdae_stepper_init(sdae_stepper **s, void *mem, size_t len, const sdae_model *m,
                      const sdae_options *o) {
  size_t bytes;
  int rc;
  if (!s || !mem) return SDAE_ERR_NULL;
  if ((rc = validate(m, o)) != SDAE_OK) return rc;
  if ((rc = measure(m, o, &bytes)) != SDAE_OK) return rc;
  if (len < bytes) return SDAE_ERR_BUFFER;
  *s = build(mem, m, o);
  return SDAE_OK;
}

int sdae_stepper_alloc_with(sdae_stepper **s, const sdae_model *m, const sdae_options *o,
                            const sdae_allocator *a) {
  size_t bytes;
  void *mem;
  int rc;
  if (!s) return SDAE_ERR_NULL;
  if ((rc = validate(m, o)) != SDAE_OK) return rc;
  if ((rc = measure(m, o, &bytes)) != SDAE_OK) return rc;
  if (!(mem = sdae__alloc(a, bytes))) return SDAE_ERR_NOMEM;
  *s = build(mem, m, o);
  (*s)->block = mem;
  (*s)->block_bytes = bytes;
  if (a) (*s)->allocator = *a;
  return SDAE_OK;
}

int sdae_stepper_alloc(sdae_stepper **s, const sdae_model *m, const sdae_options *o) {
  return sdae_stepper_alloc_with(s, m, o, NULL);
}

void sdae_stepper_free(sdae_stepper *s) {
  /* block is NULL for a stepper in the caller's memory */
  if (s) sdae__free(&s->allocator, s->block, s->block_bytes);
}

/* mu+ = mu + T (phi_T(mu, mu+) + Q xi) (eq. 11 and 15, mu row), from the explicit predictor
 * mu + T (phi_T(mu, mu) + Q xi), exact for the explicit maps */
static int mu_update(sdae_stepper *s, double t, double T, const double *mu) {
  size_t n = s->model.n_mu;
  int rc;
  s->stats.newton_iters_last = 0; /* counts the map's own solves too (dg4's stages) */
  rc = s->opt.map->phi(s, t, T, mu, mu, s->phi);
  s->stats.phi_evals++;
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) s->mu_new[i] = mu[i] + T * (s->phi[i] + s->Qxi[i]);
  if (s->opt.map->implicit) rc = sdae__newton(s, s->opt.map, t, T, mu, s->Qxi, s->mu_new);
  s->stats.newton_iters_total += s->stats.newton_iters_last;
  return rc;
}

static int check_call(const sdae_stepper *s, double t, const double *xi, const double *mu) {
  if (!s || !xi || !mu) return SDAE_ERR_NULL;
  if (!isfinite(t)) return SDAE_ERR_PARAM;
  if (!sdae__all_finite(xi, s->model.n_xi) || !sdae__all_finite(mu, s->model.n_mu))
    return SDAE_ERR_STATE;
  return SDAE_OK;
}

int sdae_step(sdae_stepper *s, double t, double T, double *xi, double *mu) {
  int rc = check_call(s, t, xi, mu);
  if (rc != SDAE_OK) return rc;
  if (!positive_finite(T)) return SDAE_ERR_STEP;
  if ((rc = sdae__eval_Q(s, t, xi, mu)) != SDAE_OK) return rc;
  if ((rc = sdae__xi_update(s, T, xi)) != SDAE_OK) return rc;
  if ((rc = mu_update(s, t, T, mu)) != SDAE_OK) return rc;
  if (!sdae__all_finite(s->xi_new, s->model.n_xi) || !sdae__all_finite(s->mu_new, s->model.n_mu))
    return SDAE_ERR_NONFINITE;
  sdae__copy(xi, s->xi_new, s->model.n_xi);
  sdae__copy(mu, s->mu_new, s->model.n_mu);
  s->stats.steps++;
  return SDAE_OK;
}

int sdae_stepper_gains(sdae_stepper *s, double t, const double *xi, const double *mu,
                       double *k) {
  int rc = check_call(s, t, xi, mu);
  if (rc != SDAE_OK) return rc;
  if (!k) return SDAE_ERR_NULL;
  if ((rc = sdae__eval_Q(s, t, xi, mu)) != SDAE_OK) return rc;
  sdae__gains(s, k);
  return sdae__all_finite(k, s->model.n_xi) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

const sdae_stats *sdae_stepper_stats(const sdae_stepper *s) { return s ? &s->stats : NULL; }

void sdae_stepper_reset_stats(sdae_stepper *s) {
  if (s) memset(&s->stats, 0, sizeof s->stats);
}
