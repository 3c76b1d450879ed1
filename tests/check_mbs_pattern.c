/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Sparse mechanisms (sdae_mbs.mass_pattern, jacobian_pattern): a mechanism given by its nonzeros
 * is the same mechanism as given densely, so it steps to the same trajectory; a pattern that is
 * not one is refused where the stepper is built, with nothing changed; the stepper keeps its own
 * copy; and sdae_mbs_check sees a Jacobian entry left out of its pattern. */
#include <math.h>
#include <string.h>

#include "mbs/mbs_impl.h"
#include "mechanisms.h"
#include "rope.h"
#include "testmodels.h"

static sdae_options options(const sdae_map_type *map) {
  return quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
}

/* n steps of T from the start into q, v; the status of the first failure */
static int run(const sdae_mbs *sys, const sdae_options *o, size_t n, double T, double *q,
               double *v) {
  sdae_mbs_stepper *s;
  int rc = sdae_mbs_stepper_alloc(&s, sys, o);
  for (size_t k = 0; rc == SDAE_OK && k < n; k++) rc = sdae_mbs_step(s, (double)k * T, T, q, v);
  sdae_mbs_stepper_free(s);
  return rc;
}

/* M and G given by their nonzeros are M and G: without (dM/ds) v a mechanism with patterns is
 * stepped on the dense back-end (its matrices scattered from the nonzeros), and there, through
 * the implicit maps, its steps are the dense mechanism's, bit for bit */
START_TEST(a_sparse_rope_steps_as_the_dense_one) {
  const sdae_map_type *maps[] = {sdae_map_midpoint, sdae_map_dgrad};
  for (int closed = 0; closed <= 1; closed++)
    for (size_t k = 0; k < sizeof maps / sizeof *maps; k++) {
      mech_rope dense = mech_rope_unit(5, closed, 0), sparse = mech_rope_unit(5, closed, 1);
      sdae_mbs sd, ss;
      sdae_options o = options(maps[k]);
      double q[10], v[10], q2[10], v2[10];
      ck_assert_int_eq(mech_rope_system(&sd, &dense), 0);
      ck_assert_int_eq(mech_rope_system(&ss, &sparse), 0);
      sd.mass_dot_v = ss.mass_dot_v = NULL;
      ck_assert_int_eq(mech_rope_start(&dense, 0.5, q, v), 0);
      ck_assert_int_eq(mech_rope_start(&sparse, 0.5, q2, v2), 0);
      ck_assert_int_eq(run(&sd, &o, 100, 1e-2, q, v), SDAE_OK);
      ck_assert_int_eq(run(&ss, &o, 100, 1e-2, q2, v2), SDAE_OK);
      ck_assert_mem_eq(q, q2, sizeof q);
      ck_assert_mem_eq(v, v2, sizeof v);
      ck_assert_double_le(mech_max_abs_c(&ss, 1.0, q2), 1e-13);
      mech_rope_free(&sparse);
    }
}
END_TEST

/* Through an explicit map a sparse mechanism is stepped in its own coordinates (the chart of
 * core/sparse_lu.c), another discretization of the same motion: it agrees with the dense one
 * to truncation error, the difference falling as T^4 under rk4 (by 16 when T halves) */
START_TEST(a_sparse_rope_agrees_with_the_dense_one_to_truncation) {
  for (int closed = 0; closed <= 1; closed++) {
    double diff[2];
    for (int h = 0; h < 2; h++) {
      mech_rope dense = mech_rope_unit(5, closed, 0), sparse = mech_rope_unit(5, closed, 1);
      sdae_mbs sd, ss;
      sdae_options o = options(sdae_map_rk4);
      double q[10], v[10], q2[10], v2[10], T = h ? 0.01 : 0.02;
      size_t n = h ? 100 : 50;
      ck_assert_int_eq(mech_rope_system(&sd, &dense), 0);
      ck_assert_int_eq(mech_rope_system(&ss, &sparse), 0);
      ck_assert_int_eq(mech_rope_start(&dense, 0.5, q, v), 0);
      ck_assert_int_eq(mech_rope_start(&sparse, 0.5, q2, v2), 0);
      ck_assert_int_eq(run(&sd, &o, n, T, q, v), SDAE_OK);
      ck_assert_int_eq(run(&ss, &o, n, T, q2, v2), SDAE_OK);
      diff[h] = max_abs_diff(q, q2, 10);
      mech_rope_free(&sparse);
    }
    ck_assert_double_gt(diff[1], 0.0);
    ck_assert_double_le(diff[0], 1e-4);
    ck_assert_double_ge(diff[0] / diff[1], 10.0); /* 16 for order 4 */
  }
}
END_TEST

