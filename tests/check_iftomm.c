/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The IFToMM benchmark problems (examples/models): the N-four-bar (A02) against its one-angle
 * reduction, which the parallelogram geometry gives in closed form, and the library's steps
 * across its singular configurations; an isosceles slider-crank across its bifurcation, a
 * singular configuration of another kind; Bricard's mechanism (A04) with all its 24 constraints
 * of rank 23. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stabdae/mbs.h>

#include <gsl/gsl_linalg.h>
#include <gsl/gsl_odeiv2.h>

#include "bricard.h"
#include "mbs/mbs_impl.h"
#include "nfourbar.h"
#include "testmodels.h"

/* the reduction's constants: J theta'' = K ga sin theta */
static void reduction(const mech_nfourbar *p, double *J, double *K) {
  double N = (double)p->N;
  *J = (N + 1.0) * p->m / 3.0 + N * p->m;
  *K = (N + 1.0) * p->m / 2.0 + N * p->m;
}

/* every rocker at theta from the upright turning at omega: B_i = A_i + (sin, cos) theta */
static void parallelogram(const mech_nfourbar *p, double theta, double omega, double *q,
                          double *v) {
  for (size_t i = 0; i <= p->N; i++) {
    q[2 * i] = (double)i + sin(theta), q[2 * i + 1] = cos(theta);
    v[2 * i] = omega * cos(theta), v[2 * i + 1] = -omega * sin(theta);
  }
}

/* The elliptic reference against classical RK4 on theta'' = (K ga / J) sin theta from (0, 1),
 * h = 1e-4 (its error about 1e-13 over 3 s): B_0 agrees to 1e-10 at every output, through the
 * first flat positions (t = 0.72, 1.24) and a whole turn (its period 1.97 s). */
START_TEST(the_reference_is_the_reduced_pendulum) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  double J, K, w2, x[2] = {0.0, 1.0}, h = 1e-4;
  reduction(&p, &J, &K);
  w2 = K * p.ga / J;
  for (int i = 1; i <= 30000; i++) {
    double k1[2], k2[2], k3[2], k4[2];
    k1[0] = x[1], k1[1] = w2 * sin(x[0]);
    k2[0] = x[1] + 0.5 * h * k1[1], k2[1] = w2 * sin(x[0] + 0.5 * h * k1[0]);
    k3[0] = x[1] + 0.5 * h * k2[1], k3[1] = w2 * sin(x[0] + 0.5 * h * k2[0]);
    k4[0] = x[1] + h * k3[1], k4[1] = w2 * sin(x[0] + h * k3[0]);
    for (int j = 0; j < 2; j++) x[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    if (i % 2500 == 0) {
      double b[2];
      mech_nfourbar_reference(&p, i * h, b);
      ck_assert_double_eq_tol(b[0], sin(x[0]), 1e-10);
      ck_assert_double_eq_tol(b[1], cos(x[0]), 1e-10);
    }
  }
}
END_TEST

/* The mechanism is the reduction: on the parallelogram every constraint holds and G v = 0 (c
 * to rounding), the energy is (1/2) J omega^2 + K ga cos theta (its potential counted from the
 * pivots' height), and every derivative it gives agrees with differences. */
START_TEST(the_mechanism_is_the_parallelogram) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[82], v[82], c[81], *G = malloc(81 * 82 * sizeof *G), J, K;
  mech_nfourbar_system(&sys, &p);
  reduction(&p, &J, &K);
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  for (double theta = 0.1; theta < 6.2; theta += 0.7) {
    double omega = 1.0 + theta, E;
    sdae_mbs_check_report r;
    parallelogram(&p, theta, omega, q, v);
    ck_assert_int_eq(sys.constraint(0.0, q, c, sys.params), 0);
    ck_assert_int_eq(sys.jacobian(0.0, q, G, sys.params), 0);
    for (size_t j = 0; j < sys.n_c; j++) {
      double gv = 0.0;
      for (size_t k = 0; k < sys.n_q; k++) gv += G[j * sys.n_q + k] * v[k];
      ck_assert_double_le(fabs(c[j]), 1e-15 * (double)(p.N + 1));
      ck_assert_double_le(fabs(gv), 1e-13 * omega * (double)(p.N + 1));
    }
    ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E), SDAE_OK);
    ck_assert_double_eq_tol(E, 0.5 * J * omega * omega + K * p.ga * cos(theta), 1e-12 * fabs(E));
    ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
    ck_assert(r.consistent);
  }
  sdae_mbs_stepper_free(s);
  free(G);
}
END_TEST

/* What a run of N four-bars from the benchmark's start to tf found (across the flat positions
 * at t = 0.72 and 1.24 for tf = 1.5): the benchmark's error (B_0
 * against the reference, each 0.05 s), the energy's relative change, the largest |c_j| after
 * any step, the steps projected */
typedef struct crossing {
  double err, dE, c;
  unsigned long projected;
} crossing;

/* sparse: the mechanism given its patterns (the sparse back-end) */
static crossing cross_flat(const sdae_map_type *map, double T, size_t N, double tf, int sparse) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[82], v[82], c[81], E0, E;
  crossing r = {0.0, 0.0, 0.0, 0};
  size_t steps = (size_t)lround(tf / T), every = (size_t)lround(0.05 / T);
  p.N = N; /* at most the benchmark's 40: the arrays' sizes */
  p.sparse = sparse;
  ck_assert_int_eq(mech_nfourbar_system(&sys, &p), 0);
  sdae_options_default(&o);
  o.map = map;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  mech_nfourbar_start(&p, q, v);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E0), SDAE_OK);
  for (size_t i = 0; i < steps; i++) {
    double t = (double)(i + 1) * T, b[2];
    ck_assert_int_eq(sdae_mbs_step(s, (double)i * T, T, q, v), SDAE_OK);
    ck_assert_int_eq(sys.constraint(t, q, c, sys.params), 0);
    for (size_t j = 0; j < sys.n_c; j++) r.c = fmax(r.c, fabs(c[j]));
    if ((i + 1) % every != 0) continue;
    mech_nfourbar_reference(&p, t, b);
    r.err = fmax(r.err, hypot(q[0] - b[0], q[1] - b[1]));
    ck_assert_int_eq(sdae_mbs_energy(s, t, q, v, &E), SDAE_OK);
    r.dE = fmax(r.dE, fabs(E - E0) / fabs(E0));
  }
  r.projected = sdae_mbs_stepper_stats(s)->projected_steps;
  ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, sparse);
  sdae_mbs_stepper_free(s);
  mech_nfourbar_free(&p);
  return r;
}

static crossing cross_flat_positions(const sdae_map_type *map, double T, size_t N, double tf) {
  return cross_flat(map, T, N, tf, 0);
}

