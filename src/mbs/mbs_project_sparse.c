/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The projection's linear algebra through the patterns (mbs_project_linalg.h): the
 * saddle-point system with its constraints softened, on the sparse back-end's analysis of K.
 * Softened by rho = floor^2 (Tikhonov's regularization: the multiplier of a row of sine s to
 * the others answers s^2 / (s^2 + rho) of its part), then refined twice against the exact
 * system (iterated Tikhonov, an augmented Lagrangian's iteration: (rho / (s^2 + rho))^3 of a
 * row's part left), so that the rows well above the floor are kept to rounding and those below
 * it set aside, as the dense back-end's QR drops them; no pivot then falls below rho of its
 * scale, whatever the rank of G. The step it replaces lends it K's values, the factorization
 * and the vectors (sdae_mbs_sparse_lent): a projection step is taken between two of its
 * solves, never inside one, and the step after it factors K afresh (the coordinates reuse
 * their factors at a chart step's end alone: its start cleared that mark, which the roll-back
 * before the projection does not restore). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "mbs_project_linalg.h"

#define REFINEMENTS 2

void sdae__mbs_project_sparse_init(sdae_mbs_project_sparse *s, sdae_mbs_eval *eval,
                                   const sdae_mbs_sparse_layout *ly,
                                   const sdae_mbs_sparse_lent *lent) {
  memset(s, 0, sizeof *s);
  s->eval = eval;
  s->ly = ly;
  s->lent = lent;
  s->n_q = eval->n_q;
  s->n_c = eval->n_c;
  s->n_k = s->n_q + s->n_c;
}

static void carve(void *p, sdae_arena *a) {
  sdae_mbs_project_sparse *s = p;
  const sdae_mbs *sys = &s->eval->sys;
  s->G = sdae__take(a, sys->jacobian_pattern->nnz, 1);
  s->M = sdae__take(a, sys->mass_pattern->nnz, 1);
  s->delta = sdae__take(a, s->n_c, 1);
  s->Gd = sdae__take(a, sys->jacobian_pattern->nnz, 1);
  s->ctd = sdae__take(a, s->n_c, 1);
}

/* rho = floor^2, but above the factorization's rounding test (n eps of a pivot's scale), so
 * that a rank lost to rounding is softened too, not refused */
static int refactor(void *p, double floor) {
  sdae_mbs_project_sparse *s = p;
  const sdae_mbs_sparse_lent *w = s->lent;
  double rho = fmax(floor * floor, 4.0 * (double)s->n_k * DBL_EPSILON);
  sdae__mbs_sparse_kkt_soften(s->ly, s->M, s->G, rho, w->K, s->delta);
  return sdae__sparse_ldl_factor(w->kkt, w->K);
}

static int factor(void *p, double t, const double *q, double floor) {
  sdae_mbs_project_sparse *s = p;
  int rc;
  if ((rc = sdae__mbs_jacobian_values(s->eval, t, q, s->G)) != SDAE_OK ||
      (rc = sdae__mbs_mass_values(s->eval, t, q, s->M)) != SDAE_OK ||
      (rc = sdae__mbs_sparse_mass_symmetric(s->ly, s->M)) != SDAE_OK)
    return rc;
  return refactor(p, floor);
}

/* res = rhs - K sol, K the exact system: the softened one's product with the softening added
 * back on the multipliers */
static void residual(const sdae_mbs_project_sparse *s) {
  const sdae_mbs_sparse_lent *w = s->lent;
  const SuiteSparse_long *start = s->ly->ksym.Ap, *col = s->ly->ksym.Ai;
  for (size_t i = 0; i < s->n_k; i++) {
    double acc = w->rhs[i];
    for (SuiteSparse_long e = start[i]; e < start[i + 1]; e++) acc -= w->K[e] * w->sol[col[e]];
    w->res[i] = acc;
  }
  for (size_t j = 0; j < s->n_c; j++) w->res[s->n_q + j] -= s->delta[j] * w->sol[s->n_q + j];
}

static void solve(void *p, const double *F, const double *g, double *x) {
  sdae_mbs_project_sparse *s = p;
  const sdae_mbs_sparse_lent *w = s->lent;
  size_t n_q = s->n_q;
  for (size_t i = 0; i < n_q; i++) w->rhs[i] = F ? F[i] : 0.0;
  for (size_t j = 0; j < s->n_c; j++) w->rhs[n_q + j] = -g[j];
  sdae__sparse_ldl_solve(w->kkt, w->rhs, w->sol);
  for (int it = 0; it < REFINEMENTS; it++) {
    residual(s);
    sdae__sparse_ldl_solve(w->kkt, w->res, w->dx);
    for (size_t i = 0; i < s->n_k; i++) w->sol[i] += w->dx[i];
  }
  memcpy(x, w->sol, n_q * sizeof *x);
}

static int gamma_at(void *p, double t, const double *q, const double *v, double *gamma) {
  sdae_mbs_project_sparse *s = p;
  int rc;
  if ((rc = sdae__mbs_jacobian_dot_values(s->eval, t, q, v, s->Gd)) != SDAE_OK ||
      (rc = sdae__mbs_ct_dot(s->eval, t, q, v, s->ctd)) != SDAE_OK)
    return rc;
  sdae__mbs_sparse_g_times(s->ly, s->Gd, v, s->ctd, gamma);
  return SDAE_OK;
}

static void g_times(const void *p, const double *x, const double *add, double *out) {
  const sdae_mbs_project_sparse *s = p;
  sdae__mbs_sparse_g_times(s->ly, s->G, x, add, out);
}

static double row_size(const void *p, size_t j) {
  const sdae_mbs_project_sparse *s = p;
  const sdae_pattern *G = s->ly->Gp;
  double g = 0.0;
  for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++) g += fabs(s->G[e]);
  return g;
}

const sdae_mbs_project_linalg sdae__mbs_project_sparse_linalg = {
    .carve = carve,
    .factor = factor,
    .refactor = refactor,
    .solve = solve,
    .gamma = gamma_at,
    .g_times = g_times,
    .row_size = row_size,
};
