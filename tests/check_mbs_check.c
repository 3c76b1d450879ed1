/* SPDX-License-Identifier: GPL-3.0-or-later */
/* sdae_mbs_check on a bead of position-dependent mass m (1 + x^2) on a line through the origin
 * turning at rate w, c = x sin(w t) - y cos(w t), with gravity as a potential: every derivative
 * in closed form, then each one given with a wrong sign, which the check must name. */
#include <float.h>
#include <math.h>

#include <stabdae/mbs.h>

#include "nfourbar.h"
#include "testmodels.h"

typedef struct bead {
  double m, w, g;
  int wrong;     /* -1: none, else the sdae_mbs_derivative given with a wrong sign */
  double V0, k3; /* V = V0 + m g y + k3 ((x - 0.6)^3 + (y - 0.8)^3) / 3 */
} bead;

static double sign(const bead *b, sdae_mbs_derivative d) { return b->wrong == (int)d ? -1 : 1; }

static int mass(double t, const double *q, double *M, void *params) {
  const bead *b = params;
  double mu = b->m * (1 + q[0] * q[0]);
  (void)t;
  M[0] = M[3] = mu, M[1] = M[2] = 0;
  return 0;
}

/* -dV/dq + (1/2) v^T dM/dq v - Mdot v with V = m g y, dM/dx = 2 m x I, Mdot = 2 m x vx I */
static int force(double t, const double *q, const double *v, double *F, void *params) {
  const bead *b = params;
  double s = sign(b, SDAE_MBS_FORCE), x = q[0], vv = v[0] * v[0] + v[1] * v[1];
  (void)t;
  double dx = x - 0.6, dy = q[1] - 0.8;
  F[0] = s * (b->m * x * vv - 2 * b->m * x * v[0] * v[0] - b->k3 * dx * dx);
  F[1] = -b->m * b->g - 2 * b->m * x * v[0] * v[1] - b->k3 * dy * dy;
  return 0;
}

static int potential(double t, const double *q, double *V, void *params) {
  const bead *b = params;
  (void)t;
  double dx = q[0] - 0.6, dy = q[1] - 0.8;
  *V = b->V0 + b->m * b->g * q[1] + b->k3 * (dx * dx * dx + dy * dy * dy) / 3;
  return 0;
}

static int constraint(double t, const double *q, double *c, void *params) {
  const bead *b = params;
  c[0] = q[0] * sin(b->w * t) - q[1] * cos(b->w * t);
  return 0;
}

static int jacobian(double t, const double *q, double *G, void *params) {
  const bead *b = params;
  (void)q;
  G[0] = sign(b, SDAE_MBS_JACOBIAN) * sin(b->w * t), G[1] = -cos(b->w * t);
  return 0;
}

static int constraint_t(double t, const double *q, double *ct, void *params) {
  const bead *b = params;
  double s = sign(b, SDAE_MBS_CONSTRAINT_T);
  ct[0] = s * b->w * (q[0] * cos(b->w * t) + q[1] * sin(b->w * t));
  return 0;
}

static int mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  const bead *b = params;
  double k = sign(b, SDAE_MBS_MASS_DOT_V) * 2 * b->m * q[0] * v[0];
  (void)t;
  out[0] = k * v[0], out[1] = k * v[1];
  return 0;
}

static int jacobian_dot(double t, const double *q, const double *v, double *Gdot, void *params) {
  const bead *b = params;
  (void)q, (void)v;
  Gdot[0] = b->w * cos(b->w * t);
  Gdot[1] = sign(b, SDAE_MBS_JACOBIAN_DOT) * b->w * sin(b->w * t);
  return 0;
}

static int constraint_t_dot(double t, const double *q, const double *v, double *out, void *params) {
  const bead *b = params;
  double c = cos(b->w * t), s = sin(b->w * t);
  out[0] = b->w * (v[0] * c + v[1] * s) +
           sign(b, SDAE_MBS_CONSTRAINT_T_DOT) * b->w * b->w * (q[1] * c - q[0] * s);
  return 0;
}

