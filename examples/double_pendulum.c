/* SPDX-License-Identifier: GPL-3.0-or-later */
/* double_pendulum: two point masses on two massless rods in Cartesian coordinates through the
 * mechanical front-end (<stabdae/mbs.h>): q = (x1, y1, x2, y2), M = diag(m1, m1, m2, m2),
 * c = ((|p1|^2 - L1^2)/2, (|p2 - p1|^2 - L2^2)/2), V = ga (m1 y1 + m2 y2).
 *
 * The default start, at rest with the arms at 2.0 and 2.5 rad from the downward vertical (both
 * above the horizontal), has the energy ga (m1 y1 + m2 y2) = 16.0 for unit lengths and masses,
 * above 9.81, the potential with the inner arm straight up and the outer one hanging: either
 * arm can go over the top, the regime where the double pendulum is chaotic (README.md shows
 * two starts 1e-9 apart separating). Output: t,q1..q4,v1..v4,lambda1,lambda2,max_abs_c,E,
 * switches. */
#include <math.h>

#include "mbs_cli.h"
#include "mechanisms.h"
#include "programs.h"

#define NFLAGS 7

typedef struct args {
  mech_double_pendulum p;
  double theta0[2], omega0[2];
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates a double pendulum in Cartesian coordinates through the mechanical front-end\n"
    "(two constraints: the rods L1 and L2) and writes CSV:\n"
    "t,q1,q2,q3,q4,v1,v2,v3,v4,lambda1,lambda2,max_abs_c,E,switches.\n"
    "Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.p = {1.0, 1.0, 1.0, 1.0, 9.81},
              .theta0 = {2.0, 2.5},
              .omega0 = {0.0, 0.0},
              .run = mbs_run_defaults()};
  const cli_flag model_flags[NFLAGS] = {
      {"L1", CLI_POSITIVE, &a->p.L1, NULL, 0, "inner rod length"},
      {"L2", CLI_POSITIVE, &a->p.L2, NULL, 0, "outer rod length"},
      {"m1", CLI_POSITIVE, &a->p.m1, NULL, 0, "inner mass"},
      {"m2", CLI_POSITIVE, &a->p.m2, NULL, 0, "outer mass"},
      {"ga", CLI_REAL, &a->p.ga, NULL, 0, "gravitational acceleration"},
      {"theta0", CLI_VECTOR, a->theta0, NULL, 2, "start angles a1,a2 from the downward vertical"},
      {"omega0", CLI_VECTOR, a->omega0, NULL, 2, "start angular rates w1,w2"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  double q[4], v[4];
  mech_double_pendulum_system(&sys, &a->p);
  mech_double_pendulum_state(&a->p, a->theta0, a->omega0, q, v);
  const mbs_program prog = {"double_pendulum", &sys, q, v};
  return mbs_execute_to(&prog, &a->run, sink);
}

const cli_def double_pendulum_def = {"double_pendulum", summary, CLI_LAYOUT(args),
                                     parse_args,        run,     NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&double_pendulum_def, argc, argv); }
#endif
