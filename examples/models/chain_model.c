/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Chain of N masses: each mass is the Section IV oscillator, with cubic couplings between
 * neighbours. Coordinates per mass as eq. 21: xi_i = (Y_i, Ydot_i), mu_i = (X_i + Y_i,
 * Y_i + Xdot_i); L_g mu = 0 as for one mass (g only touches the Ydot_i).
 *
 * With a = mu_{.,1} (= X on the manifold), e = xi_{.,1} (= Y): X = a - e, Xdot = mu_{.,2} - e,
 *   mu_{i,1}' = mu_{i,2} - e_i + xi_{i,2}
 *   mu_{i,2}' = xi_{i,2} + F_i(a - e, mu_2 - e)/m,
 * and F_i(a - e, .) - F_i(a, .) is linear in e through a^3 - b^3 = (a - b)(a^2 + ab + b^2):
 *   own spring:  -k ((a_i - e_i)^3 - a_i^3)  = e_i k (3 a_i^2 - 3 a_i e_i + e_i^2)
 *   damping:     -d ((mu_{i,2} - e_i) - mu_{i,2}) = d e_i
 *   bond j = (j, j+1), D_j = a_{j+1} - a_j, u_j = D_j - (e_{j+1} - e_j):
 *     kc (u_j^3 - D_j^3) = -kc s_j (e_{j+1} - e_j),   s_j = u_j^2 + u_j D_j + D_j^2 >= 0,
 *     entering F_j with + and F_{j+1} with -.
 * So row (i,2) of Q has c_i = (k (3 a_i^2 - 3 a_i e_i + e_i^2) + d + kc s_{i-1} + kc s_i)/m in
 * column (i,1), -kc s_{i-1}/m in column (i-1,1), -kc s_i/m in column (i+1,1) and 1 in column
 * (i,2); row (i,1) has -1 in column (i,1) and 1 in column (i,2). Column norms:
 *   ||q_{i,1}||^2 = 1 + c_i^2 + (kc s_{i-1}/m)^2 + (kc s_i/m)^2,   ||q_{i,2}||^2 = 2
 * (missing bonds at the free ends count 0). For N = 1 this is the oscillator's corrected Q. */
#include "chain_model.h"

#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

static double cube(double v) { return v * v * v; }

/* F_i at positions X and velocities V, read with a stride (x and mu store them interleaved) */
static double chain_force(const chain_params *p, const double *X, const double *V, size_t stride,
                          size_t i) {
  double Xi = X[i * stride];
  double F = -p->k * cube(Xi) - p->d * V[i * stride];
  if (i + 1 < p->N) F += p->kc * cube(X[(i + 1) * stride] - Xi);
  if (i > 0) F -= p->kc * cube(Xi - X[(i - 1) * stride]);
  return F;
}

void chain_to_coords(const chain_params *p, const double *x, double *xi, double *mu) {
  for (size_t i = 0; i < p->N; i++) { /* eq. 21, per mass */
    const double *xs = x + 4 * i;
    xi[2 * i] = xs[1];
    xi[2 * i + 1] = xs[3];
    mu[2 * i] = xs[0] + xs[1];
    mu[2 * i + 1] = xs[1] + xs[2];
  }
}

void chain_from_coords(const chain_params *p, const double *xi, const double *mu, double *x) {
  for (size_t i = 0; i < p->N; i++) {
    double *xs = x + 4 * i;
    xs[0] = mu[2 * i] - xi[2 * i];
    xs[1] = xi[2 * i];
    xs[2] = mu[2 * i + 1] - xi[2 * i];
    xs[3] = xi[2 * i + 1];
  }
}

void chain_dae_rhs(const chain_params *p, const double *x, const double *lambda, double *xdot) {
  for (size_t i = 0; i < p->N; i++) {
    xdot[4 * i] = x[4 * i + 2];
    xdot[4 * i + 1] = x[4 * i + 3];
    xdot[4 * i + 2] = chain_force(p, x, x + 2, 4, i) / p->m;
    xdot[4 * i + 3] = -p->ga - lambda[i] / p->m;
  }
}

