/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Redundant constraints (sdae_mbs.rank < n_c): a pendulum whose rod is written two and three
 * times (n_c >= n_q), and a particle on a circle in space held by three constraints of rank two
 * whose best pair changes along the swing; each against the pendulum's exact motion (Jacobi's
 * elliptic functions), its multipliers against the pseudo-inverse's. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include <gsl/gsl_linalg.h>
#include <stabdae/mbs.h>

#include "core/bytes.h"
#include "mechanisms.h"
#include "testmodels.h"

#define GA 9.81

/* ---- the rod written n times: c_k = a_k (x^2 + y^2 - 1) / 2, q = (x, y) ---- */

typedef struct rods {
  size_t n;
  double a[3];
} rods;

static int unit_mass(double t, const double *q, double *M, void *p) {
  const rods *r = p;
  size_t n = r ? 2 : 3; /* the rods' plane or the circle's space */
  (void)t, (void)q;
  memset(M, 0, n * n * sizeof *M);
  for (size_t i = 0; i < n; i++) M[i * n + i] = 1.0;
  return 0;
}
static int weight(double t, const double *q, const double *v, double *F, void *p) {
  (void)t, (void)q, (void)v;
  F[0] = 0.0, F[1] = -GA;
  if (!p) F[2] = 0.0;
  return 0;
}
static int height(double t, const double *q, double *V, void *p) {
  (void)t, (void)p;
  *V = GA * q[1];
  return 0;
}
static int rods_c(double t, const double *q, double *c, void *p) {
  const rods *r = p;
  (void)t;
  for (size_t k = 0; k < r->n; k++) c[k] = r->a[k] * 0.5 * (q[0] * q[0] + q[1] * q[1] - 1.0);
  return 0;
}
static int rods_G(double t, const double *q, double *G, void *p) {
  const rods *r = p;
  (void)t;
  for (size_t k = 0; k < r->n; k++) G[2 * k] = r->a[k] * q[0], G[2 * k + 1] = r->a[k] * q[1];
  return 0;
}
static sdae_mbs rods_system(rods *r) {
  return (sdae_mbs){.n_q = 2,
                    .n_c = r->n,
                    .rank = 1,
                    .mass = unit_mass,
                    .force = weight,
                    .constraint = rods_c,
                    .jacobian = rods_G,
                    .potential = height,
                    .params = r};
}

/* ---- the circle x^2 + y^2 = 1, z = 0 in space: c_k = cos b_k z + sin b_k s, s = (x^2 + y^2 -
 * 1) / 2, b_0 = 0, b_1 = 1.02 + 1.2 x, b_2 = 1.12 - 1.2 x: on the circle G_k = cos b_k e_z +
 * sin b_k (x, y, 0), three gradients in a normal plane at angles b_k. Along a swing from x =
 * 0.6, the pair {0, 1} has the sine |sin b_1| = 0.30 at x = -0.6 and {0, 2} |sin b_2| = 0.39 at
 * x = 0.6, where the other pair has 0.96 and 0.99: more than SDAE_MBS_CHART_FACTOR, so the rows
 * chosen must change at each end of the swing. ---- */

static void angles(double x, double *b, double *db) {
  b[0] = 0.0, b[1] = 1.02 + 1.2 * x, b[2] = 1.12 - 1.2 * x;
  db[0] = 0.0, db[1] = 1.2, db[2] = -1.2;
}
static int circle_c(double t, const double *q, double *c, void *p) {
  double b[3], db[3], s = 0.5 * (q[0] * q[0] + q[1] * q[1] - 1.0);
  (void)t, (void)p;
  angles(q[0], b, db);
  for (int k = 0; k < 3; k++) c[k] = cos(b[k]) * q[2] + sin(b[k]) * s;
  return 0;
}
static int circle_G(double t, const double *q, double *G, void *p) {
  double b[3], db[3], s = 0.5 * (q[0] * q[0] + q[1] * q[1] - 1.0);
  (void)t, (void)p;
  angles(q[0], b, db);
  for (int k = 0; k < 3; k++) {
    G[3 * k] = (-sin(b[k]) * q[2] + cos(b[k]) * s) * db[k] + sin(b[k]) * q[0];
    G[3 * k + 1] = sin(b[k]) * q[1];
    G[3 * k + 2] = cos(b[k]);
  }
  return 0;
}
static sdae_mbs circle_system(void) {
  return (sdae_mbs){.n_q = 3,
                    .n_c = 3,
                    .rank = 2,
                    .mass = unit_mass,
                    .force = weight,
                    .constraint = circle_c,
                    .jacobian = circle_G,
                    .potential = height};
}

