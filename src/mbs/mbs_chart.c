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
#include <stabdae/mbs.h>

#include "core/lu.h"
#include "mbs_chart.h"
#include "mbs_linalg.h"

static void sort(size_t *x, size_t n) {
  for (size_t i = 1; i < n; i++)
    for (size_t j = i; j > 0 && x[j - 1] > x[j]; j--) {
      size_t tmp = x[j];
      x[j] = x[j - 1];
      x[j - 1] = tmp;
    }
}

void sdae__mbs_chart_init(sdae_mbs_atlas *ch, size_t n_q, size_t n_c) {
  ch->n_q = n_q;
  ch->n_c = n_c;
  ch->n_f = n_q - n_c;
}

void sdae__mbs_chart_carve(sdae_mbs_atlas *ch, sdae_arena *a) {
  size_t n_q = ch->n_q, n_c = ch->n_c, n_f = ch->n_f;
  ch->dep = sdae__take_indices(a, n_c);
  ch->ind = sdae__take_indices(a, n_f);
  ch->qr = sdae__take(a, n_c, n_q);
  ch->tau = sdae__take(a, n_c, 1);
  ch->norm = sdae__take(a, n_q, 1);
  ch->perm = sdae__take_indices(a, n_q);
  ch->cand_dep = sdae__take_indices(a, n_c);
  ch->cand_ind = sdae__take_indices(a, n_f);
  ch->gd = sdae__take(a, n_c, n_c);
  ch->GD = sdae__take(a, n_c, n_c <= SDAE_SMALL_DENSE ? n_c : sdae__lu_band_cols(n_c - 1, n_c - 1));
  ch->piv = sdae__take_pivots(a, n_c);
  ch->order = sdae__take_indices(a, n_c);
  ch->first = sdae__take_indices(a, n_c);
  ch->last = sdae__take_indices(a, n_c);
  ch->slot = sdae__take_indices(a, n_c + 1);
  ch->rhs = sdae__take(a, n_c, 1);
  ch->A = sdae__take(a, n_c, n_f);
  ch->W = sdae__take(a, n_q, n_f);
  ch->col = sdae__take(a, n_c, 1);
  ch->sol = sdae__take(a, n_c, 1);
}

/* G_D's rows ordered by their first nonzero column (a counting sort, ties in their order), and
 * the bandwidths of that order: a mechanism whose constraints each join a few neighbouring
 * coordinates (a chain, a row of loops) has a narrow band in it, whatever order its rows were
 * written in, and the banded LU costs n_c lb (lb + ub) instead of n_c^3. Read from the numbers
 * at each factorization, since an entry zero at one configuration need not be at the next;
 * a zero row goes last (the LU then finds G_D singular). */
static void band_order(sdae_mbs_atlas *ch, const double *G, const size_t *dep) {
  size_t n_q = ch->n_q, n_c = ch->n_c;
  memset(ch->slot, 0, (n_c + 1) * sizeof *ch->slot);
  for (size_t i = 0; i < n_c; i++) {
    ch->first[i] = n_c, ch->last[i] = 0;
    for (size_t j = 0; j < n_c; j++)
      if (G[i * n_q + dep[j]] != 0.0) {
        if (ch->first[i] == n_c) ch->first[i] = j;
        ch->last[i] = j;
      }
    ch->slot[ch->first[i]]++;
  }
  for (size_t k = 0, at = 0; k <= n_c; k++) {
    size_t count = ch->slot[k];
    ch->slot[k] = at, at += count;
  }
  for (size_t i = 0; i < n_c; i++) ch->order[ch->slot[ch->first[i]]++] = i;
  ch->lb = ch->ub = 0;
  for (size_t k = 0; k < n_c; k++) {
    size_t i = ch->order[k]; /* a zero row (first n_c, last 0) passes both tests */
    if (k > ch->first[i] && k - ch->first[i] > ch->lb) ch->lb = k - ch->first[i];
    if (ch->last[i] > k && ch->last[i] - k > ch->ub) ch->ub = ch->last[i] - k;
  }
}

/* G_D's LU from the chart dep's columns of G: the small dense one for up to SDAE_SMALL_DENSE
 * constraints (GSL's views and calls would dominate), GSL's banded one in band_order's row order
 * otherwise; SDAE_ERR_RANK when it is singular */
