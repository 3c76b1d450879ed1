/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The ensemble runner (examples/ensemble.c): an example program run once per row of a members
 * file, over MPI. One concept per file: the models it knows (models.c), the members file
 * (members.c), one member's run into its output row (member.c), the output and --resume
 * (output.c), the master-worker schedule (schedule.c) and the split --certify (certify.c). */
#ifndef STABDAE_EXAMPLES_ENSEMBLE_H
#define STABDAE_EXAMPLES_ENSEMBLE_H

#include <stddef.h>
#include <stdio.h>

#include "cli.h"

#define ENS_PROG "ensemble"

/* ---- models.c: the programs a member can run ---------------------------------------------- */

extern const cli_def *const ens_models[]; /* NULL-terminated */

/* ---- the job ------------------------------------------------------------------------------- */

typedef struct ens_members {
  size_t ncols, nrows;
  char **names;            /* ncols flag names (the header) */
  char **flags;            /* ncols "--name" */
  char **fields;           /* nrows x ncols values */
  size_t *line;            /* the file's line of each row */
  unsigned long long hash; /* FNV-1a of the file's bytes */
  char *text;              /* the file, which names and fields point into */
} ens_members;

typedef struct ens_job {
  const cli_def *def; /* the model's program */
  const char *members_path, *out;
  const char *at_text; /* --at as given */
  double at[64];
  size_t n_at;
  int resume, quiet, certify;
  size_t chunk;    /* 0: adaptive */
  size_t pieces;   /* --certify: sub-boxes */
  double progress; /* seconds between progress lines */
  int nshared;
  char **shared; /* the flags for every member (argv[1..]) */
  ens_members members;
  size_t prog_cols; /* the columns of the program's CSV (set by ens_header) */
} ens_job;

/* ---- members.c ----------------------------------------------------------------------------- */

/* Reads the members file: a header of flag names, then one row per member ("" quotes a field
 * with commas). CLI_BAD with err naming the line otherwise. */
int ens_members_read(const char *path, ens_members *m, char *err, size_t errlen);
void ens_members_free(ens_members *m);
/* argv for member i: the program's name, the shared flags, then --name value per column;
 * argv has room for ens_argv_len(job) entries. Returns argc. */
size_t ens_argv_len(const ens_job *job);
int ens_member_argv(const ens_job *job, size_t i, char **argv);
/* Every row parsed by the program before any work: CLI_BAD with err naming the file's line. */
int ens_members_check(const ens_job *job, void *args, char *err, size_t errlen);

/* ---- member.c ------------------------------------------------------------------------------ */

/* The output's columns (header line without newline) into a malloc'ed string, or NULL; sets
 * job->prog_cols. */
char *ens_header(ens_job *job, void *args);
/* Runs member i and appends its output row (with newline) to *buf (grown as needed, *cap);
 * args is the program's argument storage. 0, or -1 when out of memory. */
int ens_member_run(const ens_job *job, size_t i, void *args, char **buf, size_t *len, size_t *cap);
/* Whether an output row records a failed member (its status is not "ok"). */
int ens_row_failed(const char *row);

/* ---- output.c ------------------------------------------------------------------------------ */

/* The output opened for the job: a fresh file with its header and the job file (OUT.job), or
 * with --resume the complete rows already there kept (*first: the first member to run).
 * NULL with one line on stderr when it cannot be (exit 2). */
FILE *ens_output_open(const ens_job *job, const char *header, size_t *first);

/* ---- schedule.c ---------------------------------------------------------------------------- */

/* Runs members [first, nrows) over the ranks of MPI_COMM_WORLD, rank 0 writing the rows to
 * out in member order. Every rank calls it; out is used on rank 0 only. The exit code. */
int ens_schedule(const ens_job *job, void *args, FILE *out, size_t first);

/* ---- certify.c ----------------------------------------------------------------------------- */

/* --certify: the box split into job->pieces sub-boxes shared by the ranks; rank 0 prints the
 * certificate of the sub-box with the largest sup. The exit code. */
int ens_certify(const ens_job *job, void *args);

#endif /* STABDAE_EXAMPLES_ENSEMBLE_H */