/* the pendulum's state at theta from the downward vertical, at rest (z = 0 in space) */
static void pendulum_at(double theta, size_t n_q, double *q, double *v) {
  memset(q, 0, n_q * sizeof *q), memset(v, 0, n_q * sizeof *v);
  q[0] = sin(theta), q[1] = -cos(theta);
}

/* max |c_k| over every row */
static double residual(const sdae_mbs *sys, const double *q) {
  double c[3], worst = 0.0;
  sys->constraint(0.0, q, c, sys->params);
  for (size_t k = 0; k < sys->n_c; k++) worst = fmax(worst, fabs(c[k]));
  return worst;
}

/* The least-norm multipliers of the rows at (q, v): the rod's tension lambda_p = |v|^2 - ga y
 * (m = L = 1) is the force the rows share, -G^T lambda = -lambda_p (x, y, 0); the least-norm
 * lambda with G^T lambda = lambda_p (x, y, 0) from GSL's SVD G = U S V^T (n_c >= n_q here):
 * lambda = U S^+ V^T f, the singular values below 1e-8 of the largest dropped: the
 * pseudo-inverse, independent of the library's rows */
static void pseudo_inverse_lambda(const sdae_mbs *sys, const double *q, const double *v,
                                  double *lambda) {
  size_t n_q = sys->n_q, n_c = sys->n_c;
  double U[9], V[9], S[3], work[3], f[3] = {0}, u[3];
  double tension = v[0] * v[0] + v[1] * v[1] - GA * q[1];
  sys->jacobian(0.0, q, U, sys->params);
  f[0] = tension * q[0], f[1] = tension * q[1];
  gsl_matrix_view Um = gsl_matrix_view_array(U, n_c, n_q), Vm = gsl_matrix_view_array(V, n_q, n_q);
  gsl_vector_view Sv = gsl_vector_view_array(S, n_q), wv = gsl_vector_view_array(work, n_q);
  ck_assert_int_eq(gsl_linalg_SV_decomp(&Um.matrix, &Vm.matrix, &Sv.vector, &wv.vector), 0);
  for (size_t k = 0; k < n_q; k++) { /* u = S^+ V^T f */
    double acc = 0.0;
    for (size_t i = 0; i < n_q; i++) acc += V[i * n_q + k] * f[i];
    u[k] = S[k] > 1e-8 * S[0] ? acc / S[k] : 0.0;
  }
  for (size_t j = 0; j < n_c; j++) {
    lambda[j] = 0.0;
    for (size_t k = 0; k < n_q; k++) lambda[j] += U[j * n_q + k] * u[k];
  }
}

/* rk4 at T = 1e-3 from rest at theta0 to t: theta against the exact swing at every 0.1 s (to
 * 1e-9: rk4's error at this T, C T^4 with C of order ga^2), every row at rounding, and at the
 * end the multipliers against the pseudo-inverse's (to 1e-9 of the tension) */
static void swing_by(const sdae_mbs *stepped, const sdae_mbs *sys, const sdae_map_type *map,
                     double theta0, double tf, unsigned long *row_switches) {
  mech_pendulum exact = {1.0, 1.0, GA, 0.0};
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[3], v[3], lambda[3], expect[3];
  size_t n = (size_t)llround(tf / 1e-3);
  sdae_options_default(&o);
  o.map = map;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, stepped, &o), SDAE_OK);
  pendulum_at(theta0, sys->n_q, q, v);
  for (size_t i = 0; i < n; i++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)i * 1e-3, 1e-3, q, v), SDAE_OK);
    ck_assert_double_le(residual(sys, q), 1e-14);
    if ((i + 1) % 100 == 0) {
      double theta, omega;
      mech_pendulum_exact(&exact, theta0, (double)(i + 1) * 1e-3, &theta, &omega);
      ck_assert_double_le(fabs(atan2(q[0], -q[1]) - theta), 1e-9);
      if (sys->n_q == 3) ck_assert_double_le(fabs(q[2]), 1e-14);
    }
  }
  {
    double xi[6], c[3], G[9];
    ck_assert_int_eq(sdae_mbs_xi(s, tf, q, v, xi), SDAE_OK); /* every row's (c_k, G_k v) */
    sys->constraint(tf, q, c, sys->params), sys->jacobian(tf, q, G, sys->params);
    for (size_t k = 0; k < sys->n_c; k++) {
      double gv = 0.0;
      for (size_t i = 0; i < sys->n_q; i++) gv += G[k * sys->n_q + i] * v[i];
      ck_assert_double_eq(xi[2 * k], c[k]);
      ck_assert_double_eq_tol(xi[2 * k + 1], gv, 1e-12); /* G differenced: 1e-13 |v| */
    }
  }
  ck_assert_int_eq(sdae_mbs_lambda(s, tf, q, v, lambda), SDAE_OK);
  pseudo_inverse_lambda(sys, q, v, expect);
  for (size_t k = 0; k < sys->n_c; k++) ck_assert_double_eq_tol(lambda[k], expect[k], 1e-9 * GA);
  if (row_switches) *row_switches = sdae_mbs_stepper_stats(s)->row_switches;
  sdae_mbs_stepper_free(s);
}