static sdae_mbs system_of(bead *b) {
  return (sdae_mbs){.n_q = 2,
                    .n_c = 1,
                    .mass = mass,
                    .force = force,
                    .constraint = constraint,
                    .jacobian = jacobian,
                    .constraint_t = constraint_t,
                    .potential = potential,
                    .mass_dot_v = mass_dot_v,
                    .jacobian_dot = jacobian_dot,
                    .constraint_t_dot = constraint_t_dot,
                    .params = b};
}

static const double t0 = 0.7, q0[2] = {0.8, -0.35}, v0[2] = {-1.3, 0.9};

/* Right derivatives: every one compared, each within the differences' accuracy (about 1e-9
 * relative for these smooth functions), consistent at 1e-6. */
START_TEST(right_derivatives_are_consistent) {
  bead b = {2.0, 3.0, 9.81, -1, 0.0, 0.0};
  sdae_mbs sys = system_of(&b);
  sdae_mbs_check_report r;
  ck_assert_int_eq(sdae_mbs_check(&sys, t0, q0, v0, 1e-6, &r), SDAE_OK);
  ck_assert_uint_eq(r.checked, (1u << SDAE_MBS_DERIVATIVES) - 1);
  for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++) ck_assert_double_lt(r.mismatch[d], 1e-8);
  ck_assert_int_eq(r.consistent, 1);
}
END_TEST

/* One sign wrong: its mismatch is of order 1 (the entry changes by twice itself, relative to
 * the largest entry), the check is inconsistent and names it, and only it. */
START_TEST(a_wrong_sign_is_named) {
  for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++) {
    bead b = {2.0, 3.0, 9.81, d, 0.0, 0.0};
    sdae_mbs sys = system_of(&b);
    sdae_mbs_check_report r;
    ck_assert_int_eq(sdae_mbs_check(&sys, t0, q0, v0, 1e-6, &r), SDAE_OK);
    ck_assert_int_eq(r.consistent, 0);
    ck_assert_int_eq(r.worst, d);
    ck_assert_double_gt(r.mismatch[d], 0.1);
    for (int e = 0; e < SDAE_MBS_DERIVATIVES; e++) /* Gdot and ct_dot are checked against G
                                                    * and ct as given */
      if (e != d && !(d == SDAE_MBS_JACOBIAN && e == SDAE_MBS_JACOBIAN_DOT) &&
          !(d == SDAE_MBS_CONSTRAINT_T && e == SDAE_MBS_CONSTRAINT_T_DOT))
        ck_assert_double_lt(r.mismatch[e], 1e-8);
  }
}
END_TEST

