/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanisms stabdae_gen writes from the descriptions in examples/models/sym (the libraries
 * sym_<model> of examples/models) against the hand-written ones of models/mechanisms.c and
 * models/benchmarks.c, which they describe: every callback entry by entry at random states and
 * times (where the hand-written one omits a callback, against the mathematics), their derivatives
 * by sdae_mbs_check (and a wrong one caught), their defaults and starts, and their trajectories
 * through <stabdae/mbs.h> with the example programs' settings. */
#include <check.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "andrews.h"
#include "benchmarks.h"
#include "car_axis.h"
#include "double_pendulum.h"
#include "fourbar.h"
#include "fourbar_sparse.h"
#include "mechanisms.h"
#include "slider_crank.h"
#include "test_util.h"

enum { FOURBAR, DPEND, CRANK, CAR, ANDREWS, MODELS };

#define NQ 7 /* the largest n_q */
#define NC 6 /* the largest n_c */

/* the parameters both sides share, field by field */
#define FOURBAR_FIELDS X(a) X(b) X(e) X(d) X(mB) X(mC) X(ga)
#define DPEND_FIELDS X(L1) X(L2) X(m1) X(m2) X(ga)
#define CRANK_FIELDS X(a) X(J1) X(m2) X(J2) X(k) X(c) X(l0) X(F)
#define CAR_FIELDS X(eps) X(mass) X(L) X(L0) X(r) X(w) X(g)
/* Andrews' 42 in bench_andrews' order, unformatted: clang-format reflows the list anew on
 * every run */
/* clang-format off */
#define ANDREWS_FIELDS \
  X(m1) X(m2) X(m3) X(m4) X(m5) X(m6) X(m7) X(xa) X(ya) X(xb) X(yb) X(xc) X(yc) X(c0) \
  X(i1) X(i2) X(i3) X(i4) X(i5) X(i6) X(i7) X(d) X(da) X(e) X(ea) X(rr) X(ra) X(l0) \
  X(ss) X(sa) X(sb) X(sc) X(sd) X(ta) X(tb) X(u) X(ua) X(ub) X(zf) X(zt) X(fa) X(mom)
/* clang-format on */

typedef struct models {
  fourbar_params g_fourbar;
  double_pendulum_params g_dpend;
  slider_crank_params g_crank;
  car_axis_params g_car;
  andrews_params g_andrews;
  mech_fourbar fourbar;
  mech_double_pendulum dpend;
  bench_slider_crank crank;
  bench_car_axis car;
  bench_andrews andrews;
  sdae_mbs gen[MODELS], hand[MODELS];
} models;

/* the hand-written parameters into the generated ones */
static void copy_params(models *m) {
#define X(f) m->g_fourbar.f = m->fourbar.f;
  FOURBAR_FIELDS
#undef X
#define X(f) m->g_dpend.f = m->dpend.f;
  DPEND_FIELDS
#undef X
#define X(f) m->g_crank.f = m->crank.f;
  CRANK_FIELDS
#undef X
#define X(f) m->g_car.f = m->car.f;
  CAR_FIELDS
#undef X
#define X(f) m->g_andrews.f = m->andrews.f;
  ANDREWS_FIELDS
#undef X
}

static void build(models *m) {
  m->gen[FOURBAR] = fourbar_mbs(&m->g_fourbar);
  m->gen[DPEND] = double_pendulum_mbs(&m->g_dpend);
  m->gen[CRANK] = slider_crank_mbs(&m->g_crank);
  m->gen[CAR] = car_axis_mbs(&m->g_car);
  m->gen[ANDREWS] = andrews_mbs(&m->g_andrews);
  mech_fourbar_system(&m->hand[FOURBAR], &m->fourbar);
  mech_double_pendulum_system(&m->hand[DPEND], &m->dpend);
  bench_slider_crank_system(&m->hand[CRANK], &m->crank);
  bench_car_axis_system(&m->hand[CAR], &m->car);
  bench_andrews_system(&m->hand[ANDREWS], &m->andrews);
}

