/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "cli.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

const char *const cli_scheme_choices[] = {"11", "15", NULL};
const char *const cli_stabilizer_choices[] = {"paper", "none", "baumgarte", NULL};

int cli_fail(char *err, size_t errlen, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, errlen, fmt, ap);
  va_end(ap);
  /* the message quotes arguments: a control character in one (a newline) would break the
   * one-line rule, so it is shown as '?' */
  for (char *c = err; *c; c++)
    if ((unsigned char)*c < 0x20 || *c == 0x7f) *c = '?';
  return CLI_BAD;
}

/* ---- numbers ------------------------------------------------------------------------------ */

int cli_parse_double(const char *s, double *out) {
  char *end;
  errno = 0;
  if (*s == '\0') return -1;
  double v = strtod(s, &end);
  /* ERANGE on underflow still gives a usable (tiny or zero) number; overflow gives Inf */
  if (*end != '\0' || !isfinite(v)) return -1;
  *out = v;
  return 0;
}

/* Digits only: strtoul would accept "-1" and wrap it around. */
static int all_digits(const char *s) {
  if (*s == '\0') return 0;
  for (; *s; s++)
    if (*s < '0' || *s > '9') return 0;
  return 1;
}

int cli_parse_ulong(const char *s, unsigned long *out) {
  char *end;
  if (!all_digits(s)) return -1;
  errno = 0;
  unsigned long v = strtoul(s, &end, 10);
  if (errno == ERANGE || *end != '\0') return -1;
  *out = v;
  return 0;
}

int cli_parse_size(const char *s, size_t *out) {
  char *end;
  if (!all_digits(s)) return -1;
  errno = 0;
  unsigned long long v = strtoull(s, &end, 10);
  if (errno == ERANGE || *end != '\0' || v > SIZE_MAX) return -1;
  *out = (size_t)v;
  return 0;
}

/* ---- flags -------------------------------------------------------------------------------- */

int cli_parse_vector(const char *s, double *out, size_t n, const char *name, char *err,
                     size_t errlen) {
  size_t count = 0;
  const char *p = s;
  for (;;) {
    const char *comma = strchr(p, ',');
    size_t len = comma ? (size_t)(comma - p) : strlen(p);
    char buf[64];
    if (len == 0 || len >= sizeof buf)
      return cli_fail(err, errlen, "--%s: '%s' is not a comma-separated list of numbers", name, s);
    memcpy(buf, p, len);
    buf[len] = '\0';
    double v;
    if (cli_parse_double(buf, &v))
      return cli_fail(err, errlen, "--%s: '%s' is not a finite number", name, buf);
    if (out && count < n) out[count] = v;
    count++;
    if (!comma) break;
    p = comma + 1;
  }
  if (count != n)
    return cli_fail(err, errlen, "--%s: expected %zu values, got %zu", name, n, count);
  return CLI_OK;
}

static int find_choice(const char *s, const char *const *choices) {
  for (int i = 0; choices[i]; i++)
    if (strcmp(s, choices[i]) == 0) return i;
  return -1;
}

/* "a|b|c" */
static void choice_list(const char *const *choices, char *list, size_t len) {
  list[0] = '\0';
  for (int i = 0; choices[i]; i++) {
    if (i) strncat(list, "|", len - strlen(list) - 1);
    strncat(list, choices[i], len - strlen(list) - 1);
  }
}

static int parse_choice(const char *s, const cli_flag *fl, char *err, size_t errlen) {
  int i = find_choice(s, fl->choices);
  if (i >= 0) {
    *(int *)fl->target = i;
    return CLI_OK;
  }
  char list[128];
  choice_list(fl->choices, list, sizeof list);
  return cli_fail(err, errlen, "--%s: unknown value '%s' (expected %s)", fl->name, s, list);
}

/* A map by the library's name; the program's choices are the maps its model can serve. */
static int parse_map(const char *s, const cli_flag *fl, char *err, size_t errlen) {
  const sdae_map_type *map = sdae_map_by_name(s);
  if (map && find_choice(s, fl->choices) >= 0) {
    *(const sdae_map_type **)fl->target = map;
    return CLI_OK;
  }
  char list[128];
  choice_list(fl->choices, list, sizeof list);
  if (map)
    return cli_fail(err, errlen,
                    "--%s: '%s' needs callbacks this program's model does not give (expected %s)",
                    fl->name, s, list);
  return cli_fail(err, errlen, "--%s: unknown value '%s' (expected %s)", fl->name, s, list);
}

