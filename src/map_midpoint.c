/* The implicit midpoint map phi_T(mu, mu+) = q0((mu + mu+)/2): symmetric, order 2. */
#include "internal.h"

static int midpoint_check(const sdae_model *m, const sdae_options *o) {
  (void)m;
  (void)o;
  return SDAE_OK;
}

static size_t midpoint_scratch(const sdae_model *m, const sdae_options *o) {
  (void)o;
  return m->n_mu; /* the midpoint */
}

static const double *midpoint(sdae_stepper *s, const double *mu, const double *mu_next) {
  double *mid = s->map_work;
  for (size_t i = 0; i < s->model.n_mu; i++) mid[i] = 0.5 * (mu[i] + mu_next[i]);
  return mid;
}

static int midpoint_phi(sdae_stepper *s, double t, double T, const double *mu,
                        const double *mu_next, double *out) {
  return sdae__eval_q0(s, t + 0.5 * T, midpoint(s, mu, mu_next), out);
}

/* d phi / d mu+ = q0'(mid) / 2 */
static int midpoint_jac(sdae_stepper *s, double t, double T, const double *mu,
                        const double *mu_next, double *out) {
  size_t n = s->model.n_mu;
  int rc = sdae__eval_q0_jac(s, t + 0.5 * T, midpoint(s, mu, mu_next), out);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n * n; i++) out[i] *= 0.5;
  return SDAE_OK;
}

static int midpoint_jac_given(const sdae_model *m, const sdae_options *o) {
  (void)o;
  return m->q0_jac != NULL;
}

static const sdae_map_type midpoint_type = {
    .name = "midpoint",
    .implicit = 1,
    .uses_newton = 1,
    .check = midpoint_check,
    .scratch = midpoint_scratch,
    .phi = midpoint_phi,
    .jac = midpoint_jac,
    .jac_given = midpoint_jac_given,
};

const sdae_map_type *const sdae_map_midpoint = &midpoint_type;
