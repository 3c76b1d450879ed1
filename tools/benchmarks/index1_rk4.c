/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The index-1 RK4 baseline and its rk8pd reference (index1_rk4.h). The derivatives along the
 * motion a mechanism leaves out are differenced as the front-end differences them
 * (src/mbs/mbs_eval.c): the fourth-order central difference
 *
 *   f'(0) ~ [8 (f(s) - f(-s)) - (f(2s) - f(-2s))] / (12 s)
 *
 * with s about eps^(1/5) of the motion's scale, so that both pay the same four calls for it and
 * neither is the more accurate by its stencil. */
#include "index1_rk4.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "core/difference.h"
#include "core/lu.h"

/* The saddle-point system [M G^T; G 0] [a; lambda] = [F; -gamma] by its Schur complement, in
 * the library's own written-out Cholesky (src/core/lu.c), as lean as the front-end's solves
 * (GSL's banded LU, used here before, took three quarters of this step in BLAS calls and views
 * for these small systems): M = L L^T, Y = M^-1 G^T, S = G Y, S lambda = G M^-1 F + gamma,
 * a = M^-1 F - Y lambda. It needs M positive definite (the library needs its reduced mass
 * positive definite only). */
struct index1 {
  sdae_mbs sys;
  size_t n_q, n_c;
  double *S, *Y, *lambda; /* n_c x n_c (factored in place), n_c x n_q (rows M^-1 G_r^T), n_c */
  double *M, *F, *G, *Gs, *gamma, *g, *gk, *ct; /* g: the stencil's sum, gk: its k-th value */
  double *qs;                                   /* a stencil point, or a stage's q */
  double *kq[4], *kv[4], *sq, *sv;              /* RK4's stage rates and stage state */
  double *block;                                /* every array above, one allocation */
};

index1 *index1_alloc(const sdae_mbs *sys) {
  size_t n = sys->n_q, m = sys->n_c;
  if (!sys->mass || !sys->force || !sys->jacobian || m == 0 || m >= n) return NULL;
  index1 *w = calloc(1, sizeof *w);
  /* S, Y, lambda, M, F, G, Gs, gamma, g, gk, ct, qs, kq[4], kv[4], sq, sv */
  size_t total = m * m + m * n + m + n * n + n + 2 * m * n + 4 * m + n + 8 * n + 2 * n;
  if (!w || !(w->block = malloc(total * sizeof(double)))) {
    index1_free(w);
    return NULL;
  }
  w->sys = *sys, w->n_q = n, w->n_c = m;
  double *p = w->block;
  w->S = p, p += m * m;
  w->Y = p, p += m * n;
  w->lambda = p, p += m;
  w->M = p, p += n * n;
  w->F = p, p += n;
  w->G = p, p += m * n;
  w->Gs = p, p += m * n;
  w->gamma = p, p += m;
  w->g = p, p += m;
  w->gk = p, p += m;
  w->ct = p, p += m;
  w->qs = p, p += n;
  for (int s = 0; s < 4; s++) w->kq[s] = p, p += n;
  for (int s = 0; s < 4; s++) w->kv[s] = p, p += n;
  w->sq = p, p += n;
  w->sv = p;
  return w;
}

void index1_free(index1 *w) {
  if (!w) return;
  free(w->block);
  free(w);
}

index1_source index1_gdot_source(const index1 *w) {
  return w->sys.jacobian_dot ? INDEX1_GIVEN : INDEX1_DIFFERENCES;
}

index1_source index1_ct_dot_source(const index1 *w) {
  if (!w->sys.constraint_t) return INDEX1_ZERO;
  return w->sys.constraint_t_dot ? INDEX1_GIVEN : INDEX1_DIFFERENCES;
}

/* the larger of m and |x|, written out: fmax is a call (its NaN rules), on every stage's path */
static double max_abs(double m, double x) { return fabs(x) > m ? fabs(x) : m; }

