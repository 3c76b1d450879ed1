/* SPDX-License-Identifier: GPL-3.0-or-later */
/* slider_crank: the slider crank of SUNDIALS' idaSlCrank_dns (after Haug) through the
 * mechanical front-end (<stabdae/mbs.h>): q = (theta, x, phi), crank angle, slider position
 * and connecting-rod angle, two constraints (the crank a and the rod 1 close the loop at the
 * slider), a spring-damper between the crank's and the rod's midpoints and a constant force F
 * (models/benchmarks.h has the equations). From rest at theta = pi/2, the spring compressed
 * to 0.43 (l0 = 1), the spring and F swing the crank to theta = -1.43 near t = 5 and back to
 * 1.28 at t = 10 (as in idaSlCrank_dns's output), the damper taking energy out. The default
 * step T = 0.001 puts the state at t = 10 within about 3e-8 (from the differences of runs at
 * T and T/2, order 2). The spring and F are a potential and the damper a Rayleigh damping,
 * so the default map dgrad never increases the energy v^T M v / 2 + V.
 * Output: t,q1..q3,v1..v3,lambda1,lambda2,max_abs_c,E,switches. */
#include "benchmarks.h"
#include "mbs_cli.h"

#define NFLAGS 8

typedef struct args {
  bench_slider_crank p;
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates SUNDIALS' slider crank (idaSlCrank_dns, after Haug): q = (crank angle, slider\n"
    "position, rod angle), a spring-damper and a constant force, through the mechanical\n"
    "front-end; writes CSV: t,q1..q3,v1..v3,lambda1,lambda2,max_abs_c,E,switches.\n"
    "Defaults: tf 10 and T 0.001 (an error near 3e-8 at t = 10), map dgrad (the energy\n"
    "never increases). Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.p = bench_slider_crank_default(), .run = mbs_run_defaults()};
  const cli_flag model_flags[NFLAGS] = {
      {"a", CLI_POSITIVE, &a->p.a, NULL, 0, "crank length (< 1, the rod's)"},
      {"J1", CLI_POSITIVE, &a->p.J1, NULL, 0, "crank moment of inertia"},
      {"m2", CLI_POSITIVE, &a->p.m2, NULL, 0, "connecting rod mass"},
      {"J2", CLI_POSITIVE, &a->p.J2, NULL, 0, "connecting rod moment of inertia"},
      {"k", CLI_NONNEG, &a->p.k, NULL, 0, "spring constant"},
      {"c", CLI_NONNEG, &a->p.c, NULL, 0, "damper constant"},
      {"l0", CLI_NONNEG, &a->p.l0, NULL, 0, "spring free length"},
      {"F", CLI_REAL, &a->p.F, NULL, 0, "constant force"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  if (!(a->p.a < 1.0))
    return cli_fail(err, errlen,
                    "--a: %g does not close the loop (the crank must be shorter "
                    "than the rod, 1)",
                    a->p.a);
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  double q[3], v[3];
  bench_slider_crank_system(&sys, &a->p);
  bench_slider_crank_initial(&a->p, q, v);
  const mbs_program prog = {"slider_crank", &sys, q, v};
  return mbs_execute_to(&prog, &a->run, sink);
}

const cli_def slider_crank_def = {"slider_crank", summary, CLI_LAYOUT(args), parse_args, run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&slider_crank_def, argc, argv); }
#endif
