/* SPDX-License-Identifier: GPL-3.0-or-later */
#include <check.h>

#include "test_util.h"

#include <gsl/gsl_randist.h>

void tu_directional(tu_map phi, const void *ctx, const double *x, const double *v, size_t n_x,
                    size_t n_z, double h, double *out) {
  double xp[64], xm[64], zp[64], zm[64];
  for (size_t i = 0; i < n_x; i++) {
    xp[i] = x[i] + h * v[i];
    xm[i] = x[i] - h * v[i];
  }
  phi(xp, zp, ctx);
  phi(xm, zm, ctx);
  for (size_t i = 0; i < n_z; i++) out[i] = (zp[i] - zm[i]) / (2 * h);
}

double tu_flat(gsl_rng *r, double a, double b) { return gsl_ran_flat(r, a, b); }

int tu_integrate(const sdae_model *m, const sdae_options *o, double T, size_t nsteps, double *xi,
                 double *mu) {
  sdae_stepper *s = NULL;
  int status = sdae_stepper_alloc(&s, m, o);
  if (status != SDAE_OK) return status;
  status = sdae_integrate(s, 0.0, T, nsteps, nsteps, xi, mu, NULL, NULL, NULL);
  sdae_stepper_free(s);
  return status;
}

void tu_assert_derivatives_exact(const sdae_mbs *s, double t, const double *q, const double *v,
                                 unsigned given) {
  sdae_mbs_check_report r;
  ck_assert_int_eq(sdae_mbs_check(s, t, q, v, 1e-6, &r), SDAE_OK);
  ck_assert_uint_eq(r.checked, given);
  ck_assert_int_eq(r.consistent, 1);
  for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++) ck_assert_double_lt(r.mismatch[d], 1e-7);
}
