/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Residuals and iteration matrices of the index-reduced oscillator and pendulum; see
 * ida_models.h for the equations. */
#include "ida_models.h"

#include <math.h>
#include <string.h>

/* The pieces of the mechanical system at one state: applied force, its derivatives, and the
 * constraint with its gradient G and (constant) Hessian H. Matrices are [row][column]. */
typedef struct mech {
  double f[2], dfdq[2][2], dfdv[2][2];
  double h, G[2], H[2][2];
} mech;

static void oscillator_mech(const idaref_model *p, const double *q, const double *v, mech *s) {
  s->f[0] = -p->k * q[0] * q[0] * q[0] - p->d * v[0];
  s->f[1] = -p->m * p->ga;
  s->dfdq[0][0] = -3.0 * p->k * q[0] * q[0];
  s->dfdv[0][0] = -p->d;
  s->h = q[1];
  s->G[0] = 0.0;
  s->G[1] = 1.0;
}

static void pendulum_mech(const idaref_model *p, const double *q, mech *s) {
  s->f[0] = 0.0;
  s->f[1] = -p->m * p->ga;
  s->h = 0.5 * (q[0] * q[0] + q[1] * q[1] - p->L * p->L);
  s->G[0] = q[0];
  s->G[1] = q[1];
  s->H[0][0] = 1.0;
  s->H[1][1] = 1.0;
}

static void eval_mech(const idaref_model *p, const double *q, const double *v, mech *s) {
  memset(s, 0, sizeof *s);
  if (p->kind == IDAREF_OSCILLATOR)
    oscillator_mech(p, q, v, s);
  else
    pendulum_mech(p, q, s);
}

/* Acceleration from the dynamics: q'' = (f - G^T lambda) / m. */
static void acceleration(const idaref_model *p, const mech *s, double lambda, double *acc) {
  for (int i = 0; i < 2; i++) acc[i] = (s->f[i] - s->G[i] * lambda) / p->m;
}

/* v^T H v, the part of hdd that does not involve q''. */
static double curvature(const mech *s, const double *v) {
  double c = 0.0;
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) c += v[i] * s->H[i][j] * v[j];
  return c;
}

idaref_model idaref_model_default(idaref_kind kind) {
  idaref_model p = {.kind = kind, .k = 2.0, .d = 0.03, .L = 1.0, .m = 1.0, .ga = 9.81};
  return p;
}

size_t idaref_dim(idaref_form form) { return form == IDAREF_GGL ? 6 : 5; }

void idaref_id(idaref_form form, double *id) {
  size_t n = idaref_dim(form);
  for (size_t i = 0; i < n; i++) id[i] = i < IDAREF_LAMBDA ? 1.0 : 0.0;
}

void idaref_residual(const idaref_model *p, idaref_form form, const double *y, const double *yp,
                     double *r) {
  const double *q = y, *v = y + IDAREF_XDOT;
  double lambda = y[IDAREF_LAMBDA];
  double nu = form == IDAREF_GGL ? y[IDAREF_NU] : 0.0;
  mech s;
  double acc[2];
  eval_mech(p, q, v, &s);
  acceleration(p, &s, lambda, acc);
  for (int i = 0; i < 2; i++) {
    r[i] = yp[i] - v[i] + s.G[i] * nu; /* q' = v - G^T nu (nu only in ggl) */
    r[2 + i] = yp[2 + i] - acc[i];     /* v' = (f - G^T lambda) / m */
  }
  if (form == IDAREF_INDEX1) {
    r[4] = s.G[0] * acc[0] + s.G[1] * acc[1] + curvature(&s, v); /* hdd = 0 */
  } else {
    r[4] = s.h;                           /* h = 0 */
    r[5] = s.G[0] * v[0] + s.G[1] * v[1]; /* hdot = G v = 0 */
  }
}

void idaref_jacobian(const idaref_model *p, idaref_form form, double cj, const double *y,
                     double *J) {
  const size_t n = idaref_dim(form);
  const double *q = y, *v = y + IDAREF_XDOT;
  double lambda = y[IDAREF_LAMBDA];
  double nu = form == IDAREF_GGL ? y[IDAREF_NU] : 0.0;
  mech s;
  double acc[2], dacc_dq[2][2], dacc_dv[2][2];
  eval_mech(p, q, v, &s);
  acceleration(p, &s, lambda, acc);
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      dacc_dq[i][j] = (s.dfdq[i][j] - s.H[i][j] * lambda) / p->m; /* dG_i/dq_j = H_ij */
      dacc_dv[i][j] = s.dfdv[i][j] / p->m;
    }
  memset(J, 0, n * n * sizeof *J);
