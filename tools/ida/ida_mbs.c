/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanism's residuals for IDA (ida_mbs.h), the consistent start by GSL's Cholesky, and the
 * run: context, vectors, dense solver with IDA's difference-quotient matrix, then one IDASolve
 * per output time with tstop set to it. Scratch is allocated once per run (a tool, not the
 * library). */
#include "ida_mbs.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the mechanism and its derivatives ------------------------------------------------------ */

typedef struct mech {
  const sdae_mbs *sys;
  idambs_form form;
  size_t n_q, n_c;
  double *block;          /* every array below, one allocation */
  double *M, *F, *G;      /* the residual's evaluations */
  double *Gv;             /* G where G v + dc/dt is evaluated (a point along (1, v)) */
  double *qa, *fa;        /* a point along (1, v) and the values there */
  double *qj, *cj;        /* a point of G's or dc/dt's differences and c there */
  double *MiGT, *MiF, *A; /* the consistent start: M^-1 G^T, M^-1 F, G M^-1 G^T */
} mech;

/* The fourth-order central stencils over 12 h (first derivative) and 12 h^2 (second):
 * f' ~ [8 (f(h) - f(-h)) - (f(2h) - f(-2h))] / (12 h),
 * f'' ~ [16 (f(h) + f(-h)) - (f(2h) + f(-2h)) - 30 f(0)] / (12 h^2). */
static const double offset[5] = {1.0, -1.0, 2.0, -2.0, 0.0};
static const double weight1[5] = {8.0, -8.0, -1.0, 1.0, 0.0};
static const double weight2[5] = {16.0, 16.0, -1.0, -1.0, -30.0};
/* Steps about eps^(1/5) (first derivative) and eps^(1/6) (second) times the variable's scale:
 * truncation h^4 and rounding eps/h (eps/h^2) balance there. */
#define FD_STEP1 7.4e-4
#define FD_STEP2 2.5e-3

static int mech_init(mech *m, const sdae_mbs *sys, idambs_form form) {
  size_t nq = sys->n_q, nc = sys->n_c;
  size_t len[] = {nq * nq, nq, nc * nq, nc * nq, nq, nc, nq, nc, nq * nc, nq, nc * nc};
  double **dst[] = {&m->M,  &m->F,  &m->G,    &m->Gv,  &m->qa, &m->fa,
                    &m->qj, &m->cj, &m->MiGT, &m->MiF, &m->A};
  size_t total = 0;
  *m = (mech){.sys = sys, .form = form, .n_q = nq, .n_c = nc};
  for (size_t i = 0; i < sizeof len / sizeof len[0]; i++) total += len[i];
  if (!(m->block = calloc(total, sizeof *m->block))) return -1;
  total = 0;
  for (size_t i = 0; i < sizeof len / sizeof len[0]; i++) {
    *dst[i] = m->block + total;
    total += len[i];
  }
  return 0;
}

static void mech_free(mech *m) { free(m->block); }

/* A callback's status as IDA reads it: < 0 fatal, > 0 (or a non-finite value) recoverable. */
static int checked(int rc, const double *x, size_t n) {
  if (rc != 0) return rc < 0 ? -1 : 1;
  for (size_t i = 0; i < n; i++)
    if (!isfinite(x[i])) return 1;
  return 0;
}

static int constraint(mech *m, double t, const double *q, double *c) {
  return checked(m->sys->constraint(t, q, c, m->sys->params), c, m->n_c);
}

/* a step near h0 that x + h represents exactly */
static double exact_step(double x, double h0) { return (x + h0) - x; }

/* G column by column: d/dh c(t, q + h e_j) */
static int jacobian_fd(mech *m, double t, const double *q, double *G) {
  size_t nq = m->n_q, nc = m->n_c;
  memcpy(m->qj, q, nq * sizeof *q);
  for (size_t j = 0; j < nq; j++) {
    double h = exact_step(q[j], FD_STEP1 * fmax(1.0, fabs(q[j])));
    for (size_t i = 0; i < nc; i++) G[i * nq + j] = 0.0;
    for (int k = 0; k < 4; k++) {
      int rc;
      m->qj[j] = q[j] + offset[k] * h;
      if ((rc = constraint(m, t, m->qj, m->cj)) != 0) return rc;
      for (size_t i = 0; i < nc; i++) G[i * nq + j] += weight1[k] * m->cj[i] / (12.0 * h);
    }
    m->qj[j] = q[j];
  }
  return 0;
}

