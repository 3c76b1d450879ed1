/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A sparse mechanism's matrices through their patterns (mbs_sparse_layout.h). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "mbs_sparse_layout.h"

int sdae__mbs_sparse_layout_init(sdae_mbs_sparse_layout *ly, sdae_mbs_eval *eval) {
  const sdae_mbs *sys = &eval->sys;
  size_t gnz = sys->jacobian_pattern->nnz, mnz = sys->mass_pattern->nnz;
  ly->eval = eval;
  ly->n_q = eval->n_q;
  ly->n_c = eval->n_c;
  ly->n_k = ly->n_q + ly->n_c;
  return gnz < SIZE_MAX / 4 && sdae__sparse_ldl_fits(ly->n_k, mnz + 2 * gnz + ly->n_c)
             ? SDAE_OK
             : SDAE_ERR_OVERFLOW;
}

/* ---- the saddle-point system's pattern ---- */

/* position of (i, j) in a pattern's row i, (size_t)-1 if none */
static size_t find(const sdae_pattern *p, size_t i, size_t j) {
  for (size_t e = p->row_start[i]; e < p->row_start[i + 1]; e++)
    if (p->col[e] == j) return e;
  return (size_t)-1;
}

/* K = [M G^T; G 0] in compressed rows, columns ascending, in LDL's arrays (SuiteSparse_long):
 * row i < n_q holds M's row i, then the constraints whose rows hold column i; row n_q + j holds
 * G's row j, then its diagonal entry (zero but in the projection's regularized system,
 * sdae__mbs_sparse_kkt_soften). start (n_k + 1) is G^T's row counts first. */
static void build_k(sdae_mbs_sparse_layout *ly, SuiteSparse_long *start, SuiteSparse_long *col,
                    size_t *fill) {
  const sdae_pattern *M = ly->Mp, *G = ly->Gp;
  size_t n_q = ly->n_q;
  memset(fill, 0, n_q * sizeof *fill);
  for (size_t e = 0; e < G->nnz; e++) fill[G->col[e]]++;
  start[0] = 0;
  for (size_t i = 0; i < n_q; i++)
    start[i + 1] = start[i] + (SuiteSparse_long)(M->row_start[i + 1] - M->row_start[i] + fill[i]);
  for (size_t j = 0; j < ly->n_c; j++)
    start[n_q + j + 1] =
        start[n_q + j] + (SuiteSparse_long)(G->row_start[j + 1] - G->row_start[j] + 1);
  for (size_t i = 0; i < n_q; i++) { /* M's row, then G^T's entries appended below */
    fill[i] = (size_t)start[i];
    for (size_t e = M->row_start[i]; e < M->row_start[i + 1]; e++) {
      ly->k_of_m[e] = fill[i];
      col[fill[i]++] = (SuiteSparse_long)M->col[e];
    }
  }
  for (size_t j = 0; j < ly->n_c; j++) /* rows j ascending: G^T's columns ascending */
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++) {
      size_t i = G->col[e];
      ly->k_of_gt[e] = fill[i];
      col[fill[i]++] = (SuiteSparse_long)(n_q + j);
      size_t k = (size_t)start[n_q + j] + (e - G->row_start[j]);
      ly->k_of_g[e] = k;
      col[k] = (SuiteSparse_long)i;
    }
  for (size_t j = 0; j < ly->n_c; j++) {
    ly->k_of_d[j] = (size_t)start[n_q + j + 1] - 1;
    col[ly->k_of_d[j]] = (SuiteSparse_long)(n_q + j);
  }
  for (size_t i = 0; i < n_q; i++) /* the mirror of each mass entry (i, j): (j, i) */
    for (size_t e = M->row_start[i]; e < M->row_start[i + 1]; e++)
      ly->m_mirror[e] = find(M, M->col[e], i);
}

