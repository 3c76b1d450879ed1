/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The nonlinear oscillator of the paper's Section IV: a mass m on a cubic spring k with damping
 * d, held on the floor Y = 0 (one constraint of relative degree 2). With m = 1 it is the
 * paper's model; the mass enters as in erratum 3 of docs/paper.md. */
#ifndef STABDAE_EXAMPLES_OSCILLATOR_MODEL_H
#define STABDAE_EXAMPLES_OSCILLATOR_MODEL_H

#include <stabdae/stabdae.h>

typedef enum osc_q_variant {
  OSC_Q_CORRECTED = 0, /* c = (k (3 mu1^2 - 3 mu1 xi1 + xi1^2) + d)/m, derived from eq. 22 */
  OSC_Q_PAPER = 1      /* c = (k (3 mu1 xi1 - 3 mu1^2 - xi1^2) + d xi1)/m, as printed */
} osc_q_variant;

typedef struct osc_params {
  double k, d, m, ga;
  osc_q_variant q;
  double inv_m; /* 1/m, set by osc_model: the step's callbacks multiply, a division costs more */
} osc_params;

/* x = (X, Y, Xdot, Ydot); z = (xi1, xi2, mu1, mu2) of eq. 21 */
void osc_to_coords(const osc_params *p, const double *x, double *xi, double *mu);
void osc_from_coords(const osc_params *p, const double *xi, const double *mu, double *x);
/* The DAE of eq. 1: xdot = f(x) + g(x) lambda, h(x) = Y. */
void osc_dae(const osc_params *p, const double *x, double *f, double *g);
double osc_energy(const osc_params *p, const double *x); /* E, total, in x */
double osc_W(const osc_params *p, const double *mu);     /* W on the manifold, in mu */
double osc_c(const osc_params *p, const double *xi, const double *mu); /* Q's entry (2,1) */

/* The model: q0, Q, q0_jac, one constraint of relative degree 2; for sdae_map_dgrad H = W,
 * grad W, hess W and S = [[0, 1/m], [-1/m, -d/m^2]]; for sdae_map_user the paper's phi_T with
 * its Jacobian. params = p, whose inv_m it sets (call it again after a change of m). */
void osc_model(sdae_model *model, osc_params *p);

/* The DAE (f, g), Phi and Phi^-1 as sdae_check_model wants them; params = p. */
void osc_dae_spec(sdae_dae *d, osc_params *p);

#endif /* STABDAE_EXAMPLES_OSCILLATOR_MODEL_H */