/* The entry: jacobian_dot's second entry (row-major index 1) holds the wrong sign. */
START_TEST(the_wrong_entry_is_named) {
  bead b = {2.0, 3.0, 9.81, SDAE_MBS_JACOBIAN_DOT, 0.0, 0.0};
  sdae_mbs sys = system_of(&b);
  sdae_mbs_check_report r;
  ck_assert_int_eq(sdae_mbs_check(&sys, t0, q0, v0, 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.worst, SDAE_MBS_JACOBIAN_DOT);
  ck_assert_uint_eq(r.worst_index, 1);
}
END_TEST

/* Without the optional callbacks only what is given is compared. */
START_TEST(only_given_derivatives_are_compared) {
  bead b = {2.0, 3.0, 9.81, -1, 0.0, 0.0};
  sdae_mbs sys = system_of(&b);
  sdae_mbs_check_report r;
  sys.potential = NULL, sys.mass_dot_v = NULL, sys.constraint_t_dot = NULL;
  ck_assert_int_eq(sdae_mbs_check(&sys, t0, q0, v0, 1e-6, &r), SDAE_OK);
  ck_assert_uint_eq(r.checked, (1u << SDAE_MBS_JACOBIAN) | (1u << SDAE_MBS_CONSTRAINT_T) |
                                   (1u << SDAE_MBS_JACOBIAN_DOT));
  ck_assert_double_eq(r.mismatch[SDAE_MBS_FORCE], 0.0);
  ck_assert_int_eq(r.consistent, 1);
}
END_TEST

static int failing(double t, const double *q, const double *v, double *out, void *params) {
  (void)t, (void)q, (void)v, (void)out, (void)params;
  return -1;
}

static int failing_force(double t, const double *q, const double *v, double *F, void *params) {
  (void)t, (void)q, (void)v, (void)F, (void)params;
  return 1;
}

static int nan_out(double t, const double *q, const double *v, double *out, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  out[0] = out[1] = NAN;
  return 0;
}

/* Bad input: a named status, the report untouched. */
START_TEST(bad_input_is_a_status) {
  bead b = {2.0, 3.0, 9.81, -1, 0.0, 0.0};
  sdae_mbs sys = system_of(&b), bad;
  sdae_mbs_check_report r = {.worst = 77};
  const double qn[2] = {NAN, 0.0};
  ck_assert_int_eq(sdae_mbs_check(NULL, t0, q0, v0, 1e-6, &r), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_check(&sys, t0, q0, v0, 1e-6, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_check(&sys, t0, q0, v0, 0.0, &r), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_mbs_check(&sys, t0, qn, v0, 1e-6, &r), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_mbs_check(&sys, INFINITY, q0, v0, 1e-6, &r), SDAE_ERR_PARAM);
  bad = sys, bad.jacobian = NULL; /* jacobian_dot is checked against jacobian */
  ck_assert_int_eq(sdae_mbs_check(&bad, t0, q0, v0, 1e-6, &r), SDAE_ERR_NULL);
  bad = sys, bad.n_c = 0;
  ck_assert_int_eq(sdae_mbs_check(&bad, t0, q0, v0, 1e-6, &r), SDAE_ERR_DIM);
  bad = sys, bad.mass_dot_v = failing;
  ck_assert_int_eq(sdae_mbs_check(&bad, t0, q0, v0, 1e-6, &r), SDAE_ERR_CALLBACK_FATAL);
  bad = sys, bad.force = failing_force; /* checked against Lagrange's equations */
  ck_assert_int_eq(sdae_mbs_check(&bad, t0, q0, v0, 1e-6, &r), SDAE_ERR_CALLBACK_RECOVERABLE);
  bad = sys, bad.mass_dot_v = nan_out;
  ck_assert_int_eq(sdae_mbs_check(&bad, t0, q0, v0, 1e-6, &r), SDAE_ERR_NONFINITE);
  ck_assert_int_eq(r.worst, 77);
}
END_TEST

/* Late times: the step in t does not grow with t (the line turns as fast at t = 1e6 as at 0),
 * so the check keeps its sharpness there but for the rounding of the phase w t itself, eps t
 * per value, which the difference of step h = 7.4e-4 turns into eps t / h relative. */
START_TEST(late_times_are_checked_as_sharply) {
  const double ts[2] = {1e3, 1e6};
  for (int i = 0; i < 2; i++) {
    bead b = {2.0, 3.0, 9.81, -1, 0.0, 0.0};
    sdae_mbs sys = system_of(&b);
    sdae_mbs_check_report r;
    ck_assert_int_eq(sdae_mbs_check(&sys, ts[i], q0, v0, 1e-6, &r), SDAE_OK);
    for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++)
      ck_assert_double_lt(r.mismatch[d], 1e-8 + 4.0 * DBL_EPSILON * ts[i] / 7.4e-4);
    ck_assert_int_eq(r.consistent, 1);
    ck_assert_int_eq(r.state, r.worst < 0 ? -1 : 0); /* no pattern: the state given alone */
  }
}
END_TEST

/* At an equilibrium (v = 0, g = 0, the cubic's gradient zero at (0.6, 0.8)) the force is 0 and
 * its differences are rounding of V0 = 1e4: no mismatch. */
START_TEST(equilibrium_force_is_consistent) {
  bead b = {2.0, 3.0, 0.0, -1, 1e4, 5.0};
  sdae_mbs sys = system_of(&b);
  sdae_mbs_check_report r;
  const double qe[2] = {0.6, 0.8}, ve[2] = {0.0, 0.0};
  ck_assert_int_eq(sdae_mbs_check(&sys, t0, qe, ve, 1e-6, &r), SDAE_OK);
  ck_assert_double_eq(r.mismatch[SDAE_MBS_FORCE], 0.0);
  ck_assert_int_eq(r.consistent, 1);
}
END_TEST

/* c = (1e7 (x - y), (|q|^2 - 1) / 2): a wrong sign in the small second row of G is found, its
 * entries far below the first row's. */
static int flip_small_row;
static int scaled_mass(double t, const double *q, double *M, void *params) {
  (void)t, (void)q, (void)params;
  for (int i = 0; i < 9; i++) M[i] = i % 4 == 0;
  return 0;
}
static int scaled_force(double t, const double *q, const double *v, double *F, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  F[0] = F[1] = F[2] = 0.0;
  return 0;
}
static int scaled_constraint(double t, const double *q, double *c, void *params) {
  (void)t, (void)params;
  c[0] = 1e7 * (q[0] - q[1]);
  c[1] = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - 1) / 2;
  return 0;
}
static int scaled_jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  G[0] = 1e7, G[1] = -1e7, G[2] = 0.0;
  G[3] = q[0], G[4] = q[1], G[5] = flip_small_row ? -q[2] : q[2];
  return 0;
}

