/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The index-1 form (index1.h): the callbacks' statuses, the derivatives by the library's
 * stencil, gamma, and the saddle-point system by its Schur complement. */
#include "index1.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/difference.h"
#include "core/lu.h"

struct index1 {
  sdae_mbs sys;
  size_t n_q, n_c, m_len, g_len; /* m_len, g_len: the values mass() and jacobian() write */
  double *block;                 /* every array below */
  double *Gs, *ct;               /* G or Gdot, dc/dt or its derivative, where gamma is formed */
  double *g, *gk;                /* a stencil's sum and its k-th value */
  double *qa, *qj, *cj, *Fi;     /* points along (1, v) and of G's differences, c there; input */
  /* index1_accel's, with solve: the mechanism's M, F, G; M and G dense (themselves without
   * patterns); Y = M^-1 G^T by rows, S = G Y (factored in place), lambda */
  double *M, *F, *G, *Md, *Gd, *Y, *S, *lambda;
};

/* a pattern of rows x cols (pattern.h): row_start from 0 to nnz, columns ascending, below cols */
static int pattern_ok(const sdae_pattern *p, size_t rows, size_t cols) {
  if (!p->row_start || (p->nnz > 0 && !p->col) || p->row_start[0] != 0 ||
      p->row_start[rows] != p->nnz)
    return 0;
  for (size_t i = 0; i < rows; i++) {
    if (p->row_start[i + 1] < p->row_start[i]) return 0;
    for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++)
      if (p->col[k] >= cols || (k > p->row_start[i] && p->col[k] <= p->col[k - 1])) return 0;
  }
  return 1;
}

const char *index1_refused(const sdae_mbs *sys) {
  if (!sys->mass || !sys->force || !sys->constraint) return "mass, force and constraint needed";
  if (sys->mass_pattern && !pattern_ok(sys->mass_pattern, sys->n_q, sys->n_q))
    return "mass_pattern is not a pattern of n_q rows and columns (pattern.h)";
  if (sys->jacobian_pattern && !pattern_ok(sys->jacobian_pattern, sys->n_c, sys->n_q))
    return "jacobian_pattern is not a pattern of n_c rows and n_q columns (pattern.h)";
  if (sys->jacobian_pattern && !sys->jacobian)
    return "jacobian_pattern without jacobian: G's differences are dense";
  return NULL;
}

index1 *index1_alloc(const sdae_mbs *sys, int solve) {
  size_t n = sys->n_q, m = sys->n_c, d = solve ? 1 : 0;
  size_t m_len = sys->mass_pattern ? sys->mass_pattern->nnz : n * n;
  size_t g_len = sys->jacobian_pattern ? sys->jacobian_pattern->nnz : m * n;
  size_t len[] = {g_len,     m,     m,         m,         n,         n,         m,         n,
                  d * m_len, d * n, d * g_len, d * n * n, d * m * n, d * m * n, d * m * m, d * m};
  index1 *w;
  size_t total = 1; /* a block of one double at least */
  if (index1_refused(sys) || !(w = calloc(1, sizeof *w))) return NULL;
  for (size_t i = 0; i < sizeof len / sizeof len[0]; i++) total += len[i];
  if (!(w->block = calloc(total, sizeof *w->block))) {
    free(w);
    return NULL;
  }
  double **dst[] = {&w->Gs, &w->ct, &w->g, &w->gk, &w->qa, &w->qj, &w->cj, &w->Fi,
                    &w->M,  &w->F,  &w->G, &w->Md, &w->Gd, &w->Y,  &w->S,  &w->lambda};
  double *p = w->block;
  for (size_t i = 0; i < sizeof len / sizeof len[0]; i++) *dst[i] = p, p += len[i];
  w->sys = *sys, w->n_q = n, w->n_c = m, w->m_len = m_len, w->g_len = g_len;
  if (solve && !sys->mass_pattern) w->Md = w->M;
  if (solve && !sys->jacobian_pattern) w->Gd = w->G;
  if (!solve) w->M = NULL;
  return w;
}

