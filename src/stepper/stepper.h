/* SPDX-License-Identifier: GPL-3.0-or-later */
/* What the layers above the stepper may know of one, besides the public API. */
#ifndef STABDAE_SRC_STEPPER_STEPPER_H
#define STABDAE_SRC_STEPPER_STEPPER_H

#include <stabdae/stabdae.h>

#include "core/bytes.h"

/* SDAE_OK when the model and options make a stepper, the status saying why not otherwise */
int sdae__stepper_validate(const sdae_model *m, const sdae_options *o);
/* the stepper's copy of its model */
const sdae_model *sdae__stepper_model(const sdae_stepper *s);
/* the allocator the stepper was allocated with (zero for the caller's memory: malloc) */
const sdae_allocator *sdae__stepper_allocator(const sdae_stepper *s);

/* Newton's matrix by differences kept across steps and stages (core/newton.h, keep): for
 * a front-end whose every residual is costly (the mechanical one's: a Phi^-1 each); the
 * stepper alone rebuilds it at every solve */
void sdae__stepper_keep_newton(sdae_stepper *s);
/* the Newton matrix kept across steps is no longer the model's (a front-end changed its
 * coordinates: a chart switch; a failed step) */
void sdae__stepper_newton_forget(sdae_stepper *s);
/* what the next step depends on besides (xi, mu): the counters and what Newton keeps, counted,
 * written or read (core/bytes.h) */
void sdae__stepper_state(sdae_stepper *s, sdae_bytes *b);
/* the bytes sdae__stepper_state counts for a stepper of this model and options, before one is
 * built (a front-end's block holds a copy) */
size_t sdae__stepper_state_bytes(const sdae_model *m, const sdae_options *o);
/* what was read indexes nothing outside the stepper (Newton's pivots) */
int sdae__stepper_state_valid(const sdae_stepper *s);

/* nsteps fixed steps of a stepper of either kind (sdae_integrate, sdae_mbs_integrate): step
 * advances the state (x, y) (xi and mu, or q and v) of the stepper s from t by T, the observer
 * sees step 0, every `every`-th step and the last (integrate.c) */
typedef int (*sdae_step_fn)(void *s, double t, double T, double *x, double *y);
int sdae__run(void *s, sdae_step_fn step, double t0, double T, size_t nsteps, size_t every,
              double *x, double *y, sdae_observer obs, void *data, size_t *steps_done);

#endif /* STABDAE_SRC_STEPPER_STEPPER_H */
