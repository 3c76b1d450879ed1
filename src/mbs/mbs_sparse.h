/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a sparse mechanism at the cost of its nonzeros (mbs_sparse.c): the same
 * xi, mu, Phi^-1 and mu-dynamics as mbs_coords.c, with G, M and dG/ds as their nonzeros, the
 * chart by core/sparse_lu.c (G = L U, G_D = L U_D, no G_D^-1 G_I formed) and the velocity from
 * the saddle-point system [M G^T; G 0] [v; nu] = [P^T (0, p); xi_v - dc/dt], factored by
 * core/sparse_ldl.c (SuiteSparse's AMD and LDL): W^T y = y_I - G_I^T G_D^-T y_D, and the
 * multipliers give G_D^-T (M v)_D = -nu, so that
 *
 *   p' = W^T (F + (dM/dt) v + (dG/dt)^T nu).
 *
 * Used for a mechanism with both patterns, jacobian_dot and mass_dot_v, stepped by an explicit
 * map (sdae__mbs_sparse_applies). */
#ifndef STABDAE_SRC_MBS_MBS_SPARSE_H
#define STABDAE_SRC_MBS_MBS_SPARSE_H

#include <stabdae/stabdae.h>

#include "core/arena.h"
#include "core/bytes.h"
#include "core/newton.h"
#include "core/sparse_ldl.h"
#include "core/sparse_lu.h"
#include "mbs_eval.h"

typedef struct sdae_mbs_sparse {
  sdae_mbs_eval *eval;
  size_t n_q, n_c, n_f, n_k;   /* n_k = n_q + n_c: the saddle-point system's size */
  unsigned newton_max_iter;    /* Phi^-1's Newton: the options' cap */
  const sdae_pattern *Gp, *Mp; /* the mechanism's, the eval's copies */
  size_t *m_mirror;            /* nnz(M): where M's entry (j, i) is for its entry (i, j) */
  /* the chart: the current factorization and a candidate's, swapped on a switch */
  sdae_sparse_lu lu[2];
  int cur, have, kept;
  size_t *ind;    /* n_f: the current chart's q_I, ascending */
  int switched;   /* the last choice replaced the chart (the first one does not) */
  double measure; /* ||G_D^-1 G_I||_1 (estimated) of the current chart where chosen */
  /* the saddle-point system: its pattern, where M's and G's values go in it, its order and
   * structure (analysed when the stepper is built, shared with the query) and its factors */
  sdae_pattern Kp;
  size_t *k_of_m, *k_of_g, *k_of_gt;
  double *K;
  sdae_sparse_ldl_symbolic ksym;
  sdae_sparse_ldl kkt;
  /* the point Phi^-1 left (or the step's start), as mbs_coords' */
  double *q, *v, *c, *ct; /* n_q, n_q, n_c, n_c */
  double *G, *M, *Gd;     /* nnz(G), nnz(M), nnz(G) */
  double *nu;             /* n_c: the multipliers of the velocity's system */
  int valid, at_start, base_here;
  /* the chart's and the saddle-point system's factors are at the point a state's Phi^-1 left
   * (fresh; not in the state's bytes, so that a rollback or a state set clears it), and the
   * step's start is that point, where they serve as they are (reuse) */
  int fresh, reuse;
  double key_t, *key; /* 2 n_q */
  double *base_q, *base_c, *base_ct, base_t;
  /* scratch */
  double *Mv, *F, *Mdv, *y, *rhs, *sol; /* n_q, n_q, n_q, n_q, n_k, n_k */
  double *zc, *yd, *q_D, *res;          /* n_c each */
  double *est_x, *est_z;                /* n_q each: the norm estimate's */
  sdae_newton newton;                   /* Phi^-1's chord, G_D's factors kept from the base */
  unsigned long phi_inv_iters;          /* since the step's start, as mbs_coords' */
} sdae_mbs_sparse;

/* the sparse coordinates serve this mechanism and options: both patterns, jacobian_dot and
 * mass_dot_v given, an explicit map */
int sdae__mbs_sparse_applies(const sdae_mbs *sys, const sdae_options *o);
void sdae__mbs_sparse_init(sdae_mbs_sparse *sp, sdae_mbs_eval *eval, unsigned newton_max_iter);
/* the saddle-point system's sizes fit its factorization's indices */
int sdae__mbs_sparse_fits(const sdae_mbs_sparse *sp);
/* its arrays, counted or handed out; handed out, the saddle-point pattern built and analysed:
 * SDAE_OK, or sdae__sparse_ldl_analyse's refusal */
int sdae__mbs_sparse_carve(sdae_mbs_sparse *sp, sdae_arena *a);

/* as mbs_coords' and mbs_chart's functions of the same names */
int sdae__mbs_sparse_xi(sdae_mbs_sparse *sp, double t, const double *q, const double *v,
                        double *xi);
int sdae__mbs_sparse_choose(sdae_mbs_sparse *sp, int force_best);
int sdae__mbs_sparse_begin(sdae_mbs_sparse *sp, double t, const double *q, const double *v,
                           double *mu);
void sdae__mbs_sparse_floors(const sdae_mbs_sparse *sp, const double *q, const double *v,
                             double *floor);
int sdae__mbs_sparse_seed(sdae_mbs_sparse *sp, double t, const double *q, const double *v,
                          const double *mu);
int sdae__mbs_sparse_phi_inv(sdae_mbs_sparse *sp, double t, const double *xi, const double *mu);
int sdae__mbs_sparse_phi_inv_state(sdae_mbs_sparse *sp, double t, const double *xi,
                                   const double *mu);
int sdae__mbs_sparse_mu_dot(sdae_mbs_sparse *sp, double t, double *out);
/* the factors made anew at the next step's start (a state was set) */
void sdae__mbs_sparse_stale(sdae_mbs_sparse *sp);
/* the dependent coordinates, ascending, into dep (n_c) */
void sdae__mbs_sparse_chart(const sdae_mbs_sparse *sp, size_t *dep);
/* products through the patterns: out (n_c) = G x + add (add may be NULL), out (n_q) = M x; M
 * symmetric to rounding (SDAE_ERR_MASS otherwise); K's values from M's and G's */
void sdae__mbs_sparse_g_times(const sdae_mbs_sparse *sp, const double *vals, const double *x,
                              const double *add, double *out);
void sdae__mbs_sparse_m_times(const sdae_mbs_sparse *sp, const double *vals, const double *x,
                              double *out);
int sdae__mbs_sparse_mass_symmetric(const sdae_mbs_sparse *sp, const double *M);
void sdae__mbs_sparse_kkt_values(const sdae_mbs_sparse *sp, const double *M, const double *G,
                                 double *K);

/* what the next step depends on, counted, written or read; and whether bytes read hold pivots
 * that index the mechanism's columns */
void sdae__mbs_sparse_state(sdae_mbs_sparse *sp, sdae_bytes *b);
int sdae__mbs_sparse_valid(sdae_mbs_sparse *sp);

#endif /* STABDAE_SRC_MBS_MBS_SPARSE_H */
