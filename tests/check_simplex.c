/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The Nelder-Mead minimizer of src/core/simplex.c against its definition: the first simplex u,
 * u + step e_j, the moves p = c + coeff (x_worst - c) with coeff -1 (reflection), -2
 * (expansion), 1/2 (contraction), the shrink of every vertex halfway to the best (Nelder and
 * Mead 1965, with the acceptance rules of Lagarias et al. 1998: an expansion is kept only when
 * it beats the reflection, a reflection is expanded only when it beats the best vertex; and
 * GSL's nmsimplex2, whose moves the file follows, for the rest: a reflection not better than
 * the second worst vertex is contracted, replacing the worst first when it is no worse than it,
 * the contraction kept when it is no worse than the worst vertex as it then is, otherwise the
 * simplex shrinks; the worst and the best are the first of equal vertices), the
 * stop on the vertices' RMS distance from their center, the iteration limit, the objective's
 * failure returned at once; and its work size, (n + 1)^2 + 3 n doubles or SIZE_MAX. Every
 * sequence of points below is worked out by hand from those rules. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "testmodels.h"

#include "core/simplex.h"

#define MAX_EVALS 4096

typedef struct recorder {
  double (*f)(const double *u, size_t n);
  size_t n;
  long calls, fail_at; /* fail_at: the call (1-based) that returns status; 0: none */
  int status;
  double pts[64][4]; /* the first 64 points evaluated */
} recorder;

static int recorded(const double *u, double *value, void *data) {
  recorder *r = data;
  r->calls++;
  if (r->calls <= 64) memcpy(r->pts[r->calls - 1], u, r->n * sizeof *u);
  if (r->calls == r->fail_at) return r->status;
  *value = r->f(u, r->n);
  return 0;
}

/* the work array between two canaries: the minimizer must stay inside its (n + 1)^2 + 3 n */
static double work_buf[2 + 64];

static int minimize(recorder *r, double *u, double step, double tol, int max_iter) {
  size_t w = sdae__simplex_work(r->n);
  uint64_t canary = 0x7ff4dead7ff4beefULL;
  int rc;
  ck_assert_uint_le(w, 64);
  memcpy(&work_buf[0], &canary, sizeof canary);
  memcpy(&work_buf[1 + w], &canary, sizeof canary);
  rc = sdae__simplex_minimize(recorded, r, r->n, u, step, tol, max_iter, work_buf + 1);
  /* nothing written outside the work the header promises is enough */
  ck_assert_mem_eq(&work_buf[0], &canary, sizeof canary);
  ck_assert_mem_eq(&work_buf[1 + w], &canary, sizeof canary);
  return rc;
}

static void expect_points(const recorder *r, const double (*pts)[2], long count) {
  ck_assert_int_eq(r->calls, count);
  for (long i = 0; i < count; i++)
    for (size_t j = 0; j < r->n; j++)
      ck_assert_msg(fabs(r->pts[i][j] - pts[i][j]) <= 1e-14, "point %ld [%zu]: %.17g, not %.17g", i,
                    j, r->pts[i][j], pts[i][j]);
}

/* ---- the work size ---- */

/* exact (n + 1)^2 + 3 n, or SIZE_MAX when it does not fit: the compiler's checked arithmetic
 * is the reference */
static size_t work_reference(size_t n) {
  size_t sq, three, sum;
  if (n == 0) return 0;
  if (__builtin_mul_overflow(n + 1, n + 1, &sq) || __builtin_mul_overflow(n, (size_t)3, &three) ||
      __builtin_add_overflow(sq, three, &sum))
    return SIZE_MAX;
  return sum;
}

START_TEST(work_size) {
  size_t half = (size_t)1 << (sizeof(size_t) * 4);   /* sqrt(SIZE_MAX + 1) */
  ck_assert_uint_eq(sdae__simplex_work(0), 0);       /* header: 0 for n = 0 */
  ck_assert_uint_eq(sdae__simplex_work(1), 4 + 3);   /* 2^2 + 3 */
  ck_assert_uint_eq(sdae__simplex_work(2), 9 + 6);   /* 3^2 + 6 */
  ck_assert_uint_eq(sdae__simplex_work(4), 25 + 12); /* 5^2 + 12 */
  /* around the largest n that fits: (n + 1)^2 + 3 n crosses SIZE_MAX near n = 2^(bits/2) */
  for (size_t n = half - 8; n < half + 8; n++)
    ck_assert_uint_eq(sdae__simplex_work(n), work_reference(n));
  ck_assert_uint_eq(sdae__simplex_work(SIZE_MAX / 4 - 1), SIZE_MAX);
  ck_assert_uint_eq(sdae__simplex_work(SIZE_MAX / 2), SIZE_MAX);
  ck_assert_uint_eq(sdae__simplex_work(SIZE_MAX), SIZE_MAX);
}
END_TEST

