/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae's checks (layer: analysis), the one place for them: is a normal form typed by hand
 * (q0, Q) consistent with the original DAE xdot = f(x) + g(x) lambda, 0 = h(x) and its
 * coordinates z = Phi(x) = (xi, mu) (sdae_check_model)? Are the derivatives a mechanism gives
 * those of its callbacks (sdae_mbs_check)? */
#ifndef STABDAE_CHECK_H
#define STABDAE_CHECK_H

#include <stddef.h>

#include <stabdae/base.h>
#include <stabdae/dae.h>
#include <stabdae/mbs.h>
#include <stabdae/model.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sdae_check_kind {
  SDAE_CHECK_INVERSE = 0, /* Phi(Phi^-1(z)) = z */
  SDAE_CHECK_LG = 1,      /* L_g phi_j = 0 for mu and all but the last of each xi chain */
  SDAE_CHECK_CHAIN = 2,   /* L_f xi_j = xi_{j+1} along each chain */
  SDAE_CHECK_DYNAMICS = 3 /* q0(mu) + Q(xi, mu) xi = L_f mu(Phi^-1(xi, mu)) */
} sdae_check_kind;

typedef struct sdae_check_report {
  size_t points;      /* points checked */
  double residual[4]; /* the worst residual of each check, relative to its terms' size */
  int worst_check;    /* the check with the largest residual */
  size_t worst_index; /* the component of z where it was found */
  int consistent;     /* every residual <= tol */
} sdae_check_report;

/* At npoints random points of the box lo <= z <= hi (seeded, reproducible) checks the model
 * against the DAE. Jacobians of Phi by central differences unless Phi_jac is given; Phi^-1 by
 * Newton from x = z unless Phi_inv is given. The relative degrees come from the model's
 * rel_degree (one chain of n_xi when it has none; SDAE_ERR_REL_DEGREE when they are not
 * n_constraints values >= 1 summing to n_xi). worst_z (n values, or NULL) receives the
 * point where the largest residual was found; *r is written whole. */
SDAE_API int sdae_check_model(const sdae_model *model, const sdae_dae *dae, double t,
                              const double *lo, const double *hi, size_t npoints,
                              unsigned long seed, double tol, double *worst_z,
                              sdae_check_report *r);

/* sdae_check_model with its workspace (one block, given back before the call returns) from the
 * allocator a; NULL means malloc and free. SDAE_ERR_NOMEM when there is no room, and then *r is
 * untouched. */
SDAE_API int sdae_check_model_with(const sdae_model *model, const sdae_dae *dae, double t,
                                   const double *lo, const double *hi, size_t npoints,
                                   unsigned long seed, double tol, double *worst_z,
                                   const sdae_allocator *a, sdae_check_report *r);

/* ---- a mechanism's derivatives ------------------------------------------------------- */

/* The derivatives a mechanism gives, each compared by sdae_mbs_check with differences of the
 * callbacks it derives from. */
typedef enum sdae_mbs_derivative {
  SDAE_MBS_JACOBIAN = 0,         /* jacobian against c */
  SDAE_MBS_CONSTRAINT_T = 1,     /* constraint_t against c in t */
  SDAE_MBS_MASS_DOT_V = 2,       /* mass_dot_v against M along (1, v) */
  SDAE_MBS_JACOBIAN_DOT = 3,     /* jacobian_dot against jacobian along (1, v) */
  SDAE_MBS_CONSTRAINT_T_DOT = 4, /* constraint_t_dot against constraint_t along (1, v) */
  SDAE_MBS_FORCE = 5             /* force against -dV/dq, the Lagrangian's velocity terms and
                                  * -D v, where a potential is given */
} sdae_mbs_derivative;
#define SDAE_MBS_DERIVATIVES 6

/* the states sdae_mbs_check compares at: the one given and two around it */
#define SDAE_MBS_CHECK_STATES 3

