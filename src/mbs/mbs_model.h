/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The normal form of a mechanism in the current chart (mbs_model.c): the sdae_model handed to the
 * stepper, its q0 and Q by the rule of derive.c from the mu-dynamics, and with a potential the
 * energy structure of the discrete gradients. A failing callback of the mechanism reaches the
 * stepper as a callback's failure; the status behind it is kept here for the front-end. */
#ifndef STABDAE_SRC_MBS_MBS_MODEL_H
#define STABDAE_SRC_MBS_MBS_MODEL_H

#include <stabdae/stabdae.h>

#include "core/arena.h"
#include "mbs_coords.h"
#include "model/derive.h"

typedef struct sdae_mbs_model {
  sdae_model model;    /* params = this */
  sdae_derive derive;  /* q0 and Q from the mu-dynamics */
  sdae_mbs_coords *co; /* the coordinates (mbs_coords.h) */
  size_t n_c, n_f;
  int input;     /* the mechanism has forces from outside the Lagrangian (input_force) */
  int status;    /* the status behind the last failing callback of the normal form */
  double *Rx;    /* n_f: R x, R = W^T D W on the manifold */
  double *row;   /* n_f: grad H's first half while q0's is still read */
  double *Bu;    /* n_f: W^T F_in, the input's momentum part, taken from q0 in grad H */
  double *Bu_mu; /* n_mu: the mu Bu was evaluated at (with Bu_t), kept for the map's input */
  double Bu_t;
  int Bu_have;
  double *floor; /* 2 n_c: xi's floors at the step's start (derive.c skips below) */
} sdae_mbs_model;

/* the normal form of a mechanism in its coordinates co (the energy structure where the
 * mechanism has a potential, the implicit maps' linear solve where the back-end keeps Newton's
 * factors); the arrays come from sdae__mbs_model_carve */
void sdae__mbs_model_init(sdae_mbs_model *m, const sdae_mbs_eval *eval, sdae_mbs_coords *co);
void sdae__mbs_model_carve(sdae_mbs_model *m, sdae_arena *a);
/* forgets the q0 and B u kept: another start of Phi^-1, another chart */
void sdae__mbs_model_forget(sdae_mbs_model *m);

#endif /* STABDAE_SRC_MBS_MBS_MODEL_H */