/* ---- the moves, traced by hand in one and two dimensions ---- */

static double linear(const double *u, size_t n) {
  (void)n;
  return u[0];
}

/* f = u from 0, step 0.2: vertices 0 (f 0), 0.2 (worst). Reflection through c = 0: -0.2,
 * beats the best -> expansion c - 2 (0.2 - c) = -0.4, better than the reflection: kept.
 * Then c = -0.4 (the best), worst 0: reflection -0.8, expansion -0.4 - 2 (0.4) = -1.2. */
START_TEST(reflect_and_expand) {
  static const double pts[6][2] = {{0}, {0.2}, {-0.2}, {-0.4}, {-0.8}, {-1.2}};
  recorder r = {.f = linear, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.0, 2), 0);
  expect_points(&r, pts, 6);
  ck_assert_double_le(fabs(u[0] - -1.2), 1e-15); /* the best vertex */
}
END_TEST

/* A tent: f = -10 u (u < 0), 30 u (0 <= u <= 0.1), 3 - 20 (u - 0.1) (u > 0.1), so f(0) = 0,
 * f(0.2) = 1, f(-0.2) = 2, f(0.1) = 3, f(-0.1) = 1, f(-0.05) = 0.5, f(0.05) = 1.5,
 * f(-0.025) = 0.25. From 0, step 0.2:
 *   1: reflection -0.2 (2) is worse than the worst (1): contraction c + (0.2 - c)/2 = 0.1
 *      (3) is worse too: shrink, 0.2 -> (0.2 + 0)/2 = 0.1, evaluated again;
 *   2: vertices 0, 0.1 (3): reflection -0.1 (1) beats the worst, replaces it, and is
 *      contracted: 0 + (-0.1 - 0)/2 = -0.05 (0.5), better than 1: kept;
 *   3: reflection 0.05 (1.5) worse than the worst (0.5): contraction -0.025 (0.25), kept. */
static double tent(const double *u, size_t n) {
  double x = u[0];
  (void)n;
  if (x < 0.0) return -10.0 * x;
  return x <= 0.1 ? 30.0 * x : 3.0 - 20.0 * (x - 0.1);
}

START_TEST(contract_and_shrink) {
  static const double pts[9][2] = {{0},    {0.2},   {-0.2}, {0.1},   {0.1},
                                   {-0.1}, {-0.05}, {0.05}, {-0.025}};
  recorder r = {.f = tent, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.0, 3), 0);
  expect_points(&r, pts, 9);
  ck_assert_double_eq(u[0], 0.0); /* f = 0 there, 0.25 at the other vertex */
}
END_TEST

/* f = |u + 0.01| from 0, step 0.2: f(0) = 0.01 (best), f(0.2) = 0.21 (worst); the reflection
 * -0.2 (0.19) does not beat the second worst (here the best, 0.01) but beats the worst: it
 * replaces it and is contracted to -0.1 (0.09), kept. A second worst taken as the worst would
 * accept the reflection and stop there. */
static double abs_shifted(const double *u, size_t n) {
  (void)n;
  return fabs(u[0] + 0.01);
}

START_TEST(second_worst_decides_contraction) {
  static const double pts[4][2] = {{0}, {0.2}, {-0.2}, {-0.1}};
  recorder r = {.f = abs_shifted, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.0, 1), 0);
  expect_points(&r, pts, 4);
  ck_assert_double_eq(u[0], 0.0); /* 0.01 against 0.09 */
}
END_TEST

/* f = max(u, -0.2) from 0, step 0.2: the reflection -0.2 (f -0.2) beats the best (0): the
 * expansion -0.4 has f = -0.2 too, does not beat the reflection: the reflection is kept
 * (Lagarias et al.: x_e only when f_e < f_r). Iteration 2, vertices 0 (worst), -0.2: the
 * reflection -0.4 (f -0.2) only ties the best: it is not expanded to -0.2 - 2 (0 + 0.2) = -0.6;
 * it only ties the second worst too (the same vertex in one dimension): not contracted (GSL),
 * accepted. Both vertices then have f = -0.2: the best returned is the first, -0.4. */
