/* SPDX-License-Identifier: GPL-3.0-or-later */
/* workprecision: final error against CPU time for the oscillator on its manifold, stabdae's maps
 * over a sweep of the step T and SUNDIALS IDA (index-1 and GGL forms) over a sweep of rtol, all
 * measured in one run.
 *
 *   workprecision --reference FILE [--out FILE] [--reps N] [--budget S]
 *
 * Start x0 = (X, Y, Xdot, Ydot) = (0.7, 0, 0.6, 0) (on the manifold: xi = 0), k = 2, m = 1, and
 * two cases: d = 0.03 to t = 100 and d = 0 to t = 1000. The reference file (reference.py) holds
 * the exact (X, Xdot) at each final time; the error is max(|X - X_ref|, |Xdot - Xdot_ref|). CPU
 * time is the process's (CLOCK_PROCESS_CPUTIME_ID) for the whole run, stepper or IDA set-up
 * included; the median over up to N repetitions, fewer once a point has used S seconds. A sweep
 * stops refining once its error is below 1e-13 (rounding).
 *
 * CSV (%.17g): d,tf,solver,setting,param,steps,reps,cpu_s,error,status; status is ok or the
 * reason a run failed (a failed run is a point, not the end of the study). Bad input: one line
 * on stderr, exit 2, no file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "ida_solve.h"
#include "measure.h"
#include "oscillator_model.h"

#define PROG "workprecision"

static const double x0[4] = {0.7, 0.0, 0.6, 0.0};

typedef struct study_case {
  double d, tf;
  double X, Xdot; /* the exact state at tf, from the reference file */
  int have_ref;
} study_case;

typedef struct settings {
  int reps;
  double budget; /* CPU seconds per point before the repetitions stop */
  FILE *out;
} settings;

/* ---- measurement ------------------------------------------------------------------------- */

/* One run: final (X, Xdot), steps taken, and a status text ("ok" or why it failed). */
typedef struct outcome {
  double X, Xdot;
  long steps;
  char status[128];
} outcome;

typedef void (*run_fn)(const study_case *c, const void *setting, double param, outcome *o);

typedef struct point {
  const char *solver, *setting;
  double param, cpu, error;
  int reps;
  outcome o;
} point;

typedef struct trial {
  const study_case *c;
  run_fn run;
  const void *setting;
  double param;
  outcome *o;
} trial;

static int run_trial(void *ctx) {
  trial *tr = ctx;
  tr->run(tr->c, tr->setting, tr->param, tr->o);
  return strcmp(tr->o->status, "ok") != 0;
}

/* Runs one point up to s->reps times (fewer past the budget); the median CPU time. */
static point measure(const study_case *c, const settings *s, run_fn run, const void *setting,
                     const char *solver, const char *name, double param) {
  point p = {.solver = solver, .setting = name, .param = param, .error = NAN};
  trial tr = {c, run, setting, param, &p.o};
  p.reps = wp_repeat(s->reps, s->budget, run_trial, &tr, &p.cpu);
  if (strcmp(p.o.status, "ok") == 0) p.error = fmax(fabs(p.o.X - c->X), fabs(p.o.Xdot - c->Xdot));
  return p;
}

/* ---- stabdae ------------------------------------------------------------------------------ */

typedef struct stab_map {
  const sdae_map_type *const *map; /* its setting in the CSV is the library's name for it */
  double n_first, n_last;          /* the sweep of step counts per unit of tf: T = 1/n .. */
} stab_map;

static void stabdae_run(const study_case *c, const void *setting, double T, outcome *o) {
  const stab_map *sm = setting;
  osc_params p = {.k = 2.0, .d = c->d, .m = 1.0, .ga = 9.81, .q = OSC_Q_CORRECTED};
  sdae_model m;
  sdae_options opt;
  sdae_stepper *s = NULL;
  double xi[2], mu[2], x[4];
  size_t nsteps = (size_t)llround(c->tf / T), done = 0;
  osc_model(&m, &p);
  sdae_options_default(&opt);
  opt.delta = 2.0;
  opt.map = *sm->map;
  osc_to_coords(&p, x0, xi, mu);
  int rc = sdae_stepper_alloc(&s, &m, &opt);
  if (rc == SDAE_OK) rc = sdae_integrate(s, 0.0, T, nsteps, nsteps, xi, mu, NULL, NULL, &done);
  sdae_stepper_free(s);
  osc_from_coords(&p, xi, mu, x);
  o->X = x[0], o->Xdot = x[2], o->steps = (long)done;
  if (rc == SDAE_OK)
    snprintf(o->status, sizeof o->status, "ok");
  else
    snprintf(o->status, sizeof o->status, "%s after %zu steps", sdae_strerror(rc), done);
}