/* stepped as the test evaluates it */
static void swing(const sdae_mbs *sys, const sdae_map_type *map, double theta0, double tf,
                  unsigned long *row_switches) {
  swing_by(sys, sys, map, theta0, tf, row_switches);
}

/* the rod twice (n_c = n_q) and three times (n_c > n_q): the pendulum's motion, its tension
 * shared as lambda = lambda_p a / |a|^2 (the pseudo-inverse's) */
START_TEST(a_rod_written_twice_is_the_pendulum) {
  rods twice = {2, {1.0, 2.0}}, thrice = {3, {1.0, 2.0, -1.0}};
  sdae_mbs a = rods_system(&twice), b = rods_system(&thrice);
  swing(&a, sdae_map_rk4, 1.0, 2.0, NULL);
  swing(&b, sdae_map_rk4, 1.0, 2.0, NULL);
}
END_TEST

/* the circle's rows: the motion, every row at rounding, the least-norm multipliers, and the
 * rows chosen replaced at each end of the swing (period 2.06 s: four ends in 4 s) */
START_TEST(the_rows_chosen_follow_the_motion) {
  sdae_mbs sys = circle_system();
  unsigned long switches;
  swing(&sys, sdae_map_rk4, asin(0.6), 4.0, &switches);
  ck_assert_uint_ge(switches, 3);
}
END_TEST

/* The hysteresis: {0, 1} gives way to {0, 2} only where sin b_2 exceeds 1.5 sin b_1, at x =
 * -0.25 on the way out, and back where sin b_1 exceeds 1.5 sin b_2, at x = 0.34 (the pairs are
 * equal at x = 0.04, where a rule without hysteresis would switch): every switch at |x| > 0.2 */
START_TEST(the_rows_switch_by_the_hysteresis) {
  sdae_mbs sys = circle_system();
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[3], v[3];
  unsigned long seen = 0;
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  pendulum_at(asin(0.6), 3, q, v);
  for (int i = 0; i < 4000; i++) {
    ck_assert_int_eq(sdae_mbs_step(s, i * 1e-3, 1e-3, q, v), SDAE_OK);
    if (sdae_mbs_stepper_stats(s)->row_switches == seen) continue;
    seen = sdae_mbs_stepper_stats(s)->row_switches;
    ck_assert_double_gt(fabs(q[0]), 0.2);
  }
  ck_assert_uint_ge(seen, 3);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* dgrad keeps the energy on the circle's redundant rows (to 1e-12 relative over 2 s, across
 * the switches of rows) */
START_TEST(dgrad_keeps_the_energy_on_redundant_rows) {
  sdae_mbs sys = circle_system();
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[3], v[3], E0, E;
  sdae_options_default(&o);
  o.map = sdae_map_dgrad;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  pendulum_at(asin(0.6), 3, q, v);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E0), SDAE_OK);
  for (int i = 0; i < 2000; i++) ck_assert_int_eq(sdae_mbs_step(s, i * 1e-3, 1e-3, q, v), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_energy(s, 2.0, q, v, &E), SDAE_OK);
  ck_assert_double_le(fabs(E - E0), 1e-12 * fabs(E0));
  ck_assert_uint_ge(sdae_mbs_stepper_stats(s)->row_switches, 1);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* the rank must be the motion's: below it (the circle given rank 1) the rows left out are not
 * implied, SDAE_ERR_RANK at the first step with the state kept; the rank's bounds (at most n_c,
 * below n_q; n_c >= n_q only with a rank) are SDAE_ERR_DIM */
