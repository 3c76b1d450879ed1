/* Newton on R(mu+) = mu+ - mu - T (phi_T + Q xi): quadratic convergence with the analytic
 * Jacobian, the same root with finite differences, and the singular and capped cases. */
#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "testmodels.h"

/* The midpoint map of x'' = -x^3 as a user map that records every mu+ it is called with. */
typedef struct trace {
  quartic q;
  int n;
  double y[64][2];
  int singular; /* the Jacobian callback makes I - T dphi/dmu+ = 0 */
} trace;

static int traced_phi(double t, double T, const double *mu, const double *y, double *out,
                      void *params) {
  trace *tr = params;
  double mid[2] = {0.5 * (mu[0] + y[0]), 0.5 * (mu[1] + y[1])};
  (void)t, (void)T;
  if (tr->n < 64) memcpy(tr->y[tr->n++], y, sizeof tr->y[0]);
  out[0] = mid[1];
  out[1] = -mid[0] * mid[0] * mid[0];
  return 0;
}

static int traced_jac(double t, double T, const double *mu, const double *y, double *out,
                      void *params) {
  trace *tr = params;
  double m0 = 0.5 * (mu[0] + y[0]);
  (void)t;
  if (tr->singular) {
    out[0] = 1.0 / T, out[1] = 0.0, out[2] = 0.0, out[3] = 1.0 / T;
    return 0;
  }
  out[0] = 0.0, out[1] = 0.5, out[2] = -1.5 * m0 * m0, out[3] = 0.0;
  return 0;
}

static int run(trace *tr, int analytic, unsigned max_iter, double T, double *mu, int *status) {
  sdae_model m = quartic_model(&tr->q);
  sdae_options o = quartic_options(sdae_map_user, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.0, 0.0};
  m.params = tr;
  m.user_phi = traced_phi;
  m.user_phi_jac = analytic ? traced_jac : NULL;
  o.newton_max_iter = max_iter;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  *status = sdae_step(s, 0.0, T, xi, mu);
  int iters = (int)sdae_stepper_stats(s)->newton_iters_last;
  sdae_stepper_free(s);
  return iters;
}

/* A large step (T = 0.8 from (1.5, 0.5)) so that the predictor is far from the root: the
 * errors e_k = |y_k - y*| must satisfy e_{k+1} <= C e_k^2. */
START_TEST(quadratic_convergence_analytic) {
  trace tr = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0};
  double mu[2] = {1.5, 0.5};
  int status, iters = run(&tr, 1, 20, 0.8, mu, &status);
  ck_assert_int_eq(status, SDAE_OK);
  ck_assert_int_ge(iters, 3);
  ck_assert_int_le(iters, 8);
  /* tr.y[0] is the predictor's phi(mu, mu); tr.y[1..] the Newton iterates */
  double e[64];
  int n = tr.n - 1;
  for (int k = 0; k < n; k++)
    e[k] = fmax(fabs(tr.y[k + 1][0] - mu[0]), fabs(tr.y[k + 1][1] - mu[1]));
  ck_assert_double_gt(e[0], 1e-2);
  int checked = 0;
  for (int k = 0; k + 1 < n; k++)
    if (e[k] > 1e-7) {
      ck_assert_double_le(e[k + 1], 5.0 * e[k] * e[k]);
      checked++;
    }
  ck_assert_int_ge(checked, 2);
}
END_TEST

START_TEST(finite_differences_same_root) {
  trace ta = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0}, tf = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0};
  double a[2] = {1.5, 0.5}, f[2] = {1.5, 0.5};
  int sa, sf;
  run(&ta, 1, 20, 0.8, a, &sa);
  run(&tf, 0, 20, 0.8, f, &sf);
  ck_assert_int_eq(sa, SDAE_OK);
  ck_assert_int_eq(sf, SDAE_OK);
  ck_assert_double_le(rel_diff(a[0], f[0]), 1e-14);
  ck_assert_double_le(rel_diff(a[1], f[1]), 1e-14);
}
END_TEST

static int gsl_handler_calls;
static void counting_handler(const char *reason, const char *file, int line, int gsl_errno) {
  (void)reason, (void)file, (void)line, (void)gsl_errno;
  gsl_handler_calls++;
}

