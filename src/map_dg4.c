/* A fourth-order energy-conserving map: the symmetric discrete-gradient map Psi_h (Gonzalez's,
 * with S at the midpoint, so Psi_-h is the inverse of Psi_h) composed by Yoshida's triple jump,
 *
 *   Psi4_T = Psi_{g1 T} o Psi_{g2 T} o Psi_{g1 T},  g1 = 1/(2 - 2^(1/3)),  g2 = 1 - 2 g1 < 0,
 *
 * and phi_T(mu) = (Psi4_T(mu) - mu)/T. Each stage conserves H when S is skew, so the composition
 * does. The map is explicit in mu+ (its stages are solved inside), so the step stays one
 * scheme-11/15 step: xi is updated once per T, never by the negative middle substep. */
#include <math.h>
#include <string.h>

#include "internal.h"

static int dg4_check(const sdae_model *m, const sdae_options *o) {
  return sdae_map_dgrad->check(m, o);
}

/* the discrete gradient's scratch, then the stage's start and end */
static size_t dg4_scratch(const sdae_model *m, const sdae_options *o) {
  return sdae_map_dgrad->scratch(m, o) + 2 * m->n_mu;
}

/* one stage y = Psi_h(x): Newton on y = x + h S gradbar H(x, y) from x + h q0(x) */
static int stage(sdae_stepper *s, double t, double h, const double *x, double *y) {
  size_t n = s->model.n_mu;
  int rc = sdae_map_dgrad->phi(s, t, h, x, x, s->phi);
  s->stats.phi_evals++;
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) y[i] = x[i] + h * s->phi[i];
  return sdae__newton(s, sdae_map_dgrad, t, h, x, NULL, y);
}

static int dg4_phi(sdae_stepper *s, double t, double T, const double *mu,
                   const double *mu_next, double *out) {
  size_t n = s->model.n_mu;
  double *a = s->map_work + sdae_map_dgrad->scratch(&s->model, &s->opt), *b = a + n;
  const double g1 = 1.0 / (2.0 - cbrt(2.0)), gamma[3] = {g1, 1.0 - 2.0 * g1, g1};
  int rc = SDAE_OK;
  (void)mu_next;
  memcpy(a, mu, n * sizeof *mu);
  for (int k = 0; k < 3 && rc == SDAE_OK; k++) {
    rc = stage(s, t, gamma[k] * T, a, b);
    t += gamma[k] * T;
    memcpy(a, b, n * sizeof *b);
  }
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) out[i] = (a[i] - mu[i]) / T;
  return SDAE_OK;
}

static const sdae_map_type dg4_type = {
    .name = "dg4",
    .implicit = 0,
    .uses_newton = 1,
    .check = dg4_check,
    .scratch = dg4_scratch,
    .phi = dg4_phi,
};

const sdae_map_type *const sdae_map_dg4 = &dg4_type;
