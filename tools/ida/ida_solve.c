/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The IDA driver: context, vectors, dense linear solver with the analytic iteration matrix,
 * consistent initial values by IDACalcIC on the index-1 form, then one IDASolve per output time
 * with tstop set to it (so every output is a step of IDA's, not an interpolation). */
#include "ida_solve.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct problem {
  const idaref_model *model;
  idaref_form form;
} problem;

typedef struct run {
  problem pb;
  idaref_ida ida;
} run;

static int residual_cb(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void *user_data) {
  const problem *pb = user_data;
  (void)t;
  idaref_residual(pb->model, pb->form, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp),
                  N_VGetArrayPointer(rr));
  for (sunindextype i = 0; i < N_VGetLength(rr); i++)
    if (!isfinite(N_VGetArrayPointer(rr)[i]))
      return 1; /* recoverable: IDA retries with a smaller step */
  return 0;
}

static int jacobian_cb(realtype t, realtype cj, N_Vector yy, N_Vector yp, N_Vector rr,
                       SUNMatrix Jac, void *user_data, N_Vector t1, N_Vector t2, N_Vector t3) {
  const problem *pb = user_data;
  size_t n = idaref_dim(pb->form);
  double J[IDAREF_MAX_DIM * IDAREF_MAX_DIM];
  (void)t, (void)yp, (void)rr, (void)t1, (void)t2, (void)t3;
  idaref_jacobian(pb->model, pb->form, cj, N_VGetArrayPointer(yy), J);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++)
      SM_ELEMENT_D(Jac, (sunindextype)i, (sunindextype)j) = J[i * n + j];
  return 0;
}

void idaref_error_handler(int code, const char *module, const char *function, char *msg,
                          void *data) {
  idaref_result *res = data;
  (void)module;
  if (code >= 0) return;
  snprintf(res->message, sizeof res->message, "%s: %s", function, msg);
  for (char *c = res->message; *c; c++)
    if (*c == '\n' || *c == '\r') *c = ' ';
}

int idaref_failed(idaref_result *res, int flag, const char *function) {
  if (flag >= 0) return 0;
  char *name = IDAGetReturnFlagName(flag); /* malloc'd by IDA */
  res->ida_flag = flag;
  res->function = function;
  snprintf(res->flag_name, sizeof res->flag_name, "%s", name ? name : "?");
  free(name);
  return -1;
}

int idaref_ida_create(idaref_ida *r, size_t n, idaref_result *res) {
  sunindextype len = (sunindextype)n;
  if (idaref_failed(res, SUNContext_Create(NULL, &r->ctx), "SUNContext_Create")) return -1;
  r->mem = IDACreate(r->ctx);
  r->yy = N_VNew_Serial(len, r->ctx);
  r->yp = N_VNew_Serial(len, r->ctx);
  r->id = N_VNew_Serial(len, r->ctx);
  r->A = SUNDenseMatrix(len, len, r->ctx);
  if (!r->mem || !r->yy || !r->yp || !r->id || !r->A)
    return idaref_failed(res, IDA_MEM_FAIL, "IDACreate");
  r->ls = SUNLinSol_Dense(r->yy, r->A, r->ctx);
  return r->ls ? 0 : idaref_failed(res, IDA_MEM_FAIL, "SUNLinSol_Dense");
}

void idaref_ida_destroy(idaref_ida *r) {
  IDAFree(&r->mem);
  SUNLinSolFree(r->ls);
  SUNMatDestroy(r->A);
  N_VDestroy(r->id);
  N_VDestroy(r->yp);
  N_VDestroy(r->yy);
  SUNContext_Free(&r->ctx);
}

/* Absolute tolerances: --atol for X, Y, Xdot, Ydot and lambda; 1 for GGL's nu. nu vanishes on
 * every solution, and what IDA computes for it is rounding noise of size eps |q| cj (cj ~ 1/step,
 * so largest on the tiny first steps); --atol on it makes the Newton test fail on that noise
 * (IDA_CONV_FAIL at rtol 1e-10, atol 1e-12 for the pendulum). Its effect on q, G^T nu / cj, is
 * still held to q's own tolerance. */