/* the pendulum's M = m I and D = d I by their diagonals */
static int diagonal_mass(double t, const double *q, double *M, void *params) {
  const mech_pendulum *p = params;
  (void)t, (void)q;
  M[0] = M[1] = p->m;
  return 0;
}

static int diagonal_damping(double t, const double *q, double *D, void *params) {
  const mech_pendulum *p = params;
  (void)t, (void)q;
  D[0] = D[1] = p->d;
  return 0;
}

/* the damping is written in the mass's pattern: a diagonal M and D by their diagonals step as
 * the dense ones, under the discrete gradient (which reads D) and an explicit map */
START_TEST(a_diagonal_mass_and_damping_step_as_the_dense_ones) {
  static const size_t diag_start[] = {0, 1, 2}, diag_col[] = {0, 1};
  static const sdae_pattern diagonal = {2, diag_start, diag_col};
  const sdae_map_type *maps[] = {sdae_map_dgrad, sdae_map_rk4};
  for (size_t k = 0; k < 2; k++) {
    mech_pendulum p = {.L = 1.0, .m = 2.0, .ga = 9.81, .d = 0.3};
    sdae_mbs dense, sparse;
    sdae_options o = options(maps[k]);
    double q[2], v[2], q2[2], v2[2];
    mech_pendulum_system(&dense, &p);
    sparse = dense;
    sparse.mass_pattern = &diagonal;
    sparse.mass = diagonal_mass;
    sparse.damping = diagonal_damping;
    mech_pendulum_state(&p, 1.0, 0.0, q, v);
    mech_pendulum_state(&p, 1.0, 0.0, q2, v2);
    ck_assert_int_eq(run(&dense, &o, 50, 1e-2, q, v), SDAE_OK);
    ck_assert_int_eq(run(&sparse, &o, 50, 1e-2, q2, v2), SDAE_OK);
    ck_assert_mem_eq(q, q2, sizeof q);
    ck_assert_mem_eq(v, v2, sizeof v);
  }
}
END_TEST

/* On the sparse back-end (both patterns and the derivatives given) the damping is read by
 * products, R x = W^T D W x (mbs_coords.c): a damped pendulum under dgrad dissipates its energy
 * at every step, and steps as on the dense back-end (both choose the same chart for one degree
 * of freedom) to rounding over 0.5 s, at two steps; without the damping's term the two would
 * differ by the energy it takes, 1e-2 here */
START_TEST(a_damped_pendulum_on_the_sparse_back_end) {
  static const size_t diag_start[] = {0, 1, 2}, diag_col[] = {0, 1};
  static const size_t row_start[] = {0, 2}, row_col[] = {0, 1};
  static const sdae_pattern diagonal = {2, diag_start, diag_col}, row = {2, row_start, row_col};
  double diff[2];
  for (int h = 0; h < 2; h++) {
    mech_pendulum p = {.L = 1.0, .m = 2.0, .ga = 9.81, .d = 0.3};
    sdae_mbs dense, sparse;
    sdae_mbs_stepper *s;
    sdae_options o = options(sdae_map_dgrad);
    double q[2], v[2], q2[2], v2[2], T = h ? 5e-3 : 1e-2, E, E_last;
    size_t n = h ? 100 : 50;
    mech_pendulum_system(&dense, &p);
    sparse = dense;
    sparse.mass_pattern = &diagonal;
    sparse.mass = diagonal_mass;
    sparse.damping = diagonal_damping;
    sparse.jacobian_pattern = &row;
    mech_pendulum_state(&p, 1.0, 0.0, q, v);
    mech_pendulum_state(&p, 1.0, 0.0, q2, v2);
    ck_assert_int_eq(run(&dense, &o, n, T, q, v), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sparse, &o), SDAE_OK);
    ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, 1);
    ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q2, v2, &E_last), SDAE_OK);
    for (size_t k = 0; k < n; k++) {
      ck_assert_int_eq(sdae_mbs_step(s, (double)k * T, T, q2, v2), SDAE_OK);
      ck_assert_int_eq(sdae_mbs_energy(s, (double)(k + 1) * T, q2, v2, &E), SDAE_OK);
      ck_assert_double_lt(E, E_last);
      E_last = E;
    }
    sdae_mbs_stepper_free(s);
    diff[h] = max_abs_diff(q, q2, 2);
  }
  ck_assert_double_le(fmax(diff[0], diff[1]), 1e-12);
}
END_TEST

