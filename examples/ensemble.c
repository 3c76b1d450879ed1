/* SPDX-License-Identifier: GPL-3.0-or-later */
/* ensemble: an example program run once per row of a members file, over MPI (docs/ensembles.md).
 *
 *   mpirun -n P build/examples/ensemble --model NAME --members FILE --out FILE [flags]
 *
 * Every flag the runner does not know is the model's, given to every member; the members
 * file's header names more of the model's flags and each row gives their values. The output
 * has one row per member in member order: member,status,steps, the last row of the program's
 * CSV, max_violation,energy_change,newton_iters_total,chart_switches, then the rows at --at.
 * A member's row depends on its flags alone, not on P or the chunks. --certify instead splits
 * the model's --certify box over the ranks. Exit codes: 0 done (failed members are recorded
 * in the file), 1 the output could not be written, 2 bad input (nothing run, no file). */
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "ensemble.h"

#define MAX_MODELS 32
/* keeps a chunk's rows within one MPI message (an int count of chars): 1024 members of at
 * most 65 rows (the last and 64 --at times) of a few hundred bytes each stay far below 2^31 */
#define CHUNK_LIMIT 1024
/* MPI guarantees message tags up to 32767; --certify tags a slab's result with its index */
#define PIECES_LIMIT 32767

static const char summary[] =
    "Runs an example program once per row of --members over MPI (mpirun -n P ...): the\n"
    "members file's header names flags of the model, each row gives their values; the\n"
    "flags the runner does not know are the model's, for every member. Writes one CSV row\n"
    "per member in member order (member,status,steps, the program's last row, summaries,\n"
    "the rows at --at). --certify splits the model's --certify box over the ranks.";

typedef struct ens_args {
  int model;
  const char *members, *out, *at;
  int resume, quiet, certify;
  size_t chunk, pieces;
  double progress;
} ens_args;

static size_t own_flags(ens_args *a, const char *const *names, cli_flag *fl) {
  const cli_flag own[] = {
      {"model", CLI_CHOICE, &a->model, names, 0, "the example program of every member"},
      {"members", CLI_PATH, &a->members, NULL, 0, "CSV: a header of flag names, a row a member"},
      {"out", CLI_PATH, &a->out, NULL, 0, "the output CSV (and OUT.job, for --resume)"},
      {"at", CLI_LIST, &a->at, NULL, 0, "times t1,t2,... (ascending) whose rows are added"},
      {"resume", CLI_SWITCH, &a->resume, NULL, 0, "keep the complete rows of --out, run the rest"},
      {"quiet", CLI_SWITCH, &a->quiet, NULL, 0, "no progress lines on stderr"},
      {"progress", CLI_NONNEG, &a->progress, NULL, 0, "seconds between progress lines"},
      {"chunk", CLI_COUNT, &a->chunk, NULL, 0, "members per message [guided: adapts]"},
      {"certify", CLI_SWITCH, &a->certify, NULL, 0, "the model's --certify, split over ranks"},
      {"pieces", CLI_COUNT, &a->pieces, NULL, 0, "--certify: slabs of the box"},
  };
  memcpy(fl, own, sizeof own);
  return sizeof own / sizeof own[0];
}

/* argv split into the runner's flags (own) and the model's (shared, after argv[0]) */
static void split_argv(int argc, char **argv, const cli_flag *fl, size_t nfl, char **own, int *nown,
                       char **shared, int *nshared) {
  *nown = *nshared = 1;
  own[0] = shared[0] = argv[0];
  for (int i = 1; i < argc; i++) {
    const char *name = argv[i] + 2, *eq = strchr(name, '=');
    size_t len = eq ? (size_t)(eq - name) : strlen(name);
    const cli_flag *f = NULL;
    for (size_t k = 0; strncmp(argv[i], "--", 2) == 0 && k < nfl && !f; k++)
      if (strlen(fl[k].name) == len && strncmp(fl[k].name, name, len) == 0) f = &fl[k];
    if (!f && strcmp(argv[i], "--help") != 0 && strcmp(argv[i], "-h") != 0) {
      shared[(*nshared)++] = argv[i];
      continue;
    }
    own[(*nown)++] = argv[i];
    if (f && !eq && f->kind != CLI_SWITCH && i + 1 < argc) own[(*nown)++] = argv[++i];
  }
}

/* --at: ascending finite times >= 0 */
static int parse_at(ens_job *job, char *err, size_t errlen) {
  size_t n = 1;
  const size_t max = sizeof job->at / sizeof job->at[0];
  for (const char *c = job->at_text; *c; c++) n += *c == ',';
  if (n > max) return cli_fail(err, errlen, "--at: at most %zu times", max);
  if (cli_parse_vector(job->at_text, job->at, n, "at", err, errlen) != CLI_OK) return CLI_BAD;
  for (size_t k = 0; k < n; k++)
    if (job->at[k] < 0 || (k > 0 && job->at[k] <= job->at[k - 1]))
      return cli_fail(err, errlen, "--at: the times must be >= 0 and ascending");
  job->n_at = n;
  return CLI_OK;
}

