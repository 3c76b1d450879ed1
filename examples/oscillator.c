/* SPDX-License-Identifier: GPL-3.0-or-later */
/* oscillator: the nonlinear oscillator of the paper's Section IV integrated with stabdae.
 *
 * A mass on a cubic spring, damped, held on the floor Y = 0 by the constraint force. The
 * defaults are the paper's setup (k 2, d 0.03, m 1, delta 2, epsilon 1, T 0.001, tf 50, start
 * (0.1, 0.6, 0, 0) off the floor, scheme 15, the paper's map); the output is one CSV row per
 * --every steps: t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,W,newton_iters. Y -> 0 shows the constraint
 * being restored; E is dissipated for d > 0 and W conserved on the manifold for d = 0. */
#include <math.h>
#include <stdio.h>

#include "certify_cli.h"
#include "cli.h"
#include "oscillator_model.h"
#include "programs.h"

/* every map of the library: the model gives q0, q0_jac, H, grad_H, S, hess_H and, as its user
 * map, the paper's Section IV map */
static const char *const map_choices[] = {"euler",     "midpoint",  "dgrad", "user", "dg4", "dg6",
                                          "midpoint4", "midpoint6", "rk4",   "rk8",  NULL};
static const char *const q_choices[] = {"corrected", "paper", NULL};

typedef struct osc_args {
  osc_params p;
  int q;
  double x0[4];
  cli_run run;
  cli_certify cert;
  cli_flag flags[6 + CLI_RUN_NFLAGS + CERT_NFLAGS];
  size_t nflags;
} osc_args;

static const char summary[] =
    "Integrates the constrained nonlinear oscillator of the paper's Section IV\n"
    "(Xdd = (-k X^3 - d Xdot)/m, Ydd = -ga - lambda/m, 0 = Y) and writes CSV:\n"
    "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,W,newton_iters. Steps: ceil(tf/T - 1e-9).";

/* Defaults, the flag table, parsing and validation; separate from main for tests and fuzzing. */
static int osc_parse_args(int argc, char *const *argv, void *args, char *err, size_t errlen) {
  osc_args *a = args;
  *a = (osc_args){.p = {.k = 2.0, .d = 0.03, .m = 1.0, .ga = 9.81, .q = OSC_Q_CORRECTED},
                  .q = 0,
                  .x0 = {0.1, 0.6, 0.0, 0.0},
                  .run = {.delta = 2.0,
                          .eps = 1.0,
                          .T = 0.001,
                          .tf = 50.0,
                          .scheme = 1,
                          .map = sdae_map_user,
                          .every = 1},
                  .cert = {.grid = 41, .lo = {-0.7, 0.0, -0.9, -0.9}, .hi = {0.7, 0.0, 0.9, 0.9}}};
  const cli_flag model_flags[6] = {
      {"k", CLI_REAL, &a->p.k, NULL, 0, "spring constant (force -k X^3)"},
      {"d", CLI_REAL, &a->p.d, NULL, 0, "damping (force -d Xdot)"},
      {"m", CLI_POSITIVE, &a->p.m, NULL, 0, "mass"},
      {"ga", CLI_REAL, &a->p.ga, NULL, 0, "gravitational acceleration"},
      {"x0", CLI_VECTOR, a->x0, NULL, 4, "start X,Y,Xdot,Ydot"},
      {"q", CLI_CHOICE, &a->q, q_choices, 0, "Q of Section IV: derived, or as printed"},
  };
  for (size_t i = 0; i < 6; i++) a->flags[i] = model_flags[i];
  a->nflags = 6 + cli_run_flags(a->flags + 6, &a->run, map_choices,
                                "mu-map: dgrad = Gonzalez with H = W, "
                                "user = the paper's Section IV map");
  a->nflags += cli_certify_flags(a->flags + a->nflags, &a->cert,
                                 "box of (xi, mu), the paper's B with xi2 fixed "
                                 "[xi1=-0.7:0.7,xi2=0:0,mu1=-0.9:0.9,mu2=-0.9:0.9]");
  int rc = cli_parse(argc, argv, a->flags, a->nflags, err, errlen);
  if (rc != CLI_OK) return rc;
  a->p.q = a->q == 0 ? OSC_Q_CORRECTED : OSC_Q_PAPER;
  if (cli_certify_finish(&a->cert, err, errlen) != CLI_OK) return CLI_BAD;
  return cli_run_finish(&a->run, err, errlen) ? CLI_BAD : CLI_OK;
}

static int osc_row(cli_row_out *o, double t, const double *xi, const double *mu, void *ctx,
                   const char **why) {
  const osc_params *p = ctx;
  double x[4];
  (void)why;
  osc_from_coords(p, xi, mu, x);
  const double v[11] = {
      t, x[0], x[1], x[2], x[3], xi[0], xi[1], mu[0], mu[1], osc_energy(p, x), osc_W(p, mu)};
  return cli_emit(o, v, 11, fabs(xi[0]), v[9]); /* xi1 = Y, the constraint */
}

static void osc_setup(osc_args *a, sdae_model *model, sdae_options *opt) {
  osc_model(model, &a->p);
  sdae_options_default(opt);
  cli_run_options(&a->run, opt);
  opt->map = a->run.map;
}

static void osc_certify_setup(void *args, cli_certify_setup *c) {
  osc_args *a = args;
  osc_setup(a, &c->model, &c->options);
  cli_certify_box(&a->cert, c);
}

static int osc_run(void *args, cli_sink *sink) {
  osc_args *a = args;
  sdae_model model;
  sdae_options opt;
  double xi[2], mu[2];
  osc_setup(a, &model, &opt);
  if (!sink && a->cert.certify) return cli_certify_run("oscillator", &a->cert, &model, &opt);
  if (!sink && a->cert.check_model) {
    sdae_dae dae;
    osc_dae_spec(&dae, &a->p);
    return cli_check_model_run("oscillator", &a->cert, &model, &dae);
  }
  osc_to_coords(&a->p, a->x0, xi, mu);
  const cli_program prog = {"oscillator", "t,X,Y,Xdot,Ydot,xi1,xi2,mu1,mu2,E,W,newton_iters",
                            &model,       &opt,
                            xi,           mu,
                            osc_row,      &a->p};
  return cli_execute_to(&prog, &a->run, sink);
}

const cli_def oscillator_def = {"oscillator",   summary, CLI_LAYOUT(osc_args),
                                osc_parse_args, osc_run, osc_certify_setup};

#ifndef CLI_NO_MAIN
int main(int argc, char **argv) { return cli_main(&oscillator_def, argc, argv); }
#endif
