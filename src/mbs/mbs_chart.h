/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Charts of the constraint manifold (mbs_chart.c): the split of q into dependent q_D (n_c) and
 * independent q_I, the best one by pivoted QR of G, G_D's factors, A = G_D^-1 G_I and
 * W = dq/dq_I = P [-A; I] at the G factored last. Its functions take that G as an argument; the
 * chart knows nothing of the configuration it came from, nor of the coordinates built on it. */
#ifndef STABDAE_SRC_MBS_MBS_CHART_H
#define STABDAE_SRC_MBS_MBS_CHART_H

#include <stddef.h>

#include "core/arena.h"
#include "core/bytes.h"

/* the charts of the manifold, an atlas: the current one, the search for the best, its factors */
typedef struct sdae_mbs_atlas {
  size_t n_q, n_c, n_f;
  int have;          /* a chart was chosen */
  int kept;          /* the last choice kept the current chart over a better proposal */
  size_t *dep, *ind; /* the chart: n_c and n_f coordinates, ascending */
  /* the search for the best chart: QRPT's work (n_c x n_q, n_c, n_q) and its permutation, the
   * candidate chart */
  double *qr, *tau, *norm;
  size_t *perm, *cand_dep, *cand_ind;
  /* the factors at the G factored last */
  double *gd;    /* n_c x n_c: G_D's rows in band order, the banded factorization's input */
  double *GD;    /* G_D's LU: small dense (n_c <= SDAE_SMALL_DENSE) or GSL's band format */
  unsigned *piv; /* n_c */
  /* the band format's: G_D's rows reordered by their first nonzero, row k of the factors row
   * order[k] of G_D, and the bandwidths lb, ub of that order; first, last, slot its work */
  size_t *order, *first, *last, *slot, lb, ub;
  double *rhs;         /* n_c: a right-hand side in that order */
  double *A;           /* n_c x n_f: G_D^-1 G_I */
  double *W;           /* n_q x n_f: dq/dq_I, spans ker G */
  double *col, *sol;   /* n_c each: a column of G_I and G_D^-1 of it */
  int switched;        /* the last choice replaced the chart (the first choice does not) */
  double measure;      /* max |A| of the current chart where it was chosen */
  double independence; /* the rows' least sine at the last choice (R's last pivot / first) */
} sdae_mbs_atlas;

/* the sizes; the arrays come from sdae__mbs_chart_carve */
void sdae__mbs_chart_init(sdae_mbs_atlas *ch, size_t n_q, size_t n_c);
void sdae__mbs_chart_carve(sdae_mbs_atlas *ch, sdae_arena *a);

/* from the last and first diagonal entries of the QR of G (rows of unit length), n_q columns:
 * SDAE_ERR_RANK when last <= n_q eps first, SDAE_ERR_CHART when below SDAE_MBS_CHART_MIN first */
int sdae__mbs_chart_verdict(double last, double first, size_t n_q);
/* the best chart for G (n_c x n_q) by column-pivoted QR, kept unless it beats the current one by
 * SDAE_MBS_CHART_FACTOR (force_best: whatever the hysteresis); leaves ch->kept and
 * ch->switched, the chart factored at G; SDAE_ERR_RANK, SDAE_ERR_CHART */
int sdae__mbs_chart_choose(sdae_mbs_atlas *ch, const double *G, int force_best);
/* G_D's LU, A and W at G in the current chart; SDAE_ERR_RANK when G_D is singular;
 * *measure = max |A| (may be NULL) */
int sdae__mbs_chart_factor(sdae_mbs_atlas *ch, const double *G, double *measure);
/* G_D's LU alone at G in the current chart (Newton's matrix); SDAE_ERR_RANK */
int sdae__mbs_gd_factor(sdae_mbs_atlas *ch, const double *G);
/* x = G_D^-1 rhs (n_c values) with the factors; the banded path reorders rhs into ch->rhs, the
 * chart's scratch, so rhs must not be ch->rhs */
void sdae__mbs_gd_solve(const sdae_mbs_atlas *ch, const double *rhs, double *x);
/* out (n_f) = W^T u for u (n_q) */
void sdae__mbs_Wt(const sdae_mbs_atlas *ch, const double *u, double *out);

/* the chart and its measure (what the next step depends on), counted, written or read
 * (core/bytes.h) */
void sdae__mbs_chart_state(sdae_mbs_atlas *ch, sdae_bytes *b);
/* the chart is a split of the coordinates (or there is none): what bytes read may not hold */
int sdae__mbs_chart_valid(const sdae_mbs_atlas *ch);

#endif /* STABDAE_SRC_MBS_MBS_CHART_H */
