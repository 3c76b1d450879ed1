/* SPDX-License-Identifier: GPL-3.0-or-later */
/* sparse_race: work-precision of the sparse back-end against SUNDIALS IDA with KLU on the same
 * mechanisms from the same callbacks (tools/ida: the index-1 form, its iteration matrix by KLU),
 * on a rope of 64 masses (examples/models/rope.h, open, at rest 0.3 rad below the horizontal)
 * to t = 1 and on a ladder of 16 four-bar cells between two walls (examples/models/truss.h) to
 * t = 0.1 (after it, the ladder's cells fold near configurations where every chart is poorly
 * conditioned, and the front-end's error there no longer falls steadily with T: issue of the
 * singular configurations), each from its start at rest: the CPU seconds of a whole run (set-up
 * included; the median of the repetitions) against the error of the positions at the end,
 * max_j abs(q_j - q_ref,j) over
 * max_j abs(q_ref,j), q_ref by GSL's rk8pd on the index-1 ODE at 1e-14 (index1_rk4.h). stabdae
 * by rk4 and rk8 and by the implicit dgrad and dg4 (Newton-Krylov on the sparse back-end) over a
 * sweep of T, IDA over a sweep of rtol (atol the same). A markdown table
 * on stdout; with --csv FILE the points as mechanism,solver,setting,seconds,error.
 *
 *   sparse_race [--reps R (1..15, default 3)] [--budget S (CPU seconds a point, default 2)]
 *               [--csv FILE]
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <stabdae/mbs.h>

#include "ida_mbs.h"
#include "index1_rk4.h"
#include "measure.h"
#include "rope.h"
#include "truss.h"

typedef struct race {
  const char *name;
  double tf; /* the run's end */
  sdae_mbs sys;
  double *q0, *v0, *ref, *q; /* n_q each: the start, the reference at tf, a run's end */
} race;

typedef struct point {
  const race *r;
  const sdae_map_type *map; /* NULL: IDA */
  double setting;           /* T, or IDA's rtol */
  int status;               /* the run's: 0, a library status, or IDA's */
} point;

static double error_of(const race *r) {
  double e = 0.0, size = 0.0;
  for (size_t i = 0; i < r->sys.n_q; i++)
    e = fmax(e, fabs(r->q[i] - r->ref[i])), size = fmax(size, fabs(r->ref[i]));
  return e / size;
}

static int keep_q(double t, const double *q, const double *v, const double *lambda, void *ctx) {
  race *r = ctx;
  (void)t, (void)v, (void)lambda;
  memcpy(r->q, q, r->sys.n_q * sizeof *q);
  return 0;
}

/* one whole run into r->q: stabdae's stepper built and stepped to tf, or IDA's solve */
static int run(void *p) {
  point *pt = p;
  race *r = (race *)pt->r;
  size_t n = r->sys.n_q;
  double *v = malloc(n * sizeof *v);
  if (!v) return pt->status = SDAE_ERR_NOMEM;
  memcpy(r->q, r->q0, n * sizeof *r->q), memcpy(v, r->v0, n * sizeof *v);
  if (pt->map) {
    sdae_options o;
    sdae_mbs_stepper *s;
    size_t steps = (size_t)lround(r->tf / pt->setting);
    sdae_options_default(&o);
    o.map = pt->map, o.delta = 2.0, o.epsilon = 1.0;
    pt->status = sdae_mbs_stepper_alloc(&s, &r->sys, &o);
    for (size_t k = 0; k < steps && pt->status == SDAE_OK; k++)
      pt->status = sdae_mbs_step(s, (double)k * pt->setting, pt->setting, r->q, v);
    sdae_mbs_stepper_free(s);
  } else {
    idaref_options o = {pt->setting, pt->setting, r->tf, r->tf, 1000000L};
    idaref_result res;
    pt->status = idambs_solve_with(&r->sys, IDAMBS_INDEX1, IDAMBS_KLU, 0.0, r->q0, r->v0, &o,
                                   keep_q, r, &res);
  }
  free(v);
  return pt->status != 0;
}

static void race_point(race *r, const sdae_map_type *map, double setting, int reps, double budget,
                       FILE *csv) {
  point pt = {r, map, setting, 0};
  const char *solver = map ? sdae_map_name(map) : "IDA/KLU index-1";
  double cpu = 0.0;
  wp_repeat(reps, budget, run, &pt, &cpu);
  printf("| %s | %s | %s %g |", r->name, solver, map ? "T" : "rtol", setting);
  if (pt.status != 0) {
    printf(" failed (%s) | - |\n", map ? sdae_strerror(pt.status) : "IDA");
    return;
  }
  printf(" %.3g | %.2g |\n", cpu, error_of(r));
  if (csv) fprintf(csv, "%s,%s,%g,%.6g,%.6g\n", r->name, solver, setting, cpu, error_of(r));
}

