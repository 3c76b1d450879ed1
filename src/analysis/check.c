/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Model consistency against the original DAE: at random points z of a box, with x = Phi^-1(z),
 *
 *   Phi(x) = z,   L_g phi_j(x) = 0 (mu, and every xi but the last of each chain: Prop. 1),
 *   L_f xi_j(x) = xi_{j+1} (the chains of eq. 2),   L_f mu(x) = q0(mu) + Q(xi, mu) xi (eq. 5),
 *
 * each residual relative to the size of the terms it is made of (so finite-difference
 * Jacobians, good to ~1e-10 of those terms, pass a tolerance like 1e-6). */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <gsl/gsl_rng.h>

#include <stabdae/check.h>

#include "core/alloc.h"
#include "core/arena.h"
#include "core/callback.h"
#include "dae/coords.h"
#include "model/stabilizer.h"

typedef struct work {
  const sdae_model *model;
  const sdae_dae *dae;
  double t;
  size_t n, n_xi, n_mu;
  sdae_coords coords; /* Phi's Jacobian (in coords.J) and Phi^-1 */
  double *z, *x, *z2, *F, *G, *q0, *Q, *Qxi, *qn2, *fb;
  unsigned char *chain_last; /* n_xi: 1 for the last coordinate of a chain (L_g may be != 0) */
  gsl_rng rng;               /* mt19937, its state in the block (gsl_rng_alloc would malloc) */
  double *worst_z;           /* the caller's, n values, or NULL */
} work;

/* x = Phi^-1(z): the callback, or Newton from x = z */
static int invert(work *w) {
  memcpy(w->x, w->z, w->n * sizeof *w->x);
  return sdae__coords_invert(&w->coords, w->t, w->z, w->x);
}

static double rel(double residual, double scale) {
  return residual == 0.0 ? 0.0 : fabs(residual) / fmax(scale, DBL_MIN);
}

static void note(sdae_check_report *r, const work *w, int kind, size_t index, double res) {
  if (res > r->residual[kind]) r->residual[kind] = res;
  double worst = r->residual[r->worst_check];
  if (res > worst || (kind == r->worst_check && res == worst)) {
    r->worst_check = kind;
    r->worst_index = index;
    if (w->worst_z) memcpy(w->worst_z, w->z, w->n * sizeof *w->z);
  }
}

/* (J v)_i and the size of its terms, sum_k |J_ik v_k| */
static double row_dot(const work *w, size_t i, const double *v, size_t stride, double *size) {
  double acc = 0.0;
  *size = 0.0;
  for (size_t k = 0; k < w->n; k++) {
    acc += w->coords.J[i * w->n + k] * v[k * stride];
    *size += fabs(w->coords.J[i * w->n + k] * v[k * stride]);
  }
  return acc;
}

static void check_lie(work *w, sdae_check_report *r) {
  size_t n_xi = w->n_xi;
  double size;
  for (size_t i = 0; i < w->n; i++) {
    if (i < n_xi && w->chain_last[i]) continue;
    for (size_t c = 0; c < w->dae->m; c++) {
      double lg = row_dot(w, i, w->G + c, w->dae->m, &size);
      note(r, w, SDAE_CHECK_LG, i, rel(lg, size));
    }
  }
  for (size_t i = 0; i + 1 < n_xi; i++) {
    if (w->chain_last[i]) continue;
    double lf = row_dot(w, i, w->F, 1, &size);
    note(r, w, SDAE_CHECK_CHAIN, i, rel(lf - w->z[i + 1], size + fabs(w->z[i + 1])));
  }
}