START_TEST(a_small_row_is_not_hidden) {
  sdae_mbs sys = {.n_q = 3,
                  .n_c = 2,
                  .mass = scaled_mass,
                  .force = scaled_force,
                  .constraint = scaled_constraint,
                  .jacobian = scaled_jacobian};
  const double q[3] = {0.5, 0.5, 0.7}, v[3] = {0.1, 0.1, -0.2};
  sdae_mbs_check_report r;
  flip_small_row = 0;
  ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 1);
  flip_small_row = 1;
  ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_int_eq(r.worst, SDAE_MBS_JACOBIAN);
  ck_assert_uint_eq(r.worst_index, 5);
}
END_TEST

/* Nothing to compare: worst is -1. */
START_TEST(nothing_given_nothing_compared) {
  sdae_mbs sys = {.n_q = 3,
                  .n_c = 2,
                  .mass = scaled_mass,
                  .force = scaled_force,
                  .constraint = scaled_constraint};
  const double q[3] = {0.5, 0.5, 0.7}, v[3] = {0.1, 0.1, -0.2};
  sdae_mbs_check_report r;
  ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
  ck_assert_uint_eq(r.checked, 0);
  ck_assert_int_eq(r.worst, -1);
  ck_assert_int_eq(r.consistent, 1);
}
END_TEST

/* A pendulum hanging from the origin, q = (x, y), c = (x^2 + y^2 - 1) / 2, its Jacobian given
 * by a pattern: the whole row, or y's entry alone. Hanging straight down G = (0, -1): the
 * pattern without x's entry writes the same G there, and only a state moved off the vertical
 * shows what it leaves out (an SDAE_MBS_JACOBIAN mismatch of 1 at entry 0: the given 0 against
 * x); the whole row is consistent at every state. */
static int unit_mass(double t, const double *q, double *M, void *p) {
  (void)t, (void)q, (void)p;
  M[0] = M[1] = 1.0; /* the diagonal pattern's two entries */
  return 0;
}
static int gravity(double t, const double *q, const double *v, double *F, void *p) {
  (void)t, (void)q, (void)v, (void)p;
  F[0] = 0.0, F[1] = -9.81;
  return 0;
}
static int circle(double t, const double *q, double *c, void *p) {
  (void)t, (void)p;
  c[0] = 0.5 * (q[0] * q[0] + q[1] * q[1] - 1.0);
  return 0;
}
static int row_by_pattern(double t, const double *q, double *G, void *p) {
  const sdae_pattern *jp = p; /* params: the Jacobian's pattern */
  (void)t;
  for (size_t e = 0; e < jp->nnz; e++) G[e] = q[jp->col[e]];
  return 0;
}