START_TEST(a_rank_not_the_motions_is_refused) {
  sdae_mbs sys = circle_system(), bad;
  rods twice = {2, {1.0, 2.0}};
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[3], v[3], q0[3];
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  bad = sys, bad.rank = 1;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &bad, &o), SDAE_OK);
  pendulum_at(0.3, 3, q, v);
  memcpy(q0, q, sizeof q);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_ERR_RANK);
  ck_assert_mem_eq(q, q0, sizeof q);
  sdae_mbs_stepper_free(s);
  bad = sys, bad.rank = 4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &bad, &o), SDAE_ERR_DIM);
  bad = sys, bad.rank = 3; /* no degree of freedom left */
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &bad, &o), SDAE_ERR_DIM);
  bad = rods_system(&twice), bad.rank = 0; /* n_c = n_q: only with a rank */
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &bad, &o), SDAE_ERR_DIM);
}
END_TEST

/* where the rows chosen start in the state's bytes: the header (36 bytes), the four counters,
 * the flag that rows were chosen */
#define ROWS_AT (36 + 4 * sizeof(unsigned long) + sizeof(int))

static void reseal(unsigned char *state, size_t len) {
  uint64_t sum = sdae__fnv(SDAE_FNV_START, state, len - sizeof sum);
  memcpy(state + len - sizeof sum, &sum, sizeof sum);
}

/* n steps of s from step `from` */
static void steps(sdae_mbs_stepper *s, int from, int n, double *q, double *v) {
  for (int i = from; i < from + n; i++)
    ck_assert_int_eq(sdae_mbs_step(s, i * 1e-3, 1e-3, q, v), SDAE_OK);
}

/* The rows chosen are in the state's bytes. At t = 0.5 the swing is near x = 0, where the pairs
 * {0, 1} and {0, 2} are within the hysteresis of each other, so whichever is current stays:
 * the state set into another stepper continues bit for bit, the same state with its rows
 * rewritten to the other pair (resealed) continues in those, not bit for bit, rows that are
 * not a choice (unsorted, out of range) are damaged, and a stepper of another rank refuses it.
 * A query between steps leaves the state's bytes as they were. */
START_TEST(the_state_keeps_the_rows_chosen) {
  sdae_mbs sys = circle_system(), other = sys;
  sdae_mbs_stepper *a, *b, *c;
  sdae_options o;
  double qa[3], va[3], qb[3], vb[3], q0[3], v0[3], lambda[3], xi[6];
  unsigned char buf[4096], again[4096];
  size_t len, *rows;
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  other.rank = 1;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&a, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&b, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&c, &other, &o), SDAE_OK);
  pendulum_at(asin(0.6), 3, qa, va);
  steps(a, 0, 500, qa, va);
  len = sdae_mbs_state_size(a);
  ck_assert_uint_le(len, sizeof buf);
  ck_assert_int_eq(sdae_mbs_get_state(a, buf, len), SDAE_OK);
  pendulum_at(-0.7, 3, q0, v0); /* queries where the other pair is best leave the state */
  ck_assert_int_eq(sdae_mbs_lambda(a, 0.0, q0, v0, lambda), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_xi(a, 0.0, q0, v0, xi), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_get_state(a, again, len), SDAE_OK);
  ck_assert_mem_eq(buf, again, len);
  ck_assert_int_ne(sdae_mbs_set_state(c, buf, len), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_set_state(b, buf, len), SDAE_OK);
  memcpy(qb, qa, sizeof qa), memcpy(vb, va, sizeof va), memcpy(q0, qa, sizeof qa),
      memcpy(v0, va, sizeof va);
  steps(a, 500, 100, qa, va);
  steps(b, 500, 100, qb, vb);
  ck_assert_mem_eq(qa, qb, sizeof qa);
  ck_assert_mem_eq(va, vb, sizeof va);
  rows = (size_t *)(void *)(buf + ROWS_AT); /* the other pair with row 0 */
  ck_assert_uint_eq(rows[0], 0);
  rows[1] = 3 - rows[1];
  reseal(buf, len);
  ck_assert_int_eq(sdae_mbs_set_state(b, buf, len), SDAE_OK);
  memcpy(qb, q0, sizeof q0), memcpy(vb, v0, sizeof v0);
  steps(b, 500, 100, qb, vb);
  ck_assert(memcmp(qa, qb, sizeof qa) != 0);
  rows[0] = rows[1], rows[1] = 0; /* unsorted */
  reseal(buf, len);
  ck_assert_int_eq(sdae_mbs_set_state(b, buf, len), SDAE_ERR_STATE_DAMAGED);
  rows[0] = 0, rows[1] = 3; /* no such row */
  reseal(buf, len);
  ck_assert_int_eq(sdae_mbs_set_state(b, buf, len), SDAE_ERR_STATE_DAMAGED);
  sdae_mbs_stepper_free(a), sdae_mbs_stepper_free(b), sdae_mbs_stepper_free(c);
}
END_TEST

