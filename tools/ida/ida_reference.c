/* SPDX-License-Identifier: GPL-3.0-or-later */
/* ida_reference: SUNDIALS IDA solution of the index-reduced oscillator or pendulum, the
 * independent reference the stabilized schemes are compared with.
 *
 *   ida_reference oscillator|pendulum --form index1|ggl --rtol R --atol A --tf TF
 *                 --x0 X,Y,Xdot,Ydot --every-dt DT --out FILE [--project] [model flags]
 *
 * CSV: t,X,Y,Xdot,Ydot,lambda every DT (t = 0 and tf included), then '#' lines with IDA's
 * counters. Bad input: one line on stderr, exit 2, no file. IDA failure: the rows computed so
 * far are kept, exit 1. */
#include "ida_solve.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PROG "ida_reference"

enum { FOR_OSCILLATOR = 1, FOR_PENDULUM = 2, FOR_BOTH = 3 };

typedef struct cli {
  idaref_model model;
  idaref_form form;
  idaref_options opt;
  double x0[4];
  int have_x0, project;
  const char *out;
} cli;

static const char usage[] =
    "usage: " PROG " oscillator|pendulum [options]\n"
    "  --form index1|ggl   index1: hdd = 0, lambda algebraic (default);\n"
    "                      ggl: Gear-Gupta-Leimkuhler index 2, h = 0 and hdot = 0\n"
    "  --rtol R --atol A   IDA tolerances (default 1e-10, 1e-12)\n"
    "  --tf TF             final time (default 50)\n"
    "  --every-dt DT       output spacing (default 0.01); t = 0 and tf always written\n"
    "  --x0 X,Y,Xdot,Ydot  initial state (default: oscillator 0.1,0.6,0,0;\n"
    "                      pendulum L sin 0.5,-L cos 0.5,0,0); must satisfy h = hdot = 0\n"
    "  --project           project x0 onto the constraint manifold instead of refusing it\n"
    "  --max-steps N       IDA steps allowed per output interval (default 100000)\n"
    "  --out FILE          CSV file (default: stdout)\n"
    "  oscillator: --k K --d D --m M --ga G (defaults 2, 0.03, 1, 9.81)\n"
    "  pendulum:   --L L --m M --ga G (defaults 1, 1, 9.81)\n"
    "CSV: t,X,Y,Xdot,Ydot,lambda, then '#' lines with the solver counters.\n";

/* Bad input: one line on stderr, exit status 2. */
static int bad(const char *fmt, ...) {
  va_list ap;
  fputs(PROG ": ", stderr);
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputc('\n', stderr);
  return 2;
}

static int parse_number(const char *flag, const char *s, double *v) {
  char *end;
  if (!s) return bad("%s needs a value", flag);
  *v = strtod(s, &end);
  if (end == s || *end != '\0') return bad("%s: '%s' is not a number", flag, s);
  if (!isfinite(*v)) /* also overflow: strtod returns HUGE_VAL */
    return bad("%s: '%s' is not a finite number", flag, s);
  return 0;
}

static int parse_x0(const char *s, double *x0) {
  char buf[512], *field, *rest;
  size_t count = 1;
  for (const char *c = s; *c; c++) count += *c == ',';
  if (count != 4) return bad("--x0 needs 4 comma-separated values X,Y,Xdot,Ydot (got %zu)", count);
  if (strlen(s) >= sizeof buf) return bad("--x0: value too long");
  strcpy(buf, s);
  rest = buf;
  for (int i = 0; i < 4; i++) {
    field = rest;
    rest = strchr(rest, ',');
    if (rest) *rest++ = '\0';
    if (parse_number("--x0", field, &x0[i])) return 2;
  }
  return 0;
}

static int parse_form(const char *s, idaref_form *form) {
  if (strcmp(s, "index1") == 0)
    *form = IDAREF_INDEX1;
  else if (strcmp(s, "ggl") == 0)
    *form = IDAREF_GGL;
  else
    return bad("--form: unknown form '%s' (index1 or ggl)", s);
  return 0;
}

static int parse_count(const char *flag, const char *s, long *v) {
  char *end;
  errno = 0;
  *v = strtol(s, &end, 10);
  if (end == s || *end != '\0' || errno == ERANGE || *v <= 0)
    return bad("%s: '%s' is not a positive integer", flag, s);
  return 0;
}