static double bonds_energy(const chain_params *p, const double *X, size_t stride) {
  double e = 0.0;
  for (size_t i = 0; i + 1 < p->N; i++) {
    double D = X[(i + 1) * stride] - X[i * stride];
    e += p->kc * D * D * D * D / 4;
  }
  return e;
}

double chain_energy(const chain_params *p, const double *x) {
  double e = bonds_energy(p, x, 4);
  for (size_t i = 0; i < p->N; i++) {
    const double *xs = x + 4 * i;
    double X2 = xs[0] * xs[0];
    e += p->m * (xs[2] * xs[2] + xs[3] * xs[3]) / 2 + p->k * X2 * X2 / 4 + p->m * p->ga * xs[1];
  }
  return e;
}

double chain_H(const chain_params *p, const double *mu) {
  double e = bonds_energy(p, mu, 2);
  for (size_t i = 0; i < p->N; i++) {
    double a2 = mu[2 * i] * mu[2 * i], v = mu[2 * i + 1];
    e += p->m * v * v / 2 + p->k * a2 * a2 / 4;
  }
  return e;
}

/* ---- callbacks ---------------------------------------------------------------------------- */

static int chain_q0(double t, const double *mu, double *out, void *params) {
  const chain_params *p = params;
  (void)t;
  for (size_t i = 0; i < p->N; i++) {
    out[2 * i] = mu[2 * i + 1];
    out[2 * i + 1] = chain_force(p, mu, mu + 1, 2, i) / p->m;
  }
  return 0;
}

/* s_j of bond (j, j+1): (a^3 - b^3)/(a - b) with a = u_j, b = D_j */
static double bond_secant(const double *xi, const double *mu, size_t j) {
  double D = mu[2 * j + 2] - mu[2 * j], u = D - (xi[2 * j + 2] - xi[2 * j]);
  return u * u + u * D + D * D;
}

static int chain_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                         void *params) {
  const chain_params *p = params;
  (void)t;
  double s_left = 0.0; /* s_{i-1}; 0 before the first mass */
  for (size_t i = 0; i < p->N; i++) {
    double a = mu[2 * i], e = xi[2 * i], e2 = xi[2 * i + 1];
    double s_right = i + 1 < p->N ? bond_secant(xi, mu, i) : 0.0;
    double e_left = i > 0 ? xi[2 * i - 2] : 0.0, e_right = i + 1 < p->N ? xi[2 * i + 2] : 0.0;
    double wl = p->kc * s_left / p->m, wr = p->kc * s_right / p->m;
    double c = (p->k * (3 * a * a - 3 * a * e + e * e) + p->d) / p->m + wl + wr;
    Qxi[2 * i] = -e + e2;
    Qxi[2 * i + 1] = c * e - wl * e_left - wr * e_right + e2;
    qnorm2[2 * i] = 1 + c * c + wl * wl + wr * wr;
    qnorm2[2 * i + 1] = 2.0;
    s_left = s_right;
  }
  return 0;
}

/* Row r of dq0/dmu in band form: out[o] is entry (r, r + o - CHAIN_JAC_LOWER) */
static void chain_jac_row(const chain_params *p, const double *mu, size_t r, double *out) {
  size_t i = r / 2;
  memset(out, 0, CHAIN_JAC_WIDTH * sizeof *out);
  if (r % 2 == 0) { /* mu_{i,1}' = mu_{i,2} */
    out[CHAIN_JAC_LOWER + 1] = 1.0;
    return;
  }
  const double w = 3 * p->kc / p->m, a = mu[2 * i];
  double diag = -3 * p->k * a * a / p->m;
  if (i > 0) { /* column 2i-2 = r-3 */
    double D = a - mu[2 * i - 2];
    out[CHAIN_JAC_LOWER - 3] = w * D * D;
    diag -= w * D * D;
  }
  if (i + 1 < p->N) { /* column 2i+2 = r+1 */
    double D = mu[2 * i + 2] - a;
    out[CHAIN_JAC_LOWER + 1] = w * D * D;
    diag -= w * D * D;
  }
  out[CHAIN_JAC_LOWER - 1] = diag;     /* column 2i */
  out[CHAIN_JAC_LOWER] = -p->d / p->m; /* column 2i+1 */
}