/* The example programs' parameters (examples/fourbar.c, double_pendulum.c: their defaults;
 * the benchmarks' published constants), the generated side from its own defaults */
static void program_defaults(models *m) {
  fourbar_params_default(&m->g_fourbar);
  double_pendulum_params_default(&m->g_dpend);
  slider_crank_params_default(&m->g_crank);
  car_axis_params_default(&m->g_car);
  andrews_params_default(&m->g_andrews);
  m->fourbar = (mech_fourbar){1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81};
  m->dpend = (mech_double_pendulum){1.0, 1.0, 1.0, 1.0, 9.81};
  m->crank = bench_slider_crank_default();
  m->car = bench_car_axis_default();
  bench_andrews_default(&m->andrews);
  build(m);
}

/* Parameters away from the defaults and from one another (the defaults repeat values: unit
 * lengths and masses, Andrews' e = sd = zf and ea = fa), so that a parameter read in the place
 * of another shows; the start's parameters at their defaults */
static void varied(models *m) {
  program_defaults(m);
  m->fourbar = (mech_fourbar){1.1, 3.9, 3.2, 4.4, 0.9, 1.6, 9.7};
  m->dpend = (mech_double_pendulum){1.1, 0.8, 0.6, 1.7, 9.3};
  m->crank = (bench_slider_crank){
      .a = 0.4, .J1 = 1.3, .m2 = 0.7, .J2 = 2.2, .k = 1.5, .c = 0.6, .l0 = 0.9, .F = 1.2};
  m->car = (bench_car_axis){
      .eps = 1.2e-2, .mass = 9.0, .L = 1.1, .L0 = 0.45, .r = 0.12, .w = 9.0, .g = 1.3};
  double scale = 1.0;
#define X(f) m->andrews.f *= (scale += 0.01);
  ANDREWS_FIELDS
#undef X
  copy_params(m);
  build(m);
}

/* ---- the callbacks, one by one ------------------------------------------------------------ */

enum {
  CB_MASS,
  CB_FORCE,
  CB_CONSTRAINT,
  CB_JACOBIAN,
  CB_CONSTRAINT_T,
  CB_POTENTIAL,
  CB_DAMPING,
  CB_MASS_DOT_V,
  CB_JACOBIAN_DOT,
  CB_CONSTRAINT_T_DOT,
  CALLBACKS
};
#define ABSENT (-100)

/* the shape of callback cb's output: rows x cols values */
static void shape(const sdae_mbs *s, int cb, size_t *rows, size_t *cols) {
  size_t n = s->n_q, m = s->n_c;
  *rows = cb == CB_MASS || cb == CB_DAMPING            ? n
          : cb == CB_JACOBIAN || cb == CB_JACOBIAN_DOT ? m
                                                       : 1;
  *cols = cb == CB_CONSTRAINT || cb == CB_CONSTRAINT_T || cb == CB_CONSTRAINT_T_DOT ? m
          : cb == CB_POTENTIAL                                                      ? 1
                                                                                    : n;
}

/* callback cb of s at (t, q, v) into out; ABSENT when s has none */
static int call(const sdae_mbs *s, int cb, double t, const double *q, const double *v,
                double *out) {
  void *p = s->params;
  switch (cb) {
  case CB_MASS: return s->mass ? s->mass(t, q, out, p) : ABSENT;
  case CB_FORCE: return s->force ? s->force(t, q, v, out, p) : ABSENT;
  case CB_CONSTRAINT: return s->constraint ? s->constraint(t, q, out, p) : ABSENT;
  case CB_JACOBIAN: return s->jacobian ? s->jacobian(t, q, out, p) : ABSENT;
  case CB_CONSTRAINT_T: return s->constraint_t ? s->constraint_t(t, q, out, p) : ABSENT;
  case CB_POTENTIAL: return s->potential ? s->potential(t, q, out, p) : ABSENT;
  case CB_DAMPING: return s->damping ? s->damping(t, q, out, p) : ABSENT;
  case CB_MASS_DOT_V: return s->mass_dot_v ? s->mass_dot_v(t, q, v, out, p) : ABSENT;
  case CB_JACOBIAN_DOT: return s->jacobian_dot ? s->jacobian_dot(t, q, v, out, p) : ABSENT;
  default: return s->constraint_t_dot ? s->constraint_t_dot(t, q, v, out, p) : ABSENT;
  }
}

