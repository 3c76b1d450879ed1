/* SPDX-License-Identifier: GPL-3.0-or-later */
/* One member: the program run in-process with the member's flags, its rows caught by a sink
 * that keeps the last row, the rows at --at and the summaries, then formatted as one output
 * row. Nothing here depends on the rank or on the other members. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "ensemble.h"

#define MAX_COLS 4096 /* of a program's CSV; the mechanisms have a few dozen */

typedef struct capture {
  cli_sink base;
  const ens_job *job;
  double T;     /* the member's step: --at picks the row at t >= t_k - 1e-9 T */
  size_t n;     /* values per row (the columns but the last) */
  double *last; /* n values and the last column, then n_at rows of the same */
  int have_last;
  size_t next_at; /* the first --at time not reached yet */
  double vmax, e0, e_last;
  unsigned long newton, switches;
  int status, ended;
  size_t steps;
  char why[128]; /* the reason of SDAE_STOPPED */
} capture;

static double *slot(capture *c, size_t k) { return c->last + k * (c->n + 1); }

static int cap_header(cli_sink *s, const char *line) {
  (void)s, (void)line;
  return 0;
}

static void keep(capture *c, size_t k, const double *v, unsigned last) {
  memcpy(slot(c, k), v, c->n * sizeof *v);
  slot(c, k)[c->n] = last;
}

static int cap_row(cli_sink *s, const double *v, size_t n, unsigned last,
                   const cli_row_info *info) {
  capture *c = (capture *)s;
  if (n != c->n) return 1; /* a row unlike the program's header: cannot happen */
  if (!c->have_last) c->e0 = info->energy, c->vmax = info->violation;
  c->have_last = 1;
  keep(c, 0, v, last);
  c->vmax = fmax(c->vmax, info->violation);
  c->e_last = info->energy;
  c->newton = info->newton_total;
  c->switches = info->switches;
  while (c->next_at < c->job->n_at && v[0] >= c->job->at[c->next_at] - 1e-9 * c->T)
    keep(c, 1 + c->next_at++, v, last);
  return 0;
}

static void cap_end(cli_sink *s, int status, size_t steps, const char *why) {
  capture *c = (capture *)s;
  snprintf(c->why, sizeof c->why, "%s", why ? why : sdae_strerror(status));
  c->status = status;
  c->steps = steps;
  c->ended = 1;
}

/* ---- text ------------------------------------------------------------------------------- */

typedef struct text {
  char **buf;
  size_t *len, *cap;
  int bad;
} text;

static void put(text *t, const char *fmt, ...) {
  for (;;) {
    va_list ap;
    va_start(ap, fmt);
    size_t room = *t->cap - *t->len;
    int n = t->bad ? 0 : vsnprintf(*t->buf ? *t->buf + *t->len : NULL, room, fmt, ap);
    va_end(ap);
    if (t->bad || n < 0) {
      t->bad = 1;
      return;
    }
    if ((size_t)n < room) {
      *t->len += (size_t)n;
      return;
    }
    size_t cap = 2 * *t->cap + (size_t)n + 256;
    char *b = realloc(*t->buf, cap);
    if (!b) {
      t->bad = 1;
      return;
    }
    *t->buf = b, *t->cap = cap;
  }
}

/* a CSV field: quoted when it holds a comma or a quote */
static void put_field(text *t, const char *s) {
  if (!strpbrk(s, ",\"\n")) {
    put(t, ",%s", s);
    return;
  }
  put(t, ",\"");
  for (; *s; s++) {
    if (*s == '"')
      put(t, "\"\"");
    else
      put(t, "%c", *s);
  }
  put(t, "\"");
}

/* n values %.17g and the last column %u, or n + 1 empty fields */
static void put_row(text *t, const double *row, size_t n, int have) {
  for (size_t j = 0; j <= n; j++) {
    if (!have)
      put(t, ",");
    else if (j < n)
      put(t, ",%.17g", row[j]);
    else
      put(t, ",%u", (unsigned)row[j]);
  }
}

/* the program's column names, split from its header line into cols (max MAX_COLS) */
static size_t split_header(char *line, char **cols) {
  size_t n = 0;
  for (char *p = line; p && n < MAX_COLS; n++) {
    cols[n] = p;
    p = strchr(p, ',');
    if (p) *p++ = '\0';
  }
  return n;
}

/* ---- the program's header: a run with tf = 0 that keeps it ----------------------------- */

typedef struct header_sink {
  cli_sink base;
  char *line;
} header_sink;

static int keep_header(cli_sink *s, const char *line) {
  header_sink *h = (header_sink *)s;
  free(h->line);
  h->line = malloc(strlen(line) + 1);
  if (h->line) strcpy(h->line, line);
  return 1; /* the header is all it wants: stop */
}