static int parse_real(const char *s, const cli_flag *fl, char *err, size_t errlen) {
  double v;
  if (cli_parse_double(s, &v))
    return cli_fail(err, errlen, "--%s: '%s' is not a finite number", fl->name, s);
  if (fl->kind == CLI_POSITIVE && !(v > 0))
    return cli_fail(err, errlen, "--%s: must be > 0, got %s", fl->name, s);
  if (fl->kind == CLI_NONNEG && !(v >= 0))
    return cli_fail(err, errlen, "--%s: must be >= 0, got %s", fl->name, s);
  *(double *)fl->target = v;
  return CLI_OK;
}

static int parse_value(const char *s, const cli_flag *fl, char *err, size_t errlen) {
  switch (fl->kind) {
  case CLI_REAL:
  case CLI_POSITIVE:
  case CLI_NONNEG: return parse_real(s, fl, err, errlen);
  case CLI_COUNT: {
    size_t v;
    if (cli_parse_size(s, &v) || v == 0)
      return cli_fail(err, errlen, "--%s: '%s' is not a whole number >= 1", fl->name, s);
    *(size_t *)fl->target = v;
    return CLI_OK;
  }
  case CLI_SEED: {
    unsigned long v;
    if (cli_parse_ulong(s, &v))
      return cli_fail(err, errlen, "--%s: '%s' is not a whole number in [0, %lu]", fl->name, s,
                      ULONG_MAX);
    *(unsigned long *)fl->target = v;
    return CLI_OK;
  }
  case CLI_CHOICE: return parse_choice(s, fl, err, errlen);
  case CLI_MAP: return parse_map(s, fl, err, errlen);
  case CLI_VECTOR: return cli_parse_vector(s, fl->target, fl->n, fl->name, err, errlen);
  case CLI_LIST:
    if (*s == '\0') return cli_fail(err, errlen, "--%s: empty list", fl->name);
    *(const char **)fl->target = s;
    return CLI_OK;
  case CLI_PATH:
  case CLI_TEXT:
    if (*s == '\0') return cli_fail(err, errlen, "--%s: empty value", fl->name);
    *(const char **)fl->target = s;
    return CLI_OK;
  case CLI_SWITCH: return cli_fail(err, errlen, "--%s takes no value", fl->name);
  }
  return cli_fail(err, errlen, "--%s: internal error (unknown kind)", fl->name);
}

static const cli_flag *find_flag(const char *name, size_t len, const cli_flag *flags,
                                 size_t nflags) {
  for (size_t i = 0; i < nflags; i++)
    if (strlen(flags[i].name) == len && strncmp(flags[i].name, name, len) == 0) return &flags[i];
  return NULL;
}

/* a program's table with a name twice would give the second one no way in */
static const char *repeated_name(const cli_flag *flags, size_t nflags) {
  for (size_t i = 0; i < nflags; i++)
    for (size_t j = i + 1; j < nflags; j++)
      if (strcmp(flags[i].name, flags[j].name) == 0) return flags[i].name;
  return NULL;
}

int cli_parse(int argc, char *const *argv, const cli_flag *flags, size_t nflags, char *err,
              size_t errlen) {
  const char *twice = repeated_name(flags, nflags);
  if (twice) return cli_fail(err, errlen, "--%s: the program defines it twice", twice);
  for (int i = 1; i < argc; i++) {
    const char *arg = argv[i];
    if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) return CLI_HELP;
    if (strncmp(arg, "--", 2) != 0)
      return cli_fail(err, errlen, "unexpected argument '%s' (flags start with --)", arg);
    const char *name = arg + 2, *eq = strchr(name, '=');
    size_t len = eq ? (size_t)(eq - name) : strlen(name);
    const cli_flag *fl = find_flag(name, len, flags, nflags);
    if (!fl) return cli_fail(err, errlen, "unknown flag '--%.*s'", (int)len, name);
    const char *value = eq ? eq + 1 : NULL;
    if (fl->kind == CLI_SWITCH && !value) {
      *(int *)fl->target = 1;
      continue;
    }
    if (!value) {
      if (i + 1 >= argc) return cli_fail(err, errlen, "--%s: missing value", fl->name);
      value = argv[++i];
    }
    int rc = parse_value(value, fl, err, errlen);
    if (rc != CLI_OK) return rc;
  }
  return CLI_OK;
}