/* A random state where both sides are defined and smooth: the slider crank's slider near its
 * range (its spring away from zero length, where the hand-written force fails), Andrews' rates
 * of the size it reaches (1.4e3 at t = 0.03), times over the benchmarks' intervals */
static void random_state(gsl_rng *r, int k, double *t, double *q, double *v) {
  size_t n = k == ANDREWS ? 7 : k == CRANK ? 3 : 4;
  double rate = k == ANDREWS ? 1e3 : 3.0;
  *t = tu_flat(r, 0.0, 3.0);
  for (size_t i = 0; i < n; i++) q[i] = tu_flat(r, -3, 3), v[i] = tu_flat(r, -rate, rate);
  if (k == CRANK) q[1] = tu_flat(r, 0.5, 1.5);
}

/* The largest mismatch |generated - hand| / scale of one callback at one state, the scale the
 * largest |entry| of the hand-written row (a matrix row; the whole vector of a vector-valued
 * callback) and at least the smallest normal number. Both sides sum the same terms in other
 * orders (sympy's expanded and common-subexpression form, the hand-written factored one), so
 * they differ by a few roundings of the largest term; at random states the terms are of the
 * row's size, which bounds that rounding, while an entry that cancels to a small value (a
 * constraint's row near 0) would make a per-entry scale demand more than rounding allows. The
 * callbacks the hand-written mechanism omits are the mathematics: the four-bar's and the
 * double pendulum's constraints do not depend on t, dc/dt and its derivative are 0. */
static double callback_mismatch(const sdae_mbs *gen, const sdae_mbs *hand, int cb, double t,
                                const double *q, const double *v) {
  /* one more value each: a callback writes its rows x cols values, no more */
  double g[NQ * NQ + 1], h[NQ * NQ + 1], worst = 0.0;
  size_t rows, cols;
  shape(hand, cb, &rows, &cols);
  g[rows * cols] = h[rows * cols] = -1.0;
  int rg = call(gen, cb, t, q, v, g);
  int rh = call(hand, cb, t, q, v, h);
  ck_assert(g[rows * cols] == -1.0 && h[rows * cols] == -1.0);
  if (rh == ABSENT) {
    /* the generated side has more only where the hand-written one relies on dc/dt = 0 */
    ck_assert(rg == ABSENT || cb == CB_CONSTRAINT_T || cb == CB_CONSTRAINT_T_DOT);
    if (rg == ABSENT) return 0.0;
    for (size_t i = 0; i < rows * cols; i++) h[i] = 0.0;
  } else {
    ck_assert_int_eq(rg, 0);
    ck_assert_int_eq(rh, 0);
  }
  for (size_t i = 0; i < rows; i++) {
    double scale = DBL_MIN;
    for (size_t j = 0; j < cols; j++) scale = fmax(scale, fabs(h[i * cols + j]));
    for (size_t j = 0; j < cols; j++)
      worst = fmax(worst, fabs(g[i * cols + j] - h[i * cols + j]) / scale);
  }
  return worst;
}

/* every callback at 200 random states per mechanism, with the programs' and with varied
 * parameters: within 1e-12 of its row (measured at most 1.0e-13, the car axis' dc/dt where its
 * two terms cancel, and 8e-14, the four-bar's potential; elsewhere 2e-14) */