static int no_row(cli_sink *s, const double *v, size_t n, unsigned last, const cli_row_info *info) {
  (void)s, (void)v, (void)n, (void)last, (void)info;
  return 1;
}

static void no_end(cli_sink *s, int status, size_t steps, const char *why) {
  (void)s, (void)status, (void)steps, (void)why;
}

/* the program's header line for the shared flags (malloc'ed), or NULL */
static char *program_header(const ens_job *job, void *args) {
  char **argv = malloc(((size_t)job->nshared + 2) * sizeof *argv);
  char err[CLI_ERR_LEN];
  header_sink h = {{keep_header, no_row, no_end}, NULL};
  if (!argv) return NULL;
  argv[0] = (char *)job->def->name;
  for (int k = 0; k < job->nshared; k++) argv[k + 1] = job->shared[k];
  if (job->def->parse(job->nshared + 1, argv, args, err, sizeof err) == CLI_OK)
    job->def->run(args, &h.base);
  free(argv);
  return h.line;
}

/* t_k as short as it reads back exactly */
static void put_time(text *t, double at) {
  char buf[32];
  snprintf(buf, sizeof buf, "%.15g", at);
  if (strtod(buf, NULL) != at) snprintf(buf, sizeof buf, "%.17g", at);
  put(t, "%s", buf);
}

char *ens_header(ens_job *job, void *args) {
  char *line = program_header(job, args), *out = NULL;
  char **cols = malloc(MAX_COLS * sizeof *cols);
  size_t len = 0, cap = 0;
  text t = {&out, &len, &cap, 0};
  if (line && cols) {
    size_t n = split_header(line, cols);
    job->prog_cols = n;
    put(&t, "member,status,steps");
    for (size_t j = 0; j < n; j++) put(&t, ",%s", cols[j]);
    put(&t, ",max_violation,energy_change,newton_iters_total,chart_switches");
    for (size_t k = 0; k < job->n_at; k++)
      for (size_t j = 0; j < n; j++) {
        put(&t, ",%s@", cols[j]);
        put_time(&t, job->at[k]);
      }
  }
  free(line);
  free(cols);
  if (t.bad || !out) {
    free(out);
    return NULL;
  }
  return out;
}

/* ---- a member -------------------------------------------------------------------------- */

static void put_result(text *t, const ens_job *job, size_t i, const capture *c,
                       const char *status) {
  put(t, "%zu", i);
  put_field(t, status);
  put(t, ",%zu", c->steps);
  put_row(t, c->last, c->n, c->have_last);
  if (c->have_last)
    put(t, ",%.17g,%.17g,%lu,%lu", c->vmax, c->e_last - c->e0, c->newton, c->switches);
  else
    put(t, ",,,,");
  for (size_t k = 0; k < job->n_at; k++)
    put_row(t, c->last + (1 + k) * (c->n + 1), c->n, k < c->next_at);
  put(t, "\n");
}

/* the outcome's text: "ok", the library's reason (the row's when it stopped the run), or the
 * parser's message */
static const char *status_text(const capture *c, int parsed, const char *err) {
  if (parsed != CLI_OK) return err;
  /* a program stops before its driver only when memory for its own state is missing */
  if (!c->ended) return sdae_strerror(SDAE_ERR_NOMEM);
  return c->status == SDAE_OK        ? "ok"
         : c->status == SDAE_STOPPED ? c->why
                                     : sdae_strerror(c->status);
}

int ens_member_run(const ens_job *job, size_t i, void *args, char **buf, size_t *len, size_t *cap) {
  size_t n = job->prog_cols - 1;
  capture c = {.base = {cap_header, cap_row, cap_end}, .job = job, .n = n};
  char **argv = malloc(ens_argv_len(job) * sizeof *argv);
  char err[CLI_ERR_LEN] = "";
  text t = {buf, len, cap, 0};
  c.last = malloc((1 + job->n_at) * (n + 1) * sizeof *c.last);
  if (!argv || !c.last) t.bad = 1;
  if (!t.bad) {
    int argc = ens_member_argv(job, i, argv);
    int parsed = job->def->parse(argc, argv, args, err, sizeof err);
    if (parsed == CLI_OK) {
      c.T = cli_args_run(job->def, args)->T;
      job->def->run(args, &c.base);
    }
    put_result(&t, job, i, &c, status_text(&c, parsed, err));
  }
  free(argv);
  free(c.last);
  return t.bad ? -1 : 0;
}

int ens_row_failed(const char *row) {
  const char *comma = strchr(row, ',');
  return !comma || strncmp(comma + 1, "ok,", 3) != 0;
}
