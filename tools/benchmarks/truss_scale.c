/* SPDX-License-Identifier: GPL-3.0-or-later */
/* truss_scale: the sparse back-end on the topologies of examples/models/truss.h (a cart under k
 * pendulums, a ladder of four-bar cells, a cloth in space, a binary tree), each at growing
 * sizes: rk4's CPU time a step (the median over repetitions of 20 steps, T = 1e-3, the stepper
 * kept between them), the nonzeros of M and G, the growth exponent of the time against them
 * between two sizes, and up to --dense-max coordinates the error after 0.2 s of the sparse and
 * the dense rk4 against the dense rk8 at T / 4 (the depth of a tree is not scaled). A size whose
 * stepper cannot be built or stepped is reported with the library's reason. A markdown table on
 * stdout.
 *
 *   truss_scale [--reps R (1..15, default 5)] [--budget S (CPU seconds per size, default 0.5)]
 *               [--dense-max N (coordinates, default 256)] [--scale X (sizes times X, default 1)]
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stabdae/mbs.h>

#include "measure.h"
#include "truss.h"

static const double T = 1e-3;
enum { CHUNK = 20, SIZES = 4 };

typedef struct topology {
  const char *name, *size_name;
  int (*build)(mech_truss *, size_t, int);
  size_t sizes[SIZES], least; /* the least size the builder takes */
} topology;

static const topology topologies[] = {
    {"cart under k pendulums", "k", mech_truss_star, {25, 50, 100, 200}, 1},
    {"ladder of n four-bar cells", "n", mech_truss_ladder, {4, 8, 16, 24}, 3},
    {"cloth of n x n masses", "n", mech_truss_cloth, {4, 6, 8, 12}, 2},
    {"binary tree of depth d", "d", mech_truss_tree, {4, 5, 6, 7}, 1},
};

typedef struct stepping {
  sdae_mbs_stepper *s;
  double *q, *v, t;
  int status; /* the first failed step's */
} stepping;

static int chunk(void *p) {
  stepping *w = p;
  for (int k = 0; k < CHUNK && w->status == SDAE_OK; k++, w->t += T)
    w->status = sdae_mbs_step(w->s, w->t, T, w->q, w->v);
  return w->status != SDAE_OK;
}

/* a stepper of the truss by map (sparse: with its patterns) at its start into w: 0 or the
 * library's status */
static int start(const topology *tp, size_t size, int sparse, const sdae_map_type *map,
                 mech_truss *p, stepping *w) {
  sdae_mbs sys;
  sdae_options o;
  if (tp->build(p, size, sparse) != 0 || mech_truss_system(&sys, p) != 0) return SDAE_ERR_NOMEM;
  w->q = malloc(sys.n_q * sizeof *w->q), w->v = malloc(sys.n_q * sizeof *w->v), w->t = 0.0;
  w->status = SDAE_OK;
  if (!w->q || !w->v) return SDAE_ERR_NOMEM;
  mech_truss_start(p, w->q, w->v);
  sdae_options_default(&o);
  o.map = map, o.delta = 2.0, o.epsilon = 1.0;
  return sdae_mbs_stepper_alloc(&w->s, &sys, &o);
}

static void finish(mech_truss *p, stepping *w) {
  sdae_mbs_stepper_free(w->s);
  free(w->q), free(w->v);
  mech_truss_free(p);
  memset(w, 0, sizeof *w);
}

/* q after 0.2 s by map at step h, into out (n values): 0 or the status */
static int motion(const topology *tp, size_t size, int sparse, const sdae_map_type *map, double h,
                  double *out, size_t n) {
  mech_truss p;
  stepping w = {0};
  int rc = start(tp, size, sparse, map, &p, &w);
  size_t steps = (size_t)lround(0.2 / h);
  for (size_t k = 0; rc == SDAE_OK && k < steps; k++) rc = sdae_mbs_step(w.s, k * h, h, w.q, w.v);
  if (rc == SDAE_OK) memcpy(out, w.q, n * sizeof *out);
  finish(&p, &w);
  return rc;
}

static double max_diff(const double *a, const double *b, size_t n) {
  double m = 0.0;
  for (size_t i = 0; i < n; i++) m = fmax(m, fabs(a[i] - b[i]));
  return m;
}