static int jacobian(mech *m, double t, const double *q, double *G) {
  if (!m->sys->jacobian) return jacobian_fd(m, t, q, G);
  return checked(m->sys->jacobian(t, q, G, m->sys->params), G, m->n_c * m->n_q);
}

/* dc/dt: the callback, or d/dh c(t + h, q) (exactly 0 when c does not depend on t) */
static int constraint_t(mech *m, double t, const double *q, double *ct) {
  double h = exact_step(t, FD_STEP1 * fmax(1.0, fabs(t)));
  if (m->sys->constraint_t)
    return checked(m->sys->constraint_t(t, q, ct, m->sys->params), ct, m->n_c);
  memset(ct, 0, m->n_c * sizeof *ct);
  for (int k = 0; k < 4; k++) {
    int rc = constraint(m, t + offset[k] * h, q, m->cj);
    if (rc != 0) return rc;
    for (size_t i = 0; i < m->n_c; i++) ct[i] += weight1[k] * m->cj[i] / (12.0 * h);
  }
  return 0;
}

static double inf_norm(const double *x, size_t n) {
  double worst = 0.0;
  for (size_t i = 0; i < n; i++) worst = fmax(worst, fabs(x[i]));
  return worst;
}

/* A function of (t, q, v) with n_c values, differentiated along (1, v). */
typedef int (*along_fn)(mech *m, double t, const double *q, const double *v, double *out);

static int c_along(mech *m, double t, const double *q, const double *v, double *out) {
  (void)v;
  return constraint(m, t, q, out);
}

/* d^order/ds^order f(t + s, q + s v) at s = 0 (order 1 or 2), the step scaled so that the
 * displacement h |v| stays near h0 relative to |q|. f must not itself difference along (1, v)
 * (qa, fa are this function's). */
static int derivative_along(mech *m, along_fn f, int order, double t, const double *q,
                            const double *v, double *out) {
  double nq = inf_norm(q, m->n_q), h0 = order == 1 ? FD_STEP1 : FD_STEP2;
  double h = exact_step(t, h0 * (1.0 + nq) / (1.0 + nq + inf_norm(v, m->n_q)));
  const double *w = order == 1 ? weight1 : weight2;
  double scale = order == 1 ? 12.0 * h : 12.0 * h * h;
  memset(out, 0, m->n_c * sizeof *out);
  for (int k = 0; k < (order == 1 ? 4 : 5); k++) {
    int rc;
    for (size_t j = 0; j < m->n_q; j++) m->qa[j] = q[j] + offset[k] * h * v[j];
    if ((rc = f(m, t + offset[k] * h, m->qa, v, m->fa)) != 0) return rc;
    for (size_t i = 0; i < m->n_c; i++) out[i] += w[k] * m->fa[i] / scale;
  }
  return 0;
}

/* G v + dc/dt with the callbacks (G into m->Gv, m->G being the residual's); without
 * jacobian, d/ds c along (1, v) */
static int velocity_constraint(mech *m, double t, const double *q, const double *v, double *g) {
  int rc;
  if (!m->sys->jacobian) return derivative_along(m, c_along, 1, t, q, v, g);
  if ((rc = jacobian(m, t, q, m->Gv)) != 0 || (rc = constraint_t(m, t, q, g)) != 0) return rc;
  for (size_t i = 0; i < m->n_c; i++)
    for (size_t j = 0; j < m->n_q; j++) g[i] += m->Gv[i * m->n_q + j] * v[j];
  return 0;
}

