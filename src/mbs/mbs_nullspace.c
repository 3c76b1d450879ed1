/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The saddle-point system by the null-space method on G's pivoted QR (mbs_nullspace.h): one
 * factorization per point serves the acceleration, the multipliers and the projections. */
#include <math.h>
#include <string.h>

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
  ns->Z = sdae__take(a, n_q, n_q);
  ns->MZ = sdae__take(a, n_q, n_q);
  ns->Mr = sdae__take(a, n_q, n_q);
  ns->xZ = sdae__take(a, n_q, 1);
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

/* x = Q x (n_q values), or Q^T x, by the Householder vectors */
static void apply_Q(const sdae_mbs_nullspace *ns, double *x, int transposed) {
  gsl_matrix_const_view QR = gsl_matrix_const_view_array(ns->GT, ns->n_q, ns->n_c);
  gsl_vector_const_view tau = gsl_vector_const_view_array(ns->tau, ns->n_c);
  gsl_vector_view X = gsl_vector_view_array(x, ns->n_q);
  if (transposed)
    gsl_linalg_QR_QTvec(&QR.matrix, &tau.vector, &X.vector);
  else
    gsl_linalg_QR_Qvec(&QR.matrix, &tau.vector, &X.vector);
}

/* Z, Q's last n_f = n_q - rank columns, Q applied to the unit vectors; then Z^T M Z, factored
 * by Cholesky */
static int reduced_mass(sdae_mbs_nullspace *ns) {
  size_t n_q = ns->n_q, r = ns->rank, n_f = n_q - r;
  const double *Z = ns->Z, *M = ns->M;
  for (size_t b = 0; b < n_f; b++) {
    memset(ns->res, 0, n_q * sizeof *ns->res);
    ns->res[r + b] = 1.0;
    apply_Q(ns, ns->res, 0);
    for (size_t i = 0; i < n_q; i++) ns->Z[i * n_f + b] = ns->res[i];
  }
  for (size_t i = 0; i < n_q; i++)
    for (size_t b = 0; b < n_f; b++) {
      double acc = 0.0;
      for (size_t j = 0; j < n_q; j++) acc += M[i * n_q + j] * Z[j * n_f + b];
      ns->MZ[i * n_f + b] = acc;
    }
  for (size_t a = 0; a < n_f; a++)
    for (size_t b = a; b < n_f; b++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++) acc += Z[i * n_f + a] * ns->MZ[i * n_f + b];
      ns->Mr[a * n_f + b] = ns->Mr[b * n_f + a] = acc;
    }
  return sdae__cholesky_factor(ns->Mr, n_f);
}

int sdae__mbs_nullspace_factor(sdae_mbs_nullspace *ns, const double *G, const double *M,
                               double floor) {
  size_t n_q = ns->n_q, n_c = ns->n_c;
  gsl_matrix_view GT = gsl_matrix_view_array(ns->GT, n_q, n_c);
  gsl_vector_view tau = gsl_vector_view_array(ns->tau, n_c);
  gsl_vector_view norm = gsl_vector_view_array(ns->norm, n_c);
  gsl_permutation perm = {n_c, ns->perm};
  int signum, rc;
  if ((rc = scaled_transpose(ns, G)) != SDAE_OK) return rc;
  /* no error for a matrix of this shape: GSL's handler is never called */
  gsl_linalg_QRPT_decomp(&GT.matrix, &tau.vector, &perm, &signum, &norm.vector);
  ns->rank = n_c;
  ns->M = M;
  return sdae__mbs_nullspace_truncate(ns, floor);
}

int sdae__mbs_nullspace_truncate(sdae_mbs_nullspace *ns, double floor) {
  size_t n_c = ns->n_c, r = 0;
  while (r < ns->rank && fabs(ns->GT[r * n_c + r]) > floor * fabs(ns->GT[0])) r++;
  ns->rank = r;
  return reduced_mass(ns);
}

void sdae__mbs_nullspace_solve(sdae_mbs_nullspace *ns, const double *F, const double *g,
                               double *x) {
  size_t n_q = ns->n_q, n_c = ns->n_c, r = ns->rank, n_f = n_q - r;
  const double *R = ns->GT;
  double *z = ns->xZ;
  for (size_t k = 0; k < r; k++) { /* R_11^T x_Y = -(P^T D g)_r, R_11^T lower triangular */
    size_t j = ns->perm[k];
    double acc = -g[j] * ns->scale[j];
    for (size_t l = 0; l < k; l++) acc -= R[l * n_c + k] * x[l];
    x[k] = acc / R[k * n_c + k];
  }
  memset(x + r, 0, n_f * sizeof *x);
  apply_Q(ns, x, 0);                 /* x = Y x_Y */
  for (size_t i = 0; i < n_q; i++) { /* res = F - M x */
    double acc = F ? F[i] : 0.0;
    for (size_t j = 0; j < n_q; j++) acc -= ns->M[i * n_q + j] * x[j];
    ns->res[i] = acc;
  }
  for (size_t a = 0; a < n_f; a++) {
    double acc = 0.0;
    for (size_t i = 0; i < n_q; i++) acc += ns->Z[i * n_f + a] * ns->res[i];
    z[a] = acc;
  }
  sdae__cholesky_solve(ns->Mr, n_f, z);
  for (size_t i = 0; i < n_q; i++)
    for (size_t a = 0; a < n_f; a++) x[i] += ns->Z[i * n_f + a] * z[a];
}

/* G^T lambda = F - M x with G^T = D^-1 Q R P^T: R mu = Y^T (F - M x), lambda = D P mu */
void sdae__mbs_nullspace_lambda(sdae_mbs_nullspace *ns, const double *F, const double *x,
                                double *lambda) {
  size_t n_q = ns->n_q, n_c = ns->n_c;
  const double *R = ns->GT;
  for (size_t i = 0; i < n_q; i++) {
    double acc = F[i];
    for (size_t j = 0; j < n_q; j++) acc -= ns->M[i * n_q + j] * x[j];
    ns->res[i] = acc;
  }
  apply_Q(ns, ns->res, 1);
  for (size_t j = n_c; j-- > 0;) { /* back substitution */
    double acc = ns->res[j];
    for (size_t k = j + 1; k < n_c; k++) acc -= R[j * n_c + k] * ns->mu[k];
    ns->mu[j] = acc / R[j * n_c + j];
  }
  for (size_t k = 0; k < n_c; k++) lambda[ns->perm[k]] = ns->mu[k] * ns->scale[ns->perm[k]];
}