/* Flags with a numeric value, and which model they belong to; value NULL when missing. */
static int parse_numeric_flag(cli *c, const char *flag, const char *value, int *known) {
  const struct {
    const char *name;
    double *target;
    int models;
  } table[] = {
      {"--rtol", &c->opt.rtol, FOR_BOTH},   {"--atol", &c->opt.atol, FOR_BOTH},
      {"--tf", &c->opt.tf, FOR_BOTH},       {"--every-dt", &c->opt.dt, FOR_BOTH},
      {"--m", &c->model.m, FOR_BOTH},       {"--ga", &c->model.ga, FOR_BOTH},
      {"--k", &c->model.k, FOR_OSCILLATOR}, {"--d", &c->model.d, FOR_OSCILLATOR},
      {"--L", &c->model.L, FOR_PENDULUM},
  };
  int model = c->model.kind == IDAREF_OSCILLATOR ? FOR_OSCILLATOR : FOR_PENDULUM;
  for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
    if (strcmp(flag, table[i].name) != 0) continue;
    *known = 1;
    if (!(table[i].models & model))
      return bad("%s is not an option of the %s", flag,
                 model == FOR_OSCILLATOR ? "oscillator" : "pendulum");
    return parse_number(flag, value, table[i].target);
  }
  *known = 0;
  return 0;
}

static int parse_flag(cli *c, const char *flag, const char *value) {
  int known, status = parse_numeric_flag(c, flag, value, &known);
  if (known || status) return status;
  if (strcmp(flag, "--form") != 0 && strcmp(flag, "--x0") != 0 &&
      strcmp(flag, "--max-steps") != 0 && strcmp(flag, "--out") != 0)
    return bad("unknown option '%s' (see --help)", flag);
  if (!value) return bad("%s needs a value", flag);
  if (strcmp(flag, "--form") == 0) return parse_form(value, &c->form);
  if (strcmp(flag, "--x0") == 0) {
    c->have_x0 = 1;
    return parse_x0(value, c->x0);
  }
  if (strcmp(flag, "--max-steps") == 0) return parse_count(flag, value, &c->opt.max_steps);
  c->out = value;
  return value[0] ? 0 : bad("--out: empty file name");
}

static int parse_model(const char *s, cli *c) {
  if (strcmp(s, "oscillator") == 0)
    c->model = idaref_model_default(IDAREF_OSCILLATOR);
  else if (strcmp(s, "pendulum") == 0)
    c->model = idaref_model_default(IDAREF_PENDULUM);
  else
    return bad("unknown model '%s' (oscillator or pendulum)", s);
  return 0;
}

static int parse_args(int argc, char **argv, cli *c) {
  if (argc < 2 || argv[1][0] == '-')
    return bad("the first argument must be the model (oscillator or pendulum); see --help");
  if (parse_model(argv[1], c)) return 2;
  c->form = IDAREF_INDEX1;
  c->opt =
      (idaref_options){.rtol = 1e-10, .atol = 1e-12, .tf = 50.0, .dt = 0.01, .max_steps = 100000};
  for (int i = 2; i < argc; i++) {
    if (strcmp(argv[i], "--project") == 0) {
      c->project = 1;
      continue;
    }
    if (strncmp(argv[i], "--", 2) != 0)
      return bad("unexpected argument '%s' (see --help)", argv[i]);
    if (parse_flag(c, argv[i], i + 1 < argc ? argv[i + 1] : NULL)) return 2;
    i++;
  }
  return 0;
}

static int validate(cli *c) {
  const idaref_model *p = &c->model;
  if (!(c->opt.rtol > 0.0)) return bad("--rtol must be > 0 (got %g)", c->opt.rtol);
  if (!(c->opt.atol > 0.0)) return bad("--atol must be > 0 (got %g)", c->opt.atol);
  if (c->opt.tf < 0.0) return bad("--tf must be >= 0 (got %g)", c->opt.tf);
  if (!(c->opt.dt > 0.0)) return bad("--every-dt must be > 0 (got %g)", c->opt.dt);
  if (!(p->m > 0.0)) return bad("--m must be > 0 (got %g)", p->m);
  if (p->kind == IDAREF_PENDULUM && !(p->L > 0.0)) return bad("--L must be > 0 (got %g)", p->L);
  return 0;
}