START_TEST(test_callbacks_equal) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  models m;
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 0)
      program_defaults(&m);
    else
      varied(&m);
    for (int k = 0; k < MODELS; k++) {
      ck_assert_uint_eq(m.gen[k].n_q, m.hand[k].n_q);
      ck_assert_uint_eq(m.gen[k].n_c, m.hand[k].n_c);
      for (int trial = 0; trial < 200; trial++) {
        double t, q[NQ], v[NQ];
        random_state(r, k, &t, q, v);
        for (int cb = 0; cb < CALLBACKS; cb++)
          ck_assert_double_lt(callback_mismatch(&m.gen[k], &m.hand[k], cb, t, q, v), 1e-12);
      }
    }
  }
  gsl_rng_free(r);
}
END_TEST

/* The comparison sees a wrong callback: the hand-written four-bar with its rocker's length
 * for the coupler's (the constraint's second entry off by (e^2 - b^2)/2 = -3.5) and the
 * generated double pendulum with the outer mass for the inner one */
START_TEST(test_callbacks_wrong_caught) {
  models m;
  program_defaults(&m);
  double q[NQ] = {0.3, -0.9, 2.1, 0.4}, v[NQ] = {0.5, -0.2, 0.7, 1.1};
  m.fourbar.b = m.fourbar.e;
  ck_assert_double_gt(
      callback_mismatch(&m.gen[FOURBAR], &m.hand[FOURBAR], CB_CONSTRAINT, 0.0, q, v), 0.1);
  varied(&m);
  m.g_dpend.m1 = m.g_dpend.m2;
  ck_assert_double_gt(callback_mismatch(&m.gen[DPEND], &m.hand[DPEND], CB_MASS, 0.0, q, v), 0.1);
  ck_assert_double_gt(callback_mismatch(&m.gen[DPEND], &m.hand[DPEND], CB_FORCE, 0.0, q, v), 0.1);
}
END_TEST

/* ---- the derivatives against sdae_mbs_check ------------------------------------------------ */

#define ALL_DERIVATIVES ((1u << SDAE_MBS_DERIVATIVES) - 1)

/* A random state for the check: Andrews' rates of tens per second (the check differences the
 * callbacks with steps relative to the state; rates of 1e3 wind the angles by more than their
 * period within them) */
static void check_state(gsl_rng *r, int k, double *t, double *q, double *v) {
  random_state(r, k, t, q, v);
  if (k == ANDREWS)
    for (int i = 0; i < 7; i++) v[i] *= 0.02;
}

/* Every generated mechanism's derivatives at 20 random states: consistent at tol 1e-6, each
 * within 1e-7; all six compared, the car axis' force excepted (no potential: its road moves) */
START_TEST(test_derivatives_consistent) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  models m;
  varied(&m);
  for (int k = 0; k < MODELS; k++) {
    unsigned given = ALL_DERIVATIVES & ~(k == CAR ? 1u << SDAE_MBS_FORCE : 0u);
    for (int trial = 0; trial < 20; trial++) {
      double t, q[NQ], v[NQ];
      check_state(r, k, &t, q, v);
      tu_assert_derivatives_exact(&m.gen[k], t, q, v, given);
    }
  }
  gsl_rng_free(r);
}
END_TEST

/* one derivative along the motion negated through a wrapper (the three share a signature) */
typedef int (*along_motion)(double t, const double *q, const double *v, double *out, void *params);
static along_motion true_derivative;
static size_t derivative_len;

static int negated_derivative(double t, const double *q, const double *v, double *out,
                              void *params) {
  int rc = true_derivative(t, q, v, out, params);
  for (size_t i = 0; i < derivative_len; i++) out[i] = -out[i];
  return rc;
}

/* the check names the negated derivative, not consistent at tol 1e-6, where the mechanism
 * itself is consistent */
