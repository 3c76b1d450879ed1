/* SPDX-License-Identifier: GPL-3.0-or-later */
/* bench_generated: the generated mechanisms (examples/models/sym/, tools/stabdae_gen) against
 * the hand-written ones (examples/models/) they describe. For each mechanism and map, the CPU
 * time per sdae_mbs_step of either over the same steps from the same start (median of the
 * repetitions), and the time of one set of the callbacks both give (each called once at the
 * states of the run); writes a Markdown table to stdout. The two run in the same process,
 * alternately, so that they see the same machine. Usage: bench_generated [--reps N] [--smoke]. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "andrews.h"
#include "benchmarks.h"
#include "car_axis.h"
#include "double_pendulum.h"
#include "fourbar.h"
#include "measure.h"
#include "mechanisms.h"
#include "slider_crank.h"

#define NQ 7
#define NC 6
#define STATES 64 /* states of the run at which the callbacks are timed */

typedef struct problem {
  const char *name;
  sdae_mbs hand, generated;
  double q0[NQ], v0[NQ], T;
  size_t steps;
} problem;

typedef struct run_ctx {
  const problem *p;
  const sdae_mbs *sys;
  sdae_mbs_stepper *s;
  double states[STATES][2 * NQ]; /* q, v along the run, for the callbacks' timing */
  int record;
} run_ctx;

typedef struct params {
  mech_double_pendulum dp;
  mech_fourbar fb;
  bench_slider_crank sc;
  bench_car_axis ca;
  bench_andrews an;
  double_pendulum_params gdp;
  fourbar_params gfb;
  slider_crank_params gsc;
  car_axis_params gca;
  andrews_params gan;
} params;

/* the five mechanisms with the example programs' defaults: start, T, and a few seconds' steps */
static size_t problems(params *P, problem *out) {
  const double a[2] = {2.0, 1.5}, w[2] = {0.0, 0.0};
  P->dp = (mech_double_pendulum){1.0, 1.0, 1.0, 1.0, 9.81};
  P->fb = (mech_fourbar){1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81};
  P->sc = bench_slider_crank_default();
  P->ca = bench_car_axis_default();
  bench_andrews_default(&P->an);
  double_pendulum_params_default(&P->gdp);
  fourbar_params_default(&P->gfb);
  slider_crank_params_default(&P->gsc);
  car_axis_params_default(&P->gca);
  andrews_params_default(&P->gan);

  out[0] = (problem){.name = "double_pendulum", .T = 1e-3, .steps = 2000};
  mech_double_pendulum_system(&out[0].hand, &P->dp);
  out[0].generated = double_pendulum_mbs(&P->gdp);
  mech_double_pendulum_state(&P->dp, a, w, out[0].q0, out[0].v0);

  out[1] = (problem){.name = "fourbar", .T = 1e-3, .steps = 2000};
  mech_fourbar_system(&out[1].hand, &P->fb);
  out[1].generated = fourbar_mbs(&P->gfb);
  (void)mech_fourbar_state(&P->fb, 0.0, 5.0, out[1].q0, out[1].v0);

  out[2] = (problem){.name = "slider_crank", .T = 1e-3, .steps = 2000};
  bench_slider_crank_system(&out[2].hand, &P->sc);
  out[2].generated = slider_crank_mbs(&P->gsc);
  bench_slider_crank_initial(&P->sc, out[2].q0, out[2].v0);

  out[3] = (problem){.name = "car_axis", .T = 1e-3, .steps = 2000};
  bench_car_axis_system(&out[3].hand, &P->ca);
  out[3].generated = car_axis_mbs(&P->gca);
  bench_car_axis_initial(&P->ca, out[3].q0, out[3].v0);

  out[4] = (problem){.name = "andrews", .T = 1e-5, .steps = 2000};
  bench_andrews_system(&out[4].hand, &P->an);
  out[4].generated = andrews_mbs(&P->gan);
  bench_andrews_initial(out[4].q0, out[4].v0);
  return 5;
}

static int run_steps(void *vctx) {
  run_ctx *c = vctx;
  const problem *p = c->p;
  size_t n = p->hand.n_q, every = p->steps / STATES;
  double q[NQ], v[NQ];
  memcpy(q, p->q0, sizeof q);
  memcpy(v, p->v0, sizeof v);
  for (size_t k = 0; k < p->steps; k++) {
    if (sdae_mbs_step(c->s, (double)k * p->T, p->T, q, v) != SDAE_OK) return 1;
    if (c->record && k % every == 0 && k / every < STATES) {
      memcpy(c->states[k / every], q, n * sizeof *q);
      memcpy(c->states[k / every] + n, v, n * sizeof *v);
    }
  }
  return 0;
}

