/* SPDX-License-Identifier: GPL-3.0-or-later */
/* benchmarks: the race on the standard index-3 benchmarks (examples/models/benchmarks.h): the
 * final error against CPU time for stabdae's mechanical front-end, each suitable map over a
 * sweep of the step T, beside SUNDIALS IDA from the same callbacks (tools/ida/ida_mbs.h, its
 * index-1 and GGL forms) over a sweep of rtol, all measured in one run.
 *
 *   benchmarks [--problems a,b,...] [--out FILE] [--reps N] [--budget S] [--smoke]
 *
 * The references: the car axis and Andrews' mechanism the Test Set's solutions at their end
 * times; the slider crank the ODE q' = v, v' = M^-1 (F - G^T lambda) (lambda from the
 * acceleration-level constraint, tools/ida's idambs_lambda) by GSL's rk8pd at 1e-14, computed
 * here first; its distance to IDA's index-1 form at rtol 1e-12 is printed on stderr. The error is
 * max_i |q_i - q_ref,i| / max_i |q_ref,i| (err_q, and err_v alike for the velocities).
 * Evaluations are the mechanism's callback calls, counted by the same wrapper for both solvers.
 * CPU time is the process's for the whole run, set-up included; the median over up to N
 * repetitions, fewer once a point has used S seconds. A sweep stops once its error is below
 * 1e-12 or a run has taken 5 s. --smoke: two points per setting, one repetition.
 *
 * CSV (%.17g): problem,solver,setting,param,steps,evals,rhs,newton,reps,cpu_s,err_q,err_v,
 * status; rhs counts the evaluations of the discretized dynamics (stabdae's map phi, IDA's
 * residual, those for its difference-quotient Jacobian included), each of which costs callbacks;
 * newton is stabdae's Newton iterations (the stages' included) or IDA's nonlinear iterations;
 * status is ok or why a run failed (a failed run is a point, not the end of the study). Bad
 * input: one line on stderr, exit 2, no file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <stabdae/mbs.h>

#include "benchmarks.h"
#include "ida_mbs.h"
#include "measure.h"

#define PROG "benchmarks"

enum { MAX_Q = 7 };

/* ---- the mechanisms, with their callbacks counted ------------------------------------------ */

typedef struct counted {
  sdae_mbs inner;
  unsigned long calls;
} counted;

#define FORWARD(name, sig, args)                                                                   \
  static int counted_##name sig {                                                                  \
    counted *k = params;                                                                           \
    k->calls++;                                                                                    \
    return k->inner.name args;                                                                     \
  }
FORWARD(mass, (double t, const double *q, double *M, void *params), (t, q, M, k->inner.params))
FORWARD(force, (double t, const double *q, const double *v, double *F, void *params),
        (t, q, v, F, k->inner.params))
FORWARD(constraint, (double t, const double *q, double *c, void *params),
        (t, q, c, k->inner.params))
FORWARD(jacobian, (double t, const double *q, double *G, void *params), (t, q, G, k->inner.params))
FORWARD(constraint_t, (double t, const double *q, double *ct, void *params),
        (t, q, ct, k->inner.params))
FORWARD(potential, (double t, const double *q, double *V, void *params), (t, q, V, k->inner.params))
FORWARD(damping, (double t, const double *q, double *D, void *params), (t, q, D, k->inner.params))
FORWARD(mass_dot_v, (double t, const double *q, const double *v, double *out, void *params),
        (t, q, v, out, k->inner.params))
FORWARD(jacobian_dot, (double t, const double *q, const double *v, double *Gdot, void *params),
        (t, q, v, Gdot, k->inner.params))
FORWARD(constraint_t_dot, (double t, const double *q, const double *v, double *out, void *params),
        (t, q, v, out, k->inner.params))
#undef FORWARD

