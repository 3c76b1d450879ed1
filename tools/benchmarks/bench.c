/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae benchmark: in-process timings of sdae_step for the example models.
 *
 *   bench [--smoke] [--reps N] [--report FILE]
 *
 * Each case builds its stepper once, runs one warm-up repetition, then --reps timed repetitions
 * of a fixed number of steps, each from the same start (so every repetition does the same work);
 * it reports the median CPU time per step (CLOCK_THREAD_CPUTIME_ID, which leaves out the time
 * other processes take on a shared machine). malloc, calloc and realloc are
 * interposed and counted while steps run: the library promises none. A last section checks the
 * conservation of W by dgrad, dg4 and dg6 over 10^6 steps (d = 0, on the manifold).
 *
 * The mechanical front-end (<stabdae/mbs.h>, sdae_mbs_step) is timed on the Cartesian pendulum
 * (beside the hand-written pendulum model, the same map: their ratio), the Cartesian double
 * pendulum and a four-bar, the problem library's mechanisms (examples/models/mechanisms.h), with
 * their callbacks' evaluations counted per step. Beside each mechanism's maps, in the same run,
 * at the same T and number of steps: the classical RK4 on its index-1 form from the same
 * counted callbacks (index1_rk4.h), whose drift off c = 0 nothing holds; the front-end's cost
 * over it is the price of zero drift. What each buys is measured outside the timing: the error
 * of the positions at the end against rk8pd on the index-1 ODE at a tight tolerance, and
 * max abs(c) over the warm-up run (the same steps from the same start).
 *
 * The table goes to stdout and, in full mode, to the Markdown report (default
 * build/report/bench.md) with the machine, the date and the command. --smoke runs every case
 * briefly (a second or two) for ctest: it fails (exit 1) on a failed step or an allocation,
 * never on a time. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, sysconf */

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <stabdae/mbs.h>
#include <stabdae/stabdae.h>

#include <gsl/gsl_errno.h>

#include "chain_model.h"
#include "index1_rk4.h"
#include "mechanisms.h"
#include "oscillator_model.h"
#include "pendulum_model.h"

#ifndef BENCH_REPORT
#define BENCH_REPORT "report/bench.md"
#endif

/* ---- allocation counter (not in sanitizer builds, which interpose the allocator) ---------- */

static volatile int counting;
static volatile long allocations;

#if BENCH_COUNT_ALLOCS
extern void *__libc_malloc(size_t n);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t n);

void *malloc(size_t n) {
  if (counting) allocations++;
  return __libc_malloc(n);
}

void *calloc(size_t n, size_t size) {
  if (counting) allocations++;
  return __libc_calloc(n, size);
}

void *realloc(void *p, size_t n) {
  if (counting) allocations++;
  return __libc_realloc(p, n);
}
#endif

/* ---- the cases ------------------------------------------------------------------------------ */

typedef enum model_kind {
  OSCILLATOR,
  PENDULUM,
  CHAIN,
  MBS_PENDULUM,
  MBS_DOUBLE,
  MBS_FOURBAR
} model_kind;

typedef struct bench_case {
  model_kind kind;
  const char *map; /* the library's name (sdae_map_by_name) */
  sdae_scheme scheme;
  size_t N;     /* masses (1 for the oscillator and the pendulum) */
  size_t steps; /* per repetition, full mode */
} bench_case;

/* One problem: the model, its options, the start and the running state. */
typedef struct problem {
  osc_params osc;
  pend_params pend;
  chain_params chain;
  sdae_model model;
  sdae_options opt;
  double *xi0, *mu0, *xi, *mu, *x;
  size_t n_xi, n_mu;
} problem;

static const double step_T = 0.001; /* the examples' default step */

static void problem_free(problem *P) {
  free(P->xi0), free(P->mu0), free(P->xi), free(P->mu), free(P->x);
  chain_model_free(&P->chain);
}

static int problem_arrays(problem *P, size_t n_xi, size_t n_mu, size_t n_x) {
  P->n_xi = n_xi, P->n_mu = n_mu;
  P->xi0 = malloc(n_xi * sizeof(double)), P->xi = malloc(n_xi * sizeof(double));
  P->mu0 = malloc(n_mu * sizeof(double)), P->mu = malloc(n_mu * sizeof(double));
  P->x = malloc(n_x * sizeof(double));
  return P->xi0 && P->xi && P->mu0 && P->mu && P->x ? 0 : -1;
}

/* The examples' defaults: delta 2, epsilon 1; oscillator k 2, d 0.03, m 1 from (0.1, 0.6, 0, 0);
 * pendulum L 1 from rest at 0.5 rad; chain k 2, kc 1, d 0.03 from its seeded random start. */
static int problem_init(problem *P, const bench_case *c) {
  memset(P, 0, sizeof *P);
  sdae_options_default(&P->opt);
  P->opt.delta = 2.0;
  P->opt.epsilon = 1.0;
  P->opt.scheme = c->scheme;
  P->opt.map = sdae_map_by_name(c->map);
  switch (c->kind) {
  case OSCILLATOR:
    P->osc = (osc_params){.k = 2.0, .d = 0.03, .m = 1.0, .ga = 9.81, .q = OSC_Q_CORRECTED};
    osc_model(&P->model, &P->osc);
    if (problem_arrays(P, 2, 2, 4)) return -1;
    memcpy(P->x, (double[4]){0.1, 0.6, 0.0, 0.0}, 4 * sizeof(double));
    osc_to_coords(&P->osc, P->x, P->xi0, P->mu0);
    return 0;
  case PENDULUM:
    P->pend = (pend_params){1.0, 1.0, 9.81};
    pend_model(&P->model, &P->pend);
    if (problem_arrays(P, 2, 2, 4)) return -1;
    memcpy(P->x, (double[4]){sin(0.5), -cos(0.5), 0.0, 0.0}, 4 * sizeof(double));
    return pend_to_coords(&P->pend, P->x, P->xi0, P->mu0);
  case CHAIN:
    P->chain = (chain_params){c->N, 2.0, 1.0, 0.03, 1.0, 9.81, NULL};
    if (chain_model(&P->model, &P->chain)) return -1;
    P->opt.bandwidth = CHAIN_BANDWIDTH;
    if (problem_arrays(P, 2 * c->N, 2 * c->N, 4 * c->N)) return -1;
    if (chain_random_start(&P->chain, 1, P->x)) return -1;
    chain_to_coords(&P->chain, P->x, P->xi0, P->mu0);
    return 0;
  case MBS_PENDULUM: /* measure_mbs's: no model of the normal form */
  case MBS_DOUBLE:
  case MBS_FOURBAR: break;
  }
  return -1;
}