static int gd_factor(sdae_mbs_atlas *ch, const double *G, const size_t *dep) {
  size_t n_q = ch->n_q, n_c = ch->n_c;
  if (n_c <= SDAE_SMALL_DENSE) {
    for (size_t i = 0; i < n_c; i++)
      for (size_t j = 0; j < n_c; j++) ch->GD[i * n_c + j] = G[i * n_q + dep[j]];
    return sdae__lu_small_factor(ch->GD, ch->piv, n_c) == SDAE_OK ? SDAE_OK : SDAE_ERR_RANK;
  }
  band_order(ch, G, dep);
  for (size_t k = 0; k < n_c; k++)
    for (size_t j = 0; j < n_c; j++) ch->gd[k * n_c + j] = G[ch->order[k] * n_q + dep[j]];
  sdae__lu_pack(ch->gd, n_c, ch->lb, ch->ub, ch->GD);
  return sdae__lu_factor(ch->GD, ch->piv, n_c, ch->lb, ch->ub) == SDAE_OK ? SDAE_OK : SDAE_ERR_RANK;
}

int sdae__mbs_gd_factor(sdae_mbs_atlas *ch, const double *G) { return gd_factor(ch, G, ch->dep); }

void sdae__mbs_gd_solve(const sdae_mbs_atlas *ch, const double *rhs, double *x) {
  size_t n_c = ch->n_c;
  if (n_c <= SDAE_SMALL_DENSE) {
    sdae__lu_small_solve(ch->GD, ch->piv, n_c, rhs, x);
    return;
  }
  for (size_t k = 0; k < n_c; k++) ch->rhs[k] = rhs[ch->order[k]];
  sdae__lu_factored_solve(ch->GD, ch->piv, n_c, ch->lb, ch->ub, ch->rhs, x);
}

/* G_D's LU and A = G_D^-1 G_I in the chart (dep, ind); max |A| into *measure */
static int factor(sdae_mbs_atlas *ch, const double *G, const size_t *dep, const size_t *ind,
                  double *measure) {
  size_t n_q = ch->n_q, n_c = ch->n_c, n_f = ch->n_f;
  double m = 0.0;
  if (gd_factor(ch, G, dep) != SDAE_OK) return SDAE_ERR_RANK;
  for (size_t k = 0; k < n_f; k++) {
    for (size_t i = 0; i < n_c; i++) ch->col[i] = G[i * n_q + ind[k]];
    sdae__mbs_gd_solve(ch, ch->col, ch->sol);
    for (size_t i = 0; i < n_c; i++) {
      ch->A[i * n_f + k] = ch->sol[i];
      m = fabs(ch->sol[i]) > m ? fabs(ch->sol[i]) : m;
    }
  }
  memset(ch->W, 0, n_q * n_f * sizeof *ch->W);
  for (size_t k = 0; k < n_f; k++) {
    ch->W[ind[k] * n_f + k] = 1.0;
    for (size_t j = 0; j < n_c; j++) ch->W[dep[j] * n_f + k] = -ch->A[j * n_f + k];
  }
  if (measure) *measure = m;
  return SDAE_OK;
}

int sdae__mbs_chart_factor(sdae_mbs_atlas *ch, const double *G, double *measure) {
  return factor(ch, G, ch->dep, ch->ind, measure);
}

