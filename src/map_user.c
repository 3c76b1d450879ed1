/* A user map phi_T(mu, mu+) given as a callback, with an optional Jacobian d phi / d mu+
 * (e.g. the paper's Section IV map). */
#include "internal.h"

static int user_check(const sdae_model *m, const sdae_options *o) {
  (void)m;
  return o->user_phi ? SDAE_OK : SDAE_ERR_MAP;
}

static size_t user_scratch(const sdae_model *m, const sdae_options *o) {
  (void)m, (void)o;
  return 0;
}

static int user_phi(sdae_stepper *s, double t, double T, const double *mu,
                    const double *mu_next, double *out) {
  const sdae_model *m = &s->model;
  int rc = sdae__status_of_callback(s->opt.user_phi(t, T, mu, mu_next, out, m->params));
  if (rc != SDAE_OK) return rc;
  return sdae__all_finite(out, m->n_mu) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int user_jac(sdae_stepper *s, double t, double T, const double *mu,
                    const double *mu_next, double *out) {
  const sdae_model *m = &s->model;
  int rc = sdae__status_of_callback(s->opt.user_phi_jac(t, T, mu, mu_next, out, m->params));
  if (rc != SDAE_OK) return rc;
  return sdae__all_finite(out, m->n_mu * m->n_mu) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

static int user_jac_given(const sdae_model *m, const sdae_options *o) {
  (void)m;
  return o->user_phi_jac != NULL;
}

/* Implicit: a user map may depend on mu+; for one that does not, Newton converges in one
 * iteration. */
static const sdae_map_type user_type = {
    .name = "user",
    .implicit = 1,
    .uses_newton = 1,
    .check = user_check,
    .scratch = user_scratch,
    .phi = user_phi,
    .jac = user_jac,
    .jac_given = user_jac_given,
};

const sdae_map_type *const sdae_map_user = &user_type;
