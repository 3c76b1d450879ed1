/* SPDX-License-Identifier: GPL-3.0-or-later */
/* andrews: Andrews' squeezing mechanism, problem andrews of the Test Set for IVP Solvers
 * (Hairer and Wanner, Solving ODEs II, VII.7), through the mechanical front-end
 * (<stabdae/mbs.h>): seven rigid bodies, q their seven angles (beta, theta, gamma, phi, delta,
 * omega, epsilon), six constraints closing three loops, a configuration-dependent M(q) and
 * velocity terms in the force (models/benchmarks.h). The motor's constant torque mom drives
 * beta against a stiff spring c0: beta turns 2.5 times in the 0.03 s of the problem, the rates
 * reaching 1.4e3 rad/s, so the default step is T = 1e-5 (3000 steps; the state at t = 0.03 is
 * then within 5.4e-5 in q, 2.1e-2 in v of the Test Set's, order 2). The torque and the spring
 * are a potential, -mom beta + c0 (l - l0)^2/2: the default map dgrad conserves the energy
 * v^T M v / 2 + V. Output: t,q1..q7,v1..v7,lambda1..lambda6,max_abs_c,E,switches. */
#include "benchmarks.h"
#include "mbs_cli.h"

#define NFLAGS 2

typedef struct args {
  bench_andrews p;
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates Andrews' squeezing mechanism (the Test Set's andrews, Hairer-Wanner II VII.7;\n"
    "seven bodies, q = their angles, six constraints) through the mechanical front-end and\n"
    "writes CSV: t,q1..q7,v1..v7,lambda1..lambda6,max_abs_c,E,switches. Defaults: tf 0.03,\n"
    "T 1e-5 (rates up to 1.4e3 rad/s), map dgrad (the energy conserved).\n"
    "Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.run = mbs_run_defaults()};
  bench_andrews_default(&a->p);
  a->run.tf = 0.03;
  a->run.T = 1e-5;
  const cli_flag model_flags[NFLAGS] = {
      {"mom", CLI_REAL, &a->p.mom, NULL, 0, "the motor's driving torque"},
      {"c0", CLI_NONNEG, &a->p.c0, NULL, 0, "the spring's stiffness"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  double q[7], v[7];
  bench_andrews_system(&sys, &a->p);
  bench_andrews_initial(q, v);
  const mbs_program prog = {"andrews", &sys, q, v};
  return mbs_execute_to(&prog, &a->run, sink);
}

const cli_def andrews_def = {"andrews", summary, CLI_LAYOUT(args), parse_args, run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&andrews_def, argc, argv); }
#endif
