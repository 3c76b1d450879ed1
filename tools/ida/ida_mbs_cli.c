/* SPDX-License-Identifier: GPL-3.0-or-later */
/* ida_mbs: SUNDIALS IDA solution of a mechanism of the examples (ida_mbs.h), the independent
 * reference of the mechanical programs, from the same callbacks, parameters and start.
 *
 *   ida_mbs MODEL [--form index1|ggl] [--rtol R] [--atol A] [--tf TF] [--every-dt DT]
 *                 [--max-steps N] [--out FILE]
 *
 * CSV: t,q1..,v1..,lambda1..,max_abs_c (the mechanical programs' column names) every DT from
 * t = 0, tf included, then '#' lines with IDA's counters. Bad input: one line on stderr, exit 2,
 * no file. IDA failure: the rows so far are kept, exit 1, one line on stderr. A new model is a
 * setup function and one line of the registry. */
#include "ida_mbs.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "benchmarks.h"
#include "cli.h"
#include "mechanisms.h"

#define PROG "ida_mbs"

/* ---- the registry ---------------------------------------------------------------------------- */

/* Room for any model's parameters (the mechanism keeps a pointer to them) and its start. */
typedef union model_params {
  mech_pendulum pendulum;
  mech_double_pendulum double_pendulum;
  mech_fourbar fourbar;
  bench_slider_crank slider_crank;
  bench_car_axis car_axis;
  bench_andrews andrews;
} model_params;
enum { MAX_Q = 32 };

/* The examples' default parameters and start (pendulum_mbs.c, double_pendulum.c, fourbar.c). */
static void pendulum(model_params *p, sdae_mbs *sys, double *q0, double *v0) {
  p->pendulum = (mech_pendulum){.L = 1.0, .m = 1.0, .ga = 9.81};
  mech_pendulum_system(sys, &p->pendulum);
  q0[0] = sin(0.5), q0[1] = -cos(0.5);
  v0[0] = v0[1] = 0.0;
}

static void double_pendulum(model_params *p, sdae_mbs *sys, double *q0, double *v0) {
  const double theta0[2] = {2.0, 2.5}, omega0[2] = {0.0, 0.0};
  p->double_pendulum = (mech_double_pendulum){1.0, 1.0, 1.0, 1.0, 9.81};
  mech_double_pendulum_system(sys, &p->double_pendulum);
  mech_double_pendulum_state(&p->double_pendulum, theta0, omega0, q0, v0);
}

static void fourbar(model_params *p, sdae_mbs *sys, double *q0, double *v0) {
  p->fourbar = (mech_fourbar){1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81};
  mech_fourbar_system(sys, &p->fourbar);
  mech_fourbar_state(&p->fourbar, 0.0, 5.0, q0, v0); /* a crank-rocker closes at 0 */
}

/* the standard benchmarks (benchmarks.h): the published constants and starts */
static void slider_crank(model_params *p, sdae_mbs *sys, double *q0, double *v0) {
  p->slider_crank = bench_slider_crank_default();
  bench_slider_crank_system(sys, &p->slider_crank);
  bench_slider_crank_initial(&p->slider_crank, q0, v0);
}

static void car_axis(model_params *p, sdae_mbs *sys, double *q0, double *v0) {
  p->car_axis = bench_car_axis_default();
  bench_car_axis_system(sys, &p->car_axis);
  bench_car_axis_initial(&p->car_axis, q0, v0);
}

static void andrews(model_params *p, sdae_mbs *sys, double *q0, double *v0) {
  bench_andrews_default(&p->andrews);
  bench_andrews_system(sys, &p->andrews);
  bench_andrews_initial(q0, v0);
}

static const struct model_entry {
  const char *name;
  void (*setup)(model_params *p, sdae_mbs *sys, double *q0, double *v0);
  double tf, dt; /* the default end time and output spacing: the example program's */
} registry[] = {
    {"pendulum", pendulum, 10.0, 0.01}, {"double_pendulum", double_pendulum, 10.0, 0.01},
    {"fourbar", fourbar, 10.0, 0.01},   {"slider_crank", slider_crank, 10.0, 0.01},
    {"car_axis", car_axis, 3.0, 0.01},  {"andrews", andrews, 0.03, 1e-4},
};
#define NMODELS (sizeof registry / sizeof registry[0])

/* ---- the command line ------------------------------------------------------------------------ */

static const char *const form_choices[] = {"index1", "ggl", NULL};

typedef struct args {
  const struct model_entry *model;
  int form; /* index into form_choices, the order of idambs_form */
  idaref_options opt;
  size_t max_steps;
  cli_run out; /* only out: the examples' output handling */
} args;

#define NFLAGS 7

static void flags_of(args *a, cli_flag *flags) {
  const cli_flag table[NFLAGS] = {
      {"form", CLI_CHOICE, &a->form, form_choices, 0,
       "index1: G v' + gamma = 0, lambda algebraic; ggl: Gear-Gupta-Leimkuhler, index 2"},
      {"rtol", CLI_POSITIVE, &a->opt.rtol, NULL, 0, "IDA's relative tolerance"},
      {"atol", CLI_POSITIVE, &a->opt.atol, NULL, 0, "IDA's absolute tolerance"},
      {"tf", CLI_NONNEG, &a->opt.tf, NULL, 0,
       "final time (default: the model's, 3 for car_axis, 0.03 for andrews, else 10)"},
      {"every-dt", CLI_POSITIVE, &a->opt.dt, NULL, 0,
       "output spacing (default 1e-4 for andrews, else 0.01); tf always written"},
      {"max-steps", CLI_COUNT, &a->max_steps, NULL, 0, "IDA steps per output interval"},
      {"out", CLI_PATH, &a->out.out, NULL, 0, "CSV file (default: stdout)"},
  };
  memcpy(flags, table, sizeof table);
}