static void assert_negation_caught(const sdae_mbs *s, sdae_mbs_derivative d, double t,
                                   const double *q, const double *v) {
  sdae_mbs wrong = *s;
  sdae_mbs_check_report r;
  if (d == SDAE_MBS_MASS_DOT_V) {
    true_derivative = s->mass_dot_v, wrong.mass_dot_v = negated_derivative;
    derivative_len = s->n_q;
  } else if (d == SDAE_MBS_JACOBIAN_DOT) {
    true_derivative = s->jacobian_dot, wrong.jacobian_dot = negated_derivative;
    derivative_len = s->n_c * s->n_q;
  } else {
    true_derivative = s->constraint_t_dot, wrong.constraint_t_dot = negated_derivative;
    derivative_len = s->n_c;
  }
  ck_assert_int_eq(sdae_mbs_check(s, t, q, v, 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 1);
  ck_assert_int_eq(sdae_mbs_check(&wrong, t, q, v, 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_int_eq(r.worst, d);
}

/* jacobian_dot negated on every generated mechanism (it is not 0 where v is not), and the
 * derivatives that are not 0 on a mechanism: Andrews' (d/ds M) v (M depends on q) and the car
 * axis' d/ds dc/dt (its road moves) */
START_TEST(test_wrong_derivative_caught) {
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  models m;
  varied(&m);
  for (int k = 0; k < MODELS; k++) {
    double t, q[NQ], v[NQ];
    check_state(r, k, &t, q, v);
    assert_negation_caught(&m.gen[k], SDAE_MBS_JACOBIAN_DOT, t, q, v);
    if (k == ANDREWS) assert_negation_caught(&m.gen[k], SDAE_MBS_MASS_DOT_V, t, q, v);
    if (k == CAR) assert_negation_caught(&m.gen[k], SDAE_MBS_CONSTRAINT_T_DOT, t, q, v);
  }
  gsl_rng_free(r);
}
END_TEST

/* ---- the defaults and the starts ----------------------------------------------------------- */

/* the generated defaults are the programs' parameters, exactly (both are the same decimal
 * constants read by the compiler) */
START_TEST(test_defaults_equal) {
  models m, h;
  program_defaults(&m);
  program_defaults(&h);
  copy_params(&h); /* h.g_*: the hand-written values where the sides share a parameter */
#define X(f) ck_assert(m.g_fourbar.f == h.g_fourbar.f);
  FOURBAR_FIELDS
#undef X
#define X(f) ck_assert(m.g_dpend.f == h.g_dpend.f);
  DPEND_FIELDS
#undef X
#define X(f) ck_assert(m.g_crank.f == h.g_crank.f);
  CRANK_FIELDS
#undef X
#define X(f) ck_assert(m.g_car.f == h.g_car.f);
  CAR_FIELDS
#undef X
#define X(f) ck_assert(m.g_andrews.f == h.g_andrews.f);
  ANDREWS_FIELDS
#undef X
  /* the start's own parameters: examples/fourbar.c's crank angle 0 turning at 5, and
   * examples/double_pendulum.c's arms at rest at 2.0 and 2.5 */
  ck_assert(m.g_fourbar.theta0 == 0.0 && m.g_fourbar.omega0 == 5.0);
  ck_assert(m.g_dpend.theta1 == 2.0 && m.g_dpend.theta2 == 2.5);
  ck_assert(m.g_dpend.omega1 == 0.0 && m.g_dpend.omega2 == 0.0);
}
END_TEST

/* the hand-written start of mechanism k with the start parameters of the generated side */
static void hand_start(const models *m, int k, double *q, double *v) {
  const double a[2] = {m->g_dpend.theta1, m->g_dpend.theta2};
  const double w[2] = {m->g_dpend.omega1, m->g_dpend.omega2};
  switch (k) {
  case FOURBAR:
    ck_assert_int_eq(
        mech_fourbar_state(&m->fourbar, m->g_fourbar.theta0, m->g_fourbar.omega0, q, v), 0);
    break;
  case DPEND: mech_double_pendulum_state(&m->dpend, a, w, q, v); break;
  case CRANK: bench_slider_crank_initial(&m->crank, q, v); break;
  case CAR: bench_car_axis_initial(&m->car, q, v); break;
  default: bench_andrews_initial(q, v);
  }
}

static void generated_start(const models *m, int k, double *q, double *v) {
  switch (k) {
  case FOURBAR: fourbar_start(&m->g_fourbar, q, v); break;
  case DPEND: double_pendulum_start(&m->g_dpend, q, v); break;
  case CRANK: slider_crank_start(&m->g_crank, q, v); break;
  case CAR: car_axis_start(&m->g_car, q, v); break;
  default: andrews_start(&m->g_andrews, q, v);
  }
}

/* entry by entry within tol relative to max(1, |entry|): the starts are O(1) numbers computed
 * by the same formulas in other orders (measured at most 2.2e-16) */
static void assert_starts_equal(const models *m, double tol) {
  for (int k = 0; k < MODELS; k++) {
    double qg[NQ], vg[NQ], qh[NQ], vh[NQ];
    generated_start(m, k, qg, vg);
    hand_start(m, k, qh, vh);
    for (size_t i = 0; i < m->gen[k].n_q; i++) {
      ck_assert_double_eq_tol(qg[i], qh[i], tol * fmax(1.0, fabs(qh[i])));
      ck_assert_double_eq_tol(vg[i], vh[i], tol * fmax(1.0, fabs(vh[i])));
    }
  }
}

/* the defaults' starts, and the starts of varied parameters with the four-bar's crank at 0.7
 * turning backwards and the double pendulum's arms in motion (at rest the rates' formula is
 * not seen) */
START_TEST(test_starts_equal) {
  models m;
  program_defaults(&m);
  assert_starts_equal(&m, 1e-14);
  varied(&m);
  m.g_fourbar.theta0 = 0.7, m.g_fourbar.omega0 = -2.0;
  m.g_dpend.theta1 = 0.3, m.g_dpend.theta2 = -1.2;
  m.g_dpend.omega1 = 0.7, m.g_dpend.omega2 = -1.9;
  assert_starts_equal(&m, 1e-14);
}
END_TEST

/* ---- the trajectories ----------------------------------------------------------------------- */

/* n steps of T from the start with the example programs' gains (scheme 15, delta 2, epsilon 1)
 * and map; the state after every step into q, v (n x n_q each) */
static void trajectory(const sdae_mbs *sys, const sdae_map_type *map, double T, size_t n,
                       const double *q0, const double *v0, double *q, double *v) {
  sdae_options o;
  sdae_mbs_stepper *s = NULL;
  size_t nq = sys->n_q;
  sdae_options_default(&o);
  o.delta = 2.0;
  o.epsilon = 1.0;
  o.map = map;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, sys, &o), SDAE_OK);
  double qk[NQ], vk[NQ];
  for (size_t i = 0; i < nq; i++) qk[i] = q0[i], vk[i] = v0[i];
  for (size_t k = 0; k < n; k++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)k * T, T, qk, vk), SDAE_OK);
    for (size_t i = 0; i < nq; i++) q[k * nq + i] = qk[i], v[k * nq + i] = vk[i];
  }
  sdae_mbs_stepper_free(s);
}

