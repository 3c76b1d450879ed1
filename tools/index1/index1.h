/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The index-1 form of a mechanism of <stabdae/mbs.h> from its own callbacks, written once for
 * the tools that integrate it: IDA's residuals (tools/ida/ida_mbs.c) and the classical RK4
 * baseline with its rk8pd reference (tools/benchmarks/index1_rk4.c). With y = (q, v),
 *
 *     q' = v,   [M  G^T] [v'    ]   [F     ]
 *               [G  0  ] [lambda] = [-gamma],   gamma = d/ds (G v + dc/dt)(t + s, q + s v) at 0,
 *
 * G v' + gamma = 0 being the derivative of the velocity constraint G v + dc/dt = 0 along the
 * motion (1, v) with v fixed, and F the force plus input_force where the mechanism gives it (as
 * the front-end reads F). What the mechanism leaves out is differenced by the library's one
 * fourth-order central stencil (src/core/difference.h): G of c in q, dc/dt of c in t, the terms
 * of gamma not given (jacobian_dot, constraint_t_dot) along (1, v) on one stencil, or, without
 * jacobian, the second derivative of c itself along (1, v). Matrices are the mechanism's:
 * row-major, or their nonzeros in pattern order where it gives mass_pattern, jacobian_pattern.
 *
 * Every call returns 0; 1 for a callback's positive status or a value it wrote that is not
 * finite (what IDA may recover from by a shorter step); -1 for a callback's negative status, or
 * in index1_accel a system that is not positive definite or a v' that is not finite. */
#ifndef STABDAE_TOOLS_INDEX1_H
#define STABDAE_TOOLS_INDEX1_H

#include <stddef.h>

#include <stabdae/mbs.h>

typedef struct index1 index1;

/* How a term of gamma is had: from the mechanism, or by the stencil (4 calls of jacobian or
 * constraint_t per evaluation). */
typedef enum index1_source { INDEX1_GIVEN = 0, INDEX1_DIFFERENCES = 1 } index1_source;

/* Why sys has no index-1 form here, or NULL: a callback of mass, force, constraint missing, a
 * pattern that is not one (pattern.h), jacobian_pattern without jacobian. */
const char *index1_refused(const sdae_mbs *sys);

/* The workspace for sys (copied; its params must outlive it), all its arrays in one allocation.
 * With solve, also index1_accel's dense ones (2 n_q^2 + n_c^2 + ...); without, index1_accel
 * returns -1 (a large sparse mechanism's residual needs none of them). NULL when refused or out
 * of memory. */
index1 *index1_alloc(const sdae_mbs *sys, int solve);
void index1_free(index1 *w); /* NULL is fine */

index1_source index1_gdot_source(const index1 *w);   /* Gdot v */
index1_source index1_ct_dot_source(const index1 *w); /* d/ds dc/dt */

/* A callback's status rc and its n values x as this form reports them (above). */
int index1_status(int rc, const double *x, size_t n);

/* c (n_c values), G (the mechanism's layout), F + input_force (n_q values) at (t, q[, v]) */
int index1_constraint(index1 *w, double t, const double *q, double *c);
int index1_jacobian(index1 *w, double t, const double *q, double *G);
int index1_force(index1 *w, double t, const double *q, const double *v, double *F);

/* y += A x (rows x cols): A row-major (p NULL) or its nonzeros in p's order */
void index1_mul_add(const sdae_pattern *p, const double *a, size_t rows, size_t cols,
                    const double *x, double *y);

/* G v + dc/dt at (t, q, v); without jacobian, d/ds c(t + s, q + s v) at 0 */
int index1_velocity(index1 *w, double t, const double *q, const double *v, double *g);

/* gamma at (t, q, v) (n_c values) */
int index1_gamma(index1 *w, double t, const double *q, const double *v, double *gamma);

/* v' (n_q values) and lambda (n_c values, or NULL) at (t, q, v), by the Schur complement in the
 * library's own Cholesky (src/core/lu.h): M = L L^T, Y = M^-1 G^T, S = G Y,
 * S lambda = G M^-1 F + gamma, v' = M^-1 F - Y lambda. It needs M positive definite (the
 * library needs the reduced mass positive definite only); -1 when M or S is not. */
int index1_accel(index1 *w, double t, const double *q, const double *v, double *vdot,
                 double *lambda);

#endif /* STABDAE_TOOLS_INDEX1_H */