/* the same mechanism, every callback it has counted in k->calls */
static sdae_mbs counting(counted *k) {
  const sdae_mbs *s = &k->inner;
  return (sdae_mbs){.n_q = s->n_q,
                    .n_c = s->n_c,
                    .mass = counted_mass,
                    .force = counted_force,
                    .constraint = counted_constraint,
                    .jacobian = s->jacobian ? counted_jacobian : NULL,
                    .constraint_t = s->constraint_t ? counted_constraint_t : NULL,
                    .potential = s->potential ? counted_potential : NULL,
                    .damping = s->damping ? counted_damping : NULL,
                    .mass_dot_v = s->mass_dot_v ? counted_mass_dot_v : NULL,
                    .jacobian_dot = s->jacobian_dot ? counted_jacobian_dot : NULL,
                    .constraint_t_dot = s->constraint_t_dot ? counted_constraint_t_dot : NULL,
                    .params = k};
}

/* ---- the problems --------------------------------------------------------------------------- */

typedef struct problem {
  const char *name;
  double tf;
  double n_first, n_last;  /* the sweep of steps per unit time: T = 1/n .. */
  const char *const *maps; /* the suitable maps, by the library's names */
  union {
    bench_slider_crank slider_crank;
    bench_car_axis car_axis;
    bench_andrews andrews;
  } p;
  sdae_mbs sys;
  double q0[MAX_Q], v0[MAX_Q], q_ref[MAX_Q], v_ref[MAX_Q];
} problem;

static const char *const gradient_maps[] = {"midpoint", "midpoint4", "midpoint6", "dgrad", "dg4",
                                            "dg6",      "rk4",       "rk8",       NULL};
static const char *const any_force_maps[] = {"midpoint", "midpoint4", "midpoint6",
                                             "rk4",      "rk8",       NULL};

static void setup_slider_crank(problem *pb) {
  pb->p.slider_crank = bench_slider_crank_default();
  bench_slider_crank_system(&pb->sys, &pb->p.slider_crank);
  bench_slider_crank_initial(&pb->p.slider_crank, pb->q0, pb->v0);
}

static void setup_car_axis(problem *pb) {
  pb->p.car_axis = bench_car_axis_default();
  bench_car_axis_system(&pb->sys, &pb->p.car_axis);
  bench_car_axis_initial(&pb->p.car_axis, pb->q0, pb->v0);
  double lambda[2];
  bench_car_axis_reference(pb->q_ref, pb->v_ref, lambda);
}

static void setup_andrews(problem *pb) {
  bench_andrews_default(&pb->p.andrews);
  bench_andrews_system(&pb->sys, &pb->p.andrews);
  bench_andrews_initial(pb->q0, pb->v0);
  double lambda[6];
  bench_andrews_reference(pb->q_ref, pb->v_ref, lambda);
}

typedef struct problem_def {
  const char *name;
  double tf, n_first, n_last;
  const char *const *maps;
  void (*setup)(problem *pb);
} problem_def;

static const problem_def problems[] = {
    {"slider_crank", 10.0, 10.0, 1e5, gradient_maps, setup_slider_crank},
    {"car_axis", 3.0, 100.0, 1e6, any_force_maps, setup_car_axis},
    {"andrews", 0.03, 1e4, 1e8, gradient_maps, setup_andrews},
};
enum { NPROBLEMS = sizeof problems / sizeof problems[0] };

/* ---- one run of either solver --------------------------------------------------------------- */

typedef struct outcome {
  double q[MAX_Q], v[MAX_Q];
  long steps;
  unsigned long evals, rhs, newton;
  char status[160];
} outcome;

typedef struct trial {
  const problem *pb;
  const sdae_map_type *map; /* stabdae's, or NULL for IDA */
  idambs_form form;
  double param; /* T, or rtol */
  outcome o;
} trial;