/* the runner's settings, then the model's shared flags parsed alone */
static int setup(const ens_args *a, ens_job *job, void *args, char *err, size_t errlen) {
  char msg[CLI_ERR_LEN];
  *job = (ens_job){.def = ens_models[a->model],
                   .members_path = a->members,
                   .out = a->out,
                   .at_text = a->at,
                   .resume = a->resume,
                   .quiet = a->quiet,
                   .certify = a->certify,
                   .chunk = a->chunk,
                   .pieces = a->pieces,
                   .progress = a->progress,
                   .nshared = job->nshared,
                   .shared = job->shared};
  if (a->chunk > CHUNK_LIMIT) return cli_fail(err, errlen, "--chunk: at most %d", CHUNK_LIMIT);
  if (a->pieces > PIECES_LIMIT)
    return cli_fail(err, errlen, "--pieces: at most %d (MPI's least bound on tags)", PIECES_LIMIT);
  for (int k = 1; k < job->nshared; k++)
    if (strncmp(job->shared[k], "--check-model", 13) == 0)
      return cli_fail(err, errlen, "--check-model is not an ensemble's flag");
  if (a->certify && !job->def->certify_setup)
    return cli_fail(err, errlen, "--certify: %s has no certificate", job->def->name);
  if (!a->certify && (!a->members || !a->out))
    return cli_fail(err, errlen, "--members and --out are needed (or --certify)");
  if (a->at && parse_at(job, err, errlen) != CLI_OK) return CLI_BAD;
  int rc = job->def->parse(job->nshared, job->shared, args, msg, sizeof msg);
  if (rc != CLI_OK)
    return cli_fail(err, errlen, "%s: %s", job->def->name,
                    rc == CLI_HELP ? "--help is the runner's" : msg);
  /* the members see the shared flags after argv[0] */
  job->shared++, job->nshared--;
  return CLI_OK;
}

/* the members file read and every row parsed; the output's header. CLI_OK or CLI_BAD */
static int prepare(ens_job *job, void *args, char **header, char *err, size_t errlen) {
  if (ens_members_read(job->members_path, &job->members, err, errlen) != CLI_OK ||
      ens_members_check(job, args, err, errlen) != CLI_OK)
    return CLI_BAD;
  if (!(*header = ens_header(job, args)))
    return cli_fail(err, errlen, "%s refuses the shared flags (or out of memory)", job->def->name);
  return CLI_OK;
}

static int sweep(ens_job *job, void *args, int rank) {
  char err[CLI_ERR_LEN] = "", *header = NULL;
  size_t first = 0;
  FILE *out = NULL;
  int rc = prepare(job, args, &header, err, sizeof err);
  if (rc != CLI_OK && rank == 0) fprintf(stderr, "%s: %s\n", ENS_PROG, err);
  if (rc == CLI_OK && rank == 0 && !(out = ens_output_open(job, header, &first))) rc = CLI_BAD;
  /* rank 0 alone opens the output: the others learn whether it could */
  MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (rc == CLI_OK)
    rc = ens_schedule(job, args, out, first);
  else
    rc = CLI_EXIT_USAGE;
  if (out && fclose(out)) rc = CLI_EXIT_FAILED;
  free(header);
  ens_members_free(&job->members);
  return rc;
}

static int run(int argc, char **argv, int rank) {
  const char *names[MAX_MODELS + 1];
  size_t nm = 0;
  for (; ens_models[nm] && nm < MAX_MODELS; nm++) names[nm] = ens_models[nm]->name;
  names[nm] = NULL;
  ens_args a = {.model = -1, .pieces = 8, .progress = 5.0};
  ens_job job = {0};
  cli_flag fl[16];
  size_t nfl = own_flags(&a, names, fl);
  char **own = malloc(2 * ((size_t)argc + 1) * sizeof *own), err[CLI_ERR_LEN] = "";
  void *args = NULL;
  if (!own) return CLI_EXIT_FAILED;
  int nown;
  job.shared = own + argc + 1;
  split_argv(argc, argv, fl, nfl, own, &nown, job.shared, &job.nshared);
  int rc = cli_parse(nown, own, fl, nfl, err, sizeof err);
  if (rc == CLI_OK && a.model < 0) rc = cli_fail(err, sizeof err, "--model is needed");
  if (rc == CLI_OK && !(args = malloc(ens_models[a.model]->layout.size)))
    rc = cli_fail(err, sizeof err, "out of memory");
  if (rc == CLI_OK) rc = setup(&a, &job, args, err, sizeof err);
  if (rank == 0)
    rc = cli_parse_or_exit(rc, ENS_PROG, summary, fl, nfl, err);
  else
    rc = rc == CLI_OK ? -1 : rc == CLI_HELP ? CLI_EXIT_OK : CLI_EXIT_USAGE; /* rank 0 says */
  if (rc < 0) rc = a.certify ? ens_certify(&job, args) : sweep(&job, args, rank);
  free(args);
  free(own);
  return rc;
}

int main(int argc, char **argv) {
  int rank;
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int rc = run(argc, argv, rank);
  MPI_Finalize();
  return rc;
}