START_TEST(a_pattern_wrong_off_the_state_alone_is_found) {
  static const size_t diag_start[] = {0, 1, 2}, diag_col[] = {0, 1};
  static const size_t row_start[] = {0, 2}, row_col[] = {0, 1}, y_start[] = {0, 1}, y_col[] = {1};
  const sdae_pattern M = {2, diag_start, diag_col};
  const sdae_pattern whole = {2, row_start, row_col}, y_only = {1, y_start, y_col};
  const double q[2] = {0.0, -1.0}, v[2] = {0.5, 0.0};
  for (int wrong = 0; wrong < 2; wrong++) {
    const sdae_pattern *jp = wrong ? &y_only : &whole;
    sdae_mbs sys = {.n_q = 2,
                    .n_c = 1,
                    .mass = unit_mass,
                    .force = gravity,
                    .constraint = circle,
                    .jacobian = row_by_pattern,
                    .mass_pattern = &M,
                    .jacobian_pattern = jp,
                    .params = (void *)jp};
    sdae_mbs_check_report r;
    ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
    ck_assert_int_eq(r.consistent, !wrong);
    if (!wrong) continue;
    ck_assert_int_eq(r.worst, SDAE_MBS_JACOBIAN);
    ck_assert_uint_eq(r.worst_index, 0);
    ck_assert_int_gt(r.state, 0);
    ck_assert_double_ge(r.mismatch[SDAE_MBS_JACOBIAN], 0.99);
  }
}
END_TEST

/* ---- redundant constraints ---- */

/* A particle in the plane on rows that are unit gradients at the angles a_j: c_j = cos a_j x +
 * sin a_j y, so G's rows are (cos a_j, sin a_j), at angles known exactly. */
typedef struct lines {
  size_t n;
  double a[4];
  double w;    /* row 1 turns: its angle a[1] + w t */
  int fail_at; /* 1: c fails away from q = (0.3, -0.2), 2: everywhere (0: never) */
} lines;
static int lines_mass(double t, const double *q, double *M, void *p) {
  (void)t, (void)q, (void)p;
  M[0] = M[3] = 1.0, M[1] = M[2] = 0.0;
  return 0;
}
static int lines_force(double t, const double *q, const double *v, double *F, void *p) {
  (void)t, (void)q, (void)v, (void)p;
  F[0] = 0.0, F[1] = -9.81;
  return 0;
}
static int lines_constraint(double t, const double *q, double *c, void *params) {
  const lines *l = params;
  if (l->fail_at == 2 || (l->fail_at == 1 && (q[0] != 0.3 || q[1] != -0.2))) return 1;
  for (size_t j = 0; j < l->n; j++) {
    double a = l->a[j] + (j == 1 ? l->w * t : 0.0);
    c[j] = cos(a) * q[0] + sin(a) * q[1];
  }
  return 0;
}
static int lines_jacobian(double t, const double *q, double *G, void *params) {
  const lines *l = params;
  (void)q;
  for (size_t j = 0; j < l->n; j++) {
    double a = l->a[j] + (j == 1 ? l->w * t : 0.0);
    G[2 * j] = cos(a), G[2 * j + 1] = sin(a);
  }
  return 0;
}
static sdae_mbs lines_system(lines *l) {
  return (sdae_mbs){.n_q = 2,
                    .n_c = l->n,
                    .mass = lines_mass,
                    .force = lines_force,
                    .constraint = lines_constraint,
                    .params = l};
}

/* Two rows at the angle d: QR's second diagonal entry is sin d (the first row's unit length
 * times the sine), so the independence is sin d, the rank 2 down to SDAE_MBS_CHART_MIN and 1
 * below it; a row repeated, or a third row in a plane of two (n_c >= n_q), is redundant on the
 * others: rank 1 and 2, the redundant row the one left last in the order. */
