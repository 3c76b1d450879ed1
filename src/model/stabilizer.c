/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The xi update, one table per stabilizer: the paper's (eq. 6 gains with scheme 11 or 15) and,
 * for comparison, the linear baselines of index reduction and Baumgarte. */
#include <math.h>

#include "core/callback.h"
#include "core/lu.h"
#include "stabilizer.h"

void sdae__gains(const sdae_options *o, const double *qnorm2, size_t n, double *k) {
  double half_d2 = 0.5 * o->delta * o->delta;
  for (size_t i = 0; i < n; i++) k[i] = -half_d2 * qnorm2[i] - o->epsilon; /* eq. 6 */
}

/* ---- the paper's ---- */

static void paper_carve(sdae_stab_ctx *c, sdae_arena *a) {
  c->k = sdae__take(a, c->model->n_xi, 1);
}

/* Gains that overflow (delta^2 ||q_i||^2 beyond the doubles) are refused under either scheme:
 * scheme 15's xi / (1 - T k) would turn k = -inf into a silent xi+ = 0, scheme 11 into Inf. */
static int paper_update(sdae_stab_ctx *c, double T, const double *xi, double *xi_new) {
  size_t n = c->model->n_xi;
  sdae__gains(c->opt, c->qnorm2, n, c->k);
  if (!sdae__all_finite(c->k, n)) return SDAE_ERR_NONFINITE;
  if (c->opt->scheme == SDAE_SCHEME_EXPLICIT)
    for (size_t i = 0; i < n; i++) xi_new[i] = (1.0 + T * c->k[i]) * xi[i]; /* eq. 11 */
  else
    for (size_t i = 0; i < n; i++)
      xi_new[i] = xi[i] / (1.0 - T * c->k[i]); /* eq. 15: k_i < 0, never a zero divisor */
  return SDAE_OK;
}

static const sdae_stabilizer_type paper = {
    .name = "paper",
    .carve = paper_carve,
    .xi_update = paper_update,
};

/* ---- the baselines: per constraint, its chain (h, L_f h, ..., L_f^{r-1} h) ---- */

int sdae__rel_degree_check(const sdae_model *m, unsigned max) {
  size_t sum = 0;
  if (!m->rel_degree || m->n_constraints == 0) return SDAE_ERR_REL_DEGREE;
  for (size_t c = 0; c < m->n_constraints; c++) {
    unsigned r = m->rel_degree[c];
    if (r < 1 || r > max || r > m->n_xi - sum) return SDAE_ERR_REL_DEGREE;
    sum += r;
  }
  return sum == m->n_xi ? SDAE_OK : SDAE_ERR_REL_DEGREE;
}

static int baumgarte_validate(const sdae_model *m, const sdae_options *o) {
  for (int j = 0; j < SDAE_MAX_REL_DEGREE; j++)
    if (!isfinite(o->baumgarte_alpha[j])) return SDAE_ERR_PARAM;
  return sdae__rel_degree_check(m, SDAE_MAX_REL_DEGREE);
}

static int none_validate(const sdae_model *m, const sdae_options *o) {
  (void)o;
  return sdae__rel_degree_check(m, SDAE_MAX_REL_DEGREE);
}

/* one r x r block at a time */
static void chain_carve(sdae_stab_ctx *c, sdae_arena *a) {
  size_t r = SDAE_MAX_REL_DEGREE;
  c->blk = sdae__take(a, r, r);
  c->blk_LU = sdae__take(a, r, sdae__lu_band_cols(r - 1, r - 1));
  c->blk_piv = sdae__take_pivots(a, r);
}

/* The chain matrix A of one constraint of relative degree r: xi_j' = xi_{j+1}, and the last
 * derivative 0 (index reduction) or -sum_j alpha_j xi_j (Baumgarte). */
static double chain_entry(const sdae_stab_ctx *c, unsigned r, unsigned i, unsigned j) {
  if (i + 1 < r) return j == i + 1 ? 1.0 : 0.0;
  return c->opt->stabilizer == SDAE_STAB_BAUMGARTE ? -c->opt->baumgarte_alpha[j] : 0.0;
}

/* Scheme 11: xi+ = (I + T A) xi. */
static void chain_explicit(const sdae_stab_ctx *c, unsigned r, double T, const double *xi,
                           double *out) {
  for (unsigned i = 0; i < r; i++) {
    double acc = xi[i];
    for (unsigned j = 0; j < r; j++) acc += T * chain_entry(c, r, i, j) * xi[j];
    out[i] = acc;
  }
}

/* Scheme 15: (I - T A) xi+ = xi. */
static int chain_semi_implicit(sdae_stab_ctx *c, unsigned r, double T, const double *xi,
                               double *out) {
  for (unsigned i = 0; i < r; i++)
    for (unsigned j = 0; j < r; j++)
      c->blk[i * r + j] = (i == j ? 1.0 : 0.0) - T * chain_entry(c, r, i, j);
  sdae__lu_pack(c->blk, r, r - 1, r - 1, c->blk_LU);
  return sdae__lu_solve(c->blk_LU, c->blk_piv, r, r - 1, r - 1, xi, out);
}

static int chain_update(sdae_stab_ctx *c, double T, const double *xi, double *xi_new) {
  size_t off = 0;
  for (size_t k = 0; k < c->model->n_constraints; k++) {
    unsigned r = c->model->rel_degree[k];
    if (c->opt->scheme == SDAE_SCHEME_EXPLICIT) {
      chain_explicit(c, r, T, xi + off, xi_new + off);
    } else {
      int rc = chain_semi_implicit(c, r, T, xi + off, xi_new + off);
      if (rc != SDAE_OK) return rc;
    }
    off += r;
  }
  return SDAE_OK;
}

static const sdae_stabilizer_type none = {
    .name = "none",
    .validate = none_validate,
    .carve = chain_carve,
    .xi_update = chain_update,
};

static const sdae_stabilizer_type baumgarte = {
    .name = "baumgarte",
    .validate = baumgarte_validate,
    .carve = chain_carve,
    .xi_update = chain_update,
};

const sdae_stabilizer_type *sdae__stabilizer_type(sdae_stabilizer which) {
  switch (which) {
  case SDAE_STAB_PAPER: return &paper;
  case SDAE_STAB_NONE: return &none;
  case SDAE_STAB_BAUMGARTE: return &baumgarte;
  }
  return NULL;
}
