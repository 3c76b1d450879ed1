/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The baseline of the price of zero drift: the classical RK4 on the index-1 form of a mechanism
 * of <stabdae/mbs.h>, from its own callbacks. y = (q, v), q' = v, v' = a, with a from the KKT
 * system of every stage
 *
 *     [M  G^T] [a     ]   [F     ]
 *     [G  0  ] [lambda] = [-gamma],    gamma = Gdot v + d/ds c_t(t + s, q + s v),
 *
 * G v' + gamma = 0 being the derivative of G v + c_t = 0 along the motion (1, v) with v fixed.
 * Nothing holds the map on c = 0: its drift grows with its local errors, which is what the
 * front-end's higher cost per step buys off. Also the reference both are measured against: the
 * same index-1 ODE by GSL's adaptive rk8pd at a tight tolerance. */
#ifndef STABDAE_TOOLS_INDEX1_RK4_H
#define STABDAE_TOOLS_INDEX1_RK4_H

#include <stddef.h>

#include <stabdae/mbs.h>

typedef struct index1 index1;

/* Which of gamma's derivatives come from the mechanism and which from a fourth-order central
 * difference along (1, v) (4 calls of jacobian or constraint_t per evaluation). */
typedef enum index1_source {
  INDEX1_GIVEN = 0,       /* jacobian_dot, constraint_t_dot */
  INDEX1_DIFFERENCES = 1, /* the stencil */
  INDEX1_ZERO = 2         /* no constraint_t: c is taken as independent of t */
} index1_source;

/* The workspace for sys (copied; its params must outlive it): every array and GSL's LU, so that
 * a step allocates nothing. NULL when out of memory or when sys has no jacobian (the baseline
 * does not difference c for G) or n_c >= n_q. */
index1 *index1_alloc(const sdae_mbs *sys);
void index1_free(index1 *w); /* NULL is fine */

/* How Gdot and d/ds c_t are obtained for this mechanism. */
index1_source index1_gdot_source(const index1 *w);
index1_source index1_ct_dot_source(const index1 *w);

/* v' = a at (t, q, v) (n_q values): 0, a callback's non-zero status, or -1 when the KKT matrix
 * is singular (G without full rank, M not invertible on ker G). */
int index1_accel(index1 *w, double t, const double *q, const double *v, double *a);

/* One classical RK4 step of size T from (t, q, v), four evaluations of a; q and v updated in
 * place, untouched on failure (the status of index1_accel). */
int index1_rk4_step(index1 *w, double t, double T, double *q, double *v);

/* The index-1 ODE from t0 to tf by GSL's rk8pd (embedded 8(9) pair, the error per step held to
 * tol absolute and relative); q, v updated in place. It allocates (a driver per call): for a
 * reference outside any timing. *steps (may be NULL): the steps taken. 0 or GSL's status (the
 * caller turns GSL's error handler off). */
int index1_reference(index1 *w, double t0, double tf, double tol, double *q, double *v,
                     unsigned long *steps);

#endif /* STABDAE_TOOLS_INDEX1_RK4_H */
