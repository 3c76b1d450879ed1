/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The one difference stencil (src/core/difference.c), against Taylor's theorem: the first
 * derivative's combination is exact for polynomials of degree 4 and falls short by exactly
 * h^4 f^(5) / 30 on x^5 (4 h^4 there); the second's is exact to degree 5 and falls short by
 * h^4 f^(6) / 90 on x^6 (8 h^4). With h = 1/8 and x = 1/2 every point and power is a binary
 * fraction, so the sums are exact and the errors come out to the last bit. */
#include <math.h>

#include "testmodels.h"

#include "core/difference.h"

static double power(double x, int p) {
  double y = 1.0;
  for (int i = 0; i < p; i++) y *= x;
  return y;
}

/* the stencil's derivative (second: order 2) of x^p at x with step h */
static double derivative(int order, int p, double x, double h) {
  double out = 0.0;
  int points = order == 1 ? SDAE_FD_POINTS : SDAE_FD2_POINTS;
  for (int k = 0; k < points; k++) {
    double f = power(x + sdae__fd_offset[k] * h, p);
    if (order == 1)
      sdae__fd_add(&out, 1, &f, 1, k);
    else
      sdae__fd2_add(&out, 1, &f, 1, k);
  }
  if (order == 1)
    sdae__fd_finish(&out, 1, 1, h);
  else
    sdae__fd2_finish(&out, 1, 1, h);
  return out;
}

START_TEST(first_derivative_is_fourth_order) {
  const double x = 0.5, h = 0.125;
  for (int p = 0; p <= 4; p++) /* exact through degree 4 */
    ck_assert_double_eq(derivative(1, p, x, h), p ? p * power(x, p - 1) : 0.0);
  ck_assert_double_eq(derivative(1, 5, x, h) - 5.0 * power(x, 4), -4.0 * power(h, 4));
}
END_TEST

START_TEST(second_derivative_is_fourth_order) {
  const double x = 0.5, h = 0.125;
  for (int p = 0; p <= 5; p++) /* exact through degree 5 */
    ck_assert_double_eq(derivative(2, p, x, h), p > 1 ? p * (p - 1) * power(x, p - 2) : 0.0);
  ck_assert_double_eq(derivative(2, 6, x, h) - 30.0 * power(x, 4), -8.0 * power(h, 4));
}
END_TEST

/* strided: a column of a row-major matrix, the other entries untouched */
START_TEST(a_column_is_differenced_in_place) {
  double G[6] = {7.0, 0.0, 7.0, 7.0, 0.0, 7.0}, f[2];
  const double h = 0.25;
  for (int k = 0; k < SDAE_FD_POINTS; k++) {
    double s = sdae__fd_offset[k] * h;
    f[0] = 3.0 * s, f[1] = -2.0 * s; /* slopes 3 and -2 */
    sdae__fd_add(G + 1, 3, f, 2, k);
  }
  sdae__fd_finish(G + 1, 3, 2, h);
  ck_assert_double_eq(G[1], 3.0);
  ck_assert_double_eq(G[4], -2.0);
  ck_assert_double_eq(G[0] + G[2] + G[3] + G[5], 28.0);
}
END_TEST

/* the step is exactly representable at x: x + h - x == h */
START_TEST(the_step_is_exact_at_x) {
  const double xs[4] = {0.0, 1.0, 1e6 + 0.1, -3.7e12};
  for (int i = 0; i < 4; i++) {
    double h = sdae__fd_step(xs[i], SDAE_FD_STEP * fmax(1.0, fabs(xs[i])));
    ck_assert_double_eq((xs[i] + h) - xs[i], h);
    ck_assert_double_le(fabs(h - SDAE_FD_STEP * fmax(1.0, fabs(xs[i]))),
                        1e-12 * fmax(1.0, fabs(xs[i])));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("difference");
  ADD_CASE(s, first_derivative_is_fourth_order);
  ADD_CASE(s, second_derivative_is_fourth_order);
  ADD_CASE(s, a_column_is_differenced_in_place);
  ADD_CASE(s, the_step_is_exact_at_x);
  return run_suite(s);
}