#define STEPS 300

/* the largest |a - b| over a trajectory's values relative to the largest |b| (and 1) */
static double trajectory_mismatch(const double *a, const double *b, size_t len) {
  double diff = 0.0, size = 1.0;
  for (size_t i = 0; i < len; i++) {
    diff = fmax(diff, fabs(a[i] - b[i]));
    size = fmax(size, fabs(b[i]));
  }
  return diff / size;
}

/* The map's own response to rounding: the largest mismatch (q or v) of the hand-written
 * trajectory against itself from the start with one coordinate moved by one ulp, over the
 * coordinates */
static double rounding_response(const sdae_mbs *hand, const sdae_map_type *map, double T,
                                const double *q0, const double *v0, const double *qh,
                                const double *vh) {
  static double q[STEPS * NQ], v[STEPS * NQ];
  size_t n = hand->n_q;
  double worst = 0.0;
  for (size_t i = 0; i < n; i++) {
    double q1[NQ];
    for (size_t j = 0; j < n; j++) q1[j] = q0[j];
    q1[i] = nextafter(q1[i], INFINITY);
    trajectory(hand, map, T, STEPS, q1, v0, q, v);
    worst = fmax(
        worst, fmax(trajectory_mismatch(q, qh, STEPS * n), trajectory_mismatch(v, vh, STEPS * n)));
  }
  return worst;
}

