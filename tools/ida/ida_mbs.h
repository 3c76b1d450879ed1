/* SPDX-License-Identifier: GPL-3.0-or-later */
/* SUNDIALS IDA for any mechanism of <stabdae/mbs.h>,
 *
 *     q' = v,   M(t, q) v' = F(t, q, v) - G(t, q)^T lambda,   c(t, q) = 0,   G = dc/dq,
 *
 * from the mechanism's own callbacks and nothing of the stabdae library (only the struct type),
 * so that it stays an independent reference. Two index-reduced forms:
 *   index1: y = (q, v, lambda); the constraint at acceleration level G v' + gamma = 0, gamma the
 *           derivative of G v + dc/dt along (1, v) in (t, q) with v fixed (lambda algebraic);
 *   ggl:    y = (q, v, lambda, nu); Gear-Gupta-Leimkuhler: q' = v - G^T nu with c = 0 and
 *           G v + dc/dt = 0 (index 2; lambda and nu algebraic, nu = 0 on every solution).
 * Derivatives the mechanism leaves out are fourth-order central differences: G of c in q,
 * dc/dt of c in t, gamma of G v + dc/dt along (1, v), or, without jacobian, the second
 * derivative of c itself along (1, v). IDA builds its own iteration matrix by differences
 * (dense solver). */
#ifndef STABDAE_TOOLS_IDA_MBS_H
#define STABDAE_TOOLS_IDA_MBS_H

#include <stddef.h>

#include <stabdae/mbs.h>

#include "ida_solve.h"

typedef enum idambs_form { IDAMBS_INDEX1, IDAMBS_GGL } idambs_form;

/* idambs_solve's statuses beyond ida_solve.h's: no consistent start (a callback failed, M or
 * G M^-1 G^T not positive definite, or no memory); res->function and res->message say which. */
enum { IDAMBS_START_FAILED = -3 };

/* Number of components of y: 2 n_q + n_c (index1) or 2 n_q + 2 n_c (ggl). */
size_t idambs_dim(const sdae_mbs *sys, idambs_form form);

/* Called at every output time with the state and its multipliers; non-zero stops the run with
 * IDAREF_OUTPUT_FAILED. */
typedef int (*idambs_row_fn)(double t, const double *q, const double *v, const double *lambda,
                             void *ctx);

/* The constraint forces at (t, q, v): (G M^-1 G^T) lambda = G M^-1 F + gamma, and the
 * acceleration v' = M^-1 (F - G^T lambda) (vdot may be NULL). Returns 0, or -1 when a callback
 * fails or a matrix is not positive definite (lambda, vdot then undefined). */
int idambs_lambda(const sdae_mbs *sys, double t, const double *q, const double *v, double *lambda,
                  double *vdot);

/* Integrates from (q0, v0) at t0, which must satisfy c = 0 and G v + dc/dt = 0 (lambda and v'
 * are computed, nu = 0), to o->tf (>= t0) with rows at t0, t0 + DT, ... and tf, each hit
 * exactly through IDA's tstop. No I/O: the caller may time this call alone. Returns IDAREF_OK,
 * IDAREF_IDA_FAILED, IDAREF_OUTPUT_FAILED or IDAMBS_START_FAILED (details in *res; the counters
 * also on failure). */
int idambs_solve(const sdae_mbs *sys, idambs_form form, double t0, const double *q0,
                 const double *v0, const idaref_options *o, idambs_row_fn row, void *ctx,
                 idaref_result *res);

#endif