static void usage(const cli_flag *flags) {
  char summary[512] = "SUNDIALS IDA solution of a mechanism; MODEL, the first argument, one of";
  for (size_t i = 0; i < NMODELS; i++) {
    strncat(summary, i ? ", " : " ", sizeof summary - strlen(summary) - 1);
    strncat(summary, registry[i].name, sizeof summary - strlen(summary) - 1);
  }
  strncat(summary, ".\nCSV: t,q1..,v1..,lambda1..,max_abs_c, then '#' lines with IDA's counters.",
          sizeof summary - strlen(summary) - 1);
  cli_usage(stdout, PROG " MODEL", summary, flags, NFLAGS);
}

static const struct model_entry *find_model(const char *name) {
  for (size_t i = 0; i < NMODELS; i++)
    if (strcmp(registry[i].name, name) == 0) return &registry[i];
  return NULL;
}

/* CLI_OK, CLI_HELP, or CLI_BAD with err set. */
static int parse_args(int argc, char **argv, args *a, cli_flag *flags, char *err, size_t len) {
  *a = (args){.opt = {.rtol = 1e-10, .atol = 1e-12, .tf = 10.0, .dt = 0.01}, .max_steps = 100000};
  flags_of(a, flags);
  for (int i = 1; i < argc; i++)
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) return CLI_HELP;
  if (argc < 2 || argv[1][0] == '-')
    return cli_fail(err, len, "the first argument must be the model (see --help)");
  if (!(a->model = find_model(argv[1])))
    return cli_fail(err, len, "unknown model '%s' (see --help)", argv[1]);
  a->opt.tf = a->model->tf, a->opt.dt = a->model->dt;
  return cli_parse(argc - 1, argv + 1, flags, NFLAGS, err, len);
}

/* ---- the run --------------------------------------------------------------------------------- */

typedef struct sink {
  FILE *f;
  const sdae_mbs *sys;
} sink;

static int write_row(double t, const double *q, const double *v, const double *lambda, void *ctx) {
  const sink *s = ctx;
  size_t nq = s->sys->n_q, nc = s->sys->n_c;
  int bad = fprintf(s->f, "%.17g", t) < 0;
  for (size_t i = 0; i < nq; i++) bad |= fprintf(s->f, ",%.17g", q[i]) < 0;
  for (size_t i = 0; i < nq; i++) bad |= fprintf(s->f, ",%.17g", v[i]) < 0;
  for (size_t i = 0; i < nc; i++) bad |= fprintf(s->f, ",%.17g", lambda[i]) < 0;
  return bad | (fprintf(s->f, ",%.17g\n", mech_max_abs_c(s->sys, t, q)) < 0);
}

static void write_header(FILE *f, const sdae_mbs *sys) {
  fputs("t", f);
  for (size_t i = 1; i <= sys->n_q; i++) fprintf(f, ",q%zu", i);
  for (size_t i = 1; i <= sys->n_q; i++) fprintf(f, ",v%zu", i);
  for (size_t i = 1; i <= sys->n_c; i++) fprintf(f, ",lambda%zu", i);
  fputs(",max_abs_c\n", f);
}

static void write_trailer(FILE *f, const idaref_result *res, int status) {
  idaref_write_stats(f, &res->stats);
  if (status == IDAREF_OK)
    fputs("# status: ok\n", f);
  else if (status == IDAREF_OUTPUT_FAILED)
    fputs("# status: output failed\n", f);
  else
    fprintf(f, "# status: %s at t = %.17g\n", res->flag_name, res->t_reached);
}

static int report_failure(const char *out, const idaref_result *res, int status) {
  if (status == IDAREF_OUTPUT_FAILED)
    fprintf(stderr, PROG ": writing %s failed at t = %.17g\n", out ? out : "stdout",
            res->t_reached);
  else
    fprintf(stderr, PROG ": %s failed with %s at t = %.17g%s%s\n", res->function, res->flag_name,
            res->t_reached, res->message[0] ? " -- " : "", res->message);
  return CLI_EXIT_FAILED;
}

static int execute(const args *a, const sdae_mbs *sys, const double *q0, const double *v0,
                   FILE *f) {
  sink s = {f, sys};
  idaref_result res;
  int status;
  write_header(f, sys);
  status = idambs_solve(sys, (idambs_form)a->form, 0.0, q0, v0, &a->opt, write_row, &s, &res);
  write_trailer(f, &res, status);
  if ((fflush(f) != 0 || ferror(f)) && status == IDAREF_OK) status = IDAREF_OUTPUT_FAILED;
  if (f != stdout && fclose(f) != 0 && status == IDAREF_OK) status = IDAREF_OUTPUT_FAILED;
  return status == IDAREF_OK ? CLI_EXIT_OK : report_failure(a->out.out, &res, status);
}

int main(int argc, char **argv) {
  args a;
  cli_flag flags[NFLAGS];
  char err[CLI_ERR_LEN] = "";
  model_params params;
  sdae_mbs sys;
  double q0[MAX_Q], v0[MAX_Q];
  FILE *f;
  int rc = parse_args(argc, argv, &a, flags, err, sizeof err);
  if (rc == CLI_HELP) {
    usage(flags);
    return CLI_EXIT_OK;
  }
  if (rc != CLI_OK) {
    fprintf(stderr, PROG ": %s\n", err);
    return CLI_EXIT_USAGE;
  }
  a.opt.max_steps = a.max_steps > 1000000000 ? 1000000000 : (long)a.max_steps;
  a.model->setup(&params, &sys, q0, v0);
  if (!(f = cli_open_output(&a.out, PROG))) return CLI_EXIT_USAGE;
  return execute(&a, &sys, q0, v0, f);
}