static const char *kind_hint(const cli_flag *fl) {
  switch (fl->kind) {
  case CLI_REAL: return "X";
  case CLI_POSITIVE: return "X>0";
  case CLI_NONNEG: return "X>=0";
  case CLI_COUNT: return "N>=1";
  case CLI_SEED: return "N";
  case CLI_CHOICE:
  case CLI_MAP: return "CHOICE";
  case CLI_VECTOR:
  case CLI_LIST: return "X,X,..";
  case CLI_PATH: return "FILE";
  case CLI_TEXT: return "SPEC";
  case CLI_SWITCH: return "";
  }
  return "";
}

/* the value the target holds now: the default when called before parsing went further */
static void print_default(FILE *f, const cli_flag *fl) {
  switch (fl->kind) {
  case CLI_REAL:
  case CLI_POSITIVE:
  case CLI_NONNEG: fprintf(f, " [%g]", *(const double *)fl->target); break;
  case CLI_COUNT: fprintf(f, " [%zu]", *(const size_t *)fl->target); break;
  case CLI_SEED: fprintf(f, " [%lu]", *(const unsigned long *)fl->target); break;
  case CLI_CHOICE: fprintf(f, " [%s]", fl->choices[*(const int *)fl->target]); break;
  case CLI_MAP:
    fprintf(f, " [%s]", sdae_map_name(*(const sdae_map_type *const *)fl->target));
    break;
  case CLI_VECTOR: {
    const double *v = fl->target;
    if (isnan(v[0])) break; /* a default computed from other flags, told in the help text */
    fputs(" [", f);
    for (size_t j = 0; j < fl->n; j++) fprintf(f, "%s%g", j ? "," : "", v[j]);
    fputc(']', f);
    break;
  }
  case CLI_LIST: break; /* its default is told in the help text */
  case CLI_PATH: {
    const char *path = *(const char *const *)fl->target;
    fprintf(f, " [%s]", path ? path : "stdout");
    break;
  }
  case CLI_TEXT:
  case CLI_SWITCH: break; /* the help text tells the default */
  }
}

void cli_usage(FILE *f, const char *prog, const char *summary, const cli_flag *flags,
               size_t nflags) {
  fprintf(f, "usage: %s [flags]\n%s\n\nflags:\n", prog, summary);
  for (size_t i = 0; i < nflags; i++) {
    char head[48];
    snprintf(head, sizeof head, "--%s %s", flags[i].name, kind_hint(&flags[i]));
    fprintf(f, "  %-22s %s", head, flags[i].help);
    if (flags[i].kind == CLI_CHOICE || flags[i].kind == CLI_MAP) {
      fputs(" (", f);
      for (int j = 0; flags[i].choices[j]; j++)
        fprintf(f, "%s%s", j ? "|" : "", flags[i].choices[j]);
      fputc(')', f);
    }
    print_default(f, &flags[i]);
    fputc('\n', f);
  }
  fprintf(f, "  %-22s %s\n", "--help", "this text");
}

int cli_parse_or_exit(int rc, const char *prog, const char *summary, const cli_flag *flags,
                      size_t nflags, const char *err) {
  if (rc == CLI_HELP) {
    cli_usage(stdout, prog, summary, flags, nflags);
    return CLI_EXIT_OK;
  }
  if (rc != CLI_OK) {
    fprintf(stderr, "%s: %s\n", prog, err);
    return CLI_EXIT_USAGE;
  }
  return -1;
}

/* ---- shared run settings ------------------------------------------------------------------- */

