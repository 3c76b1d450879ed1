/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The planar pendulum: a mass m on a massless rod of length L, gravity ga; index 3, one
 * constraint h = (X^2 + Y^2 - L^2)/2 of relative degree 2. */
#ifndef STABDAE_EXAMPLES_PENDULUM_MODEL_H
#define STABDAE_EXAMPLES_PENDULUM_MODEL_H

#include <stabdae/stabdae.h>

typedef struct pend_params {
  double L, m, ga;
} pend_params;

/* x = (X, Y, Xdot, Ydot); xi = (h, L_f h), mu = (theta, r^2 theta'). pend_from_coords returns
 * -1 when xi1 <= -L^2/2 (no point has that h), pend_to_coords when X = Y = 0. */
int pend_to_coords(const pend_params *p, const double *x, double *xi, double *mu);
int pend_from_coords(const pend_params *p, const double *xi, const double *mu, double *x);
/* The DAE: xdot = f(x) + g(x) lambda, h(x) = (X^2 + Y^2 - L^2)/2. */
void pend_dae(const pend_params *p, const double *x, double *f, double *g);
double pend_energy(const pend_params *p, const double *x); /* E in x */
double pend_H(const pend_params *p, const double *mu);     /* E on the manifold, in mu */

/* The model: q0, Q, q0_jac, one constraint of relative degree 2, and for sdae_map_dgrad H,
 * grad H, hess H and S = [[0, 1/m], [-1/m, 0]] (S grad H = q0, S skew). */
void pend_model(sdae_model *model, pend_params *p);

/* The DAE (f, g), Phi and Phi^-1 as sdae_check_model wants them; params = p. */
void pend_dae_spec(sdae_dae *d, pend_params *p);

#endif /* STABDAE_EXAMPLES_PENDULUM_MODEL_H */
