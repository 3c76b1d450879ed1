/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Fixed steps with an observer: the driver loop around sdae_step. */
#include <math.h>

#include "internal.h"

/* The observer sees step 0, every `every`-th step and the last one. */
static int observe(sdae_observer obs, void *data, size_t i, size_t every, size_t nsteps,
                   double t, const double *xi, const double *mu) {
  if (!obs || (i % every != 0 && i != nsteps)) return 0;
  return obs(i, t, xi, mu, data);
}

int sdae_integrate(sdae_stepper *s, double t0, double T, size_t nsteps, size_t every,
                   double *xi, double *mu, sdae_observer obs, void *data, size_t *steps_done) {
  size_t i;
  int rc = SDAE_OK;
  if (steps_done) *steps_done = 0;
  if (!s || !xi || !mu) return SDAE_ERR_NULL;
  if (!(isfinite(T) && T > 0.0)) return SDAE_ERR_STEP;
  if (!isfinite(t0) || every == 0) return SDAE_ERR_PARAM;
  if (observe(obs, data, 0, every, nsteps, t0, xi, mu)) return SDAE_STOPPED;
  for (i = 1; i <= nsteps; i++) {
    /* times as t0 + i T, not accumulated, so they do not drift over long runs */
    rc = sdae_step(s, t0 + (double)(i - 1) * T, T, xi, mu);
    if (rc != SDAE_OK) break;
    if (steps_done) *steps_done = i;
    if (observe(obs, data, i, every, nsteps, t0 + (double)i * T, xi, mu)) return SDAE_STOPPED;
  }
  return rc;
}