START_TEST(the_rank_counts_the_independent_rows) {
  const double q[2] = {0.3, -0.2}, v[2] = {0.0, 0.0};
  const double d[] = {0.5, 1e-4, 2.0 * SDAE_MBS_CHART_MIN, 0.5 * SDAE_MBS_CHART_MIN};
  for (size_t i = 0; i < sizeof d / sizeof *d; i++) {
    lines l = {2, {0.3, 0.3 + d[i]}, 0.0, 0};
    sdae_mbs sys = lines_system(&l);
    size_t rank = 9, rows[2];
    double independence = -1.0;
    ck_assert_int_eq(sdae_mbs_redundant(&sys, 0.0, q, &rank, rows, &independence), SDAE_OK);
    ck_assert_uint_eq(rank, d[i] >= SDAE_MBS_CHART_MIN ? 2 : 1);
    ck_assert_uint_eq(rows[0] + rows[1], 1); /* a permutation of {0, 1} */
    ck_assert_uint_ne(rows[0], rows[1]);
    if (rank == 2) ck_assert_double_eq_tol(independence, sin(d[i]), 1e-6 * sin(d[i]));
  }
  {
    lines l = {3, {0.3, 0.3, 1.2}, 0.0, 0}; /* the first repeated: 3 rows on 2 coordinates */
    sdae_mbs sys = lines_system(&l);
    sdae_mbs_check_report r;
    size_t rank, rows[3];
    ck_assert_int_eq(sdae_mbs_redundant(&sys, 0.0, q, &rank, rows, NULL), SDAE_OK);
    ck_assert_uint_eq(rank, 2);
    ck_assert_uint_ne(rows[2], 2); /* a copy of row 0 or 1 left last, row 2 chosen */
    ck_assert(rows[0] == 2 || rows[1] == 2);
    ck_assert(rows[0] != rows[1] && rows[0] < 3 && rows[1] < 3);
    ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
    ck_assert_uint_eq(r.rank[0], 2);
    ck_assert_double_eq_tol(r.independence, sin(0.9), 1e-12);
  }
  { /* row 1 turning at w = 3: at t = 0.7 the rows are 2.1 rad apart, their sine 0.863 */
    lines l = {2, {0.3, 0.3}, 3.0, 0};
    for (int given = 0; given < 2; given++) { /* G differenced, and given */
      sdae_mbs sys = lines_system(&l);
      sdae_mbs_check_report r;
      size_t rank;
      double independence;
      if (given) sys.jacobian = lines_jacobian;
      ck_assert_int_eq(sdae_mbs_redundant(&sys, 0.7, q, &rank, NULL, &independence), SDAE_OK);
      ck_assert_double_eq_tol(independence, sin(2.1), 1e-9);
      ck_assert_int_eq(sdae_mbs_check(&sys, 0.7, q, v, 1e-6, &r), SDAE_OK);
      ck_assert_double_eq_tol(r.independence, sin(2.1), 1e-9);
    }
  }
}
END_TEST

/* The N-four-bar: upright, every gradient independent (the rockers' along y, the couplers'
 * along x at two points: rank 2N + 1); flat, every gradient along x, in the span of the N + 1
 * points' x (rank N + 1, N redundant); within 1e-3 rad of flat independent again, but nearly
 * so: the least sine between 1e-8 and 1e-2. The check reports the rank at its states. */
