/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The worst step (docs/embedded.md): for each example model and map, the distribution of one
 * step's time over --steps steps (median, 99.9th percentile, max: the wall clock of each
 * sdae_step or sdae_mbs_step alone, CLOCK_MONOTONIC) and the counts that bound it, the most
 * in one step: Newton iterations of the map, Newton iterations of Phi^-1, chart switches (a
 * switch redoes the step's start in the new chart). With --cap K, newton_max_iter = K for
 * every Newton (the map's and Phi^-1's): a step that needs more returns its named status with
 * the state kept, and the table says how many did. The models and starts are those of the
 * Cortex-M7 probe (tools/cross/cortex-m7/probe.c); T = 1e-3. A wall clock on a shared
 * machine also times what preempts the step: the mechanisms' SLOW slowest steps are therefore
 * replayed, REPLAYS times each from their saved state (sdae_mbs_get_state, before the step;
 * a refused step too), and "replayed" is the largest of their median times, what the step
 * itself costs.
 *
 *   build/tools/worst_step [--steps N] [--cap K]     (defaults: 1000000 steps, the options' cap)
 *
 * One Markdown table on stdout; bad usage: one line on stderr, exit 2. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <stabdae/stabdae.h>

#include "mechanisms.h"
#include "oscillator_model.h"

#define T 1e-3
#define WARM 1000
#define SLOW 8
#define REPLAYS 51
#define STATE_MAX 65536

static const struct {
  const char *name;
  const sdae_map_type *const *map;
  int implicit; /* a Newton per step */
} MAPS[] = {{"euler", &sdae_map_euler, 0},
            {"midpoint", &sdae_map_midpoint, 1},
            {"dgrad", &sdae_map_dgrad, 1},
            {"rk4", &sdae_map_rk4, 0},
            {"rk8", &sdae_map_rk8, 0}};
#define N_MAPS (sizeof MAPS / sizeof MAPS[0])

/* a step to replay: its time, its start (t, q, v) and the stepper's state before it */
typedef struct slow {
  uint32_t ns;
  double t, q[4], v[4];
  unsigned char state[STATE_MAX];
} slow;

typedef struct tally {
  unsigned long steps, failed; /* steps taken; steps refused (the cap) */
  int refusal;                 /* the first refused step's status */
  unsigned max_newton, max_phi_inv, max_switches;
  double mean_newton, mean_phi_inv;
  size_t block;       /* the stepper's block (sdae_*_size) */
  double replayed;    /* the slowest steps' largest median replay, ns (0: not replayed) */
  uint32_t *ns;       /* each step's time */
  slow *slowest;      /* SLOW of them, the fastest first */
  unsigned char *pre; /* the state before the current step */
} tally;

static uint64_t now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

static int cmp_u32(const void *a, const void *b) {
  uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
  return (x > y) - (x < y);
}

static unsigned umax(unsigned a, unsigned long b) { return b > a ? (unsigned)b : a; }

/* keeps the step among the SLOW slowest (slowest[0] the fastest of them) */
static void keep_if_slow(tally *r, uint32_t ns, double t, const double *q, const double *v,
                         size_t len) {
  slow *w = r->slowest;
  if (ns <= w[0].ns) return;
  size_t i = 0;
  while (i + 1 < SLOW && w[i + 1].ns < ns) {
    w[i] = w[i + 1];
    i++;
  }
  w[i].ns = ns, w[i].t = t;
  memcpy(w[i].q, q, sizeof w[i].q), memcpy(w[i].v, v, sizeof w[i].v);
  memcpy(w[i].state, r->pre, len);
}

/* each kept step REPLAYS times from its state: the largest median */
static double replay(sdae_mbs_stepper *s, tally *r, size_t len) {
  double worst = 0.0;
  uint32_t ns[REPLAYS];
  for (int i = 0; i < SLOW; i++) {
    if (r->slowest[i].ns == 0) continue;
    for (int k = 0; k < REPLAYS; k++) {
      double q[4], v[4];
      memcpy(q, r->slowest[i].q, sizeof q), memcpy(v, r->slowest[i].v, sizeof v);
      if (sdae_mbs_set_state(s, r->slowest[i].state, len) != SDAE_OK) return 0.0;
      uint64_t t0 = now_ns();
      sdae_mbs_step(s, r->slowest[i].t, T, q, v);
      ns[k] = (uint32_t)(now_ns() - t0);
    }
    qsort(ns, REPLAYS, sizeof *ns, cmp_u32);
    if (ns[REPLAYS / 2] > worst) worst = ns[REPLAYS / 2];
  }
  return worst;
}

/* N steps of a mechanism; a refused step (the cap) is counted, the state kept, and the run goes
 * on from it with the next step */
static void run_mbs(const sdae_mbs *sys, const sdae_options *o, double *q, double *v,
                    unsigned long n, tally *r) {
  sdae_mbs_stepper *s = NULL;
  double t = 0.0;
  size_t len;
  r->block = sdae_mbs_stepper_size(sys, o);
  if (sdae_mbs_stepper_alloc(&s, sys, o) != SDAE_OK) return;
  if ((len = sdae_mbs_state_size(s)) > STATE_MAX || sys->n_q > 4) len = 0; /* no replays */
  for (int k = 0; k < WARM; k++, t += T) sdae_mbs_step(s, t, T, q, v);
  for (unsigned long k = 0; k < n; k++, t += T) {
    const sdae_mbs_stats *st = sdae_mbs_stepper_stats(s);
    unsigned long newton = st->step.newton_iters_total, phi = st->phi_inv_iters;
    unsigned long sw = st->chart_switches;
    double q0[4], v0[4];
    if (len) {
      sdae_mbs_get_state(s, r->pre, len);
      memcpy(q0, q, sys->n_q * sizeof *q), memcpy(v0, v, sys->n_q * sizeof *v);
    }
    uint64_t t0 = now_ns();
    int rc = sdae_mbs_step(s, t, T, q, v);
    uint32_t ns = (uint32_t)(now_ns() - t0);
    r->ns[r->steps++] = ns;
    if (len) keep_if_slow(r, ns, t, q0, v0, len); /* a refused step too: its cost under the cap */
    if (rc != SDAE_OK && r->failed++ == 0) r->refusal = rc;
    r->max_newton = umax(r->max_newton, st->step.newton_iters_total - newton);
    r->max_phi_inv = umax(r->max_phi_inv, st->phi_inv_iters - phi);
    r->max_switches = umax(r->max_switches, st->chart_switches - sw);
  }
  r->mean_newton = (double)sdae_mbs_stepper_stats(s)->step.newton_iters_total / (double)(n + WARM);
  r->mean_phi_inv = (double)sdae_mbs_stepper_stats(s)->phi_inv_iters / (double)(n + WARM);
  if (len) r->replayed = replay(s, r, len);
  sdae_mbs_stepper_free(s);
}

/* the same for the paper's oscillator as a model of the normal form (scheme 15) */
static void run_model(const sdae_model *m, const sdae_options *o, double *xi, double *mu,
                      unsigned long n, tally *r) {
  sdae_stepper *s = NULL;
  double t = 0.0;
  r->block = sdae_stepper_size(m, o);
  if (sdae_stepper_alloc(&s, m, o) != SDAE_OK) return;
  for (int k = 0; k < WARM; k++, t += T) sdae_step(s, t, T, xi, mu);
  for (unsigned long k = 0; k < n; k++, t += T) {
    unsigned long newton = sdae_stepper_stats(s)->newton_iters_total;
    uint64_t t0 = now_ns();
    int rc = sdae_step(s, t, T, xi, mu);
    r->ns[r->steps++] = (uint32_t)(now_ns() - t0);
    if (rc != SDAE_OK && r->failed++ == 0) r->refusal = rc;
    r->max_newton = umax(r->max_newton, sdae_stepper_stats(s)->newton_iters_total - newton);
  }
  r->mean_newton = (double)sdae_stepper_stats(s)->newton_iters_total / (double)(n + WARM);
  sdae_stepper_free(s);
}

static void row(const char *model, const char *map, tally *r) {
  size_t n = r->steps;
  if (n == 0) {
    printf("| %s | %s | the stepper could not be built |\n", model, map);
    return;
  }
  qsort(r->ns, n, sizeof *r->ns, cmp_u32);
  double med = r->ns[n / 2], p999 = r->ns[(size_t)(0.999 * (double)(n - 1))], max = r->ns[n - 1];
  char replayed[32] = "-", refused[96] = "0";
  if (r->replayed > 0.0) snprintf(replayed, sizeof replayed, "%.0f", r->replayed);
  if (r->failed)
    snprintf(refused, sizeof refused, "%lu (%s)", r->failed,
             r->refusal == SDAE_ERR_NEWTON    ? "SDAE_ERR_NEWTON"
             : r->refusal == SDAE_ERR_PHI_INV ? "SDAE_ERR_PHI_INV"
                                              : sdae_strerror(r->refusal));
  printf("| %s | %s | %lu | %lu | %.0f | %.0f | %.0f | %s | %.1f | %u (%.2f) | %u (%.2f) | %u | "
         "%s |\n",
         model, map, (unsigned long)r->block, (unsigned long)n, med, p999, max, replayed, max / med,
         r->max_newton, r->mean_newton, r->max_phi_inv, r->mean_phi_inv, r->max_switches, refused);
}

static int usage(const char *why, const char *arg) {
  fprintf(stderr, "worst_step: %s%s (usage: worst_step [--steps N] [--cap K])\n", why,
          arg ? arg : "");
  return 2;
}

static int count(const char *v, unsigned long max, unsigned long *out) {
  char *end;
  errno = 0;
  *out = strtoul(v, &end, 10);
  return errno || end == v || *end || *v == '-' || *out == 0 || *out > max;
}

int main(int argc, char **argv) {
  unsigned long steps = 1000000, cap = 0;
  for (int i = 1; i < argc; i += 2) {
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (strcmp(argv[i], "--steps") != 0 && strcmp(argv[i], "--cap") != 0)
      return usage("unknown option ", argv[i]);
    if (!v) return usage("a flag without its value: ", argv[i]);
    if (strcmp(argv[i], "--steps") == 0 ? count(v, 100000000, &steps) : count(v, 1000, &cap))
      return usage("not a count in range: ", v);
  }
  uint32_t *ns = malloc(steps * sizeof *ns);
  slow *slowest = malloc(SLOW * sizeof *slowest);
  unsigned char *pre = malloc(STATE_MAX);
  if (!ns || !slowest || !pre) return usage("no memory for the times of --steps steps", NULL);
  mech_pendulum pendulum = {1.0, 1.0, 9.81, 0.0};
  mech_double_pendulum dp = {1.0, 1.0, 1.0, 1.0, 9.81};
  mech_fourbar fourbar = {1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81};
  osc_params osc = {2.0, 0.03, 1.0, 9.81, OSC_Q_CORRECTED, 1.0};
  sdae_mbs sys[3];
  sdae_model model;
  const char *names[3] = {"pendulum", "double pendulum", "four-bar"};
  mech_pendulum_system(&sys[0], &pendulum);
  mech_double_pendulum_system(&sys[1], &dp);
  mech_fourbar_system(&sys[2], &fourbar);
  osc_model(&model, &osc);
  printf("| model | map | block, bytes | steps | median ns | 99.9 %% ns | max ns | slowest "
         "replayed, ns | max / median | Newton it. max (mean) | Phi^-1 it. max (mean) | chart "
         "switches max | refused (cap) |\n"
         "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (size_t m = 0; m < N_MAPS; m++) {
    const double x0[4] = {0.1, 0.6, 0.0, 0.0}, a[2] = {0.5, 0.3}, w[2] = {0.0, 0.0};
    double xi[2], mu[2], q[4], v[4];
    sdae_options o;
    sdae_options_default(&o);
    o.map = *MAPS[m].map, o.delta = 2.0, o.epsilon = 1.0;
    if (cap) o.newton_max_iter = (unsigned)cap;
    for (int k = 0; k < 4; k++) {
      tally r = {.ns = ns, .slowest = slowest, .pre = pre};
      memset(slowest, 0, SLOW * sizeof *slowest);
      if (k == 0) {
        osc_to_coords(&osc, x0, xi, mu);
        run_model(&model, &o, xi, mu, steps, &r);
      } else {
        if (k == 1) mech_pendulum_state(&pendulum, 0.5, 0.0, q, v);
        if (k == 2) mech_double_pendulum_state(&dp, a, w, q, v);
        if (k == 3) mech_fourbar_state(&fourbar, 0.0, 5.0, q, v);
        run_mbs(&sys[k - 1], &o, q, v, steps, &r);
      }
      row(k == 0 ? "oscillator (normal form)" : names[k - 1], MAPS[m].name, &r);
      fflush(stdout);
    }
  }
  free(ns), free(slowest), free(pre);
  return 0;
}
