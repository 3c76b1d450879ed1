/* SPDX-License-Identifier: GPL-3.0-or-later */
#include <stdlib.h>
#include <string.h>

#include "ensemble.h"

/* flags a members file may not set: where the runner writes, and the programs' other modes */
static const char *const refused[] = {"out", "certify", "check-model", "help", NULL};

static unsigned long long fnv1a(unsigned long long h, const char *s, size_t n) {
  for (size_t i = 0; i < n; i++) h = (h ^ (unsigned char)s[i]) * 1099511628211ull;
  return h;
}

/* the whole file, NUL-terminated, or NULL */
static char *slurp(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  char *buf = NULL;
  size_t cap = 0, n = 0, got;
  if (!f) return NULL;
  do {
    if (n + 4096 + 1 > cap) {
      char *b = realloc(buf, cap = 2 * cap + 4096 + 1);
      if (!b) break;
      buf = b;
    }
    got = fread(buf + n, 1, cap - n - 1, f);
    n += got;
  } while (got > 0);
  int bad = ferror(f) || !buf || n + 1 > cap;
  fclose(f);
  if (bad) {
    free(buf);
    return NULL;
  }
  buf[n] = '\0';
  *len = n;
  return buf;
}

/* Splits one line (NUL-terminated, in place) into fields: "a,b" or "\"a,b\",c" ("" inside
 * quotes is a quote). Returns the number of fields, up to max, or -1 on a stray quote. */
static long split_line(char *line, char **fields, size_t max) {
  size_t n = 0;
  char *r = line, *w = line;
  for (;;) {
    char *start = w;
    if (*r == '"') {
      for (r++;; r++) {
        if (*r == '\0') return -1;
        if (*r == '"' && r[1] == '"')
          *w++ = *r++;
        else if (*r == '"')
          break;
        else
          *w++ = *r;
      }
      r++;
      if (*r != ',' && *r != '\0') return -1;
    } else {
      while (*r != ',' && *r != '\0') {
        if (*r == '"') return -1;
        *w++ = *r++;
      }
    }
    if (n < max) fields[n] = start;
    n++;
    if (*r == '\0') {
      *w = '\0';
      return (long)n;
    }
    *w++ = '\0';
    r++;
  }
}

static int check_names(ens_members *m, const char *path, char *err, size_t errlen) {
  for (size_t c = 0; c < m->ncols; c++) {
    const char *name = m->names[c];
    if (*name == '\0') return cli_fail(err, errlen, "%s:1: column %zu has no name", path, c + 1);
    for (size_t k = 0; refused[k]; k++)
      if (strcmp(name, refused[k]) == 0)
        return cli_fail(err, errlen, "%s:1: column '%s': the runner sets --%s itself", path, name,
                        name);
    for (size_t d = 0; d < c; d++)
      if (strcmp(name, m->names[d]) == 0)
        return cli_fail(err, errlen, "%s:1: column '%s' twice", path, name);
  }
  return CLI_OK;
}

/* the lines: the header, then the rows (a blank last line is the file's end) */
static int split_rows(ens_members *m, char *text, const char *path, char *err, size_t errlen) {
  size_t nlines = 1;
  for (char *c = text; *c; c++) nlines += *c == '\n';
  m->names = malloc(nlines * sizeof *m->names);
  m->line = malloc(nlines * sizeof *m->line);
  if (!m->names || !m->line) return cli_fail(err, errlen, "%s: out of memory", path);
  char *p = text;
  size_t count = 0, lineno = 0;
  while (*p) {
    char *nl = strchr(p, '\n');
    lineno++;
    if (nl) *nl = '\0';
    if (nl && nl > p && nl[-1] == '\r') nl[-1] = '\0';
    if (*p == '\0' && !nl) break;
    m->names[count] = p; /* the raw lines for now */
    m->line[count++] = lineno;
    p = nl ? nl + 1 : p + strlen(p);
  }
  if (count == 0) return cli_fail(err, errlen, "%s: empty (no header)", path);
  m->nrows = count - 1;
  return CLI_OK;
}