static void default_x0(const idaref_model *p, double *x0) {
  if (p->kind == IDAREF_OSCILLATOR) {
    const double x[4] = {0.1, 0.6, 0.0, 0.0};
    memcpy(x0, x, sizeof x);
  } else {
    const double x[4] = {p->L * sin(0.5), -p->L * cos(0.5), 0.0, 0.0};
    memcpy(x0, x, sizeof x);
  }
}

/* IDA needs x0 on the manifold h = 0, hdot = 0 (IDACalcIC only finds lambda and y'). */
static int settle_x0(cli *c) {
  const double tol = 1e-12;
  double h, hdot;
  if (!c->have_x0) default_x0(&c->model, c->x0);
  h = idaref_h(&c->model, c->x0);
  hdot = idaref_hdot(&c->model, c->x0);
  if (fabs(h) <= tol && fabs(hdot) <= tol) return 0;
  if (!c->project)
    return bad("x0 is off the constraint manifold (h = %g, hdot = %g, tolerance %g); "
               "give --project to project it",
               h, hdot, tol);
  if (idaref_project(&c->model, c->x0) != 0)
    return bad("x0 cannot be projected onto the constraint manifold (h = %g)", h);
  fprintf(stderr, PROG ": x0 projected onto the constraint manifold: %.17g,%.17g,%.17g,%.17g\n",
          c->x0[0], c->x0[1], c->x0[2], c->x0[3]);
  return 0;
}

static int write_row(double t, const double *y, void *ctx) {
  FILE *fp = ctx;
  int n = fprintf(fp, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", t, y[IDAREF_X], y[IDAREF_Y],
                  y[IDAREF_XDOT], y[IDAREF_YDOT], y[IDAREF_LAMBDA]);
  return n < 0 ? -1 : 0;
}

static void write_trailer(FILE *fp, const idaref_result *res, int status) {
  idaref_write_stats(fp, &res->stats);
  if (status == IDAREF_IDA_FAILED)
    fprintf(fp, "# status: %s at t = %.17g\n", res->flag_name, res->t_reached);
  else
    fprintf(fp, "# status: %s\n", status == IDAREF_OK ? "ok" : "output failed");
}

static int report_failure(const cli *c, const idaref_result *res, int status) {
  if (status == IDAREF_OUTPUT_FAILED) {
    fprintf(stderr, PROG ": writing %s failed at t = %.17g\n", c->out ? c->out : "stdout",
            res->t_reached);
    return 1;
  }
  fprintf(stderr, PROG ": %s failed with %s at t = %.17g%s%s\n", res->function, res->flag_name,
          res->t_reached, res->message[0] ? " -- " : "", res->message);
  return 1;
}

static int run(const cli *c, FILE *fp) {
  idaref_result res;
  int status;
  fputs("t,X,Y,Xdot,Ydot,lambda\n", fp);
  status = idaref_solve(&c->model, c->form, c->x0, &c->opt, write_row, fp, &res);
  write_trailer(fp, &res, status);
  if (ferror(fp) && status == IDAREF_OK) status = IDAREF_OUTPUT_FAILED;
  return status == IDAREF_OK ? 0 : report_failure(c, &res, status);
}

int main(int argc, char **argv) {
  cli c = {0};
  FILE *fp = stdout;
  int status;
  for (int i = 1; i < argc; i++)
    if (strcmp(argv[i], "--help") == 0) {
      fputs(usage, stdout);
      return 0;
    }
  if (parse_args(argc, argv, &c) || validate(&c) || settle_x0(&c)) return 2;
  if (c.out && !(fp = fopen(c.out, "w")))
    return bad("cannot write --out '%s': %s", c.out, strerror(errno));
  status = run(&c, fp);
  if (fp != stdout ? fclose(fp) != 0 : fflush(fp) != 0) {
    fprintf(stderr, PROG ": writing %s failed\n", c.out ? c.out : "stdout");
    return 1;
  }
  return status;
}
