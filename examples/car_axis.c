/* SPDX-License-Identifier: GPL-3.0-or-later */
/* car_axis: the car axis of the Test Set for IVP Solvers (problem caraxis; Hairer and Wanner,
 * Solving ODEs II, VII.7) through the mechanical front-end (<stabdae/mbs.h>): q = (xl, yl,
 * xr, yr), the ends of an axis of length L on two springs, the left one to the ground and the
 * right one to a wheel rolling over a bump, yb = r sin(w t); two constraints, one of them
 * moving with the wheel (models/benchmarks.h has the equations). The masses k = mass eps^2/2
 * on springs of unit stiffness oscillate at 1/sqrt(k) = 44.7 rad/s, 4.5 times the road's
 * w = 10: the default step T = 0.001 resolves both (44.7 T = 0.045; the state at t = 3 is then
 * within 3e-4 in q, 2e-2 in v of the Test Set's, order 2). The moving wheel makes the forces
 * depend on t: no potential, so the default map is the midpoint rule and dgrad, dg4, dg6 are
 * refused by the library. The multipliers are minus the Test Set's (k v' = f + G^T lambda
 * there). Output: t,q1..q4,v1..v4,lambda1,lambda2,max_abs_c,E (the kinetic energy),switches. */
#include "benchmarks.h"
#include "mbs_cli.h"

#define NFLAGS 7

typedef struct args {
  bench_car_axis p;
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates the Test Set's car axis (caraxis, Hairer-Wanner II VII.7): an axis on two\n"
    "springs, the right one on a wheel over a bump, through the mechanical front-end; writes\n"
    "CSV: t,q1..q4 (xl,yl,xr,yr),v1..v4,lambda1,lambda2 (minus the Test Set's),max_abs_c,\n"
    "E (kinetic),switches. Defaults: tf 3, T 0.001 (the springs' period is 0.14), map midpoint\n"
    "(no potential: the road moves; dgrad, dg4, dg6 are refused). Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.p = bench_car_axis_default(), .run = mbs_run_defaults()};
  a->run.tf = 3.0;
  a->run.map = sdae_map_midpoint;
  const cli_flag model_flags[NFLAGS] = {
      {"epsm", CLI_POSITIVE, &a->p.eps, NULL, 0, "the Test Set's eps: masses k = mass eps^2/2"},
      {"mass", CLI_POSITIVE, &a->p.mass, NULL, 0, "the mass M"},
      {"L", CLI_POSITIVE, &a->p.L, NULL, 0, "axis length"},
      {"L0", CLI_POSITIVE, &a->p.L0, NULL, 0, "springs' rest length"},
      {"r", CLI_NONNEG, &a->p.r, NULL, 0, "the bump's height (< L)"},
      {"w", CLI_REAL, &a->p.w, NULL, 0, "the bump's frequency"},
      {"g", CLI_REAL, &a->p.g, NULL, 0, "gravitational acceleration"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  if (!(a->p.r < a->p.L))
    return cli_fail(err, errlen, "--r: %g must be below --L, %g (the wheel at distance L)", a->p.r,
                    a->p.L);
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  double q[4], v[4];
  bench_car_axis_system(&sys, &a->p);
  bench_car_axis_initial(&a->p, q, v);
  const mbs_program prog = {"car_axis", &sys, q, v};
  return mbs_execute_to(&prog, &a->run, sink);
}

const cli_def car_axis_def = {"car_axis", summary, CLI_LAYOUT(args), parse_args, run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&car_axis_def, argc, argv); }
#endif