static int set_tolerances(run *r, const idaref_options *o) {
  N_Vector atol = N_VClone(r->ida.yy);
  int flag;
  if (!atol) return IDA_MEM_FAIL;
  for (size_t i = 0; i < idaref_dim(r->pb.form); i++)
    N_VGetArrayPointer(atol)[i] = i == IDAREF_NU ? 1.0 : o->atol;
  flag = IDASVtolerances(r->ida.mem, o->rtol, atol);
  N_VDestroy(atol);
  return flag;
}

/* IDAInit from (y, y') and the options: tolerances, the dense solver with the analytic matrix,
 * the id vector, and for GGL the algebraic variables out of the error test. */
static int configure(run *r, const double *y, const double *yp, const idaref_options *o,
                     idaref_result *res) {
  void *mem = r->ida.mem;
  size_t n = idaref_dim(r->pb.form);
  memcpy(N_VGetArrayPointer(r->ida.yy), y, n * sizeof *y);
  memcpy(N_VGetArrayPointer(r->ida.yp), yp, n * sizeof *yp);
  idaref_id(r->pb.form, N_VGetArrayPointer(r->ida.id));
  if (idaref_failed(res, IDASetErrHandlerFn(mem, idaref_error_handler, res),
                    "IDASetErrHandlerFn") ||
      idaref_failed(res, IDAInit(mem, residual_cb, 0.0, r->ida.yy, r->ida.yp), "IDAInit") ||
      idaref_failed(res, IDASetUserData(mem, &r->pb), "IDASetUserData") ||
      idaref_failed(res, set_tolerances(r, o), "IDASVtolerances") ||
      idaref_failed(res, IDASetLinearSolver(mem, r->ida.ls, r->ida.A), "IDASetLinearSolver") ||
      idaref_failed(res, IDASetJacFn(mem, jacobian_cb), "IDASetJacFn") ||
      idaref_failed(res, IDASetId(mem, r->ida.id), "IDASetId") ||
      idaref_failed(res, IDASetMaxNumSteps(mem, o->max_steps), "IDASetMaxNumSteps"))
    return -1;
  /* GGL is index 2: its algebraic variables cannot be error-controlled like differential ones */
  if (r->pb.form == IDAREF_GGL &&
      idaref_failed(res, IDASetSuppressAlg(mem, SUNTRUE), "IDASetSuppressAlg"))
    return -1;
  return 0;
}

/* Consistent lambda and y' at x0 from IDACalcIC on the index-1 form. The GGL form cannot give
 * them itself (its algebraic rows h = 0, G v = 0 do not involve lambda or nu), and its lambda is
 * the same one (hdd = 0 holds along any solution with h = 0), with nu = 0 and q' = v.
 * y and yp have IDAREF_MAX_DIM entries; nu and nu' are left 0. */
static int consistent_start(const idaref_model *p, const double *x0, const idaref_options *o,
                            double *y, double *yp, idaref_result *res) {
  run r = {.pb = {.model = p, .form = IDAREF_INDEX1}};
  double t1;
  int status = -1;
  if (idaref_output_time(o->tf, o->dt, 1.0, &t1) != 0)
    t1 = o->dt; /* tf = 0: IDACalcIC still wants a direction and a scale of time */
  memset(y, 0, IDAREF_MAX_DIM * sizeof *y);
  memset(yp, 0, IDAREF_MAX_DIM * sizeof *yp);
  idaref_initial_guess(p, IDAREF_INDEX1, x0, y, yp);
  if (idaref_ida_create(&r.ida, idaref_dim(IDAREF_INDEX1), res) == 0 &&
      configure(&r, y, yp, o, res) == 0 &&
      !idaref_failed(res, IDACalcIC(r.ida.mem, IDA_YA_YDP_INIT, t1), "IDACalcIC") &&
      !idaref_failed(res, IDAGetConsistentIC(r.ida.mem, r.ida.yy, r.ida.yp),
                     "IDAGetConsistentIC")) {
    memcpy(y, N_VGetArrayPointer(r.ida.yy), idaref_dim(IDAREF_INDEX1) * sizeof *y);
    memcpy(yp, N_VGetArrayPointer(r.ida.yp), idaref_dim(IDAREF_INDEX1) * sizeof *yp);
    status = 0;
  }
  idaref_ida_destroy(&r.ida);
  return status;
}