/* gamma = d/ds (G v + dc/dt)(t + s, q + s v) = d^2/ds^2 c(t + s, q + s v) at s = 0 */
static int gamma_at(mech *m, double t, const double *q, const double *v, double *gamma) {
  if (!m->sys->jacobian) return derivative_along(m, c_along, 2, t, q, v, gamma);
  return derivative_along(m, velocity_constraint, 1, t, q, v, gamma);
}

/* M, F and G at (t, q, v) into m->M, m->F, m->G */
static int dynamics(mech *m, double t, const double *q, const double *v) {
  const sdae_mbs *s = m->sys;
  size_t nq = m->n_q;
  int rc = checked(s->mass(t, q, m->M, s->params), m->M, nq * nq);
  if (rc == 0) rc = checked(s->force(t, q, v, m->F, s->params), m->F, nq);
  return rc != 0 ? rc : jacobian(m, t, q, m->G);
}

/* r += G^T x */
static void add_GT(const mech *m, const double *x, double *r) {
  for (size_t i = 0; i < m->n_c; i++)
    for (size_t j = 0; j < m->n_q; j++) r[j] += m->G[i * m->n_q + j] * x[i];
}

/* r = M v' - F + G^T lambda */
static void momentum_rows(const mech *m, const double *vp, const double *lambda, double *r) {
  size_t nq = m->n_q;
  for (size_t i = 0; i < nq; i++) {
    r[i] = -m->F[i];
    for (size_t j = 0; j < nq; j++) r[i] += m->M[i * nq + j] * vp[j];
  }
  add_GT(m, lambda, r);
}

/* The residual of the form (ida_mbs.h). */
static int residual(mech *m, double t, const double *y, const double *yp, double *r) {
  size_t nq = m->n_q, nc = m->n_c;
  const double *q = y, *v = y + nq, *lambda = y + 2 * nq, *vp = yp + nq;
  double *rl = r + 2 * nq;
  int rc = dynamics(m, t, q, v);
  if (rc != 0) return rc;
  for (size_t i = 0; i < nq; i++) r[i] = yp[i] - v[i]; /* q' = v */
  momentum_rows(m, vp, lambda, r + nq);
  if (m->form == IDAMBS_INDEX1) {
    if ((rc = gamma_at(m, t, q, v, rl)) != 0) return rc;
    for (size_t i = 0; i < nc; i++)
      for (size_t j = 0; j < nq; j++) rl[i] += m->G[i * nq + j] * vp[j]; /* G v' + gamma = 0 */
    return 0;
  }
  add_GT(m, y + 2 * nq + nc, r); /* q' = v - G^T nu */
  if ((rc = constraint(m, t, q, rl)) != 0) return rc;
  return velocity_constraint(m, t, q, v, rl + nc);
}

/* ---- the consistent start ------------------------------------------------------------------- */

/* GSL's handler is off while factoring: a matrix that is not positive definite is a status
 * here, not an abort. */
static int spd_factor(double *A, size_t n) {
  gsl_error_handler_t *handler = gsl_set_error_handler_off();
  gsl_matrix_view a = gsl_matrix_view_array(A, n, n);
  int rc = gsl_linalg_cholesky_decomp1(&a.matrix);
  gsl_set_error_handler(handler);
  return rc == GSL_SUCCESS ? 0 : -1;
}

/* B = L^-T L^-1 B for each of the k columns of B (n x k, row-major), L from spd_factor */
static void spd_solve(double *L, size_t n, double *B, size_t k) {
  gsl_matrix_view a = gsl_matrix_view_array(L, n, n);
  for (size_t j = 0; j < k; j++) {
    gsl_vector_view col = gsl_vector_view_array_with_stride(B + j, k, n);
    gsl_linalg_cholesky_svx(&a.matrix, &col.vector);
  }
}

