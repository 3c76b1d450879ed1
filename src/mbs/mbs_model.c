/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The normal form of a mechanism in the current chart, as an sdae_model for the stepper:
 * G(t, xi, mu) = mu-dynamics at Phi^-1(t, xi, mu), q0 and Q by the rule of derive.c, and with a
 * potential the energy structure of the discrete gradients:
 *
 *   H(mu) = v^T M v / 2 + V(q) at Phi^-1(t, 0, mu),   S = J - R = [[0, I], [-I, -W^T D W]]
 *   (applied by products, never formed),
 *   B u = (0, W^T F_in),   grad H = S^-1 (q0 - B u) = (-(q0 - B u)_p - R q0_q, q0_q),
 *
 * (q_I, p_I) being canonical on the manifold, so no further derivative is needed; F_in are the
 * forces from outside the Lagrangian (input_force), a port of the energy. */
#include <string.h>

#include "core/callback.h"
#include "mbs_model.h"

/* a callback's return for a status, the status kept for sdae_mbs_step to report */
static int code(sdae_mbs_model *m, int rc) {
  if (rc != SDAE_OK) m->status = rc;
  return sdae__callback_code(rc);
}

static int rate(void *ctx, double t, const double *xi, const double *mu, double *out) {
  sdae_mbs_model *m = ctx;
  int rc = sdae__mbs_phi_inv(m->co, t, xi, mu);
  return rc == SDAE_OK ? sdae__mbs_mu_dot(m->co, t, out) : rc;
}

static int q0(double t, const double *mu, double *out, void *params) {
  sdae_mbs_model *m = params;
  return code(m, sdae__derive_q0(&m->derive, t, mu, out));
}

static int Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                   void *params) {
  sdae_mbs_model *m = params;
  return code(m, sdae__derive_Q_apply(&m->derive, t, xi, mu, Qxi, qnorm2));
}

static int H(double t, const double *mu, double *out, void *params) {
  sdae_mbs_model *m = params;
  return code(m, sdae__mbs_energy_on(m->co, t, mu, out));
}

/* m->Bu = W^T F_in at Phi^-1(t, 0, mu), the momentum part of B u; kept for the next call at the
 * same (t, mu) within a step (grad H and the discrete gradient's input take it at the same
 * midpoint, one after the other) */
static int input_p(sdae_mbs_model *m, double t, const double *mu) {
  size_t n_mu = 2 * m->n_f;
  int rc;
  if (m->Bu_have && m->Bu_t == t && memcmp(m->Bu_mu, mu, n_mu * sizeof *mu) == 0) return SDAE_OK;
  m->Bu_have = 0;
  if ((rc = sdae__mbs_input_on(m->co, t, mu, m->Bu)) != SDAE_OK) return rc;
  memcpy(m->Bu_mu, mu, n_mu * sizeof *mu);
  m->Bu_t = t, m->Bu_have = 1;
  return SDAE_OK;
}

static int input(double t, const double *mu, double *out, void *params) {
  sdae_mbs_model *m = params;
  int rc = input_p(m, t, mu);
  if (rc != SDAE_OK) return code(m, rc);
  memset(out, 0, m->n_f * sizeof *out);
  memcpy(out + m->n_f, m->Bu, m->n_f * sizeof *out);
  return SDAE_OK;
}

static int grad_H(double t, const double *mu, double *out, void *params) {
  sdae_mbs_model *m = params;
  size_t n_f = m->n_f;
  int rc = sdae__derive_q0(&m->derive, t, mu, out);
  if (rc == SDAE_OK) rc = sdae__mbs_damping_on(m->co, t, mu, out, m->Rx);
  if (rc == SDAE_OK && m->input) rc = input_p(m, t, mu);
  if (rc != SDAE_OK) return code(m, rc);
  for (size_t a = 0; a < n_f && m->input; a++) out[n_f + a] -= m->Bu[a];
  for (size_t a = 0; a < n_f; a++) { /* out = (q0_q, q0_p) becomes (-q0_p - R q0_q, q0_q) */
    double qa = out[a];
    m->row[a] = -out[n_f + a] - m->Rx[a];
    out[n_f + a] = qa;
  }
  memcpy(out, m->row, n_f * sizeof *out);
  return 0;
}

/* S g = (g_p, -g_q - R g_p) */
static int S_apply(double t, const double *mu, const double *g, double *out, void *params) {
  sdae_mbs_model *m = params;
  size_t n_f = m->n_f;
  int rc = sdae__mbs_damping_on(m->co, t, mu, g + n_f, m->Rx);
  if (rc != SDAE_OK) return code(m, rc);
  for (size_t a = 0; a < n_f; a++) {
    out[a] = g[n_f + a];
    out[n_f + a] = -g[a] - m->Rx[a];
  }
  return 0;
}

static int lsetup(double t, const double *mu, double a, void *params) {
  sdae_mbs_model *m = params;
  return code(m, sdae__mbs_lsetup(m->co, t, mu, a));
}

static int lsolve(const double *r, double *z, void *params) {
  sdae_mbs_model *m = params;
  return code(m, sdae__mbs_lsolve(m->co, r, z));
}

void sdae__mbs_model_init(sdae_mbs_model *m, const sdae_mbs_eval *eval, sdae_mbs_coords *co) {
  sdae_model *nf = &m->model;
  m->co = co;
  m->n_c = eval->n_c;
  m->n_f = eval->n_q - eval->n_c;
  m->input = eval->sys.input_force != NULL;
  memset(nf, 0, sizeof *nf);
  nf->n_xi = 2 * m->n_c;
  nf->n_mu = 2 * m->n_f;
  nf->q0 = q0;
  nf->Q_apply = Q_apply;
  if (eval->sys.potential) { /* the energy structure: the discrete gradients */
    nf->H = H;
    nf->grad_H = grad_H;
    nf->S_apply = S_apply;
    if (m->input) nf->input = input;
  }
  if (sdae__mbs_coords_solves(co)) nf->q0_lsetup = lsetup, nf->q0_lsolve = lsolve;
  nf->params = m;
}

void sdae__mbs_model_carve(sdae_mbs_model *m, sdae_arena *a) {
  size_t n_f = m->n_f, structure = m->model.H ? n_f : 0; /* the energy structure's alone */
  sdae__derive_carve(&m->derive, 2 * m->n_c, 2 * n_f, rate, m, a);
  m->Rx = sdae__take(a, structure, 1);
  m->row = sdae__take(a, structure, 1);
  m->Bu = sdae__take(a, structure, 1);
  m->Bu_mu = sdae__take(a, 2 * structure, 1);
  m->floor = sdae__take(a, 2 * m->n_c, 1);
  m->derive.floor = m->floor;
}

void sdae__mbs_model_forget(sdae_mbs_model *m) {
  sdae__derive_forget(&m->derive);
  m->Bu_have = 0;
}