/* rk8 across the first two flat positions to t = 1.5: the benchmark's 40 four-bars at T =
 * 1e-2, and 10 at 1e-3, where the chart alone lost accuracy as T shrank (its steps land nearer
 * the flat positions: without the projection, B_0 is 9.6e-4 off and the energy 8.9e-4). The
 * steps near them projected, B_0 within 1e-9 of the reference (rk8's own error there is about
 * 1e-11), the energy to 1e-10, every constraint at rounding after every step */
START_TEST(rk8_crosses_the_flat_positions_as_T_shrinks) {
  const double Ts[2] = {1e-2, 1e-3};
  const size_t Ns[2] = {40, 10};
  for (int k = 0; k < 2; k++) {
    crossing r = cross_flat_positions(sdae_map_rk8, Ts[k], Ns[k], 1.5);
    ck_assert_uint_gt(r.projected, 0);
    ck_assert_double_le(r.err, 1e-9);
    ck_assert_double_le(r.dE, 1e-10);
    ck_assert_double_le(r.c, 1e-13);
  }
}
END_TEST

/* The error falls at the map's order through the first two crossings, on 10 four-bars (the
 * same singular structure, rank 21 to 11 where flat, at a twentieth of the cost): T = 5e-3
 * against 2.5e-3 to t = 1.5, the errors' ratio 2^p within [lo, hi] (the projected steps are
 * rk8's, more accurate) */
static void converges_at_order(const sdae_map_type *map, double lo, double hi) {
  crossing big = cross_flat_positions(map, 5e-3, 10, 1.5);
  crossing small = cross_flat_positions(map, 2.5e-3, 10, 1.5);
  ck_assert_uint_gt(small.projected, big.projected);
  ck_assert_double_le(small.err, 1e-3); /* the benchmark's high-precision criterion */
  ck_assert_double_ge(big.err / small.err, lo);
  ck_assert_double_le(big.err / small.err, hi);
  ck_assert_double_le(fmax(big.c, small.c), 1e-13);
}

/* The same on the sparse back-end (the mechanism given its patterns), whose independence is
 * its velocity system's (mbs_sparse.c) and whose projection solves the softened saddle-point
 * system (mbs_project_sparse.c): rk4 at T = 1e-3 and 5e-4 to t = 1.5 across both flat
 * positions, where the chart alone returned SDAE_OK with an error growing as T shrank (1.1e-6
 * at rk8's T = 1e-2, 1e-3 at rk4's 1e-4 over 5 s). The steps near them projected, the error
 * and the energy's change falling at rk4's order, B_0 within 1e-9 (measured 2.5e-10, the dense
 * back-end's 1.8e-10), the constraints at rounding. */
START_TEST(the_sparse_back_end_projects_through_the_crossings) {
  crossing big = cross_flat(sdae_map_rk4, 1e-3, 10, 1.5, 1);
  crossing small = cross_flat(sdae_map_rk4, 5e-4, 10, 1.5, 1);
  ck_assert_uint_gt(big.projected, 0);
  ck_assert_uint_gt(small.projected, big.projected);
  ck_assert_double_le(small.err, 1e-9);
  ck_assert_double_ge(big.err / small.err, 8.0); /* 2^4 = 16 */
  ck_assert_double_le(big.err / small.err, 24.0);
  ck_assert_double_ge(big.dE / small.dE, 8.0); /* rk4's energy error, at its order too */
  ck_assert_double_le(fmax(big.c, small.c), 1e-13);
}
END_TEST

START_TEST(rk4_converges_at_order_four_through_the_crossings) {
  converges_at_order(sdae_map_rk4, 12.0, 24.0);
}
END_TEST

START_TEST(midpoint_converges_at_order_two_through_the_crossings) {
  converges_at_order(sdae_map_midpoint, 3.0, 5.5);
}
END_TEST

/* dgrad at its order, and its energy kept through the crossings (rk8's projected steps leave it
 * within about 1e-12 there) */
START_TEST(dgrad_converges_and_keeps_the_energy_through_the_crossings) {
  converges_at_order(sdae_map_dgrad, 3.0, 5.5);
  ck_assert_double_le(cross_flat_positions(sdae_map_dgrad, 5e-3, 10, 1.5).dE, 1e-10);
}
END_TEST

/* The N-four-bar pushed along x at every tip B_i by h(t) = 0.5 sin(3 t) N (an input force:
 * time-dependent, applied in the projected steps too): the parallelogram is kept, and its angle
 * follows J theta'' = K ga sin theta + (N + 1) h(t) cos theta (the push's work on x_i = i +
 * sin theta), integrated by GSL's rk8pd to 1e-13. rk8 at T = 1e-2 to t = 1.5, across the first
 * flat positions: B_0 within 1e-8 of it, the steps near them projected. */
typedef struct pushed {
  mech_nfourbar p; /* first: the model's callbacks read their mech_nfourbar here */
  double h, w;
} pushed;

static int push(double t, const double *q, const double *v, double *F, void *params) {
  const pushed *w = params;
  (void)q, (void)v;
  for (size_t i = 0; i <= w->p.N; i++) F[2 * i] = w->h * sin(w->w * t), F[2 * i + 1] = 0.0;
  return 0;
}

static int pushed_angle(double t, const double *y, double *f, void *params) {
  const pushed *w = params;
  double J, K;
  reduction(&w->p, &J, &K);
  f[0] = y[1];
  f[1] = (K * w->p.ga * sin(y[0]) + (double)(w->p.N + 1) * w->h * sin(w->w * t) * cos(y[0])) / J;
  return GSL_SUCCESS;
}

/* rk8 at T = 1e-2 from (q, v) at t = 0 to 1.5 against the reduced angle (ode, from theta = 0,
 * theta' = 1, by GSL's rk8pd to 1e-13): B_0 at every 0.05 s within tol of (x0(t) + sin theta,
 * cos theta), x0 the frame's shift (NULL: none), and some steps projected */
static void follows_the_reduced_angle(const sdae_mbs *sys, double *q, double *v,
                                      gsl_odeiv2_system *ode, double (*x0)(const void *, double),
                                      double tol) {
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(ode, gsl_odeiv2_step_rk8pd, 1e-3, 1e-13, 0.0);
  sdae_mbs_stepper *s;
  sdae_options o;
  double y[2] = {0.0, 1.0}, t = 0.0;
  sdae_options_default(&o);
  o.map = sdae_map_rk8;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, sys, &o), SDAE_OK);
  for (int i = 0; i < 150; i++) {
    double ti = (i + 1) * 1e-2, shift;
    ck_assert_int_eq(sdae_mbs_step(s, i * 1e-2, 1e-2, q, v), SDAE_OK);
    if ((i + 1) % 5 != 0) continue;
    ck_assert_int_eq(gsl_odeiv2_driver_apply(d, &t, ti, y), GSL_SUCCESS);
    shift = x0 ? x0(ode->params, ti) : 0.0;
    ck_assert_double_le(hypot(q[0] - shift - sin(y[0]), q[1] - cos(y[0])), tol);
  }
  ck_assert_uint_gt(sdae_mbs_stepper_stats(s)->projected_steps, 0);
  sdae_mbs_stepper_free(s);
  gsl_odeiv2_driver_free(d);
}

