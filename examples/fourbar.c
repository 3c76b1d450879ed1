/* SPDX-License-Identifier: GPL-3.0-or-later */
/* fourbar: a four-bar linkage, a closed loop, through the mechanical front-end
 * (<stabdae/mbs.h>). Ground pivots A = (0, 0) and D = (d, 0), crank AB (a), coupler BC (b),
 * rocker CD (e); q = (Bx, By, Cx, Cy) with point masses mB at B and mC at C, three constraints
 * |B| = a, |C - B| = b, |C - D| = e: one degree of freedom, the crank angle atan2(By, Bx).
 *
 * The default geometry a = 1, b = 4, e = 3, d = 4.5 is a Grashof crank-rocker (s + l = 1 + 4.5
 * = 5.5 <= p + q = 4 + 3 = 7, the crank the shortest link): the loop closes at every crank
 * angle. The default start, crank at 0 turning at 5 rad/s under gravity 9.81 with unit
 * masses, has the energy 50.18, above the potential's maximum 38.01 along the loop (where the
 * crank is at 1.36 rad): the crank never stops and turns at 3.7 to 8.7 rad/s, a full turn in
 * less than 1.7 s. Output: t,q1..q4,v1..v4,lambda1..lambda3,max_abs_c,E,switches. */
#include <math.h>

#include "mbs_cli.h"
#include "mechanisms.h"
#include "programs.h"

#define NFLAGS 10

/* --derivatives: the mechanism's derivative callbacks given, or left to the front-end's
 * differences (jacobian, jacobian_dot, mass_dot_v and constraint_t_dot left out) */
static const char *const derivative_choices[] = {"exact", "differences", NULL};

typedef struct args {
  mech_fourbar p;
  double theta0, omega0;
  int derivatives;   /* an index into derivative_choices */
  double q[4], v[4]; /* the start, from theta0 and omega0 */
  cli_run run;
  cli_flag flags[NFLAGS + CLI_RUN_NFLAGS];
  size_t nflags;
} args;

static const char summary[] =
    "Integrates a four-bar linkage (crank AB, coupler BC, rocker CD, ground pivots A = (0,0)\n"
    "and D = (d,0)) in the coordinates of B and C through the mechanical front-end and\n"
    "writes CSV: t,q1..q4 (Bx,By,Cx,Cy),v1..v4,lambda1..lambda3,max_abs_c,E,switches.\n"
    "The geometry must be a Grashof crank-rocker. Steps: ceil(tf/T - 1e-9).";

static int parse_args(int argc, char *const *argv, void *vargs, char *err, size_t errlen) {
  args *a = vargs;
  *a = (args){.p = {1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81},
              .theta0 = 0.0,
              .omega0 = 5.0,
              .run = mbs_run_defaults()};
  const cli_flag model_flags[NFLAGS] = {
      {"a", CLI_POSITIVE, &a->p.a, NULL, 0, "crank length |AB|"},
      {"b", CLI_POSITIVE, &a->p.b, NULL, 0, "coupler length |BC|"},
      {"e", CLI_POSITIVE, &a->p.e, NULL, 0, "rocker length |CD|"},
      {"d", CLI_POSITIVE, &a->p.d, NULL, 0, "ground length |AD|"},
      {"mB", CLI_POSITIVE, &a->p.mB, NULL, 0, "mass at B"},
      {"mC", CLI_POSITIVE, &a->p.mC, NULL, 0, "mass at C"},
      {"ga", CLI_REAL, &a->p.ga, NULL, 0, "gravitational acceleration"},
      {"theta0", CLI_REAL, &a->theta0, NULL, 0, "start crank angle"},
      {"omega0", CLI_REAL, &a->omega0, NULL, 0, "start crank speed"},
      {"derivatives", CLI_CHOICE, &a->derivatives, derivative_choices, 0,
       "exact: dc/dq and the derivatives along the motion given; differences: left out "
       "(jacobian, jacobian_dot, mass_dot_v, constraint_t_dot), the front-end differentiates"},
  };
  int rc = mbs_parse(argc, argv, model_flags, NFLAGS, a->flags, &a->nflags, &a->run, err, errlen);
  if (rc != CLI_OK) return rc;
  if (!mech_fourbar_crank_rocker(&a->p))
    return cli_fail(err, errlen,
                    "--a --b --e --d: %g, %g, %g, %g is not a Grashof crank-rocker "
                    "(the crank must be the shortest link and s + l <= p + q)",
                    a->p.a, a->p.b, a->p.e, a->p.d);
  /* a crank-rocker closes at every angle but at its change points (s + l = p + q) */
  if (mech_fourbar_state(&a->p, a->theta0, a->omega0, a->q, a->v))
    return cli_fail(err, errlen, "--theta0: the loop does not close at %g (a dead point)",
                    a->theta0);
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int run(void *vargs, cli_sink *sink) {
  args *a = vargs;
  sdae_mbs sys;
  mech_fourbar_system(&sys, &a->p);
  if (a->derivatives == 1)
    sys.jacobian = NULL, sys.jacobian_dot = NULL, sys.mass_dot_v = NULL,
    sys.constraint_t_dot = NULL;
  const mbs_program prog = {"fourbar", &sys, a->q, a->v};
  return mbs_execute_to(&prog, &a->run, sink);
}

const cli_def fourbar_def = {"fourbar", summary, CLI_LAYOUT(args), parse_args, run, NULL};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&fourbar_def, argc, argv); }
#endif
