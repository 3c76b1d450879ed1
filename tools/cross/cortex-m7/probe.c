/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A step's footprint on the board, for each example model (examples/models) and map: the
 * stepper's block (sdae_*_size), the stack 100 steps take at most (the stack painted below the
 * caller's frame, read back after the run), and the heap after set-up: once the stepper is
 * built, every malloc, calloc and realloc fails (the linker's --wrap), and the run must still
 * complete. One Markdown row a case; exit status 1 when a run fails or asks for the heap. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "mechanisms.h"
#include "oscillator_model.h"

#define STEPS 100
#define T 1e-3
#define PAINT 0xA5A5A5A5u

#define ROOM (64 * 1024) /* the stack painted below the caller; a step using it all shows ROOM */

/* ---- the heap, closed once the stepper is built ------------------------------------------- */

static int closed;
static unsigned long refused;

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t n);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *p, size_t n);

void *__wrap_malloc(size_t n) { return closed ? (refused++, NULL) : __real_malloc(n); }
void *__wrap_calloc(size_t n, size_t size) {
  return closed ? (refused++, NULL) : __real_calloc(n, size);
}
void *__wrap_realloc(void *p, size_t n) {
  return closed ? (refused++, NULL) : __real_realloc(p, n);
}

/* ---- the painted stack -------------------------------------------------------------------- */

/* the pattern from ROOM below `from` up to 64 bytes below this frame: the frames between `from`
 * and there (the run's loop, this call) are not painted, so a use smaller than they are reads
 * as their size, the measure's floor (a leaf on bare metal without interrupts: nothing else
 * writes below its stack pointer) */
static __attribute__((noinline)) void paint(char *from) {
  uint32_t *p = (uint32_t *)(void *)(from - ROOM);
  uint32_t *top = (uint32_t *)__builtin_frame_address(0) - 16;
  while (p < top) *p++ = PAINT;
}

/* bytes of stack below `from` written since paint(from): down to the lowest word changed */
static size_t used_below(const char *from) {
  const uint32_t *p = (const uint32_t *)(const void *)(from - ROOM);
  while (*p == PAINT) p++;
  return (size_t)(from - (const char *)p);
}

/* ---- the cases ---------------------------------------------------------------------------- */

typedef struct result {
  size_t block, stack;
  unsigned long heap;
  int steps, rc;
} result;

static const struct {
  const char *name;
  const sdae_map_type *const *map;
} MAPS[] = {{"euler", &sdae_map_euler}, {"midpoint", &sdae_map_midpoint},
            {"dgrad", &sdae_map_dgrad}, {"dg4", &sdae_map_dg4},
            {"dg6", &sdae_map_dg6},     {"rk4", &sdae_map_rk4},
            {"rk8", &sdae_map_rk8}};
#define N_MAPS (sizeof MAPS / sizeof MAPS[0])

static void options(sdae_options *o, size_t m) {
  sdae_options_default(o);
  o->map = *MAPS[m].map;
  o->delta = 2.0;
  o->epsilon = 1.0;
}

/* STEPS steps of a mechanism from (q, v), the heap closed and the stack painted */
static __attribute__((noinline)) result run_mbs(const sdae_mbs *sys, size_t m, double *q,
                                                double *v) {
  result r = {0};
  sdae_options o;
  sdae_mbs_stepper *s = NULL;
  char *base = __builtin_frame_address(0);
  options(&o, m);
  r.block = sdae_mbs_stepper_size(sys, &o);
  if ((r.rc = sdae_mbs_stepper_alloc(&s, sys, &o)) != SDAE_OK) return r;
  closed = 1, refused = 0;
  paint(base);
  for (r.steps = 0; r.steps < STEPS; r.steps++)
    if ((r.rc = sdae_mbs_step(s, r.steps * T, T, q, v)) != SDAE_OK) break;
  r.stack = used_below(base);
  closed = 0, r.heap = refused;
  sdae_mbs_stepper_free(s);
  return r;
}

/* the same for the paper's oscillator as a model of the normal form (scheme 15) */
static __attribute__((noinline)) result run_model(const sdae_model *model, size_t m, double *xi,
                                                  double *mu) {
  result r = {0};
  sdae_options o;
  sdae_stepper *s = NULL;
  char *base = __builtin_frame_address(0);
  options(&o, m);
  o.scheme = SDAE_SCHEME_SEMI_IMPLICIT;
  r.block = sdae_stepper_size(model, &o);
  if ((r.rc = sdae_stepper_alloc(&s, model, &o)) != SDAE_OK) return r;
  closed = 1, refused = 0;
  paint(base);
  for (r.steps = 0; r.steps < STEPS; r.steps++)
    if ((r.rc = sdae_step(s, r.steps * T, T, xi, mu)) != SDAE_OK) break;
  r.stack = used_below(base);
  closed = 0, r.heap = refused;
  sdae_stepper_free(s);
  return r;
}

static int row(const char *model, size_t m, result r) {
  /* newlib as Debian builds it has no C99 length modifiers (%zu prints "zu") */
  printf("| %s | %s | %lu | %lu | %lu | %d | %s |\n", model, MAPS[m].name, (unsigned long)r.block,
         (unsigned long)r.stack, r.heap, r.steps, sdae_strerror(r.rc));
  return r.rc != SDAE_OK || r.heap != 0 || r.steps != STEPS;
}

int main(void) {
  mech_pendulum pendulum = {1.0, 1.0, 9.81, 0.0};
  mech_double_pendulum dp = {1.0, 1.0, 1.0, 1.0, 9.81};
  mech_fourbar fourbar = {1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81};
  osc_params osc = {2.0, 0.03, 1.0, 9.81, OSC_Q_CORRECTED, 1.0};
  sdae_mbs sys[3];
  sdae_model model;
  const char *names[3] = {"pendulum", "double pendulum", "four-bar"};
  int bad = 0;
  mech_pendulum_system(&sys[0], &pendulum);
  mech_double_pendulum_system(&sys[1], &dp);
  mech_fourbar_system(&sys[2], &fourbar);
  osc_model(&model, &osc);
  printf("| model | map | block, bytes | stack of a step, bytes | heap calls after set-up | "
         "steps | status |\n|---|---|---:|---:|---:|---:|---|\n");
  for (size_t m = 0; m < N_MAPS; m++) {
    const double x0[4] = {0.1, 0.6, 0.0, 0.0}, a[2] = {0.5, 0.3}, w[2] = {0.0, 0.0};
    double xi[2], mu[2], q[4], v[4];
    if (MAPS[m].map != &sdae_map_dg4 && MAPS[m].map != &sdae_map_dg6) {
      osc_to_coords(&osc, x0, xi, mu);
      bad |= row("oscillator (normal form)", m, run_model(&model, m, xi, mu));
    }
    mech_pendulum_state(&pendulum, 0.5, 0.0, q, v);
    bad |= row(names[0], m, run_mbs(&sys[0], m, q, v));
    mech_double_pendulum_state(&dp, a, w, q, v);
    bad |= row(names[1], m, run_mbs(&sys[1], m, q, v));
    mech_fourbar_state(&fourbar, 0.0, 5.0, q, v);
    bad |= row(names[2], m, run_mbs(&sys[2], m, q, v));
  }
  return bad;
}