START_TEST(a_pushed_nfourbar_crosses_the_flat_positions) {
  pushed w = {mech_nfourbar_benchmark(), 0.5, 3.0};
  gsl_odeiv2_system ode = {pushed_angle, NULL, 2, &w};
  sdae_mbs sys;
  double q[82], v[82];
  mech_nfourbar_system(&sys, &w.p);
  sys.params = &w;
  sys.input_force = push;
  mech_nfourbar_start(&w.p, q, v);
  follows_the_reduced_angle(&sys, q, v, &ode, NULL, 1e-8);
}
END_TEST

/* The N-four-bar whose rods' masses swell and shrink in time, M(t) = s(t) M_0 with s(t) = 1 +
 * 0.2 sin(3 t), under the weights of the unit masses: the front-end's M(t, q) v' = F - G^T lambda
 * keeps the parallelogram, its angle following s(t) J theta'' = K ga sin theta (GSL's rk8pd).
 * (dM/dt) v = s'(t) M_0 v given. rk8 at T = 1e-2 to t = 1.5 through the first flat positions,
 * on the dense back-end and given the patterns on the sparse one: within 1e-8 of it, the
 * projected steps' M at their own times (with the projection's M read a second late, B_0
 * leaves it). */
typedef struct swelling {
  mech_nfourbar p; /* first: the model's callbacks read their mech_nfourbar here */
  sdae_mbs base;
  double M[82 * 82];
} swelling;

static double swell(double t) { return 1.0 + 0.2 * sin(3.0 * t); }

/* M's values: n_q^2, or its pattern's */
static size_t swelling_values(const swelling *w) {
  return w->p.sparse ? w->p.mass_pattern.nnz : w->base.n_q * w->base.n_q;
}

static int swelling_mass(double t, const double *q, double *M, void *params) {
  swelling *w = params;
  int rc = w->base.mass(t, q, M, params);
  for (size_t k = 0; k < swelling_values(w); k++) M[k] *= swell(t);
  return rc;
}

static int swelling_mass_dot_v(double t, const double *q, const double *v, double *out,
                               void *params) {
  swelling *w = params;
  const sdae_pattern *P = &w->p.mass_pattern;
  size_t n = w->base.n_q;
  int rc = w->base.mass(t, q, w->M, params);
  for (size_t i = 0; i < n; i++) {
    double acc = 0.0;
    if (w->p.sparse)
      for (size_t e = P->row_start[i]; e < P->row_start[i + 1]; e++) acc += w->M[e] * v[P->col[e]];
    else
      for (size_t k = 0; k < n; k++) acc += w->M[i * n + k] * v[k];
    out[i] = 0.6 * cos(3.0 * t) * acc;
  }
  return rc;
}

static int swelling_angle(double t, const double *y, double *f, void *params) {
  const swelling *w = params;
  double J, K;
  reduction(&w->p, &J, &K);
  f[0] = y[1];
  f[1] = K * w->p.ga * sin(y[0]) / (swell(t) * J);
  return GSL_SUCCESS;
}

START_TEST(an_nfourbar_of_swelling_masses_crosses_the_flat_positions) {
  static swelling w;
  gsl_odeiv2_system ode = {swelling_angle, NULL, 2, &w};
  for (int sparse = 0; sparse < 2; sparse++) {
    sdae_mbs sys;
    double q[82], v[82];
    w.p = mech_nfourbar_benchmark();
    w.p.sparse = sparse;
    ck_assert_int_eq(mech_nfourbar_system(&w.base, &w.p), 0);
    sys = w.base;
    sys.params = &w;
    sys.mass = swelling_mass, sys.mass_dot_v = swelling_mass_dot_v;
    mech_nfourbar_start(&w.p, q, v);
    follows_the_reduced_angle(&sys, q, v, &ode, NULL, 1e-8);
    mech_nfourbar_free(&w.p);
  }
}
END_TEST

/* The N-four-bar on a ground that shakes along x, every pivot at A_i = (i + a(t), 0), a(t) =
 * 0.05 sin(4 t): the constraints depend on t (dc/dt and its derivative differenced, in the
 * projected steps too), the mass matrix is the fixed pivots' (each rocker's kinetic energy
 * m |B_i'|^2 / 6, the pivot's own motion carrying none). Every B_i moves alike,
 * B_i' = (a' + theta' cos theta, -theta' sin theta), so the kinetic energy is J |B_0'|^2 / 2 and
 * Lagrange's equation J theta'' = K ga sin theta - J a''(t) cos theta, B_0 = (a + sin theta,
 * cos theta), by GSL's rk8pd to 1e-13. rk8 at T = 1e-2 to t = 1.5 across the first flat positions:
 * B_0 within 1e-9 of it (the differenced derivatives good to about 1e-10), the steps near them
 * projected; and given the patterns, on the sparse back-end, with Gdot and the derivative of
 * dc/dt exact (each projected step's G at its own time). */
typedef struct shaken {
  mech_nfourbar p; /* first: the model's callbacks read their mech_nfourbar here */
  sdae_mbs base;
  double A, w;
  double rel[82], vrel[82], G[81 * 82], Gd[81 * 82];
} shaken;

static double ground(const void *params, double t) {
  const shaken *g = params;
  return g->A * sin(g->w * t);
}

/* q in the ground's frame */
static const double *in_frame(shaken *g, double t, const double *q) {
  for (size_t i = 0; i <= g->p.N; i++)
    g->rel[2 * i] = q[2 * i] - ground(g, t), g->rel[2 * i + 1] = q[2 * i + 1];
  return g->rel;
}

static int shaken_constraint(double t, const double *q, double *c, void *params) {
  shaken *g = params;
  return g->base.constraint(t, in_frame(g, t, q), c, params);
}

static int shaken_jacobian(double t, const double *q, double *G, void *params) {
  shaken *g = params;
  return g->base.jacobian(t, in_frame(g, t, q), G, params);
}

/* sum_i dc_j/dx_i of a matrix of G's shape (dense, or in the pattern's order) */
static double x_sum(const shaken *g, const double *G, size_t j) {
  const sdae_pattern *P = &g->p.jacobian_pattern;
  double sum = 0.0;
  if (!g->p.sparse) {
    for (size_t i = 0; i <= g->p.N; i++) sum += G[j * g->base.n_q + 2 * i];
    return sum;
  }
  for (size_t e = P->row_start[j]; e < P->row_start[j + 1]; e++)
    if (P->col[e] % 2 == 0) sum += G[e];
  return sum;
}

