/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The linear algebra of a mechanism's coordinates behind one table, as SUNDIALS' integrators
 * call SUNLinSolSetup and SUNLinSolSolve whatever the solver: the coordinates are written once
 * (mbs_coords.c: the step's start, Phi^-1, the mu-dynamics, the point, the floors, the state's
 * bytes, the energy structure) over a back-end that owns G and M at the point, the chart and
 * its factors, and the velocity's system. Two back-ends: dense (mbs_dense.c: the chart by
 * pivoted QR, the reduced mass W^T M W) and sparse (mbs_sparse.c: the chart by sparse LU, the
 * saddle-point system by LDL), each a static const table as a map's (maps/map.h). */
#ifndef STABDAE_SRC_MBS_MBS_LINALG_H
#define STABDAE_SRC_MBS_MBS_LINALG_H

#include <stabdae/stabdae.h>

#include "core/alloc.h"
#include "core/arena.h"
#include "core/bytes.h"
#include "mbs_eval.h"

/* what became of the chart at a step's start */
typedef struct sdae_mbs_choice {
  int switched; /* the chart was replaced */
  int kept;     /* the current chart was kept over a better one by the hysteresis */
  /* the constraints' independence at the stored G (the dense chart's pivoted QR's least sine,
   * set even where it refuses G; the sparse back-end's least singular value of D G M^-1/2 on
   * its velocity system, which its choice factors) */
  double independence;
} sdae_mbs_choice;

/* The hysteresis, one rule for both back-ends: the best chart is sought at every step's start
 * and the current one kept over it unless force_best or its measure now (HUGE_VAL where it is
 * singular) exceeds SDAE_MBS_CHART_FACTOR times the best's (each back-end measures
 * G_D^-1 G_I in its own norm: max |entry| formed, or the 1-norm estimated) */
static inline int sdae__mbs_chart_keeps(int force_best, double now, double best) {
  return !force_best && !(now > SDAE_MBS_CHART_FACTOR * best);
}

typedef struct sdae_mbs_linalg {
  const char *name;
  /* wired to the callbacks and the options (SDAE_ERR_OVERFLOW: sizes it cannot index); what
   * its sizes depend on beyond the dimensions found by analyse in scratch (NULL: nothing),
   * before its arrays are counted; the arrays counted or handed out by carve, which may refuse
   * what its analysis at the build refuses */
  int (*init)(void *la, sdae_mbs_eval *eval, const sdae_options *o);
  int (*analyse)(void *la, const sdae_scratch *scratch);
  int (*carve)(void *la, sdae_arena *a);
  /* G and M at (t, q) into the back-end's own storage, and M's symmetry (SDAE_ERR_MASS) */
  int (*jacobian)(void *la, double t, const double *q);
  int (*mass)(void *la, double t, const double *q);
  int (*mass_symmetric)(const void *la);
  /* products with the stored matrices: out (n_c) = G x + add (add may be NULL), out (n_q) =
   * M x; the 1-norm of G's row j */
  void (*g_times)(const void *la, const double *x, const double *add, double *out);
  void (*m_times)(const void *la, const double *x, double *out);
  double (*row_size)(const void *la, size_t j);
  /* the chart at the stored G (and M, stored first), kept or chosen anew by the hysteresis
   * (the best one with force_best); reuse: the factors are at this G already */
  int (*choose)(void *la, int force_best, int reuse, sdae_mbs_choice *choice);
  /* the chart's factors at the stored G (SDAE_OK or an error), and G_D's alone (Newton's
   * matrix) */
  int (*factor)(void *la);
  int (*gd_factor)(void *la);
  /* the current chart: dep (n_c), q_D's coordinates in the order of G_D's unknowns, and ind
   * (n_f), q_I's ascending */
  void (*split)(const void *la, const size_t **dep, const size_t **ind);
  /* x = G_D^-1 rhs; dq_D (n_c) = G_D^-1 dxi - G_D^-1 G_I dq_I, the chart's linearization, dq
   * (n_q) read at q_I alone; out (n_f) = W^T y */
  void (*gd_solve)(void *la, const double *rhs, double *x);
  void (*move)(void *la, const double *dxi, const double *dq, double *dq_D);
  void (*wt)(void *la, const double *y, double *out);
  /* the velocity's system at the stored G and M factored (its factors reused where they hold
   * with reuse), and v (n_q) with G v = g, W^T M v = p; seed: at a step's start whose v is
   * given, factored with what the momentum rate needs there, where the choice has not (v may
   * be overwritten) */
  int (*velocity_factor)(void *la, int reuse);
  int (*velocity)(void *la, const double *g, const double *p, double *v);
  int (*seed)(void *la, int reuse, const double *g, const double *p, double *v);
  /* out (n_f) = W^T (F + (dM/dt) v) + (dW/dt)^T M v at the point (q, v) last solved for; F
   * (n_q) holds the applied force and serves as scratch */
  int (*momentum_rate)(void *la, double t, const double *q, const double *v, double *F,
                       double *out);
  /* the energy v^T M v / 2 + V(q) with the stored M; out (n_q) = D(t, q) x, the damping's
   * product (the energy structure of the discrete gradients: R = W^T D W by products) */
  int (*energy)(void *la, double t, const double *q, const double *v, double *E);
  int (*damping_times)(void *la, double t, const double *q, const double *x, double *out);
  /* optional (NULL: the implicit maps' Newton forms its own matrix): the velocity's factors at
   * the point kept as Newton's (newton_keep), and with them w (n_q) such that G w = 0,
   * W^T M w = b (b n_f): the reduced mass solved for at the cost of the factors' nonzeros */
  void (*newton_keep)(void *la);
  int (*newton_velocity)(void *la, const double *b, double *w);
  /* the chart: its dependent coordinates ascending (SDAE_ERR_CHART before the first), and its
   * measure where it was chosen or kept */
  int (*chart)(const void *la, size_t *dependent);
  double (*measure)(const void *la);
  /* what the next step depends on, counted, written or read (core/bytes.h); after a read,
   * whether it is whole (indices in range) */
  void (*state)(void *la, sdae_bytes *b);
  int (*state_read)(void *la);
  /* the quantities at a state, on the back-end's own scratch (sdae_mbs_xi, _energy, _lambda) */
  int (*query_xi)(void *la, double t, const double *q, const double *v, double *xi);
  int (*query_energy)(void *la, double t, const double *q, const double *v, double *E);
  int (*query_lambda)(void *la, double t, const double *q, const double *v, double *lambda);
} sdae_mbs_linalg;

#endif /* STABDAE_SRC_MBS_MBS_LINALG_H */