typedef struct sdae_mbs_check_report {
  unsigned checked;                      /* bit k set: derivative k was given and compared */
  double mismatch[SDAE_MBS_DERIVATIVES]; /* each one's worst entry: what |given - differences|
                                          * exceeds the differences' rounding by, relative to
                                          * the entry (0 when not given; Inf for a NaN) */
  int worst;          /* the derivative with the largest mismatch; -1: none given */
  size_t worst_index; /* its entry (row-major) where that mismatch is */
  int consistent;     /* every mismatch <= tol */
  int state;          /* where the worst is: 0 the state given, 1 or 2 one moved around it
                       * (a mechanism with patterns); -1: none given */
  /* the constraints' rank at each state checked (0 at a state not checked), as
   * sdae_mbs_redundant counts it, and the least independence among the rows it counts there:
   * near SDAE_MBS_CHART_MIN, constraints nearly dependent (a modelling question) */
  size_t rank[SDAE_MBS_CHECK_STATES];
  double independence;
} sdae_mbs_check_report;

/* Compares every derivative the mechanism gives with fourth-order central differences of the
 * callbacks it derives from, at the state (t, q, v) (choose one away from symmetries, where a
 * wrong sign would show), and for a mechanism with patterns also the derivatives a pattern
 * shapes (G and Gdot, Mdot v and the force) at two states around it (q and v moved by 1e-3
 * (1 + |x_i|) in fixed directions, so that an entry zero at the state alone, which a pattern
 * may leave out, shows), and reports the worst mismatch and where. Entry by entry, so a row
 * of large entries hides no wrong small one; the differences' rounding is allowed for, so a
 * derivative that vanishes at the state (a force at equilibrium) is no false alarm. Smooth
 * callbacks agree to about 1e-9: tol = 1e-6 separates a right derivative from a wrong one.
 * With a jacobian_pattern, an entry of G that the differences of c show nonzero outside it is a
 * mismatch of SDAE_MBS_JACOBIAN there (the given G is zero there). An entry outside a
 * mass_pattern is never written, so it shows only through what M's derivatives change: the
 * checks of mass_dot_v and of the force.
 * On SDAE_OK *r is written whole; otherwise it is untouched and the status says why:
 * SDAE_ERR_NULL (sys, q, v, r, a required callback, jacobian_dot without jacobian,
 * constraint_t_dot without constraint_t, or jacobian_pattern without jacobian), SDAE_ERR_DIM,
 * SDAE_ERR_PATTERN, SDAE_ERR_PARAM (tol not positive, a
 * state not finite), SDAE_ERR_NOMEM, SDAE_ERR_OVERFLOW, or a callback's failure
 * (SDAE_ERR_CALLBACK_*, SDAE_ERR_NONFINITE). With its workspace (one block, given back before
 * it returns) from the allocator a in sdae_mbs_check_with (NULL: malloc). */
SDAE_API int sdae_mbs_check(const sdae_mbs *sys, double t, const double *q, const double *v,
                            double tol, sdae_mbs_check_report *r);
SDAE_API int sdae_mbs_check_with(const sdae_mbs *sys, double t, const double *q, const double *v,
                                 double tol, const sdae_allocator *a, sdae_mbs_check_report *r);

/* Redundant constraints at (t, q): G's rows scaled to unit length (G from jacobian, or
 * fourth-order differences of c without it), GSL's QR with column pivoting of G^T orders the
 * constraints so that each is the farthest from the span of those before it; the k-th one's
 * distance, R's diagonal relative to the first, is the sine of its angle to that span. *rank
 * counts the rows down to the first below SDAE_MBS_CHART_MIN (the chart's limit: at or under it
 * a constraint is taken as dependent on those before it, redundant); rows (n_c, may be NULL)
 * receives the order, the first *rank independent, the rest redundant on them; *independence
 * (may be NULL) the least sine among the independent ones. Any n_c >= 1, n_c >= n_q included.
 * SDAE_ERR_NULL, SDAE_ERR_DIM (n_c or n_q zero), SDAE_ERR_PATTERN, SDAE_ERR_PARAM (t or q not
 * finite), SDAE_ERR_NOMEM, SDAE_ERR_OVERFLOW or a callback's failure, the outputs untouched;
 * workspace from the allocator a in sdae_mbs_redundant_with (NULL: malloc). */
SDAE_API int sdae_mbs_redundant(const sdae_mbs *sys, double t, const double *q, size_t *rank,
                                size_t *rows, double *independence);
SDAE_API int sdae_mbs_redundant_with(const sdae_mbs *sys, double t, const double *q,
                                     const sdae_allocator *a, size_t *rank, size_t *rows,
                                     double *independence);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_CHECK_H */