/* dc/dt = -a'(t) sum_i dc/dx_i */
static int shaken_constraint_t(double t, const double *q, double *ct, void *params) {
  shaken *g = params;
  int rc = g->base.jacobian(t, in_frame(g, t, q), g->G, params);
  for (size_t j = 0; j < g->base.n_c; j++) ct[j] = -g->A * g->w * cos(g->w * t) * x_sum(g, g->G, j);
  return rc;
}

/* along (1, v): Gdot at the velocities in the ground's frame, v - (a', 0) */
static int shaken_jacobian_dot(double t, const double *q, const double *v, double *Gd,
                               void *params) {
  shaken *g = params;
  for (size_t i = 0; i <= g->p.N; i++)
    g->vrel[2 * i] = v[2 * i] - g->A * g->w * cos(g->w * t), g->vrel[2 * i + 1] = v[2 * i + 1];
  return g->base.jacobian_dot(t, in_frame(g, t, q), g->vrel, Gd, params);
}

/* d/ds of dc/dt along (1, v): -a'' sum_i dc/dx_i - a' sum_i (Gdot)_{j, x_i} */
static int shaken_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                   void *params) {
  shaken *g = params;
  double a1 = g->A * g->w * cos(g->w * t), a2 = -g->A * g->w * g->w * sin(g->w * t);
  int rc = shaken_jacobian_dot(t, q, v, g->Gd, params);
  if (rc == 0) rc = g->base.jacobian(t, in_frame(g, t, q), g->G, params);
  for (size_t j = 0; j < g->base.n_c; j++)
    out[j] = -a2 * x_sum(g, g->G, j) - a1 * x_sum(g, g->Gd, j);
  return rc;
}

static int shaken_angle(double t, const double *y, double *f, void *params) {
  const shaken *g = params;
  double J, K, acc = -g->A * g->w * g->w * sin(g->w * t);
  reduction(&g->p, &J, &K);
  f[0] = y[1];
  f[1] = (K * g->p.ga * sin(y[0]) - J * acc * cos(y[0])) / J;
  return GSL_SUCCESS;
}

START_TEST(an_nfourbar_on_a_shaking_ground_crosses_the_flat_positions) {
  static shaken g;
  gsl_odeiv2_system ode = {shaken_angle, NULL, 2, &g};
  for (int sparse = 0; sparse < 2; sparse++) {
    sdae_mbs sys;
    double q[82], v[82];
    g.p = mech_nfourbar_benchmark(), g.A = 0.05, g.w = 4.0;
    g.p.sparse = sparse;
    ck_assert_int_eq(mech_nfourbar_system(&g.base, &g.p), 0);
    sys = g.base;
    sys.params = &g;
    sys.constraint = shaken_constraint, sys.jacobian = shaken_jacobian;
    sys.constraint_t = shaken_constraint_t;
    /* dense: differenced along (1, v); sparse: given, as the sparse back-end needs them */
    sys.jacobian_dot = sparse ? shaken_jacobian_dot : NULL;
    sys.constraint_t_dot = sparse ? shaken_constraint_t_dot : NULL;
    mech_nfourbar_start(&g.p, q, v);
    /* the benchmark's start in the ground's frame: B_i at 1 m/s relative to it, plus a'(0) */
    for (size_t i = 0; i <= g.p.N; i++) v[2 * i] += g.A * g.w;
    follows_the_reduced_angle(&sys, q, v, &ode, ground, 1e-9);
    mech_nfourbar_free(&g.p);
  }
}
END_TEST

/* A callback that fails within a projected step (from its first evaluation past the step's
 * start, so the chart's start at t sees none of it): the step returns the callback's status,
 * SDAE_ERR_CALLBACK_RECOVERABLE, with q, v and the statistics as they were, and once the
 * callback is well the same step is projected; each of constraint, jacobian, mass, force,
 * jacobian_dot and constraint_t (zero: given so that it can fail) in turn, and constraint
 * failing at the stages alone (well again at the step's end). Two four-bars 1e-3 rad from the flat
 * position at 5 rad/s. */
typedef struct flaky {
  mech_nfourbar p; /* first: the model's callbacks read their mech_nfourbar here */
  sdae_mbs base;
  int which; /* 0 constraint, 1 jacobian, 2 mass, 3 force, 4 jacobian_dot, 5 constraint_t */
  double t_fail, t_well; /* failing for t_fail < t < t_well */
} flaky;

static int fails(const flaky *f, int which, double t) {
  return f->which == which && t > f->t_fail && t < f->t_well;
}

static int flaky_constraint(double t, const double *q, double *c, void *params) {
  flaky *f = params;
  return fails(f, 0, t) ? 1 : f->base.constraint(t, q, c, params);
}

static int flaky_jacobian(double t, const double *q, double *G, void *params) {
  flaky *f = params;
  return fails(f, 1, t) ? 1 : f->base.jacobian(t, q, G, params);
}

static int flaky_mass(double t, const double *q, double *M, void *params) {
  flaky *f = params;
  return fails(f, 2, t) ? 1 : f->base.mass(t, q, M, params);
}

static int flaky_force(double t, const double *q, const double *v, double *F, void *params) {
  flaky *f = params;
  return fails(f, 3, t) ? 1 : f->base.force(t, q, v, F, params);
}

static int flaky_constraint_t(double t, const double *q, double *ct, void *params) {
  flaky *f = params;
  (void)q;
  memset(ct, 0, f->base.n_c * sizeof *ct);
  return fails(f, 5, t) ? 1 : 0;
}

static int flaky_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                              void *params) {
  flaky *f = params;
  return fails(f, 4, t) ? 1 : f->base.jacobian_dot(t, q, v, Gdot, params);
}

START_TEST(a_failing_callback_in_a_projected_step_keeps_the_state) {
  for (int k = 0; k < 7; k++) {
    /* the seventh: the constraint failing before the step's end alone */
    flaky f = {mech_nfourbar_benchmark(), {0}, k < 6 ? k : 0, HUGE_VAL, k < 6 ? HUGE_VAL : 1.01};
    sdae_mbs sys;
    sdae_mbs_stepper *s;
    sdae_options o;
    double q[6], v[6];
    f.p.N = 2;
    mech_nfourbar_system(&f.base, &f.p);
    sys = f.base;
    sys.params = &f;
    sys.constraint = flaky_constraint, sys.jacobian = flaky_jacobian;
    sys.mass = flaky_mass, sys.force = flaky_force, sys.jacobian_dot = flaky_jacobian_dot;
    sys.constraint_t = flaky_constraint_t;
    sdae_options_default(&o);
    o.map = sdae_map_rk4;
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    parallelogram(&f.p, 0.3, 1.0, q, v);
    ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
    parallelogram(&f.p, M_PI / 2.0 - 1e-3, 5.0, q, v);
    f.t_fail = 1.0;
    expect_step_fails(s, 1.0, 1e-2, q, v, 6, SDAE_ERR_CALLBACK_RECOVERABLE);
    ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->projected_steps, 0);
    f.t_fail = HUGE_VAL;
    ck_assert_int_eq(sdae_mbs_step(s, 1.0, 1e-2, q, v), SDAE_OK);
    ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->projected_steps, 1);
    sdae_mbs_stepper_free(s);
  }
}
END_TEST

