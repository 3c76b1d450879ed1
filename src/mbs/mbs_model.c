/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The normal form of a mechanism in the current chart, as an sdae_model for the stepper:
 * G(t, xi, mu) = mu-dynamics at Phi^-1(t, xi, mu), q0 and Q by the rule of derive.c, and with a
 * potential the energy structure of the discrete gradients:
 *
 *   H(mu) = v^T M v / 2 + V(q) at Phi^-1(t, 0, mu),   S = J - R = [[0, I], [-I, -W^T D W]],
 *   grad H = S^-1 q0 = (-q0_p - R q0_q, q0_q),
 *
 * (q_I, p_I) being canonical on the manifold, so no further derivative is needed. */
#include <string.h>

#include "mbs_impl.h"

/* a callback's return for a status, the status kept for sdae_mbs_step to report */
static int code(sdae_mbs_stepper *s, int rc) {
  if (rc != SDAE_OK) s->status = rc;
  return sdae__callback_code(rc);
}

static int rate(void *ctx, double t, const double *xi, const double *mu, double *out) {
  sdae_mbs_stepper *s = ctx;
  int rc = sdae__mbs_phi_inv(s, t, xi, mu);
  return rc == SDAE_OK ? sdae__mbs_mu_dot(s, t, out) : rc;
}

static int q0(double t, const double *mu, double *out, void *params) {
  sdae_mbs_stepper *s = params;
  return code(s, sdae__derive_q0(&s->derive, t, mu, out));
}

static int Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                   void *params) {
  sdae_mbs_stepper *s = params;
  return code(s, sdae__derive_Q_apply(&s->derive, t, xi, mu, Qxi, qnorm2));
}

static int H(double t, const double *mu, double *out, void *params) {
  sdae_mbs_stepper *s = params;
  const sdae_mbs_point *p = &s->pt;
  double V, kinetic = 0.0;
  int rc = sdae__mbs_phi_inv(s, t, s->zero, mu);
  if (rc == SDAE_OK) rc = sdae__mbs_potential(s, t, p->q, &V);
  if (rc != SDAE_OK) return code(s, rc);
  for (size_t i = 0; i < s->n_q; i++)
    for (size_t j = 0; j < s->n_q; j++) kinetic += p->v[i] * p->M[i * s->n_q + j] * p->v[j];
  *out = 0.5 * kinetic + V;
  return 0;
}

/* R = W^T D W at Phi^-1(t, 0, mu) into s->R; zero without damping */
static int damping(sdae_mbs_stepper *s, double t, const double *mu) {
  size_t n_q = s->n_q, n_f = s->n_f;
  const double *W = s->pt.W, *D = s->fd_M;
  int rc;
  memset(s->R, 0, n_f * n_f * sizeof *s->R);
  if (!s->sys.damping) return SDAE_OK;
  if ((rc = sdae__mbs_phi_inv(s, t, s->zero, mu)) != SDAE_OK ||
      (rc = sdae__mbs_damping(s, t, s->pt.q, s->fd_M)) != SDAE_OK)
    return rc;
  for (size_t a = 0; a < n_f; a++)
    for (size_t b = 0; b < n_f; b++) {
      double acc = 0.0;
      for (size_t i = 0; i < n_q; i++)
        for (size_t j = 0; j < n_q; j++) acc += W[i * n_f + a] * D[i * n_q + j] * W[j * n_f + b];
      s->R[a * n_f + b] = acc;
    }
  return SDAE_OK;
}

static int grad_H(double t, const double *mu, double *out, void *params) {
  sdae_mbs_stepper *s = params;
  size_t n_f = s->n_f;
  int rc = sdae__derive_q0(&s->derive, t, mu, out);
  if (rc == SDAE_OK) rc = damping(s, t, mu);
  if (rc != SDAE_OK) return code(s, rc);
  for (size_t a = 0; a < n_f; a++) { /* out = (q0_q, q0_p) becomes (-q0_p - R q0_q, q0_q) */
    double qa = out[a];
    s->rf[a] = -out[n_f + a];
    for (size_t b = 0; b < n_f; b++) s->rf[a] -= s->R[a * n_f + b] * out[b];
    out[n_f + a] = qa;
  }
  memcpy(out, s->rf, n_f * sizeof *out);
  return 0;
}

static int S(double t, const double *mu, double *out, void *params) {
  sdae_mbs_stepper *s = params;
  size_t n_f = s->n_f, n = 2 * n_f;
  int rc = damping(s, t, mu);
  if (rc != SDAE_OK) return code(s, rc);
  memset(out, 0, n * n * sizeof *out);
  for (size_t a = 0; a < n_f; a++) {
    out[a * n + n_f + a] = 1.0;
    out[(n_f + a) * n + a] = -1.0;
    for (size_t b = 0; b < n_f; b++) out[(n_f + a) * n + n_f + b] = -s->R[a * n_f + b];
  }
  return 0;
}

void sdae__mbs_model(sdae_mbs_stepper *s) {
  sdae_model *m = &s->model;
  memset(m, 0, sizeof *m);
  m->n_xi = 2 * s->n_c;
  m->n_mu = 2 * s->n_f;
  m->q0 = q0;
  m->Q_apply = Q_apply;
  if (s->sys.potential) {
    m->H = H;
    m->grad_H = grad_H;
    m->S = S;
  }
  m->params = s;
}

/* the derive rule's G for this stepper's arrays */
void sdae__mbs_derive_carve(sdae_mbs_stepper *s, sdae_arena *a) {
  sdae__derive_carve(&s->derive, 2 * s->n_c, 2 * s->n_f, rate, s, a);
}