/* lambda and v' from (G M^-1 G^T) lambda = G M^-1 F + gamma, v' = M^-1 (F - G^T lambda) */
static int start_lambda(mech *m, double t, const double *q, const double *v, double *lambda,
                        double *vdot) {
  size_t nq = m->n_q, nc = m->n_c;
  if (dynamics(m, t, q, v) != 0 || gamma_at(m, t, q, v, lambda) != 0) return -1;
  for (size_t j = 0; j < nq; j++) {
    m->MiF[j] = m->F[j];
    for (size_t i = 0; i < nc; i++) m->MiGT[j * nc + i] = m->G[i * nq + j];
  }
  if (spd_factor(m->M, nq) != 0) return -1;
  spd_solve(m->M, nq, m->MiGT, nc);
  spd_solve(m->M, nq, m->MiF, 1);
  for (size_t i = 0; i < nc; i++) {
    for (size_t j = 0; j < nq; j++) lambda[i] += m->G[i * nq + j] * m->MiF[j];
    for (size_t l = 0; l < nc; l++) {
      m->A[i * nc + l] = 0.0;
      for (size_t j = 0; j < nq; j++) m->A[i * nc + l] += m->G[i * nq + j] * m->MiGT[j * nc + l];
    }
  }
  if (spd_factor(m->A, nc) != 0) return -1;
  spd_solve(m->A, nc, lambda, 1);
  for (size_t j = 0; vdot && j < nq; j++) {
    vdot[j] = m->MiF[j];
    for (size_t i = 0; i < nc; i++) vdot[j] -= m->MiGT[j * nc + i] * lambda[i];
  }
  return 0;
}

size_t idambs_dim(const sdae_mbs *sys, idambs_form form) {
  return 2 * sys->n_q + (form == IDAMBS_GGL ? 2 : 1) * sys->n_c;
}

int idambs_lambda(const sdae_mbs *sys, double t, const double *q, const double *v, double *lambda,
                  double *vdot) {
  mech m;
  int rc;
  if (mech_init(&m, sys, IDAMBS_INDEX1) != 0) return -1;
  rc = start_lambda(&m, t, q, v, lambda, vdot);
  mech_free(&m);
  return rc;
}

/* ---- the run -------------------------------------------------------------------------------- */

typedef struct run {
  mech m;
  idaref_ida ida;
  int configured; /* the linear solver attached: the counters can be read */
} run;

static int residual_cb(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void *user_data) {
  return residual(user_data, t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp),
                  N_VGetArrayPointer(rr));
}

/* y = (q0, v0, lambda[, nu = 0]), y' = (v0, v'[, 0, 0]) and the id vector (1 for q and v). */
static int consistent_start(run *r, double t0, const double *q0, const double *v0,
                            idaref_result *res) {
  size_t nq = r->m.n_q, n = idambs_dim(r->m.sys, r->m.form);
  double *y = N_VGetArrayPointer(r->ida.yy), *yp = N_VGetArrayPointer(r->ida.yp);
  double *id = N_VGetArrayPointer(r->ida.id);
  for (size_t i = 0; i < n; i++) {
    y[i] = yp[i] = 0.0;
    id[i] = i < 2 * nq ? 1.0 : 0.0;
  }
  memcpy(y, q0, nq * sizeof *q0);
  memcpy(y + nq, v0, nq * sizeof *v0);
  memcpy(yp, v0, nq * sizeof *v0);
  if (start_lambda(&r->m, t0, q0, v0, y + 2 * nq, yp + nq) == 0) return 0;
  res->function = "idambs_lambda";
  snprintf(res->flag_name, sizeof res->flag_name, "no consistent start");
  snprintf(res->message, sizeof res->message,
           "a callback failed or M or G M^-1 G^T is not positive definite at t = %.17g", t0);
  return -1;
}

/* Absolute tolerances: atol for q, v and lambda; 1 for GGL's nu, which vanishes on every
 * solution and which IDA computes as rounding noise of size eps |q| cj (as ida_solve.c says). */
static int set_tolerances(run *r, const idaref_options *o) {
  N_Vector atol = N_VClone(r->ida.yy);
  size_t nq = r->m.n_q, nc = r->m.n_c;
  int flag;
  if (!atol) return IDA_MEM_FAIL;
  for (size_t i = 0; i < idambs_dim(r->m.sys, r->m.form); i++)
    N_VGetArrayPointer(atol)[i] = i >= 2 * nq + nc ? 1.0 : o->atol;
  flag = IDASVtolerances(r->ida.mem, o->rtol, atol);
  N_VDestroy(atol);
  return flag;
}

