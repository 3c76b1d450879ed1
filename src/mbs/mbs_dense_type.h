/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The dense coordinates as a type (mbs_type.h, mbs_dense_type.c): the chart of mbs_chart.c, the
 * point, Phi^-1 and the mu-dynamics of mbs_coords.c, the quantities at a state of mbs_query.c,
 * and with a potential the energy structure on the manifold. Every implicit map, and every
 * mechanism without both patterns, is stepped in these. */
#ifndef STABDAE_SRC_MBS_MBS_DENSE_TYPE_H
#define STABDAE_SRC_MBS_MBS_DENSE_TYPE_H

#include "mbs_chart.h"
#include "mbs_coords.h"
#include "mbs_query.h"
#include "mbs_type.h"

typedef struct sdae_mbs_dense_parts {
  sdae_mbs_eval *eval;
  sdae_mbs_atlas chart;
  sdae_mbs_coords coords;
  sdae_mbs_query query;
  int energy_map; /* the map conserves H: the constraints must not depend on t */
  /* the energy structure's scratch */
  double *zero; /* 2 n_c zeros: xi on the manifold */
  double *D;    /* n_q x n_q: the damping D(q) */
  double *F_in; /* n_q: the forces from outside the Lagrangian */
} sdae_mbs_dense_parts;

extern const sdae_mbs_type sdae__mbs_dense_type;

#endif /* STABDAE_SRC_MBS_MBS_DENSE_TYPE_H */
