/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Charts of the constraint manifold: the coordinates split into dependent q_D (n_c) and
 * independent q_I, W = dq/dq_I = P [-G_D^-1 G_I; I] spanning ker G. A chart is measured by the
 * size of dq_D/dq_I = -G_D^-1 G_I (its curvature), not by cond(G_D), which is 1 for any 1 x 1
 * block; the best one comes from GSL's QR with column pivoting of G, and replaces the current
 * one only when better by SDAE_MBS_CHART_FACTOR (hysteresis: no switching back and forth). */
#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_linalg.h>
#include <gsl/gsl_permutation.h>

#include "mbs.h"

static void sort(size_t *x, size_t n) {
  for (size_t i = 1; i < n; i++)
    for (size_t j = i; j > 0 && x[j - 1] > x[j]; j--) {
      size_t tmp = x[j];
      x[j] = x[j - 1];
      x[j - 1] = tmp;
    }
}

/* G_D's LU and A = G_D^-1 G_I in the chart (dep, ind); max |A| into *measure */
static int factor(sdae_mbs_stepper *s, const size_t *dep, const size_t *ind, double *measure) {
  size_t n_q = s->n_q, n_c = s->n_c, n_f = s->n_f, b = n_c - 1;
  sdae_mbs_point *p = &s->pt;
  double m = 0.0;
  for (size_t i = 0; i < n_c; i++)
    for (size_t j = 0; j < n_c; j++) s->LA[i * n_c + j] = p->G[i * n_q + dep[j]];
  sdae__lu_pack(s->LA, n_c, b, b, p->GD);
  if (sdae__lu_factor(p->GD, p->piv, n_c, b, b) != SDAE_OK) return SDAE_ERR_RANK;
  for (size_t k = 0; k < n_f; k++) {
    for (size_t i = 0; i < n_c; i++) s->r1[i] = p->G[i * n_q + ind[k]];
    sdae__lu_factored_solve(p->GD, p->piv, n_c, b, b, s->r1, s->r2);
    for (size_t i = 0; i < n_c; i++) {
      p->A[i * n_f + k] = s->r2[i];
      m = fabs(s->r2[i]) > m ? fabs(s->r2[i]) : m;
    }
  }
  memset(p->W, 0, n_q * n_f * sizeof *p->W);
  for (size_t k = 0; k < n_f; k++) {
    p->W[ind[k] * n_f + k] = 1.0;
    for (size_t j = 0; j < n_c; j++) p->W[dep[j] * n_f + k] = -p->A[j * n_f + k];
  }
  if (measure) *measure = m;
  return SDAE_OK;
}

int sdae__mbs_chart_factor(sdae_mbs_stepper *s, double *measure) {
  return factor(s, s->dep, s->ind, measure);
}

void sdae__mbs_Wt(const sdae_mbs_stepper *s, const double *u, double *out) {
  for (size_t k = 0; k < s->n_f; k++) {
    double acc = u[s->ind[k]];
    for (size_t j = 0; j < s->n_c; j++) acc -= s->pt.A[j * s->n_f + k] * u[s->dep[j]];
    out[k] = acc;
  }
}

/* QR with column pivoting of G: the first n_c pivot columns are the best dependent
 * coordinates; SDAE_ERR_RANK when R's last diagonal entry is zero to working precision */
static int best_chart(sdae_mbs_stepper *s) {
  size_t n_q = s->n_q, n_c = s->n_c;
  gsl_matrix_view R = gsl_matrix_view_array(s->qr, n_c, n_q);
  gsl_vector_view tau = gsl_vector_view_array(s->tau, n_c);
  gsl_vector_view norm = gsl_vector_view_array(s->norm, n_q);
  gsl_permutation perm = {n_q, s->perm};
  int signum;
  memcpy(s->qr, s->pt.G, n_c * n_q * sizeof *s->qr);
  gsl_linalg_QRPT_decomp(&R.matrix, &tau.vector, &perm, &signum, &norm.vector);
  double tol = (double)n_q * DBL_EPSILON * fabs(s->qr[0]);
  if (!(fabs(s->qr[(n_c - 1) * n_q + (n_c - 1)]) > tol)) return SDAE_ERR_RANK;
  memcpy(s->cand_dep, s->perm, n_c * sizeof *s->perm);
  memcpy(s->cand_ind, s->perm + n_c, s->n_f * sizeof *s->perm);
  sort(s->cand_dep, n_c);
  sort(s->cand_ind, s->n_f);
  return SDAE_OK;
}

static void adopt(sdae_mbs_stepper *s) {
  memcpy(s->dep, s->cand_dep, s->n_c * sizeof *s->dep);
  memcpy(s->ind, s->cand_ind, s->n_f * sizeof *s->ind);
  if (s->have_chart) s->stats.chart_switches++;
  s->have_chart = 1;
  sdae__mbs_forget(s);
}

int sdae__mbs_choose_chart(sdae_mbs_stepper *s) {
  double now = HUGE_VAL, best;
  int rc = best_chart(s);
  if (rc != SDAE_OK) return rc;
  if (s->have_chart && memcmp(s->dep, s->cand_dep, s->n_c * sizeof *s->dep) == 0) {
    rc = factor(s, s->dep, s->ind, &best);
  } else {
    if (s->have_chart && factor(s, s->dep, s->ind, &now) != SDAE_OK) now = HUGE_VAL;
    if ((rc = factor(s, s->cand_dep, s->cand_ind, &best)) != SDAE_OK) return rc;
    if (!s->have_chart || now > SDAE_MBS_CHART_FACTOR * best)
      adopt(s);
    else /* the current one stays: its factors again */
      rc = factor(s, s->dep, s->ind, &best);
  }
  if (rc != SDAE_OK) return rc;
  s->stats.chart_measure = best;
  return best > SDAE_MBS_CHART_MAX ? SDAE_ERR_CHART : SDAE_OK;
}
