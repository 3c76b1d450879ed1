/* SPDX-License-Identifier: GPL-3.0-or-later */
/* rope_scale: a step's cost against the size of a mechanism, the rope of examples/models/rope.h
 * (N point masses on unit rods hung from the origin, 2N Cartesian coordinates, N constraints,
 * exact derivatives), from N = 8 up: the front-end's rk4 step on the rope given by its patterns
 * (the sparse coordinates, src/mbs/mbs_sparse.c) and, up to --dense-max, on the rope given
 * densely (the dense coordinates) and the classical RK4 on the index-1 form from the same
 * callbacks (index1_rk4.c, dense algebra); up to --implicit-max the implicit midpoint and
 * discrete-gradient maps on the rope's patterns (Newton-Krylov on the sparse back-end's linear
 * solve), with dgrad's Newton iterations and phi evaluations a step and its energy's largest
 * change relative to its size over the warm-up run; T = 1e-3, median CPU time of the thread
 * over the repetitions, and max abs(c) over the sparse run. For every N also SUNDIALS IDA on the
 * index-1 form with KLU on the rope's patterns (tools/ida/ida_mbs.h: the iteration matrix by
 * grouped differences of the residual, 14 groups at every N), rtol = atol = 1e-8, over 0.25 s from
 * the same start (the rope falling from rest, and its first swing): the median CPU time of the
 * thread of the whole idambs_solve_with call (its consistent start, the matrix's structure and
 * coloring, about 4 % of it at N = 4096, and the run) per 1e-3 s simulated, the time a step of the
 * others covers, and max abs(c) at its end (index 1 lets c drift). Its interval is the same at
 * every N and not cut to the budget, which sizes the fixed-step runs only: IDA's cost per simulated
 * time depends on the interval (its first steps are short). A Markdown table on stdout, one row per
 * N, and on stderr the sparse step's growth exponent between successive N and IDA's matrix (order,
 * nonzeros, column groups) and counters.
 *
 * With --rope closed, the rope fixed at both ends (its last mass on one more rod to an anchor
 * half its length from the origin: a closed loop, N + 1 constraints), N = 7, 15, ..., 2^k - 1
 * (its start needs N odd).
 *
 *   rope_scale [--max-n N (8..4096, default 4096)] [--dense-max N (default 256)]
 *              [--implicit-max N (default 1024)] [--stretch K (steps every run takes;
 *              default: as many as fit the budget, at most 2000)]
 *              [--reps R (1..15, default 5)] [--rope open|closed (default open)]
 *              [--budget S (seconds of CPU per stepper and N, default 0.5)] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <stabdae/mbs.h>

#include "ida_mbs.h"
#include "index1_rk4.h"
#include "measure.h"
#include "rope.h"

static const double T = 1e-3;
/* IDA's run: tolerances (rtol = atol) and its interval */
static const double IDA_TOL = 1e-8, IDA_TF = 0.25;

static double thread_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

typedef int (*step_fn)(void *stepper, double t, double *q, double *v);

static int frontend(void *s, double t, double *q, double *v) {
  return sdae_mbs_step(s, t, T, q, v);
}

static int baseline(void *w, double t, double *q, double *v) {
  return index1_rk4_step(w, t, T, q, v);
}

/* max abs(c) at q into *c_max, c (n_c values) the caller's */
static int track_c(const sdae_mbs *sys, const double *q, double *c, double *c_max) {
  int rc = sys->constraint(0.0, q, c, sys->params);
  for (size_t j = 0; rc == 0 && j < sys->n_c; j++) *c_max = fmax(*c_max, fabs(c[j]));
  return rc;
}

/* steps from the rope's start; the seconds per step, and max abs(c) over them when c_max (its
 * evaluations inside the timing: only the untimed warm-up asks for it) */
static int run(step_fn step, void *s, const mech_rope *r, const sdae_mbs *sys, size_t steps,
               double *per_step, double *c_max) {
  size_t n = 2 * r->N;
  double *q = malloc(n * sizeof *q), *v = malloc(n * sizeof *v), *c = malloc(sys->n_c * sizeof *c);
  double t0;
  int rc = q && v && c ? 0 : -1;
  if (rc == 0) mech_rope_start(r, 0.3, q, v);
  if (c_max) *c_max = 0.0;
  t0 = thread_seconds();
  for (size_t k = 0; k < steps && rc == 0; k++) {
    rc = step(s, (double)k * T, q, v);
    if (c_max && rc == 0) rc = track_c(sys, q, c, c_max);
  }
  *per_step = (thread_seconds() - t0) / (double)steps;
  free(q), free(v), free(c);
  return rc;
}