/* the two errors after 0.2 s (sparse, dense), or NaN where a run fails */
static void errors(const topology *tp, size_t size, size_t n, double *e_sparse, double *e_dense) {
  double *ref = malloc(n * sizeof *ref), *q = malloc(n * sizeof *q);
  *e_sparse = *e_dense = NAN;
  if (ref && q && motion(tp, size, 0, sdae_map_rk8, T / 4, ref, n) == SDAE_OK) {
    if (motion(tp, size, 1, sdae_map_rk4, T, q, n) == SDAE_OK) *e_sparse = max_diff(q, ref, n);
    if (motion(tp, size, 0, sdae_map_rk4, T, q, n) == SDAE_OK) *e_dense = max_diff(q, ref, n);
  }
  free(ref), free(q);
}

static void row(const topology *tp, size_t size, int reps, double budget, size_t dense_max,
                double *last_t, double *last_nnz) {
  mech_truss p;
  stepping w = {0};
  double cpu = 0.0, e_sparse = NAN, e_dense = NAN, nnz;
  int rc = start(tp, size, 1, sdae_map_rk4, &p, &w);
  size_t n_q = p.n_masses * p.dim;
  nnz = (double)(p.mass_pattern.nnz + p.jacobian_pattern.nnz);
  if (rc == SDAE_OK) wp_repeat(reps, budget, chunk, &w, &cpu);
  if (rc == SDAE_OK) rc = w.status; /* a run that failed: its step's status */
  finish(&p, &w);
  printf("| %s | %s = %zu | %zu | %.0f |", tp->name, tp->size_name, size, n_q, nnz);
  if (rc != SDAE_OK) {
    printf(" %s | - | - | - |\n", sdae_strerror(rc));
    *last_t = 0.0;
    return;
  }
  cpu /= CHUNK;
  if (n_q <= dense_max) errors(tp, size, n_q, &e_sparse, &e_dense);
  printf(" %.1f |", 1e6 * cpu);
  if (*last_t > 0.0 && nnz > *last_nnz)
    printf(" %.2f |", log(cpu / *last_t) / log(nnz / *last_nnz));
  else
    printf(" - |");
  if (isnan(e_sparse) || isnan(e_dense))
    printf(" - | - |\n");
  else
    printf(" %.2g | %.2g |\n", e_sparse, e_dense);
  *last_t = cpu, *last_nnz = nnz;
}

int main(int argc, char **argv) {
  double reps = 5, budget = 0.5, dense_max = 256, scale = 1;
  for (int i = 1; i < argc; i += 2) {
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    int rc;
    if (!v) return wp_bad("truss_scale", "a flag without its value: ", argv[i]);
    if (strcmp(argv[i], "--reps") == 0)
      rc = wp_parse_positive("truss_scale", "--reps", v, WP_MAX_REPS, &reps);
    else if (strcmp(argv[i], "--budget") == 0)
      rc = wp_parse_positive("truss_scale", "--budget", v, 1e4, &budget);
    else if (strcmp(argv[i], "--dense-max") == 0)
      rc = wp_parse_positive("truss_scale", "--dense-max", v, 1e4, &dense_max);
    else if (strcmp(argv[i], "--scale") == 0)
      rc = wp_parse_positive("truss_scale", "--scale", v, 64, &scale);
    else
      return wp_bad("truss_scale", "unknown flag: ", argv[i]);
    if (rc != 0) return rc;
  }
  printf(
      "| topology | size | coordinates | nnz(M) + nnz(G) | rk4 sparse, us/step | growth "
      "exponent | error sparse rk4 | error dense rk4 |\n|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (size_t k = 0; k < sizeof topologies / sizeof topologies[0]; k++) {
    double last_t = 0.0, last_nnz = 0.0;
    for (int i = 0; i < SIZES; i++) {
      size_t size = topologies[k].sizes[i];
      if (topologies[k].build != mech_truss_tree) size = (size_t)lround((double)size * scale);
      if (size < topologies[k].least) size = topologies[k].least;
      row(&topologies[k], size, (int)reps, budget, (size_t)dense_max, &last_t, &last_nnz);
    }
  }
  return 0;
}