size_t cli_run_flags(cli_flag *dst, cli_run *run, const char *const *map_choices,
                     const char *map_help) {
  const cli_flag common[CLI_RUN_NFLAGS] = {
      {"delta", CLI_POSITIVE, &run->delta, NULL, 0, "stabilizer gain delta (eq. 6)"},
      {"eps", CLI_POSITIVE, &run->eps, NULL, 0, "stabilizer gain epsilon (eq. 6)"},
      {"T", CLI_POSITIVE, &run->T, NULL, 0, "step size"},
      {"tf", CLI_NONNEG, &run->tf, NULL, 0, "final time (ceil(tf/T - 1e-9) steps)"},
      {"scheme", CLI_CHOICE, &run->scheme, cli_scheme_choices, 0,
       "discretization: eq. 11 explicit, eq. 15 semi-implicit"},
      {"map", CLI_MAP, &run->map, map_choices, 0, map_help},
      {"stabilizer", CLI_CHOICE, &run->stabilizer, cli_stabilizer_choices, 0,
       "xi update: eq. 6, index reduction, Baumgarte (alpha 1,2)"},
      {"every", CLI_COUNT, &run->every, NULL, 0, "a row every N steps (t = 0 and the end too)"},
      {"out", CLI_PATH, &run->out, NULL, 0, "CSV output file"},
  };
  memcpy(dst, common, sizeof common);
  return CLI_RUN_NFLAGS;
}

int cli_run_finish(cli_run *run, char *err, size_t errlen) {
  double steps = run->tf / run->T;
  /* doubles count exactly up to 2^53; beyond that the step count itself is not representable */
  double n = ceil(steps - 1e-9);
  if (!isfinite(steps) || n > 9007199254740992.0 || n >= (double)SIZE_MAX) {
    cli_fail(err, errlen, "--tf/--T: %g steps cannot be represented", steps);
    return -1;
  }
  run->nsteps = n > 0 ? (size_t)n : 0;
  return 0;
}

void cli_run_options(const cli_run *run, sdae_options *o) {
  o->scheme = run->scheme == 0 ? SDAE_SCHEME_EXPLICIT : SDAE_SCHEME_SEMI_IMPLICIT;
  o->delta = run->delta;
  o->epsilon = run->eps;
  static const sdae_stabilizer stabilizers[] = {SDAE_STAB_PAPER, SDAE_STAB_NONE,
                                                SDAE_STAB_BAUMGARTE};
  o->stabilizer = stabilizers[run->stabilizer];
}

/* ---- CSV ---------------------------------------------------------------------------------- */

int cli_csv_row(FILE *f, const double *v, size_t n, unsigned newton_iters) {
  for (size_t i = 0; i < n; i++)
    if (fprintf(f, "%.17g,", v[i]) < 0) return -1;
  return fprintf(f, "%u\n", newton_iters) < 0 ? -1 : 0;
}

static int file_header(cli_sink *s, const char *line) {
  return fprintf(((cli_file_sink *)s)->f, "%s\n", line) < 0;
}

static int file_row(cli_sink *s, const double *v, size_t n, unsigned last,
                    const cli_row_info *info) {
  (void)info; /* the CSV has its own columns */
  return cli_csv_row(((cli_file_sink *)s)->f, v, n, last) != 0;
}

static void file_end(cli_sink *s, int status, size_t steps, const char *why) {
  (void)s, (void)status, (void)steps, (void)why; /* the serial driver reports it itself */
}

cli_file_sink cli_file_sink_make(FILE *f) {
  return (cli_file_sink){{file_header, file_row, file_end}, f};
}

FILE *cli_open_output(const cli_run *run, const char *prog) {
  if (!run->out) return stdout;
  FILE *f = fopen(run->out, "w");
  if (!f)
    fprintf(stderr, "%s: --out: cannot open '%s' for writing: %s\n", prog, run->out,
            strerror(errno));
  return f;
}

void cli_discard_output(FILE *f, const cli_run *run) {
  if (f == stdout) return;
  fclose(f);
  remove(run->out);
}

int cli_close_output(FILE *f, const char *prog) {
  int bad = fflush(f) != 0 || ferror(f);
  if (f != stdout && fclose(f) != 0) bad = 1;
  if (bad) fprintf(stderr, "%s: error writing the output\n", prog);
  return bad;
}

int cli_report_failure(const char *prog, const cli_run *run, int status, size_t done,
                       const char *why) {
  if (status == SDAE_STOPPED)
    fprintf(stderr, "%s: stopped at step %zu (t = %.17g): %s\n", prog, done, (double)done * run->T,
            why);
  else
    fprintf(stderr, "%s: step %zu from t = %.17g failed: %s\n", prog, done + 1,
            (double)done * run->T, sdae_strerror(status));
  return CLI_EXIT_FAILED;
}

/* ---- driver ------------------------------------------------------------------------------- */

