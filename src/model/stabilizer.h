/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The xi update: the paper's stabilizer (the gains of eq. 6) or a baseline, a table each. */
#ifndef STABDAE_SRC_MODEL_STABILIZER_H
#define STABDAE_SRC_MODEL_STABILIZER_H

#include <stabdae/stabdae.h>

#include "core/arena.h"

typedef struct sdae_stab_ctx {
  const sdae_model *model;
  const sdae_options *opt;
  const double *qnorm2; /* ||q_i||^2 at (xi, mu), n_xi */
  double *k;            /* the paper's: the gains (eq. 6), n_xi */
  double *blk, *blk_LU; /* the baselines': one chain's (I - T A) and its factors */
  unsigned *blk_piv;
} sdae_stab_ctx;

typedef struct sdae_stabilizer_type {
  const char *name;
  int (*validate)(const sdae_model *m, const sdae_options *o); /* optional */
  void (*carve)(sdae_stab_ctx *c, sdae_arena *a);              /* optional: its workspace */
  int (*xi_update)(sdae_stab_ctx *c, double T, const double *xi, double *xi_new);
} sdae_stabilizer_type;

/* the table of a stabilizer, NULL for an unknown one */
const sdae_stabilizer_type *sdae__stabilizer_type(sdae_stabilizer which);
/* SDAE_OK when the model's rel_degree gives n_constraints degrees in 1..max summing to n_xi,
 * SDAE_ERR_REL_DEGREE otherwise */
int sdae__rel_degree_check(const sdae_model *m, unsigned max);
/* k_i = -(delta^2/2) ||q_i||^2 - epsilon (eq. 6), n values */
void sdae__gains(const sdae_options *o, const double *qnorm2, size_t n, double *k);

#endif /* STABDAE_SRC_MODEL_STABILIZER_H */