/* every callback both mechanisms give, once at each recorded state */
static volatile double sink;
static int run_callbacks(void *vctx) {
  run_ctx *c = vctx;
  const sdae_mbs *s = c->sys, *h = &c->p->hand;
  size_t n = s->n_q;
  double M[NQ * NQ], F[NQ], cc[NC], G[NC * NQ], ct[NC], out[NC * NQ], acc = 0.0;
  for (int r = 0; r < 20; r++)
    for (size_t k = 0; k < STATES; k++) {
      const double *q = c->states[k], *v = c->states[k] + n, t = (double)k * c->p->T;
      int rc = s->mass(t, q, M, s->params) | s->force(t, q, v, F, s->params) |
               s->constraint(t, q, cc, s->params) | s->jacobian(t, q, G, s->params) |
               s->mass_dot_v(t, q, v, out, s->params) | s->jacobian_dot(t, q, v, out, s->params);
      if (h->constraint_t) rc |= s->constraint_t(t, q, ct, s->params);
      if (h->constraint_t_dot) rc |= s->constraint_t_dot(t, q, v, out, s->params);
      if (h->potential) rc |= s->potential(t, q, ct, s->params);
      if (rc) return 1;
      acc += M[0] + F[0] + cc[0] + G[0] + out[0] + ct[0];
    }
  sink = acc;
  return 0;
}

typedef struct timing {
  double step_ns, callbacks_ns;
} timing;

static int measure(const problem *p, const sdae_mbs *sys, const sdae_options *o, int reps,
                   run_ctx *ctx, timing *tm) {
  double cpu;
  *ctx = (run_ctx){.p = p, .sys = sys, .record = 1};
  if (sdae_mbs_stepper_alloc(&ctx->s, sys, o) != SDAE_OK) return 1;
  int ok = run_steps(ctx) == 0; /* a warm-up, recording the states */
  ctx->record = 0;
  ok = ok && wp_repeat(reps, 30.0, run_steps, ctx, &cpu) == reps;
  tm->step_ns = cpu / (double)p->steps * 1e9;
  ok = ok && wp_repeat(reps, 30.0, run_callbacks, ctx, &cpu) == reps;
  tm->callbacks_ns = cpu / (20.0 * STATES) * 1e9;
  sdae_mbs_stepper_free(ctx->s);
  return !ok;
}

int main(int argc, char **argv) {
  int reps = 7, smoke = 0;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--smoke") == 0) {
      smoke = 1, reps = 1;
    } else if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc) {
      reps = atoi(argv[++i]);
      if (reps < 1 || reps > WP_MAX_REPS) return wp_bad(argv[0], "--reps: 1 to 15, not ", argv[i]);
    } else {
      return wp_bad(argv[0], "unknown argument ", argv[i]);
    }
  }
  static params P;
  static problem prob[5];
  static run_ctx ctx;
  size_t np = problems(&P, prob);
  printf("| mechanism | map | T | hand ns/step | generated ns/step | ratio | hand callbacks ns "
         "| generated callbacks ns | ratio |\n|---|---|---|---|---|---|---|---|---|\n");
  for (size_t i = 0; i < np; i++) {
    const char *maps[2] = {"rk4", prob[i].hand.potential ? "dgrad" : "midpoint"};
    if (smoke) prob[i].steps = 2 * STATES;
    for (int m = 0; m < 2; m++) {
      sdae_options o;
      timing th, tg;
      sdae_options_default(&o);
      o.delta = 2.0, o.epsilon = 1.0, o.map = sdae_map_by_name(maps[m]);
      if (measure(&prob[i], &prob[i].hand, &o, reps, &ctx, &th) ||
          measure(&prob[i], &prob[i].generated, &o, reps, &ctx, &tg)) {
        fprintf(stderr, "bench_generated: %s with %s failed\n", prob[i].name, maps[m]);
        return 1;
      }
      printf("| %s | %s | %g | %.0f | %.0f | %.2f | %.0f | %.0f | %.2f |\n", prob[i].name, maps[m],
             prob[i].T, th.step_ns, tg.step_ns, tg.step_ns / th.step_ns, th.callbacks_ns,
             tg.callbacks_ns, tg.callbacks_ns / th.callbacks_ns);
    }
  }
  return 0;
}