static double inf_norm(const double *x, size_t n) {
  double m = 0.0;
  for (size_t i = 0; i < n; i++) m = max_abs(m, x[i]);
  return m;
}

/* out += A v, A n_c x n_q row-major */
static void add_product(const double *A, const double *v, size_t rows, size_t cols, double *out) {
  for (size_t i = 0; i < rows; i++) {
    double s = 0.0;
    for (size_t j = 0; j < cols; j++) s += A[i * cols + j] * v[j];
    out[i] += s;
  }
}

/* gamma = Gdot v + d/ds c_t(t + s, q + s v): the given derivatives called once, the others
 * differenced together on one stencil of g(s) = G(s) v + c_t(s) (the terms not given) */
static int gamma_at(index1 *w, double t, const double *q, const double *v) {
  const sdae_mbs *s = &w->sys;
  size_t n = w->n_q, m = w->n_c;
  int fd_G = !s->jacobian_dot, fd_ct = s->constraint_t && !s->constraint_t_dot, rc;
  memset(w->gamma, 0, m * sizeof *w->gamma);
  if (s->jacobian_dot) {
    if ((rc = s->jacobian_dot(t, q, v, w->Gs, s->params)) != 0) return rc;
    add_product(w->Gs, v, m, n, w->gamma);
  }
  if (s->constraint_t && s->constraint_t_dot) {
    if ((rc = s->constraint_t_dot(t, q, v, w->ct, s->params)) != 0) return rc;
    for (size_t i = 0; i < m; i++) w->gamma[i] += w->ct[i];
  }
  if (!fd_G && !fd_ct) return 0;
  /* the front-end's step along (1, v): eps^(1/5) when |v| is small against 1 + |q|, shorter as
   * the motion is faster */
  double nq = inf_norm(q, n);
  double h = sdae__fd_step(t, SDAE_FD_STEP * (1.0 + nq) / (1.0 + nq + inf_norm(v, n)));
  memset(w->g, 0, m * sizeof *w->g);
  for (int k = 0; k < SDAE_FD_POINTS; k++) {
    double ts = t + sdae__fd_offset[k] * h;
    for (size_t j = 0; j < n; j++) w->qs[j] = q[j] + sdae__fd_offset[k] * h * v[j];
    memset(w->gk, 0, m * sizeof *w->gk);
    if (fd_G) {
      if ((rc = s->jacobian(ts, w->qs, w->Gs, s->params)) != 0) return rc;
      add_product(w->Gs, v, m, n, w->gk);
    }
    if (fd_ct) {
      if ((rc = s->constraint_t(ts, w->qs, w->ct, s->params)) != 0) return rc;
      for (size_t i = 0; i < m; i++) w->gk[i] += w->ct[i];
    }
    sdae__fd_add(w->g, 1, w->gk, m, k);
  }
  sdae__fd_finish(w->g, 1, m, h);
  for (size_t i = 0; i < m; i++) w->gamma[i] += w->g[i];
  return 0;
}

/* The Schur complement's solve (above): M and S factored by Cholesky; -1 when either is not
 * positive definite to working precision */
