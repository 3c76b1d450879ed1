/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Condition (18) along a trajectory, (W(mu+) - W(mu))/T <= gamma W(mu), and the left side of
 * (17), (mean_i (W(mu+) - W(mu))/(mu_i+ - mu_i))^2 / W(mu): the discrete counterparts of (7)
 * and (8) that Theorem 5 asks of the map. Measured between consecutive observations, so the
 * observer should see every step. */
#include <math.h>
#include <string.h>

#include "core/callback.h"

int sdae_cond18_init(sdae_cond18 *c, size_t n_mu,
                     int (*W)(double t, const double *mu, double *out, void *params), void *params,
                     double *mu_prev) {
  if (!c || !W || !mu_prev) return SDAE_ERR_NULL;
  if (n_mu == 0) return SDAE_ERR_DIM;
  memset(c, 0, sizeof *c);
  c->n_mu = n_mu;
  c->W = W;
  c->params = params;
  c->mu_prev = mu_prev;
  c->gamma_min = -INFINITY;
  c->sup17 = 0.0;
  return SDAE_OK;
}

/* (1/n_mu) sum_i (W(mu+) - W(mu)) / (mu_i+ - mu_i), eq. 16-17: the paper divides by n - r,
 * all of mu's components; one that did not move adds 0 (in (16) its term carries
 * phi_T,i = 0) */
static double mean_quotient(const sdae_cond18 *c, const double *mu, double dW) {
  double sum = 0.0;
  for (size_t i = 0; i < c->n_mu; i++) {
    double d = mu[i] - c->mu_prev[i];
    if (d != 0.0) sum += dW / d;
  }
  return sum / (double)c->n_mu;
}

static void measure_step(sdae_cond18 *c, double t, const double *mu, double W) {
  double T = t - c->t_prev, dW = W - c->W_prev;
  if (!(c->W_prev > 0.0) || !(T > 0.0)) return;
  double ratio = dW / (T * c->W_prev); /* eq. 18 */
  double q = mean_quotient(c, mu, dW);
  if (ratio > c->gamma_min) c->gamma_min = ratio, c->worst_t = c->t_prev;
  c->sup17 = fmax(c->sup17, q * q / c->W_prev); /* eq. 17 */
  c->steps++;
}

int sdae_cond18_observe(size_t step, double t, const double *xi, const double *mu, void *cond18) {
  sdae_cond18 *c = cond18;
  double W;
  (void)step, (void)xi;
  c->status = sdae__status_of_callback(c->W(t, mu, &W, c->params));
  if (c->status == SDAE_OK && !isfinite(W)) c->status = SDAE_ERR_NONFINITE;
  if (c->status != SDAE_OK) return 1;
  if (c->have_prev) measure_step(c, t, mu, W);
  memcpy(c->mu_prev, mu, c->n_mu * sizeof *mu);
  c->t_prev = t, c->W_prev = W, c->have_prev = 1;
  return 0;
}