static double floored(const double *u, size_t n) {
  (void)n;
  return fmax(u[0], -0.2);
}

/* f = (u - 10)^2 from 0, step 1, by hand: {0 (100), 1 (81)}: reflection 2 (64) beats the best,
 * expansion 3 (49) beats it: kept. {3, 1 (worst)}: reflection 5 (25), expansion 7 (9): kept.
 * {3 (worst), 7}: reflection 11 (1), expansion 15 (25) does not beat it: 11 kept. {11, 7 (9,
 * worst)}: reflection 15 (25) is worse than the worst: contraction 11 + (7 - 11)/2 = 9 (1),
 * kept. The stored values decide every choice: the expansion 7 kept with another value than
 * f(7) = 9 would make the last contraction start elsewhere. */
static double square_at_10(const double *u, size_t n) {
  (void)n;
  return (u[0] - 10.0) * (u[0] - 10.0);
}

START_TEST(expansion_keeps_its_own_value) {
  static const double pts[10][2] = {{0}, {1}, {2}, {3}, {5}, {7}, {11}, {15}, {15}, {9}};
  recorder r = {.f = square_at_10, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&r, u, 1.0, 0.0, 4), 0);
  expect_points(&r, pts, 10);
}
END_TEST

/* f = u^2 from -1, step 0.75 (exact in binary): the first vertex is the worst (1 against
 * 0.0625), the second worst the other one. The reflection 0.5 (0.25) is worse than it: it
 * replaces the worst (it beats 1) and is contracted to -0.25 + (0.5 + 0.25)/2 = 0.125
 * (0.015625), kept. Taking vertex 0 for the second worst too would accept the reflection. */
static double square(const double *u, size_t n) {
  (void)n;
  return u[0] * u[0];
}

START_TEST(second_worst_when_the_first_vertex_is_worst) {
  static const double pts[4][2] = {{-1.0}, {-0.25}, {0.5}, {0.125}};
  recorder r = {.f = square, .n = 1};
  double u[1] = {-1.0};
  ck_assert_int_eq(minimize(&r, u, 0.75, 0.0, 1), 0);
  expect_points(&r, pts, 4);
  ck_assert_double_eq(u[0], 0.125); /* 0.015625 against 0.0625 */
}
END_TEST

START_TEST(ties_neither_expand_nor_keep_expansion) {
  recorder r = {.f = floored, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.0, 2), 0);
  ck_assert_int_ge(r.calls, 5);
  ck_assert_double_eq(r.pts[3][0], -0.4);               /* the expansion, tried */
  ck_assert_double_le(fabs(r.pts[4][0] - -0.4), 1e-15); /* reflection of 0 through -0.2 */
  for (long i = 0; i < r.calls; i++) /* no expansion of a reflection that only ties the best */
    ck_assert_double_gt(fabs(r.pts[i][0] - -0.6), 1e-9);
  ck_assert_int_eq(r.calls, 5); /* nor a contraction */
  ck_assert_double_le(fabs(u[0] - -0.4), 1e-15);
}
END_TEST

/* f = 15 u (u >= 0), -20 u (-0.1 <= u < 0), 2 + 10 (u + 0.1) (u < -0.1): f(0) = 0, f(0.2) = 3,
 * f(-0.2) = 1, f(-0.1) = 2. The reflection -0.2 (1) does not beat the second worst (0) but
 * beats the worst (3): it replaces it. The contraction -0.1 (2) is worse than that new worst
 * vertex (1): the simplex shrinks, -0.2 -> -0.1, rather than trade the reflection for a worse
 * point. */
static double notch(const double *u, size_t n) {
  double x = u[0];
  (void)n;
  if (x >= 0.0) return 15.0 * x;
  return x >= -0.1 ? -20.0 * x : 2.0 + 10.0 * (x + 0.1);
}

START_TEST(contraction_no_worse_than_new_worst) {
  static const double pts[5][2] = {{0}, {0.2}, {-0.2}, {-0.1}, {-0.1}};
  recorder r = {.f = notch, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.0, 1), 0);
  expect_points(&r, pts, 5);
  ck_assert_double_eq(u[0], 0.0);
}
END_TEST

/* Ties with the worst vertex (GSL: "no worse" is <=). f = 5 |u|: the reflection -0.2 has
 * f = 1 = f(0.2), replaces it, and the contraction is taken from it: 0 + (-0.2 - 0)/2 = -0.1
 * (0.5), kept. Then f = -10 u (u < 0), min(10 u, 1) (u >= 0): the reflection -0.2 (2) is
 * worse than the worst (1); the contraction 0.1 has f = 1, no worse than the worst: kept,
 * no shrink. */
