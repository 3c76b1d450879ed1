/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The output: the CSV (its header, then one row per member in member order, each written
 * whole) and beside it OUT.job, what --resume checks: the model, the members file (its rows
 * and hash), --at and the shared flags. A resumed run keeps the complete rows of members
 * 0, 1, ... and appends the rest: the same file as a run that was never stopped. */
#define _POSIX_C_SOURCE 200809L /* truncate */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "ensemble.h"

/* the job file's text into buf; 0, or -1 when it does not fit */
static int job_text(const ens_job *job, char *buf, size_t len) {
  size_t at = (size_t)snprintf(buf, len,
                               "stabdae ensemble\nmodel: %s\nmembers: %zu rows, fnv1a-64 %016llx\n"
                               "at: %s\n",
                               job->def->name, job->members.nrows, job->members.hash,
                               job->at_text ? job->at_text : "");
  for (int k = 0; k < job->nshared && at < len; k++)
    at += (size_t)snprintf(buf + at, len - at, "flag: %s\n", job->shared[k]);
  return at < len ? 0 : -1;
}

static char *job_path(const ens_job *job) {
  size_t n = strlen(job->out) + 5;
  char *p = malloc(n);
  if (p) snprintf(p, n, "%s.job", job->out);
  return p;
}

/* a whole small file, NUL-terminated, into buf; its length, or -1 */
static long read_small(const char *path, char *buf, size_t len) {
  FILE *f = fopen(path, "rb");
  if (!f) return -1;
  size_t n = fread(buf, 1, len - 1, f);
  int more = fgetc(f) != EOF;
  fclose(f);
  if (more) return -1;
  buf[n] = '\0';
  return (long)n;
}

static int write_job(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  int bad = fputs(text, f) < 0;
  return (fclose(f) != 0) | bad ? -1 : 0;
}

static FILE *fresh(const ens_job *job, const char *header, const char *jpath, const char *jtext) {
  if (write_job(jpath, jtext)) {
    fprintf(stderr, "%s: cannot write '%s': %s\n", ENS_PROG, jpath, strerror(errno));
    return NULL;
  }
  FILE *f = fopen(job->out, "w");
  if (!f || fprintf(f, "%s\n", header) < 0 || fflush(f)) {
    fprintf(stderr, "%s: --out: cannot write '%s': %s\n", ENS_PROG, job->out, strerror(errno));
    if (f) fclose(f);
    return NULL;
  }
  return f;
}

/* the complete rows of members 0, 1, ... after the header: their count, and the offset after
 * them in *keep; -1 when the header is not this job's */
static long complete_rows(FILE *f, const char *header, size_t nrows, long *keep) {
  char *line = NULL;
  size_t cap = 0;
  ssize_t n;
  long rows = -1;
  if ((n = getline(&line, &cap, f)) > 0 && line[n - 1] == '\n') {
    line[n - 1] = '\0';
    if (strcmp(line, header) == 0) rows = 0;
  }
  *keep = ftell(f);
  while (rows >= 0 && (size_t)rows < nrows && (n = getline(&line, &cap, f)) > 0) {
    char *end;
    if (line[n - 1] != '\n') break; /* the row being written when the job was stopped */
    if (strtoul(line, &end, 10) != (unsigned long)rows || *end != ',') break;
    rows++;
    *keep = ftell(f);
  }
  free(line);
  return rows;
}

static FILE *resume(const ens_job *job, const char *header, size_t *first) {
  long keep;
  FILE *f = fopen(job->out, "r");
  if (!f) {
    fprintf(stderr, "%s: --resume: cannot read '%s': %s\n", ENS_PROG, job->out, strerror(errno));
    return NULL;
  }
  long rows = complete_rows(f, header, job->members.nrows, &keep);
  fclose(f);
  if (rows < 0) {
    fprintf(stderr, "%s: --resume: '%s' does not have this job's header\n", ENS_PROG, job->out);
    return NULL;
  }
  if (truncate(job->out, keep) || !(f = fopen(job->out, "a"))) {
    fprintf(stderr, "%s: --resume: cannot write '%s': %s\n", ENS_PROG, job->out, strerror(errno));
    return NULL;
  }
  *first = (size_t)rows;
  return f;
}

FILE *ens_output_open(const ens_job *job, const char *header, size_t *first) {
  static char jtext[1 << 16], old[1 << 16];
  char *jpath = job_path(job);
  FILE *f = NULL;
  *first = 0;
  if (!jpath || job_text(job, jtext, sizeof jtext)) {
    fprintf(stderr, "%s: out of memory or too many shared flags\n", ENS_PROG);
  } else if (!job->resume) {
    f = fresh(job, header, jpath, jtext);
  } else if (read_small(jpath, old, sizeof old) < 0) {
    fprintf(stderr, "%s: --resume: cannot read '%s'\n", ENS_PROG, jpath);
  } else if (strcmp(old, jtext) != 0) {
    fprintf(stderr,
            "%s: --resume: '%s' belongs to another job (model, members, --at or flags "
            "differ)\n",
            ENS_PROG, jpath);
  } else {
    f = resume(job, header, first);
  }
  free(jpath);
  return f;
}