/* the reference at tf and the arrays; 0 or -1 */
static int race_init(race *r, const char *name, double tf) {
  size_t n = r->sys.n_q;
  index1_rk4 *w = index1_rk4_alloc(&r->sys);
  r->name = name, r->tf = tf;
  r->ref = malloc(n * sizeof *r->ref), r->q = malloc(n * sizeof *r->q);
  double *v = malloc(n * sizeof *v);
  int rc = w && r->ref && r->q && v ? 0 : -1;
  if (rc == 0) {
    memcpy(r->ref, r->q0, n * sizeof *r->ref), memcpy(v, r->v0, n * sizeof *v);
    rc = index1_reference(w, 0.0, r->tf, 1e-14, r->ref, v, NULL);
  }
  free(v);
  index1_rk4_free(w);
  return rc;
}

static void race_all(race *r, int reps, double budget, FILE *csv) {
  static const double rk4_T[] = {1e-2, 5e-3, 2.5e-3, 1.25e-3, 6.25e-4};
  static const double rk8_T[] = {2e-2, 1e-2, 5e-3, 2.5e-3};
  static const double dg_T[] = {1e-2, 5e-3, 2.5e-3, 1.25e-3};
  static const double rtol[] = {1e-4, 1e-6, 1e-8, 1e-10};
  for (size_t i = 0; i < sizeof rk4_T / sizeof *rk4_T; i++)
    race_point(r, sdae_map_rk4, rk4_T[i], reps, budget, csv);
  for (size_t i = 0; i < sizeof rk8_T / sizeof *rk8_T; i++)
    race_point(r, sdae_map_rk8, rk8_T[i], reps, budget, csv);
  for (size_t i = 0; i < sizeof dg_T / sizeof *dg_T; i++) /* the implicit maps: energy kept */
    race_point(r, sdae_map_dgrad, dg_T[i], reps, budget, csv);
  for (size_t i = 0; i < sizeof dg_T / sizeof *dg_T; i++)
    race_point(r, sdae_map_dg4, dg_T[i], reps, budget, csv);
  for (size_t i = 0; i < sizeof rtol / sizeof *rtol; i++)
    race_point(r, NULL, rtol[i], reps, budget, csv);
}

int main(int argc, char **argv) {
  double reps = 3, budget = 2;
  const char *csv_path = NULL;
  FILE *csv = NULL;
  mech_rope rope = mech_rope_unit(64, 0, 1);
  mech_truss ladder;
  race r[2] = {{0}, {0}};
  for (int i = 1; i < argc; i += 2) {
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    int rc = 0;
    if (!v) return wp_bad("sparse_race", "a flag without its value: ", argv[i]);
    if (strcmp(argv[i], "--reps") == 0)
      rc = wp_parse_positive("sparse_race", "--reps", v, WP_MAX_REPS, &reps);
    else if (strcmp(argv[i], "--budget") == 0)
      rc = wp_parse_positive("sparse_race", "--budget", v, 1e4, &budget);
    else if (strcmp(argv[i], "--csv") == 0)
      csv_path = v;
    else
      return wp_bad("sparse_race", "unknown flag: ", argv[i]);
    if (rc != 0) return rc;
  }
  if (csv_path && !(csv = fopen(csv_path, "w")))
    return wp_bad("sparse_race", "cannot write the CSV file ", csv_path);
  gsl_set_error_handler_off();
  if (mech_rope_system(&r[0].sys, &rope) != 0 || mech_truss_ladder(&ladder, 16, 1) != 0 ||
      mech_truss_system(&r[1].sys, &ladder) != 0) {
    fprintf(stderr, "sparse_race: out of memory\n");
    return 1;
  }
  for (int k = 0; k < 2; k++) {
    size_t n = r[k].sys.n_q;
    r[k].q0 = malloc(n * sizeof(double)), r[k].v0 = malloc(n * sizeof(double));
  }
  mech_rope_start(&rope, 0.3, r[0].q0, r[0].v0);
  mech_truss_start(&ladder, r[1].q0, r[1].v0);
  if (race_init(&r[0], "rope of 64 masses (t = 1)", 1.0) != 0 ||
      race_init(&r[1], "ladder of 16 cells (t = 0.1)", 0.1) != 0) {
    fprintf(stderr, "sparse_race: the reference failed\n");
    return 1;
  }
  if (csv) fprintf(csv, "mechanism,solver,setting,seconds,error\n");
  printf("| mechanism | solver | setting | CPU seconds | error at the end |\n"
         "|---|---|---|---:|---:|\n");
  for (int k = 0; k < 2; k++) race_all(&r[k], (int)reps, budget, csv);
  if (csv) fclose(csv);
  for (int k = 0; k < 2; k++) free(r[k].q0), free(r[k].v0), free(r[k].ref), free(r[k].q);
  mech_rope_free(&rope), mech_truss_free(&ladder);
  return 0;
}
