/* SPDX-License-Identifier: GPL-3.0-or-later */
/* --certify over the ranks: the box cut into job->pieces slabs along its first free coordinate,
 * slab p certified by rank p mod P with sdae_certify_box (the same grid per slab), and the
 * certificate of the slab with the largest sup kept (the first on a tie). The slabs cover the
 * box, so the sup over them is the sup over the box; the slabs and their order do not depend
 * on P, so neither does the answer. */
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "certify_cli.h"
#include "ensemble.h"

enum { F_STATUS, F_SUP, F_IMAX, F_TBAR, F_T15, F_T11, F_EVALS, F_ARGMAX };

/* slab p of `pieces` along coordinate j into lo, hi (copies of the box) */
static void slab(const cli_certify_setup *c, size_t dim, size_t j, size_t p, size_t pieces,
                 double *lo, double *hi) {
  memcpy(lo, c->lo, dim * sizeof *lo);
  memcpy(hi, c->hi, dim * sizeof *hi);
  double w = c->hi[j] - c->lo[j];
  lo[j] = c->lo[j] + w * (double)p / (double)pieces;
  if (p + 1 < pieces) hi[j] = c->lo[j] + w * (double)(p + 1) / (double)pieces;
}

/* certifies slab p into r: F_STATUS, the certificate, then argmax */
static void certify_slab(const cli_certify_setup *c, size_t dim, size_t j, size_t p, size_t pieces,
                         double *r) {
  double *lo = malloc(2 * dim * sizeof *lo);
  sdae_stepper *s = NULL;
  sdae_certificate cert;
  int rc = lo ? sdae_stepper_alloc(&s, &c->model, &c->options) : SDAE_ERR_NOMEM;
  if (rc == SDAE_OK) {
    slab(c, dim, j, p, pieces, lo, lo + dim);
    rc = sdae_certify_box(s, 0.0, lo, lo + dim, c->grid, NULL, r + F_ARGMAX, &cert);
    sdae_stepper_free(s);
  }
  free(lo);
  r[F_STATUS] = rc;
  if (rc != SDAE_OK) return;
  r[F_SUP] = cert.sup_neg_k, r[F_IMAX] = (double)cert.i_max, r[F_TBAR] = cert.T_bar;
  r[F_T15] = cert.T_thm5_scheme15, r[F_T11] = cert.T_thm5_scheme11;
  r[F_EVALS] = (double)cert.evaluations;
}

/* the slabs' results, in slab order, on rank 0: the best one printed */
static int report(double *all, size_t len, size_t pieces) {
  size_t best = 0;
  double evals = 0;
  for (size_t p = 0; p < pieces; p++) {
    const double *r = all + p * len;
    if (r[F_STATUS] != SDAE_OK) {
      int rc = (int)r[F_STATUS];
      fprintf(stderr, "%s: --certify: %s\n", ENS_PROG, sdae_strerror(rc));
      return rc == SDAE_ERR_PARAM ? CLI_EXIT_USAGE : CLI_EXIT_FAILED;
    }
    if (r[F_SUP] > all[best * len + F_SUP]) best = p;
    evals += r[F_EVALS];
  }
  const double *r = all + best * len;
  sdae_certificate cert = {r[F_SUP], (size_t)r[F_IMAX], r[F_TBAR],
                           r[F_T15], r[F_T11],          (size_t)evals};
  cli_certify_print(&cert, r + F_ARGMAX);
  printf("slabs: %zu\nevaluations: %zu\n", pieces, cert.evaluations);
  return CLI_EXIT_OK;
}

/* the first coordinate with lo < hi, or dim */
static size_t first_free(const cli_certify_setup *c, size_t dim) {
  size_t j = 0;
  while (j < dim && !(c->lo[j] < c->hi[j])) j++;
  return j;
}

int ens_certify(const ens_job *job, void *args) {
  int rank, ranks, rc = CLI_EXIT_OK;
  cli_certify_setup c;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  job->def->certify_setup(args, &c);
  size_t n_xi = c.model.n_xi, dim = n_xi + c.model.n_mu, j = first_free(&c, dim);
  size_t pieces = j < dim ? job->pieces : 1, len = F_ARGMAX + n_xi * dim;
  double *all = calloc(pieces * len, sizeof *all);
  if (!all) {
    fprintf(stderr, "%s: out of memory\n", ENS_PROG);
    MPI_Abort(MPI_COMM_WORLD, CLI_EXIT_FAILED);
  }
  for (size_t p = (size_t)rank; p < pieces; p += (size_t)ranks)
    certify_slab(&c, dim, j, p, pieces, all + p * len);
  for (size_t p = 0; p < pieces; p++) {
    int owner = (int)(p % (size_t)ranks);
    if (owner == 0) continue;
    if (rank == owner)
      MPI_Send(all + p * len, (int)len, MPI_DOUBLE, 0, (int)p, MPI_COMM_WORLD);
    else if (rank == 0)
      MPI_Recv(all + p * len, (int)len, MPI_DOUBLE, owner, (int)p, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
  }
  if (rank == 0) rc = report(all, len, pieces);
  free(all);
  return rc;
}