static double five_abs(const double *u, size_t n) {
  (void)n;
  return 5.0 * fabs(u[0]);
}
static double capped(const double *u, size_t n) {
  (void)n;
  return u[0] < 0.0 ? -10.0 * u[0] : fmin(10.0 * u[0], 1.0);
}

START_TEST(ties_with_the_worst) {
  static const double pts_a[4][2] = {{0}, {0.2}, {-0.2}, {-0.1}},
                      pts_b[4][2] = {{0}, {0.2}, {-0.2}, {0.1}};
  recorder a = {.f = five_abs, .n = 1}, b = {.f = capped, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&a, u, 0.2, 0.0, 1), 0);
  expect_points(&a, pts_a, 4);
  u[0] = 0.0;
  ck_assert_int_eq(minimize(&b, u, 0.2, 0.0, 1), 0);
  expect_points(&b, pts_b, 4);
}
END_TEST

/* Two dimensions, f = (x - 0.2)^2 + y (0.6 x - 0.1), from (0, 0), step 0.2: the first
 * simplex (0, 0) (0.04, worst), (0.2, 0) (0, best), (0, 0.2) (0.02, second worst). The
 * centroid of the other two is (0.1, 0.1): reflection (0.2, 0.2), f = 0.004, between the best
 * and the second worst: accepted, nothing else evaluated. */
static double saddle(const double *u, size_t n) {
  (void)n;
  return (u[0] - 0.2) * (u[0] - 0.2) + u[1] * (0.6 * u[0] - 0.1);
}

START_TEST(two_dimensional_reflection) {
  static const double pts[4][2] = {{0, 0}, {0.2, 0}, {0, 0.2}, {0.2, 0.2}};
  recorder r = {.f = saddle, .n = 2};
  double u[2] = {0.0, 0.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.0, 1), 0);
  expect_points(&r, pts, 4);
  ck_assert_double_eq(u[0], 0.2); /* f = 0 at (0.2, 0), the least */
  ck_assert_double_eq(u[1], 0.0);
}
END_TEST

/* ---- stopping ---- */

static double constant(const double *u, size_t n) {
  (void)u, (void)n;
  return 1.0;
}

/* f constant in one dimension: no move beats anything, every iteration reflects a vertex
 * through the other, and the two vertices stay step = 0.2 apart: their RMS distance from
 * their center is 0.1. A tolerance above it stops after one iteration (2 + 1 evaluations), one
 * below it never stops: 2 + max_iter evaluations. */
START_TEST(stops_on_simplex_size) {
  recorder r = {.f = constant, .n = 1};
  double u[1] = {0.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.101, 50), 0);
  ck_assert_int_eq(r.calls, 3);
  /* all equal: the worst is the first vertex, 0, reflected through 0.2 to 0.4 */
  ck_assert_double_le(fabs(r.pts[2][0] - 0.4), 1e-15);
  r.calls = 0;
  ck_assert_int_eq(minimize(&r, u, 0.2, 0.099, 50), 0);
  ck_assert_int_eq(r.calls, 2 + 50);
  r.calls = 0;
  r.n = 3; /* any n: n + 1 evaluations of the first simplex, then one per iteration */
  double v[3] = {0.0, 0.0, 0.0};
  ck_assert_int_eq(minimize(&r, v, 0.2, 0.0, 7), 0);
  ck_assert_int_eq(r.calls, 4 + 7);
  for (size_t i = 0; i < 4; i++) /* the first simplex: u and u + 0.2 e_j */
    for (size_t j = 0; j < 3; j++) ck_assert_double_eq(r.pts[i][j], i == j + 1 ? 0.2 : 0.0);
}
END_TEST

/* ---- known minima ---- */

static const double quad_center[4] = {0.3, -0.7, 1.1, 0.25};
static double quadratic(const double *u, size_t n) {
  double s = 0.0;
  for (size_t j = 0; j < n; j++)
    s += (double)(j + 1) * (u[j] - quad_center[j]) * (u[j] - quad_center[j]);
  return s;
}

static double rosenbrock(const double *u, size_t n) {
  (void)n;
  return 100.0 * (u[1] - u[0] * u[0]) * (u[1] - u[0] * u[0]) + (1.0 - u[0]) * (1.0 - u[0]);
}

