/* SPDX-License-Identifier: GPL-3.0-or-later */
/* pendulum: the planar pendulum (index 3) integrated with stabdae.
 *
 * A mass m on a rod of length L: the constraint X^2 + Y^2 = L^2 is restored from any start
 * away from the pivot, and on it the angle follows theta'' = -(ga/L) sin theta. Coordinates
 * xi = (h, L_f h), mu = (theta, r^2 theta') (see models/pendulum_model.c). Output, one CSV row
 * per --every steps: t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,newton_iters. */
#include <math.h>
#include <stdio.h>

#include "certify_cli.h"
#include "cli.h"
#include "pendulum_model.h"
#include "programs.h"

/* the model has no user map (user_phi) */
static const char *const map_choices[] = {"euler",     "midpoint",  "dgrad", "dg4", "dg6",
                                          "midpoint4", "midpoint6", "rk4",   "rk8", NULL};

typedef struct pend_args {
  pend_params p;
  double x0[4];
  cli_run run;
  cli_certify cert;
  cli_flag flags[4 + CLI_RUN_NFLAGS + CERT_NFLAGS];
  size_t nflags;
} pend_args;

static const char summary[] =
    "Integrates the planar pendulum (Xdd = -lambda X/m, Ydd = -ga - lambda Y/m,\n"
    "0 = (X^2 + Y^2 - L^2)/2) and writes CSV:\n"
    "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,newton_iters. Steps: ceil(tf/T - 1e-9).";

static int pend_parse_args(int argc, char *const *argv, void *args, char *err, size_t errlen) {
  pend_args *a = args;
  *a = (pend_args){
      .p = {1.0, 1.0, 9.81},
      .x0 = {NAN, NAN, 0.0, 0.0},
      .run = {.delta = 2.0,
              .eps = 1.0,
              .T = 0.001,
              .tf = 10.0,
              .scheme = 1,
              .map = sdae_map_dgrad,
              .every = 1},
      .cert = {.grid = 41, .lo = {-0.1, -0.5, -3.14159, -2.0}, .hi = {0.1, 0.5, 3.14159, 2.0}}};
  const cli_flag model_flags[4] = {
      {"L", CLI_POSITIVE, &a->p.L, NULL, 0, "rod length"},
      {"m", CLI_POSITIVE, &a->p.m, NULL, 0, "mass"},
      {"ga", CLI_REAL, &a->p.ga, NULL, 0, "gravitational acceleration"},
      {"x0", CLI_VECTOR, a->x0, NULL, 4,
       "start X,Y,Xdot,Ydot (default L sin 0.5, -L cos 0.5, 0, 0)"},
  };
  for (size_t i = 0; i < 4; i++) a->flags[i] = model_flags[i];
  a->nflags = 4 + cli_run_flags(a->flags + 4, &a->run, map_choices,
                                "mu-map: dgrad = Gonzalez with the pendulum's energy");
  a->nflags += cli_certify_flags(a->flags + a->nflags, &a->cert,
                                 "box of (xi, mu) "
                                 "[xi1=-0.1:0.1,xi2=-0.5:0.5,mu1=-3.14159:3.14159,mu2=-2:2]");
  int rc = cli_parse(argc, argv, a->flags, a->nflags, err, errlen);
  if (rc != CLI_OK) return rc;
  if (isnan(a->x0[0])) { /* the default start depends on L: 0.5 rad from the bottom, at rest */
    a->x0[0] = a->p.L * sin(0.5);
    a->x0[1] = -a->p.L * cos(0.5);
  }
  if (a->x0[0] == 0.0 && a->x0[1] == 0.0) {
    snprintf(err, errlen,
             "--x0: the start is at the pivot (X = Y = 0), where the angle is "
             "undefined");
    return CLI_BAD;
  }
  if (cli_certify_finish(&a->cert, err, errlen) != CLI_OK) return CLI_BAD;
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int pend_row(cli_row_out *o, double t, const double *xi, const double *mu, void *ctx,
                    const char **why) {
  const pend_params *p = ctx;
  double x[4];
  if (pend_from_coords(p, xi, mu, x)) {
    *why = "the state left the chart (xi1 <= -L^2/2: the mass would be at the pivot)";
    return 1;
  }
  const double v[10] = {t, x[0], x[1], x[2], x[3], xi[0], xi[1], mu[0], mu[1], pend_energy(p, x)};
  return cli_emit(o, v, 10, fabs(xi[0]), v[9]); /* xi1 = (X^2 + Y^2 - L^2)/2 */
}

static void pend_setup(pend_args *a, sdae_model *model, sdae_options *opt) {
  pend_model(model, &a->p);
  sdae_options_default(opt);
  cli_run_options(&a->run, opt);
  opt->map = a->run.map;
}

static void pend_certify_setup(void *args, cli_certify_setup *c) {
  pend_args *a = args;
  pend_setup(a, &c->model, &c->options);
  cli_certify_box(&a->cert, c);
}

static int pend_run(void *args, cli_sink *sink) {
  pend_args *a = args;
  sdae_model model;
  sdae_options opt;
  double xi[2], mu[2];
  pend_setup(a, &model, &opt);
  if (!sink && a->cert.certify) return cli_certify_run("pendulum", &a->cert, &model, &opt);
  if (!sink && a->cert.check_model) {
    sdae_dae dae;
    pend_dae_spec(&dae, &a->p);
    return cli_check_model_run("pendulum", &a->cert, &model, &dae);
  }
  pend_to_coords(&a->p, a->x0, xi, mu); /* the pivot was refused by the parser */
  const cli_program prog = {
      "pendulum", "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,newton_iters", &model, &opt, xi, mu, pend_row,
      &a->p};
  return cli_execute_to(&prog, &a->run, sink);
}

const cli_def pendulum_def = {"pendulum",      summary,  CLI_LAYOUT(pend_args),
                              pend_parse_args, pend_run, pend_certify_setup};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&pendulum_def, argc, argv); }
#endif
