/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Fixed steps with an observer: one run (its adapter and driver loop) for sdae_step and
 * sdae_mbs_step. */
#include <math.h>

#include "stepper.h"

typedef struct run {
  void *s;
  sdae_step_fn step;
  double *x, *y;
  sdae_observer obs;
  void *data;
} run;

static int observe(const run *r, size_t i, double t) {
  return r->obs && r->obs(i, t, r->x, r->y, r->data);
}

static int drive(const run *r, double t0, double T, size_t nsteps, size_t every,
                 size_t *steps_done) {
  int rc = SDAE_OK;
  if (!(isfinite(T) && T > 0.0)) return SDAE_ERR_STEP;
  if (!isfinite(t0) || every == 0) return SDAE_ERR_PARAM;
  if (observe(r, 0, t0)) return SDAE_STOPPED;
  for (size_t i = 1; i <= nsteps; i++) {
    /* times as t0 + i T, not accumulated, so they do not drift over long runs */
    rc = r->step(r->s, t0 + (double)(i - 1) * T, T, r->x, r->y);
    if (rc != SDAE_OK) break;
    if (steps_done) *steps_done = i;
    if ((i % every == 0 || i == nsteps) && observe(r, i, t0 + (double)i * T)) return SDAE_STOPPED;
  }
  return rc;
}

int sdae__run(void *s, sdae_step_fn step, double t0, double T, size_t nsteps, size_t every,
              double *x, double *y, sdae_observer obs, void *data, size_t *steps_done) {
  const run r = {s, step, x, y, obs, data};
  if (steps_done) *steps_done = 0;
  if (!s || !x || !y) return SDAE_ERR_NULL;
  return drive(&r, t0, T, nsteps, every, steps_done);
}

static int step(void *s, double t, double T, double *xi, double *mu) {
  return sdae_step(s, t, T, xi, mu);
}

int sdae_integrate(sdae_stepper *s, double t0, double T, size_t nsteps, size_t every, double *xi,
                   double *mu, sdae_observer obs, void *data, size_t *steps_done) {
  return sdae__run(s, step, t0, T, nsteps, every, xi, mu, obs, data, steps_done);
}
