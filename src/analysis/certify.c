/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Step-size certificates. Theorem 3: scheme 11 drives xi to 0 from a compact box B when
 * T < 2 / max_i sup_B (-k_i) (eq. 14); Theorem 5 keeps the equilibrium's stability for
 * T <= (sqrt(5) - 1)/4 T_bar (scheme 15) and T <= T_bar/2 (scheme 11). The sup is found by a
 * grid over the box and a Nelder-Mead refinement (src/core/simplex.c) from the best grid points, in
 * coordinates z_j = lo_j + (hi_j - lo_j)(1 + sin u_j)/2 that keep every probe inside B. All the
 * search's memory is one block from the stepper's allocator. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/alloc.h"
#include "core/arena.h"
#include "core/simplex.h"
#include "stepper/stepper.h"

#define CANDIDATES 3     /* grid points refined per gain */
#define SIMPLEX_STEP 0.2 /* the first simplex: u and u + 0.2 e_j, in the sin-mapped coordinates */
#define SIMPLEX_SIZE 1e-12
#define SIMPLEX_ITER 1000

typedef struct search {
  sdae_stepper *s;
  size_t n_xi; /* the stepper's model's */
  double t;
  const double *lo, *hi;
  size_t dim, n_free, *free; /* the coordinates with lo < hi */
  size_t *digit;             /* n_free + 1: the grid's odometer */
  double *z, *k, *z0;        /* dim, n_xi, CANDIDATES x dim: the starts of the refinements */
  double *best;              /* n_xi x CANDIDATES x (1 + dim): value, then the point */
  double *u, *simplex;       /* n_free, sdae__simplex_work(n_free) */
  size_t i;                  /* the gain being refined */
  size_t evals;
  int status;
} search;

static int evaluate(search *S, const double *z) {
  size_t n_xi = S->n_xi;
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
  for (size_t i = 0; i < S->n_xi; i++) offer(S, i, -S->k[i], z);
}

/* every point of the grid: an odometer over the free coordinates */
static void scan_grid(search *S, unsigned grid) {
  size_t *digit = S->digit;
  memset(digit, 0, (S->n_free + 1) * sizeof *digit);
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
}

static void from_u(const search *S, const double *u, double *z) {
  memcpy(z, S->lo, S->dim * sizeof(double));
  for (size_t f = 0; f < S->n_free; f++) {
    size_t j = S->free[f];
    z[j] = S->lo[j] + (S->hi[j] - S->lo[j]) * 0.5 * (1.0 + sin(u[f]));
  }
}

/* the minimizer's objective: k_i (so -k_i is maximized); a failed gain stops the search */
static int objective(const double *u, double *value, void *data) {
  search *S = data;
  int rc;
  from_u(S, u, S->z);
  if ((rc = evaluate(S, S->z)) != SDAE_OK) return rc;
  offer(S, S->i, -S->k[S->i], S->z);
  *value = S->k[S->i];
  return 0;
}

static void refine(search *S, const double *z0) {
  for (size_t f = 0; f < S->n_free; f++) {
    size_t j = S->free[f];
    double r = 2.0 * (z0[j] - S->lo[j]) / (S->hi[j] - S->lo[j]) - 1.0;
    S->u[f] = asin(fmax(-1.0, fmin(1.0, r)));
  }
  /* a failure is in S->status already */
  (void)sdae__simplex_minimize(objective, S, S->n_free, S->u, SIMPLEX_STEP, SIMPLEX_SIZE,
                               SIMPLEX_ITER, S->simplex);
}

/* from each of the grid's best points for gain i, copied first: the refinements offer their
 * own points and would push the later starts out of the slots */
static void refine_all(search *S) {
  if (S->n_free == 0) return;
  for (S->i = 0; S->status == SDAE_OK && S->i < S->n_xi; S->i++) {
    size_t starts = 0;
    for (size_t c = 0; c < CANDIDATES; c++)
      if (isfinite(slot(S, S->i, c)[0]))
        memcpy(S->z0 + starts++ * S->dim, slot(S, S->i, c) + 1, S->dim * sizeof *S->z0);
    for (size_t c = 0; c < starts && S->status == SDAE_OK; c++) refine(S, S->z0 + c * S->dim);
  }
}