static int stabdae_run(void *ctx) {
  trial *tr = ctx;
  const problem *pb = tr->pb;
  counted k = {pb->sys, 0};
  sdae_mbs sys = counting(&k);
  sdae_options opt;
  sdae_mbs_stepper *s = NULL;
  size_t n = (size_t)llround(pb->tf / tr->param), done = 0;
  sdae_options_default(&opt);
  opt.delta = 2.0;
  opt.map = tr->map;
  memcpy(tr->o.q, pb->q0, sizeof pb->q0);
  memcpy(tr->o.v, pb->v0, sizeof pb->v0);
  int rc = sdae_mbs_stepper_alloc(&s, &sys, &opt);
  if (rc == SDAE_OK)
    rc = sdae_mbs_integrate(s, 0.0, tr->param, n, n, tr->o.q, tr->o.v, NULL, NULL, &done);
  if (s) {
    const sdae_mbs_stats *st = sdae_mbs_stepper_stats(s);
    tr->o.newton = st->step.newton_iters_total, tr->o.rhs = st->step.phi_evals;
  }
  sdae_mbs_stepper_free(s);
  tr->o.steps = (long)done, tr->o.evals = k.calls;
  if (rc == SDAE_OK)
    snprintf(tr->o.status, sizeof tr->o.status, "ok");
  else
    snprintf(tr->o.status, sizeof tr->o.status, "%s after %zu steps", sdae_strerror(rc), done);
  return rc != SDAE_OK;
}

static int keep_last(double t, const double *q, const double *v, const double *lambda, void *ctx) {
  trial *tr = ctx;
  size_t n = tr->pb->sys.n_q;
  (void)t, (void)lambda;
  memcpy(tr->o.q, q, n * sizeof *q);
  memcpy(tr->o.v, v, n * sizeof *v);
  return 0;
}

/* atol = rtol times the size of the start's positions */
static int ida_run(void *ctx) {
  trial *tr = ctx;
  const problem *pb = tr->pb;
  counted k = {pb->sys, 0};
  sdae_mbs sys = counting(&k);
  double scale = 0.0;
  for (size_t i = 0; i < pb->sys.n_q; i++) scale = fmax(scale, fabs(pb->q0[i]));
  idaref_options opt = {tr->param, tr->param * scale, pb->tf, pb->tf, 100000000L};
  idaref_result res;
  int rc = idambs_solve(&sys, tr->form, 0.0, pb->q0, pb->v0, &opt, keep_last, tr, &res);
  tr->o.steps = res.stats.steps, tr->o.evals = k.calls;
  tr->o.newton = (unsigned long)res.stats.nonlin_iters;
  tr->o.rhs = (unsigned long)(res.stats.res_evals + res.stats.lin_res_evals);
  if (rc == IDAREF_OK)
    snprintf(tr->o.status, sizeof tr->o.status, "ok");
  else
    snprintf(tr->o.status, sizeof tr->o.status, "%s in %s at t = %g", res.flag_name,
             res.function ? res.function : "?", res.t_reached);
  return rc != IDAREF_OK;
}

/* ---- the study ------------------------------------------------------------------------------ */

typedef struct settings {
  int reps, smoke;
  double budget;
  FILE *out;
} settings;

static double relative_error(const double *x, const double *ref, size_t n) {
  double diff = 0.0, size = 0.0;
  for (size_t i = 0; i < n; i++) {
    diff = fmax(diff, fabs(x[i] - ref[i]));
    size = fmax(size, fabs(ref[i]));
  }
  return diff / size;
}

/* Runs and writes one point; returns its err_q (NaN when it failed) and its CPU time. */
static double point(const settings *s, trial *tr, const char *solver, const char *setting,
                    double *cpu) {
  int (*run)(void *) = tr->map ? stabdae_run : ida_run;
  int reps = wp_repeat(s->smoke ? 1 : s->reps, s->budget, run, tr, cpu);
  size_t n = tr->pb->sys.n_q;
  int ok = strcmp(tr->o.status, "ok") == 0;
  double eq = ok ? relative_error(tr->o.q, tr->pb->q_ref, n) : NAN;
  double ev = ok ? relative_error(tr->o.v, tr->pb->v_ref, n) : NAN;
  fprintf(s->out, "%s,%s,%s,%.17g,%ld,%lu,%lu,%lu,%d,%.17g,%.17g,%.17g,%s\n", tr->pb->name, solver,
          setting, tr->param, tr->o.steps, tr->o.evals, tr->o.rhs, tr->o.newton, reps, *cpu, eq, ev,
          tr->o.status);
  fflush(s->out);
  fprintf(stderr, "%s: %s %s %g: error %.3g, %.3g s CPU (%d reps)%s%s\n", tr->pb->name, solver,
          setting, tr->param, eq, *cpu, reps, ok ? "" : ", ", ok ? "" : tr->o.status);
  return eq;
}

