/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The master-worker schedule. Rank 0 hands out chunks of consecutive members, IN_FLIGHT per
 * worker so that a worker never waits for its next chunk, computes members itself between
 * messages, and writes the rows in member order as the prefix of finished members grows. The
 * chunk is --chunk, or guided: a quarter of the remaining members per rank, so that the last
 * chunks are small and the ranks finish together whatever the members cost. */
#include <mpi.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ensemble.h"

enum { TAG_WORK = 1, TAG_RESULT = 2, TAG_STOP = 3 };
#define IN_FLIGHT 2
#define CHUNK_MAX 1024 /* guided chunks: at most this many members per message */

typedef struct chunk {
  size_t first, count;
} chunk;

typedef struct master {
  const ens_job *job;
  void *args;
  FILE *out;
  int ranks;
  size_t first, n;      /* the members to run: [first, n) */
  size_t next, written; /* the first member not handed out, not written */
  char **rows;          /* the rows of members not yet written, by member - first */
  chunk *queue;         /* IN_FLIGHT per worker, oldest first */
  size_t *queued;
  int *stopped;
  size_t done, failed;  /* members finished in this run */
  size_t own, messages; /* members run by rank 0, results received */
  double t0, reported;
  int bad;   /* the output could not be written */
  char *buf; /* the rows of the master's members and of the received chunks */
  size_t len, cap;
} master;

static size_t chunk_size(const master *m) {
  if (m->job->chunk) return m->job->chunk;
  size_t c = (m->n - m->next) / (4 * (size_t)m->ranks);
  return c < 1 ? 1 : c > CHUNK_MAX ? CHUNK_MAX : c;
}

/* worker w's next chunk, or its stop once it has no work left */
static void give(master *m, int w) {
  chunk *q = m->queue + (size_t)(w - 1) * IN_FLIGHT;
  size_t *nq = &m->queued[w - 1];
  if (m->next < m->n && *nq < IN_FLIGHT) {
    size_t c = chunk_size(m);
    if (c > m->n - m->next) c = m->n - m->next;
    uint64_t msg[2] = {m->next, c};
    q[(*nq)++] = (chunk){m->next, c};
    m->next += c;
    MPI_Send(msg, 2, MPI_UINT64_T, w, TAG_WORK, MPI_COMM_WORLD);
  } else if (m->next >= m->n && *nq == 0 && !m->stopped[w - 1]) {
    m->stopped[w - 1] = 1;
    MPI_Send(NULL, 0, MPI_UINT64_T, w, TAG_STOP, MPI_COMM_WORLD);
  }
}

static void progress(master *m, int last) {
  double now = MPI_Wtime(), dt = now - m->t0;
  if (m->job->quiet || (!last && now - m->reported < m->job->progress)) return;
  m->reported = now;
  double rate = dt > 0 ? (double)m->done / dt : 0.0;
  if (last) {
    /* rank 0's share of the work and its messages tell whether --chunk should be larger */
    fprintf(stderr,
            "%s: %zu members in %.3g s (%zu failed), %.4g members/s; rank 0 ran %zu "
            "and received %zu chunks\n",
            ENS_PROG, m->done, dt, m->failed, rate, m->own, m->messages);
    return;
  }
  size_t left = m->n - m->first - m->done;
  fprintf(stderr, "%s: %zu/%zu members done (%zu failed), %.4g members/s, ETA %.0f s\n", ENS_PROG,
          m->first + m->done, m->n, m->failed, rate, rate > 0 ? (double)left / rate : 0.0);
}

/* keeps the row of member i (a line of text, newline included) */
static int store(master *m, size_t i, const char *row, size_t len) {
  char *copy = malloc(len + 1);
  if (!copy) return -1;
  memcpy(copy, row, len);
  copy[len] = '\0';
  m->rows[i - m->first] = copy;
  m->done++;
  m->failed += (size_t)ens_row_failed(copy);
  return 0;
}

/* the rows of members [first, first + count) in buf[0..len) */
static int store_all(master *m, size_t first, size_t count, const char *buf, size_t len) {
  const char *p = buf, *end = buf + len;
  for (size_t k = 0; k < count; k++) {
    const char *nl = memchr(p, '\n', (size_t)(end - p));
    if (!nl || store(m, first + k, p, (size_t)(nl + 1 - p))) return -1;
    p = nl + 1;
  }
  return 0;
}