/* SDAE_OK and the number of free coordinates (lo < hi), or SDAE_ERR_PARAM */
static int check_box(size_t dim, const double *lo, const double *hi, size_t *n_free) {
  *n_free = 0;
  for (size_t j = 0; j < dim; j++) {
    if (!isfinite(lo[j]) || !isfinite(hi[j]) || lo[j] > hi[j]) return SDAE_ERR_PARAM;
    if (lo[j] < hi[j]) (*n_free)++;
  }
  return SDAE_OK;
}

/* the search's arrays, counted or handed out (arena.c) */
static void carve(search *S, sdae_arena *a) {
  size_t n_xi = S->n_xi;
  S->z = sdae__take(a, S->dim, 1);
  S->z0 = sdae__take(a, CANDIDATES, S->dim);
  S->k = sdae__take(a, n_xi, 1);
  S->best = sdae__take(a, n_xi * CANDIDATES, 1 + S->dim);
  S->u = sdae__take(a, S->n_free, 1);
  S->simplex = sdae__take(a, S->n_free > 0 ? sdae__simplex_work(S->n_free) : 0, 1);
  S->free = sdae__take_array(a, S->n_free, sizeof(size_t), _Alignof(size_t));
  S->digit = sdae__take_array(a, S->n_free + 1, sizeof(size_t), _Alignof(size_t));
}

/* the block from the stepper's allocator, carved; the free coordinates listed */
static int take_block(search *S, void **block, size_t *bytes) {
  sdae_arena a = {0};
  carve(S, &a);
  if (sdae__arena_bytes(&a, 0, bytes) != SDAE_OK) return SDAE_ERR_OVERFLOW;
  if (!(*block = sdae__alloc(sdae__stepper_allocator(S->s), *bytes))) return SDAE_ERR_NOMEM;
  a = (sdae_arena){.base = *block};
  carve(S, &a);
  for (size_t j = 0, f = 0; j < S->dim; j++)
    if (S->lo[j] < S->hi[j]) S->free[f++] = j;
  return SDAE_OK;
}

static void report(const search *S, double *sup_i, double *argmax, sdae_certificate *c) {
  size_t n_xi = S->n_xi;
  c->sup_neg_k = -INFINITY;
  c->i_max = 0;
  for (size_t i = 0; i < n_xi; i++) {
    const double *b = slot(S, i, 0);
    if (sup_i) sup_i[i] = b[0];
    if (argmax) memcpy(argmax + i * S->dim, b + 1, S->dim * sizeof(double));
    if (b[0] > c->sup_neg_k) c->sup_neg_k = b[0], c->i_max = i;
  }
  c->T_bar = 2.0 / c->sup_neg_k;                           /* eq. 14 */
  c->T_thm5_scheme15 = (sqrt(5.0) - 1.0) / 4.0 * c->T_bar; /* Theorem 5 */
  c->T_thm5_scheme11 = c->T_bar / 2.0;
  c->evaluations = S->evals;
}

int sdae_certify_box(sdae_stepper *s, double t, const double *lo, const double *hi, unsigned grid,
                     double *sup_i, double *argmax, sdae_certificate *c) {
  search S = {0};
  size_t bytes;
  void *block;
  int rc;
  if (!s || !lo || !hi || !c) return SDAE_ERR_NULL;
  if (grid < 2 || !isfinite(t)) return SDAE_ERR_PARAM;
  S.s = s, S.t = t, S.lo = lo, S.hi = hi;
  S.n_xi = sdae__stepper_model(s)->n_xi;
  S.dim = S.n_xi + sdae__stepper_model(s)->n_mu;
  if ((rc = check_box(S.dim, lo, hi, &S.n_free)) != SDAE_OK) return rc;
  if ((rc = take_block(&S, &block, &bytes)) != SDAE_OK) return rc;
  for (size_t i = 0; i < S.n_xi * CANDIDATES; i++) S.best[i * (1 + S.dim)] = -INFINITY;
  scan_grid(&S, grid);
  if (S.status == SDAE_OK) refine_all(&S);
  if ((rc = S.status) == SDAE_OK) report(&S, sup_i, argmax, c);
  sdae__free(sdae__stepper_allocator(s), block, bytes);
  return rc;
}