/* the sweep stops at rounding level, after a long run, or after two points in a smoke run */
static int sweep_done(const settings *s, int points, double error, double cpu) {
  return error < 1e-12 || cpu > 5.0 || (s->smoke && points >= 2);
}

/* step counts n tf with n = n_first .. n_last per unit time, sqrt(10) apart; T = tf / steps */
static void stabdae_sweep(const settings *s, const problem *pb, const char *map) {
  trial tr = {.pb = pb, .map = sdae_map_by_name(map)};
  int points = 0;
  /* orders 4, 6 and 8 start sqrt(10), 10 and 10^1.5 times coarser: already accurate there */
  double first = log10(pb->n_first) - (sdae_map_order(tr.map) - 2) / 4.0;
  for (double e = first; e <= log10(pb->n_last) + 1e-9; e += 0.5) {
    double cpu;
    tr.param = pb->tf / round(pb->tf * pow(10.0, e));
    double err = point(s, &tr, "stabdae", map, &cpu);
    if (sweep_done(s, ++points, err, cpu)) break;
  }
}

static void ida_sweep(const settings *s, const problem *pb, idambs_form form, const char *name) {
  trial tr = {.pb = pb, .form = form};
  int points = 0;
  for (double e = 3.0; e <= 12.0 + 1e-9; e += 1.0) {
    double cpu;
    tr.param = pow(10.0, -e);
    double err = point(s, &tr, "ida", name, &cpu);
    if (sweep_done(s, ++points, err, cpu)) break;
  }
}

/* the index-1 ODE of the mechanism for GSL: y = (q, v) */
static int ode(double t, const double *y, double *dydt, void *params) {
  const problem *pb = params;
  size_t n = pb->sys.n_q;
  double lambda[MAX_Q];
  memcpy(dydt, y + n, n * sizeof *y);
  return idambs_lambda(&pb->sys, t, y, y + n, lambda, dydt + n) ? GSL_EBADFUNC : GSL_SUCCESS;
}

/* The slider crank's reference by rk8pd at 1e-14 (the drift off c = 0 of the index-1 ODE grows
 * only with its local errors, at that tolerance far below the 1e-9 studied); its distance to
 * IDA's index-1 form at rtol 1e-12 on stderr. 0, or -1 when either fails. */
static int ode_reference(problem *pb) {
  size_t n = pb->sys.n_q;
  double y[2 * MAX_Q], t = 0.0;
  gsl_odeiv2_system sys = {ode, NULL, 2 * n, pb};
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-3, 1e-14, 1e-14);
  trial ida = {.pb = pb, .form = IDAMBS_INDEX1, .param = 1e-12};
  memcpy(y, pb->q0, n * sizeof *y);
  memcpy(y + n, pb->v0, n * sizeof *y);
  int rc = d ? gsl_odeiv2_driver_apply(d, &t, pb->tf, y) : GSL_ENOMEM;
  gsl_odeiv2_driver_free(d);
  if (rc != GSL_SUCCESS || ida_run(&ida)) {
    fprintf(stderr, PROG ": the %s reference failed: %s / %s\n", pb->name, gsl_strerror(rc),
            ida.o.status);
    return -1;
  }
  memcpy(pb->q_ref, y, n * sizeof *y);
  memcpy(pb->v_ref, y + n, n * sizeof *y);
  fprintf(stderr,
          "%s: reference rk8pd at 1e-14; IDA index1 at rtol 1e-12 differs by %.3g (q), "
          "%.3g (v), relative\n",
          pb->name, relative_error(ida.o.q, pb->q_ref, n), relative_error(ida.o.v, pb->v_ref, n));
  return 0;
}

