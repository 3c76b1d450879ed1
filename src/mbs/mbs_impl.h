/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanical front-end's internals (<stabdae/mbs.h>): the stepper and the modules that
 * share it. Data flows one way: the mechanism's callbacks (mbs_eval.c) -> the chart
 * (mbs_chart.c) -> the coordinates Phi, Phi^-1 and the mu-dynamics (mbs_coords.c) -> the normal
 * form handed to the stepper (mbs_model.c) -> the step in (q, v) (mbs.c). */
#ifndef STABDAE_SRC_MBS_MBS_IMPL_H
#define STABDAE_SRC_MBS_MBS_IMPL_H

#include <stabdae/mbs.h>

#include "core/alloc.h"
#include "core/arena.h"
#include "core/callback.h"
#include "core/lu.h"
#include "model/derive.h"

/* What is known at one configuration in the current chart, left by Phi^-1 or by the chart's
 * factorization for the mu-dynamics there. */
typedef struct sdae_mbs_point {
  double *q, *v;   /* n_q each */
  double *c, *ct;  /* n_c each */
  double *G;       /* n_c x n_q: dc/dq */
  double *GD;      /* G_D's LU: small dense (n_c <= SDAE_SMALL_DENSE) or GSL's band format */
  unsigned *piv;   /* n_c */
  double *A;       /* n_c x n_f: G_D^-1 G_I, so that W = P [-A; I] */
  double *W;       /* n_q x n_f: dq/dq_I, spans ker G */
  double *M;       /* n_q x n_q */
} sdae_mbs_point;

struct sdae_mbs_stepper {
  sdae_mbs sys;
  sdae_options opt;
  size_t n_q, n_c, n_f;
  sdae_model model;      /* the normal form in the current chart, params = this stepper */
  sdae_stepper *inner;   /* its stepper, in this block */
  sdae_derive derive;    /* q0 and Q from the mu-dynamics */
  sdae_block block;      /* what sdae_mbs_stepper_alloc_with allocated */
  sdae_mbs_stats stats;
  int status;            /* the status behind the last failing callback of the normal form */
  int energy_map;        /* the map conserves H: the constraints must not depend on t */
  /* the chart: dependent and independent coordinates, ascending */
  int have_chart;
  int kept;              /* the last choice kept the current chart over a better proposal */
  int force_best;        /* take the best chart whatever the hysteresis (a retry) */
  size_t *dep, *ind;     /* n_c, n_f */
  size_t *perm;          /* n_q: QRPT's column permutation, a candidate chart */
  size_t *cand_dep, *cand_ind;
  double *qr, *tau, *norm; /* QRPT's work: n_c x n_q, n_c, n_q */
  /* the configuration Phi^-1 found last, kept for the next call at the same (t, xi, mu) */
  sdae_mbs_point pt;
  int pt_valid;
  double pt_t;
  double *pt_key;        /* 2 n_q: (xi, mu) */
  double *q_base;        /* n_q: where Phi^-1's Newton starts (the step's q) */
  /* scratch */
  double *xi, *mu;       /* 2 n_c, 2 n_f: the step's state in the chart */
  double *zero;          /* 2 n_c zeros: xi on the manifold */
  double *Mr, *R;        /* n_f x n_f: the reduced mass W^T M W, the damping W^T D W */
  double *rf;            /* n_f */
  size_t *saved;         /* n_q: the chart before a step, given back when the step fails */
  /* differences: the shifted q (along the motion, and for G), G, M, c, dc/dt there */
  double *fd_q, *fd_qj, *fd_G, *fd_M, *fd_c, *fd_ct;
  double *Gdot, *Mdv, *gdot; /* along (1, v): n_c x n_q, n_q, n_c */
  double *fd_Gt, *fd_Mdvt, *fd_gdott; /* their parts along t alone, at late times */
  double *r1, *r2, *r3;  /* n_q each */
  double *X;             /* n_c x n_f */
  double *LY, *LA;       /* lambda: n_c x n_q (G M^-1), n_c x n_c */
  double *query_xi;      /* 2 n_c: sdae_mbs_xi's result before it is checked */
};