/* The first step: the one whose backward-Euler local error in q, h^2 |q''| / 2, is the
 * tolerance, in IDA's weighted max norm (0: IDA's own choice, when q'' = 0). IDA's own choice,
 * h |y'| within the tolerance, is far smaller at tight tolerances, and there GGL's Newton
 * fails: its index-2 iteration matrix has a condition growing as 1/h^2 (the four-bar at rtol
 * 1e-10: IDA_CONV_FAIL at t = 0 with h = 3e-19). */
static double first_step(const run *r, const idaref_options *o) {
  const double *q = N_VGetArrayPointer(r->ida.yy);
  const double *qdd = N_VGetArrayPointer(r->ida.yp) + r->m.n_q;
  double worst = 0.0;
  for (size_t j = 0; j < r->m.n_q; j++)
    worst = fmax(worst, fabs(qdd[j]) / (o->rtol * fabs(q[j]) + o->atol));
  return worst > 0.0 ? sqrt(2.0 / worst) : 0.0;
}

static int configure(run *r, double t0, const idaref_options *o, idaref_result *res) {
  void *mem = r->ida.mem;
  if (idaref_failed(res, IDASetErrHandlerFn(mem, idaref_error_handler, res),
                    "IDASetErrHandlerFn") ||
      idaref_failed(res, IDAInit(mem, residual_cb, t0, r->ida.yy, r->ida.yp), "IDAInit") ||
      idaref_failed(res, IDASetUserData(mem, &r->m), "IDASetUserData") ||
      idaref_failed(res, set_tolerances(r, o), "IDASVtolerances") ||
      idaref_failed(res, IDASetLinearSolver(mem, r->ida.ls, r->ida.A), "IDASetLinearSolver") ||
      idaref_failed(res, IDASetId(mem, r->ida.id), "IDASetId") ||
      idaref_failed(res, IDASetMaxNumSteps(mem, o->max_steps), "IDASetMaxNumSteps"))
    return -1;
  /* lambda (and nu) out of the error test: they are functions of (q, v), as accurate as those
   * to the Newton tolerance; their own BDF error estimate, lambda changing much faster than q
   * on a mechanism, only costs steps (index 1: the four-bar's steps fall from 20000 to 2400) */
  if (idaref_failed(res, IDASetSuppressAlg(mem, SUNTRUE), "IDASetSuppressAlg") ||
      idaref_failed(res, IDASetInitStep(mem, first_step(r, o)), "IDASetInitStep"))
    return -1;
  r->configured = 1;
  return 0;
}

/* the rows as the caller wants them: (t, q, v, lambda) */
typedef struct emit_ctx {
  const run *r;
  idambs_row_fn row;
  void *ctx;
} emit_ctx;

static int emit(double t, const double *y, void *data) {
  const emit_ctx *e = data;
  size_t nq = e->r->m.n_q;
  return e->row(t, y, y + nq, y + 2 * nq, e->ctx);
}

int idambs_solve(const sdae_mbs *sys, idambs_form form, double t0, const double *q0,
                 const double *v0, const idaref_options *o, idambs_row_fn row, void *ctx,
                 idaref_result *res) {
  run r = {0};
  int status = IDAREF_IDA_FAILED;
  memset(res, 0, sizeof *res);
  res->t_reached = t0;
  emit_ctx e = {&r, row, ctx};
  if (mech_init(&r.m, sys, form) != 0) {
    idaref_failed(res, IDA_MEM_FAIL, "calloc");
    return status;
  }
  if (idaref_ida_create(&r.ida, idambs_dim(sys, form), res) == 0) {
    if (consistent_start(&r, t0, q0, v0, res) != 0)
      status = IDAMBS_START_FAILED;
    else if (configure(&r, t0, o, res) == 0)
      status = idaref_march(&r.ida, t0, o, emit, &e, res);
  }
  if (r.configured) idaref_collect_stats(r.ida.mem, &res->stats);
  idaref_ida_destroy(&r.ida);
  mech_free(&r.m);
  return status;
}
