/* The xi update: the paper's stabilizer (eq. 6 gains with scheme 11 or 15) and, for
 * comparison, the linear baselines of index reduction and Baumgarte. */
#include <math.h>

#include "internal.h"

/* The baselines work per constraint on its chain (h, L_f h, ..., L_f^{r-1} h). */
static int rel_degree_check(const sdae_model *m) {
  size_t sum = 0;
  if (!m->rel_degree || m->n_constraints == 0) return SDAE_ERR_REL_DEGREE;
  for (size_t c = 0; c < m->n_constraints; c++) {
    unsigned r = m->rel_degree[c];
    if (r < 1 || r > SDAE_MAX_REL_DEGREE) return SDAE_ERR_REL_DEGREE;
    sum += r;
  }
  return sum == m->n_xi ? SDAE_OK : SDAE_ERR_REL_DEGREE;
}

int sdae__stabilizer_check(const sdae_model *m, const sdae_options *o) {
  switch (o->stabilizer) {
  case SDAE_STAB_PAPER: return SDAE_OK;
  case SDAE_STAB_NONE: return rel_degree_check(m);
  case SDAE_STAB_BAUMGARTE:
    for (int j = 0; j < SDAE_MAX_REL_DEGREE; j++)
      if (!isfinite(o->baumgarte_alpha[j])) return SDAE_ERR_PARAM;
    return rel_degree_check(m);
  }
  return SDAE_ERR_OPTION;
}

void sdae__gains(const sdae_stepper *s, double *k) {
  double half_d2 = 0.5 * s->opt.delta * s->opt.delta;
  for (size_t i = 0; i < s->model.n_xi; i++)
    k[i] = -half_d2 * s->qnorm2[i] - s->opt.epsilon; /* eq. 6 */
}

static void paper_update(sdae_stepper *s, double T, const double *xi) {
  sdae__gains(s, s->k);
  if (s->opt.scheme == SDAE_SCHEME_EXPLICIT)
    for (size_t i = 0; i < s->model.n_xi; i++)
      s->xi_new[i] = (1.0 + T * s->k[i]) * xi[i]; /* eq. 11 */
  else
    for (size_t i = 0; i < s->model.n_xi; i++)
      s->xi_new[i] = xi[i] / (1.0 - T * s->k[i]); /* eq. 15: k_i < 0, never a zero divisor */
}

/* The chain matrix A of one constraint of relative degree r: xi_j' = xi_{j+1}, and the last
 * derivative 0 (index reduction) or -sum_j alpha_j xi_j (Baumgarte). */
static double chain_entry(const sdae_stepper *s, unsigned r, unsigned i, unsigned j) {
  if (i + 1 < r) return j == i + 1 ? 1.0 : 0.0;
  return s->opt.stabilizer == SDAE_STAB_BAUMGARTE ? -s->opt.baumgarte_alpha[j] : 0.0;
}

/* Scheme 11: xi+ = (I + T A) xi. */
static void chain_explicit(sdae_stepper *s, unsigned r, double T, const double *xi,
                           double *out) {
  for (unsigned i = 0; i < r; i++) {
    double acc = xi[i];
    for (unsigned j = 0; j < r; j++) acc += T * chain_entry(s, r, i, j) * xi[j];
    out[i] = acc;
  }
}

/* Scheme 15: (I - T A) xi+ = xi. */
static int chain_semi_implicit(sdae_stepper *s, unsigned r, double T, const double *xi,
                               double *out) {
  for (unsigned i = 0; i < r; i++)
    for (unsigned j = 0; j < r; j++)
      s->blk[i * r + j] = (i == j ? 1.0 : 0.0) - T * chain_entry(s, r, i, j);
  sdae__lu_pack(s->blk, r, r - 1, r - 1, s->blk_LU);
  return sdae__lu_solve(s->blk_LU, s->blk_piv, r, r - 1, r - 1, xi, out);
}

static int baseline_update(sdae_stepper *s, double T, const double *xi) {
  size_t off = 0;
  for (size_t c = 0; c < s->model.n_constraints; c++) {
    unsigned r = s->model.rel_degree[c];
    if (s->opt.scheme == SDAE_SCHEME_EXPLICIT) {
      chain_explicit(s, r, T, xi + off, s->xi_new + off);
    } else {
      int rc = chain_semi_implicit(s, r, T, xi + off, s->xi_new + off);
      if (rc != SDAE_OK) return rc;
    }
    off += r;
  }
  return SDAE_OK;
}

int sdae__xi_update(sdae_stepper *s, double T, const double *xi) {
  if (s->opt.stabilizer == SDAE_STAB_PAPER) {
    paper_update(s, T, xi);
    return SDAE_OK;
  }
  return baseline_update(s, T, xi);
}
