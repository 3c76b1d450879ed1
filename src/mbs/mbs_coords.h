/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a mechanism in the current chart (mbs_coords.c): xi = per constraint
 * (c_j, G_j v + dc_j/dt), mu = (q_I, W^T M v), Phi^-1 and the mu-dynamics. It owns the point, the
 * configuration and velocity Phi^-1 found last (or the step's start) with what is known there,
 * and keeps it for the next call at the same (t, xi, mu). It reads the chart and has it factor
 * the point's G; it never changes the chart's choice. */
#ifndef STABDAE_SRC_MBS_MBS_COORDS_H
#define STABDAE_SRC_MBS_MBS_COORDS_H

#include "core/arena.h"
#include "core/newton.h"
#include "mbs_chart.h"
#include "mbs_eval.h"

typedef struct sdae_mbs_coords {
  sdae_mbs_eval *eval;
  sdae_mbs_atlas *chart;
  size_t n_q, n_c, n_f;
  unsigned newton_max_iter; /* Phi^-1's Newton: the options' cap */
  /* the point */
  double *q, *v;  /* n_q each */
  double *c, *ct; /* n_c each */
  double *G;      /* n_c x n_q: dc/dq */
  double *M;      /* n_q x n_q */
  double *Mr;     /* n_f x n_f: the reduced mass W^T M W, factored (Phi^-1) */
  int valid;      /* the point is Phi^-1(key_t, key) */
  int at_start;   /* the step started at the point (its G, dc/dt and M kept) */
  double key_t;
  double *key; /* 2 n_q: (xi, mu) */
  /* the base: the configuration Phi^-1 converged at last (first the step's start), where the
   * chart was factored; the next solve is predicted from it */
  double *base_q;           /* n_q */
  double *base_c, *base_ct; /* n_c each: c (xi's c-part) and dc/dt there */
  double base_t;
  int base_here; /* the point's q, G, dc/dt, M and reduced mass are the base's */
  /* scratch, one array a role */
  double *Mv;             /* n_q: M v at the point */
  double *res, *dq_D;     /* n_c each: the prediction's (and the finish's) c - xi_c, update */
  double *q_D;            /* n_c: Phi^-1's unknowns, q's dependent part */
  double *dq_I;           /* n_f: q_I's move from the base */
  double *Y;              /* n_q: a column of M W */
  double *rhs, *z_D;      /* n_c each: G_D z_D = xi's velocity part - dc/dt */
  double *Mz;             /* n_q: M z */
  double *v_I;            /* n_f: v's independent part */
  double *F, *Gdot, *Mdv; /* the mu-dynamics: F + (dM/dt) v (n_q), dG/dt (n_c x n_q),
                             (dM/dt) v (n_q) */
  double *GdW, *X;        /* n_c each: a column of (dG/dt) W, G_D^-1 of it */
  double *dW;             /* n_f: X^T (M v)_D, minus (dW/dt)^T M v */
  sdae_newton newton;     /* Phi^-1's: a chord with G_D's factors kept from the base */
  /* Newton iterations of Phi^-1 since the step's start, reported to the stepper, which
   * commits them when the step succeeds */
  unsigned long phi_inv_iters;
} sdae_mbs_coords;

/* wired to the callbacks and the chart; the arrays come from sdae__mbs_coords_carve */
void sdae__mbs_coords_init(sdae_mbs_coords *co, sdae_mbs_eval *eval, sdae_mbs_atlas *chart,
                           unsigned newton_max_iter);
void sdae__mbs_coords_carve(sdae_mbs_coords *co, sdae_arena *a);

/* xi (2 n_c) of (t, q, v) at a step's start, the same in every chart; leaves c, G and dc/dt
 * at q in the point, and the iterations' count at zero.
 * At the point Phi^-1 left (the last step's end, t within rounding) G and dc/dt are kept: c
 * alone is evaluated, and _begin keeps M. */
int sdae__mbs_coords_xi(sdae_mbs_coords *co, double t, const double *q, const double *v,
                        double *xi);
/* a step's start at (t, q, v), the chart factored at q: M at q into the point (SDAE_ERR_MASS
 * unless symmetric), mu (2 n_f) in the chart, and q as Phi^-1's start */
int sdae__mbs_coords_begin(sdae_mbs_coords *co, double t, const double *q, const double *v,
                           double *mu);
/* the floors of xi (2 n_c) at the step's start (t, q, v), after sdae__mbs_coords_xi: per
 * constraint, a few eps times the size of the terms of c_j and of G_j v + dc_j/dt, below which
 * they are rounding (derive.c skips their columns) */
void sdae__mbs_coords_floors(const sdae_mbs_coords *co, const double *q, const double *v,
                             double *floor);
/* the step's start (t, q, v) taken as Phi^-1(t, 0, mu) (mu its coordinates), once every xi_i
 * is at its floor: the two differ by rounding (docs/front-ends.md, the cost of a step); G, dc/dt
 * and M at q from sdae__mbs_coords_xi and _begin, the reduced mass formed in the current chart */
int sdae__mbs_coords_seed(sdae_mbs_coords *co, double t, const double *q, const double *v,
                          const double *mu);
/* the point's q, v = Phi^-1(t, xi, mu), with G, M and the chart's W there */
int sdae__mbs_phi_inv(sdae_mbs_coords *co, double t, const double *xi, const double *mu);
/* the same for the state handed to the user (the step's end): its q_D finished by a step of
 * Newton from 1e-12 away, so that the rounding left in c does not keep one sign step after
 * step (one more call of c) */
int sdae__mbs_phi_inv_state(sdae_mbs_coords *co, double t, const double *xi, const double *mu);
/* the mu-dynamics (q_I', d/dt W^T M v) at the point Phi^-1 left, n_mu values */
int sdae__mbs_mu_dot(sdae_mbs_coords *co, double t, double *out);
/* the point Phi^-1 left (the last step's end, what the next step's start keeps of it), counted,
 * written or read (core/bytes.h) */
void sdae__mbs_coords_state(sdae_mbs_coords *co, sdae_bytes *b);

#endif /* STABDAE_SRC_MBS_MBS_COORDS_H */