void idaref_collect_stats(void *mem, idaref_stats *s) {
  if (!mem) return;
  IDAGetNumSteps(mem, &s->steps);
  IDAGetNumResEvals(mem, &s->res_evals);
  IDAGetNumLinResEvals(mem, &s->lin_res_evals);
  IDAGetNumJacEvals(mem, &s->jac_evals);
  IDAGetNumErrTestFails(mem, &s->err_test_fails);
  IDAGetNumNonlinSolvConvFails(mem, &s->nonlin_conv_fails);
  IDAGetNumNonlinSolvIters(mem, &s->nonlin_iters);
}

void idaref_write_stats(FILE *f, const idaref_stats *s) {
  fprintf(f, "# steps: %ld\n", s->steps);
  fprintf(f, "# residual evaluations: %ld\n", s->res_evals);
  fprintf(f, "# residual evaluations for the Jacobian: %ld\n", s->lin_res_evals);
  fprintf(f, "# jacobian evaluations: %ld\n", s->jac_evals);
  fprintf(f, "# error test failures: %ld\n", s->err_test_fails);
  fprintf(f, "# nonlinear convergence failures: %ld\n", s->nonlin_conv_fails);
  fprintf(f, "# nonlinear iterations: %ld\n", s->nonlin_iters);
}

/* The k-th output time from t0: t0 + k DT, the last one tf itself. */
static int output_time(double t0, double tf, double dt, double k, double *t) {
  double s;
  if (idaref_output_time(tf - t0, dt, k, &s) != 0) return -1;
  *t = s == tf - t0 ? tf : t0 + s;
  return 0;
}

int idaref_march(idaref_ida *r, double t0, const idaref_options *o, idaref_row_fn row, void *ctx,
                 idaref_result *res) {
  double t;
  res->t_reached = t0;
  if (row(t0, N_VGetArrayPointer(r->yy), ctx) != 0) return IDAREF_OUTPUT_FAILED;
  for (double k = 1.0; output_time(t0, o->tf, o->dt, k, &t) == 0; k += 1.0) {
    realtype tret = res->t_reached;
    if (idaref_failed(res, IDASetStopTime(r->mem, t), "IDASetStopTime") ||
        idaref_failed(res, IDASolve(r->mem, t, &tret, r->yy, r->yp, IDA_NORMAL), "IDASolve")) {
      IDAGetCurrentTime(r->mem, &res->t_reached);
      return IDAREF_IDA_FAILED;
    }
    res->t_reached = tret;
    if (row(tret, N_VGetArrayPointer(r->yy), ctx) != 0) return IDAREF_OUTPUT_FAILED;
  }
  return IDAREF_OK;
}

/* Output k (k >= 1) lies strictly inside (0, tf), short of tf by more than rounding. */
static int before_tf(double tf, double dt, double k) { return k * dt < tf - 1e-9 * dt; }

int idaref_output_time(double tf, double dt, double k, double *t) {
  if (k == 0.0 || before_tf(tf, dt, k)) {
    *t = k * dt;
    return 0;
  }
  if (tf > 0.0 && (k == 1.0 || before_tf(tf, dt, k - 1.0))) {
    *t = tf;
    return 0;
  }
  return -1;
}

int idaref_solve(const idaref_model *p, idaref_form form, const double *x0, const idaref_options *o,
                 idaref_row_fn row, void *ctx, idaref_result *res) {
  run r = {.pb = {.model = p, .form = form}};
  double y[IDAREF_MAX_DIM], yp[IDAREF_MAX_DIM];
  int status = IDAREF_IDA_FAILED;
  memset(res, 0, sizeof *res);
  if (consistent_start(p, x0, o, y, yp, res) != 0) return status;
  if (idaref_ida_create(&r.ida, idaref_dim(form), res) == 0 && configure(&r, y, yp, o, res) == 0)
    status = idaref_march(&r.ida, 0.0, o, row, ctx, res);
  idaref_collect_stats(r.ida.mem, &res->stats);
  idaref_ida_destroy(&r.ida);
  return status;
}
