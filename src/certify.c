/* Step-size certificates. Theorem 3: scheme 11 drives xi to 0 from a compact box B when
 * T < 2 / max_i sup_B (-k_i) (eq. 14); Theorem 5 keeps the equilibrium's stability for
 * T <= (sqrt(5) - 1)/4 T_bar (scheme 15) and T <= T_bar/2 (scheme 11). The sup is found by a
 * grid over the box and a Nelder-Mead refinement (GSL multimin) from the best grid points, in
 * coordinates z_j = lo_j + (hi_j - lo_j)(1 + sin u_j)/2 that keep every probe inside B. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_multimin.h>

#include "internal.h"

#define CANDIDATES 3 /* grid points refined per gain */

typedef struct search {
  sdae_stepper *s;
  double t;
  const double *lo, *hi;
  size_t dim, n_free, *free; /* the coordinates with lo < hi */
  double *z, *k;             /* dim, n_xi */
  double *best;              /* n_xi x CANDIDATES x (1 + dim): value, then the point */
  size_t i;                  /* the gain being refined */
  size_t evals;
  int status;
} search;

static int evaluate(search *S, const double *z) {
  size_t n_xi = S->s->model.n_xi;
  int rc = sdae_stepper_gains(S->s, S->t, z, z + n_xi, S->k);
  S->evals++;
  if (rc != SDAE_OK && S->status == SDAE_OK) S->status = rc;
  return rc;
}

static double *slot(const search *S, size_t i, size_t c) {
  return S->best + (i * CANDIDATES + c) * (1 + S->dim);
}

/* keeps, for gain i, the CANDIDATES largest values of -k_i seen, in decreasing order */
static void offer(search *S, size_t i, double value, const double *z) {
  size_t c = CANDIDATES;
  while (c > 0 && value > slot(S, i, c - 1)[0]) c--;
  if (c == CANDIDATES) return;
  for (size_t d = CANDIDATES - 1; d > c; d--)
    memcpy(slot(S, i, d), slot(S, i, d - 1), (1 + S->dim) * sizeof(double));
  slot(S, i, c)[0] = value;
  memcpy(slot(S, i, c) + 1, z, S->dim * sizeof(double));
}

static void offer_all(search *S, const double *z) {
  if (evaluate(S, z) != SDAE_OK) return;
  for (size_t i = 0; i < S->s->model.n_xi; i++) offer(S, i, -S->k[i], z);
}

/* every point of the grid: an odometer over the free coordinates */
static void scan_grid(search *S, unsigned grid) {
  size_t *digit = calloc(S->n_free + 1, sizeof *digit);
  if (!digit) {
    S->status = SDAE_ERR_NOMEM;
    return;
  }
  memcpy(S->z, S->lo, S->dim * sizeof(double));
  while (S->status == SDAE_OK) {
    for (size_t f = 0; f < S->n_free; f++) {
      size_t j = S->free[f];
      S->z[j] = S->lo[j] + (S->hi[j] - S->lo[j]) * (double)digit[f] / (double)(grid - 1);
    }
    offer_all(S, S->z);
    size_t f = 0;
    while (f < S->n_free && ++digit[f] == grid) digit[f++] = 0;
    if (f == S->n_free) break;
  }
  free(digit);
}

static void from_u(const search *S, const gsl_vector *u, double *z) {
  memcpy(z, S->lo, S->dim * sizeof(double));
  for (size_t f = 0; f < S->n_free; f++) {
    size_t j = S->free[f];
    z[j] = S->lo[j] + (S->hi[j] - S->lo[j]) * 0.5 * (1.0 + sin(gsl_vector_get(u, f)));
  }
}

/* the minimizer's objective: k_i (so -k_i is maximized); always finite, so GSL never raises */
static double objective(const gsl_vector *u, void *data) {
  search *S = data;
  from_u(S, u, S->z);
  if (evaluate(S, S->z) != SDAE_OK) return 0.0;
  offer(S, S->i, -S->k[S->i], S->z);
  return S->k[S->i];
}

static void refine(search *S, const double *z0, gsl_multimin_fminimizer *mz, gsl_vector *u,
                   gsl_vector *step) {
  gsl_multimin_function fn = {objective, S->n_free, S};
  for (size_t f = 0; f < S->n_free; f++) {
    size_t j = S->free[f];
    double r = 2.0 * (z0[j] - S->lo[j]) / (S->hi[j] - S->lo[j]) - 1.0;
    gsl_vector_set(u, f, asin(fmax(-1.0, fmin(1.0, r))));
    gsl_vector_set(step, f, 0.2);
  }
  gsl_multimin_fminimizer_set(mz, &fn, u, step);
  for (int it = 0; it < 1000 && S->status == SDAE_OK; it++) {
    if (gsl_multimin_fminimizer_iterate(mz) != GSL_SUCCESS) break;
    if (gsl_multimin_test_size(gsl_multimin_fminimizer_size(mz), 1e-12) == GSL_SUCCESS) break;
  }
}

