/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanism's callbacks (mbs_eval.c), every status and value checked, and the derivatives
 * the mechanism may leave out, by fourth-order central differences: the lowest part of the
 * mechanical front-end, which knows the user's sdae_mbs and nothing else. Its scratch serves its
 * difference stencils alone. */
#ifndef STABDAE_SRC_MBS_MBS_EVAL_H
#define STABDAE_SRC_MBS_MBS_EVAL_H

#include <stabdae/mbs.h>

#include "core/arena.h"
#include "core/bytes.h"
#include "core/pattern.h"

typedef struct sdae_mbs_eval {
  sdae_mbs sys; /* its patterns point at the copies below */
  size_t n_q, n_c;
  sdae_pattern mass_pattern, jacobian_pattern; /* the mechanism's, copied (nnz 0: none) */
  double *mass_values, *jacobian_values;       /* nnz each: what a callback with one writes */
  double *jac_q, *jac_c; /* G by differences: q moved in one coordinate, c there */
  double *ct_c;          /* dc/dt by differences: c at a moved t */
  double *along_q;       /* the derivatives along (1, v): q moved along v, and there */
  double *along_G, *along_M, *along_ct; /* G, M and dc/dt */
  double *along_Mv;                     /* a row of M times v, term by term */
  double *along_Gdot, *along_ctdot;     /* gamma's Gdot and d/ds dc/dt */
  double *t_Gdot, *t_Mdv, *t_ctdot;     /* the stencils' parts along t alone, at late times */
  double *input;                        /* n_q: the forces from outside the Lagrangian */
  int matrices; /* the stencils' matrices carved (G and M along the motion): not for a sparse
                 * mechanism's coordinates, which read the derivatives given */
  /* Redundant constraints (sys.rank < sys.n_c): the front-end sees the n_c = rank rows chosen
   * among the n_rows the callbacks write, rows (ascending; have: chosen once), each of them
   * gathered from all (c, G, dc/dt and their derivatives: all_c, all_G, all_ct); the choice's
   * QR (n_q x n_rows, its tau, norms and pivoting) and candidate */
  size_t n_rows;
  int have;
  size_t *rows, *cand;
  double *all_c, *all_G, *all_ct;
  double *qr, *qr_tau, *qr_norm;
  size_t *qr_perm;
} sdae_mbs_eval;

/* The n rows of G (row-major, n_q columns) listed (list NULL: the first n), scaled to unit
 * length, as the columns of qr (n_q x n), GSL's QR with column pivoting (tau min(n_q, n), norm
 * and perm n): perm orders the rows so that each is the farthest from the span of those before
 * it, and sdae__mbs_rows_sine's k-th value (R's diagonal relative to its first) is the sine of
 * its angle to that span (0 past min(n_q, n) or for a zero G). */
void sdae__mbs_rows_qr(const double *G, size_t n_q, const size_t *list, size_t n, double *qr,
                       double *tau, double *norm, size_t *perm);
double sdae__mbs_rows_sine(const double *qr, size_t n_q, size_t n, size_t k);
/* the rank the front-end steps: sys->rank, or n_c where it is 0 */
size_t sdae__mbs_rank(const sdae_mbs *sys);
/* some constraints are redundant: the rows are chosen */
int sdae__mbs_redundant(const sdae_mbs_eval *e);
/* At a step's start (t, q): the rank rows chosen from G there (all rows given or differenced,
 * scaled to unit length, QR with column pivoting of G^T), the current ones kept unless
 * force_best, their own least sine below SDAE_MBS_CHART_MIN, or the best's above theirs by
 * SDAE_MBS_CHART_FACTOR; *changed when the rows are new, *kept when kept over other rows.
 * SDAE_ERR_RANK when G's rank there is not rank (the best's r-th sine below
 * SDAE_MBS_CHART_MIN, or the next one's at or above it). Nothing to choose without redundancy. */
int sdae__mbs_select(sdae_mbs_eval *e, double t, const double *q, int force_best, int *changed,
                     int *kept);
/* G of every row at (t, q), given or differenced, into all_G */
int sdae__mbs_jacobian_all(sdae_mbs_eval *e, double t, const double *q);
/* the rows chosen (what the next step depends on), counted, written or read; and whether read
 * ones are a choice (ascending, each a row) */
void sdae__mbs_eval_state(sdae_mbs_eval *e, sdae_bytes *b);
int sdae__mbs_eval_valid(const sdae_mbs_eval *e);
/* with redundant constraints, xi of every row (2 n_rows values), per constraint as xi_of */
int sdae__mbs_xi_all(sdae_mbs_eval *e, double t, const double *q, const double *v, double *xi);

