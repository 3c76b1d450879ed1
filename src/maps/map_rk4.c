/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The classical Runge-Kutta method of order 4 as a map: phi_T(mu) = (k1 + 2 k2 + 2 k3 + k4)/6
 * with k1 = q0(t, mu), k2 = q0(t + T/2, mu + T k1/2), k3 = q0(t + T/2, mu + T k2/2),
 * k4 = q0(t + T, mu + T k3). Explicit (phi does not depend on mu+), 4 evaluations of q0, no
 * Newton; on the manifold a step is the method's step on mu' = q0(t, mu). Stable on the
 * imaginary axis up to |T lambda| = 2 sqrt(2); past that it is still the method's result. */
#include "map_rk.h"

/* Kutta (1901), "the classical Runge-Kutta method": Hairer, Norsett, Wanner, Solving Ordinary
 * Differential Equations I, 2nd ed. (Springer 1993), Sect. II.1. */
static const double rk4_a[] = {0.5,            /* a21 */
                               0.0, 0.5,       /* a31 a32 */
                               0.0, 0.0, 1.0}; /* a41 a42 a43 */
static const double rk4_b[] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
static const double rk4_c[] = {0.0, 0.5, 0.5, 1.0};

static const sdae_rk_tableau rk4 = {4, rk4_a, rk4_b, rk4_c};

static size_t rk4_scratch(const sdae_model *m, const sdae_options *o) {
  (void)o;
  return sdae__rk_scratch(&rk4, m);
}

static int rk4_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                   double *out) {
  (void)mu_next;
  return sdae__rk_phi(&rk4, c, t, T, mu, out);
}

static const sdae_map_type rk4_type = {
    .name = "rk4",
    .order = 4,
    .implicit = 0,
    .scratch = rk4_scratch,
    .phi = rk4_phi,
};

const sdae_map_type *const sdae_map_rk4 = &rk4_type;
