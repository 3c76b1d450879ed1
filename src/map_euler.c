/* The explicit map phi_T(mu, mu+) = q0(mu): order 1, no Newton. */
#include "internal.h"

static int euler_check(const sdae_model *m, const sdae_options *o) {
  (void)m;
  (void)o;
  return SDAE_OK;
}

static size_t euler_scratch(const sdae_model *m, const sdae_options *o) {
  (void)m, (void)o;
  return 0;
}

static int euler_phi(sdae_stepper *s, double t, double T, const double *mu,
                     const double *mu_next, double *out) {
  (void)T;
  (void)mu_next;
  return sdae__eval_q0(s, t, mu, out);
}

static const sdae_map_type euler_type = {
    .name = "euler",
    .implicit = 0,
    .uses_newton = 0,
    .check = euler_check,
    .scratch = euler_scratch,
    .phi = euler_phi,
};

const sdae_map_type *const sdae_map_euler = &euler_type;