/* Without the Jacobian (G by differences of every row, for the choice too) the same motion to
 * the differences' accuracy */
START_TEST(the_rows_are_chosen_by_differences_too) {
  sdae_mbs sys = circle_system(), differenced = sys;
  differenced.jacobian = NULL;
  swing_by(&differenced, &sys, sdae_map_rk4, asin(0.6), 2.0, NULL);
}
END_TEST

/* ---- a moving pivot: the rod from (X(t), 0), X = 0.3 sin 2t, written once and twice ---- */

typedef struct moving {
  size_t n;
  double a[2];
  int fail; /* the callback that fails: 1 c, 2 G, 3 dc/dt, 4 Gdot, 5 d/ds dc/dt (0: none) */
} moving;
static double pivot(double t) { return 0.3 * sin(2.0 * t); }
static int moving_c(double t, const double *q, double *c, void *p) {
  const moving *m = p;
  double dx = q[0] - pivot(t);
  if (m->fail == 1) return 1;
  for (size_t k = 0; k < m->n; k++) c[k] = m->a[k] * 0.5 * (dx * dx + q[1] * q[1] - 1.0);
  return 0;
}
static int moving_G(double t, const double *q, double *G, void *p) {
  const moving *m = p;
  if (m->fail == 2) return 1;
  for (size_t k = 0; k < m->n; k++)
    G[2 * k] = m->a[k] * (q[0] - pivot(t)), G[2 * k + 1] = m->a[k] * q[1];
  return 0;
}
static int moving_ct(double t, const double *q, double *ct, void *p) {
  const moving *m = p;
  if (m->fail == 3) return 1;
  for (size_t k = 0; k < m->n; k++) ct[k] = -m->a[k] * (q[0] - pivot(t)) * 0.6 * cos(2.0 * t);
  return 0;
}

/* the derivatives along (1, v): Gdot = a (v_x - X', v_y), d/ds dc/dt = -a ((v_x - X') X' + (x -
 * X) X''), X' = 0.6 cos 2t, X'' = -1.2 sin 2t */
static int moving_Gdot(double t, const double *q, const double *v, double *Gd, void *p) {
  const moving *m = p;
  (void)q;
  if (m->fail == 4) return 1;
  for (size_t k = 0; k < m->n; k++)
    Gd[2 * k] = m->a[k] * (v[0] - 0.6 * cos(2.0 * t)), Gd[2 * k + 1] = m->a[k] * v[1];
  return 0;
}
static int moving_ct_dot(double t, const double *q, const double *v, double *out, void *p) {
  const moving *m = p;
  double X1 = 0.6 * cos(2.0 * t), X2 = -1.2 * sin(2.0 * t);
  if (m->fail == 5) return 1;
  for (size_t k = 0; k < m->n; k++) out[k] = -m->a[k] * ((v[0] - X1) * X1 + (q[0] - pivot(t)) * X2);
  return 0;
}
static int zero_mdv(double t, const double *q, const double *v, double *out, void *p) {
  (void)t, (void)q, (void)v, (void)p;
  out[0] = out[1] = 0.0;
  return 0;
}

/* the rod written twice on the moving pivot, rank 1, every derivative given */
static sdae_mbs moving_twice(moving *m) {
  return (sdae_mbs){.n_q = 2,
                    .n_c = 2,
                    .rank = 1,
                    .mass = unit_mass,
                    .force = weight,
                    .constraint = moving_c,
                    .jacobian = moving_G,
                    .constraint_t = moving_ct,
                    .params = m,
                    .mass_dot_v = zero_mdv,
                    .jacobian_dot = moving_Gdot,
                    .constraint_t_dot = moving_ct_dot};
}