void chain_q0_jac_band(const chain_params *p, const double *mu, double *band) {
  for (size_t r = 0; r < 2 * p->N; r++) chain_jac_row(p, mu, r, band + r * CHAIN_JAC_WIDTH);
}

static int chain_q0_jac(double t, const double *mu, double *out, void *params) {
  const chain_params *p = params;
  size_t n = 2 * p->N;
  double row[CHAIN_JAC_WIDTH];
  (void)t;
  memset(out, 0, n * n * sizeof *out);
  for (size_t r = 0; r < n; r++) {
    chain_jac_row(p, mu, r, row);
    for (size_t o = 0; o < CHAIN_JAC_WIDTH; o++) {
      size_t c = r + o; /* the column plus CHAIN_JAC_LOWER */
      if (c >= CHAIN_JAC_LOWER && c - CHAIN_JAC_LOWER < n)
        out[r * n + c - CHAIN_JAC_LOWER] = row[o];
    }
  }
  return 0;
}

void chain_model_free(chain_params *p) {
  free(p->rel_degree);
  p->rel_degree = NULL;
}

/* ---- maps --------------------------------------------------------------------------------- */

static int chain_H_cb(double t, const double *mu, double *out, void *params) {
  (void)t;
  out[0] = chain_H(params, mu);
  return 0;
}

/* grad H per mass: (dH/da_i, m v_i) with dH/da_i = -(F_i + d v_i), the conservative force */
static int chain_grad_H(double t, const double *mu, double *out, void *params) {
  const chain_params *p = params;
  (void)t;
  for (size_t i = 0; i < p->N; i++) {
    double v = mu[2 * i + 1];
    out[2 * i] = -(chain_force(p, mu, mu + 1, 2, i) + p->d * v);
    out[2 * i + 1] = p->m * v;
  }
  return 0;
}

/* S v with S = block-diag([[0, 1/m], [-1/m, -d/m^2]]), in O(N) */
static int chain_S_apply(double t, const double *mu, const double *v, double *out, void *params) {
  const chain_params *p = params;
  (void)t;
  (void)mu;
  for (size_t i = 0; i < p->N; i++) {
    out[2 * i] = v[2 * i + 1] / p->m;
    out[2 * i + 1] = -v[2 * i] / p->m - p->d / (p->m * p->m) * v[2 * i + 1];
  }
  return 0;
}

int chain_model(sdae_model *model, chain_params *p) {
  *model = (sdae_model){0};
  p->rel_degree = malloc(p->N * sizeof *p->rel_degree);
  if (!p->rel_degree) return SDAE_ERR_NOMEM;
  for (size_t i = 0; i < p->N; i++) p->rel_degree[i] = 2;
  model->n_xi = 2 * p->N;
  model->n_mu = 2 * p->N;
  model->q0 = chain_q0;
  model->Q_apply = chain_Q_apply;
  model->q0_jac = chain_q0_jac;
  model->H = chain_H_cb;
  model->grad_H = chain_grad_H;
  model->S_apply = chain_S_apply;
  model->n_constraints = p->N;
  model->rel_degree = p->rel_degree;
  model->params = p;
  return 0;
}

int chain_random_start(const chain_params *p, unsigned long seed, double *x) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  if (!r) return -1;
  gsl_rng_set(r, seed);
  for (size_t i = 0; i < p->N; i++) {
    x[4 * i] = gsl_ran_flat(r, -0.5, 0.5);
    x[4 * i + 1] = gsl_ran_flat(r, -0.2, 0.2);
    x[4 * i + 2] = gsl_ran_flat(r, -0.1, 0.1);
    x[4 * i + 3] = gsl_ran_flat(r, -0.1, 0.1);
  }
  gsl_rng_free(r);
  return 0;
}