void index1_free(index1 *w) {
  if (!w) return;
  free(w->block);
  free(w);
}

index1_source index1_gdot_source(const index1 *w) {
  return w->sys.jacobian && w->sys.jacobian_dot ? INDEX1_GIVEN : INDEX1_DIFFERENCES;
}

index1_source index1_ct_dot_source(const index1 *w) {
  return w->sys.constraint_t && w->sys.constraint_t_dot ? INDEX1_GIVEN : INDEX1_DIFFERENCES;
}

int index1_status(int rc, const double *x, size_t n) {
  if (rc != 0) return rc < 0 ? -1 : 1;
  for (size_t i = 0; i < n; i++)
    if (!isfinite(x[i])) return 1;
  return 0;
}

/* the larger of m and |x|, written out: fmax is a call (its NaN rules), on every stage's path */
static double max_abs(double m, double x) { return fabs(x) > m ? fabs(x) : m; }

static double inf_norm(const double *x, size_t n) {
  double m = 0.0;
  for (size_t i = 0; i < n; i++) m = max_abs(m, x[i]);
  return m;
}

void index1_mul_add(const sdae_pattern *p, const double *a, size_t rows, size_t cols,
                    const double *x, double *y) {
  if (!p) {
    for (size_t i = 0; i < rows; i++) {
      double s = 0.0;
      for (size_t j = 0; j < cols; j++) s += a[i * cols + j] * x[j];
      y[i] += s;
    }
    return;
  }
  for (size_t i = 0; i < rows; i++)
    for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++) y[i] += a[k] * x[p->col[k]];
}

/* the dense rows x cols matrix of A's nonzeros in p's order */
static void expand(const sdae_pattern *p, const double *a, size_t rows, size_t cols, double *d) {
  memset(d, 0, rows * cols * sizeof *d);
  for (size_t i = 0; i < rows; i++)
    for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++) d[i * cols + p->col[k]] = a[k];
}

int index1_constraint(index1 *w, double t, const double *q, double *c) {
  return index1_status(w->sys.constraint(t, q, c, w->sys.params), c, w->n_c);
}

/* G column by column: d/dh c(t, q + h e_j), row-major */
static int jacobian_differences(index1 *w, double t, const double *q, double *G) {
  size_t n = w->n_q, m = w->n_c;
  memcpy(w->qj, q, n * sizeof *q);
  for (size_t j = 0; j < n; j++) {
    double h = sdae__fd_step(q[j], SDAE_FD_STEP * fmax(1.0, fabs(q[j])));
    for (size_t i = 0; i < m; i++) G[i * n + j] = 0.0;
    for (int k = 0; k < SDAE_FD_POINTS; k++) {
      int rc;
      w->qj[j] = q[j] + sdae__fd_offset[k] * h;
      if ((rc = index1_constraint(w, t, w->qj, w->cj)) != 0) return rc;
      sdae__fd_add(G + j, n, w->cj, m, k);
    }
    sdae__fd_finish(G + j, n, m, h);
    w->qj[j] = q[j];
  }
  return 0;
}

int index1_jacobian(index1 *w, double t, const double *q, double *G) {
  if (!w->sys.jacobian) return jacobian_differences(w, t, q, G);
  return index1_status(w->sys.jacobian(t, q, G, w->sys.params), G, w->g_len);
}

int index1_force(index1 *w, double t, const double *q, const double *v, double *F) {
  const sdae_mbs *s = &w->sys;
  int rc = index1_status(s->force(t, q, v, F, s->params), F, w->n_q);
  if (rc != 0 || !s->input_force) return rc;
  if ((rc = index1_status(s->input_force(t, q, v, w->Fi, s->params), w->Fi, w->n_q)) != 0)
    return rc;
  for (size_t j = 0; j < w->n_q; j++) F[j] += w->Fi[j];
  return 0;
}

