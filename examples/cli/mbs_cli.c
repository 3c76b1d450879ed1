/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "mbs_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mechanisms.h"

const char *const mbs_map_choices[] = {"euler",     "midpoint",  "dgrad", "dg4", "dg6",
                                       "midpoint4", "midpoint6", "rk4",   "rk8", NULL};

cli_run mbs_run_defaults(void) {
  return (cli_run){.delta = 2.0,
                   .eps = 1.0,
                   .T = 0.001,
                   .tf = 10.0,
                   .scheme = 1,
                   .map = sdae_map_dgrad,
                   .every = 1};
}

int mbs_parse(int argc, char *const *argv, const cli_flag *model, size_t n, cli_flag *flags,
              size_t *nflags, cli_run *run, char *err, size_t errlen) {
  for (size_t i = 0; i < n; i++) flags[i] = model[i];
  *nflags = n + cli_run_flags(flags + n, run, mbs_map_choices,
                              "mu-map: dgrad = Gonzalez with the mechanism's energy");
  return cli_parse(argc, argv, flags, *nflags, err, errlen);
}

/* ---- the CSV ------------------------------------------------------------------------------- */

/* t,q1..qn,v1..vn,lambda1..lambdam,max_abs_c,E,switches into buf */
static int make_header(const sdae_mbs *sys, char *buf, size_t len) {
  size_t at = (size_t)snprintf(buf, len, "t");
  for (size_t i = 1; i <= sys->n_q && at < len; i++)
    at += (size_t)snprintf(buf + at, len - at, ",q%zu", i);
  for (size_t i = 1; i <= sys->n_q && at < len; i++)
    at += (size_t)snprintf(buf + at, len - at, ",v%zu", i);
  for (size_t j = 1; j <= sys->n_c && at < len; j++)
    at += (size_t)snprintf(buf + at, len - at, ",lambda%zu", j);
  if (at < len) at += (size_t)snprintf(buf + at, len - at, ",max_abs_c,E,switches");
  return at < len ? 0 : -1;
}

typedef struct row_data {
  const mbs_program *p;
  sdae_mbs_stepper *s;
  cli_sink *sink;
  double T;
  double *row;     /* t, q, v, lambda, max_abs_c, E; then xi's 2 n_c, scratch */
  const char *why; /* set when a row could not be written */
  char why_buf[96];
} row_data;

static int row_fail(row_data *d, const char *what, int status) {
  snprintf(d->why_buf, sizeof d->why_buf, "%s: %s", what, sdae_strerror(status));
  d->why = d->why_buf;
  return 1;
}

/* one row at t = step T exactly (not an accumulated sum) */
static int observe(size_t step, double t, const double *q, const double *v, void *data) {
  row_data *d = data;
  const sdae_mbs *sys = d->p->sys;
  size_t n = sys->n_q, m = sys->n_c, len = 1 + 2 * n + m + 2;
  double *lambda = d->row + 1 + 2 * n;
  int status;
  d->row[0] = (double)step * d->T;
  memcpy(d->row + 1, q, n * sizeof *q);
  memcpy(d->row + 1 + n, v, n * sizeof *v);
  if ((status = sdae_mbs_lambda(d->s, t, q, v, lambda)) != SDAE_OK)
    return row_fail(d, "the constraint forces", status);
  if ((status = sdae_mbs_energy(d->s, t, q, v, &d->row[len - 1])) != SDAE_OK)
    return row_fail(d, "the energy", status);
  if ((status = sdae_mbs_xi(d->s, t, q, v, d->row + len)) != SDAE_OK)
    return row_fail(d, "the constraints", status);
  d->row[len - 2] = 0.0; /* every constraint's c, xi's c-parts (redundant rows included) */
  for (size_t j = 0; j < m; j++) d->row[len - 2] = fmax(d->row[len - 2], fabs(d->row[len + 2 * j]));
  const sdae_mbs_stats *st = sdae_mbs_stepper_stats(d->s);
  const cli_row_info info = {d->row[len - 2], d->row[len - 1], st->step.newton_iters_total,
                             st->chart_switches};
  /* the switch count fits the unsigned column: one per step at most */
  if (d->sink->row(d->sink, d->row, len, (unsigned)st->chart_switches, &info)) {
    d->why = "cannot write the output";
    return 1;
  }
  return 0;
}