/* ---- IDA ----------------------------------------------------------------------------------- */

typedef struct ida_form {
  const char *name;
  idaref_form form;
} ida_form;

typedef struct last_row {
  double y[IDAREF_MAX_DIM];
} last_row;

static int keep_row(double t, const double *y, void *ctx) {
  (void)t;
  memcpy(((last_row *)ctx)->y, y, sizeof((last_row *)ctx)->y);
  return 0;
}

/* atol = rtol: the solution is of size 1 */
static void ida_run(const study_case *c, const void *setting, double rtol, outcome *o) {
  const ida_form *f = setting;
  idaref_model p = idaref_model_default(IDAREF_OSCILLATOR);
  idaref_options opt = {rtol, rtol, c->tf, c->tf, 100000000L};
  idaref_result res;
  last_row last = {{0}};
  p.k = 2.0, p.m = 1.0, p.d = c->d;
  int rc = idaref_solve(&p, f->form, x0, &opt, keep_row, &last, &res);
  o->X = last.y[IDAREF_X], o->Xdot = last.y[IDAREF_XDOT], o->steps = res.stats.steps;
  if (rc == IDAREF_OK)
    snprintf(o->status, sizeof o->status, "ok");
  else
    snprintf(o->status, sizeof o->status, "%s in %s at t = %g", res.flag_name,
             res.function ? res.function : "?", res.t_reached);
}

/* ---- the study ----------------------------------------------------------------------------- */

static void write_point(const settings *s, const study_case *c, const point *p) {
  fprintf(s->out, "%.17g,%.17g,%s,%s,%.17g,%ld,%d,%.17g,%.17g,%s\n", c->d, c->tf, p->solver,
          p->setting, p->param, p->o.steps, p->reps, p->cpu, p->error, p->o.status);
  fflush(s->out);
  fprintf(stderr, "d = %g: %s %s %g: error %.3g, %.3g s CPU (%d reps)%s%s\n", c->d, p->solver,
          p->setting, p->param, p->error, p->cpu, p->reps, strcmp(p->o.status, "ok") ? ", " : "",
          strcmp(p->o.status, "ok") ? p->o.status : "");
}

/* the sweep stops once the error is at rounding level, or after a failure at a fine setting */
static int sweep_done(const point *p) { return p->error < 1e-13; }

/* step counts n tf with n = n_first .. n_last per unit time, sqrt(10) apart; T = 1/n */
static void stabdae_sweep(const settings *s, const study_case *c, const stab_map *sm) {
  for (double e = log10(sm->n_first); e <= log10(sm->n_last) + 1e-9; e += 0.5) {
    double T = c->tf / round(c->tf * pow(10.0, e));
    point p = measure(c, s, stabdae_run, sm, "stabdae", sdae_map_name(*sm->map), T);
    write_point(s, c, &p);
    if (sweep_done(&p)) break;
  }
}

static void ida_sweep(const settings *s, const study_case *c, const ida_form *f) {
  for (int e = 3; e <= 12; e++) {
    point p = measure(c, s, ida_run, f, "ida", f->name, pow(10.0, -e));
    write_point(s, c, &p);
    if (sweep_done(&p)) break;
  }
}

/* The sweeps, from coarse to fine: per unit of time, 1/T from n_first to n_last. */
static const stab_map maps[] = {
    {&sdae_map_euler, 10.0, 1e4}, {&sdae_map_midpoint, 10.0, 1e4}, {&sdae_map_dgrad, 10.0, 1e4},
    {&sdae_map_user, 10.0, 1e4}, /* the oscillator's user map: the paper's Section IV map */
    {&sdae_map_dg4, 1.0, 1e3},    {&sdae_map_dg6, 1.0, 1e3},       {&sdae_map_rk4, 1.0, 1e3},
    {&sdae_map_rk8, 1.0, 1e3},
};