/* dc/dt: the callback, or d/dh c(t + h, q) (exactly 0 when c does not depend on t) */
static int constraint_t(index1 *w, double t, const double *q, double *ct) {
  double h = sdae__fd_step(t, SDAE_FD_STEP * fmax(1.0, fabs(t)));
  if (w->sys.constraint_t)
    return index1_status(w->sys.constraint_t(t, q, ct, w->sys.params), ct, w->n_c);
  memset(ct, 0, w->n_c * sizeof *ct);
  for (int k = 0; k < SDAE_FD_POINTS; k++) {
    int rc = index1_constraint(w, t + sdae__fd_offset[k] * h, q, w->cj);
    if (rc != 0) return rc;
    sdae__fd_add(ct, 1, w->cj, w->n_c, k);
  }
  sdae__fd_finish(ct, 1, w->n_c, h);
  return 0;
}

/* What the stencil along (1, v) differences at one of its points: c itself (of_c), or the
 * terms of G v + dc/dt whose derivative the mechanism does not give. */
static int stencil_value(index1 *w, int of_c, double t, const double *q, const double *v,
                         double *out) {
  int rc;
  if (of_c) return index1_constraint(w, t, q, out);
  memset(out, 0, w->n_c * sizeof *out);
  if (index1_gdot_source(w) == INDEX1_DIFFERENCES) {
    if ((rc = index1_jacobian(w, t, q, w->Gs)) != 0) return rc;
    index1_mul_add(w->sys.jacobian_pattern, w->Gs, w->n_c, w->n_q, v, out);
  }
  if (index1_ct_dot_source(w) == INDEX1_DIFFERENCES) {
    if ((rc = constraint_t(w, t, q, w->ct)) != 0) return rc;
    for (size_t i = 0; i < w->n_c; i++) out[i] += w->ct[i];
  }
  return 0;
}

/* d^order/ds^order of stencil_value at (t + s, q + s v), s = 0, into out (n_c values); the step
 * scaled so that the displacement h |v| stays near h0 relative to |q|: eps^(1/5) (eps^(1/6) for
 * the second derivative) when |v| is small against 1 + |q|, shorter as the motion is faster */
static int along(index1 *w, int order, int of_c, double t, const double *q, const double *v,
                 double *out) {
  double nq = inf_norm(q, w->n_q), h0 = order == 1 ? SDAE_FD_STEP : SDAE_FD2_STEP;
  double h = sdae__fd_step(t, h0 * (1.0 + nq) / (1.0 + nq + inf_norm(v, w->n_q)));
  memset(out, 0, w->n_c * sizeof *out);
  for (int k = 0; k < (order == 1 ? SDAE_FD_POINTS : SDAE_FD2_POINTS); k++) {
    int rc;
    for (size_t j = 0; j < w->n_q; j++) w->qa[j] = q[j] + sdae__fd_offset[k] * h * v[j];
    if ((rc = stencil_value(w, of_c, t + sdae__fd_offset[k] * h, w->qa, v, w->gk)) != 0) return rc;
    if (order == 1)
      sdae__fd_add(out, 1, w->gk, w->n_c, k);
    else
      sdae__fd2_add(out, 1, w->gk, w->n_c, k);
  }
  if (order == 1)
    sdae__fd_finish(out, 1, w->n_c, h);
  else
    sdae__fd2_finish(out, 1, w->n_c, h);
  return 0;
}

int index1_velocity(index1 *w, double t, const double *q, const double *v, double *g) {
  int rc;
  if (!w->sys.jacobian) return along(w, 1, 1, t, q, v, g);
  if ((rc = index1_jacobian(w, t, q, w->Gs)) != 0 || (rc = constraint_t(w, t, q, g)) != 0)
    return rc;
  index1_mul_add(w->sys.jacobian_pattern, w->Gs, w->n_c, w->n_q, v, g);
  return 0;
}

/* gamma: the given derivatives called once, the other terms differenced together on one
 * stencil; without jacobian, d^2/ds^2 c(t + s, q + s v) */
