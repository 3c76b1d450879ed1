/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Fixed steps with an observer: one driver loop for sdae_step and sdae_mbs_step. */
#include <math.h>

#include "stepper.h"

int sdae__drive(const sdae_drive *d, double t0, double T, size_t nsteps, size_t every,
                size_t *steps_done) {
  int rc = SDAE_OK;
  if (!(isfinite(T) && T > 0.0)) return SDAE_ERR_STEP;
  if (!isfinite(t0) || every == 0) return SDAE_ERR_PARAM;
  if (d->observe && d->observe(d->ctx, 0, t0)) return SDAE_STOPPED;
  for (size_t i = 1; i <= nsteps; i++) {
    /* times as t0 + i T, not accumulated, so they do not drift over long runs */
    rc = d->step(d->ctx, t0 + (double)(i - 1) * T, T);
    if (rc != SDAE_OK) break;
    if (steps_done) *steps_done = i;
    if (d->observe && (i % every == 0 || i == nsteps) && d->observe(d->ctx, i, t0 + (double)i * T))
      return SDAE_STOPPED;
  }
  return rc;
}

typedef struct run {
  sdae_stepper *s;
  double *xi, *mu;
  sdae_observer obs;
  void *data;
} run;

static int step(void *ctx, double t, double T) {
  run *r = ctx;
  return sdae_step(r->s, t, T, r->xi, r->mu);
}

static int observe(void *ctx, size_t i, double t) {
  run *r = ctx;
  return r->obs(i, t, r->xi, r->mu, r->data);
}

int sdae_integrate(sdae_stepper *s, double t0, double T, size_t nsteps, size_t every, double *xi,
                   double *mu, sdae_observer obs, void *data, size_t *steps_done) {
  run r = {s, xi, mu, obs, data};
  sdae_drive d = {step, obs ? observe : NULL, &r};
  if (steps_done) *steps_done = 0;
  if (!s || !xi || !mu) return SDAE_ERR_NULL;
  return sdae__drive(&d, t0, T, nsteps, every, steps_done);
}