/* ---- timing ---------------------------------------------------------------------------------- */

/* CPU time of this thread: on a shared machine it leaves out the time other processes run */
static double now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e9 * (double)ts.tv_sec + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, size_t n) {
  qsort(v, n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* nsteps steps from the start; the allocation counter is up only while steps run */
static int run_steps(sdae_stepper *s, problem *P, size_t nsteps, double *ns) {
  int rc = SDAE_OK;
  memcpy(P->xi, P->xi0, P->n_xi * sizeof(double));
  memcpy(P->mu, P->mu0, P->n_mu * sizeof(double));
  double t0 = now_ns();
  counting = 1;
  for (size_t i = 0; i < nsteps && rc == SDAE_OK; i++)
    rc = sdae_step(s, (double)i * step_T, step_T, P->xi, P->mu);
  counting = 0;
  *ns = now_ns() - t0;
  return rc;
}

/* ---- the front-end's mechanisms: the problem library's, their evaluations counted --------- */

enum {
  EV_MASS,
  EV_FORCE,
  EV_CONSTRAINT,
  EV_JACOBIAN,
  EV_CONSTRAINT_T,
  EV_POTENTIAL,
  EV_DAMPING,
  EV_MASS_DOT_V,
  EV_JACOBIAN_DOT,
  EV_CONSTRAINT_T_DOT,
  EV_KINDS
};

/* One of the problem library's mechanisms (examples/models/mechanisms.h, the examples' own) in
 * front of callbacks that count their evaluations, for the cost per step, and call its own. */
typedef struct mechanism {
  union {
    mech_pendulum pendulum;
    mech_double_pendulum doubled;
    mech_fourbar fourbar;
  } p;
  sdae_mbs inner;
  unsigned long evals[EV_KINDS];
} mechanism;

/* counted_NAME: counts in evals[KIND], then calls the mechanism's own NAME */
#define COUNTED(name, kind, sig, args)                                                             \
  static int counted_##name sig {                                                                  \
    mechanism *k = params;                                                                         \
    k->evals[kind]++;                                                                              \
    return k->inner.name args;                                                                     \
  }
COUNTED(mass, EV_MASS, (double t, const double *q, double *M, void *params),
        (t, q, M, k->inner.params))
COUNTED(force, EV_FORCE, (double t, const double *q, const double *v, double *F, void *params),
        (t, q, v, F, k->inner.params))
COUNTED(constraint, EV_CONSTRAINT, (double t, const double *q, double *c, void *params),
        (t, q, c, k->inner.params))
COUNTED(jacobian, EV_JACOBIAN, (double t, const double *q, double *G, void *params),
        (t, q, G, k->inner.params))
COUNTED(constraint_t, EV_CONSTRAINT_T, (double t, const double *q, double *ct, void *params),
        (t, q, ct, k->inner.params))
COUNTED(potential, EV_POTENTIAL, (double t, const double *q, double *V, void *params),
        (t, q, V, k->inner.params))
COUNTED(damping, EV_DAMPING, (double t, const double *q, double *D, void *params),
        (t, q, D, k->inner.params))
COUNTED(mass_dot_v, EV_MASS_DOT_V,
        (double t, const double *q, const double *v, double *out, void *params),
        (t, q, v, out, k->inner.params))
COUNTED(jacobian_dot, EV_JACOBIAN_DOT,
        (double t, const double *q, const double *v, double *Gdot, void *params),
        (t, q, v, Gdot, k->inner.params))
COUNTED(constraint_t_dot, EV_CONSTRAINT_T_DOT,
        (double t, const double *q, const double *v, double *out, void *params),
        (t, q, v, out, k->inner.params))
#undef COUNTED

/* The mechanism of kind (unit masses and bars, ga 9.81), its start from rest, and n_q; 0 when
 * the start cannot be assembled. */
static size_t mechanism_init(mechanism *k, model_kind kind, double *q) {
  double v[4];
  memset(k, 0, sizeof *k);
  if (kind == MBS_PENDULUM) { /* the hand-written pendulum's start: rest at 0.5 rad */
    k->p.pendulum = (mech_pendulum){.L = 1.0, .m = 1.0, .ga = 9.81};
    mech_pendulum_system(&k->inner, &k->p.pendulum);
    mech_pendulum_state(&k->p.pendulum, 0.5, 0.0, q, v);
  } else if (kind == MBS_DOUBLE) { /* rest at angles (1, 1.5) from the downward vertical */
    const double a[2] = {1.0, 1.5}, w[2] = {0.0, 0.0};
    k->p.doubled = (mech_double_pendulum){.L1 = 1.0, .L2 = 1.0, .m1 = 1.0, .m2 = 1.0, .ga = 9.81};
    mech_double_pendulum_system(&k->inner, &k->p.doubled);
    mech_double_pendulum_state(&k->p.doubled, a, w, q, v);
  } else { /* a crank-rocker: ground pivots A = (0, 0) and D = (2, 0), crank AB 1, coupler BC 2,
            * rocker CD 1.5; B straight above A, C where the circles about B and D meet above */
    k->p.fourbar =
        (mech_fourbar){.a = 1.0, .b = 2.0, .e = 1.5, .d = 2.0, .mB = 1.0, .mC = 1.0, .ga = 9.81};
    mech_fourbar_system(&k->inner, &k->p.fourbar);
    if (mech_fourbar_state(&k->p.fourbar, asin(1.0), 0.0, q, v) != 0) return 0;
  }
  return k->inner.n_q;
}

/* the mechanism with every callback it gives counted; those it leaves out stay NULL, so that
 * the front-end and the RK4 baseline difference what the mechanism does not give */
static void mechanism_sys(sdae_mbs *sys, mechanism *k) {
  const sdae_mbs *in = &k->inner;
  *sys = *in;
  sys->mass = counted_mass, sys->force = counted_force, sys->constraint = counted_constraint;
  sys->jacobian = in->jacobian ? counted_jacobian : NULL;
  sys->constraint_t = in->constraint_t ? counted_constraint_t : NULL;
  sys->potential = in->potential ? counted_potential : NULL;
  sys->damping = in->damping ? counted_damping : NULL;
  sys->mass_dot_v = in->mass_dot_v ? counted_mass_dot_v : NULL;
  sys->jacobian_dot = in->jacobian_dot ? counted_jacobian_dot : NULL;
  sys->constraint_t_dot = in->constraint_t_dot ? counted_constraint_t_dot : NULL;
  sys->params = k;
}

static int is_mbs(model_kind k) { return k == MBS_PENDULUM || k == MBS_DOUBLE || k == MBS_FOURBAR; }

/* One step of either stepper of a mechanism, behind one signature so that both are timed by the
 * same loop (the indirect call costs both the same nanosecond or two). */
typedef int (*mech_step_fn)(void *stepper, double t, double T, double *q, double *v);

static int frontend_step(void *s, double t, double T, double *q, double *v) {
  return sdae_mbs_step(s, t, T, q, v);
}

static int rk4_step(void *w, double t, double T, double *q, double *v) {
  return index1_rk4_step(w, t, T, q, v);
}

/* The end of a checked run: q after the last step, max_j abs(c_j) over the start and every
 * step (by the mechanism's own, uncounted constraint). */
typedef struct mech_check {
  double q_end[4], max_c, c_end;
} mech_check;

/* nsteps steps from the start (q0, v0 = 0); with chk, max abs(c) after every step (outside
 * the timed runs: the warm-up) */
static int run_mech_steps(mech_step_fn step, void *s, const mechanism *k, const double *q0,
                          size_t nsteps, double *ns, mech_check *chk) {
  size_t n_q = k->inner.n_q;
  double q[4], v[4] = {0.0, 0.0, 0.0, 0.0};
  int rc = 0;
  memcpy(q, q0, n_q * sizeof(double));
  if (chk) chk->max_c = mech_max_abs_c(&k->inner, 0.0, q);
  double t0 = now_ns();
  counting = 1;
  for (size_t i = 0; i < nsteps && rc == 0; i++) {
    rc = step(s, (double)i * step_T, step_T, q, v);
    if (chk && rc == 0)
      chk->max_c = fmax(chk->max_c, mech_max_abs_c(&k->inner, (double)(i + 1) * step_T, q));
  }
  counting = 0;
  *ns = now_ns() - t0;
  if (chk) {
    memcpy(chk->q_end, q, n_q * sizeof(double));
    chk->c_end = mech_max_abs_c(&k->inner, (double)nsteps * step_T, q);
  }
  return rc;
}

typedef struct result {
  const bench_case *c;
  size_t steps;
  double ns_step;    /* median over the repetitions */
  double iters_step; /* Newton iterations per step */
  long allocs;
  int rc;
  /* the front-end: callback evaluations, Phi^-1 iterations per step, chart switches, and its
   * warm-up's end and max abs(c) */
  double evals_step[EV_KINDS], phi_inv_step;
  unsigned long switches;
  mech_check chk;
} result;

enum { MAX_REPS = 101 };

static double evals_total(const double *evals_step) {
  double sum = 0.0;
  for (int e = 0; e < EV_KINDS; e++) sum += evals_step[e];
  return sum;
}

static result measure_mbs(const bench_case *c, size_t steps, int reps) {
  result r = {.c = c, .steps = steps, .rc = SDAE_ERR_NOMEM};
  mechanism k;
  sdae_mbs sys;
  sdae_options opt;
  sdae_mbs_stepper *s = NULL;
  double q0[4], t[MAX_REPS];
  size_t n_q = mechanism_init(&k, c->kind, q0);
  if (n_q == 0) { /* the four-bar did not close */
    r.rc = SDAE_ERR_PARAM;
    return r;
  }
  mechanism_sys(&sys, &k);
  sdae_options_default(&opt);
  opt.delta = 2.0, opt.epsilon = 1.0, opt.scheme = c->scheme, opt.map = sdae_map_by_name(c->map);
  if ((r.rc = sdae_mbs_stepper_alloc(&s, &sys, &opt)) != SDAE_OK) return r;
  allocations = 0;
  r.rc = run_mech_steps(frontend_step, s, &k, q0, steps, &t[0], &r.chk); /* warm-up */
  sdae_mbs_stepper_reset_stats(s);
  memset(k.evals, 0, sizeof k.evals);
  for (int i = 0; i < reps && r.rc == SDAE_OK; i++)
    r.rc = run_mech_steps(frontend_step, s, &k, q0, steps, &t[i], NULL);
  r.allocs = allocations;
  if (r.rc == SDAE_OK) {
    const sdae_mbs_stats *st = sdae_mbs_stepper_stats(s);
    double total = (double)steps * reps;
    r.ns_step = median(t, (size_t)reps) / (double)steps;
    r.iters_step = (double)st->step.newton_iters_total / total;
    r.phi_inv_step = (double)st->phi_inv_iters / total;
    r.switches = st->chart_switches;
    for (int e = 0; e < EV_KINDS; e++) r.evals_step[e] = (double)k.evals[e] / total;
  }
  sdae_mbs_stepper_free(s);
  return r;
}

/* ---- the baseline: RK4 on the index-1 form, and the reference ------------------------------ */

/* The classical RK4 on the index-1 form of one mechanism (index1_rk4.h), timed as the
 * front-end is, at the same T and number of steps, and the reference both are measured
 * against: rk8pd on the same index-1 ODE at REF_TOL, once, outside the timing. */
typedef struct baseline {
  model_kind kind;
  size_t n_q, steps;
  int rc; /* 0, or the failing step's status */
  long allocs;
  double ns_step, evals_step[EV_KINDS];
  mech_check chk;             /* its warm-up's */
  index1_source gdot, ct_dot; /* how gamma's derivatives were had */
  int ref_rc;                 /* GSL's status */
  unsigned long ref_steps;
  double q_ref[4];
  double ref_spread; /* max_j abs(q_ref,j less the same by rk8pd at REF_TOL_CHECK) */
  double ref_exact;  /* the pendulum's: max_j abs(q_ref,j - q_exact,j); NaN for the others */
} baseline;

/* The reference's tolerance, and a looser one whose distance to it bounds its error: on the
 * pendulum over 100 s (by its exact solution) rk8pd's error was 1.7e-10 at 1e-13 and 9e-11 at
 * 1e-14, the two 2.6e-10 apart. */
#define REF_TOL 1e-14
#define REF_TOL_CHECK 1e-13

static baseline measure_baseline(model_kind kind, size_t steps, int reps) {
  baseline b = {.kind = kind, .steps = steps, .rc = -1, .ref_rc = GSL_ENOMEM};
  mechanism k;
  sdae_mbs sys;
  double q0[4], v0[4] = {0.0, 0.0, 0.0, 0.0}, t[MAX_REPS], tf = (double)steps * step_T;
  index1_rk4 *w = NULL;
  size_t n_q = b.n_q = mechanism_init(&k, kind, q0);
  if (n_q == 0) return b;
  mechanism_sys(&sys, &k);
  if (!(w = index1_rk4_alloc(&sys))) return b;
  b.gdot = index1_gdot_source(index1_rk4_form(w));
  b.ct_dot = index1_ct_dot_source(index1_rk4_form(w));
  allocations = 0;
  b.rc = run_mech_steps(rk4_step, w, &k, q0, steps, &t[0], &b.chk); /* warm-up */
  memset(k.evals, 0, sizeof k.evals);
  for (int i = 0; i < reps && b.rc == 0; i++)
    b.rc = run_mech_steps(rk4_step, w, &k, q0, steps, &t[i], NULL);
  b.allocs = allocations;
  if (b.rc == 0) {
    b.ns_step = median(t, (size_t)reps) / (double)steps;
    for (int e = 0; e < EV_KINDS; e++)
      b.evals_step[e] = (double)k.evals[e] / ((double)steps * reps);
  }
  /* the reference twice, its callbacks counted no more */
  double q[4] = {0.0, 0.0, 0.0, 0.0}, v[4], qc[4];
  memcpy(q, q0, n_q * sizeof *q), memcpy(v, v0, sizeof v);
  b.ref_rc = index1_reference(w, 0.0, tf, REF_TOL, q, v, &b.ref_steps);
  memcpy(b.q_ref, q, sizeof q);
  memcpy(qc, q0, n_q * sizeof *qc), memcpy(v, v0, sizeof v);
  if (b.ref_rc == GSL_SUCCESS) b.ref_rc = index1_reference(w, 0.0, tf, REF_TOL_CHECK, qc, v, NULL);
  for (size_t j = 0; j < n_q; j++) b.ref_spread = fmax(b.ref_spread, fabs(qc[j] - q[j]));
  b.ref_exact = NAN;
  if (kind == MBS_PENDULUM) { /* the exact swing from rest at 0.5 rad (mechanism_init's) */
    double th, om, L = k.p.pendulum.L;
    mech_pendulum_exact(&k.p.pendulum, 0.5, tf, &th, &om);
    b.ref_exact = fmax(fabs(q[0] - L * sin(th)), fabs(q[1] + L * cos(th)));
  }
  index1_rk4_free(w);
  return b;
}

static result measure(const bench_case *c, size_t steps, int reps) {
  result r = {.c = c, .steps = steps, .rc = SDAE_ERR_NOMEM};
  problem P;
  if (is_mbs(c->kind)) return measure_mbs(c, steps, reps);
  sdae_stepper *s = NULL;
  double t[MAX_REPS];
  if (problem_init(&P, c) == 0 && (r.rc = sdae_stepper_alloc(&s, &P.model, &P.opt)) == SDAE_OK) {
    allocations = 0;
    r.rc = run_steps(s, &P, steps, &t[0]); /* warm-up */
    sdae_stepper_reset_stats(s);
    for (int k = 0; k < reps && r.rc == SDAE_OK; k++) r.rc = run_steps(s, &P, steps, &t[k]);
    r.allocs = allocations;
    if (r.rc == SDAE_OK) {
      r.ns_step = median(t, (size_t)reps) / (double)steps;
      r.iters_step = (double)sdae_stepper_stats(s)->newton_iters_total / ((double)steps * reps);
    }
  }
  sdae_stepper_free(s);
  problem_free(&P);
  return r;
}

/* ---- W conservation: d = 0, on the manifold, T = 0.01 ------------------------------------ */

typedef struct drift {
  const char *map;
  size_t steps;
  double max_rel; /* max_n |W_n - W_0| / W_0 */
  int rc;
} drift;

static drift w_drift(const char *map, const sdae_map_type *type, size_t steps) {
  drift r = {map, steps, 0.0, SDAE_ERR_NOMEM};
  osc_params p = {.k = 2.0, .d = 0.0, .m = 1.0, .ga = 9.81, .q = OSC_Q_CORRECTED};
  const double x0[4] = {0.7, 0.0, 0.6, 0.0};
  double xi[2], mu[2], W0;
  sdae_model m;
  sdae_options o;
  sdae_stepper *s;
  osc_model(&m, &p);
  sdae_options_default(&o);
  o.delta = 2.0;
  o.map = type;
  osc_to_coords(&p, x0, xi, mu);
  W0 = osc_W(&p, mu);
  if ((r.rc = sdae_stepper_alloc(&s, &m, &o)) != SDAE_OK) return r;
  for (size_t i = 0; i < steps && r.rc == SDAE_OK; i++) {
    r.rc = sdae_step(s, (double)i * 0.01, 0.01, xi, mu);
    r.max_rel = fmax(r.max_rel, fabs(osc_W(&p, mu) - W0) / W0);
  }
  sdae_stepper_free(s);
  return r;
}

/* ---- report ---------------------------------------------------------------------------------- */

static const char *model_name(model_kind k) {
  static const char *const names[] = {"oscillator",   "pendulum",        "chain",
                                      "pendulum_mbs", "double_pendulum", "fourbar"};
  return names[k];
}

static void cpu_model(char *out, size_t len) {
  FILE *f = fopen("/proc/cpuinfo", "r");
  char line[512];
  snprintf(out, len, "unknown");
  while (f && fgets(line, sizeof line, f)) {
    char *colon = strchr(line, ':');
    if (strncmp(line, "model name", 10) == 0 && colon) {
      snprintf(out, len, "%s", colon + 2);
      out[strcspn(out, "\n")] = '\0';
      break;
    }
  }
  if (f) fclose(f);
}

static void print_row(FILE *f, const result *r) {
  const bench_case *c = r->c;
  if (r->rc != SDAE_OK) {
    fprintf(f, "| %s | %zu | %s | %d | %zu | failed: %s | | | | %ld |\n", model_name(c->kind), c->N,
            c->map, (int)c->scheme, r->steps, sdae_strerror(r->rc), r->allocs);
    return;
  }
  fprintf(f, "| %s | %zu | %s | %d | %zu | %.1f | %.3g | %.2f | %.2f | %ld |\n",
          model_name(c->kind), c->N, c->map, (int)c->scheme, r->steps, r->ns_step, 1e9 / r->ns_step,
          r->ns_step / (double)c->N, r->iters_step, r->allocs);
}

static void print_table(FILE *f, const result *res, size_t n) {
  fprintf(f, "| model | N | map | scheme | steps/rep | median ns/step | steps/s | "
             "ns/(mass step) | Newton it/step | allocations |\n");
  fprintf(f, "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (size_t i = 0; i < n; i++) print_row(f, &res[i]);
}

static const result *find(const result *res, size_t n, model_kind k, const char *map,
                          sdae_scheme scheme, size_t N) {
  for (size_t i = 0; i < n; i++)
    if (res[i].c->kind == k && strcmp(res[i].c->map, map) == 0 && res[i].c->scheme == scheme &&
        res[i].c->N == N && res[i].rc == SDAE_OK)
      return &res[i];
  return NULL;
}

static const char *verdict(int ok) { return ok ? "met" : "missed"; }

static void print_targets(FILE *f, const result *res, size_t n, const drift *dr, size_t ndr,
                          long allocs) {
  const result *osc = find(res, n, OSCILLATOR, "user", SDAE_SCHEME_SEMI_IMPLICIT, 1);
  fprintf(f, "\n| target | measured | |\n|---|---|---|\n");
  if (osc)
    fprintf(f,
            "| oscillator, scheme 15 + user (the paper's map): <= 150 ns/step | %.1f ns/step "
            "| %s |\n",
            osc->ns_step, verdict(osc->ns_step <= 150.0));
  for (size_t m = 0; m < 2; m++) {
    const char *map = m == 0 ? "euler" : "dgrad";
    const result *a = find(res, n, CHAIN, map, SDAE_SCHEME_SEMI_IMPLICIT, 100);
    const result *b = find(res, n, CHAIN, map, SDAE_SCHEME_SEMI_IMPLICIT, 100000);
    if (!a || !b) continue;
    double ra = a->ns_step / 100.0, rb = b->ns_step / 100000.0;
    fprintf(f,
            "| chain, %s: ns/(mass step) at N = 1e5 within 1.5x of N = 100 | "
            "%.2f / %.2f = %.2fx | %s |\n",
            map, rb, ra, rb / ra, verdict(rb / ra <= 1.5));
  }
  for (size_t i = 0; i < ndr; i++)
    fprintf(f,
            "| d = 0, on the manifold, %zu steps of T = 0.01, %s: max abs(W - W0)/W0 <= "
            "1e-12 | %s%.2e | %s |\n",
            dr[i].steps, dr[i].map, dr[i].rc == SDAE_OK ? "" : "failed, ", dr[i].max_rel,
            verdict(dr[i].rc == SDAE_OK && dr[i].max_rel <= 1e-12));
#if BENCH_COUNT_ALLOCS
  fprintf(f, "| zero heap allocations per step | %ld in all timed steps | %s |\n", allocs,
          verdict(allocs == 0));
#else
  (void)allocs;
  fprintf(f, "| zero heap allocations per step | not counted (sanitizer build) | |\n");
#endif
}

static const baseline *find_any_baseline(const baseline *bl, size_t nbl, model_kind kind) {
  for (size_t i = 0; i < nbl; i++)
    if (bl[i].kind == kind) return &bl[i];
  return NULL;
}

static const baseline *find_baseline(const baseline *bl, size_t nbl, model_kind kind,
                                     size_t steps) {
  for (size_t i = 0; i < nbl; i++)
    if (bl[i].kind == kind && bl[i].steps == steps && bl[i].rc == 0) return &bl[i];
  return NULL;
}

/* max_j abs(q_j - q_ref,j): the positions' error at the end */
static double error_q(const double *q, const baseline *b) {
  double e = 0.0;
  for (size_t j = 0; j < b->n_q; j++) e = fmax(e, fabs(q[j] - b->q_ref[j]));
  return e;
}

static const char *source_name(index1_source s) {
  static const char *const names[] = {"given", "differences"};
  return names[s];
}

/* The front-end's cases: their cost per step against the classical RK4 on the index-1 form of
 * the same mechanism at the same T (the price of zero drift) and against the hand-written
 * pendulum of the same map (target: at most 3x), the callback calls that make them, and what
 * each buys: the error at the end and the drift off c = 0. */
static void print_mbs(FILE *f, const result *res, size_t n, const baseline *bl, size_t nbl) {
  int header = 0;
  for (size_t i = 0; i < n; i++) {
    const result *r = &res[i];
    if (!is_mbs(r->c->kind) || r->rc != SDAE_OK) continue;
    if (!header++)
      fprintf(f,
              "\nThe mechanical front-end (sdae_mbs_step) beside the classical RK4 on the "
              "index-1 form of the same mechanism from the same callbacks, the same T and "
              "steps: price of zero drift = front-end ns/step / RK4 ns/step. error: max_j "
              "abs(q_j - q_ref,j) at the end, q_ref by rk8pd on the index-1 ODE at "
              "tolerance %.0e; max abs(c): over the run (every step of the warm-up run). "
              "calls: every callback, per step.\n\n"
              "| front-end | map | ns/step | RK4 index-1 ns/step | price of zero drift | "
              "calls/step | RK4 calls/step | error | RK4 error | max abs(c) | "
              "RK4 max abs(c) | hand-written pendulum | ratio | target <= 3x | "
              "Phi^-1 it/step | Newton it/step | chart switches |\n"
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|"
              "---:|\n",
              REF_TOL);
    const baseline *b = find_baseline(bl, nbl, r->c->kind, r->steps);
    const result *h =
        r->c->kind == MBS_PENDULUM ? find(res, n, PENDULUM, r->c->map, r->c->scheme, 1) : NULL;
    fprintf(f, "| %s | %s | %.1f | ", model_name(r->c->kind), r->c->map, r->ns_step);
    if (b)
      fprintf(f, "%.1f | %.1fx | %.1f | %.1f | ", b->ns_step, r->ns_step / b->ns_step,
              evals_total(r->evals_step), evals_total(b->evals_step));
    else
      fprintf(f, "| | %.1f | | ", evals_total(r->evals_step));
    if (b && b->ref_rc == GSL_SUCCESS)
      fprintf(f, "%.2e | %.2e | ", error_q(r->chk.q_end, b), error_q(b->chk.q_end, b));
    else
      fprintf(f, "| | ");
    fprintf(f, "%.1e | ", r->chk.max_c);
    if (b)
      fprintf(f, "%.1e | ", b->chk.max_c);
    else
      fprintf(f, "| ");
    if (h)
      fprintf(f, "%.1f | %.2fx | %s | ", h->ns_step, r->ns_step / h->ns_step,
              verdict(r->ns_step <= 3.0 * h->ns_step));
    else
      fprintf(f, "| | | ");
    fprintf(f, "%.2f | %.2f | %lu |\n", r->phi_inv_step, r->iters_step, r->switches);
  }
  if (!header) return;
  /* the calls by callback, the front-end's maps and the baseline one under the other */
  fprintf(f, "\nCallback calls per step, by callback (c_t: dc/dt; Mdot v, Gdot, c_t dot: the "
             "derivatives along the motion, when the mechanism gives them):\n\n"
             "| mechanism | stepper | M | F | c | G | c_t | V | D | Mdot v | Gdot | c_t dot | "
             "all |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (size_t i = 0; i < n + nbl; i++) {
    const double *ev;
    if (i < n) {
      if (!is_mbs(res[i].c->kind) || res[i].rc != SDAE_OK) continue;
      fprintf(f, "| %s | front-end, %s |", model_name(res[i].c->kind), res[i].c->map);
      ev = res[i].evals_step;
    } else {
      if (bl[i - n].rc != 0) continue;
      fprintf(f, "| %s | RK4 index-1 |", model_name(bl[i - n].kind));
      ev = bl[i - n].evals_step;
    }
    for (int e = 0; e < EV_KINDS; e++) fprintf(f, " %.2f |", ev[e]);
    fprintf(f, " %.2f |\n", evals_total(ev));
  }
  /* the baseline and its reference, mechanism by mechanism */
  fprintf(f,
          "\nThe RK4 baseline: 4 stages, each M, F, G, gamma and one solve of the "
          "KKT system [M G^T; G 0] [a; lambda] = [F; -gamma] by its Schur complement, M and "
          "G M^-1 G^T factored by the library's own Cholesky (as lean as the front-end's "
          "solves); gamma's Gdot and d/ds c_t from the mechanism when it "
          "gives them, else by the fourth-order central difference along (1, v) the "
          "front-end uses (4 calls of jacobian or constraint_t). The reference: rk8pd on the "
          "same index-1 ODE at tolerance %.0e (absolute and relative); its spread: max_j "
          "abs(q_ref,j - the same at %.0e), a bound on its error; for the pendulum also its "
          "distance to the exact swing (Jacobi's elliptic functions).\n\n"
          "| mechanism | steps | T | RK4 ns/step | Gdot | d/ds c_t | RK4 error | "
          "RK4 max abs(c) | RK4 abs(c) at the end | reference steps | reference spread | "
          "reference - exact | allocations |\n"
          "|---|---:|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
          REF_TOL, REF_TOL_CHECK);
  for (size_t i = 0; i < nbl; i++) {
    const baseline *b = &bl[i];
    fprintf(f, "| %s | %zu | %g | ", model_name(b->kind), b->steps, step_T);
    if (b->rc != 0) {
      fprintf(f, "failed (status %d) | | | | | | | | | %ld |\n", b->rc, b->allocs);
      continue;
    }
    fprintf(f, "%.1f | %s | %s | ", b->ns_step, source_name(b->gdot), source_name(b->ct_dot));
    if (b->ref_rc == GSL_SUCCESS)
      fprintf(f, "%.2e | %.1e | %.1e | %lu | %.1e | ", error_q(b->chk.q_end, b), b->chk.max_c,
              b->chk.c_end, b->ref_steps, b->ref_spread);
    else
      fprintf(f, "reference failed: %s | %.1e | %.1e | | | ", gsl_strerror(b->ref_rc), b->chk.max_c,
              b->chk.c_end);
    if (isnan(b->ref_exact))
      fprintf(f, "| %ld |\n", b->allocs);
    else
      fprintf(f, "%.1e | %ld |\n", b->ref_exact, b->allocs);
  }
}

static void print_header(FILE *f, int argc, char **argv, int reps) {
  char cpu[256], date[64];
  time_t now = time(NULL);
  strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", gmtime(&now));
  cpu_model(cpu, sizeof cpu);
  fprintf(f, "# stabdae benchmark\n\n");
  fprintf(f, "- machine: %s, %ld cores online\n", cpu, sysconf(_SC_NPROCESSORS_ONLN));
  fprintf(f, "- date: %s\n- command:", date);
  for (int i = 0; i < argc; i++) fprintf(f, " %s", argv[i]);
  fprintf(f,
          "\n- method: one warm-up and %d timed repetitions per case, each from the same "
          "start; median CPU time of the thread (CLOCK_THREAD_CPUTIME_ID) per step, whole "
          "sdae_step; T = 0.001, "
          "delta 2, epsilon 1; heap allocations counted by malloc/calloc/realloc "
          "interposition while steps run\n\n",
          reps);
}

/* ---- main ------------------------------------------------------------------------------------ */

/* 16 oscillator, 7 pendulum, 10 chain and 15 front-end cases, with room */
enum { MAX_CASES = 64 };

static size_t make_cases(bench_case *out) {
  static const char *const osc_maps[] = {"euler", "midpoint", "dgrad", "user",
                                         "dg4",   "dg6",      "rk4",   "rk8"};
  static const char *const pend_maps[] = {"euler", "midpoint", "dgrad", "dg4", "dg6", "rk4", "rk8"};
  static const size_t chain_N[] = {10, 100, 1000, 10000, 100000};
  size_t n = 0;
  for (int s = 0; s < 2; s++)
    for (size_t m = 0; m < sizeof osc_maps / sizeof osc_maps[0]; m++)
      out[n++] = (bench_case){OSCILLATOR, osc_maps[m],
                              s ? SDAE_SCHEME_SEMI_IMPLICIT : SDAE_SCHEME_EXPLICIT, 1, 200000};
  for (size_t m = 0; m < sizeof pend_maps / sizeof pend_maps[0]; m++)
    out[n++] = (bench_case){PENDULUM, pend_maps[m], SDAE_SCHEME_SEMI_IMPLICIT, 1, 200000};
  for (size_t m = 0; m < 2; m++)
    for (size_t i = 0; i < 5; i++) /* about 2e6 mass-steps per repetition */
      out[n++] = (bench_case){CHAIN, m ? "dgrad" : "euler", SDAE_SCHEME_SEMI_IMPLICIT, chain_N[i],
                              chain_N[i] < 100000 ? 2000000 / chain_N[i] : 20};
  static const char *const mbs_maps[] = {"euler", "midpoint", "dgrad", "rk4", "rk8"};
  for (size_t m = 0; m < sizeof mbs_maps / sizeof mbs_maps[0]; m++) { /* the front-end */
    out[n++] = (bench_case){MBS_PENDULUM, mbs_maps[m], SDAE_SCHEME_SEMI_IMPLICIT, 1, 100000};
    out[n++] = (bench_case){MBS_DOUBLE, mbs_maps[m], SDAE_SCHEME_SEMI_IMPLICIT, 2, 50000};
    out[n++] = (bench_case){MBS_FOURBAR, mbs_maps[m], SDAE_SCHEME_SEMI_IMPLICIT, 2, 50000};
  }
  return n;
}

/* keeps the cases whose label model/map/scheme/N starts with the fields of only (all when only
 * is NULL): "chain/dgrad" keeps every N, "chain/dgrad/15/100" N = 100 alone */
static size_t select_cases(bench_case *c, size_t n, const char *only) {
  size_t kept = 0;
  for (size_t i = 0; i < n; i++) {
    char label[96];
    snprintf(label, sizeof label, "%s/%s/%d/%zu", model_name(c[i].kind), c[i].map, (int)c[i].scheme,
             c[i].N);
    size_t len = only ? strlen(only) : 0;
    if (!only || (strncmp(label, only, len) == 0 && (label[len] == '\0' || label[len] == '/')))
      c[kept++] = c[i];
  }
  return kept;
}

static int usage_error(const char *msg, const char *arg) {
  fprintf(stderr, "bench: %s%s\n", msg, arg ? arg : "");
  return 2;
}

/* the value after option argv[*i]: a usage error when it is missing */
static const char *value_of(int argc, char **argv, int *i) {
  if (*i + 1 >= argc) return NULL;
  return argv[++*i];
}

static int parse_args(int argc, char **argv, int *smoke, int *reps, const char **report,
                      const char **only) {
  for (int i = 1; i < argc; i++) {
    const char *opt = argv[i], *v;
    if (strcmp(opt, "--smoke") == 0) {
      *smoke = 1;
    } else if (strcmp(opt, "--reps") == 0) {
      char *end;
      long r;
      if (!(v = value_of(argc, argv, &i))) return usage_error("--reps needs a value", NULL);
      errno = 0;
      r = strtol(v, &end, 10);
      if (errno || end == v || *end || r < 1 || r > MAX_REPS)
        return usage_error("--reps must be an integer in 1..101, not ", v);
      *reps = (int)r;
    } else if (strcmp(opt, "--report") == 0) {
      if (!(*report = value_of(argc, argv, &i))) return usage_error("--report needs a value", NULL);
    } else if (strcmp(opt, "--only") == 0) {
      if (!(*only = value_of(argc, argv, &i))) return usage_error("--only needs a value", NULL);
    } else if (strcmp(opt, "--help") == 0) {
      printf("usage: bench [--smoke] [--reps N (1..101; default 7, smoke 3)] [--report FILE]\n"
             "             [--only MODEL[/MAP[/SCHEME[/N]]] (e.g. oscillator/user/15)]\n"
             "default report (full mode): %s\n",
             BENCH_REPORT);
      return 0;
    } else {
      return usage_error("unknown argument ", opt);
    }
  }
  return -1;
}

/* creates the report's directory (one level, as build/report) when missing */
static void make_parent(const char *path) {
  char dir[4096];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash && slash != dir) {
    *slash = '\0';
    mkdir(dir, 0777);
  }
}

static int write_report(const char *path, int argc, char **argv, int reps, const result *res,
                        size_t n, const baseline *bl, size_t nbl, const drift *dr, size_t ndr,
                        long allocs) {
  FILE *f;
  make_parent(path);
  if (!(f = fopen(path, "w"))) {
    fprintf(stderr, "bench: cannot write %s: %s\n", path, strerror(errno));
    return -1;
  }
  print_header(f, argc, argv, reps);
  print_table(f, res, n);
  print_targets(f, res, n, dr, ndr, allocs);
  print_mbs(f, res, n, bl, nbl);
  return fclose(f) == 0 ? 0 : -1;
}

int main(int argc, char **argv) {
  int smoke = 0, reps = 0, failed = 0; /* reps 0: the mode's default */
  const char *report = NULL;
  const char *only = NULL;
  int rc = parse_args(argc, argv, &smoke, &reps, &report, &only);
  if (rc >= 0) return rc;
  if (!report && !smoke) report = BENCH_REPORT;
  if (reps == 0) reps = smoke ? 3 : 7;

  bench_case cases[MAX_CASES];
  result res[MAX_CASES];
  baseline bl[3]; /* one per mechanism */
  size_t n = select_cases(cases, make_cases(cases), only), nbl = 0;
  long allocs = 0;
  gsl_set_error_handler_off(); /* a failed reference is reported, not an abort */
  for (size_t i = 0; i < n; i++) {
    size_t steps = smoke ? (cases[i].steps + 199) / 200 : cases[i].steps;
    /* a mechanism's baseline before its first front-end case, timed in the same run */
    if (is_mbs(cases[i].kind) && !find_any_baseline(bl, nbl, cases[i].kind) &&
        nbl < sizeof bl / sizeof bl[0]) {
      bl[nbl] = measure_baseline(cases[i].kind, steps, reps);
      allocs += bl[nbl].allocs;
      failed |= bl[nbl].rc != 0 || bl[nbl].ref_rc != GSL_SUCCESS;
      fprintf(stderr, "%s: RK4 index-1 %.1f ns/step (status %d), reference: %s\n",
              model_name(cases[i].kind), bl[nbl].ns_step, bl[nbl].rc,
              gsl_strerror(bl[nbl].ref_rc)); /* progress */
      nbl++;
    }
    res[i] = measure(&cases[i], steps, reps);
    allocs += res[i].allocs;
    failed |= res[i].rc != SDAE_OK;
    print_row(stderr, &res[i]); /* progress */
  }
  /* the conservation runs only with the whole set of cases */
  static const char *const drift_maps[] = {"dgrad", "dg4", "dg6"};
  size_t ndr = only ? 0 : sizeof drift_maps / sizeof drift_maps[0];
  drift dr[sizeof drift_maps / sizeof drift_maps[0]] = {{0}};
  for (size_t i = 0; i < ndr; i++) {
    dr[i] = w_drift(drift_maps[i], sdae_map_by_name(drift_maps[i]), smoke ? 10000 : 1000000);
    failed |= dr[i].rc != SDAE_OK;
  }

  print_header(stdout, argc, argv, reps);
  print_table(stdout, res, n);
  print_targets(stdout, res, n, dr, ndr, allocs);
  print_mbs(stdout, res, n, bl, nbl);
  if (report && write_report(report, argc, argv, reps, res, n, bl, nbl, dr, ndr, allocs)) return 1;
  if (failed) fprintf(stderr, "bench: a case failed (see the table)\n");
  if (allocs) fprintf(stderr, "bench: %ld heap allocations while stepping\n", allocs);
  return failed || allocs ? 1 : 0;
}