/* the mechanism's patterns: SDAE_ERR_NULL for a Jacobian's without jacobian, SDAE_ERR_PATTERN
 * for one that is not a pattern of its matrix */
int sdae__mbs_patterns_check(const sdae_mbs *sys);
/* the mechanism (copied) and its sizes; the arrays come from sdae__mbs_eval_carve, its patterns
 * copied there */
void sdae__mbs_eval_init(sdae_mbs_eval *e, const sdae_mbs *sys);
void sdae__mbs_eval_carve(sdae_mbs_eval *e, sdae_arena *a);

/* SDAE_ERR_PARAM for a t that is not finite, SDAE_ERR_STATE for a q or v that is not */
int sdae__mbs_state_ok(const sdae_mbs_eval *e, double t, const double *q, const double *v);

int sdae__mbs_mass(sdae_mbs_eval *e, double t, const double *q, double *M);
/* M, and SDAE_ERR_MASS unless it is symmetric to rounding: what the front-end needs of M itself
 * at every state it starts from or hands out (the reduced mass W^T M W positive definite is
 * checked where it is factored: a singular M, massless points, may still give one) */
int sdae__mbs_mass_symmetric(sdae_mbs_eval *e, double t, const double *q, double *M);
/* the applied force: F plus the forces from outside the Lagrangian (input_force) */
int sdae__mbs_force(sdae_mbs_eval *e, double t, const double *q, const double *v, double *F);
/* the forces from outside the Lagrangian alone (zero without input_force) */
int sdae__mbs_input_force(sdae_mbs_eval *e, double t, const double *q, const double *v, double *F);
int sdae__mbs_constraint(sdae_mbs_eval *e, double t, const double *q, double *c);
int sdae__mbs_jacobian(sdae_mbs_eval *e, double t, const double *q, double *G);
int sdae__mbs_constraint_t(sdae_mbs_eval *e, double t, const double *q, double *ct);
int sdae__mbs_potential(sdae_mbs_eval *e, double t, const double *q, double *V);
int sdae__mbs_damping(sdae_mbs_eval *e, double t, const double *q, double *D);

/* a sparse mechanism's matrices as their nonzeros in pattern order (the patterns given), and
 * (d/ds M) v, each callback given (mbs_sparse.c) */
int sdae__mbs_mass_values(sdae_mbs_eval *e, double t, const double *q, double *values);
int sdae__mbs_damping_values(sdae_mbs_eval *e, double t, const double *q, double *values);
int sdae__mbs_jacobian_values(sdae_mbs_eval *e, double t, const double *q, double *values);
int sdae__mbs_jacobian_dot_values(sdae_mbs_eval *e, double t, const double *q, const double *v,
                                  double *values);
int sdae__mbs_mass_dot_v(sdae_mbs_eval *e, double t, const double *q, const double *v, double *out);
/* d/ds (dc/dt)(t + s, q + s v): constraint_t_dot, or the difference stencil (n_c values) */
int sdae__mbs_ct_dot(sdae_mbs_eval *e, double t, const double *q, const double *v, double *out);

/* derivatives along (1, v) in (t, q), v held fixed: Gdot = d/ds G (n_c x n_q), Mdv = (d/ds M) v
 * and gdot = d/ds (G v + dc/dt); each may be NULL (not wanted). The mechanism's jacobian_dot,
 * mass_dot_v and constraint_t_dot when given, a difference stencil for each one left out. */
int sdae__mbs_along(sdae_mbs_eval *e, double t, const double *q, const double *v, double *Gdot,
                    double *Mdv, double *gdot);

/* xi (2 n_c) from c, G and dc/dt at q: per constraint (c_j, G_j v + dc_j/dt) */
void sdae__mbs_xi_compose(const sdae_mbs_eval *e, const double *v, const double *c, const double *G,
                          const double *ct, double *xi);
/* xi (2 n_c) of (t, q, v): per constraint (c_j, G_j v + dc_j/dt), the same in every chart; c,
 * G and dc/dt at q left in c, G, ct */
int sdae__mbs_xi_of(sdae_mbs_eval *e, double t, const double *q, const double *v, double *c,
                    double *G, double *ct, double *xi);

/* the energy v^T M v / 2 + V(q) with M at q given (V = 0 without potential) */
int sdae__mbs_energy_of(sdae_mbs_eval *e, double t, const double *q, const double *v,
                        const double *M, double *E);

#endif /* STABDAE_SRC_MBS_MBS_EVAL_H */