static int study(const settings *s, const problem_def *def) {
  problem pb = {.name = def->name,
                .tf = def->tf,
                .n_first = def->n_first,
                .n_last = def->n_last,
                .maps = def->maps};
  def->setup(&pb);
  if (strcmp(def->name, "slider_crank") == 0 && ode_reference(&pb)) return -1;
  for (const char *const *m = pb.maps; *m; m++) stabdae_sweep(s, &pb, *m);
  ida_sweep(s, &pb, IDAMBS_INDEX1, "index1");
  ida_sweep(s, &pb, IDAMBS_GGL, "ggl");
  return 0;
}

/* ---- input ---------------------------------------------------------------------------------- */

static const char usage[] =
    "usage: " PROG " [--problems a,b,...] [--out FILE] [--reps N] [--budget S] [--smoke]\n"
    "  --problems LIST  some of slider_crank,car_axis,andrews (default: all three)\n"
    "  --out FILE       CSV (default: stdout)\n"
    "  --reps N         repetitions per point, median CPU time (1..15, default 3)\n"
    "  --budget S       CPU seconds per point after which repetitions stop (default 3)\n"
    "  --smoke          two points per setting, one repetition (a quick check that all runs)\n";

/* the problems named in a comma-separated list, flagged in chosen[] */
static int parse_problems(const char *list, int *chosen) {
  char buf[256];
  if (strlen(list) >= sizeof buf) return wp_bad(PROG, "--problems is too long", NULL);
  strcpy(buf, list);
  int any = 0;
  for (char *name = strtok(buf, ","); name; name = strtok(NULL, ","), any = 1) {
    size_t i = 0;
    while (i < NPROBLEMS && strcmp(problems[i].name, name) != 0) i++;
    if (i == NPROBLEMS) return wp_bad(PROG, "--problems: unknown problem ", name);
    chosen[i] = 1;
  }
  return any ? 0 : wp_bad(PROG, "--problems names no problem", NULL);
}

static int parse(int argc, char **argv, settings *s, int *chosen, const char **out) {
  double v;
  for (int i = 1; i < argc; i++) {
    const char *flag = argv[i];
    if (strcmp(flag, "--smoke") == 0) {
      s->smoke = 1;
      continue;
    }
    if (strcmp(flag, "--problems") && strcmp(flag, "--out") && strcmp(flag, "--reps") &&
        strcmp(flag, "--budget"))
      return wp_bad(PROG, "unknown argument ", flag);
    if (i + 1 >= argc) return wp_bad(PROG, flag, " needs a value");
    const char *val = argv[++i];
    if (strcmp(flag, "--problems") == 0) {
      memset(chosen, 0, NPROBLEMS * sizeof *chosen);
      if (parse_problems(val, chosen)) return 2;
    } else if (strcmp(flag, "--out") == 0) {
      *out = val;
    } else if (strcmp(flag, "--reps") == 0) {
      if (wp_parse_positive(PROG, flag, val, WP_MAX_REPS, &v)) return 2;
      if (v != floor(v)) return wp_bad(PROG, "--reps must be an integer, not ", val);
      s->reps = (int)v;
    } else if (wp_parse_positive(PROG, flag, val, 3600.0, &s->budget)) {
      return 2;
    }
  }
  return 0;
}

int main(int argc, char **argv) {
  gsl_set_error_handler_off(); /* a failed rk8pd is reported, not an abort */
  settings s = {3, 0, 3.0, stdout};
  int chosen[NPROBLEMS] = {1, 1, 1}, failed = 0;
  const char *out = NULL;
  for (int i = 1; i < argc; i++)
    if (strcmp(argv[i], "--help") == 0) {
      fputs(usage, stdout);
      return 0;
    }
  if (parse(argc, argv, &s, chosen, &out)) return 2;
  if (out && !(s.out = fopen(out, "w"))) return wp_bad(PROG, "cannot write --out ", out);
  fprintf(s.out, "problem,solver,setting,param,steps,evals,rhs,newton,reps,cpu_s,err_q,err_v,"
                 "status\n");
  for (size_t i = 0; i < NPROBLEMS; i++)
    if (chosen[i] && study(&s, &problems[i])) failed = 1;
  if (out && fclose(s.out) != 0) {
    fprintf(stderr, PROG ": error writing %s\n", out);
    return 1;
  }
  return failed;
}