static int split_fields(ens_members *m, char **lines, const char *path, char *err, size_t errlen) {
  long n = split_line(lines[0], m->names, m->ncols);
  if (n < 0) return cli_fail(err, errlen, "%s:1: a stray or unclosed quote", path);
  m->ncols = (size_t)n; /* fewer than counted when a quoted name holds a comma */
  for (size_t r = 0; r < m->nrows; r++) {
    size_t lineno = m->line[r + 1];
    n = split_line(lines[r + 1], m->fields + r * m->ncols, m->ncols);
    if (n < 0) return cli_fail(err, errlen, "%s:%zu: a stray or unclosed quote", path, lineno);
    if ((size_t)n != m->ncols)
      return cli_fail(err, errlen, "%s:%zu: %ld fields, the header has %zu", path, lineno, n,
                      m->ncols);
    for (size_t c = 0; c < m->ncols; c++)
      if (m->fields[r * m->ncols + c][0] == '\0')
        return cli_fail(err, errlen, "%s:%zu: column '%s' is empty", path, lineno, m->names[c]);
  }
  for (size_t r = 0; r < m->nrows; r++) m->line[r] = m->line[r + 1];
  return check_names(m, path, err, errlen);
}

static int make_flags(ens_members *m, const char *path, char *err, size_t errlen) {
  if (!(m->flags = calloc(m->ncols, sizeof *m->flags)))
    return cli_fail(err, errlen, "%s: out of memory", path);
  for (size_t c = 0; c < m->ncols; c++) {
    size_t n = strlen(m->names[c]) + 3;
    if (!(m->flags[c] = malloc(n))) return cli_fail(err, errlen, "%s: out of memory", path);
    snprintf(m->flags[c], n, "--%s", m->names[c]);
  }
  return CLI_OK;
}

int ens_members_read(const char *path, ens_members *m, char *err, size_t errlen) {
  size_t len;
  *m = (ens_members){0};
  char *text = slurp(path, &len);
  if (!text) return cli_fail(err, errlen, "--members: cannot read '%s'", path);
  m->text = text;
  m->hash = fnv1a(14695981039346656037ull, text, len);
  int rc = split_rows(m, text, path, err, errlen);
  if (rc != CLI_OK) return rc;
  char **lines = m->names; /* split_rows left the raw lines there */
  m->ncols = 1;
  for (const char *c = lines[0]; *c; c++) m->ncols += *c == ',';
  m->names = malloc(m->ncols * sizeof *m->names);
  m->fields = malloc((m->nrows * m->ncols + 1) * sizeof *m->fields);
  if (!m->names || !m->fields) rc = cli_fail(err, errlen, "%s: out of memory", path);
  if (rc == CLI_OK) rc = split_fields(m, lines, path, err, errlen);
  if (rc == CLI_OK) rc = make_flags(m, path, err, errlen);
  free(lines);
  return rc;
}

void ens_members_free(ens_members *m) {
  for (size_t c = 0; m->flags && c < m->ncols; c++) free(m->flags[c]);
  free(m->flags);
  free(m->names);
  free(m->fields);
  free(m->line);
  free(m->text);
  *m = (ens_members){0};
}

size_t ens_argv_len(const ens_job *job) {
  return 2 + (size_t)job->nshared + 2 * job->members.ncols;
}

int ens_member_argv(const ens_job *job, size_t i, char **argv) {
  const ens_members *m = &job->members;
  int argc = 0;
  argv[argc++] = (char *)job->def->name;
  for (int k = 0; k < job->nshared; k++) argv[argc++] = job->shared[k];
  for (size_t c = 0; c < m->ncols; c++) {
    argv[argc++] = m->flags[c];
    argv[argc++] = m->fields[i * m->ncols + c];
  }
  argv[argc] = NULL;
  return argc;
}

int ens_members_check(const ens_job *job, void *args, char *err, size_t errlen) {
  char **argv = malloc(ens_argv_len(job) * sizeof *argv);
  char msg[CLI_ERR_LEN];
  int rc = CLI_OK;
  if (!argv) return cli_fail(err, errlen, "out of memory");
  for (size_t i = 0; i < job->members.nrows && rc == CLI_OK; i++) {
    int argc = ens_member_argv(job, i, argv);
    rc = job->def->parse(argc, argv, args, msg, sizeof msg);
    if (rc == CLI_HELP) snprintf(msg, sizeof msg, "--help is not a member's flag");
    if (rc != CLI_OK)
      rc = cli_fail(err, errlen, "%s:%zu: %s", job->members_path, job->members.line[i], msg);
  }
  free(argv);
  return rc;
}