static const ida_form forms[] = {{"index1", IDAREF_INDEX1}, {"ggl", IDAREF_GGL}};

static void study(const settings *s, const study_case *c) {
  for (size_t i = 0; i < sizeof maps / sizeof maps[0]; i++) stabdae_sweep(s, c, &maps[i]);
  for (size_t i = 0; i < sizeof forms / sizeof forms[0]; i++) ida_sweep(s, c, &forms[i]);
}

/* ---- input --------------------------------------------------------------------------------- */

static int bad(const char *what, const char *arg) { return wp_bad(PROG, what, arg); }

/* d,tf,X,Xdot rows; both cases must be present */
static int read_reference(const char *path, study_case *cases, size_t n) {
  FILE *f = fopen(path, "r");
  char line[512];
  if (!f) return bad("cannot read --reference ", path);
  while (fgets(line, sizeof line, f)) {
    double d, tf, X, Xd;
    if (sscanf(line, "%lf,%lf,%lf,%lf", &d, &tf, &X, &Xd) != 4) continue; /* the header */
    for (size_t i = 0; i < n; i++)
      if (cases[i].d == d && cases[i].tf == tf && isfinite(X) && isfinite(Xd))
        cases[i].X = X, cases[i].Xdot = Xd, cases[i].have_ref = 1;
  }
  fclose(f);
  for (size_t i = 0; i < n; i++)
    if (!cases[i].have_ref) {
      char msg[128];
      snprintf(msg, sizeof msg, "--reference has no row for d = %g, tf = %g: ", cases[i].d,
               cases[i].tf);
      return bad(msg, path);
    }
  return 0;
}

static int parse_positive(const char *flag, const char *v, double max, double *out) {
  return wp_parse_positive(PROG, flag, v, max, out);
}

static const char usage[] =
    "usage: " PROG " --reference FILE [--out FILE] [--reps N] [--budget S]\n"
    "  --reference FILE  d,tf,X,Xdot of the exact final states (tools/benchmarks/reference.py)\n"
    "  --out FILE        CSV (default: stdout)\n"
    "  --reps N          repetitions per point, median CPU time (1..15, default 3)\n"
    "  --budget S        CPU seconds per point after which repetitions stop (default 3)\n";

int main(int argc, char **argv) {
  study_case cases[2] = {{0.03, 100.0, 0, 0, 0}, {0.0, 1000.0, 0, 0, 0}};
  settings s = {3, 3.0, stdout};
  const char *ref = NULL, *out = NULL;
  double v;
  for (int i = 1; i < argc; i++) {
    const char *flag = argv[i];
    if (strcmp(flag, "--help") == 0) {
      fputs(usage, stdout);
      return 0;
    }
    if (strcmp(flag, "--reference") && strcmp(flag, "--out") && strcmp(flag, "--reps") &&
        strcmp(flag, "--budget"))
      return bad("unknown argument ", flag);
    if (i + 1 >= argc) return bad(flag, " needs a value");
    const char *val = argv[++i];
    if (strcmp(flag, "--reference") == 0) {
      ref = val;
    } else if (strcmp(flag, "--out") == 0) {
      out = val;
    } else if (strcmp(flag, "--reps") == 0) {
      if (parse_positive(flag, val, WP_MAX_REPS, &v)) return 2;
      if (v != floor(v)) return bad("--reps must be an integer, not ", val);
      s.reps = (int)v;
    } else if (parse_positive(flag, val, 3600.0, &s.budget)) {
      return 2;
    }
  }
  if (!ref) return bad("--reference FILE is required", NULL);
  if (read_reference(ref, cases, 2)) return 2;
  if (out && !(s.out = fopen(out, "w"))) return bad("cannot write --out ", out);

  fprintf(s.out, "d,tf,solver,setting,param,steps,reps,cpu_s,error,status\n");
  for (size_t i = 0; i < 2; i++) study(&s, &cases[i]);
  if (out && fclose(s.out) != 0) {
    fprintf(stderr, PROG ": error writing %s\n", out);
    return 1;
  }
  return 0;
}