/* ---- the run ------------------------------------------------------------------------------- */

/* the header, then the integration; the status, steps taken in *done */
static int integrate(const mbs_program *p, const cli_run *run, row_data *d, size_t *done) {
  /* ",lambda" and a size_t's digits per column, and the last three */
  size_t len = 32 + 28 * (2 * p->sys->n_q + p->sys->n_c);
  char *header = malloc(len);
  *done = 0;
  if (!header) return SDAE_ERR_NOMEM;
  int bad = make_header(p->sys, header, len) || d->sink->header(d->sink, header);
  free(header);
  if (bad) {
    d->why = "cannot write the output";
    return SDAE_STOPPED;
  }
  return sdae_mbs_integrate(d->s, 0.0, run->T, run->nsteps, run->every, p->q, p->v, observe, d,
                            done);
}

/* the stepper and the row's storage; SDAE_OK or the failure (nothing kept) */
static int prepare(const mbs_program *p, const cli_run *run, sdae_mbs_stepper **s, double **row) {
  sdae_options opt;
  sdae_options_default(&opt);
  cli_run_options(run, &opt);
  opt.map = run->map;
  int status = sdae_mbs_stepper_alloc(s, p->sys, &opt);
  if (status != SDAE_OK) return status;
  if ((*row = malloc((3 + 2 * p->sys->n_q + 3 * p->sys->n_c) * sizeof **row))) return SDAE_OK;
  sdae_mbs_stepper_free(*s);
  return SDAE_ERR_NOMEM;
}

static int execute_file(const mbs_program *p, const cli_run *run) {
  FILE *f = cli_open_output(run, p->name);
  if (!f) return CLI_EXIT_USAGE;
  sdae_mbs_stepper *s = NULL;
  double *row = NULL;
  int status = prepare(p, run, &s, &row);
  if (status != SDAE_OK) {
    /* the library rejected the mechanism or the options: bad input, leave no file behind */
    if (status == SDAE_ERR_NOMEM)
      fprintf(stderr, "%s: out of memory\n", p->name);
    else
      fprintf(stderr, "%s: invalid settings: %s\n", p->name, sdae_strerror(status));
    cli_discard_output(f, run);
    return CLI_EXIT_USAGE;
  }
  cli_file_sink fs = cli_file_sink_make(f);
  row_data d = {.p = p, .s = s, .sink = &fs.base, .T = run->T, .row = row};
  size_t done;
  int rc = CLI_EXIT_OK;
  status = integrate(p, run, &d, &done);
  if (status != SDAE_OK) rc = cli_report_failure(p->name, run, status, done, d.why);
  free(row);
  sdae_mbs_stepper_free(s);
  if (cli_close_output(f, p->name)) rc = CLI_EXIT_FAILED;
  return rc;
}

int mbs_execute_to(const mbs_program *p, const cli_run *run, cli_sink *sink) {
  if (!sink) return execute_file(p, run);
  sdae_mbs_stepper *s = NULL;
  double *row = NULL;
  size_t done = 0;
  row_data d = {.p = p, .sink = sink, .T = run->T};
  int status = prepare(p, run, &s, &row);
  if (status == SDAE_OK) {
    d.s = s, d.row = row;
    status = integrate(p, run, &d, &done);
    free(row);
    sdae_mbs_stepper_free(s);
  }
  sink->end(sink, status, done, d.why);
  return status == SDAE_OK ? CLI_EXIT_OK : CLI_EXIT_FAILED;
}
