/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The FMU state (canGetAndSetFMUState, canSerializeFMUState): one block holding the clock, every
 * variable and the bytes of the stepper's block. The stepper's block is self-contained (its
 * pointers point into itself or to the instance's mechanism), so its bytes put back at the same
 * address in the same instance of the same binary are the stepper exactly as it was: its chart
 * and the Newton matrix it keeps, so that a step after a roll-back is bit for bit the step taken
 * before. A state set into another instance (or deserialized in another process) puts back the
 * time and every variable, and builds a new stepper at that state: the motion continues from the
 * same point, the chart and Newton's matrix chosen anew (equal to Newton's tolerance). */
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