START_TEST(the_nfourbar_loses_rank_where_it_is_flat) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  sdae_mbs sys;
  size_t n_q = 2 * (p.N + 1), rank;
  double q[82], v[82], independence;
  const double angle[3] = {2.0 * atan(1.0), 0.0, 1e-3}; /* pi / 2 */
  const size_t expect[3] = {2 * p.N + 1, p.N + 1, 2 * p.N + 1};
  mech_nfourbar_system(&sys, &p);
  ck_assert_uint_eq(sys.n_q, n_q);
  for (int k = 0; k < 3; k++) {
    for (size_t i = 0; i <= p.N; i++)
      q[2 * i] = (double)i + cos(angle[k]), q[2 * i + 1] = sin(angle[k]),
            v[2 * i] = v[2 * i + 1] = 0;
    ck_assert_int_eq(sdae_mbs_redundant(&sys, 0.0, q, &rank, NULL, &independence), SDAE_OK);
    ck_assert_uint_eq(rank, expect[k]);
    if (k == 2) ck_assert(independence > 1e-8 && independence < 1e-2);
    if (k == 0) {
      sdae_mbs_check_report r;
      ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
      ck_assert(r.consistent);
      ck_assert_uint_eq(r.rank[0], expect[0]);
      ck_assert_uint_eq(r.rank[1], 0); /* no patterns: the state given alone */
    }
  }
}
END_TEST

START_TEST(the_rank_refuses_bad_input) {
  lines l = {2, {0.3, 1.0}, 0.0, 0};
  sdae_mbs sys = lines_system(&l), bad = sys;
  const double q[2] = {0.3, -0.2}, qn[2] = {NAN, 0.0};
  size_t rank = 7, rows[2] = {5, 5};
  double independence = 3.0;
  ck_assert_int_eq(sdae_mbs_redundant(NULL, 0.0, q, &rank, rows, &independence), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_redundant(&sys, 0.0, NULL, &rank, rows, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_redundant(&sys, 0.0, q, NULL, rows, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_redundant(&sys, 0.0, qn, &rank, rows, NULL), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_mbs_redundant(&sys, NAN, q, &rank, rows, NULL), SDAE_ERR_PARAM);
  bad.n_c = 0;
  ck_assert_int_eq(sdae_mbs_redundant(&bad, 0.0, q, &rank, rows, NULL), SDAE_ERR_DIM);
  bad = sys, bad.constraint = NULL;
  ck_assert_int_eq(sdae_mbs_redundant(&bad, 0.0, q, &rank, rows, NULL), SDAE_ERR_NULL);
  { /* c failing where the differences move q, or everywhere: its status, nothing written */
    lines f = l;
    sdae_mbs failing_c = lines_system(&f);
    sdae_mbs_check_report r = {.worst = 77};
    const double v[2] = {0.0, 0.0};
    f.fail_at = 1;
    ck_assert_int_eq(sdae_mbs_redundant(&failing_c, 0.0, q, &rank, rows, &independence),
                     SDAE_ERR_CALLBACK_RECOVERABLE);
    ck_assert_int_eq(sdae_mbs_check(&failing_c, 0.0, q, v, 1e-6, &r),
                     SDAE_ERR_CALLBACK_RECOVERABLE);
    failing_c.jacobian = lines_jacobian; /* G given, compared with c's failing differences */
    ck_assert_int_eq(sdae_mbs_check(&failing_c, 0.0, q, v, 1e-6, &r),
                     SDAE_ERR_CALLBACK_RECOVERABLE);
    ck_assert_int_eq(r.worst, 77);
  }
  ck_assert_uint_eq(rank, 7);
  ck_assert_uint_eq(rows[0], 5);
  ck_assert_double_eq(independence, 3.0);
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs_check");
  ADD_CASE(s, right_derivatives_are_consistent);
  ADD_CASE(s, a_wrong_sign_is_named);
  ADD_CASE(s, the_wrong_entry_is_named);
  ADD_CASE(s, only_given_derivatives_are_compared);
  ADD_CASE(s, bad_input_is_a_status);
  ADD_CASE(s, late_times_are_checked_as_sharply);
  ADD_CASE(s, equilibrium_force_is_consistent);
  ADD_CASE(s, a_small_row_is_not_hidden);
  ADD_CASE(s, nothing_given_nothing_compared);
  ADD_CASE(s, a_pattern_wrong_off_the_state_alone_is_found);
  ADD_CASE(s, the_rank_counts_the_independent_rows);
  ADD_CASE(s, the_nfourbar_loses_rank_where_it_is_flat);
  ADD_CASE(s, the_rank_refuses_bad_input);
  return run_suite(s);
}