/* the finished prefix, each row whole, then flushed: a stopped job leaves whole rows */
static void write_prefix(master *m) {
  size_t before = m->written;
  while (m->written < m->n && m->rows[m->written - m->first]) {
    if (fputs(m->rows[m->written - m->first], m->out) < 0) m->bad = 1;
    free(m->rows[m->written - m->first]);
    m->rows[m->written - m->first] = NULL;
    m->written++;
  }
  if (m->written > before && fflush(m->out)) m->bad = 1;
}

static int receive(master *m) {
  MPI_Status st;
  int count;
  MPI_Probe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &st);
  MPI_Get_count(&st, MPI_CHAR, &count);
  if ((size_t)count > m->cap) {
    char *b = realloc(m->buf, (size_t)count);
    if (!b) return -1;
    m->buf = b, m->cap = (size_t)count;
  }
  MPI_Recv(m->buf, count, MPI_CHAR, st.MPI_SOURCE, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  int w = st.MPI_SOURCE;
  chunk *q = m->queue + (size_t)(w - 1) * IN_FLIGHT;
  chunk c = q[0];
  memmove(q, q + 1, (IN_FLIGHT - 1) * sizeof *q);
  m->queued[w - 1]--;
  m->messages++;
  give(m, w);
  return store_all(m, c.first, c.count, m->buf, (size_t)count);
}

/* one member on the master, between messages */
static int run_own(master *m) {
  size_t i = m->next++;
  m->len = 0;
  m->own++;
  if (ens_member_run(m->job, i, m->args, &m->buf, &m->len, &m->cap)) return -1;
  return store(m, i, m->buf, m->len);
}

static int master_loop(master *m) {
  for (int w = 1; w < m->ranks; w++)
    for (int k = 0; k < IN_FLIGHT; k++) give(m, w);
  while (m->written < m->n) {
    int flag = 0;
    MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
    int rc = flag || m->next >= m->n ? receive(m) : run_own(m);
    if (rc) return -1;
    write_prefix(m);
    progress(m, 0);
  }
  for (int w = 1; w < m->ranks; w++) give(m, w); /* those that never had work */
  progress(m, 1);
  return 0;
}

static int run_master(const ens_job *job, void *args, FILE *out, size_t first, int ranks) {
  size_t nw = ranks > 1 ? (size_t)ranks - 1 : 1;
  master m = {.job = job,
              .args = args,
              .out = out,
              .ranks = ranks,
              .first = first,
              .n = job->members.nrows,
              .next = first,
              .written = first,
              .t0 = MPI_Wtime()};
  m.reported = m.t0;
  m.rows = calloc(m.n - first + 1, sizeof *m.rows);
  m.queue = malloc(nw * IN_FLIGHT * sizeof *m.queue);
  m.queued = calloc(nw, sizeof *m.queued);
  m.stopped = calloc(nw, sizeof *m.stopped);
  int rc = m.rows && m.queue && m.queued && m.stopped ? master_loop(&m) : -1;
  if (rc) {
    fprintf(stderr, "%s: out of memory\n", ENS_PROG);
    MPI_Abort(MPI_COMM_WORLD, CLI_EXIT_FAILED);
  }
  if (m.bad) fprintf(stderr, "%s: error writing '%s'\n", ENS_PROG, job->out);
  free(m.rows);
  free(m.queue);
  free(m.queued);
  free(m.stopped);
  free(m.buf);
  return m.bad ? CLI_EXIT_FAILED : CLI_EXIT_OK;
}

static int run_worker(const ens_job *job, void *args) {
  char *buf = NULL;
  size_t len, cap = 0;
  for (;;) {
    uint64_t msg[2];
    MPI_Status st;
    MPI_Recv(msg, 2, MPI_UINT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
    if (st.MPI_TAG == TAG_STOP) break;
    len = 0;
    for (uint64_t k = 0; k < msg[1]; k++)
      if (ens_member_run(job, (size_t)(msg[0] + k), args, &buf, &len, &cap)) {
        fprintf(stderr, "%s: out of memory\n", ENS_PROG);
        MPI_Abort(MPI_COMM_WORLD, CLI_EXIT_FAILED);
      }
    MPI_Send(buf, (int)len, MPI_CHAR, 0, TAG_RESULT, MPI_COMM_WORLD);
  }
  free(buf);
  return CLI_EXIT_OK;
}

int ens_schedule(const ens_job *job, void *args, FILE *out, size_t first) {
  int rank, ranks;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  return rank == 0 ? run_master(job, args, out, first, ranks) : run_worker(job, args);
}
