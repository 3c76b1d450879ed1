/* SPDX-License-Identifier: GPL-3.0-or-later */
/* bricard: Bricard's mechanism, the IFToMM benchmark A04, through the mechanical front-end
 * (<stabdae/mbs.h>) with all its constraints (models/bricard.h): five rods of 1 m and 1 kg in
 * a closed loop of six revolute joints, natural coordinates (four points and four unit axes,
 * 24), 24 constraints of rank 23 (sdae_mbs.rank: the front-end chooses 23 independent ones at
 * every step), one degree of freedom, from rest under gravity along -y. Every constraint stays
 * at rounding (max_abs_c is over all 24); dgrad conserves the energy. Output:
 * t,q1..q24,v1..v24,lambda1..lambda24 (the least-norm multipliers),max_abs_c,E,switches. */
#include "bricard.h"
#include "mbs_cli.h"

#define NFLAGS 2

typedef struct args {
  mech_bricard p;
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates Bricard's mechanism (IFToMM benchmark A04: five rods, six revolute joints, 24\n"
    "constraints of rank 23 in natural coordinates) through the mechanical front-end and\n"
    "writes CSV: t,q1..q24,v1..v24,lambda1..lambda24,max_abs_c,E,switches. Defaults: tf 10,\n"
    "T 1e-3, map dgrad (the energy conserved).\n"
    "Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.run = mbs_run_defaults(), .p = mech_bricard_benchmark()};
  a->run.tf = 10.0;
  a->run.T = 1e-3;
  const cli_flag model_flags[NFLAGS] = {
      {"m", CLI_POSITIVE, &a->p.m, NULL, 0, "each rod's mass"},
      {"ga", CLI_NONNEG, &a->p.ga, NULL, 0, "gravity along -y"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  double q[MECH_BRICARD_NQ], v[MECH_BRICARD_NQ];
  mech_bricard_system(&sys, &a->p);
  mech_bricard_start(q, v);
  const mbs_program prog = {"bricard", &sys, q, v};
  return mbs_execute_to(&prog, &a->run, sink);
}

const cli_def bricard_def = {"bricard", summary, CLI_LAYOUT(args), parse_args, run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&bricard_def, argc, argv); }
#endif
