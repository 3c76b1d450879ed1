/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a mechanism behind one interface: a type is a static const table of
 * functions, as a map's (maps/map.h), over parts that own their state. Two types: the dense
 * coordinates (mbs_dense_type.c: the chart by QR, Phi^-1 with the reduced mass) and a sparse
 * mechanism's (mbs_sparse_type.c: the chart by sparse LU, the saddle-point system by LDL). The
 * stepper (mbs.c), the normal form (mbs_model.c) and the state's bytes (mbs_state.c) call
 * them through the table alone. */
#ifndef STABDAE_SRC_MBS_MBS_TYPE_H
#define STABDAE_SRC_MBS_MBS_TYPE_H

#include <stabdae/stabdae.h>

#include "core/arena.h"
#include "core/bytes.h"
#include "mbs_eval.h"

/* what one call starts a step with: the stepper's arrays, filled, and what became of the chart */
typedef struct sdae_mbs_start {
  double *xi, *mu; /* 2 n_c, 2 n_f: the state in the chart */
  double *floor;   /* 2 n_c: xi's floors, below which it is rounding (derive.c) */
  int switched;    /* the chart was replaced */
  int kept;        /* the chart was kept over a better one by the hysteresis */
} sdae_mbs_start;

/* what a step's parts did, committed to the statistics by the stepper when the step succeeds */
typedef struct sdae_mbs_report {
  unsigned long phi_inv_iters; /* Newton iterations of Phi^-1 since the step's start */
  double measure;              /* the current chart's measure where it was chosen or kept */
} sdae_mbs_report;

typedef struct sdae_mbs_type {
  const char *name;
  /* the parts wired to the callbacks and the options, their arrays counted or handed out by
   * carve from the stepper's block; init refuses sizes the type cannot index
   * (SDAE_ERR_OVERFLOW), carve what its analysis at the build refuses */
  int (*init)(void *co, sdae_mbs_eval *eval, const sdae_options *o);
  int (*carve)(void *co, sdae_arena *a);
  /* a step's start at (t, q, v): the callbacks there, the chart chosen or kept (the best one
   * with force_best), xi, mu and xi's floors; on the manifold to rounding, (t, q, v) taken as
   * Phi^-1(t, 0, mu) */
  int (*start)(void *co, double t, const double *q, const double *v, int force_best,
               sdae_mbs_start *st);
  /* the point Phi^-1(t, xi, mu); the state handed out (the step's end) finished to rounding */
  int (*phi_inv)(void *co, double t, const double *xi, const double *mu);
  int (*phi_inv_state)(void *co, double t, const double *xi, const double *mu);
  /* the mu-dynamics (q_I', p') at the point Phi^-1 left, 2 n_f values */
  int (*mu_dot)(void *co, double t, double *out);
  /* the point's q and v copied out; the step's counters and the chart's measure */
  void (*point)(const void *co, double *q, double *v);
  void (*report)(const void *co, sdae_mbs_report *r);
  /* the dependent coordinates, ascending (SDAE_ERR_CHART before the first step) */
  int (*chart)(const void *co, size_t *dependent);
  /* what the next step depends on, counted, written or read (core/bytes.h); after a read,
   * whether it is whole (indices in range), and when it is, the factors not in the bytes
   * marked stale */
  void (*state)(void *co, sdae_bytes *b);
  int (*state_read)(void *co);
  /* the quantities at a state, on the parts' own scratch (sdae_mbs_xi, _energy, _lambda) */
  int (*xi)(void *co, double t, const double *q, const double *v, double *xi);
  int (*energy)(void *co, double t, const double *q, const double *v, double *E);
  int (*lambda)(void *co, double t, const double *q, const double *v, double *lambda);
  /* the energy structure at Phi^-1(t, 0, mu), for the discrete gradients (NULL: none): the
   * energy, R = W^T D W (n_f x n_f) and W^T F_in (n_f) */
  int (*energy_on)(void *co, double t, const double *mu, double *H);
  int (*damping_on)(void *co, double t, const double *mu, double *R);
  int (*input_on)(void *co, double t, const double *mu, double *Bu);
} sdae_mbs_type;

/* every xi_i at its floor: on the manifold to rounding */
static inline int sdae__mbs_at_floors(const double *xi, const double *floor, size_t n_xi) {
  for (size_t i = 0; i < n_xi; i++)
    if (!(xi[i] >= -floor[i] && xi[i] <= floor[i])) return 0;
  return 1;
}

#endif /* STABDAE_SRC_MBS_MBS_TYPE_H */
