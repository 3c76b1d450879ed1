/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A sparse mechanism's coordinates as a type (mbs_type.h, mbs_sparse_type.c): the point, the
 * chart, Phi^-1 and the mu-dynamics of mbs_sparse.c, the quantities at a state of
 * mbs_sparse_query.c. No energy structure: the discrete gradients are implicit maps, stepped in
 * the dense coordinates (sdae__mbs_sparse_applies). */
#ifndef STABDAE_SRC_MBS_MBS_SPARSE_TYPE_H
#define STABDAE_SRC_MBS_MBS_SPARSE_TYPE_H

#include "mbs_sparse.h"
#include "mbs_sparse_query.h"
#include "mbs_type.h"

typedef struct sdae_mbs_sparse_parts {
  sdae_mbs_sparse sp;
  sdae_mbs_sparse_query query; /* on sp's patterns and analysis */
} sdae_mbs_sparse_parts;

extern const sdae_mbs_type sdae__mbs_sparse_type;

#endif /* STABDAE_SRC_MBS_MBS_SPARSE_TYPE_H */