/* the stepper s (an mbs one) from the rope's start over steps: the largest change of the energy
 * relative to its size, and Newton iterations and phi evaluations a step */
static int drift(sdae_mbs_stepper *s, const mech_rope *r, size_t steps, double *dE, double *iters,
                 double *evals) {
  size_t n = 2 * r->N;
  double *q = malloc(n * sizeof *q), *v = malloc(n * sizeof *v), E0 = 0.0, E;
  const sdae_mbs_stats *st;
  int rc = q && v ? 0 : -1;
  if (rc == 0) mech_rope_start(r, 0.3, q, v);
  if (rc == 0) rc = sdae_mbs_energy(s, 0.0, q, v, &E0);
  sdae_mbs_stepper_reset_stats(s);
  *dE = 0.0;
  for (size_t k = 0; k < steps && rc == 0; k++) {
    rc = sdae_mbs_step(s, (double)k * T, T, q, v);
    if (rc == 0) rc = sdae_mbs_energy(s, (double)(k + 1) * T, q, v, &E);
    if (rc == 0) *dE = fmax(*dE, fabs(E - E0) / fabs(E0));
  }
  st = sdae_mbs_stepper_stats(s);
  *iters = (double)st->step.newton_iters_total / (double)steps;
  *evals = (double)st->step.phi_evals / (double)steps;
  free(q), free(v);
  return rc;
}

/* --stretch: the steps every run takes (0: by the budget) */
static size_t stretch = 0;

/* the steps a run takes: --stretch, or as many as fit the budget at probe seconds a step, at
 * most 2000 */
static size_t steps_of(int reps, double budget, double probe) {
  if (stretch > 0) return stretch;
  return probe > 0.0 ? (size_t)fmax(1.0, fmin(2000.0, budget / (reps * probe))) : 2000;
}

/* the median seconds per step over reps runs of steps each (a warm-up first, which measures max
 * abs(c)) */
static int timed_over(step_fn step, void *s, const mech_rope *r, const sdae_mbs *sys, int reps,
                      size_t steps, double *median, double *c_max) {
  double t[15];
  int rc = run(step, s, r, sys, steps, &t[0], c_max);
  for (int i = 0; i < reps && rc == 0; i++) rc = run(step, s, r, sys, steps, &t[i], NULL);
  qsort(t, (size_t)reps, sizeof *t, cmp_double);
  *median = t[reps / 2];
  return rc;
}

/* the same over as many steps a run as fit the budget by a single step's time, those steps into
 * *taken unless NULL */
static int timed(step_fn step, void *s, const mech_rope *r, const sdae_mbs *sys, int reps,
                 double budget, double *median, double *c_max, size_t *taken) {
  double probe;
  size_t steps;
  int rc = run(step, s, r, sys, 1, &probe, NULL);
  steps = steps_of(reps, budget, probe);
  if (taken) *taken = steps;
  return rc ? rc : timed_over(step, s, r, sys, reps, steps, median, c_max);
}

/* the positions of an IDA run's last row */
typedef struct last_q {
  size_t n_q;
  double *q;
} last_q;

static int keep_q(double t, const double *q, const double *v, const double *lambda, void *ctx) {
  const last_q *e = ctx;
  (void)t, (void)v, (void)lambda;
  memcpy(e->q, q, e->n_q * sizeof *q);
  return 0;
}

/* IDA/KLU on the rope from its start over IDA_TF: the thread's CPU seconds of the call, and
 * max abs(c) at its end and the counters when c_end */
static int ida_run(const mech_rope *r, const sdae_mbs *sys, double *seconds, double *c_end,
                   idaref_stats *stats) {
  size_t n = 2 * r->N;
  double *q = malloc(n * sizeof *q), *v = malloc(n * sizeof *v), *c = malloc(sys->n_c * sizeof *c);
  idaref_options o = {IDA_TOL, IDA_TOL, IDA_TF, IDA_TF, 1000000L};
  idaref_result res;
  last_q end = {n, q};
  double t0;
  int rc = q && v && c ? 0 : -1;
  if (rc == 0) mech_rope_start(r, 0.3, q, v);
  t0 = thread_seconds();
  if (rc == 0)
    rc = idambs_solve_with(sys, IDAMBS_INDEX1, IDAMBS_KLU, 0.0, q, v, &o, keep_q, &end, &res);
  *seconds = thread_seconds() - t0;
  if (rc != 0 && q && v && c)
    fprintf(stderr, "rope_scale: IDA/KLU at N = %zu: %s failed with %s at t = %g: %s\n", r->N,
            res.function ? res.function : "?", res.flag_name, res.t_reached, res.message);
  if (rc == 0 && c_end) {
    *c_end = 0.0;
    rc = track_c(sys, q, c, c_end);
    *stats = res.stats;
  }
  free(q), free(v), free(c);
  return rc;
}