/* Both sides from the same (hand-written) start, 300 steps with the programs' T (1e-5 for
 * Andrews, 1e-3 otherwise) and map (dgrad; the midpoint rule for the car axis, which has no
 * potential), and with rk4: q and v agree to 1e-12 relative to their largest value (measured
 * at most 2.4e-14), or to 10 times the map's own response to a rounding where that is larger.
 * The callbacks differ by rounding, and each step's Newton iteration stops at
 * SDAE_MBS_NEWTON_TOL on both sides alike. The default double pendulum is chaotic, but its
 * largest Lyapunov exponent is about 1.6/s (starts 1e-9 apart separate to 2.7e-4 by t = 8,
 * check_mechanisms' chaos test): over these 0.3 s it amplifies a difference by about
 * e^0.5 < 2. The discrete gradient on Andrews' mechanism is the exception: its difference
 * quotient divides the rounding of H by the step's increment (<stabdae/mbs.h>), and from rest
 * at T = 1e-5 the increments are small, so one ulp of one start angle moves the hand-written
 * trajectory by up to 4e-11 relative (measured), the generated one 2.5e-11 from it. */
START_TEST(test_trajectories_agree) {
  models m;
  program_defaults(&m);
  for (int k = 0; k < MODELS; k++) {
    const sdae_map_type *maps[2] = {k == CAR ? sdae_map_midpoint : sdae_map_dgrad, sdae_map_rk4};
    double T = k == ANDREWS ? 1e-5 : 1e-3, q0[NQ], v0[NQ];
    static double qg[STEPS * NQ], vg[STEPS * NQ], qh[STEPS * NQ], vh[STEPS * NQ];
    size_t n = m.gen[k].n_q, len = STEPS * n;
    hand_start(&m, k, q0, v0);
    for (int j = 0; j < 2; j++) {
      trajectory(&m.gen[k], maps[j], T, STEPS, q0, v0, qg, vg);
      trajectory(&m.hand[k], maps[j], T, STEPS, q0, v0, qh, vh);
      double bound = fmax(1e-12, 10 * rounding_response(&m.hand[k], maps[j], T, q0, v0, qh, vh));
      /* the exception above alone: elsewhere the map's response stays below 1e-13 */
      ck_assert(bound == 1e-12 || (k == ANDREWS && maps[j] == sdae_map_dgrad));
      ck_assert_double_lt(bound, 1e-9);
      ck_assert_double_lt(trajectory_mismatch(qg, qh, len), bound);
      ck_assert_double_lt(trajectory_mismatch(vg, vh, len), bound);
      /* the motion is not trivial: the state moved by far more than the bound */
      ck_assert_double_gt(trajectory_mismatch(qh + len - n, q0, n), 1e-6);
    }
  }
}
END_TEST

/* The four-bar written by its nonzeros (sym/fourbar_sparse.py): its patterns are the
 * structural nonzeros of the geometry, M = diag(mB, mB, mC, mC) and each constraint's row at the
 * coordinates of its moving ends (B; B and C; C). Stepped in its own sparse coordinates, under
 * rk4 and under dgrad (an implicit map, its Newton on the sparse back-end's linear solve), it
 * steps as the dense generated four-bar to the map's truncation error (the two back-ends may
 * choose other charts, and a map's error depends on the chart): after 0.3 s the difference
 * falls by about 2^p as T halves, 16 for rk4, 4 for dgrad */