/* A projected step that fails on the sparse back-end, at the last step's end (the saddle-point
 * factors and vectors it borrows from the step left softened), then taken again once the
 * callback is well: the state after it (the independence its start measured among its bytes)
 * and the motion from there are the ones a stepper that never failed has, bit for bit,
 * through the crossing and on to t = 0.012. Two four-bars 0.02 rad from the flat position at
 * 5 rad/s, rk4 at T = 1e-3. */
static int twelve_steps(sdae_mbs *sys, flaky *f, double *q, double *v, int fail_at,
                        unsigned char *bytes, size_t len) {
  sdae_mbs_stepper *s;
  sdae_options o;
  int first = -1;
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, sys, &o), SDAE_OK);
  ck_assert(s->coords.linalg == &sdae__mbs_sparse_linalg);
  for (int k = 0; k < 12; k++) {
    double t = 1e-3 * k;
    unsigned long before = sdae_mbs_stepper_stats(s)->projected_steps;
    if (k == fail_at) {
      f->t_fail = t;
      expect_step_fails(s, t, 1e-3, q, v, sys->n_q, SDAE_ERR_CALLBACK_RECOVERABLE);
      f->t_fail = HUGE_VAL;
    }
    ck_assert_int_eq(sdae_mbs_step(s, t, 1e-3, q, v), SDAE_OK);
    if (first < 0 && sdae_mbs_stepper_stats(s)->projected_steps > before) {
      first = k; /* the state's bytes after it: what the next step depends on */
      ck_assert_uint_le(sdae_mbs_state_size(s), len);
      ck_assert_int_eq(sdae_mbs_get_state(s, bytes, len), SDAE_OK);
    }
  }
  sdae_mbs_stepper_free(s);
  return first;
}

START_TEST(a_projected_step_failed_and_taken_again_keeps_the_motion) {
  double q[2][6], v[2][6];
  static unsigned char bytes[2][4096];
  int at = -1;
  for (int run = 0; run < 2; run++) {
    flaky f = {mech_nfourbar_benchmark(), {0}, 0, HUGE_VAL, HUGE_VAL};
    sdae_mbs sys;
    f.p.N = 2, f.p.sparse = 1;
    ck_assert_int_eq(mech_nfourbar_system(&f.base, &f.p), 0);
    sys = f.base;
    sys.params = &f;
    sys.constraint = flaky_constraint;
    parallelogram(&f.p, M_PI / 2.0 - 0.02, 5.0, q[run], v[run]);
    if (run == 0) {
      at = twelve_steps(&sys, &f, q[run], v[run], -1, bytes[run], sizeof bytes[run]);
      ck_assert_int_gt(at, 0); /* not the first step: its start is the last one's end */
    } else {
      ck_assert_int_eq(twelve_steps(&sys, &f, q[run], v[run], at, bytes[run], sizeof bytes[run]),
                       at);
    }
    mech_nfourbar_free(&f.p);
  }
  ck_assert_mem_eq(bytes[0], bytes[1], sizeof bytes[0]);
  ck_assert_mem_eq(q[0], q[1], sizeof q[0]);
  ck_assert_mem_eq(v[0], v[1], sizeof v[0]);
}
END_TEST

/* Two four-bars 1e-3 rad from the flat position at 5 rad/s: a projected step of T = 0.05 is
 * taken; one of T = 0.4 (rk8 far past its accuracy, omega T = 2) leaves the constraints by more
 * than SDAE_MBS_PROJECT_DRIFT of its motion and is refused, SDAE_ERR_CHART, the state kept. At
 * the flat position itself a first step has no chart: SDAE_ERR_RANK, as before. */
START_TEST(a_projected_step_that_cannot_be_accurate_is_refused) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[6], v[6];
  p.N = 2;
  mech_nfourbar_system(&sys, &p);
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  parallelogram(&p, M_PI / 2.0, 5.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_ERR_RANK);
  parallelogram(&p, 0.3, 1.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  parallelogram(&p, M_PI / 2.0 - 1e-3, 5.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 0.05, q, v), SDAE_OK);
  ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->projected_steps, 1);
  parallelogram(&p, M_PI / 2.0 - 1e-3, 5.0, q, v);
  expect_step_fails(s, 0.0, 0.4, q, v, 6, SDAE_ERR_CHART);
  /* T = 1.6: the projection's Gauss-Newton finds no point within its cap */
  expect_step_fails(s, 0.0, 1.6, q, v, 6, SDAE_ERR_NEWTON);
  ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->projected_steps, 1);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* A step from the flat position itself (rank G 3 of 5, no chart), after one elsewhere: projected,
 * and B_0 after it within 1e-10 of the reduced angle from (pi / 2, its omega) by GSL's rk8pd,
 * the constraints at rounding; rk4 at T = 1e-3 (the projected step is rk8's) */
START_TEST(a_step_from_the_flat_position_itself_is_projected) {
  pushed w = {mech_nfourbar_benchmark(), 0.0, 0.0};
  gsl_odeiv2_system ode = {pushed_angle, NULL, 2, &w};
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(&ode, gsl_odeiv2_step_rk8pd, 1e-4, 1e-14, 0.0);
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[6], v[6], c[5], J, K, y[2], t = 0.0;
  w.p.N = 2;
  reduction(&w.p, &J, &K);
  y[0] = M_PI / 2.0, y[1] = sqrt(1.0 + 2.0 * K * w.p.ga / J); /* from theta' = 1 upright */
  mech_nfourbar_system(&sys, &w.p);
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  parallelogram(&w.p, 0.3, 1.0, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  parallelogram(&w.p, y[0], y[1], q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->projected_steps, 1);
  ck_assert_int_eq(gsl_odeiv2_driver_apply(d, &t, 1e-3, y), GSL_SUCCESS);
  ck_assert_double_le(hypot(q[0] - sin(y[0]), q[1] - cos(y[0])), 1e-10);
  ck_assert_int_eq(sys.constraint(1e-3, q, c, sys.params), 0);
  for (size_t j = 0; j < 5; j++) ck_assert_double_le(fabs(c[j]), 1e-14);
  sdae_mbs_stepper_free(s);
  gsl_odeiv2_driver_free(d);
}
END_TEST

/* Ten four-bars at T = 1e-4 through the first flat position, from the reference state at t =
 * 0.5 + T / 12 (a step's grid on which a step ends 6.9e-7 rad from flat, 2100 steps on): rk8's
 * truncation is far below rounding there, so the energy must stay at its start to rounding;
 * every change within 1e-11 of it (the phase scans of docs/performance.md measured 4.8e-12 at
 * most on ten four-bars at this T). With the rows kept down to a sine of 1e-8 in the
 * projections (and to 6e-6 in the acceleration) the energy was 8.4e-10 off after the steps next
 * to the flat position, of the order of eps / s (s the rows' least sine, 1.5e-7 there). From
 * afar, as a run meets a singular configuration: a stepper started at t = 0.710008 (0.034 rad
 * from flat, the independence 0.0074) takes that for its mechanism's (SDAE_MBS_SINGULAR_NEAR is
 * relative to the largest seen) and projected only within a twentieth of it: 1.008e-11. */
START_TEST(a_step_landing_next_to_a_flat_position_keeps_the_energy) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[22], v[22], b0[2], J, K, E0, E, T = 1e-4, t0 = 0.5 + T / 12.0, nearest = 1.0;
  p.N = 10;
  reduction(&p, &J, &K);
  mech_nfourbar_reference(&p, t0, b0);
  double theta = atan2(b0[0], b0[1]);
  parallelogram(&p, theta, sqrt(1.0 + 2.0 * K * p.ga * (1.0 - cos(theta)) / J), q, v);
  mech_nfourbar_system(&sys, &p);
  sdae_options_default(&o);
  o.map = sdae_map_rk8;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_energy(s, t0, q, v, &E0), SDAE_OK);
  for (int i = 0; i < 2400; i++) {
    ck_assert_int_eq(sdae_mbs_step(s, t0 + i * T, T, q, v), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_energy(s, t0, q, v, &E), SDAE_OK);
    ck_assert_double_le(fabs(E / E0 - 1.0), 1e-11);
    nearest = fmin(nearest, fabs(q[1]));
  }
  ck_assert_double_le(nearest, 1e-6); /* the case it is about */
  sdae_mbs_stepper_free(s);
}
END_TEST

