/* SPDX-License-Identifier: GPL-3.0-or-later */
/* nfourbar: the N-four-bar, the IFToMM benchmark A02, through the mechanical front-end
 * (<stabdae/mbs.h>; models/nfourbar.h): N four-bars in a row, 2N + 1 rods of 1 m and 1 kg in
 * natural coordinates (the N + 1 rockers' tips, 2N + 2), 2N + 1 constraints, one degree of
 * freedom; from the upright squares with every tip at 1 m/s along x, under gravity along -y, the
 * parallelogram turns over. Where the rockers are horizontal the rank of G drops from 2N + 1 to
 * N + 1 for an instant: a singular configuration, twice a turn, where the steps are projected
 * (docs/front-ends.md). The default rk8 at T = 1e-2 crosses them within the benchmark's
 * high-precision criterion (docs/performance.md). Output:
 * t,q1..,v1..,lambda1..,max_abs_c,E,switches. */
#include <stdio.h>
#include <stdlib.h>

#include "mbs_cli.h"
#include "nfourbar.h"

#define NFLAGS 2

typedef struct args {
  mech_nfourbar p;
  double N;
  int sparse;
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates the N-four-bar (IFToMM benchmark A02: 2N + 1 rods, natural coordinates,\n"
    "singular where the rockers are flat) through the mechanical front-end and writes CSV:\n"
    "t,q1..,v1..,lambda1..,max_abs_c,E,switches. Defaults: N 40, tf 20, T 1e-2, map rk8,\n"
    "dense (--sparse: by the patterns of M and G).\n"
    "Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.run = mbs_run_defaults(), .p = mech_nfourbar_benchmark()};
  a->N = (double)a->p.N;
  a->run.tf = 20.0;
  a->run.T = 1e-2;
  a->run.map = sdae_map_rk8;
  const cli_flag model_flags[NFLAGS] = {
      {"N", CLI_POSITIVE, &a->N, NULL, 0, "the four-bars in the row (a whole number, 1 to 1000)"},
      {"sparse", CLI_SWITCH, &a->sparse, NULL, 0,
       "M and G by their patterns: the sparse back-end (the implicit maps' Newton included)"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  if (a->N != (double)(size_t)a->N || a->N > 1000.0)
    return cli_fail(err, errlen, "--N: %g is not a whole number from 1 to 1000", a->N);
  a->p.N = (size_t)a->N;
  a->p.sparse = a->sparse;
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  size_t n_q = 2 * (a->p.N + 1);
  double *q = malloc(2 * n_q * sizeof *q);
  int rc;
  if (!q || mech_nfourbar_system(&sys, &a->p) != 0) {
    fprintf(stderr, "nfourbar: out of memory\n");
    free(q);
    return CLI_EXIT_FAILED;
  }
  mech_nfourbar_start(&a->p, q, q + n_q);
  const mbs_program prog = {"nfourbar", &sys, q, q + n_q};
  rc = mbs_execute_to(&prog, &a->run, sink);
  mech_nfourbar_free(&a->p);
  free(q);
  return rc;
}

const cli_def nfourbar_def = {"nfourbar", summary, CLI_LAYOUT(args), parse_args, run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&nfourbar_def, argc, argv); }
#endif