START_TEST(test_sparse_fourbar_steps_as_the_dense) {
  static const size_t mass_start[] = {0, 1, 2, 3, 4}, mass_col[] = {0, 1, 2, 3};
  static const size_t jac_start[] = {0, 2, 6, 8}, jac_col[] = {0, 1, 0, 1, 2, 3, 2, 3};
  fourbar_params pd;
  fourbar_sparse_params ps;
  double q0[4], v0[4];
  static double qd[STEPS * 4], vd[STEPS * 4], qs[STEPS * 4], vs[STEPS * 4];
  fourbar_params_default(&pd);
  fourbar_sparse_params_default(&ps);
  sdae_mbs dense = fourbar_mbs(&pd), sparse = fourbar_sparse_mbs(&ps);
  ck_assert_ptr_null(dense.mass_pattern);
  ck_assert_int_eq(FOURBAR_SPARSE, 0);
  ck_assert_int_eq(FOURBAR_SPARSE_SPARSE, 1);
  ck_assert_uint_eq(sparse.mass_pattern->nnz, 4);
  ck_assert_mem_eq(sparse.mass_pattern->row_start, mass_start, sizeof mass_start);
  ck_assert_mem_eq(sparse.mass_pattern->col, mass_col, sizeof mass_col);
  ck_assert_uint_eq(sparse.jacobian_pattern->nnz, 8);
  ck_assert_mem_eq(sparse.jacobian_pattern->row_start, jac_start, sizeof jac_start);
  ck_assert_mem_eq(sparse.jacobian_pattern->col, jac_col, sizeof jac_col);
  fourbar_start(&pd, q0, v0);
  const sdae_map_type *maps[] = {sdae_map_rk4, sdae_map_dgrad};
  const double falls[] = {10.0, 3.0}; /* 16 and 4, less a margin for the next order's term */
  for (int k = 0; k < 2; k++) {
    double diff[2];
    for (int h = 0; h < 2; h++) { /* the last states after 0.3 s at T = 2e-3 and 1e-3 */
      double T = h ? 1e-3 : 2e-3;
      size_t n = h ? STEPS : STEPS / 2;
      trajectory(&dense, maps[k], T, n, q0, v0, qd, vd);
      trajectory(&sparse, maps[k], T, n, q0, v0, qs, vs);
      diff[h] = trajectory_mismatch(qs + (n - 1) * 4, qd + (n - 1) * 4, 4);
    }
    ck_assert_double_gt(trajectory_mismatch(qd + (STEPS - 1) * 4, q0, 4), 1e-3);
    ck_assert_double_lt(diff[0], 1e-4);
    ck_assert_double_ge(diff[0], falls[k] * diff[1]);
  }
}
END_TEST

static Suite *generated_suite(void) {
  Suite *s = suite_create("generated");
  TCase *tc = tcase_create("callbacks");
  tcase_add_test(tc, test_callbacks_equal);
  tcase_add_test(tc, test_callbacks_wrong_caught);
  suite_add_tcase(s, tc);
  tc = tcase_create("derivatives");
  tcase_add_test(tc, test_derivatives_consistent);
  tcase_add_test(tc, test_wrong_derivative_caught);
  suite_add_tcase(s, tc);
  tc = tcase_create("starts");
  tcase_add_test(tc, test_defaults_equal);
  tcase_add_test(tc, test_starts_equal);
  suite_add_tcase(s, tc);
  tc = tcase_create("trajectories");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_trajectories_agree);
  suite_add_tcase(s, tc);
  tc = tcase_create("sparse");
  tcase_add_test(tc, test_sparse_fourbar_steps_as_the_dense);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(generated_suite());
  srunner_run_all(sr, CK_NORMAL);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
