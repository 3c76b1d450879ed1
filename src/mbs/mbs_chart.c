/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Charts of the constraint manifold: the coordinates split into dependent q_D (n_c) and
 * independent q_I, W = dq/dq_I = P [-G_D^-1 G_I; I] spanning ker G. A chart is measured by the
 * size of dq_D/dq_I = -G_D^-1 G_I (how steep q_D is over q_I), not by cond(G_D), which is 1
 * for any 1 x 1 block. The best one comes from GSL's QR with column pivoting of G improved by
 * exchanges to a measure of at most about 1, and replaces the current one only when better by
 * SDAE_MBS_CHART_FACTOR (hysteresis: no switching back and forth). */
#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_linalg.h>
#include <gsl/gsl_permutation.h>

#include "mbs_impl.h"

static void sort(size_t *x, size_t n) {
  for (size_t i = 1; i < n; i++)
    for (size_t j = i; j > 0 && x[j - 1] > x[j]; j--) {
      size_t tmp = x[j];
      x[j] = x[j - 1];
      x[j - 1] = tmp;
    }
}

/* G_D's LU in the point, from the current chart's columns of its G: the small dense one for up
 * to SDAE_SMALL_DENSE constraints (GSL's views and calls would dominate), GSL's otherwise;
 * SDAE_ERR_RANK when it is singular */
static int gd_factor(sdae_mbs_stepper *s, const size_t *dep) {
  size_t n_q = s->n_q, n_c = s->n_c, b = n_c - 1;
  for (size_t i = 0; i < n_c; i++)
    for (size_t j = 0; j < n_c; j++) s->LA[i * n_c + j] = s->pt.G[i * n_q + dep[j]];
  if (n_c <= SDAE_SMALL_DENSE) {
    memcpy(s->pt.GD, s->LA, n_c * n_c * sizeof *s->LA);
    return sdae__lu_small_factor(s->pt.GD, s->pt.piv, n_c) == SDAE_OK ? SDAE_OK : SDAE_ERR_RANK;
  }
  sdae__lu_pack(s->LA, n_c, b, b, s->pt.GD);
  return sdae__lu_factor(s->pt.GD, s->pt.piv, n_c, b, b) == SDAE_OK ? SDAE_OK : SDAE_ERR_RANK;
}

int sdae__mbs_gd_factor(sdae_mbs_stepper *s) { return gd_factor(s, s->dep); }

void sdae__mbs_gd_solve(const sdae_mbs_stepper *s, const double *rhs, double *x) {
  size_t n_c = s->n_c, b = n_c - 1;
  if (n_c <= SDAE_SMALL_DENSE)
    sdae__lu_small_solve(s->pt.GD, s->pt.piv, n_c, rhs, x);
  else
    sdae__lu_factored_solve(s->pt.GD, s->pt.piv, n_c, b, b, rhs, x);
}