/* ---- mbs_eval.c: the mechanism's callbacks, their status and values checked, and the
 * derivatives the mechanism may leave out, by fourth-order central differences ---- */
int sdae__mbs_mass(sdae_mbs_stepper *s, double t, const double *q, double *M);
int sdae__mbs_force(sdae_mbs_stepper *s, double t, const double *q, const double *v, double *F);
int sdae__mbs_constraint(sdae_mbs_stepper *s, double t, const double *q, double *c);
int sdae__mbs_jacobian(sdae_mbs_stepper *s, double t, const double *q, double *G);
int sdae__mbs_constraint_t(sdae_mbs_stepper *s, double t, const double *q, double *ct);
int sdae__mbs_potential(sdae_mbs_stepper *s, double t, const double *q, double *V);
int sdae__mbs_damping(sdae_mbs_stepper *s, double t, const double *q, double *D);
/* derivatives along (1, v) in (t, q), v held fixed: Gdot = d/ds G (n_c x n_q), Mdv = (d/ds M) v
 * (NULL: not wanted) and gdot = d/ds (G v + dc/dt) (NULL: not wanted) */
int sdae__mbs_along(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                    double *Gdot, double *Mdv, double *gdot);

/* ---- mbs_chart.c ---- */
/* from the last and first diagonal entries of the QR of G (rows of unit length), n_q columns:
 * SDAE_ERR_RANK when last <= n_q eps first, SDAE_ERR_CHART when below SDAE_MBS_CHART_MIN first */
int sdae__mbs_chart_verdict(double last, double first, size_t n_q);
/* the best chart at (t, q) by column-pivoted QR of G = s->pt.G (already evaluated there), kept
 * unless it beats the current one by SDAE_MBS_CHART_FACTOR; SDAE_ERR_RANK, SDAE_ERR_CHART */
int sdae__mbs_choose_chart(sdae_mbs_stepper *s);
/* G_D's LU, A = G_D^-1 G_I and W from s->pt.G in the current chart; SDAE_ERR_RANK when G_D is
 * singular; *measure = max |A| (may be NULL) */
int sdae__mbs_chart_factor(sdae_mbs_stepper *s, double *measure);
/* G_D's LU alone from s->pt.G in the current chart (Newton's matrix); SDAE_ERR_RANK */
int sdae__mbs_gd_factor(sdae_mbs_stepper *s);
/* x = G_D^-1 rhs (n_c values) with the point's factors */
void sdae__mbs_gd_solve(const sdae_mbs_stepper *s, const double *rhs, double *x);
/* out (n_f) = W^T u for u (n_q) */
void sdae__mbs_Wt(const sdae_mbs_stepper *s, const double *u, double *out);

/* ---- mbs_coords.c ---- */
/* xi (2 n_c) of (t, q, v), the same in every chart; leaves c, G and dc/dt at q in s->pt */
int sdae__mbs_xi_at(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                    double *xi);
/* mu (2 n_f) of (t, q, v) in the current chart, factored at q (sdae__mbs_chart_factor), with
 * M at q in s->pt */
void sdae__mbs_mu_at(sdae_mbs_stepper *s, const double *q, const double *v, double *mu);
/* s->pt.q, s->pt.v = Phi^-1(t, xi, mu), with the point's G, W, M there */
int sdae__mbs_phi_inv(sdae_mbs_stepper *s, double t, const double *xi, const double *mu);
/* the mu-dynamics (q_I', d/dt W^T M v) at the point Phi^-1 left, n_mu values */
int sdae__mbs_mu_dot(sdae_mbs_stepper *s, double t, double *out);
/* forgets the configuration and the G(0, mu) kept: after a chart switch or a new step */
void sdae__mbs_forget(sdae_mbs_stepper *s);

/* ---- mbs_model.c: the normal form handed to the stepper ---- */
void sdae__mbs_model(sdae_mbs_stepper *s);
/* the arrays of q0 and Q's rule (counted, or handed out) */
void sdae__mbs_derive_carve(sdae_mbs_stepper *s, sdae_arena *a);

#endif /* STABDAE_SRC_MBS_MBS_IMPL_H */
