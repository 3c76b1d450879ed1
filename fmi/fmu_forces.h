/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The user's mechanism with the FMU's inputs: u, the generalized forces the importer holds over
 * a communication step, added to the mechanism's input_force (forces from outside the
 * Lagrangian: with a potential, a port of the energy that the discrete gradients keep the
 * power balance of). Every other callback is the user's, called with the
 * user's params; the optional ones stay NULL where the user's are, so the library sees the
 * mechanism it would see without the FMU. */
#ifndef STABDAE_FMI_FMU_FORCES_H
#define STABDAE_FMI_FMU_FORCES_H

#include <stabdae/mbs.h>

typedef struct fmu_forces {
  sdae_mbs user;   /* the user's mechanism */
  const double *u; /* n_q inputs, read at every evaluation of F */
} fmu_forces;

/* sys: the user's mechanism with u added to its input_force, its params w (kept alive by the
 * caller) */
void fmu_forces_wrap(sdae_mbs *sys, fmu_forces *w);

#endif /* STABDAE_FMI_FMU_FORCES_H */