/* Constraints that move with t: the rod written twice (rank 1) steps as the rod written once,
 * the same manifold at every t, to rk4's error (both within 1e-10 of each other at T = 1e-3
 * over 2 s; with G and dc/dt differenced, 1e-8), every row of xi its (c, G v + dc/dt) at the
 * end, and the multipliers shared as the pseudo-inverse shares the single rod's: lambda (1, 2)
 * / 5 */
START_TEST(moving_constraints_are_redundant_too) {
  moving once = {1, {1.0, 0.0}, 0}, twice = {2, {1.0, 2.0}, 0};
  sdae_mbs a = {.n_q = 2,
                .n_c = 1,
                .mass = unit_mass,
                .force = weight,
                .constraint = moving_c,
                .jacobian = moving_G,
                .constraint_t = moving_ct,
                .params = &once};
  sdae_mbs b = a;
  sdae_mbs_stepper *sa, *sb;
  sdae_options o;
  double qa[2] = {0.0, -1.0}, va[2] = {0.0, 0.0}, qb[2], vb[2], la[1], lb[2], xi[4], c[2], G[4],
         ct[2];
  b.n_c = 2, b.rank = 1, b.params = &twice;
  a.params = &once;
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&sa, &a, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&sb, &b, &o), SDAE_OK);
  memcpy(qb, qa, sizeof qa), memcpy(vb, va, sizeof va);
  for (int i = 0; i < 2000; i++) {
    ck_assert_int_eq(sdae_mbs_step(sa, i * 1e-3, 1e-3, qa, va), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_step(sb, i * 1e-3, 1e-3, qb, vb), SDAE_OK);
  }
  for (int i = 0; i < 2; i++) {
    ck_assert_double_le(fabs(qa[i] - qb[i]), 1e-10);
    ck_assert_double_le(fabs(va[i] - vb[i]), 1e-9);
  }
  ck_assert_int_eq(sdae_mbs_xi(sb, 2.0, qb, vb, xi), SDAE_OK);
  moving_c(2.0, qb, c, &twice), moving_G(2.0, qb, G, &twice), moving_ct(2.0, qb, ct, &twice);
  for (int k = 0; k < 2; k++) {
    ck_assert_double_eq(xi[2 * k], c[k]);
    ck_assert_double_eq_tol(xi[2 * k + 1], G[2 * k] * vb[0] + G[2 * k + 1] * vb[1] + ct[k], 1e-15);
  }
  { /* the rod after a row that vanishes (chosen: row 1, gathered from every derivative given):
       the same motion, the multipliers (0, lambda) */
    moving after_zero = {2, {0.0, 1.0}, 0};
    sdae_mbs z = moving_twice(&after_zero);
    sdae_mbs_stepper *sz;
    double qz[2] = {0.0, -1.0}, vz[2] = {0.0, 0.0}, lz[2];
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&sz, &z, &o), SDAE_OK);
    for (int i = 0; i < 2000; i++)
      ck_assert_int_eq(sdae_mbs_step(sz, i * 1e-3, 1e-3, qz, vz), SDAE_OK);
    ck_assert_double_le(fabs(qz[0] - qa[0]) + fabs(qz[1] - qa[1]), 1e-10);
    ck_assert_int_eq(sdae_mbs_lambda(sa, 2.0, qz, vz, la), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_lambda(sz, 2.0, qz, vz, lz), SDAE_OK);
    ck_assert_double_eq(lz[0], 0.0);
    ck_assert_double_eq_tol(lz[1], la[0], 1e-8 * fabs(la[0]));
    sdae_mbs_stepper_free(sz);
  }
  { /* and with the derivatives along the motion given, to rk4's error */
    sdae_mbs e = moving_twice(&twice);
    sdae_mbs_stepper *se;
    double qe[2] = {0.0, -1.0}, ve[2] = {0.0, 0.0};
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&se, &e, &o), SDAE_OK);
    for (int i = 0; i < 2000; i++)
      ck_assert_int_eq(sdae_mbs_step(se, i * 1e-3, 1e-3, qe, ve), SDAE_OK);
    ck_assert_double_le(fabs(qe[0] - qa[0]) + fabs(qe[1] - qa[1]), 1e-10);
    ck_assert_int_eq(sdae_mbs_lambda(sa, 2.0, qe, ve, la), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_lambda(se, 2.0, qe, ve, lb), SDAE_OK); /* gamma from d/ds dc/dt */
    ck_assert_double_eq_tol(lb[0], la[0] / 5.0, 1e-8 * fabs(la[0]));
    ck_assert_double_eq_tol(lb[1], 2.0 * la[0] / 5.0, 1e-8 * fabs(la[0]));
    sdae_mbs_stepper_free(se);
  }
  { /* and with G and dc/dt of every row left to differences, to their accuracy */
    sdae_mbs d = b;
    sdae_mbs_stepper *sd;
    double qd[2] = {0.0, -1.0}, vd[2] = {0.0, 0.0}, xd[4];
    d.jacobian = NULL, d.constraint_t = NULL;
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&sd, &d, &o), SDAE_OK);
    for (int i = 0; i < 2000; i++)
      ck_assert_int_eq(sdae_mbs_step(sd, i * 1e-3, 1e-3, qd, vd), SDAE_OK);
    ck_assert_double_le(fabs(qd[0] - qa[0]) + fabs(qd[1] - qa[1]), 1e-8);
    ck_assert_int_eq(sdae_mbs_xi(sd, 2.0, qb, vb, xd), SDAE_OK);
    for (int k = 0; k < 4; k++) ck_assert_double_eq_tol(xd[k], xi[k], 1e-10);
    sdae_mbs_stepper_free(sd);
  }
  ck_assert_int_eq(sdae_mbs_lambda(sa, 2.0, qb, vb, la), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_lambda(sb, 2.0, qb, vb, lb), SDAE_OK);
  ck_assert_double_eq_tol(lb[0], la[0] / 5.0, 1e-10 * fabs(la[0]));
  ck_assert_double_eq_tol(lb[1], 2.0 * la[0] / 5.0, 1e-10 * fabs(la[0]));
  sdae_mbs_stepper_free(sa), sdae_mbs_stepper_free(sb);
}
END_TEST

