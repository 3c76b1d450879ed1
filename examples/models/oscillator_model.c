/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Oscillator of Section IV in the coordinates of eq. 21:
 *   xi1 = Y, xi2 = Ydot, mu1 = X + Y, mu2 = Y + Xdot.
 * g = (0, 0, 0, -1/m) touches only Ydot, on which mu does not depend, so L_g mu = 0. Eq. 22
 * (with the mass) gives mu' = q0(mu) + Q(xi, mu) xi with q0 = (mu2, (-k mu1^3 - d mu2)/m):
 *   mu1' = Xdot + Ydot = mu2 - xi1 + xi2                              -> Q row 1 = (-1, 1)
 *   mu2' = Ydot + Xdd  = xi2 + (-k (mu1 - xi1)^3 - d (mu2 - xi1))/m
 *        = q0_2 + xi2 + xi1 (k (3 mu1^2 - 3 mu1 xi1 + xi1^2) + d)/m   -> Q row 2 = (c, 1). */
#include "oscillator_model.h"

static const unsigned osc_rel_degree[1] = {2};

void osc_to_coords(const osc_params *p, const double *x, double *xi, double *mu) {
  (void)p;
  xi[0] = x[1]; /* eq. 21 */
  xi[1] = x[3];
  mu[0] = x[0] + x[1];
  mu[1] = x[1] + x[2];
}

void osc_from_coords(const osc_params *p, const double *xi, const double *mu, double *x) {
  (void)p;
  x[0] = mu[0] - xi[0];
  x[1] = xi[0];
  x[2] = mu[1] - xi[0];
  x[3] = xi[1];
}

void osc_dae(const osc_params *p, const double *x, double *f, double *g) {
  f[0] = x[2];
  f[1] = x[3];
  f[2] = (-p->k * x[0] * x[0] * x[0] - p->d * x[2]) / p->m;
  f[3] = -p->ga;
  g[0] = g[1] = g[2] = 0.0;
  g[3] = -1.0 / p->m;
}

double osc_energy(const osc_params *p, const double *x) {
  double X2 = x[0] * x[0];
  return p->m * (x[2] * x[2] + x[3] * x[3]) / 2 + p->k * X2 * X2 / 4 + p->m * p->ga * x[1];
}

double osc_W(const osc_params *p, const double *mu) {
  double mu1sq = mu[0] * mu[0];
  return p->m * mu[1] * mu[1] / 2 + p->k * mu1sq * mu1sq / 4;
}

/* m c: Q's entry (2,1) times the mass */
static double m_times_c(const osc_params *p, const double *xi, const double *mu) {
  double a = mu[0], e = xi[0];
  if (p->q == OSC_Q_PAPER) /* as printed in Section IV (erratum 1) */
    return p->k * (3 * a * e - 3 * a * a - e * e) + p->d * e;
  return p->k * (3 * a * a - 3 * a * e + e * e) + p->d;
}

/* divides, as the DAE's helpers do: it needs no osc_model (Q's entry may differ by an ulp) */
double osc_c(const osc_params *p, const double *xi, const double *mu) {
  return m_times_c(p, xi, mu) / p->m;
}

static int osc_q0(double t, const double *mu, double *out, void *params) {
  const osc_params *p = params;
  (void)t;
  out[0] = mu[1];
  out[1] = (-p->k * mu[0] * mu[0] * mu[0] - p->d * mu[1]) * p->inv_m;
  return 0;
}

static int osc_Q(double t, const double *xi, const double *mu, double *out, void *params) {
  const osc_params *p = params;
  (void)t;
  out[0] = -1.0; /* rows = mu components, columns = q_1, q_2 */
  out[1] = 1.0;
  out[2] = m_times_c(p, xi, mu) * p->inv_m;
  out[3] = 1.0;
  return 0;
}

static int osc_q0_jac(double t, const double *mu, double *out, void *params) {
  const osc_params *p = params;
  (void)t;
  out[0] = 0.0;
  out[1] = 1.0;
  out[2] = -3 * p->k * mu[0] * mu[0] * p->inv_m;
  out[3] = -p->d * p->inv_m;
  return 0;
}

