/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The baseline of the price of zero drift: the classical RK4 on the index-1 form of a mechanism
 * of <stabdae/mbs.h> (tools/index1/index1.h), from its own callbacks: y = (q, v), q' = v,
 * v' from the saddle-point system at every stage. Nothing holds the map on c = 0: its drift
 * grows with its local errors, which is what the front-end's higher cost per step buys off.
 * Also the reference both are measured against: the same index-1 ODE by GSL's adaptive rk8pd at
 * a tight tolerance. */
#ifndef STABDAE_TOOLS_INDEX1_RK4_H
#define STABDAE_TOOLS_INDEX1_RK4_H

#include <stddef.h>

#include <stabdae/mbs.h>

#include "index1.h"

typedef struct index1_rk4 index1_rk4;

/* The workspace for sys (copied; its params must outlive it): the form's and the stages'
 * arrays, so that a step allocates nothing. NULL when out of memory, when sys has no index-1
 * form (index1_refused) or no jacobian (the baseline does not difference c for G). */
index1_rk4 *index1_rk4_alloc(const sdae_mbs *sys);
void index1_rk4_free(index1_rk4 *w); /* NULL is fine */

/* The index-1 form it steps: how gamma's terms are had (index1_gdot_source, ...). */
const index1 *index1_rk4_form(const index1_rk4 *w);

/* One classical RK4 step of size T from (t, q, v), four evaluations of v'; q and v updated in
 * place, untouched on failure (the status of index1_accel). */
int index1_rk4_step(index1_rk4 *w, double t, double T, double *q, double *v);

/* The index-1 ODE from t0 to tf by GSL's rk8pd (embedded 8(9) pair, the error per step held to
 * tol absolute and relative); q, v updated in place. It allocates (a driver per call): for a
 * reference outside any timing. *steps (may be NULL): the steps taken. 0 or GSL's status (the
 * caller turns GSL's error handler off). */
int index1_reference(index1_rk4 *w, double t0, double tf, double tol, double *q, double *v,
                     unsigned long *steps);

#endif /* STABDAE_TOOLS_INDEX1_RK4_H */