/* A callback of redundant rows failing is the step's, xi's and lambda's status, the state kept */
START_TEST(a_failing_callback_of_redundant_rows_is_reported) {
  for (int fail = 1; fail <= 5; fail++) {
    moving m = {2, {1.0, 2.0}, 0};
    sdae_mbs sys = moving_twice(&m);
    sdae_mbs_stepper *s;
    sdae_options o;
    double q[2] = {0.1, -0.9}, v[2] = {0.3, 0.0}, q0[2], v0[2], xi[4] = {7, 7, 7, 7},
           lambda[2] = {7, 7};
    sdae_options_default(&o);
    o.map = sdae_map_rk4;
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
    memcpy(q0, q, sizeof q), memcpy(v0, v, sizeof v);
    m.fail = fail;
    if (fail <= 4) { /* a step reads c, G, dc/dt and Gdot (d/ds dc/dt: lambda's gamma alone) */
      ck_assert_int_eq(sdae_mbs_step(s, 1e-3, 1e-3, q, v), SDAE_ERR_CALLBACK_RECOVERABLE);
      ck_assert_mem_eq(q, q0, sizeof q);
      ck_assert_mem_eq(v, v0, sizeof v);
    }
    if (fail == 2 || fail >= 4) { /* lambda reads G, Gdot and d/ds dc/dt */
      ck_assert_int_eq(sdae_mbs_lambda(s, 1e-3, q, v, lambda), SDAE_ERR_CALLBACK_RECOVERABLE);
      ck_assert_double_eq(lambda[0], 7.0);
    }
    if (fail <= 3) { /* xi reads c, G and dc/dt */
      ck_assert_int_eq(sdae_mbs_xi(s, 1e-3, q, v, xi), SDAE_ERR_CALLBACK_RECOVERABLE);
      ck_assert_double_eq(xi[0], 7.0);
    }
    sdae_mbs_stepper_free(s);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs_redundant");
  ADD_CASE(s, a_rod_written_twice_is_the_pendulum);
  ADD_CASE(s, the_rows_chosen_follow_the_motion);
  ADD_CASE(s, the_rows_switch_by_the_hysteresis);
  ADD_CASE(s, dgrad_keeps_the_energy_on_redundant_rows);
  ADD_CASE(s, a_rank_not_the_motions_is_refused);
  ADD_CASE(s, the_state_keeps_the_rows_chosen);
  ADD_CASE(s, the_rows_are_chosen_by_differences_too);
  ADD_CASE(s, moving_constraints_are_redundant_too);
  ADD_CASE(s, a_failing_callback_of_redundant_rows_is_reported);
  return run_suite(s);
}
