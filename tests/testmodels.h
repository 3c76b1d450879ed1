/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Models with known answers, shared by the unit suites. */
#ifndef STABDAE_TESTMODELS_H
#define STABDAE_TESTMODELS_H

#include <check.h>
#include <stabdae/mbs.h>
#include <stabdae/stabdae.h>

#include "quartic.h"
#include "rotation.h"

/* options with the map and scheme as given, the rest default */
sdae_options quartic_options(const sdae_map_type *map, sdae_scheme scheme);

/* Exact solution of x'' = -k x^3 from x(0) = A, x'(0) = 0: x = A cn(A sqrt(k) t | 1/2). */
void quartic_exact(double k, double A, double t, double *x, double *v);

/* Integrates the quartic on the manifold (xi = 0) from (A, 0) to tf with step T; returns the
 * max-norm error of mu against the exact solution at tf. */
double quartic_error(const sdae_options *o, double A, double tf, double T);

double rel_diff(double a, double b);
/* max_i |a_i - b_i| over n values */
double max_abs_diff(const double *a, const double *b, size_t n);

/* One test case per behaviour; tests/CMakeLists.txt reads the ADD_CASE lines to register
 * every case as its own ctest test. */
#define ADD_CASE(suite, fn) add_case((suite), #fn, fn)
void add_case(Suite *s, const char *name, const TTest *test);

/* one step that must fail with `want`, after one good step (so a chart and a count exist):
 * q, v bitwise as they were, the step count unchanged, the chart unchanged, and the stepper's
 * whole state (sdae_mbs_get_state: the chart, the point kept, Newton's matrix, the counters)
 * the same bytes: a failed step leaves no trace */
void expect_step_fails(sdae_mbs_stepper *s, double t, double T, double *q, double *v, size_t n_q,
                       int want);

/* Runs one suite; main of every test program. */
int run_suite(Suite *s);

#endif
