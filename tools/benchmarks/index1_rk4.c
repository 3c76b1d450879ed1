/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The index-1 RK4 baseline and its rk8pd reference (index1_rk4.h). */
#include "index1_rk4.h"

#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

struct index1_rk4 {
  index1 *form;
  size_t n_q;
  double *kq[4], *kv[4], *sq, *sv; /* the stages' rates and a stage's state */
  double *block;                   /* every array above, one allocation */
};

index1_rk4 *index1_rk4_alloc(const sdae_mbs *sys) {
  size_t n = sys->n_q;
  index1_rk4 *w;
  if (!sys->jacobian || !(w = calloc(1, sizeof *w))) return NULL;
  w->n_q = n;
  if (!(w->form = index1_alloc(sys, 1)) || !(w->block = malloc((10 * n + 1) * sizeof(double)))) {
    index1_rk4_free(w);
    return NULL;
  }
  double *p = w->block;
  for (int s = 0; s < 4; s++) w->kq[s] = p, p += n;
  for (int s = 0; s < 4; s++) w->kv[s] = p, p += n;
  w->sq = p, p += n;
  w->sv = p;
  return w;
}

void index1_rk4_free(index1_rk4 *w) {
  if (!w) return;
  index1_free(w->form);
  free(w->block);
  free(w);
}

const index1 *index1_rk4_form(const index1_rk4 *w) { return w->form; }

/* stage s's rate (kq, kv) = (v_s, v'(t_s, q_s, v_s)) */
static int stage(index1_rk4 *w, int s, double ts, const double *qs, const double *vs) {
  memcpy(w->kq[s], vs, w->n_q * sizeof *vs);
  return index1_accel(w->form, ts, qs, vs, w->kv[s], NULL);
}

/* (sq, sv) = (q, v) + c T k_s */
static void advance(index1_rk4 *w, const double *q, const double *v, double cT, int s) {
  for (size_t j = 0; j < w->n_q; j++) {
    w->sq[j] = q[j] + cT * w->kq[s][j];
    w->sv[j] = v[j] + cT * w->kv[s][j];
  }
}

int index1_rk4_step(index1_rk4 *w, double t, double T, double *q, double *v) {
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
  index1_rk4 *w = params;
  size_t n = w->n_q;
  memcpy(dydt, y + n, n * sizeof *y);
  return index1_accel(w->form, t, y, y + n, dydt + n, NULL) ? GSL_EBADFUNC : GSL_SUCCESS;
}

int index1_reference(index1_rk4 *w, double t0, double tf, double tol, double *q, double *v,
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
