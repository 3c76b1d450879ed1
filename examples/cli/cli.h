/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Shared command-line layer of the example programs: one table-driven flag parser, number
 * parsing, the step count, CSV output and the integration driver with its exit codes
 * (0 done, 1 failure during integration, 2 bad input). */
#ifndef STABDAE_EXAMPLES_CLI_H
#define STABDAE_EXAMPLES_CLI_H

#include <stddef.h> /* offsetof: CLI_LAYOUT */
#include <stdio.h>

#include <stabdae/stabdae.h>

enum { CLI_OK = 0, CLI_HELP = 1, CLI_BAD = 2 };
enum { CLI_EXIT_OK = 0, CLI_EXIT_FAILED = 1, CLI_EXIT_USAGE = 2 };
#define CLI_ERR_LEN 256

typedef enum cli_kind {
  CLI_REAL,     /* double, finite */
  CLI_POSITIVE, /* double, finite, > 0 */
  CLI_NONNEG,   /* double, finite, >= 0 */
  CLI_COUNT,    /* size_t, >= 1 */
  CLI_SEED,     /* unsigned long, any value */
  CLI_CHOICE,   /* int: index into choices */
  CLI_VECTOR,   /* exactly n finite doubles separated by commas */
  CLI_LIST,     /* const char *: a list whose length the program checks (cli_parse_vector) */
  CLI_PATH,     /* const char *, non-empty */
  CLI_TEXT,     /* const char *, non-empty, parsed by the program (e.g. --box) */
  CLI_SWITCH,   /* int set to 1, takes no value */
  CLI_MAP       /* const sdae_map_type *: a library map name (sdae_map_by_name) among choices */
} cli_kind;

typedef struct cli_flag {
  const char *name; /* without the leading "--" */
  cli_kind kind;
  void *target;               /* double *, size_t *, unsigned long *, int *, const char ** */
  const char *const *choices; /* CLI_CHOICE, CLI_MAP: NULL-terminated list */
  size_t n;                   /* CLI_VECTOR: number of values */
  const char *help;
} cli_flag;

/* Parses argv[1..argc) against the table: "--name value" or "--name=value"; "--help" anywhere
 * before an error returns CLI_HELP. On CLI_BAD, err holds one line naming the problem. */
int cli_parse(int argc, char *const *argv, const cli_flag *flags, size_t nflags, char *err,
              size_t errlen);
void cli_usage(FILE *f, const char *prog, const char *summary, const cli_flag *flags,
               size_t nflags);

/* Formats a one-line message into err (control characters shown as '?'); returns CLI_BAD. */
int cli_fail(char *err, size_t errlen, const char *fmt, ...);

/* Strict conversions: the whole string, finite, in range; 0 on success, -1 otherwise. */
int cli_parse_double(const char *s, double *out);
int cli_parse_size(const char *s, size_t *out);
int cli_parse_ulong(const char *s, unsigned long *out);
/* Exactly n finite doubles separated by commas; CLI_BAD with err naming --name otherwise.
 * out may be NULL: the list is only checked. */
int cli_parse_vector(const char *s, double *out, size_t n, const char *name, char *err,
                     size_t errlen);

/* ---- the settings every program shares -------------------------------------------------- */

extern const char *const cli_scheme_choices[]; /* "11", "15" */
/* "paper", "none", "baumgarte": the order of sdae_stabilizer */
extern const char *const cli_stabilizer_choices[];

typedef struct cli_run {
  double delta, eps, T, tf;
  int scheme;               /* index into cli_scheme_choices */
  const sdae_map_type *map; /* one of the program's map choices */
  size_t every;             /* a CSV row every `every` steps, plus t = 0 and the last step */
  const char *out;          /* NULL: stdout */
  size_t nsteps;            /* set by cli_run_finish */
  int stabilizer;           /* index into cli_stabilizer_choices; 0 (paper) when not given */
} cli_run;

/* Appends the shared flags (--delta --eps --T --tf --scheme --map --stabilizer --every --out)
 * to dst, which has room for CLI_RUN_NFLAGS entries; returns the number appended. map_choices
 * are the library's names (sdae_map_name) of the maps the program's model can serve: another
 * library map, or a name the library does not know, is bad input. */
#define CLI_RUN_NFLAGS 9
size_t cli_run_flags(cli_flag *dst, cli_run *run, const char *const *map_choices,
                     const char *map_help);
/* Derived settings and cross-checks: nsteps = ceil(tf/T - 1e-9) (the final time is tf up to a
 * relative 1e-9; rows are at t = i T), which must be representable. 0 or -1 with err set. */
int cli_run_finish(cli_run *run, char *err, size_t errlen);
/* Copies scheme, delta, epsilon and the stabilizer into the options. */
void cli_run_options(const cli_run *run, sdae_options *o);

/* ---- where the rows go ------------------------------------------------------------------ */

/* What a row tells beyond its CSV columns, for the ensemble runner's summaries. */
typedef struct cli_row_info {
  double violation;           /* max |constraint| at the row */
  double energy;              /* the model's energy at the row */
  unsigned long newton_total; /* Newton iterations of every step so far */
  unsigned long switches;     /* chart switches so far (the mechanical front-end; else 0) */
} cli_row_info;

/* A destination of a program's output: the CSV file of the serial programs (cli_file_sink),
 * or the ensemble runner's capture of a member. Each callback returns non-zero to stop. */