void sdae__mbs_sparse_layout_carve(sdae_mbs_sparse_layout *ly, sdae_arena *a) {
  const sdae_mbs *sys = &ly->eval->sys;
  size_t gnz = sys->jacobian_pattern->nnz, mnz = sys->mass_pattern->nnz, mark;
  size_t *fill;
  ly->Gp = sys->jacobian_pattern, ly->Mp = sys->mass_pattern;
  ly->knz = mnz + 2 * gnz + ly->n_c;
  ly->m_mirror = sdae__take_indices(a, mnz);
  ly->k_of_m = sdae__take_indices(a, mnz);
  ly->k_of_g = sdae__take_indices(a, gnz);
  ly->k_of_gt = sdae__take_indices(a, gnz);
  ly->k_of_d = sdae__take_indices(a, ly->n_c);
  sdae__sparse_ldl_symbolic_carve(&ly->ksym, ly->n_k, ly->n_q, ly->knz, a);
  fill = sdae__arena_lend(a, ly->n_q, sizeof *fill, _Alignof(size_t), &mark);
  if (fill) build_k(ly, ly->ksym.Ap, ly->ksym.Ai, fill); /* handed out, not only counted */
  sdae__arena_reclaim(a, mark);
}

size_t sdae__mbs_sparse_layout_work_len(const sdae_mbs_sparse_layout *ly) {
  return sdae__sparse_ldl_work_len(ly->n_k, ly->knz);
}

void sdae__mbs_sparse_layout_analyse(sdae_mbs_sparse_layout *ly, SuiteSparse_long *work) {
  sdae__sparse_ldl_analyse(&ly->ksym, work);
}

/* ---- products through the patterns ---- */

void sdae__mbs_sparse_g_times(const sdae_mbs_sparse_layout *ly, const double *vals, const double *x,
                              const double *add, double *out) {
  const sdae_pattern *G = ly->Gp;
  for (size_t j = 0; j < ly->n_c; j++) {
    double s = add ? add[j] : 0.0;
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++) s += vals[e] * x[G->col[e]];
    out[j] = s;
  }
}

void sdae__mbs_sparse_m_times(const sdae_mbs_sparse_layout *ly, const double *vals, const double *x,
                              double *out) {
  const sdae_pattern *M = ly->Mp;
  for (size_t i = 0; i < ly->n_q; i++) {
    double s = 0.0;
    for (size_t e = M->row_start[i]; e < M->row_start[i + 1]; e++) s += vals[e] * x[M->col[e]];
    out[i] = s;
  }
}

/* M symmetric to rounding, entry by its mirror (sdae__symmetric's rule on the nonzeros) */
int sdae__mbs_sparse_mass_symmetric(const sdae_mbs_sparse_layout *ly, const double *M) {
  double asym = 0.0, big = 0.0;
  for (size_t e = 0; e < ly->Mp->nnz; e++) {
    double d = fabs(M[e] - M[ly->m_mirror[e]]);
    big = fmax(big, fabs(M[e]));
    asym = d > asym || d != d ? d : asym;
  }
  return asym <= 16.0 * (double)ly->n_q * DBL_EPSILON * big ? SDAE_OK : SDAE_ERR_MASS;
}

void sdae__mbs_sparse_kkt_values(const sdae_mbs_sparse_layout *ly, const double *M, const double *G,
                                 double *K) {
  for (size_t e = 0; e < ly->Mp->nnz; e++) K[ly->k_of_m[e]] = M[e];
  for (size_t e = 0; e < ly->Gp->nnz; e++) K[ly->k_of_g[e]] = K[ly->k_of_gt[e]] = G[e];
  for (size_t j = 0; j < ly->n_c; j++) K[ly->k_of_d[j]] = 0.0;
}

double sdae__mbs_sparse_kkt_soften(const sdae_mbs_sparse_layout *ly, const double *M,
                                   const double *G, double rho, double *K, double *delta) {
  double big = 0.0;
  for (size_t i = 0; i < ly->n_q; i++) {
    double row = 0.0;
    for (size_t e = ly->Mp->row_start[i]; e < ly->Mp->row_start[i + 1]; e++) row += fabs(M[e]);
    big = fmax(big, row);
  }
  sdae__mbs_sparse_kkt_values(ly, M, G, K);
  for (size_t j = 0; j < ly->n_c; j++) {
    double g = 0.0;
    for (size_t e = ly->Gp->row_start[j]; e < ly->Gp->row_start[j + 1]; e++) g += G[e] * G[e];
    delta[j] = big > 0.0 ? rho * g / big : 0.0;
    K[ly->k_of_d[j]] = -delta[j];
  }
  return big;
}