/* sum_j (j + 1)(u_j - c_j)^2: minimum 0 at c (Nelder-Mead converges on a strictly convex
 * quadratic in one and two dimensions, Lagarias et al. 1998). The run must stop on the size
 * 1e-12, before the 1000 iterations: a larger limit then changes nothing; the best vertex of so
 * small a simplex is within 1e-6 of c. (With a constant added, f would be flat to rounding near
 * c and a one-dimensional simplex there only flips, never shrinks.) */
START_TEST(quadratic_minimum_in_1_to_4_dimensions) {
  for (size_t n = 1; n <= 4; n++) {
    recorder r = {.f = quadratic, .n = n};
    double u[4] = {0.0, 0.0, 0.0, 0.0};
    ck_assert_int_eq(minimize(&r, u, 0.2, 1e-12, 1000), 0);
    for (size_t j = 0; j < n; j++) ck_assert_double_le(fabs(u[j] - quad_center[j]), 1e-6);
    long calls = r.calls;
    double v[4] = {0.0, 0.0, 0.0, 0.0};
    r.calls = 0;
    ck_assert_int_eq(minimize(&r, v, 0.2, 1e-12, 100000), 0);
    ck_assert_int_eq(r.calls, calls);
  }
}
END_TEST

/* Rosenbrock's valley 100 (y - x^2)^2 + (1 - x)^2 from (-1.2, 1): minimum 0 at (1, 1) */
START_TEST(rosenbrock_valley) {
  recorder r = {.f = rosenbrock, .n = 2};
  double u[2] = {-1.2, 1.0};
  ck_assert_int_eq(minimize(&r, u, 0.2, 1e-12, 1000), 0);
  ck_assert_double_le(fabs(u[0] - 1.0), 1e-6);
  ck_assert_double_le(fabs(u[1] - 1.0), 1e-6);
  /* n + 1 for the first simplex, then at most 2 + n per iteration (reflection, contraction,
   * n shrunk vertices) */
  ck_assert_int_le(r.calls, 3 + 1000 * 4);
}
END_TEST

/* ---- failures ---- */

/* The objective failing at its k-th call, for every k of a complete run: that status comes
 * back and the objective is not called again. */
static void fail_at_every_call(double (*f)(const double *, size_t), size_t n, const double *u0,
                               int max_iter) {
  recorder r = {.f = f, .n = n};
  double u[4];
  memcpy(u, u0, n * sizeof *u);
  ck_assert_int_eq(minimize(&r, u, 0.2, 1e-12, max_iter), 0);
  long total = r.calls;
  ck_assert_int_le(total, MAX_EVALS);
  for (long k = 1; k <= total; k++) {
    recorder q = {.f = f, .n = n, .fail_at = k, .status = k % 2 ? 3 : -2};
    memcpy(u, u0, n * sizeof *u);
    ck_assert_int_eq(minimize(&q, u, 0.2, 1e-12, max_iter), k % 2 ? 3 : -2);
    ck_assert_int_eq(q.calls, k);
  }
}

START_TEST(failure_returned_at_once) {
  static const double zero[4] = {0.0, 0.0, 0.0, 0.0}, start[2] = {-1.2, 1.0};
  fail_at_every_call(linear, 1, zero, 2); /* reflections and expansions */
  fail_at_every_call(tent, 1, zero, 3);   /* contractions and a shrink */
  fail_at_every_call(quadratic, 3, zero, 1000);
  fail_at_every_call(rosenbrock, 2, start, 300);
}
END_TEST

int main(void) {
  Suite *s = suite_create("simplex");
  ADD_CASE(s, work_size);
  ADD_CASE(s, reflect_and_expand);
  ADD_CASE(s, contract_and_shrink);
  ADD_CASE(s, second_worst_decides_contraction);
  ADD_CASE(s, expansion_keeps_its_own_value);
  ADD_CASE(s, second_worst_when_the_first_vertex_is_worst);
  ADD_CASE(s, ties_neither_expand_nor_keep_expansion);
  ADD_CASE(s, contraction_no_worse_than_new_worst);
  ADD_CASE(s, ties_with_the_worst);
  ADD_CASE(s, two_dimensional_reflection);
  ADD_CASE(s, stops_on_simplex_size);
  ADD_CASE(s, quadratic_minimum_in_1_to_4_dimensions);
  ADD_CASE(s, rosenbrock_valley);
  ADD_CASE(s, failure_returned_at_once);
  return run_suite(s);
}
