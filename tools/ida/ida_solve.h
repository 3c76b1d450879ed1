/* SPDX-License-Identifier: GPL-3.0-or-later */
/* SUNDIALS IDA run of an index-reduced model (ida_models.h) from a state on the constraint
 * manifold, with output at t = 0, DT, 2 DT, ... and tf, each hit exactly through IDA's tstop. */
#ifndef STABDAE_TOOLS_IDA_SOLVE_H
#define STABDAE_TOOLS_IDA_SOLVE_H

#include "ida_models.h"

typedef struct idaref_options {
  double rtol, atol;  /* IDASStolerances */
  double tf, dt;      /* final time (>= 0) and output spacing (> 0) */
  long max_steps;     /* IDASetMaxNumSteps: steps allowed per output interval */
} idaref_options;

typedef struct idaref_stats {
  long steps, res_evals, jac_evals, err_test_fails, nonlin_conv_fails, nonlin_iters;
} idaref_stats;

/* Called at every output time with the full y of the form (X, Y, Xdot, Ydot, lambda[, nu]);
 * a nonzero return stops the run with IDAREF_OUTPUT_FAILED. */
typedef int (*idaref_row_fn)(double t, const double *y, void *ctx);

enum { IDAREF_OK = 0, IDAREF_IDA_FAILED = -1, IDAREF_OUTPUT_FAILED = -2 };

typedef struct idaref_result {
  int ida_flag;          /* IDA's return flag of the failing call (0 when the run succeeded) */
  char flag_name[32];    /* its name (IDAGetReturnFlagName), e.g. "IDA_CONV_FAIL" */
  const char *function;  /* name of the failing SUNDIALS call, or NULL */
  double t_reached;      /* time of the last state IDA holds */
  char message[512];     /* IDA's own error message, one line (empty when none) */
  idaref_stats stats;    /* solver counters (also on failure) */
} idaref_result;

/* The k-th output time (k = 0, 1, ...): k DT while short of tf by more than 1e-9 DT, then tf.
 * Returns 0 and sets *t, or -1 past the last one. */
int idaref_output_time(double tf, double dt, double k, double *t);

/* Integrates from x0 (which must satisfy h = hdot = 0; lambda comes from IDACalcIC). Returns
 * IDAREF_OK, IDAREF_IDA_FAILED (details in *res) or IDAREF_OUTPUT_FAILED. */
int idaref_solve(const idaref_model *p, idaref_form form, const double *x0,
                 const idaref_options *o, idaref_row_fn row, void *ctx, idaref_result *res);

#endif
