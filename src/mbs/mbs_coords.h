/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates of a mechanism, written once over a linear-algebra back-end (mbs_linalg.h):
 * xi = per constraint (c_j, G_j v + dc_j/dt), mu = (q_I, W^T M v) in the back-end's chart,
 * Phi^-1 and the mu-dynamics (mbs_coords.c). It owns the point, the configuration and velocity
 * Phi^-1 found last (or the step's start), and keeps it for the next call at the same
 * (t, xi, mu); the back-end owns G and M there, the chart and the factors. */
#ifndef STABDAE_SRC_MBS_MBS_COORDS_H
#define STABDAE_SRC_MBS_MBS_COORDS_H

#include "core/arena.h"
#include "core/bytes.h"
#include "core/newton.h"
#include "mbs_eval.h"
#include "mbs_linalg.h"

/* what one call starts a step with: the stepper's arrays, filled, and what became of the chart */
typedef struct sdae_mbs_start {
  double *xi, *mu;        /* 2 n_c, 2 n_f: the state in the chart */
  double *floor;          /* 2 n_c: xi's floors, below which it is rounding (derive.c) */
  sdae_mbs_choice choice; /* the chart switched, or kept by the hysteresis */
  int rows_switched;      /* redundant constraints: the rows chosen were replaced */
} sdae_mbs_start;

typedef struct sdae_mbs_coords {
  sdae_mbs_eval *eval;
  const sdae_mbs_linalg *linalg; /* the back-end's functions, and its parts */
  void *la;
  size_t n_q, n_c, n_f;
  unsigned newton_max_iter; /* Phi^-1's Newton: the options' cap */
  int energy_map;           /* the map conserves H: the constraints must not depend on t */
  const size_t *dep, *ind;  /* the back-end's split (mbs_linalg.h), as it was last asked */
  /* the point */
  double *q, *v;  /* n_q each */
  double *c, *ct; /* n_c each */
  int valid;      /* the point is Phi^-1(key_t, key) */
  int at_start;   /* the step started at the point (its G, dc/dt and M kept) */
  /* the back-end's factors are at the point a state's Phi^-1 left (fresh; not in the state's
   * bytes, so that a state set clears it), and the step's start is that point, where they
   * serve as they are (reuse) */
  int fresh, reuse;
  double key_t;
  double *key; /* 2 n_q: (xi, mu) */
  /* the base: the configuration Phi^-1 converged at last (first the step's start), where the
   * chart was factored; the next solve is predicted from it */
  double *base_q;           /* n_q */
  double *base_c, *base_ct; /* n_c each: c (xi's c-part) and dc/dt there */
  double base_t;
  int base_here; /* the point's q, G, dc/dt, M and factors are the base's */
  /* scratch, one array a role */
  double *Mv;         /* n_q: M v at the step's start */
  double *res, *dq_D; /* n_c each: the prediction's (and the finish's) c - xi_c, update */
  double *q_D;        /* n_c: Phi^-1's unknowns, q's dependent part */
  double *dq;         /* n_q: q_I's move from the base, zero at q_D */
  double *g;          /* n_c: xi's velocity part - dc/dt, what G v must be */
  double *F, *F_in;   /* n_q each: the applied force, the forces from outside the Lagrangian */
  double *w, *Dw;     /* n_q each: W x and D W x (the damping's product), Newton's velocity */
  double newton_a;    /* the implicit maps' linear solve: its coefficient where set up */
  double *zero;       /* 2 n_c zeros: xi on the manifold */
  sdae_newton newton; /* Phi^-1's: a chord with G_D's factors kept from the base */
  /* Newton iterations of Phi^-1 since the step's start, reported to the stepper, which
   * commits them when the step succeeds */
  unsigned long phi_inv_iters;
} sdae_mbs_coords;

/* wired to the callbacks, the back-end and the options (the back-end's init's status); the
 * arrays come from sdae__mbs_coords_carve, which returns what the back-end's analysis at the
 * build refuses */
int sdae__mbs_coords_init(sdae_mbs_coords *co, sdae_mbs_eval *eval, const sdae_mbs_linalg *linalg,
                          void *la, const sdae_options *o);
/* the back-end's analysis in scratch, before a block is measured (its refusal) */
int sdae__mbs_coords_analyse(sdae_mbs_coords *co, const sdae_scratch *scratch);
int sdae__mbs_coords_carve(sdae_mbs_coords *co, sdae_arena *a);

/* a step's start at (t, q, v): c, G and dc/dt there (at the point Phi^-1 left, the last step's
 * end, G, dc/dt and M are kept: c alone is evaluated), the chart chosen or kept (the best one
 * with force_best), mu, xi and xi's floors (per constraint, a few eps times the size of the
 * terms of c_j and of G_j v + dc_j/dt, below which they are rounding: derive.c skips their
 * columns); on the manifold to rounding, (t, q, v) taken as Phi^-1(t, 0, mu) */
int sdae__mbs_coords_start(sdae_mbs_coords *co, double t, const double *q, const double *v,
                           int force_best, sdae_mbs_start *st);
/* the start's first part: xi (2 n_c) of (t, q, v), the same in every chart, with c, G and dc/dt
 * at q left in the point and the back-end; and xi's floors there */
int sdae__mbs_coords_xi(sdae_mbs_coords *co, double t, const double *q, const double *v,
                        double *xi);
void sdae__mbs_coords_floors(const sdae_mbs_coords *co, const double *q, const double *v,
                             double *floor);
/* the point's q, v = Phi^-1(t, xi, mu), with G, M and the chart's factors there */
int sdae__mbs_phi_inv(sdae_mbs_coords *co, double t, const double *xi, const double *mu);
/* the same for the state handed to the user (the step's end): its q_D finished by a step of
 * Newton from 1e-12 away, so that the rounding left in c does not keep one sign step after
 * step (one more call of c), and M symmetric there */
int sdae__mbs_phi_inv_state(sdae_mbs_coords *co, double t, const double *xi, const double *mu);
/* the mu-dynamics (q_I', d/dt W^T M v) at the point Phi^-1 left, n_mu values */
int sdae__mbs_mu_dot(sdae_mbs_coords *co, double t, double *out);
/* the point's q and v copied out */
void sdae__mbs_coords_point(const sdae_mbs_coords *co, double *q, double *v);

/* the energy structure at Phi^-1(t, 0, mu), for the discrete gradients: the energy, out (n_f) =
 * R x with R = W^T D W (zero without damping) and W^T F_in (n_f) */
int sdae__mbs_energy_on(sdae_mbs_coords *co, double t, const double *mu, double *H);
int sdae__mbs_damping_on(sdae_mbs_coords *co, double t, const double *mu, const double *x,
                         double *out);
int sdae__mbs_input_on(sdae_mbs_coords *co, double t, const double *mu, double *Bu);

/* The implicit maps' linear solve where the back-end keeps Newton's factors
 * (sdae__mbs_coords_solves): I - a J, J = d(q_I', p')/d(q_I, p), approximated by the part of a
 * free motion, q_I' = M_r^-1 p with M_r = W^T M W, the forces' and the geometry's derivatives
 * left out; set up at Phi^-1(t, 0, mu) (the velocity's factors there kept), and solved,
 * z_p = r_p, z_q = r_q + a M_r^-1 r_p, at the cost of those factors' nonzeros */
int sdae__mbs_coords_solves(const sdae_mbs_coords *co);
int sdae__mbs_lsetup(sdae_mbs_coords *co, double t, const double *mu, double a);
int sdae__mbs_lsolve(sdae_mbs_coords *co, const double *r, double *z);

/* what the next step depends on (the back-end's chart and matrices, the point), counted,
 * written or read (core/bytes.h); after a read, whether it is whole, and when it is, the
 * factors not in the bytes marked stale */
void sdae__mbs_coords_state(sdae_mbs_coords *co, sdae_bytes *b);
int sdae__mbs_coords_state_read(sdae_mbs_coords *co);

#endif /* STABDAE_SRC_MBS_MBS_COORDS_H */