/* every way a pattern can fail to be one, for the mass (symmetric) and the Jacobian: refused by
 * sdae_mbs_stepper_size, _init, _alloc and sdae_mbs_check alike, *s and the report untouched */
typedef struct bad_pattern {
  const char *why;
  int mass; /* a mass pattern (4 x 4), else a Jacobian's (2 x 4) */
  size_t nnz, row_start[5], col[8];
} bad_pattern;

static const bad_pattern bad[] = {
    {"columns unsorted", 0, 4, {0, 2, 4}, {1, 0, 2, 3}},
    {"a duplicate", 0, 4, {0, 2, 4}, {0, 0, 2, 3}},
    {"a column out of range", 0, 4, {0, 2, 4}, {0, 1, 2, 4}},
    {"row_start not from 0", 0, 4, {1, 2, 4}, {0, 1, 2, 3}},
    {"row_start decreasing", 0, 4, {0, 3, 2}, {0, 1, 2, 3}},
    {"nnz not row_start's last", 0, 3, {0, 2, 4}, {0, 1, 2, 3}},
    {"a mass not symmetric", 1, 5, {0, 2, 3, 4, 5}, {0, 1, 1, 2, 3}},
    {"a mass's row out of range", 1, 4, {0, 1, 2, 3, 4}, {0, 1, 2, 7}},
};

START_TEST(a_pattern_that_is_not_one_is_refused) {
  for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
    mech_rope r = mech_rope_unit(2, 0, 1);
    sdae_mbs sys;
    sdae_pattern p = {bad[k].nnz, bad[k].row_start, bad[k].col};
    sdae_options o = options(sdae_map_rk4);
    sdae_mbs_stepper *s = (sdae_mbs_stepper *)&r;
    sdae_mbs_check_report report, before;
    static max_align_t mem[1 << 12];
    double q[4], v[4];
    ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
    if (bad[k].mass)
      sys.mass_pattern = &p;
    else
      sys.jacobian_pattern = &p;
    ck_assert_msg(sdae_mbs_stepper_size(&sys, &o) == 0, "%s: accepted", bad[k].why);
    ck_assert_int_eq(sdae_mbs_stepper_init(&s, mem, sizeof mem, &sys, &o), SDAE_ERR_PATTERN);
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_ERR_PATTERN);
    ck_assert_ptr_eq(s, (sdae_mbs_stepper *)&r);
    ck_assert_int_eq(mech_rope_start(&r, 0.3, q, v), 0);
    memset(&report, 0x5A, sizeof report);
    before = report;
    ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &report), SDAE_ERR_PATTERN);
    ck_assert_mem_eq(&report, &before, sizeof report);
    mech_rope_free(&r);
  }
  ck_assert_str_ne(sdae_strerror(SDAE_ERR_PATTERN), "unknown status");
}
END_TEST

/* a pattern for a Jacobian the mechanism does not give: nothing would write its values */
START_TEST(a_jacobian_pattern_without_jacobian_is_refused) {
  mech_rope r = mech_rope_unit(3, 0, 1);
  sdae_mbs sys;
  sdae_options o = options(sdae_map_rk4);
  ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
  sys.jacobian = NULL;
  sys.jacobian_dot = NULL;
  ck_assert_uint_eq(sdae_mbs_stepper_size(&sys, &o), 0);
  sdae_mbs_stepper *s = NULL;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_ERR_NULL);
  ck_assert_ptr_null(s);
  mech_rope_free(&r);
}
END_TEST

/* The stepper steps with its own copy of the patterns: the caller's arrays overwritten (or
 * freed) after the build change nothing */
