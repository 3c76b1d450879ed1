/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The coordinates z = Phi(t, x) = (xi, mu) of a DAE (<stabdae/dae.h>): Phi's Jacobian, Phi^-1
 * (the DAE's own, or Newton) and the rate of mu along f. Shared by the model check (check.c) and
 * the generic front-end (dae_model.c). */
#ifndef STABDAE_SRC_DAE_COORDS_H
#define STABDAE_SRC_DAE_COORDS_H

#include <stabdae/dae.h>

#include "core/arena.h"
#include "core/newton.h"

typedef struct sdae_coords {
  const sdae_dae *dae;
  size_t n, n_xi;
  double *J;            /* n x n: dPhi/dx at the point of the last sdae__coords_jacobian */
  double *LU;           /* n x (3 n - 2): Newton's matrix in band format, then its factors */
  unsigned *piv;        /* n */
  sdae_newton newton;   /* Phi^-1's: Newton on Phi(t, x) = z */
  double *xa, *za, *zb; /* n each: a moved point and Phi at two of them */
  double *fx;           /* n: f(t, x), the direction of mu's rate */
} sdae_coords;

/* its arrays (counted, or handed out); mu is z[n_xi..n) */
void sdae__coords_carve(sdae_coords *c, const sdae_dae *dae, size_t n_xi, sdae_arena *a);
/* dPhi/dx at (t, x) into c->J: Phi_jac, or central differences */
int sdae__coords_jacobian(sdae_coords *c, double t, const double *x);
/* x = Phi^-1(t, z): Phi_inv, or Newton on Phi(t, x) = z from the x given (core/newton.h with the
 * library's default tolerance and cap: SDAE_ERR_NEWTON when it does not converge,
 * SDAE_ERR_SINGULAR when dPhi/dx is) */
int sdae__coords_invert(sdae_coords *c, double t, const double *z, double *x);
/* d/dt mu(t, x) along xdot = f(t, x) by a fourth-order central difference (n_mu values) */
int sdae__coords_mu_rate(sdae_coords *c, double t, const double *x, double *out);

#endif /* STABDAE_SRC_DAE_COORDS_H */
