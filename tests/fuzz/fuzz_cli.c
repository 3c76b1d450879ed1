/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Fuzz target for the example programs' argument parsing (examples/cli/cli.c, certify_cli.c): the
 * input, split at NUL bytes, is argv[1..]. It is parsed against a table with every flag kind:
 * the shared run flags and certification flags the programs use, and model flags like the
 * oscillator's (a real, a vector, a choice, a seed). Then the programs' cross-checks run
 * (cli_run_finish, cli_certify_finish) and the usage text is printed with the parsed values.
 * The target checks the parser's contract and aborts on a breach:
 *   - the result is OK, help or bad input; "--help" first is always help;
 *   - bad input comes with one non-empty line of message, even when an argument holds a
 *     newline (the messages escape control characters: corpus/cli/newline-in-argument);
 *   - parsed values obey their kind: reals finite, positive > 0, non-negative >= 0, counts
 *     >= 1, vectors finite, choices in range, maps the library's and among the table's,
 *     paths and texts non-empty;
 *   - the step count is ceil(tf/T - 1e-9), at most 2^53; the box has finite lo <= hi. */
#define _POSIX_C_SOURCE 200809L /* strnlen */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "certify_cli.h"
#include "cli.h"

#define REQUIRE(cond)                                                                              \
  do {                                                                                             \
    if (!(cond)) {                                                                                 \
      fprintf(stderr, "fuzz_cli: contract broken at line %d: %s\n", __LINE__, #cond);              \
      abort();                                                                                     \
    }                                                                                              \
  } while (0)

#define MAX_ARGS 64
#define MODEL_NFLAGS 5
#define NFLAGS (MODEL_NFLAGS + CLI_RUN_NFLAGS + CERT_NFLAGS)

/* the library's names of the maps a model without a user map serves (the pendulum's, the
 * chain's): "user" is a library map this table refuses, "rk4" a name the library does not know */
static const char *const map_choices[] = {"euler", "midpoint", "dgrad", "dg4", "dg6", NULL};
static const char *const q_choices[] = {"corrected", "paper", NULL};

typedef struct args {
  double k, x0[4];
  int q;
  unsigned long seed;
  const char *name;
  cli_run run;
  cli_certify cert;
  cli_flag flags[NFLAGS];
  size_t nflags;
} args;

/* The defaults of the oscillator, and its kinds of flags. */
static void table(args *a) {
  *a = (args){.k = 2.0,
              .x0 = {0.1, 0.6, 0.0, 0.0},
              .run = {.delta = 2.0,
                      .eps = 1.0,
                      .T = 0.001,
                      .tf = 50.0,
                      .scheme = 1,
                      .map = sdae_map_euler,
                      .every = 1},
              .cert = {.grid = 41, .lo = {-0.7, 0.0, -0.9, -0.9}, .hi = {0.7, 0.0, 0.9, 0.9}}};
  const cli_flag model[MODEL_NFLAGS] = {
      {"k", CLI_REAL, &a->k, NULL, 0, "a real"},
      {"x0", CLI_VECTOR, a->x0, NULL, 4, "a vector of 4"},
      {"q", CLI_CHOICE, &a->q, q_choices, 0, "a choice"},
      {"seed", CLI_SEED, &a->seed, NULL, 0, "a seed"},
      {"name", CLI_TEXT, &a->name, NULL, 0, "a text"},
  };
  memcpy(a->flags, model, sizeof model);
  a->nflags = MODEL_NFLAGS;
  a->nflags += cli_run_flags(a->flags + a->nflags, &a->run, map_choices, "a map");
  a->nflags += cli_certify_flags(a->flags + a->nflags, &a->cert, "a box");
  REQUIRE(a->nflags == NFLAGS);
}

static size_t count_newlines(const char *s) {
  size_t n = 0;
  for (; *s; s++) n += *s == '\n';
  return n;
}

static void require_one_line(const char *err) {
  size_t n = strnlen(err, CLI_ERR_LEN);
  REQUIRE(n > 0 && n < CLI_ERR_LEN);
  REQUIRE(count_newlines(err) == 0);
}

static size_t n_choices(const char *const *c) {
  size_t n = 0;
  while (c[n]) n++;
  return n;
}

static void require_kind(const cli_flag *fl) {
  switch (fl->kind) {
  case CLI_REAL: REQUIRE(isfinite(*(const double *)fl->target)); break;
  case CLI_POSITIVE: {
    double v = *(const double *)fl->target;
    REQUIRE(isfinite(v) && v > 0.0);
    break;
  }
  case CLI_NONNEG: {
    double v = *(const double *)fl->target;
    REQUIRE(isfinite(v) && v >= 0.0);
    break;
  }
  case CLI_COUNT: REQUIRE(*(const size_t *)fl->target >= 1); break;
  case CLI_SEED: break; /* any value */
  case CLI_CHOICE: {
    int i = *(const int *)fl->target;
    REQUIRE(i >= 0 && (size_t)i < n_choices(fl->choices));
    break;
  }
  case CLI_VECTOR:
    for (size_t j = 0; j < fl->n; j++) REQUIRE(isfinite(((const double *)fl->target)[j]));
    break;
  case CLI_LIST:
  case CLI_PATH:
  case CLI_TEXT: {
    const char *s = *(const char *const *)fl->target;
    REQUIRE(s == NULL || *s != '\0'); /* NULL: the default, not given */
    break;
  }
  case CLI_SWITCH: REQUIRE(*(const int *)fl->target == 0 || *(const int *)fl->target == 1); break;
  case CLI_MAP: {
    /* a map of the library, one of the table's, found again by its name */
    const sdae_map_type *map = *(const sdae_map_type *const *)fl->target;
    const char *name = sdae_map_name(map);
    size_t j = 0;
    REQUIRE(map != NULL && sdae_map_by_name(name) == map);
    while (fl->choices[j] && strcmp(fl->choices[j], name) != 0) j++;
    REQUIRE(fl->choices[j] != NULL);
    break;
  }
  }
}

static void check_parsed(args *a) {
  char err[CLI_ERR_LEN] = "";
  static FILE *sink;
  for (size_t i = 0; i < a->nflags; i++) require_kind(&a->flags[i]);
  if (cli_run_finish(&a->run, err, sizeof err) == 0) {
    double steps = a->run.tf / a->run.T, n = (double)a->run.nsteps;
    REQUIRE(n <= 9007199254740992.0);
    REQUIRE(n >= steps - 1e-9 && (n == 0.0 || n - 1.0 < steps - 1e-9)); /* the ceiling */
  } else {
    require_one_line(err);
  }
  err[0] = '\0';
  if (cli_certify_finish(&a->cert, err, sizeof err) == CLI_OK) {
    for (int j = 0; j < CERT_DIM; j++)
      REQUIRE(isfinite(a->cert.lo[j]) && isfinite(a->cert.hi[j]) && a->cert.lo[j] <= a->cert.hi[j]);
  } else {
    require_one_line(err);
  }
  if (!sink) sink = fopen("/dev/null", "w");
  if (sink) cli_usage(sink, "fuzz_cli", "summary", a->flags, a->nflags);
}

/* argv[1..] from the input split at NUL bytes; the copy ends with a NUL of its own. */
static int split(char *buf, size_t size, char **argv) {
  int argc = 1;
  argv[0] = "fuzz_cli";
  for (size_t start = 0; start <= size && argc < MAX_ARGS; argc++) {
    argv[argc] = buf + start;
    start += strlen(buf + start) + 1;
  }
  argv[argc] = NULL;
  return argc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *buf = malloc(size + 1), *argv[MAX_ARGS + 1];
  char err[CLI_ERR_LEN] = "";
  args a;
  if (!buf) return 0;
  if (size > 0) memcpy(buf, data, size);
  buf[size] = '\0';
  int argc = split(buf, size, argv);
  table(&a);
  int rc = cli_parse(argc, argv, a.flags, a.nflags, err, sizeof err);
  REQUIRE(rc == CLI_OK || rc == CLI_HELP || rc == CLI_BAD);
  if (argc > 1 && strcmp(argv[1], "--help") == 0) REQUIRE(rc == CLI_HELP);
  if (rc == CLI_BAD) require_one_line(err);
  if (rc == CLI_OK) check_parsed(&a);
  free(buf);
  return 0;
}
