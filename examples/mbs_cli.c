/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "mbs_cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "mechanisms.h"

const char *const mbs_map_choices[] = {"euler", "midpoint", "dgrad", "dg4", "dg6", NULL};

cli_run mbs_run_defaults(void) {
  return (cli_run){.delta = 2.0, .eps = 1.0, .T = 0.001, .tf = 10.0, .scheme = 1,
                   .map = sdae_map_dgrad, .every = 1};
}

size_t mbs_run_flags(cli_flag *dst, cli_run *run) {
  return cli_run_flags(dst, run, mbs_map_choices,
                       "mu-map: dgrad = Gonzalez with the mechanism's energy");
}

/* ---- the CSV ------------------------------------------------------------------------------- */

static int write_header(FILE *f, const sdae_mbs *sys) {
  int bad = fputs("t", f) < 0;
  for (size_t i = 1; i <= sys->n_q; i++) bad |= fprintf(f, ",q%zu", i) < 0;
  for (size_t i = 1; i <= sys->n_q; i++) bad |= fprintf(f, ",v%zu", i) < 0;
  for (size_t j = 1; j <= sys->n_c; j++) bad |= fprintf(f, ",lambda%zu", j) < 0;
  return bad | (fputs(",max_abs_c,E,switches\n", f) < 0);
}

typedef struct row_data {
  const mbs_program *p;
  sdae_mbs_stepper *s;
  FILE *f;
  double T;
  double *row;       /* t, q, v, lambda, max_abs_c, E */
  const char *why;   /* set when a row could not be written */
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
  d->row[len - 2] = mech_max_abs_c(sys, t, q);
  if (d->row[len - 2] < 0) return row_fail(d, "the constraints", SDAE_ERR_CALLBACK_FATAL);
  /* the switch count fits cli_csv_row's unsigned: one per step at most */
  unsigned switches = (unsigned)sdae_mbs_stepper_stats(d->s)->chart_switches;
  if (cli_csv_row(d->f, d->row, len, switches)) {
    d->why = "cannot write the output";
    return 1;
  }
  return 0;
}


static int close_output(FILE *f, const char *prog) {
  int bad = fflush(f) != 0 || ferror(f);
  if (f != stdout && fclose(f) != 0) bad = 1;
  if (bad) fprintf(stderr, "%s: error writing the output\n", prog);
  return bad;
}

/* ---- the run ------------------------------------------------------------------------------- */

static int integrate(const mbs_program *p, const cli_run *run, row_data *d) {
  size_t done = 0;
  int status = SDAE_STOPPED;
  if (write_header(d->f, p->sys))
    d->why = "cannot write the output";
  else
    status = sdae_mbs_integrate(d->s, 0.0, run->T, run->nsteps, run->every, p->q, p->v,
                                observe, d, &done);
  if (status == SDAE_OK) return CLI_EXIT_OK;
  /* the step that failed is the one after the last good one, taken from t = done T */
  if (status == SDAE_STOPPED)
    fprintf(stderr, "%s: stopped at step %zu (t = %.17g): %s\n", p->name, done,
            (double)done * run->T, d->why);
  else
    fprintf(stderr, "%s: step %zu from t = %.17g failed: %s\n", p->name, done + 1,
            (double)done * run->T, sdae_strerror(status));
  return CLI_EXIT_FAILED;
}

int mbs_execute(const mbs_program *p, const cli_run *run) {
  FILE *f = cli_open_output(run, p->name);
  if (!f) return CLI_EXIT_USAGE;
  sdae_options opt;
  sdae_options_default(&opt);
  cli_run_options(run, &opt);
  opt.map = run->map;
  sdae_mbs_stepper *s = NULL;
  int status = sdae_mbs_stepper_alloc(&s, p->sys, &opt);
  if (status != SDAE_OK) {
    /* the library rejected the mechanism or the options: bad input, leave no file behind */
    fprintf(stderr, "%s: invalid settings: %s\n", p->name, sdae_strerror(status));
    cli_discard_output(f, run);
    return CLI_EXIT_USAGE;
  }
  double *row = malloc((3 + 2 * p->sys->n_q + p->sys->n_c) * sizeof *row);
  if (!row) {
    fprintf(stderr, "%s: out of memory\n", p->name);
    sdae_mbs_stepper_free(s);
    cli_discard_output(f, run);
    return CLI_EXIT_USAGE;
  }
  row_data d = {.p = p, .s = s, .f = f, .T = run->T, .row = row};
  int rc = integrate(p, run, &d);
  free(row);
  sdae_mbs_stepper_free(s);
  if (close_output(f, p->name)) rc = CLI_EXIT_FAILED;
  return rc;
}