void sdae__mbs_Wt(const sdae_mbs_atlas *ch, const double *u, double *out) {
  for (size_t k = 0; k < ch->n_f; k++) {
    double acc = u[ch->ind[k]];
    for (size_t j = 0; j < ch->n_c; j++) acc -= ch->A[j * ch->n_f + k] * u[ch->dep[j]];
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
static int proposal(sdae_mbs_atlas *ch, const double *G) {
  size_t n_q = ch->n_q, n_c = ch->n_c;
  gsl_matrix_view R = gsl_matrix_view_array(ch->qr, n_c, n_q);
  gsl_vector_view tau = gsl_vector_view_array(ch->tau, n_c);
  gsl_vector_view norm = gsl_vector_view_array(ch->norm, n_q);
  gsl_permutation perm = {n_q, ch->perm};
  double last, first;
  int signum, rc;
  ch->independence = 0.0;
  for (size_t i = 0; i < n_c; i++) {
    double row = 0.0;
    for (size_t j = 0; j < n_q; j++) row = hypot(row, G[i * n_q + j]);
    if (!(row > 0.0)) return SDAE_ERR_RANK;
    for (size_t j = 0; j < n_q; j++) ch->qr[i * n_q + j] = G[i * n_q + j] / row;
  }
  gsl_linalg_QRPT_decomp(&R.matrix, &tau.vector, &perm, &signum, &norm.vector);
  first = fabs(ch->qr[0]);
  last = fabs(ch->qr[(n_c - 1) * n_q + (n_c - 1)]);
  ch->independence = first > 0.0 ? last / first : 0.0;
  if ((rc = sdae__mbs_chart_verdict(last, first, n_q)) != SDAE_OK) return rc;
  memcpy(ch->cand_dep, ch->perm, n_c * sizeof *ch->perm);
  memcpy(ch->cand_ind, ch->perm + n_c, ch->n_f * sizeof *ch->perm);
  sort(ch->cand_dep, n_c);
  sort(ch->cand_ind, ch->n_f);
  return SDAE_OK;
}

/* An exchange of q_D's j-th and q_I's k-th coordinate multiplies |det G_D| by |A_jk|.
 * QRPT's proposal is improved by exchanging at the largest |A_jk| while it exceeds
 * EXCHANGE (the maxvol rule): |det G_D| grows every time, so it ends, with a chart whose
 * measure is at most EXCHANGE, factored last. */
#define EXCHANGE 1.05
static int best_chart(sdae_mbs_atlas *ch, const double *G, double *measure) {
  size_t n_c = ch->n_c, n_f = ch->n_f;
  int rc = proposal(ch, G);
  for (size_t it = 0; rc == SDAE_OK; it++) {
    size_t jb = 0, kb = 0, tmp;
    if ((rc = factor(ch, G, ch->cand_dep, ch->cand_ind, measure)) != SDAE_OK) break;
    if (*measure <= EXCHANGE || it == 4 * ch->n_q) break;
    for (size_t j = 0; j < n_c; j++)
      for (size_t k = 0; k < n_f; k++)
        if (fabs(ch->A[j * n_f + k]) > fabs(ch->A[jb * n_f + kb])) jb = j, kb = k;
    tmp = ch->cand_dep[jb];
    ch->cand_dep[jb] = ch->cand_ind[kb];
    ch->cand_ind[kb] = tmp;
    sort(ch->cand_dep, n_c);
    sort(ch->cand_ind, n_f);
  }
  return rc;
}

static void adopt(sdae_mbs_atlas *ch) {
  memcpy(ch->dep, ch->cand_dep, ch->n_c * sizeof *ch->dep);
  memcpy(ch->ind, ch->cand_ind, ch->n_f * sizeof *ch->ind);
  ch->switched = ch->have;
  ch->have = 1;
}

int sdae__mbs_chart_choose(sdae_mbs_atlas *ch, const double *G, int force_best) {
  double now = HUGE_VAL, best; /* a current chart gone singular keeps HUGE_VAL: replaced */
  int rc = best_chart(ch, G, &best);
  ch->kept = ch->switched = 0;
  if (rc != SDAE_OK) return rc;
  if (!ch->have) {
    adopt(ch);
  } else if (memcmp(ch->dep, ch->cand_dep, ch->n_c * sizeof *ch->dep) != 0) {
    factor(ch, G, ch->dep, ch->ind, &now); /* sets now only when G_D is regular */
    if (!sdae__mbs_chart_keeps(force_best, now, best)) {
      adopt(ch);
      rc = factor(ch, G, ch->dep, ch->ind, &best); /* factored last was the old one */
    } else {
      best = now; /* the current one stays, factored */
      ch->kept = 1;
    }
  }
  if (rc == SDAE_OK) ch->measure = best;
  return rc;
}

void sdae__mbs_chart_state(sdae_mbs_atlas *ch, sdae_bytes *b) {
  sdae__bytes_flag(b, &ch->have);
  sdae__bytes_sizes(b, ch->dep, ch->n_c);
  sdae__bytes_sizes(b, ch->ind, ch->n_f);
  sdae__bytes_doubles(b, &ch->measure, 1);
}

int sdae__mbs_chart_valid(const sdae_mbs_atlas *ch) {
  size_t n_q = ch->n_q, n_c = ch->n_c, i = 0, j = 0;
  if (!ch->have) return 1;
  /* dep and ind, each ascending, merged: every coordinate once */
  for (size_t x = 0; x < n_q; x++) {
    if (i < n_c && ch->dep[i] == x)
      i++;
    else if (j < ch->n_f && ch->ind[j] == x)
      j++;
    else
      return 0;
  }
  return 1;
}