/* ---- maps --------------------------------------------------------------------------------- */

static int osc_H(double t, const double *mu, double *out, void *params) {
  (void)t;
  out[0] = osc_W(params, mu);
  return 0;
}

static int osc_grad_H(double t, const double *mu, double *out, void *params) {
  const osc_params *p = params;
  (void)t;
  out[0] = p->k * mu[0] * mu[0] * mu[0];
  out[1] = p->m * mu[1];
  return 0;
}

static int osc_hess_H(double t, const double *mu, double *out, void *params) {
  const osc_params *p = params;
  (void)t;
  out[0] = 3 * p->k * mu[0] * mu[0];
  out[1] = out[2] = 0.0;
  out[3] = p->m;
  return 0;
}

/* S = J - R with J skew and R = diag(0, d/m^2) >= 0: W is dissipated, S grad W = q0 */
static int osc_S(double t, const double *mu, double *out, void *params) {
  const osc_params *p = params;
  (void)t;
  (void)mu;
  out[0] = 0.0;
  out[1] = p->inv_m;
  out[2] = -p->inv_m;
  out[3] = -p->d * p->inv_m * p->inv_m;
  return 0;
}

/* The paper's phi_T of Section IV, second row divided by m (erratum 3) */
static int osc_paper_phi(double t, double T, const double *mu, const double *mu_next, double *out,
                         void *params) {
  const osc_params *p = params;
  double a = mu_next[0], b = mu[0];
  (void)t;
  (void)T;
  out[0] = (mu_next[1] + mu[1]) / 2;
  out[1] = (-p->k * (a * a * a + b * b * b + (a + b) * a * b) / 4 - p->d * mu[1]) * p->inv_m;
  return 0;
}

static int osc_paper_phi_jac(double t, double T, const double *mu, const double *mu_next,
                             double *out, void *params) {
  const osc_params *p = params;
  double a = mu_next[0], b = mu[0];
  (void)t;
  (void)T;
  out[0] = 0.0;
  out[1] = 0.5;
  out[2] = -p->k * (3 * a * a + 2 * a * b + b * b) / 4 * p->inv_m;
  out[3] = 0.0;
  return 0;
}

void osc_model(sdae_model *model, osc_params *p) {
  *model = (sdae_model){0};
  model->n_xi = 2;
  model->n_mu = 2;
  model->q0 = osc_q0;
  model->Q = osc_Q;
  model->q0_jac = osc_q0_jac;
  model->H = osc_H;
  model->grad_H = osc_grad_H;
  model->hess_H = osc_hess_H;
  model->S = osc_S;
  model->user_phi = osc_paper_phi;
  model->user_phi_jac = osc_paper_phi_jac;
  model->n_constraints = 1;
  model->rel_degree = osc_rel_degree;
  model->params = p;
  p->inv_m = 1.0 / p->m;
}

/* ---- the DAE for sdae_check_model --------------------------------------------------------- */

static int dae_f(double t, const double *x, double *out, void *params) {
  double g[4];
  (void)t;
  osc_dae(params, x, out, g);
  return 0;
}

static int dae_g(double t, const double *x, double *out, void *params) {
  double f[4];
  (void)t;
  osc_dae(params, x, f, out);
  return 0;
}

/* outside the model's domain a recoverable failure */
static int dae_Phi(double t, const double *x, double *z, void *params) {
  (void)t;
  osc_to_coords(params, x, z, z + 2);
  return 0;
}

static int dae_Phi_inv(double t, const double *z, double *x, void *params) {
  (void)t;
  osc_from_coords(params, z, z + 2, x);
  return 0;
}

void osc_dae_spec(sdae_dae *d, osc_params *p) {
  *d = (sdae_dae){
      .n = 4, .m = 1, .f = dae_f, .g = dae_g, .Phi = dae_Phi, .Phi_inv = dae_Phi_inv, .params = p};
}