/* q0(mu) + Q(xi, mu) xi at z, and the size of its terms in w->fb */
static int normal_form(work *w) {
  const sdae_model *m = w->model;
  const double *xi = w->z, *mu = w->z + w->n_xi;
  int rc = sdae__callback_checked(m->q0(w->t, mu, w->q0, m->params), w->q0, w->n_mu);
  if (rc != SDAE_OK) return rc;
  if (m->Q) {
    rc = sdae__status_of_callback(m->Q(w->t, xi, mu, w->Q, m->params));
    if (rc != SDAE_OK) return rc;
    for (size_t a = 0; a < w->n_mu; a++) {
      w->Qxi[a] = 0.0, w->fb[a] = fabs(w->q0[a]);
      for (size_t i = 0; i < w->n_xi; i++) {
        w->Qxi[a] += w->Q[a * w->n_xi + i] * xi[i];
        w->fb[a] += fabs(w->Q[a * w->n_xi + i] * xi[i]);
      }
    }
  } else {
    rc = sdae__status_of_callback(m->Q_apply(w->t, xi, mu, w->Qxi, w->qn2, m->params));
    if (rc != SDAE_OK) return rc;
    for (size_t a = 0; a < w->n_mu; a++) w->fb[a] = fabs(w->q0[a]) + fabs(w->Qxi[a]);
  }
  return sdae__all_finite(w->Qxi, w->n_mu) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int check_point(work *w, sdae_check_report *r) {
  const sdae_dae *d = w->dae;
  double size = 0.0, res = 0.0;
  size_t at = 0; /* the component of the largest |Phi(x) - z|, the first of equals */
  int rc = invert(w);
  if (rc == SDAE_OK) rc = sdae__callback_checked(d->Phi(w->t, w->x, w->z2, d->params), w->z2, w->n);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < w->n; i++) {
    double e = fabs(w->z2[i] - w->z[i]);
    size = fmax(size, fmax(fabs(w->z[i]), fabs(w->z2[i])));
    if (e > res) res = e, at = i;
  }
  note(r, w, SDAE_CHECK_INVERSE, at, rel(res, size));
  if ((rc = sdae__coords_jacobian(&w->coords, w->t, w->x)) != SDAE_OK) return rc;
  if ((rc = sdae__callback_checked(d->f(w->t, w->x, w->F, d->params), w->F, w->n)) != SDAE_OK)
    return rc;
  if ((rc = sdae__callback_checked(d->g(w->t, w->x, w->G, d->params), w->G, w->n * d->m)) !=
      SDAE_OK)
    return rc;
  check_lie(w, r);
  if ((rc = normal_form(w)) != SDAE_OK) return rc;
  for (size_t a = 0; a < w->n_mu; a++) {
    double lf = row_dot(w, w->n_xi + a, w->F, 1, &size);
    note(r, w, SDAE_CHECK_DYNAMICS, w->n_xi + a, rel(lf - w->q0[a] - w->Qxi[a], size + w->fb[a]));
  }
  return SDAE_OK;
}

/* the last coordinate of each chain; one chain of n_xi without rel_degree (validated) */
static void mark_chains(const sdae_model *m, unsigned char *last) {
  size_t off = 0;
  memset(last, 0, m->n_xi);
  if (!m->rel_degree) {
    last[m->n_xi - 1] = 1;
    return;
  }
  for (size_t c = 0; c < m->n_constraints; c++) {
    off += m->rel_degree[c];
    last[off - 1] = 1;
  }
}

static int validate(const sdae_model *m, const sdae_dae *d, const double *lo, const double *hi,
                    double tol, const sdae_check_report *r) {
  if (!m || !d || !lo || !hi || !r) return SDAE_ERR_NULL;
  if (!m->q0 || (!m->Q && !m->Q_apply) || !d->f || !d->g || !d->Phi) return SDAE_ERR_NULL;
  if (m->n_xi == 0 || m->n_mu == 0 || d->m == 0 || d->n != m->n_xi + m->n_mu) return SDAE_ERR_DIM;
  if (m->rel_degree && sdae__rel_degree_check(m, UINT_MAX) != SDAE_OK) return SDAE_ERR_REL_DEGREE;
  if (!(tol > 0.0) || !isfinite(tol)) return SDAE_ERR_PARAM;
  for (size_t j = 0; j < d->n; j++)
    if (!isfinite(lo[j]) || !isfinite(hi[j]) || lo[j] > hi[j]) return SDAE_ERR_PARAM;
  return SDAE_OK;
}

