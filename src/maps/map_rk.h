/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Explicit Runge-Kutta maps: a Butcher tableau (c, A strictly lower triangular, b) and the one
 * evaluation they share (map_rk.c); each method is its own file with its tableau and type
 * table (map_rk4.c, map_rk8.c). */
#ifndef STABDAE_SRC_MAPS_MAP_RK_H
#define STABDAE_SRC_MAPS_MAP_RK_H

#include <stddef.h>

#include "map.h"

typedef struct sdae_rk_tableau {
  size_t stages;   /* s */
  const double *a; /* a_ij, j < i, row by row: row i (from 0) is a[i (i - 1) / 2 ..], i values */
  const double *b; /* s weights */
  const double *c; /* s nodes, c_0 = 0 */
} sdae_rk_tableau;

/* doubles of scratch: the s stage derivatives and the stage state */
size_t sdae__rk_scratch(const sdae_rk_tableau *tab, const sdae_model *m);

/* phi_T(mu) = sum_i b_i k_i, k_i = q0(t + c_i T, mu + T sum_{j<i} a_ij k_j): on the manifold a
 * step mu+ = mu + T phi_T is the Runge-Kutta step on mu' = q0(t, mu). A stage state that is
 * not finite is SDAE_ERR_NONFINITE before q0 sees it. */
int sdae__rk_phi(const sdae_rk_tableau *tab, sdae_map_ctx *c, double t, double T, const double *mu,
                 double *out);

#endif /* STABDAE_SRC_MAPS_MAP_RK_H */
