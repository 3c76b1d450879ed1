/* SPDX-License-Identifier: GPL-3.0-or-later */
/* chain: N masses on the floor, each on a cubic spring, coupled to their neighbours by cubic
 * springs, started off the floor at a reproducible random state; integrated with stabdae.
 *
 * N constraints Y_i = 0; the model is given through Q_apply (O(N) per step), so the explicit
 * map runs large chains. Output, one CSV row per --every steps:
 * t,max_abs_Y,max_abs_Ydot,E,newton_iters. --x0 gives the start explicitly instead (4 N values),
 * for comparisons with other implementations. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "chain_model.h"
#include "cli.h"
#include "programs.h"

/* the model has no user map (user_phi) */
static const char *const map_choices[] = {"euler",     "midpoint",  "dgrad", "dg4", "dg6",
                                          "midpoint4", "midpoint6", "rk4",   "rk8", NULL};
/* keeps 4N doubles of state far inside size_t and memory on any machine that runs this */
#define CHAIN_MAX_N 100000000u

typedef struct chain_args {
  chain_params p;
  unsigned long seed;
  const char *x0; /* NULL: the random start */
  cli_run run;
  cli_flag flags[8 + CLI_RUN_NFLAGS];
  size_t nflags;
} chain_args;

typedef struct chain_row_ctx {
  const chain_params *p;
  double *x; /* 4N scratch values for the energy */
} chain_row_ctx;

static const char summary[] =
    "Integrates a chain of N masses held on the floor (N constraints Y_i = 0), from a\n"
    "random start (seeded MT19937: X_i in [-0.5,0.5], Y_i in [-0.2,0.2], velocities in\n"
    "[-0.1,0.1]) or from --x0, and writes CSV: t,max_abs_Y,max_abs_Ydot,E,newton_iters.\n"
    "Steps: ceil(tf/T - 1e-9).";

static int chain_parse_args(int argc, char *const *argv, void *args, char *err, size_t errlen) {
  chain_args *a = args;
  *a = (chain_args){.p = {10, 2.0, 1.0, 0.03, 1.0, 9.81, NULL},
                    .seed = 1,
                    .run = {.delta = 2.0,
                            .eps = 1.0,
                            .T = 0.001,
                            .tf = 10.0,
                            .scheme = 1,
                            .map = sdae_map_euler,
                            .every = 1}};
  const cli_flag model_flags[8] = {
      {"N", CLI_COUNT, &a->p.N, NULL, 0, "number of masses"},
      {"k", CLI_REAL, &a->p.k, NULL, 0, "anchor spring constant (force -k X_i^3)"},
      {"kc", CLI_REAL, &a->p.kc, NULL, 0, "coupling constant (kc (X_{i+1} - X_i)^3)"},
      {"d", CLI_REAL, &a->p.d, NULL, 0, "damping (force -d Xdot_i)"},
      {"m", CLI_POSITIVE, &a->p.m, NULL, 0, "mass of each body"},
      {"ga", CLI_REAL, &a->p.ga, NULL, 0, "gravitational acceleration"},
      {"seed", CLI_SEED, &a->seed, NULL, 0, "seed of the random start"},
      {"x0", CLI_LIST, &a->x0, NULL, 0,
       "start X_0,Y_0,Xdot_0,Ydot_0,X_1,... (4 N values) [random]"},
  };
  for (size_t i = 0; i < 8; i++) a->flags[i] = model_flags[i];
  a->nflags = 8 + cli_run_flags(a->flags + 8, &a->run, map_choices,
                                "mu-map (midpoint and dgrad use dense N x N algebra)");
  int rc = cli_parse(argc, argv, a->flags, a->nflags, err, errlen);
  if (rc != CLI_OK) return rc;
  if (a->p.N > CHAIN_MAX_N) {
    snprintf(err, errlen, "--N: at most %u masses", CHAIN_MAX_N);
    return CLI_BAD;
  }
  /* checked here, with every other input, read again into the state by chain_start */
  if (a->x0 && cli_parse_vector(a->x0, NULL, 4 * a->p.N, "x0", err, errlen) != CLI_OK)
    return CLI_BAD;
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int chain_row(cli_row_out *o, double t, const double *xi, const double *mu, void *vctx,
                     const char **why) {
  const chain_row_ctx *ctx = vctx;
  double maxY = 0.0, maxYd = 0.0;
  (void)why;
  for (size_t i = 0; i < ctx->p->N; i++) {
    maxY = fmax(maxY, fabs(xi[2 * i]));
    maxYd = fmax(maxYd, fabs(xi[2 * i + 1]));
  }
  chain_from_coords(ctx->p, xi, mu, ctx->x);
  const double v[4] = {t, maxY, maxYd, chain_energy(ctx->p, ctx->x)};
  return cli_emit(o, v, 4, maxY, v[3]); /* the constraints are Y_i = 0 */
}

/* x from --x0 (checked by the parser) or the seeded random start (0, or -1: out of memory) */
static int chain_start(const chain_args *a, double *x) {
  char err[CLI_ERR_LEN];
  if (a->x0) return cli_parse_vector(a->x0, x, 4 * a->p.N, "x0", err, sizeof err) ? -1 : 0;
  return chain_random_start(&a->p, a->seed, x) ? -1 : 0;
}

static int run(chain_args *a, double *x, double *xi, double *mu, cli_sink *sink) {
  sdae_model model;
  sdae_options opt;
  if (chain_model(&model, &a->p) || chain_start(a, x)) {
    fprintf(stderr, "chain: out of memory for %zu masses\n", a->p.N);
    return CLI_EXIT_FAILED;
  }
  sdae_options_default(&opt);
  cli_run_options(&a->run, &opt);
  opt.map = a->run.map;
  opt.bandwidth = CHAIN_BANDWIDTH;
  chain_to_coords(&a->p, x, xi, mu);
  chain_row_ctx ctx = {&a->p, x};
  const cli_program prog = {
      "chain", "t,max_abs_Y,max_abs_Ydot,E,newton_iters", &model, &opt, xi, mu, chain_row, &ctx};
  return cli_execute_to(&prog, &a->run, sink);
}

static int chain_run(void *args, cli_sink *sink) {
  chain_args *a = args;
  int rc;
  double *x = malloc(4 * a->p.N * sizeof *x);
  double *xi = malloc(2 * a->p.N * sizeof *xi), *mu = malloc(2 * a->p.N * sizeof *mu);
  if (x && xi && mu) {
    rc = run(a, x, xi, mu, sink);
  } else {
    fprintf(stderr, "chain: out of memory for %zu masses\n", a->p.N);
    rc = CLI_EXIT_FAILED;
  }
  chain_model_free(&a->p);
  free(x);
  free(xi);
  free(mu);
  return rc;
}

const cli_def chain_def = {"chain",          summary,   CLI_LAYOUT(chain_args),
                           chain_parse_args, chain_run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&chain_def, argc, argv); }
#endif