static void refine_all(search *S) {
  gsl_multimin_fminimizer *mz;
  gsl_vector *u, *step;
  double *z0 = malloc(S->dim * sizeof *z0);
  if (S->n_free == 0 || !z0) {
    if (!z0) S->status = SDAE_ERR_NOMEM;
    free(z0);
    return;
  }
  mz = gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, S->n_free);
  u = gsl_vector_alloc(S->n_free);
  step = gsl_vector_alloc(S->n_free);
  if (!mz || !u || !step) S->status = SDAE_ERR_NOMEM;
  for (S->i = 0; S->status == SDAE_OK && S->i < S->s->model.n_xi; S->i++)
    for (size_t c = 0; c < CANDIDATES && S->status == SDAE_OK; c++) {
      if (!isfinite(slot(S, S->i, c)[0])) continue;
      memcpy(z0, slot(S, S->i, c) + 1, S->dim * sizeof *z0); /* offer() may move the slot */
      refine(S, z0, mz, u, step);
    }
  if (mz) gsl_multimin_fminimizer_free(mz);
  if (u) gsl_vector_free(u);
  if (step) gsl_vector_free(step);
  free(z0);
}

static int check_box(size_t dim, const double *lo, const double *hi, size_t *free_idx,
                     size_t *n_free) {
  *n_free = 0;
  for (size_t j = 0; j < dim; j++) {
    if (!isfinite(lo[j]) || !isfinite(hi[j]) || lo[j] > hi[j]) return SDAE_ERR_PARAM;
    if (lo[j] < hi[j]) free_idx[(*n_free)++] = j;
  }
  return SDAE_OK;
}

static void report(const search *S, double *sup_i, double *argmax, sdae_certificate *c) {
  size_t n_xi = S->s->model.n_xi;
  c->sup_neg_k = -INFINITY;
  c->i_max = 0;
  for (size_t i = 0; i < n_xi; i++) {
    const double *b = slot(S, i, 0);
    if (sup_i) sup_i[i] = b[0];
    if (argmax) memcpy(argmax + i * S->dim, b + 1, S->dim * sizeof(double));
    if (b[0] > c->sup_neg_k) c->sup_neg_k = b[0], c->i_max = i;
  }
  c->T_bar = 2.0 / c->sup_neg_k;                              /* eq. 14 */
  c->T_thm5_scheme15 = (sqrt(5.0) - 1.0) / 4.0 * c->T_bar; /* Theorem 5 */
  c->T_thm5_scheme11 = c->T_bar / 2.0;
  c->evaluations = S->evals;
}

int sdae_certify_box(sdae_stepper *s, double t, const double *lo, const double *hi,
                     unsigned grid, double *sup_i, double *argmax, sdae_certificate *c) {
  search S = {0};
  int rc;
  if (!s || !lo || !hi || !c) return SDAE_ERR_NULL;
  if (grid < 2 || !isfinite(t)) return SDAE_ERR_PARAM;
  S.s = s, S.t = t, S.lo = lo, S.hi = hi;
  S.dim = s->model.n_xi + s->model.n_mu;
  S.free = malloc(S.dim * sizeof *S.free);
  S.z = malloc(S.dim * sizeof *S.z);
  S.k = malloc(s->model.n_xi * sizeof *S.k);
  S.best = malloc(s->model.n_xi * CANDIDATES * (1 + S.dim) * sizeof *S.best);
  if (!S.free || !S.z || !S.k || !S.best) {
    rc = SDAE_ERR_NOMEM;
  } else if ((rc = check_box(S.dim, lo, hi, S.free, &S.n_free)) == SDAE_OK) {
    for (size_t i = 0; i < s->model.n_xi * CANDIDATES; i++) S.best[i * (1 + S.dim)] = -INFINITY;
    scan_grid(&S, grid);
    if (S.status == SDAE_OK) refine_all(&S);
    if ((rc = S.status) == SDAE_OK) report(&S, sup_i, argmax, c);
  }
  free(S.free), free(S.z), free(S.k), free(S.best);
  return rc;
}
