/* SPDX-License-Identifier: GPL-3.0-or-later */
/* pendulum_mbs: the planar pendulum of examples/pendulum.c, given to the library as a
 * mechanism (<stabdae/mbs.h>) instead of a hand-written normal form: q = (x, y), M = m I,
 * F = (0, -m ga), c = (x^2 + y^2 - L^2)/2, G = (x, y), V = m ga y. The same default start, so
 * the two programs can be compared row by row. Output:
 * t,q1,q2,v1,v2,lambda1,max_abs_c,E,switches. */
#include <math.h>

#include "mbs_cli.h"
#include "mechanisms.h"
#include "programs.h"

#define NFLAGS 5

typedef struct args {
  mech_pendulum p;
  double q0[2], v0[2];
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates the planar pendulum in Cartesian coordinates through the mechanical\n"
    "front-end (m q'' = (0, -m ga) - lambda q, 0 = (x^2 + y^2 - L^2)/2) and writes CSV:\n"
    "t,q1,q2,v1,v2,lambda1,max_abs_c,E,switches. Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.p = {.L = 1.0, .m = 1.0, .ga = 9.81},
              .q0 = {NAN, NAN},
              .v0 = {0.0, 0.0},
              .run = mbs_run_defaults()};
  const cli_flag model_flags[NFLAGS] = {
      {"L", CLI_POSITIVE, &a->p.L, NULL, 0, "rod length"},
      {"m", CLI_POSITIVE, &a->p.m, NULL, 0, "mass"},
      {"ga", CLI_REAL, &a->p.ga, NULL, 0, "gravitational acceleration"},
      {"q0", CLI_VECTOR, a->q0, NULL, 2, "start X,Y (default L sin 0.5, -L cos 0.5)"},
      {"v0", CLI_VECTOR, a->v0, NULL, 2, "start velocity VX,VY"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  if (isnan(a->q0[0])) { /* the default start depends on L: 0.5 rad from the bottom, at rest */
    a->q0[0] = a->p.L * sin(0.5);
    a->q0[1] = -a->p.L * cos(0.5);
  }
  if (a->q0[0] == 0.0 && a->q0[1] == 0.0)
    return cli_fail(err, errlen,
                    "--q0: the start is at the pivot, where the constraint's "
                    "jacobian (x, y) vanishes");
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  mech_pendulum_system(&sys, &a->p);
  const mbs_program prog = {"pendulum_mbs", &sys, a->q0, a->v0};
  return mbs_execute_to(&prog, &a->run, sink);
}

const cli_def pendulum_mbs_def = {"pendulum_mbs", summary, CLI_LAYOUT(args), parse_args, run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&pendulum_mbs_def, argc, argv); }
#endif