/* ---- the isosceles slider-crank: a bifurcation ----
 * A crank O A and a rod A B of length 1 (uniform, mass 1 each), a slider B of mass 1 on the x
 * axis, no gravity; q = (x_A, y_A, x_B), M constant (a rod's kinetic energy m (|P'|^2 + P'.Q' +
 * |Q'|^2) / 6). With the rod as long as the crank, the configurations are two branches, x_B =
 * 2 x_A (the crank turning the slider) and x_B = 0 (the slider at O, the rod turning), which
 * cross where A = (0, +-1): there the two rows of G are (0, +-1, 0) twice, rank 1. A singular
 * configuration of another kind than the N-four-bar's: one crossing point, not a whole flat
 * position. On the first branch x_A = cos theta, y_A = sin theta, J(theta) = w^T M w with w =
 * (-sin, cos, -2 sin): J = 2/3 + 6 sin^2 theta, and Lagrange's equation theta'' = -J' theta'^2 /
 * (2 J), by GSL's rk8pd to 1e-13. From theta = 0.3 at 1 rad/s the crossings are at t = 2.36 and
 * 7.59 (the quadrature of theta' = sqrt(J(0.3) / J)). */
static int crank_mass(double t, const double *q, double *M, void *params) {
  const double m[9] = {2.0 / 3.0, 0.0, 1.0 / 6.0, 0.0, 2.0 / 3.0, 0.0, 1.0 / 6.0, 0.0, 4.0 / 3.0};
  (void)t, (void)q, (void)params;
  memcpy(M, m, sizeof m);
  return 0;
}

static int crank_constraint(double t, const double *q, double *c, void *params) {
  (void)t, (void)params;
  c[0] = 0.5 * (q[0] * q[0] + q[1] * q[1] - 1.0);
  c[1] = 0.5 * ((q[2] - q[0]) * (q[2] - q[0]) + q[1] * q[1] - 1.0);
  return 0;
}

/* G's rows at positions x, or Gdot's at velocities x (both linear in x) */
static void crank_rows(const double *x, double *G) {
  double d = x[2] - x[0];
  G[0] = x[0], G[1] = x[1], G[2] = 0.0;
  G[3] = -d, G[4] = x[1], G[5] = d;
}

static int crank_jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  crank_rows(q, G);
  return 0;
}

static int crank_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                              void *params) {
  (void)t, (void)q, (void)params;
  crank_rows(v, Gdot);
  return 0;
}

static int crank_zero(double t, const double *q, const double *v, double *F, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  memset(F, 0, 3 * sizeof *F);
  return 0;
}

static int crank_zero_c(double t, const double *q, double *out, void *params) {
  (void)t, (void)q, (void)params;
  out[0] = out[1] = 0.0;
  return 0;
}

static int crank_zero_V(double t, const double *q, double *V, void *params) {
  (void)t, (void)q, (void)params;
  *V = 0.0;
  return 0;
}

static int crank_angle(double t, const double *y, double *f, void *params) {
  double s = sin(y[0]), J = 2.0 / 3.0 + 6.0 * s * s;
  (void)t, (void)params;
  f[0] = y[1], f[1] = -6.0 * s * cos(y[0]) * y[1] * y[1] / J;
  return GSL_SUCCESS;
}

typedef struct cranked {
  double err, energy; /* the largest distance from the reference, |dE / E| */
  unsigned long projected;
} cranked;

/* T-steps of the map to t = 8 (both crossings) against the reduced angle */
static cranked crank_run(const sdae_map_type *map, double T) {
  sdae_mbs sys = {.n_q = 3,
                  .n_c = 2,
                  .mass = crank_mass,
                  .force = crank_zero,
                  .constraint = crank_constraint,
                  .jacobian = crank_jacobian,
                  .constraint_t = crank_zero_c,
                  .potential = crank_zero_V,
                  .mass_dot_v = crank_zero,
                  .jacobian_dot = crank_jacobian_dot};
  gsl_odeiv2_system ode = {crank_angle, NULL, 2, NULL};
  gsl_odeiv2_driver *d =
      gsl_odeiv2_driver_alloc_y_new(&ode, gsl_odeiv2_step_rk8pd, 1e-4, 1e-13, 0.0);
  sdae_mbs_stepper *s;
  sdae_options o;
  double y[2] = {0.3, 1.0}, t = 0.0, E0, E, c[2];
  double q[3] = {cos(y[0]), sin(y[0]), 2.0 * cos(y[0])};
  double v[3] = {-sin(y[0]), cos(y[0]), -2.0 * sin(y[0])};
  cranked r = {0.0, 0.0, 0};
  long n = lround(8.0 / T);
  sdae_options_default(&o);
  o.map = map;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E0), SDAE_OK);
  for (long i = 0; i < n; i++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)i * T, T, q, v), SDAE_OK);
    ck_assert_int_eq(gsl_odeiv2_driver_apply(d, &t, (double)(i + 1) * T, y), GSL_SUCCESS);
    r.err = fmax(r.err, fmax(fmax(fabs(q[0] - cos(y[0])), fabs(q[1] - sin(y[0]))),
                             fabs(q[2] - 2.0 * cos(y[0]))));
    ck_assert_int_eq(sdae_mbs_energy(s, t, q, v, &E), SDAE_OK);
    r.energy = fmax(r.energy, fabs(E / E0 - 1.0));
    ck_assert_int_eq(crank_constraint(t, q, c, NULL), 0);
    ck_assert_double_le(fmax(fabs(c[0]), fabs(c[1])), 1e-14);
  }
  r.projected = sdae_mbs_stepper_stats(s)->projected_steps;
  sdae_mbs_stepper_free(s);
  gsl_odeiv2_driver_free(d);
  return r;
}

