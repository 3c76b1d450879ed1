/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The FMU state (canGetAndSetFMUState, canSerializeFMUState): one block holding the clock, every
 * variable and the stepper's state as the library writes it (sdae_mbs_get_state: its chart, the
 * point it keeps, Newton's matrix, its counters; no pointer). Set into any instance of this
 * model (this one after a roll-back, a fresh one, one in another process), it puts back the
 * time and every variable, builds the stepper at those parameters and sets the stepper's state
 * into it: the motion continues bit for bit. */
#ifndef STABDAE_FMI_FMU_STATE_H
#define STABDAE_FMI_FMU_STATE_H

#include <stddef.h>

#include "fmu_instance.h"

typedef struct fmu_state fmu_state;

/* a new state in *state, or the one in *state (of this instance) overwritten */
fmu_status fmu_state_get(fmu_instance *fi, fmu_state **state);
fmu_status fmu_state_set(fmu_instance *fi, const fmu_state *state);
void fmu_state_free(fmu_instance *fi, fmu_state *state); /* NULL is fine */

/* the serialized form is the block itself */
size_t fmu_state_size(const fmu_state *state);
fmu_status fmu_state_serialize(fmu_instance *fi, const fmu_state *state, unsigned char *bytes,
                               size_t len);
fmu_status fmu_state_deserialize(fmu_instance *fi, const unsigned char *bytes, size_t len,
                                 fmu_state **state);

#endif /* STABDAE_FMI_FMU_STATE_H */