int cli_emit(cli_row_out *o, const double *v, size_t n, double violation, double energy) {
  o->info.violation = violation;
  o->info.energy = energy;
  return o->sink->row(o->sink, v, n, o->newton_iters, &o->info);
}

typedef struct observer_data {
  const cli_program *p;
  const sdae_stepper *stepper;
  cli_sink *sink;
  double T;
  const char *why; /* set when a row could not be written */
} observer_data;

static int observe(size_t step, double t, const double *xi, const double *mu, void *data) {
  observer_data *od = data;
  const sdae_stats *st = sdae_stepper_stats(od->stepper);
  cli_row_out o = {
      od->sink, step == 0 ? 0 : st->newton_iters_last, {.newton_total = st->newton_iters_total}};
  (void)t; /* rows are at t = i T exactly, not an accumulated sum */
  if (od->p->row(&o, (double)step * od->T, xi, mu, od->p->row_ctx, &od->why)) {
    if (!od->why) od->why = "cannot write the output";
    return 1;
  }
  return 0;
}

/* the header, then the integration; the status, steps taken in *done */
static int integrate(const cli_program *p, const cli_run *run, sdae_stepper *s, cli_sink *sink,
                     observer_data *od, size_t *done) {
  *done = 0;
  if (sink->header(sink, p->header)) {
    od->why = "cannot write the output";
    return SDAE_STOPPED;
  }
  return sdae_integrate(s, 0.0, run->T, run->nsteps, run->every, p->xi, p->mu, observe, od, done);
}

static int execute_file(const cli_program *p, const cli_run *run) {
  FILE *f = cli_open_output(run, p->name);
  if (!f) return CLI_EXIT_USAGE;
  sdae_stepper *s = NULL;
  int status = sdae_stepper_alloc(&s, p->model, p->options);
  if (status != SDAE_OK) {
    /* the library rejected the model or options: bad input, leave no file behind */
    fprintf(stderr, "%s: invalid settings: %s\n", p->name, sdae_strerror(status));
    cli_discard_output(f, run);
    return CLI_EXIT_USAGE;
  }
  cli_file_sink fs = cli_file_sink_make(f);
  observer_data od = {p, s, &fs.base, run->T, NULL};
  size_t done;
  int rc = CLI_EXIT_OK;
  status = integrate(p, run, s, &fs.base, &od, &done);
  if (status != SDAE_OK) rc = cli_report_failure(p->name, run, status, done, od.why);
  sdae_stepper_free(s);
  if (cli_close_output(f, p->name)) rc = CLI_EXIT_FAILED;
  return rc;
}

int cli_execute_to(const cli_program *p, const cli_run *run, cli_sink *sink) {
  if (!sink) return execute_file(p, run);
  sdae_stepper *s = NULL;
  size_t done = 0;
  observer_data od = {p, NULL, sink, run->T, NULL};
  int status = sdae_stepper_alloc(&s, p->model, p->options);
  if (status == SDAE_OK) {
    od.stepper = s;
    status = integrate(p, run, s, sink, &od, &done);
    sdae_stepper_free(s);
  }
  sink->end(sink, status, done, od.why);
  return status == SDAE_OK ? CLI_EXIT_OK : CLI_EXIT_FAILED;
}

/* ---- a program ---------------------------------------------------------------------------- */

cli_run *cli_args_run(const cli_def *d, void *args) {
  return (cli_run *)((char *)args + d->layout.run);
}

const cli_flag *cli_args_flags(const cli_def *d, void *args, size_t *nflags) {
  *nflags = *(const size_t *)((const char *)args + d->layout.nflags);
  return (const cli_flag *)((const char *)args + d->layout.flags);
}

int cli_main(const cli_def *d, int argc, char **argv) {
  void *args = malloc(d->layout.size);
  char err[CLI_ERR_LEN] = "";
  size_t nflags;
  if (!args) {
    fprintf(stderr, "%s: out of memory\n", d->name);
    return CLI_EXIT_FAILED;
  }
  int rc = d->parse(argc, argv, args, err, sizeof err);
  const cli_flag *flags = cli_args_flags(d, args, &nflags);
  rc = cli_parse_or_exit(rc, d->name, d->summary, flags, nflags, err);
  if (rc < 0) rc = d->run(args, NULL);
  free(args);
  return rc;
}