int index1_accel(index1 *w, double t, const double *q, const double *v, double *a) {
  const sdae_mbs *s = &w->sys;
  size_t n = w->n_q, m = w->n_c;
  int rc;
  if ((rc = s->mass(t, q, w->M, s->params)) != 0 ||
      (rc = s->force(t, q, v, w->F, s->params)) != 0 ||
      (rc = s->jacobian(t, q, w->G, s->params)) != 0 || (rc = gamma_at(w, t, q, v)) != 0)
    return rc;
  if (sdae__cholesky_factor(w->M, n) != 0) return -1;
  memcpy(a, w->F, n * sizeof *a);
  sdae__cholesky_solve(w->M, n, a); /* a = M^-1 F */
  for (size_t r = 0; r < m; r++) {  /* Y's row r = M^-1 G_r^T; S's row r = G Y_r */
    double *y = w->Y + r * n;
    memcpy(y, w->G + r * n, n * sizeof *y);
    sdae__cholesky_solve(w->M, n, y);
    w->lambda[r] = w->gamma[r];
    for (size_t j = 0; j < n; j++) w->lambda[r] += w->G[r * n + j] * a[j];
    for (size_t c = 0; c <= r; c++) { /* symmetric: the lower triangle, mirrored */
      double acc = 0.0;
      for (size_t j = 0; j < n; j++) acc += w->G[c * n + j] * y[j];
      w->S[r * m + c] = w->S[c * m + r] = acc;
    }
  }
  if (sdae__cholesky_factor(w->S, m) != 0) return -1;
  sdae__cholesky_solve(w->S, m, w->lambda);
  for (size_t r = 0; r < m; r++)
    for (size_t j = 0; j < n; j++) a[j] -= w->Y[r * n + j] * w->lambda[r];
  for (size_t j = 0; j < n; j++)
    if (!isfinite(a[j])) return -1;
  return 0;
}

/* stage s's rate (kq, kv) = (v_s, a(t_s, q_s, v_s)) */
static int stage(index1 *w, int s, double ts, const double *qs, const double *vs) {
  memcpy(w->kq[s], vs, w->n_q * sizeof *vs);
  return index1_accel(w, ts, qs, vs, w->kv[s]);
}

/* (sq, sv) = (q, v) + c T k_s */
static void advance(index1 *w, const double *q, const double *v, double cT, int s) {
  for (size_t j = 0; j < w->n_q; j++) {
    w->sq[j] = q[j] + cT * w->kq[s][j];
    w->sv[j] = v[j] + cT * w->kv[s][j];
  }
}

int index1_rk4_step(index1 *w, double t, double T, double *q, double *v) {
  int rc;
  if ((rc = stage(w, 0, t, q, v)) != 0) return rc;
  advance(w, q, v, 0.5 * T, 0);
  if ((rc = stage(w, 1, t + 0.5 * T, w->sq, w->sv)) != 0) return rc;
  advance(w, q, v, 0.5 * T, 1);
  if ((rc = stage(w, 2, t + 0.5 * T, w->sq, w->sv)) != 0) return rc;
  advance(w, q, v, T, 2);
  if ((rc = stage(w, 3, t + T, w->sq, w->sv)) != 0) return rc;
  for (size_t j = 0; j < w->n_q; j++) {
    q[j] += T / 6.0 * (w->kq[0][j] + 2.0 * (w->kq[1][j] + w->kq[2][j]) + w->kq[3][j]);
    v[j] += T / 6.0 * (w->kv[0][j] + 2.0 * (w->kv[1][j] + w->kv[2][j]) + w->kv[3][j]);
  }
  return 0;
}

/* the index-1 ODE for GSL: y = (q, v) */
static int ode(double t, const double *y, double *dydt, void *params) {
  index1 *w = params;
  size_t n = w->n_q;
  memcpy(dydt, y + n, n * sizeof *y);
  return index1_accel(w, t, y, y + n, dydt + n) ? GSL_EBADFUNC : GSL_SUCCESS;
}

int index1_reference(index1 *w, double t0, double tf, double tol, double *q, double *v,
                     unsigned long *steps) {
  size_t n = w->n_q;
  double *y = malloc(2 * n * sizeof *y), t = t0;
  gsl_odeiv2_system sys = {ode, NULL, 2 * n, w};
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-3 * (tf - t0), tol, tol);
  int rc = GSL_ENOMEM;
  if (y && d) {
    memcpy(y, q, n * sizeof *y);
    memcpy(y + n, v, n * sizeof *y);
    if ((rc = gsl_odeiv2_driver_apply(d, &t, tf, y)) == GSL_SUCCESS) {
      memcpy(q, y, n * sizeof *y);
      memcpy(v, y + n, n * sizeof *y);
    }
    if (steps) *steps = d->n;
  }
  if (d) gsl_odeiv2_driver_free(d);
  free(y);
  return rc;
}