/* Through both crossings on the crank's branch (the other branch is a distance of order 1
 * away), every map at its order from T = 1e-2 to 5e-3: rk4's error falls by 2^4 (12 to 20),
 * midpoint's and dgrad's by 2^2 (3 to 5.5), dgrad's energy at rounding, rk8 within 1e-10, the
 * steps near the crossings projected, every constraint at rounding after every step. */
START_TEST(an_isosceles_slider_crank_crosses_its_bifurcation_on_its_branch) {
  const sdae_map_type *const order[] = {sdae_map_rk4, sdae_map_midpoint, sdae_map_dgrad};
  const double lo[] = {12.0, 3.0, 3.0}, hi[] = {20.0, 5.5, 5.5};
  cranked r8 = crank_run(sdae_map_rk8, 1e-2);
  ck_assert_double_le(r8.err, 1e-10);
  ck_assert_uint_gt(r8.projected, 0);
  for (size_t k = 0; k < 3; k++) {
    cranked a = crank_run(order[k], 1e-2), b = crank_run(order[k], 5e-3);
    ck_assert_double_ge(a.err / b.err, lo[k]);
    ck_assert_double_le(a.err / b.err, hi[k]);
    ck_assert_uint_gt(b.projected, a.projected);
    if (order[k] == sdae_map_dgrad) ck_assert_double_le(a.energy, 1e-11);
  }
}
END_TEST

/* ---- Bricard's mechanism ---- */

/* T-steps of the map from the benchmark's start to t; P_3 into p3 */
static void bricard_run(const sdae_map_type *map, double T, double t, double *p3) {
  mech_bricard p = mech_bricard_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[MECH_BRICARD_NQ], v[MECH_BRICARD_NQ];
  size_t n = (size_t)llround(t / T);
  mech_bricard_system(&sys, &p);
  sdae_options_default(&o);
  o.map = map;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  mech_bricard_start(q, v);
  for (size_t i = 0; i < n; i++)
    ck_assert_int_eq(sdae_mbs_step(s, (double)i * T, T, q, v), SDAE_OK);
  memcpy(p3, q + 6, 3 * sizeof *p3);
  sdae_mbs_stepper_free(s);
}

/* Bricard's with one row left out (drop, redundant on the others), for its multipliers */
typedef struct dropped {
  sdae_mbs all;
  size_t drop;
} dropped;
static double rows24[MECH_BRICARD_NC * MECH_BRICARD_NQ];
static void drop_row(const dropped *d, const double *all, size_t cols, double *out) {
  for (size_t j = 0, k = 0; j < MECH_BRICARD_NC; j++)
    if (j != d->drop) memcpy(out + cols * k++, all + cols * j, cols * sizeof *out);
}
static int dropped_c(double t, const double *q, double *c, void *p) {
  const dropped *d = p;
  int rc = d->all.constraint(t, q, rows24, d->all.params);
  drop_row(d, rows24, 1, c);
  return rc;
}
static int dropped_G(double t, const double *q, double *G, void *p) {
  const dropped *d = p;
  int rc = d->all.jacobian(t, q, rows24, d->all.params);
  drop_row(d, rows24, MECH_BRICARD_NQ, G);
  return rc;
}
static int dropped_Gdot(double t, const double *q, const double *v, double *G, void *p) {
  const dropped *d = p;
  int rc = d->all.jacobian_dot(t, q, v, rows24, d->all.params);
  drop_row(d, rows24, MECH_BRICARD_NQ, G);
  return rc;
}
static int dropped_mass(double t, const double *q, double *M, void *p) {
  const dropped *d = p;
  return d->all.mass(t, q, M, d->all.params);
}
static int dropped_force(double t, const double *q, const double *v, double *F, void *p) {
  const dropped *d = p;
  return d->all.force(t, q, v, F, d->all.params);
}
static int dropped_zero(double t, const double *q, double *out, void *p) {
  (void)t, (void)q, (void)p;
  memset(out, 0, (MECH_BRICARD_NC - 1) * sizeof *out);
  return 0;
}
static int dropped_zero_along(double t, const double *q, const double *v, double *out, void *p) {
  (void)v;
  return dropped_zero(t, q, out, p);
}

/* the constraint force G^T lambda (n_q) of n_c rows */
static void force_of(const sdae_mbs *sys, const double *q, const double *lambda, double *f) {
  double G[MECH_BRICARD_NC * MECH_BRICARD_NQ];
  sys->jacobian(0.0, q, G, sys->params);
  for (size_t i = 0; i < sys->n_q; i++) {
    f[i] = 0.0;
    for (size_t j = 0; j < sys->n_c; j++) f[i] += G[j * sys->n_q + i] * lambda[j];
  }
}

/* As posed, with all its constraints: dgrad at T = 1e-3 for 2 s keeps every one of the 24 at
 * rounding after every step and the energy to 1e-12 relative, the rank stays 23, and the
 * multipliers are the least-norm ones: orthogonal to the left null vector of G (the one
 * dependency among the rows, from GSL's SVD of G), which any other solution has a part along,
 * with the constraint force G^T lambda of the mechanism with a redundant row left out. */