int index1_gamma(index1 *w, double t, const double *q, const double *v, double *gamma) {
  const sdae_mbs *s = &w->sys;
  size_t n = w->n_q, m = w->n_c;
  int gdot = index1_gdot_source(w) == INDEX1_GIVEN, rc;
  int ct_dot = index1_ct_dot_source(w) == INDEX1_GIVEN;
  if (!s->jacobian) return along(w, 2, 1, t, q, v, gamma);
  memset(gamma, 0, m * sizeof *gamma);
  if (gdot) {
    if ((rc = index1_status(s->jacobian_dot(t, q, v, w->Gs, s->params), w->Gs, w->g_len)) != 0)
      return rc;
    index1_mul_add(s->jacobian_pattern, w->Gs, m, n, v, gamma);
  }
  if (ct_dot) {
    if ((rc = index1_status(s->constraint_t_dot(t, q, v, w->ct, s->params), w->ct, m)) != 0)
      return rc;
    for (size_t i = 0; i < m; i++) gamma[i] += w->ct[i];
  }
  if (gdot && ct_dot) return 0;
  if ((rc = along(w, 1, 0, t, q, v, w->g)) != 0) return rc;
  for (size_t i = 0; i < m; i++) gamma[i] += w->g[i];
  return 0;
}

/* M, F, G and gamma (into lambda) at (t, q, v), M and G dense in Md, Gd */
static int saddle_point(index1 *w, double t, const double *q, const double *v) {
  const sdae_mbs *s = &w->sys;
  int rc;
  if ((rc = index1_status(s->mass(t, q, w->M, s->params), w->M, w->m_len)) != 0 ||
      (rc = index1_force(w, t, q, v, w->F)) != 0 || (rc = index1_jacobian(w, t, q, w->G)) != 0 ||
      (rc = index1_gamma(w, t, q, v, w->lambda)) != 0)
    return rc;
  if (s->mass_pattern) expand(s->mass_pattern, w->M, w->n_q, w->n_q, w->Md);
  if (s->jacobian_pattern) expand(s->jacobian_pattern, w->G, w->n_c, w->n_q, w->Gd);
  return 0;
}

int index1_accel(index1 *w, double t, const double *q, const double *v, double *vdot,
                 double *lambda) {
  size_t n = w->n_q, m = w->n_c;
  int rc;
  if (!w->M) return -1;
  if ((rc = saddle_point(w, t, q, v)) != 0) return rc;
  if (sdae__cholesky_factor(w->Md, n) != 0) return -1;
  memcpy(vdot, w->F, n * sizeof *vdot);
  sdae__cholesky_solve(w->Md, n, vdot); /* v' = M^-1 F, for now */
  for (size_t r = 0; r < m; r++) {      /* Y's row r = M^-1 G_r^T; S's row r = G Y_r */
    double *y = w->Y + r * n;
    memcpy(y, w->Gd + r * n, n * sizeof *y);
    sdae__cholesky_solve(w->Md, n, y);
    for (size_t j = 0; j < n; j++) w->lambda[r] += w->Gd[r * n + j] * vdot[j];
    for (size_t c = 0; c <= r; c++) { /* symmetric: the lower triangle, mirrored */
      double acc = 0.0;
      for (size_t j = 0; j < n; j++) acc += w->Gd[c * n + j] * y[j];
      w->S[r * m + c] = w->S[c * m + r] = acc;
    }
  }
  if (sdae__cholesky_factor(w->S, m) != 0) return -1;
  sdae__cholesky_solve(w->S, m, w->lambda);
  for (size_t r = 0; r < m; r++)
    for (size_t j = 0; j < n; j++) vdot[j] -= w->Y[r * n + j] * w->lambda[r];
  for (size_t j = 0; j < n; j++)
    if (!isfinite(vdot[j])) return -1;
  if (lambda) memcpy(lambda, w->lambda, m * sizeof *lambda);
  return 0;
}