/* the median seconds of reps IDA runs after a warm-up (which gives max abs(c) and the counters),
 * per 1e-3 s simulated */
static int ida_timed(const mech_rope *r, const sdae_mbs *sys, int reps, double *per_ms,
                     double *c_end) {
  double t[15], warm;
  idaref_stats st;
  size_t order, nnz, groups;
  int rc = ida_run(r, sys, &warm, c_end, &st);
  for (int i = 0; i < reps && rc == 0; i++) rc = ida_run(r, sys, &t[i], NULL, NULL);
  if (rc != 0) return rc;
  qsort(t, (size_t)reps, sizeof *t, cmp_double);
  *per_ms = t[reps / 2] / (IDA_TF / 1e-3);
  if (idambs_klu_structure(sys, &order, &nnz, &groups) == 0)
    fprintf(stderr,
            "rope_scale: N = %zu: IDA/KLU matrix of order %zu, %zu nonzeros, %zu groups; %ld "
            "steps, %ld Newton iterations, %ld matrices (%ld residuals), %ld error test and %ld "
            "Newton failures\n",
            r->N, order, nnz, groups, st.steps, st.nonlin_iters, st.jac_evals,
            st.res_evals + st.lin_res_evals, st.err_test_fails, st.nonlin_conv_fails);
  return 0;
}

/* a time as the table's cell: microseconds, or "-" when not measured */
static void cell(double seconds) {
  if (seconds > 0.0)
    printf(" %.1f |", 1e6 * seconds);
  else
    printf(" - |");
}

/* the implicit maps on the rope's patterns over the steps rk4's runs took (the same stretch of
 * the motion, the later steps costing more Newton iterations): midpoint's and dgrad's seconds a
 * step, and dgrad's energy drift, Newton iterations and phi evaluations a step */
typedef struct implicit_cells {
  double mid, dgrad, dE, iters, evals;
} implicit_cells;

static int implicit_row(const mech_rope *r, const sdae_mbs *sys, const sdae_options *o, int reps,
                        size_t steps, implicit_cells *ic) {
  sdae_options om = *o;
  sdae_mbs_stepper *sm = NULL, *sg = NULL;
  double c_other;
  int rc;
  om.map = sdae_map_midpoint;
  if ((rc = sdae_mbs_stepper_alloc(&sm, sys, &om)) == 0)
    rc = timed_over(frontend, sm, r, sys, reps, steps, &ic->mid, &c_other);
  om.map = sdae_map_dgrad;
  if (rc == 0 && (rc = sdae_mbs_stepper_alloc(&sg, sys, &om)) == 0)
    rc = timed_over(frontend, sg, r, sys, reps, steps, &ic->dgrad, &c_other);
  if (rc == 0) rc = drift(sg, r, steps, &ic->dE, &ic->iters, &ic->evals);
  sdae_mbs_stepper_free(sm);
  sdae_mbs_stepper_free(sg);
  return rc;
}

/* the front-end on the rope given by its patterns (the sparse coordinates); up to dense_max
 * also on the rope given densely and the index-1 baseline (dense algebra), up to implicit_max
 * the implicit maps on the patterns */
