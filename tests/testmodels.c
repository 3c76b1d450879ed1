/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "testmodels.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_sf_elljac.h>

sdae_options quartic_options(const sdae_map_type *map, sdae_scheme scheme) {
  sdae_options o;
  sdae_options_default(&o);
  o.map = map;
  o.scheme = scheme;
  return o;
}

void quartic_exact(double k, double A, double t, double *x, double *v) {
  double sn, cn, dn, w = A * sqrt(k);
  gsl_sf_elljac_e(w * t, 0.5, &sn, &cn, &dn);
  *x = A * cn;
  *v = -A * w * sn * dn; /* d/du cn = -sn dn */
}

double quartic_error(const sdae_options *o, double A, double tf, double T) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_stepper *s = NULL;
  double xi[2] = {0, 0}, mu[2] = {A, 0}, x, v;
  size_t n = (size_t)lround(tf / T);
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, T, n, n, xi, mu, NULL, NULL, NULL), SDAE_OK);
  sdae_stepper_free(s);
  quartic_exact(p.k, A, tf, &x, &v);
  return fmax(fabs(mu[0] - x), fabs(mu[1] - v));
}

double rel_diff(double a, double b) {
  double scale = fmax(fabs(a), fabs(b));
  return scale == 0.0 ? 0.0 : fabs(a - b) / scale;
}

double max_abs_diff(const double *a, const double *b, size_t n) {
  double d = 0.0;
  for (size_t i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i]));
  return d;
}

void add_case(Suite *s, const char *name, const TTest *test) {
  TCase *tc = tcase_create(name);
  tcase_set_timeout(tc, 300); /* generous: the sanitizer and valgrind builds run slower */
  tcase_add_test(tc, test);
  suite_add_tcase(s, tc);
}

int run_suite(Suite *s) {
  SRunner *r = srunner_create(s);
  srunner_run_all(r, CK_NORMAL);
  /* no test run (CK_RUN_CASE names a case this binary lacks) is a failure, not a pass */
  int failed = srunner_ntests_failed(r), ran = srunner_ntests_run(r);
  srunner_free(r);
  return failed == 0 && ran > 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

/* one step that must fail with `want`, after one good step (so a chart and a count exist):
 * q, v bitwise as they were, the step count unchanged, the chart unchanged, and the stepper's
 * whole state (sdae_mbs_get_state: the chart, the point kept, Newton's matrix, the counters)
 * the same bytes: a failed step leaves no trace */
void expect_step_fails(sdae_mbs_stepper *s, double t, double T, double *q, double *v, size_t n_q,
                       int want) {
  static unsigned char before[1 << 14], after[1 << 14];
  double q0[8], v0[8];
  size_t dep[8] = {0}, dep0[8] = {0}, len = sdae_mbs_state_size(s);
  int had_chart = sdae_mbs_chart(s, dep0) == SDAE_OK;
  unsigned long steps = sdae_mbs_stepper_stats(s)->step.steps;
  memcpy(q0, q, n_q * sizeof *q), memcpy(v0, v, n_q * sizeof *v);
  ck_assert_uint_le(len, sizeof before);
  ck_assert_int_eq(sdae_mbs_get_state(s, before, len), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_step(s, t, T, q, v), want);
  ck_assert_int_eq(sdae_mbs_get_state(s, after, len), SDAE_OK);
  ck_assert_mem_eq(after, before, len);
  ck_assert_mem_eq(q, q0, n_q * sizeof *q);
  ck_assert_mem_eq(v, v0, n_q * sizeof *v);
  ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->step.steps, steps);
  if (had_chart) {
    ck_assert_int_eq(sdae_mbs_chart(s, dep), SDAE_OK);
    ck_assert_mem_eq(dep, dep0, sizeof dep);
  }
  ck_assert_str_ne(sdae_strerror(want), "");
}
