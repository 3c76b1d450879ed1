/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The stepper's struct, seen by the stepper's own files only: one block, the struct followed by
 * the arrays its parts carve (the map's scratch and Newton, the stabilizer, the step's own). */
#ifndef STABDAE_SRC_STEPPER_STEPPER_IMPL_H
#define STABDAE_SRC_STEPPER_STEPPER_IMPL_H

#include <stabdae/stabdae.h>

#include "core/alloc.h"
#include "core/newton.h"
#include "maps/map.h"
#include "model/stabilizer.h"

struct sdae_stepper {
  sdae_model model;
  sdae_options opt;
  const sdae_stabilizer_type *stabilizer;
  sdae_block block; /* what sdae_stepper_alloc_with allocated; its allocator serves certify */
  sdae_stats stats;
  sdae_map_ctx map; /* the map's context: model, scratch, Newton */
  sdae_newton newton;
  sdae_stab_ctx stab;
  double *Q;               /* n_mu x n_xi (dense Q only) */
  double *Qxi;             /* n_mu: Q(xi, mu) xi */
  double *qnorm2;          /* n_xi: ||q_i||^2 */
  double *xi_new, *mu_new; /* n_xi, n_mu: the step's result before it is accepted */
  double *phi;             /* n_mu: the map's value at the predictor */
};

#endif /* STABDAE_SRC_STEPPER_STEPPER_IMPL_H */
