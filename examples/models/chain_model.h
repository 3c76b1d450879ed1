/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A chain of N masses on the floor: mass i has a cubic spring k X_i^3 to its own anchor,
 * damping d, and a cubic spring kc to each neighbour (free ends); N constraints Y_i = 0, each of
 * relative degree 2. Given through Q_apply (O(N) per call, no N x N matrix). */
#ifndef STABDAE_EXAMPLES_CHAIN_MODEL_H
#define STABDAE_EXAMPLES_CHAIN_MODEL_H

#include <stddef.h>

#include <stabdae/stabdae.h>

typedef struct chain_params {
  size_t N;
  double k, kc, d, m, ga;
  unsigned *rel_degree; /* N entries of 2, owned; set by chain_model */
} chain_params;

/* Bandwidths of dq0/dmu (and so of the Newton matrix I - T dphi/dmu+ of the midpoint map) in
 * the interleaved ordering mu = (mu_{0,1}, mu_{0,2}, mu_{1,1}, ...): row (i,2) = 2i+1 reaches
 * the columns 2i-2, 2i, 2i+1, 2i+2. */
#define CHAIN_JAC_LOWER 3
#define CHAIN_JAC_UPPER 1
#define CHAIN_JAC_WIDTH (CHAIN_JAC_LOWER + CHAIN_JAC_UPPER + 1)

/* x = (X_0, Y_0, Xdot_0, Ydot_0, X_1, ...), 4N values; xi and mu interleaved, 2N each. */
void chain_to_coords(const chain_params *p, const double *x, double *xi, double *mu);
void chain_from_coords(const chain_params *p, const double *xi, const double *mu, double *x);
/* xdot = f(x) + g(x) lambda of the DAE, lambda with N values. */
void chain_dae_rhs(const chain_params *p, const double *x, const double *lambda, double *xdot);
double chain_energy(const chain_params *p, const double *x); /* E in x */
double chain_H(const chain_params *p, const double *mu);     /* E on the manifold, in mu */

/* The model (with H, grad H and the block-diagonal S = diag([[0, 1/m], [-1/m, -d/m^2]]) as S v,
 * O(N), for sdae_map_dgrad); allocates p->rel_degree (0, or SDAE_ERR_NOMEM).
 * chain_model_free releases it. */
int chain_model(sdae_model *model, chain_params *p);
void chain_model_free(chain_params *p);
/* dq0/dmu in band storage: band[r * CHAIN_JAC_WIDTH + (c - r + CHAIN_JAC_LOWER)] is entry
 * (r, c); entries outside the matrix are 0. 2N rows. */
void chain_q0_jac_band(const chain_params *p, const double *mu, double *band);
/* The bandwidth of d phi / d mu+ for the midpoint and discrete-gradient maps, for the options'
 * banded Newton: mu_{i,2}' couples to mu_{i-1,1} and mu_{i+1,1}, offsets -3..+1. */
#define CHAIN_BANDWIDTH 3

/* A reproducible start off the manifold from GSL's MT19937 seeded with seed: for each mass in
 * turn X_i in [-0.5, 0.5], Y_i in [-0.2, 0.2], Xdot_i and Ydot_i in [-0.1, 0.1] (gsl_ran_flat,
 * in this order). 0, or -1 when the generator cannot be allocated. */
int chain_random_start(const chain_params *p, unsigned long seed, double *x);

#endif /* STABDAE_EXAMPLES_CHAIN_MODEL_H */
