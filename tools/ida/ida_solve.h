/* SPDX-License-Identifier: GPL-3.0-or-later */
/* SUNDIALS IDA run of an index-reduced model (ida_models.h) from a state on the constraint
 * manifold, with output at t = 0, DT, 2 DT, ... and tf, each hit exactly through IDA's tstop. */
#ifndef STABDAE_TOOLS_IDA_SOLVE_H
#define STABDAE_TOOLS_IDA_SOLVE_H

#include <stdio.h>

#include <ida/ida.h>
#include <sundials/sundials_context.h>

#include "ida_models.h"

typedef struct idaref_options {
  double rtol, atol; /* IDASStolerances */
  double tf, dt;     /* final time (>= 0) and output spacing (> 0) */
  long max_steps;    /* IDASetMaxNumSteps: steps allowed per output interval */
} idaref_options;

typedef struct idaref_stats {
  long steps, res_evals, jac_evals, err_test_fails, nonlin_conv_fails, nonlin_iters;
  long lin_res_evals; /* residuals spent on difference-quotient Jacobians (not in res_evals) */
} idaref_stats;

/* Called at every output time with the full y of the form (X, Y, Xdot, Ydot, lambda[, nu]);
 * a nonzero return stops the run with IDAREF_OUTPUT_FAILED. */
typedef int (*idaref_row_fn)(double t, const double *y, void *ctx);

enum { IDAREF_OK = 0, IDAREF_IDA_FAILED = -1, IDAREF_OUTPUT_FAILED = -2 };

typedef struct idaref_result {
  int ida_flag;         /* IDA's return flag of the failing call (0 when the run succeeded) */
  char flag_name[32];   /* its name (IDAGetReturnFlagName), e.g. "IDA_CONV_FAIL" */
  const char *function; /* name of the failing SUNDIALS call, or NULL */
  double t_reached;     /* time of the last state IDA holds */
  char message[512];    /* IDA's own error message, one line (empty when none) */
  idaref_stats stats;   /* solver counters (also on failure) */
} idaref_result;

/* The k-th output time (k = 0, 1, ...): k DT while short of tf by more than 1e-9 DT, then tf.
 * Returns 0 and sets *t, or -1 past the last one. */
int idaref_output_time(double tf, double dt, double k, double *t);

/* Integrates from x0 (which must satisfy h = hdot = 0; lambda comes from IDACalcIC). Returns
 * IDAREF_OK, IDAREF_IDA_FAILED (details in *res) or IDAREF_OUTPUT_FAILED. */
int idaref_solve(const idaref_model *p, idaref_form form, const double *x0, const idaref_options *o,
                 idaref_row_fn row, void *ctx, idaref_result *res);

/* ---- shared by the drivers (this one and ida_mbs.c) ---------------------------------------- */

/* IDA's objects for one run: context, memory, y, y', the id vector, the dense matrix and solver */
typedef struct idaref_ida {
  SUNContext ctx;
  void *mem;
  N_Vector yy, yp, id;
  SUNMatrix A;
  SUNLinearSolver ls;
} idaref_ida;

/* Creates them for n components; 0, or -1 with the failing call in *res. */
int idaref_ida_create(idaref_ida *r, size_t n, idaref_result *res);
void idaref_ida_destroy(idaref_ida *r); /* any part NULL is fine */

/* Records a failing SUNDIALS call in *res; returns -1 when flag is an error, else 0. */
int idaref_failed(idaref_result *res, int flag, const char *function);

/* IDASetErrHandlerFn's handler with data = the idaref_result: keeps IDA's error message (one
 * line) instead of letting IDA print it; warnings are dropped. */
void idaref_error_handler(int code, const char *module, const char *function, char *msg,
                          void *data);

void idaref_collect_stats(void *mem, idaref_stats *s);
/* The counters as the CLIs' trailing '#' lines ("# steps: N", ...). */
void idaref_write_stats(FILE *f, const idaref_stats *s);

/* From the configured run at t0: row(t, y) at t0, then IDASolve to t0 + DT, t0 + 2 DT, ... and
 * o->tf, each hit exactly through tstop. IDAREF_OK, IDAREF_IDA_FAILED or IDAREF_OUTPUT_FAILED;
 * res->t_reached the time of the last state IDA holds. */
int idaref_march(idaref_ida *r, double t0, const idaref_options *o, idaref_row_fn row, void *ctx,
                 idaref_result *res);

#endif