/* G_D's LU and A = G_D^-1 G_I in the chart (dep, ind); max |A| into *measure */
static int factor(sdae_mbs_stepper *s, const size_t *dep, const size_t *ind, double *measure) {
  size_t n_q = s->n_q, n_c = s->n_c, n_f = s->n_f;
  sdae_mbs_point *p = &s->pt;
  double m = 0.0;
  if (gd_factor(s, dep) != SDAE_OK) return SDAE_ERR_RANK;
  for (size_t k = 0; k < n_f; k++) {
    for (size_t i = 0; i < n_c; i++) s->r1[i] = p->G[i * n_q + ind[k]];
    sdae__mbs_gd_solve(s, s->r1, s->r2);
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

int sdae__mbs_chart_verdict(double last, double first, size_t n_q) {
  if (!(last > (double)n_q * DBL_EPSILON * first)) return SDAE_ERR_RANK;
  return last < SDAE_MBS_CHART_MIN * first ? SDAE_ERR_CHART : SDAE_OK;
}

/* QR with column pivoting of G, its rows scaled to unit length (so that the test below sees
 * the angles between the constraints' gradients, not their units), proposes the first n_c
 * pivot columns as q_D. R's last diagonal entry, relative to its first, is the sine of the
 * smallest angle between a gradient and the span of the others: zero to working precision is
 * SDAE_ERR_RANK (dependent constraints), below SDAE_MBS_CHART_MIN SDAE_ERR_CHART (nearly
 * dependent: q_D would be solved for with a condition number above 1 / SDAE_MBS_CHART_MIN). */
static int proposal(sdae_mbs_stepper *s) {
  size_t n_q = s->n_q, n_c = s->n_c;
  gsl_matrix_view R = gsl_matrix_view_array(s->qr, n_c, n_q);
  gsl_vector_view tau = gsl_vector_view_array(s->tau, n_c);
  gsl_vector_view norm = gsl_vector_view_array(s->norm, n_q);
  gsl_permutation perm = {n_q, s->perm};
  double last, first;
  int signum, rc;
  for (size_t i = 0; i < n_c; i++) {
    double row = 0.0;
    for (size_t j = 0; j < n_q; j++) row = hypot(row, s->pt.G[i * n_q + j]);
    if (!(row > 0.0)) return SDAE_ERR_RANK;
    for (size_t j = 0; j < n_q; j++) s->qr[i * n_q + j] = s->pt.G[i * n_q + j] / row;
  }
  gsl_linalg_QRPT_decomp(&R.matrix, &tau.vector, &perm, &signum, &norm.vector);
  first = fabs(s->qr[0]);
  last = fabs(s->qr[(n_c - 1) * n_q + (n_c - 1)]);
  if ((rc = sdae__mbs_chart_verdict(last, first, n_q)) != SDAE_OK) return rc;
  memcpy(s->cand_dep, s->perm, n_c * sizeof *s->perm);
  memcpy(s->cand_ind, s->perm + n_c, s->n_f * sizeof *s->perm);
  sort(s->cand_dep, n_c);
  sort(s->cand_ind, s->n_f);
  return SDAE_OK;
}

/* An exchange of q_D's j-th and q_I's k-th coordinate multiplies |det G_D| by |A_jk|.
 * QRPT's proposal is improved by exchanging at the largest |A_jk| while it exceeds
 * EXCHANGE (the maxvol rule): |det G_D| grows every time, so it ends, with a chart whose
 * measure is at most EXCHANGE, factored last. */
#define EXCHANGE 1.05
static int best_chart(sdae_mbs_stepper *s, double *measure) {
  size_t n_c = s->n_c, n_f = s->n_f;
  int rc = proposal(s);
  for (size_t it = 0; rc == SDAE_OK; it++) {
    size_t jb = 0, kb = 0, tmp;
    if ((rc = factor(s, s->cand_dep, s->cand_ind, measure)) != SDAE_OK) break;
    if (*measure <= EXCHANGE || it == 4 * s->n_q) break;
    for (size_t j = 0; j < n_c; j++)
      for (size_t k = 0; k < n_f; k++)
        if (fabs(s->pt.A[j * n_f + k]) > fabs(s->pt.A[jb * n_f + kb])) jb = j, kb = k;
    tmp = s->cand_dep[jb];
    s->cand_dep[jb] = s->cand_ind[kb];
    s->cand_ind[kb] = tmp;
    sort(s->cand_dep, n_c);
    sort(s->cand_ind, n_f);
  }
  return rc;
}

static void adopt(sdae_mbs_stepper *s) {
  memcpy(s->dep, s->cand_dep, s->n_c * sizeof *s->dep);
  memcpy(s->ind, s->cand_ind, s->n_f * sizeof *s->ind);
  if (s->have_chart) s->stats.chart_switches++;
  s->have_chart = 1;
  sdae__mbs_forget(s);
}

int sdae__mbs_choose_chart(sdae_mbs_stepper *s) {
  double now = HUGE_VAL, best; /* a current chart gone singular keeps HUGE_VAL: replaced */
  int rc = best_chart(s, &best);
  s->kept = 0;
  if (rc != SDAE_OK) return rc;
  if (!s->have_chart) {
    adopt(s);
  } else if (memcmp(s->dep, s->cand_dep, s->n_c * sizeof *s->dep) != 0) {
    factor(s, s->dep, s->ind, &now); /* sets now only when G_D is regular */
    if (s->force_best || now > SDAE_MBS_CHART_FACTOR * best) {
      adopt(s);
      rc = factor(s, s->dep, s->ind, &best); /* factored last was the old one */
    } else {
      best = now; /* the current one stays, factored */
      s->kept = 1;
    }
  }
  if (rc == SDAE_OK) s->stats.chart_measure = best;
  return rc;
}