/* I - T dphi/dmu+ = 0: a named status, the state untouched, GSL's handler never called. */
START_TEST(singular_matrix_is_reported) {
  trace tr = {{1.0, 0.0, 0, 0}, 0, {{0}}, 1};
  double mu[2] = {1.5, 0.5};
  int status;
  gsl_error_handler_t *old = gsl_set_error_handler(counting_handler);
  run(&tr, 1, 20, 0.8, mu, &status);
  gsl_set_error_handler(old);
  ck_assert_int_eq(status, SDAE_ERR_SINGULAR);
  ck_assert_double_eq(mu[0], 1.5);
  ck_assert_double_eq(mu[1], 0.5);
  ck_assert_int_eq(gsl_handler_calls, 0);
}
END_TEST

/* Quadratic convergence from an O(1) start needs more than two iterations at T = 0.8. */
START_TEST(iteration_cap_is_reported) {
  trace tr = {{1.0, 0.0, 0, 0}, 0, {{0}}, 0};
  double mu[2] = {1.5, 0.5};
  int status, iters = run(&tr, 1, 2, 0.8, mu, &status);
  ck_assert_int_eq(status, SDAE_ERR_NEWTON);
  ck_assert_int_eq(iters, 2);
  ck_assert_double_eq(mu[0], 1.5);
  ck_assert_double_eq(mu[1], 0.5);
}
END_TEST

/* Statistics: the totals add up and the last residual is at rounding level. */
START_TEST(statistics_add_up) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.1, 0.0}, mu[2] = {1.0, 0.0};
  unsigned long sum = 0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  for (int n = 0; n < 50; n++) {
    ck_assert_int_eq(sdae_step(s, n * 0.05, 0.05, xi, mu), SDAE_OK);
    sum += sdae_stepper_stats(s)->newton_iters_last;
    ck_assert_double_le(sdae_stepper_stats(s)->newton_residual_last, 1e-8);
  }
  ck_assert_uint_eq(sdae_stepper_stats(s)->newton_iters_total, sum);
  ck_assert_uint_eq(sdae_stepper_stats(s)->steps, 50);
  sdae_stepper_reset_stats(s);
  ck_assert_uint_eq(sdae_stepper_stats(s)->steps, 0);
  sdae_stepper_free(s);
}
END_TEST

/* The LU reads only what the packing writes: a caller's block full of stale huge numbers
 * (the bytes 0x7f make doubles near 1.4e306) gives the same steps, bit for bit, as a zeroed
 * one, through Newton's matrix (midpoint map) and Baumgarte's chain (scheme 15). */
static void steps_in_block(unsigned char fill, sdae_stabilizer stabilizer, double *xi,
                           double *mu) {
  static max_align_t mem[256];
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  o.stabilizer = stabilizer;
  memset(mem, fill, sizeof mem);
  ck_assert_int_eq(sdae_stepper_init(&s, mem, sizeof mem, &m, &o), SDAE_OK);
  for (int n = 0; n < 10; n++) ck_assert_int_eq(sdae_step(s, n * 0.1, 0.1, xi, mu), SDAE_OK);
}

START_TEST(stale_memory_is_never_read) {
  const sdae_stabilizer st[2] = {SDAE_STAB_PAPER, SDAE_STAB_BAUMGARTE};
  for (int i = 0; i < 2; i++) {
    double xi0[2] = {0.1, 0.2}, mu0[2] = {1.0, 0.0}, xi1[2] = {0.1, 0.2}, mu1[2] = {1.0, 0.0};
    steps_in_block(0x00, st[i], xi0, mu0);
    steps_in_block(0x7f, st[i], xi1, mu1);
    ck_assert_int_eq(memcmp(xi0, xi1, sizeof xi0), 0);
    ck_assert_int_eq(memcmp(mu0, mu1, sizeof mu0), 0);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("newton");
  ADD_CASE(s, quadratic_convergence_analytic);
  ADD_CASE(s, finite_differences_same_root);
  ADD_CASE(s, singular_matrix_is_reported);
  ADD_CASE(s, iteration_cap_is_reported);
  ADD_CASE(s, statistics_add_up);
  ADD_CASE(s, stale_memory_is_never_read);
  return run_suite(s);
}