#define JAC(i, j) J[(size_t)(i)*n + (size_t)(j)]
  for (int i = 0; i < 2; i++) {
    JAC(i, i) = cj;
    JAC(i, 2 + i) = -1.0;
    JAC(2 + i, 2 + i) = cj;
    JAC(2 + i, IDAREF_LAMBDA) = s.G[i] / p->m;
    for (int j = 0; j < 2; j++) {
      JAC(2 + i, j) = -dacc_dq[i][j];
      JAC(2 + i, 2 + j) -= dacc_dv[i][j];
    }
  }
  if (form == IDAREF_INDEX1) {
    /* r4 = sum_i G_i acc_i + v^T H v with H constant */
    for (int j = 0; j < 2; j++) {
      double dq = 0.0, dv = 0.0;
      for (int i = 0; i < 2; i++) {
        dq += s.H[i][j] * acc[i] + s.G[i] * dacc_dq[i][j];
        dv += s.G[i] * dacc_dv[i][j] + 2.0 * s.H[j][i] * v[i];
      }
      JAC(4, j) = dq;
      JAC(4, 2 + j) = dv;
    }
    JAC(4, IDAREF_LAMBDA) = -(s.G[0] * s.G[0] + s.G[1] * s.G[1]) / p->m;
  } else {
    for (int i = 0; i < 2; i++) {
      for (int j = 0; j < 2; j++) JAC(i, j) += s.H[i][j] * nu;
      JAC(i, IDAREF_NU) = s.G[i];
      JAC(4, i) = s.G[i];
      JAC(5, i) = s.H[i][0] * v[0] + s.H[i][1] * v[1];
      JAC(5, 2 + i) = s.G[i];
    }
  }
#undef JAC
}

double idaref_h(const idaref_model *p, const double *x) {
  mech s;
  eval_mech(p, x, x + 2, &s);
  return s.h;
}

double idaref_hdot(const idaref_model *p, const double *x) {
  mech s;
  eval_mech(p, x, x + 2, &s);
  return s.G[0] * x[2] + s.G[1] * x[3];
}

double idaref_energy(const idaref_model *p, const double *x) {
  double e = 0.5 * p->m * (x[2] * x[2] + x[3] * x[3]) + p->m * p->ga * x[1];
  if (p->kind == IDAREF_OSCILLATOR) e += 0.25 * p->k * x[0] * x[0] * x[0] * x[0];
  return e;
}

/* Removes the component of v along G: v <- v - G^T (G v) / |G|^2 (Euclidean projection). */
static void remove_component(const double *G, double *v) {
  double g2 = G[0] * G[0] + G[1] * G[1];
  double c = (G[0] * v[0] + G[1] * v[1]) / g2;
  v[0] -= c * G[0];
  v[1] -= c * G[1];
}

int idaref_project(const idaref_model *p, double *x) {
  enum { MAX_ITERS = 60 };
  double z[4];
  memcpy(z, x, sizeof z);
  for (int it = 0;; it++) {
    mech s;
    eval_mech(p, z, z + 2, &s);
    double g2 = s.G[0] * s.G[0] + s.G[1] * s.G[1];
    double scale = 1.0 + fabs(z[0]) + fabs(z[1]);
    if (!(g2 > 0.0) || !isfinite(s.h) || it == MAX_ITERS) return -1;
    if (fabs(s.h) <= 1e-15 * scale * scale) {
      remove_component(s.G, z + 2);
      break;
    }
    z[0] -= s.G[0] * s.h / g2; /* minimum-norm Newton step for h(q) = 0 */
    z[1] -= s.G[1] * s.h / g2;
  }
  memcpy(x, z, sizeof z);
  return 0;
}

void idaref_initial_guess(const idaref_model *p, idaref_form form, const double *x, double *y,
                          double *yp) {
  mech s;
  eval_mech(p, x, x + 2, &s);
  memset(y, 0, idaref_dim(form) * sizeof *y);
  memset(yp, 0, idaref_dim(form) * sizeof *yp);
  memcpy(y, x, 4 * sizeof *y);
  yp[0] = x[2];
  yp[1] = x[3];
  yp[2] = s.f[0] / p->m;
  yp[3] = s.f[1] / p->m;
}