static int row(size_t N, int closed, size_t dense_max, size_t implicit_max, int reps, double budget,
               double *us_sparse) {
  mech_rope r = mech_rope_unit(N, closed, 1), rd = r;
  sdae_mbs sys, dense;
  sdae_options o;
  sdae_mbs_stepper *s = NULL, *sd = NULL;
  index1_rk4 *w = NULL;
  implicit_cells ic = {0};
  size_t steps = 0;
  double c_sparse, c_other, us_dense = 0.0, us_rk4 = 0.0, ida_ms = 0.0, c_ida = 0.0;
  int rc = mech_rope_system(&sys, &r);
  rd.sparse = 0;
  if (rc == 0) rc = mech_rope_system(&dense, &rd);
  sdae_options_default(&o);
  o.map = sdae_map_rk4, o.delta = 2.0, o.epsilon = 1.0;
  if (rc == 0) rc = sdae_mbs_stepper_alloc(&s, &sys, &o);
  if (rc == 0) rc = timed(frontend, s, &r, &sys, reps, budget, us_sparse, &c_sparse, &steps);
  if (rc == 0) rc = ida_timed(&r, &sys, reps, &ida_ms, &c_ida);
  if (rc == 0 && N <= dense_max) {
    if ((rc = sdae_mbs_stepper_alloc(&sd, &dense, &o)) == 0)
      rc = timed(frontend, sd, &rd, &dense, reps, budget, &us_dense, &c_other, NULL);
    if (rc == 0 && !(w = index1_rk4_alloc(&dense))) rc = -1;
    if (rc == 0) rc = timed(baseline, w, &rd, &dense, reps, budget, &us_rk4, &c_other, NULL);
  }
  if (rc == 0 && N <= implicit_max) rc = implicit_row(&r, &sys, &o, reps, steps, &ic);
  if (rc == 0) {
    printf("| %zu | %zu | %zu |", N, 2 * N, sdae_mbs_stepper_size(&sys, &o));
    cell(*us_sparse), cell(us_dense), cell(ic.mid), cell(ic.dgrad), cell(us_rk4);
    printf(" %.1e |", c_sparse);
    if (N <= implicit_max)
      printf(" %.1e | %.2f | %.1f |", ic.dE, ic.iters, ic.evals);
    else
      printf(" - | - | - |");
    cell(ida_ms);
    printf(" %.1e |\n", c_ida);
  }
  sdae_mbs_stepper_free(s);
  sdae_mbs_stepper_free(sd);
  index1_rk4_free(w);
  mech_rope_free(&r);
  mech_rope_free(&rd);
  return rc;
}

int main(int argc, char **argv) {
  double max_n = 4096, dense_max = 256, implicit_max = 1024, reps = 5, budget = 0.5, prev = 0.0;
  double stretch_steps = 0;
  int closed = 0;
  for (int i = 1; i < argc; i += 2) {
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    int rc;
    if (!v) return wp_bad("rope_scale", "a flag without its value: ", argv[i]);
    if (strcmp(argv[i], "--max-n") == 0)
      rc = wp_parse_positive("rope_scale", "--max-n", v, 4096, &max_n);
    else if (strcmp(argv[i], "--dense-max") == 0)
      rc = wp_parse_positive("rope_scale", "--dense-max", v, 4096, &dense_max);
    else if (strcmp(argv[i], "--stretch") == 0) {
      rc = wp_parse_positive("rope_scale", "--stretch", v, 1e5, &stretch_steps);
      stretch = (size_t)stretch_steps;
    } else if (strcmp(argv[i], "--implicit-max") == 0)
      rc = wp_parse_positive("rope_scale", "--implicit-max", v, 4096, &implicit_max);
    else if (strcmp(argv[i], "--reps") == 0)
      rc = wp_parse_positive("rope_scale", "--reps", v, WP_MAX_REPS, &reps);
    else if (strcmp(argv[i], "--budget") == 0)
      rc = wp_parse_positive("rope_scale", "--budget", v, 600, &budget);
    else if (strcmp(argv[i], "--rope") == 0 && (!strcmp(v, "open") || !strcmp(v, "closed")))
      rc = 0, closed = strcmp(v, "closed") == 0;
    else if (strcmp(argv[i], "--rope") == 0)
      return wp_bad("rope_scale", "--rope is open or closed, not ", v);
    else
      return wp_bad("rope_scale", "unknown flag: ", argv[i]);
    if (rc != 0) return rc;
  }
  if (max_n < 8) return wp_bad("rope_scale", "--max-n below 8: ", "the smallest rope");
  printf("| N | coordinates | stepper bytes (sparse) | rk4 sparse, us/step | rk4 dense, us/step | "
         "midpoint sparse, us/step | dgrad sparse, us/step | index-1 RK4, us/step | "
         "max abs(c), sparse | dgrad energy drift | dgrad Newton iterations/step | "
         "dgrad phi evaluations/step | IDA/KLU index-1, us per 1e-3 s simulated | "
         "max abs(c), IDA end |\n"
         "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (size_t N = closed ? 7 : 8; N <= (size_t)max_n; N = closed ? 2 * N + 1 : 2 * N) {
    double front;
    if (row(N, closed, (size_t)dense_max, (size_t)implicit_max, (int)reps, budget, &front) != 0) {
      fprintf(stderr, "rope_scale: N = %zu failed\n", N);
      return 1;
    }
    if (prev > 0.0)
      fprintf(stderr, "rope_scale: N = %zu: growth exponent %.2f\n", N, log2(front / prev));
    prev = front;
  }
  return 0;
}
