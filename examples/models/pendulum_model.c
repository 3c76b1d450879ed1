/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Planar pendulum in the coordinates (xi, mu) of the paper's Proposition 1.
 *
 * x = (X, Y, Xdot, Ydot), f = (Xdot, Ydot, 0, -ga), g = (0, 0, -X/m, -Y/m), so that
 * Xdd = -lambda X/m and Ydd = -ga - lambda Y/m; the constraint h = (X^2 + Y^2 - L^2)/2 = (r^2 -
 * L^2)/2 with r^2 = X^2 + Y^2.
 *
 * xi: xi1 = h, xi2 = L_f h = X Xdot + Y Ydot = r rdot; L_g h = 0 and L_g L_f h = -r^2/m != 0,
 * so the relative degree is 2 (away from r = 0).
 *
 * mu must complete xi to coordinates and satisfy L_g mu_j = 0 (then lambda does not enter mu'):
 *   mu1 = theta = atan2(X, -Y), the angle from the downward vertical: it depends on positions
 *         only and g has no position components, so L_g mu1 = 0;
 *   mu2 = X Ydot - Y Xdot = r^2 theta': L_g mu2 = (-Y)(-X/m) + X(-Y/m) = 0.
 * (r, theta, rdot, theta') are polar coordinates, so (xi, mu) is a diffeomorphism wherever
 * r > 0, i.e. xi1 > -L^2/2. Inverse: r = sqrt(L^2 + 2 xi1), X = r sin mu1, Y = -r cos mu1,
 * rdot = xi2/r, theta' = mu2/r^2, Xdot = rdot sin mu1 + r cos mu1 theta',
 * Ydot = -rdot cos mu1 + r sin mu1 theta'.
 *
 * Dynamics of mu: mu1' = mu2/r^2 = mu2/(L^2 + 2 xi1), and mu2' = X Ydd - Y Xdd = -ga X
 * (the lambda terms cancel) = -ga sqrt(L^2 + 2 xi1) sin mu1. On the manifold xi = 0 (r = L):
 *   q0(mu) = (mu2/L^2, -ga L sin mu1),
 * and the rest is linear in xi (the paper's q_i): with r^2 - L^2 = 2 xi1,
 *   mu2/r^2 - mu2/L^2 = -2 mu2 xi1/(L^2 r^2),
 *   -ga (r - L) sin mu1 = -ga sin mu1 (r^2 - L^2)/(r + L) = -2 ga sin mu1 xi1/(L + r),
 * so Q = [[-2 mu2/(L^2 (L^2 + 2 xi1)), 0], [-2 ga sin mu1/(L + sqrt(L^2 + 2 xi1)), 0]] and
 * q_2 = 0 (the gain k2 is -epsilon).
 *
 * Energy on the manifold: H(mu) = m mu2^2/(2 L^2) - m ga L cos mu1 with
 * grad H = (m ga L sin mu1, m mu2/L^2) and S = [[0, 1/m], [-1/m, 0]]: S grad H = q0. */
#include "pendulum_model.h"

#include <math.h>

static const unsigned pend_rel_degree[1] = {2};

int pend_to_coords(const pend_params *p, const double *x, double *xi, double *mu) {
  double X = x[0], Y = x[1], Xd = x[2], Yd = x[3];
  if (X == 0.0 && Y == 0.0) return -1;
  xi[0] = (X * X + Y * Y - p->L * p->L) / 2;
  xi[1] = X * Xd + Y * Yd;
  mu[0] = atan2(X, -Y);
  mu[1] = X * Yd - Y * Xd;
  return 0;
}

int pend_from_coords(const pend_params *p, const double *xi, const double *mu, double *x) {
  double r2 = p->L * p->L + 2 * xi[0];
  if (!(r2 > 0)) return -1;
  double r = sqrt(r2), s = sin(mu[0]), c = cos(mu[0]);
  double rdot = xi[1] / r, thetadot = mu[1] / r2;
  x[0] = r * s;
  x[1] = -r * c;
  x[2] = rdot * s + r * c * thetadot;
  x[3] = -rdot * c + r * s * thetadot;
  return 0;
}

void pend_dae(const pend_params *p, const double *x, double *f, double *g) {
  f[0] = x[2];
  f[1] = x[3];
  f[2] = 0.0;
  f[3] = -p->ga;
  g[0] = g[1] = 0.0;
  g[2] = -x[0] / p->m;
  g[3] = -x[1] / p->m;
}

double pend_energy(const pend_params *p, const double *x) {
  return p->m * (x[2] * x[2] + x[3] * x[3]) / 2 + p->m * p->ga * x[1];
}

double pend_H(const pend_params *p, const double *mu) {
  return p->m * mu[1] * mu[1] / (2 * p->L * p->L) - p->m * p->ga * p->L * cos(mu[0]);
}

static int pend_q0(double t, const double *mu, double *out, void *params) {
  const pend_params *p = params;
  (void)t;
  out[0] = mu[1] / (p->L * p->L);
  out[1] = -p->ga * p->L * sin(mu[0]);
  return 0;
}

static int pend_Q(double t, const double *xi, const double *mu, double *out, void *params) {
  const pend_params *p = params;
  double L2 = p->L * p->L, r2 = L2 + 2 * xi[0];
  (void)t;
  if (!(r2 > 0)) return 1; /* outside the chart: recoverable with a smaller step */
  out[0] = -2 * mu[1] / (L2 * r2);
  out[1] = 0.0;
  out[2] = -2 * p->ga * sin(mu[0]) / (p->L + sqrt(r2));
  out[3] = 0.0;
  return 0;
}

static int pend_q0_jac(double t, const double *mu, double *out, void *params) {
  const pend_params *p = params;
  (void)t;
  out[0] = 0.0;
  out[1] = 1.0 / (p->L * p->L);
  out[2] = -p->ga * p->L * cos(mu[0]);
  out[3] = 0.0;
  return 0;
}

static int pend_H_cb(double t, const double *mu, double *out, void *params) {
  (void)t;
  out[0] = pend_H(params, mu);
  return 0;
}

static int pend_grad_H(double t, const double *mu, double *out, void *params) {
  const pend_params *p = params;
  (void)t;
  out[0] = p->m * p->ga * p->L * sin(mu[0]);
  out[1] = p->m * mu[1] / (p->L * p->L);
  return 0;
}

static int pend_hess_H(double t, const double *mu, double *out, void *params) {
  const pend_params *p = params;
  (void)t;
  out[0] = p->m * p->ga * p->L * cos(mu[0]);
  out[1] = out[2] = 0.0;
  out[3] = p->m / (p->L * p->L);
  return 0;
}

static int pend_S(double t, const double *mu, double *out, void *params) {
  const pend_params *p = params;
  (void)t;
  (void)mu;
  out[0] = 0.0;
  out[1] = 1.0 / p->m;
  out[2] = -1.0 / p->m;
  out[3] = 0.0;
  return 0;
}

void pend_model(sdae_model *model, pend_params *p) {
  *model = (sdae_model){0};
  model->n_xi = 2;
  model->n_mu = 2;
  model->q0 = pend_q0;
  model->Q = pend_Q;
  model->q0_jac = pend_q0_jac;
  model->H = pend_H_cb;
  model->grad_H = pend_grad_H;
  model->hess_H = pend_hess_H;
  model->S = pend_S;
  model->n_constraints = 1;
  model->rel_degree = pend_rel_degree;
  model->params = p;
}

/* ---- the DAE for sdae_check_model --------------------------------------------------------- */

static int dae_f(double t, const double *x, double *out, void *params) {
  double g[4];
  (void)t;
  pend_dae(params, x, out, g);
  return 0;
}

static int dae_g(double t, const double *x, double *out, void *params) {
  double f[4];
  (void)t;
  pend_dae(params, x, f, out);
  return 0;
}

/* outside the model's domain a recoverable failure */
static int dae_Phi(double t, const double *x, double *z, void *params) {
  (void)t;
  return pend_to_coords(params, x, z, z + 2) ? 1 : 0;
}

static int dae_Phi_inv(double t, const double *z, double *x, void *params) {
  (void)t;
  return pend_from_coords(params, z, z + 2, x) ? 1 : 0;
}

void pend_dae_spec(sdae_dae *d, pend_params *p) {
  *d = (sdae_dae){
      .n = 4, .m = 1, .f = dae_f, .g = dae_g, .Phi = dae_Phi, .Phi_inv = dae_Phi_inv, .params = p};
}
