/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The saddle-point system by the null-space method on G's pivoted QR (mbs_nullspace.h): one
 * factorization per point serves the acceleration, the multipliers and the projections. */
#include <math.h>

#include <gsl/gsl_linalg.h>
#include <stabdae/stabdae.h>

#include "core/lu.h"
#include "mbs_nullspace.h"

void sdae__mbs_nullspace_carve(sdae_mbs_nullspace *ns, size_t n_q, size_t n_c, sdae_arena *a) {
  ns->n_q = n_q;
  ns->n_c = n_c;
  ns->scale = sdae__take(a, n_c, 1);
  ns->GT = sdae__take(a, n_q, n_c);
  ns->tau = sdae__take(a, n_c, 1);
  ns->norm = sdae__take(a, n_c, 1);
  ns->perm = sdae__take_indices(a, n_c);
  ns->Q = sdae__take(a, n_q, n_q);
  ns->R = sdae__take(a, n_q, n_c);
  ns->MZ = sdae__take(a, n_q, n_q);
  ns->Mr = sdae__take(a, n_q, n_q);
  ns->xY = sdae__take(a, n_q, 1);
  ns->res = sdae__take(a, n_q, 1);
  ns->mu = sdae__take(a, n_c, 1);
}

/* G_s^T = (D G)^T, D = diag(1 / |G_j|): the QR sees the angles between the rows, not their
 * units */
static int scaled_transpose(sdae_mbs_nullspace *ns, const double *G) {
  size_t n_q = ns->n_q, n_c = ns->n_c;
  for (size_t j = 0; j < n_c; j++) {
    double row = 0.0;
    for (size_t i = 0; i < n_q; i++) row = hypot(row, G[j * n_q + i]);
    if (!(row > 0.0)) return SDAE_ERR_RANK;
    ns->scale[j] = 1.0 / row;
    for (size_t i = 0; i < n_q; i++) ns->GT[i * n_c + j] = G[j * n_q + i] / row;
  }
  return SDAE_OK;
}

/* Z^T M Z (n_f = n_q - rank), factored by Cholesky */
static int reduced_mass(sdae_mbs_nullspace *ns) {
  size_t n_q = ns->n_q, r = ns->rank, n_f = n_q - r;
  const double *Q = ns->Q, *M = ns->M;
  for (size_t i = 0; i < n_q; i++)
    for (size_t b = 0; b < n_f; b++) {
      double acc = 0.0;
      for (size_t j = 0; j < n_q; j++) acc += M[i * n_q + j] * Q[j * n_q + r + b];
      ns->MZ[i * n_f + b] = acc;
    }
  for (size_t a = 0; a < n_f; a++)
    for (size_t b = a; b < n_f; b++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += Q[i * n_q + r + a] * ns->MZ[i * n_f + b];
      ns->Mr[a * n_f + b] = ns->Mr[b * n_f + a] = acc;
    }
  return sdae__cholesky_factor(ns->Mr, n_f);
}

int sdae__mbs_nullspace_factor(sdae_mbs_nullspace *ns, const double *G, const double *M,
                               double floor) {
  size_t n_q = ns->n_q, n_c = ns->n_c;
  gsl_matrix_view GT = gsl_matrix_view_array(ns->GT, n_q, n_c);
  gsl_matrix_view Q = gsl_matrix_view_array(ns->Q, n_q, n_q);
  gsl_matrix_view R = gsl_matrix_view_array(ns->R, n_q, n_c);
  gsl_vector_view tau = gsl_vector_view_array(ns->tau, n_c);
  gsl_vector_view norm = gsl_vector_view_array(ns->norm, n_c);
  gsl_permutation perm = {n_c, ns->perm};
  int signum, rc;
  if ((rc = scaled_transpose(ns, G)) != SDAE_OK) return rc;
  /* neither call reports an error for matrices of these shapes: GSL's handler is never called */
  gsl_linalg_QRPT_decomp(&GT.matrix, &tau.vector, &perm, &signum, &norm.vector);
  gsl_linalg_QR_unpack(&GT.matrix, &tau.vector, &Q.matrix, &R.matrix);
  ns->rank = n_c;
  ns->M = M;
  return sdae__mbs_nullspace_truncate(ns, floor);
}

int sdae__mbs_nullspace_truncate(sdae_mbs_nullspace *ns, double floor) {
  size_t n_c = ns->n_c, r = 0;
  while (r < ns->rank && fabs(ns->R[r * n_c + r]) > floor * fabs(ns->R[0])) r++;
  ns->rank = r;
  return reduced_mass(ns);
}

void sdae__mbs_nullspace_solve(sdae_mbs_nullspace *ns, const double *F, const double *g,
                               double *x) {
  size_t n_q = ns->n_q, n_c = ns->n_c, r = ns->rank, n_f = n_q - r;
  const double *Q = ns->Q, *R = ns->R;
  double *xY = ns->xY, *z = ns->xY + r; /* x_Z in xY's unused tail */
  for (size_t k = 0; k < r; k++) {      /* R_11^T x_Y = -(P^T D g)_r, R_11^T lower triangular */
    size_t j = ns->perm[k];
    double acc = -g[j] * ns->scale[j];
    for (size_t l = 0; l < k; l++) acc -= R[l * n_c + k] * xY[l];
    xY[k] = acc / R[k * n_c + k];
  }
  for (size_t i = 0; i < n_q; i++) {
    double acc = 0.0;
    for (size_t k = 0; k < r; k++) acc += Q[i * n_q + k] * xY[k];
    x[i] = acc;
  }
  for (size_t i = 0; i < n_q; i++) { /* res = F - M x */
    double acc = F ? F[i] : 0.0;
    for (size_t j = 0; j < n_q; j++) acc -= ns->M[i * n_q + j] * x[j];
    ns->res[i] = acc;
  }
  for (size_t a = 0; a < n_f; a++) {
    double acc = 0.0;
    for (size_t i = 0; i < n_q; i++) acc += Q[i * n_q + r + a] * ns->res[i];
    z[a] = acc;
  }
  sdae__cholesky_solve(ns->Mr, n_f, z);
  for (size_t i = 0; i < n_q; i++)
    for (size_t a = 0; a < n_f; a++) x[i] += Q[i * n_q + r + a] * z[a];
}

/* G^T lambda = F - M x with G^T = D^-1 Q R P^T: R mu = Y^T (F - M x), lambda = D P mu */
void sdae__mbs_nullspace_lambda(sdae_mbs_nullspace *ns, const double *F, const double *x,
                                double *lambda) {
  size_t n_q = ns->n_q, n_c = ns->n_c;
  const double *Q = ns->Q, *R = ns->R;
  for (size_t i = 0; i < n_q; i++) {
    double acc = F[i];
    for (size_t j = 0; j < n_q; j++) acc -= ns->M[i * n_q + j] * x[j];
    ns->res[i] = acc;
  }
  for (size_t j = n_c; j-- > 0;) { /* back substitution */
    double acc = 0.0;
    for (size_t i = 0; i < n_q; i++) acc += Q[i * n_q + j] * ns->res[i];
    for (size_t k = j + 1; k < n_c; k++) acc -= R[j * n_c + k] * ns->mu[k];
    ns->mu[j] = acc / R[j * n_c + j];
  }
  for (size_t k = 0; k < n_c; k++) lambda[ns->perm[k]] = ns->mu[k] * ns->scale[ns->perm[k]];
}