START_TEST(the_stepper_keeps_its_own_patterns) {
  mech_rope r = mech_rope_unit(5, 1, 1), ref = mech_rope_unit(5, 1, 1);
  sdae_mbs sys, sys_ref;
  sdae_options o = options(sdae_map_rk4);
  sdae_mbs_stepper *s;
  double q[10], v[10], q2[10], v2[10];
  ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
  ck_assert_int_eq(mech_rope_system(&sys_ref, &ref), 0);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  memset(r.arrays, 0xFF, (2 * 11 + 7 + 24) * sizeof *r.arrays); /* every array of the patterns */
  ck_assert_int_eq(mech_rope_start(&r, 0.0, q, v), 0);
  ck_assert_int_eq(mech_rope_start(&ref, 0.0, q2, v2), 0);
  for (int k = 0; k < 50; k++) ck_assert_int_eq(sdae_mbs_step(s, k * 1e-2, 1e-2, q, v), SDAE_OK);
  ck_assert_int_eq(run(&sys_ref, &o, 50, 1e-2, q2, v2), SDAE_OK);
  ck_assert_mem_eq(q, q2, sizeof q);
  ck_assert_mem_eq(v, v2, sizeof v);
  sdae_mbs_stepper_free(s);
  mech_rope_free(&r);
  mech_rope_free(&ref);
}
END_TEST

/* the pendulum's G = (x, y) with only x declared (pattern {0}): the differences of c see y */
static int first_entry(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  G[0] = q[0];
  return 0;
}

START_TEST(check_sees_a_jacobian_entry_outside_its_pattern) {
  static const size_t start[] = {0, 1}, first[] = {0}, start2[] = {0, 2}, both[] = {0, 1};
  static const sdae_pattern only_x = {1, start, first}, whole = {2, start2, both};
  mech_pendulum p = {.L = 1.0, .m = 1.0, .ga = 9.81};
  sdae_mbs sys;
  sdae_mbs_check_report r;
  double q[2], v[2];
  mech_pendulum_system(&sys, &p);
  sys.jacobian_dot = NULL;
  mech_pendulum_state(&p, 0.7, 0.3, q, v);
  sys.jacobian_pattern = &whole; /* the pendulum's jacobian writes (x, y): both declared */
  ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
  ck_assert(r.consistent);
  sys.jacobian_pattern = &only_x;
  sys.jacobian = first_entry;
  ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
  ck_assert(!r.consistent);
  ck_assert_int_eq(r.worst, SDAE_MBS_JACOBIAN);
  ck_assert_uint_eq(r.worst_index, 1); /* entry (0, 1): dc/dy = y, left out */
  ck_assert_double_ge(r.mismatch[SDAE_MBS_JACOBIAN], 0.5);
}
END_TEST

/* the state of a sparse stepper is not a dense one's, nor one of another pattern */
START_TEST(a_state_of_another_pattern_is_foreign) {
  mech_rope r = mech_rope_unit(3, 0, 1), d = mech_rope_unit(3, 0, 0);
  sdae_mbs sys, sys_d;
  sdae_options o = options(sdae_map_rk4);
  sdae_mbs_stepper *s, *sd;
  unsigned char state[1 << 14];
  ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
  ck_assert_int_eq(mech_rope_system(&sys_d, &d), 0);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&sd, &sys_d, &o), SDAE_OK);
  ck_assert_uint_le(sdae_mbs_state_size(s), sizeof state);
  ck_assert_int_eq(sdae_mbs_get_state(s, state, sdae_mbs_state_size(s)), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_set_state(sd, state, sdae_mbs_state_size(s)), SDAE_ERR_STATE_FOREIGN);
  sdae_mbs_stepper_free(s);
  sdae_mbs_stepper_free(sd);
  mech_rope_free(&r);
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs_pattern");
  ADD_CASE(s, a_sparse_rope_steps_as_the_dense_one);
  ADD_CASE(s, a_sparse_rope_agrees_with_the_dense_one_to_truncation);
  ADD_CASE(s, a_diagonal_mass_and_damping_step_as_the_dense_ones);
  ADD_CASE(s, a_damped_pendulum_on_the_sparse_back_end);
  ADD_CASE(s, a_pattern_that_is_not_one_is_refused);
  ADD_CASE(s, a_jacobian_pattern_without_jacobian_is_refused);
  ADD_CASE(s, the_stepper_keeps_its_own_patterns);
  ADD_CASE(s, check_sees_a_jacobian_entry_outside_its_pattern);
  ADD_CASE(s, a_state_of_another_pattern_is_foreign);
  return run_suite(s);
}