static int run(work *w, const double *lo, const double *hi, size_t npoints, unsigned long seed,
               sdae_check_report *r) {
  int rc = SDAE_OK;
  gsl_rng_set(&w->rng, seed);
  for (size_t p = 0; p < npoints && rc == SDAE_OK; p++) {
    for (size_t j = 0; j < w->n; j++) w->z[j] = lo[j] + (hi[j] - lo[j]) * gsl_rng_uniform(&w->rng);
    rc = check_point(w, r);
    if (rc == SDAE_OK) r->points++;
  }
  return rc;
}

/* the generator's state and the work arrays, counted or handed out (arena.c) */
static void carve(work *w, sdae_arena *a) {
  size_t n = w->n, n_xi = w->n_xi, n_mu = w->n_mu;
  w->rng.type = gsl_rng_mt19937;
  w->rng.state = sdae__take_array(a, 1, gsl_rng_mt19937->size, _Alignof(max_align_t));
  sdae__coords_carve(&w->coords, w->dae, n_xi, a);
  w->z = sdae__take(a, n, 1), w->x = sdae__take(a, n, 1), w->z2 = sdae__take(a, n, 1);
  w->F = sdae__take(a, n, 1), w->G = sdae__take(a, n, w->dae->m);
  w->q0 = sdae__take(a, n_mu, 1), w->Q = sdae__take(a, n_mu, n_xi);
  w->Qxi = sdae__take(a, n_mu, 1), w->qn2 = sdae__take(a, n_xi, 1);
  w->fb = sdae__take(a, n, 1);
  w->chain_last = sdae__take_array(a, n_xi, 1, 1);
}

/* the block from the allocator, zeroed and carved */
static int take_block(work *w, const sdae_allocator *al, char **block, size_t *bytes) {
  sdae_arena a = {0};
  carve(w, &a);
  if (sdae__arena_bytes(&a, 0, bytes) != SDAE_OK) return SDAE_ERR_OVERFLOW;
  if (!(*block = sdae__alloc(al, *bytes))) return SDAE_ERR_NOMEM;
  memset(*block, 0, *bytes);
  a = (sdae_arena){.base = *block};
  carve(w, &a);
  return SDAE_OK;
}

int sdae_check_model_with(const sdae_model *model, const sdae_dae *dae, double t, const double *lo,
                          const double *hi, size_t npoints, unsigned long seed, double tol,
                          double *worst_z, const sdae_allocator *a, sdae_check_report *r) {
  int rc = validate(model, dae, lo, hi, tol, r);
  size_t bytes;
  char *block;
  work w = {0};
  if (rc != SDAE_OK) return rc;
  if (dae->n > SIZE_MAX / 4) return SDAE_ERR_OVERFLOW; /* keeps LU's 3 n - 2 columns exact */
  w.model = model, w.dae = dae, w.t = t, w.n = dae->n, w.n_xi = model->n_xi;
  w.n_mu = model->n_mu, w.worst_z = worst_z;
  if ((rc = take_block(&w, a, &block, &bytes)) != SDAE_OK) return rc;
  mark_chains(model, w.chain_last);
  memset(r, 0, sizeof *r);
  rc = run(&w, lo, hi, npoints, seed, r);
  r->consistent = rc == SDAE_OK;
  for (int k = 0; k < 4; k++) r->consistent = r->consistent && r->residual[k] <= tol;
  sdae__free(a, block, bytes);
  return rc;
}

int sdae_check_model(const sdae_model *model, const sdae_dae *dae, double t, const double *lo,
                     const double *hi, size_t npoints, unsigned long seed, double tol,
                     double *worst_z, sdae_check_report *r) {
  return sdae_check_model_with(model, dae, t, lo, hi, npoints, seed, tol, worst_z, NULL, r);
}
