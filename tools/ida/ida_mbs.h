/* SPDX-License-Identifier: GPL-3.0-or-later */
/* SUNDIALS IDA for any mechanism of <stabdae/mbs.h>,
 *
 *     q' = v,   M(t, q) v' = F(t, q, v) - G(t, q)^T lambda,   c(t, q) = 0,   G = dc/dq,
 *
 * from the mechanism's own callbacks and the index-1 form of tools/index1 (index1.h, over the
 * library's difference stencil and Cholesky), nothing of the library's stepping, so that it stays
 * an independent reference. Two index-reduced forms:
 *   index1: y = (q, v, lambda); the constraint at acceleration level G v' + gamma = 0, gamma the
 *           derivative of G v + dc/dt along (1, v) in (t, q) with v fixed (lambda algebraic);
 *   ggl:    y = (q, v, lambda, nu); Gear-Gupta-Leimkuhler: q' = v - G^T nu with c = 0 and
 *           G v + dc/dt = 0 (index 2; lambda and nu algebraic, nu = 0 on every solution).
 * Derivatives the mechanism leaves out are fourth-order central differences: G of c in q,
 * dc/dt of c in t, gamma of G v + dc/dt along (1, v), or, without jacobian, the second
 * derivative of c itself along (1, v); jacobian_dot and constraint_t_dot are differenced too,
 * even when given, so that a wrong one shows against the library. Matrices are the mechanism's:
 * row-major, or their nonzeros in pattern order where it gives mass_pattern, jacobian_pattern
 * (<stabdae/mbs.h>).
 *
 * Two linear solvers for IDA's Newton iteration:
 *   dense: SUNDIALS' dense LU on IDA's own difference-quotient matrix (n^2 memory, n^3 work);
 *   KLU:   SUNDIALS' KLU on a sparse (compressed-column) iteration matrix dF/dy + cj dF/dy' of
 *          the index1 residual, for a mechanism with both patterns: its structure follows from
 *          them (below), its values are forward differences of the same residual with the
 *          columns grouped (a greedy coloring: columns sharing no row are perturbed together, one
 *          residual per group), the consistent start by KLU on [M G^T; G 0].
 * The KLU matrix's structure, y = (q, v, lambda), S = pattern(M) + pattern(G^T G) + I:
 *   q rows:      q_k' - v_k                    -> (k, q_k) and (k, v_k)
 *   v rows:      M v' - F + G^T lambda         -> S in the q and the v columns, G^T in lambda's
 *   lambda rows: G v' + gamma                  -> pattern(G) in the q and the v columns
 * The constraint rows are exact: c_i, hence G's row i, dc_i/dt and gamma_i, depends on the
 * coordinates of G's row i alone. M v' - F assumes what mbs.h cannot say: that M and F of
 * coordinate i depend only on coordinates coupled to i by M or by a shared constraint (bodies
 * joined by joints and loaded by gravity, joint forces and dampers; not a spring or a contact
 * between bodies that share no constraint). Every Jacobian checks it with one residual more,
 * in a direction d of the increments times fixed pseudo-random factors: a v row whose difference
 * departs from the matrix's (J d)_i by more than IDAMBS_KLU_OUTSIDE of sum_j |J_ij d_j| fails the
 * run (IDA_LSETUP_FAIL, res->message naming the row). A dependence outside the structure shows
 * there whether the grouped differences left it out or gave it to a column of the same group;
 * smaller departures are harmless to the modified Newton iteration, which already holds its
 * matrix while cj moves by a factor 0.6 to 1.67. */
#ifndef STABDAE_TOOLS_IDA_MBS_H
#define STABDAE_TOOLS_IDA_MBS_H

#include <stddef.h>

#include <stabdae/mbs.h>

#include "ida_solve.h"

typedef enum idambs_form { IDAMBS_INDEX1, IDAMBS_GGL } idambs_form;

typedef enum idambs_solver { IDAMBS_DENSE, IDAMBS_KLU } idambs_solver;

/* idambs_solve's statuses beyond ida_solve.h's: no consistent start (a callback failed, M or
 * G M^-1 G^T not positive definite (dense), [M G^T; G 0] singular (KLU), or no memory); a request
 * it does not serve (KLU with the ggl form or without both patterns, a pattern that is not one,
 * jacobian_pattern without jacobian). res->function and res->message say which. */
enum { IDAMBS_START_FAILED = -3, IDAMBS_UNSUPPORTED = -4 };

/* The KLU matrix's check (above): a row of J d off by more than this fraction of
 * sum_j |J_ij d_j| fails the run. */
#define IDAMBS_KLU_OUTSIDE 1e-2

/* Number of components of y: 2 n_q + n_c (index1) or 2 n_q + 2 n_c (ggl). */
size_t idambs_dim(const sdae_mbs *sys, idambs_form form);

/* Called at every output time with the state and its multipliers; non-zero stops the run with
 * IDAREF_OUTPUT_FAILED. */
typedef int (*idambs_row_fn)(double t, const double *q, const double *v, const double *lambda,
                             void *ctx);

/* The constraint forces at (t, q, v): (G M^-1 G^T) lambda = G M^-1 F + gamma, and the
 * acceleration v' = M^-1 (F - G^T lambda) (vdot may be NULL), by dense Cholesky factors (a
 * mechanism's patterns expanded). Returns 0, or -1 when a callback fails, a pattern is not one
 * or a matrix is not positive definite (lambda, vdot then undefined). */
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

/* idambs_solve with the linear solver chosen (idambs_solve is IDAMBS_DENSE). With IDAMBS_KLU,
 * res->stats.lin_res_evals counts the residuals of the grouped differences; IDAMBS_UNSUPPORTED
 * unless the form is index1 and the mechanism gives both patterns. */
int idambs_solve_with(const sdae_mbs *sys, idambs_form form, idambs_solver solver, double t0,
                      const double *q0, const double *v0, const idaref_options *o,
                      idambs_row_fn row, void *ctx, idaref_result *res);

/* The KLU path's iteration matrix: its order n = 2 n_q + n_c, nonzeros and column groups (the
 * residuals a Jacobian costs). 0, or -1 (no KLU mechanism, a pattern that is not one, no memory).
 */
int idambs_klu_structure(const sdae_mbs *sys, size_t *n, size_t *nnz, size_t *groups);

/* For the tests: the KLU path's iteration matrix dF/dy + cj dF/dy' at (t, y, yp) of the index1
 * form (y = (q, v, lambda), n = 2 n_q + n_c), by the grouped differences with increments
 * sqrt(eps) max(|y_j|, 1), into J (n x n, row-major, 0 outside the structure); *outside the
 * check's largest ratio over the v rows (above).
 * 0, or -1 (a callback failed, no KLU mechanism, no memory). */
int idambs_klu_matrix(const sdae_mbs *sys, double t, const double *y, const double *yp, double cj,
                      double *J, double *outside);

#endif