typedef struct cli_sink cli_sink;
struct cli_sink {
  int (*header)(cli_sink *s, const char *line); /* the CSV header, without newline */
  /* one row: n values, then the last column (newton_iters, or switches) */
  int (*row)(cli_sink *s, const double *v, size_t n, unsigned last, const cli_row_info *info);
  /* the run's end: SDAE_OK or its failure, the steps taken, and for SDAE_STOPPED the reason
   * (the row's, or NULL when the sink stopped the run) */
  void (*end)(cli_sink *s, int status, size_t steps, const char *why);
};

typedef struct cli_file_sink {
  cli_sink base;
  FILE *f;
} cli_file_sink;
/* The sink writing CSV to f, numbers %.17g. */
cli_file_sink cli_file_sink_make(FILE *f);

/* Writes n values with %.17g, then the Newton iteration count, one row. */
int cli_csv_row(FILE *f, const double *v, size_t n, unsigned newton_iters);
/* The run's --out opened for writing (stdout without it), or NULL with one line on stderr
 * naming prog; and the file closed and removed when the run ends in bad input. */
FILE *cli_open_output(const cli_run *run, const char *prog);
void cli_discard_output(FILE *f, const cli_run *run);
/* fflush and close (stdout stays open); non-zero, with one line on stderr, on an error. */
int cli_close_output(FILE *f, const char *prog);
/* The line a failure during integration prints: the step after the last good one (done),
 * taken from t = done T; why is the observer's reason when it stopped the run. Returns 1. */
int cli_report_failure(const char *prog, const cli_run *run, int status, size_t done,
                       const char *why);

/* ---- the driver ---------------------------------------------------------------------------- */

/* What a program's row function hands on: the sink and the driver's part of the row. */
typedef struct cli_row_out {
  cli_sink *sink;
  unsigned newton_iters; /* of the step that ended at the row (0 at t = 0) */
  cli_row_info info;
} cli_row_out;
/* One row of n values to the sink, with the model's constraint violation and energy. */
int cli_emit(cli_row_out *o, const double *v, size_t n, double violation, double energy);

/* One CSV row from the state at time t; non-zero when the state cannot be written (outside the
 * model's domain), with a one-line reason in why. */
typedef int (*cli_row_fn)(cli_row_out *o, double t, const double *xi, const double *mu, void *ctx,
                          const char **why);

typedef struct cli_program {
  const char *name;   /* for messages */
  const char *header; /* the CSV header line, without newline */
  const sdae_model *model;
  const sdae_options *options;
  double *xi, *mu; /* the initial state, updated in place */
  cli_row_fn row;
  void *row_ctx;
} cli_program;

/* Builds the stepper and integrates run->nsteps steps, rows to the sink. sink NULL: the serial
 * program, which opens --out and returns the exit code (on a bad setup, CLI_EXIT_USAGE, the
 * output file is removed; on a failure during integration the rows so far are kept and one
 * line names the step). Otherwise the outcome goes to sink->end and nothing is printed. */
int cli_execute_to(const cli_program *p, const cli_run *run, cli_sink *sink);

/* The common main: parse (CLI_HELP prints usage on stdout), print one line and return 2 on bad
 * input. Returns -1 when the caller should go on. */
int cli_parse_or_exit(int rc, const char *prog, const char *summary, const cli_flag *flags,
                      size_t nflags, const char *err);

/* ---- a program, callable in-process ------------------------------------------------------ */

/* Where a program's argument struct keeps the shared parts: its cli_run `run`, its flag table
 * `flags` (pointing into the struct, which therefore stays where it was parsed) and `nflags`. */
typedef struct cli_layout {
  size_t size, run, flags, nflags;
} cli_layout;
#define CLI_LAYOUT(type)                                                                           \
  { sizeof(type), offsetof(type, run), offsetof(type, flags), offsetof(type, nflags) }

/* The model and options of a --certify, and its box (n = n_xi + n_mu bounds each). */
typedef struct cli_certify_setup {
  sdae_model model;
  sdae_options options;
  const double *lo, *hi;
  unsigned grid;
} cli_certify_setup;

/* An example program: its flags and its run, for its own main (cli_main) and for the ensemble
 * runner, which runs it once per member with the member's flags. */
typedef struct cli_def {
  const char *name, *summary;
  cli_layout layout;
  /* defaults, the flag table and parsing into args (layout.size bytes): CLI_OK, CLI_HELP or
   * CLI_BAD with err set; every check of the input is here, before any work */
  int (*parse)(int argc, char *const *argv, void *args, char *err, size_t errlen);
  /* integrates with the parsed args, rows to sink (NULL: as the serial program, --out and
   * its --certify/--check-model); the exit code */
  int (*run)(void *args, cli_sink *sink);
  /* NULL, or the model, options and box of --certify from the parsed args */
  void (*certify_setup)(void *args, cli_certify_setup *c);
} cli_def;

/* The serial program: parse argv, usage or one line on bad input, then run. The exit code. */
int cli_main(const cli_def *d, int argc, char **argv);
/* The parts of parsed args the layout names. */
cli_run *cli_args_run(const cli_def *d, void *args);
const cli_flag *cli_args_flags(const cli_def *d, void *args, size_t *nflags);

#endif /* STABDAE_EXAMPLES_CLI_H */
