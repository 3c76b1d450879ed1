/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Small helpers shared by the example model suites: a seeded generator, the time derivative of
 * a coordinate map along a vector field by central differences, a state integrator, and a
 * mechanism's derivatives against sdae_mbs_check. */
#ifndef STABDAE_EXAMPLES_TEST_UTIL_H
#define STABDAE_EXAMPLES_TEST_UTIL_H

#include <stddef.h>

#include <gsl/gsl_rng.h>
#include <stabdae/mbs.h>
#include <stabdae/stabdae.h>

/* z = Phi(x), n_x inputs, n_z outputs */
typedef void (*tu_map)(const double *x, double *z, const void *ctx);

/* dPhi(x)[v] by the central difference (Phi(x + h v) - Phi(x - h v)) / 2h, n_x, n_z <= 64 */
void tu_directional(tu_map phi, const void *ctx, const double *x, const double *v, size_t n_x,
                    size_t n_z, double h, double *out);

/* uniform in [a, b] */
double tu_flat(gsl_rng *r, double a, double b);

/* nsteps steps of size T from t = 0 with a fresh stepper; returns the last status */
int tu_integrate(const sdae_model *m, const sdae_options *o, double T, size_t nsteps, double *xi,
                 double *mu);

/* sdae_mbs_check at (t, q, v): exactly the derivatives `given` (bits of sdae_mbs_derivative)
 * compared, consistent at tol = 1e-6, and each within 1e-7: the check's differences are good to
 * about 1e-9 for smooth callbacks, far inside what a wrong term would exceed */
void tu_assert_derivatives_exact(const sdae_mbs *s, double t, const double *q, const double *v,
                                 unsigned given);

#endif /* STABDAE_EXAMPLES_TEST_UTIL_H */