START_TEST(bricard_keeps_all_its_constraints) {
  mech_bricard p = mech_bricard_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[MECH_BRICARD_NQ], v[MECH_BRICARD_NQ], c[MECH_BRICARD_NC], lambda[MECH_BRICARD_NC];
  double G[MECH_BRICARD_NC * MECH_BRICARD_NQ], V[MECH_BRICARD_NQ * MECH_BRICARD_NQ];
  double S[MECH_BRICARD_NQ], work[MECH_BRICARD_NQ], E0, E, along = 0.0, size = 0.0;
  size_t rank;
  mech_bricard_system(&sys, &p);
  sdae_options_default(&o);
  o.map = sdae_map_dgrad;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  mech_bricard_start(q, v);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E0), SDAE_OK);
  for (int i = 0; i < 2000; i++) {
    ck_assert_int_eq(sdae_mbs_step(s, i * 1e-3, 1e-3, q, v), SDAE_OK);
    ck_assert_int_eq(sys.constraint(0.0, q, c, sys.params), 0);
    for (size_t j = 0; j < sys.n_c; j++) ck_assert_double_le(fabs(c[j]), 1e-13);
  }
  ck_assert_int_eq(sdae_mbs_energy(s, 2.0, q, v, &E), SDAE_OK);
  ck_assert_double_le(fabs(E - E0), 1e-12 * fabs(E0));
  ck_assert_int_eq(sdae_mbs_redundant(&sys, 2.0, q, &rank, NULL, NULL), SDAE_OK);
  ck_assert_uint_eq(rank, MECH_BRICARD_NC - 1);
  ck_assert_int_eq(sdae_mbs_lambda(s, 2.0, q, v, lambda), SDAE_OK);
  ck_assert_int_eq(sys.jacobian(2.0, q, G, sys.params), 0);
  {
    gsl_matrix_view U = gsl_matrix_view_array(G, MECH_BRICARD_NC, MECH_BRICARD_NQ);
    gsl_matrix_view Vm = gsl_matrix_view_array(V, MECH_BRICARD_NQ, MECH_BRICARD_NQ);
    gsl_vector_view Sv = gsl_vector_view_array(S, MECH_BRICARD_NQ);
    gsl_vector_view wv = gsl_vector_view_array(work, MECH_BRICARD_NQ);
    ck_assert_int_eq(gsl_linalg_SV_decomp(&U.matrix, &Vm.matrix, &Sv.vector, &wv.vector), 0);
    ck_assert_double_le(S[MECH_BRICARD_NQ - 1], 1e-12 * S[0]); /* G = U S V^T: rank 23 */
  }
  for (size_t j = 0; j < sys.n_c; j++) { /* U's last column: the rows' dependency */
    along += G[j * MECH_BRICARD_NQ + MECH_BRICARD_NQ - 1] * lambda[j];
    size = fmax(size, fabs(lambda[j]));
  }
  ck_assert_double_gt(size, 1.0); /* the rods' weight is carried */
  ck_assert_double_le(fabs(along), 1e-10 * size);
  { /* the force is unique: the same as with a redundant row left out, which needs no choice */
    dropped d = {sys, 0};
    sdae_mbs_stepper *s23;
    size_t order[MECH_BRICARD_NC];
    double lambda23[MECH_BRICARD_NC - 1], f24[MECH_BRICARD_NQ], f23[MECH_BRICARD_NQ];
    sdae_mbs sys23 = sys;
    ck_assert_int_eq(sdae_mbs_redundant(&sys, 2.0, q, &rank, order, NULL), SDAE_OK);
    d.drop = order[MECH_BRICARD_NC - 1];
    sys23.n_c = MECH_BRICARD_NC - 1, sys23.rank = 0, sys23.params = &d;
    sys23.constraint = dropped_c, sys23.jacobian = dropped_G, sys23.jacobian_dot = dropped_Gdot;
    sys23.constraint_t = dropped_zero, sys23.constraint_t_dot = dropped_zero_along;
    sys23.mass = dropped_mass, sys23.force = dropped_force, sys23.potential = NULL;
    sys23.mass_dot_v = sys.mass_dot_v; /* zeros whatever its params */
    o.map = sdae_map_rk4;              /* no potential: lambda alone */
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s23, &sys23, &o), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_lambda(s23, 2.0, q, v, lambda23), SDAE_OK);
    force_of(&sys, q, lambda, f24);
    force_of(&sys23, q, lambda23, f23);
    for (size_t i = 0; i < sys.n_q; i++) ck_assert_double_le(fabs(f24[i] - f23[i]), 1e-9 * size);
    sdae_mbs_stepper_free(s23);
  }
  sdae_mbs_stepper_free(s);
}
END_TEST

/* rk4 converges at its order on the redundant rows: P_3 after 2 s at T = 0.02 and 0.01 against
 * rk8 at T = 0.0025, the errors' ratio 2^4 = 16 within 12 to 20 */
START_TEST(bricard_rk4_converges_at_order_four) {
  double ref[3], coarse[3], fine[3], e_coarse = 0.0, e_fine = 0.0, ratio;
  bricard_run(sdae_map_rk8, 0.0025, 2.0, ref);
  bricard_run(sdae_map_rk4, 0.02, 2.0, coarse);
  bricard_run(sdae_map_rk4, 0.01, 2.0, fine);
  for (int j = 0; j < 3; j++)
    e_coarse = fmax(e_coarse, fabs(coarse[j] - ref[j])),
    e_fine = fmax(e_fine, fabs(fine[j] - ref[j]));
  ratio = e_coarse / e_fine;
  ck_assert_double_ge(ratio, 12.0);
  ck_assert_double_le(ratio, 20.0);
}
END_TEST

int main(void) {
  Suite *s = suite_create("iftomm");
  ADD_CASE(s, the_reference_is_the_reduced_pendulum);
  ADD_CASE(s, the_mechanism_is_the_parallelogram);
  ADD_CASE(s, the_sparse_back_end_projects_through_the_crossings);
  ADD_CASE(s, rk8_crosses_the_flat_positions_as_T_shrinks);
  ADD_CASE(s, rk4_converges_at_order_four_through_the_crossings);
  ADD_CASE(s, midpoint_converges_at_order_two_through_the_crossings);
  ADD_CASE(s, dgrad_converges_and_keeps_the_energy_through_the_crossings);
  ADD_CASE(s, a_pushed_nfourbar_crosses_the_flat_positions);
  ADD_CASE(s, an_nfourbar_of_swelling_masses_crosses_the_flat_positions);
  ADD_CASE(s, an_nfourbar_on_a_shaking_ground_crosses_the_flat_positions);
  ADD_CASE(s, a_failing_callback_in_a_projected_step_keeps_the_state);
  ADD_CASE(s, a_projected_step_failed_and_taken_again_keeps_the_motion);
  ADD_CASE(s, a_projected_step_that_cannot_be_accurate_is_refused);
  ADD_CASE(s, a_step_from_the_flat_position_itself_is_projected);
  ADD_CASE(s, a_step_landing_next_to_a_flat_position_keeps_the_energy);
  ADD_CASE(s, an_isosceles_slider_crank_crosses_its_bifurcation_on_its_branch);
  ADD_CASE(s, bricard_keeps_all_its_constraints);
  ADD_CASE(s, bricard_rk4_converges_at_order_four);
  return run_suite(s);
}
