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

/* the model has no user map (user_phi) */
static const char *const map_choices[] = {"euler", "midpoint", "dgrad", "dg4", "dg6", NULL};
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

static int chain_parse_args(int argc, char *const *argv, chain_args *a, char *err,
                            size_t errlen) {
  *a = (chain_args){.p = {10, 2.0, 1.0, 0.03, 1.0, 9.81, NULL},
                    .seed = 1,
                    .run = {.delta = 2.0, .eps = 1.0, .T = 0.001, .tf = 10.0,
                          .scheme = 1, .map = sdae_map_euler, .every = 1}};
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
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int chain_row(FILE *f, double t, const double *xi, const double *mu, unsigned iters,
                     void *vctx, const char **why) {
  const chain_row_ctx *ctx = vctx;
  double maxY = 0.0, maxYd = 0.0;
  (void)why;
  for (size_t i = 0; i < ctx->p->N; i++) {
    maxY = fmax(maxY, fabs(xi[2 * i]));
    maxYd = fmax(maxYd, fabs(xi[2 * i + 1]));
  }
  chain_from_coords(ctx->p, xi, mu, ctx->x);
  const double v[4] = {t, maxY, maxYd, chain_energy(ctx->p, ctx->x)};
  return cli_csv_row(f, v, 4, iters);
}

/* x from --x0 (bad input: exit 2) or the seeded random start (out of memory: exit 1) */
static int chain_start(const chain_args *a, double *x) {
  char err[CLI_ERR_LEN];
  if (!a->x0) return chain_random_start(&a->p, a->seed, x) ? CLI_EXIT_FAILED : CLI_EXIT_OK;
  if (cli_parse_vector(a->x0, x, 4 * a->p.N, "x0", err, sizeof err) == CLI_OK)
    return CLI_EXIT_OK;
  fprintf(stderr, "chain: %s\n", err);
  return CLI_EXIT_USAGE;
}

static int run(chain_args *a, double *x, double *xi, double *mu) {
  sdae_model model;
  sdae_options opt;
  int rc = chain_model(&model, &a->p) ? CLI_EXIT_FAILED : chain_start(a, x);
  if (rc == CLI_EXIT_USAGE) return rc;
  if (rc != CLI_EXIT_OK) {
    fprintf(stderr, "chain: out of memory for %zu masses\n", a->p.N);
    return CLI_EXIT_FAILED;
  }
  sdae_options_default(&opt);
  cli_run_options(&a->run, &opt);
  opt.map = a->run.map;
  opt.bandwidth = CHAIN_BANDWIDTH;
  chain_to_coords(&a->p, x, xi, mu);
  chain_row_ctx ctx = {&a->p, x};
  const cli_program prog = {"chain", "t,max_abs_Y,max_abs_Ydot,E,newton_iters", &model, &opt,
                            xi, mu, chain_row, &ctx};
  return cli_execute(&prog, &a->run);
}

int main(int argc, char **argv) {
  chain_args a;
  char err[CLI_ERR_LEN] = "";
  int rc = chain_parse_args(argc, argv, &a, err, sizeof err);
  rc = cli_parse_or_exit(rc, "chain", summary, a.flags, a.nflags, err);
  if (rc >= 0) return rc;

  double *x = malloc(4 * a.p.N * sizeof *x);
  double *xi = malloc(2 * a.p.N * sizeof *xi), *mu = malloc(2 * a.p.N * sizeof *mu);
  if (x && xi && mu) {
    rc = run(&a, x, xi, mu);
  } else {
    fprintf(stderr, "chain: out of memory for %zu masses\n", a.p.N);
    rc = CLI_EXIT_FAILED;
  }
  chain_model_free(&a.p);
  free(x);
  free(xi);
  free(mu);
  return rc;
}
