/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The diagnostics against numbers worked out by hand: the left side of condition (17) along a
 * trajectory, sdae_certify_box's sup of -k_i over a box (through the public API only: its
 * search is being rewritten, the sup it must find is not), and sdae_check_model's inversion of
 * a nonlinear Phi by Newton. */
#include <float.h>
#include <math.h>

#include "testmodels.h"

/* ---- condition (17) ---- */

static int half_square(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  out[0] = 0.5 * (mu[0] * mu[0] + mu[1] * mu[1]);
  return 0;
}

static void observe(sdae_cond18 *c, size_t step, double t, double m0, double m1) {
  double mu[2] = {m0, m1}, xi[1] = {0.0};
  ck_assert_int_eq(sdae_cond18_observe(step, t, xi, mu, c), 0);
}

/* Paper eq. 17: (1/(n - r) sum_{i=1}^{n-r} (W(mu+) - W(mu)) / (mu_i+ - mu_i))^2 / W(mu), here
 * n - r = n_mu = 2 and W = |mu|^2/2. A component that does not move has no quotient; in (16),
 * of which (17) is the companion, its term is multiplied by phi_T,i = (mu_i+ - mu_i)/T = 0, so
 * it contributes 0 while the divisor stays n - r (the paper's normalisation, as the code
 * divides; its comment's "mean over the components that moved" misreads it).
 *   (1, 2) -> (1, 3), T = 1/2: W 2.5 -> 5, dW = 2.5; only mu_2 moved, by 1: (2.5/2)^2/2.5
 *     = 0.625 (a divisor of 1 would give 2.5); (18)'s ratio dW/(T W) = 2.
 *   (1, 3) -> (1, 3 - 1/4): W decreases, 5 -> 4.28125: (17) = ((-0.71875/-0.25)/2)^2/5
 *     = 0.4133, below 0.625; ratio -0.2875. */
START_TEST(cond17_divides_by_n_mu) {
  sdae_cond18 c;
  double prev[2];
  ck_assert_int_eq(sdae_cond18_init(&c, 2, half_square, NULL, prev), SDAE_OK);
  observe(&c, 0, 0.0, 1.0, 2.0);
  observe(&c, 1, 0.5, 1.0, 3.0);
  observe(&c, 2, 1.0, 1.0, 2.75);
  ck_assert_uint_eq(c.steps, 2);
  ck_assert_double_le(fabs(c.sup17 - 0.625), 2 * DBL_EPSILON);
  ck_assert_double_le(fabs(c.gamma_min - 2.0), 2 * DBL_EPSILON);
  ck_assert_double_eq(c.worst_t, 0.0); /* the start of the step that attained it */
}
END_TEST

/* Both components moving, (1, 2) -> (2, 4), T = 1/2: dW = 10 - 2.5 = 7.5, quotients 7.5/1 and
 * 7.5/2, mean 5.625, (17) = 5.625^2/2.5 = 12.65625; (18) 7.5/(0.5 2.5) = 6. A state with
 * W = 0 is skipped (the ratio is undefined there), and the step after it too. */
START_TEST(cond17_both_components_and_zero_W) {
  sdae_cond18 c;
  double prev[2];
  ck_assert_int_eq(sdae_cond18_init(&c, 2, half_square, NULL, prev), SDAE_OK);
  observe(&c, 0, 0.0, 0.0, 0.0);
  observe(&c, 1, 0.5, 1.0, 2.0);
  observe(&c, 2, 1.0, 2.0, 4.0);
  ck_assert_uint_eq(c.steps, 1);
  ck_assert_double_le(fabs(c.sup17 - 12.65625), 4 * DBL_EPSILON * 12.65625);
  ck_assert_double_le(fabs(c.gamma_min - 6.0), 4 * DBL_EPSILON * 6.0);
  ck_assert_double_eq(c.worst_t, 0.5);
}
END_TEST

/* W(t, mu) = (1 + t) |mu|^2 / 2: a time-dependent W. From t = 1 (not 0, so that T = t - t_prev
 * and t + t_prev differ): (1, 1) at t = 1, W = 2 -> (1, 2) at t = 3/2, W = 5/2 5/2 = 25/4.
 * T = 1/2, dW = 17/4: (18)'s ratio dW/(T W) = 17/4; only mu_2 moved, by 1: (17) =
 * ((17/4)/2)^2 / 2 = 289/128. All dyadic: exact. */
static int timed_half_square(double t, const double *mu, double *out, void *params) {
  (void)params;
  out[0] = (1.0 + t) * 0.5 * (mu[0] * mu[0] + mu[1] * mu[1]);
  return 0;
}

START_TEST(cond18_time_dependent_W) {
  sdae_cond18 c;
  double prev[2];
  ck_assert_int_eq(sdae_cond18_init(&c, 2, timed_half_square, NULL, prev), SDAE_OK);
  observe(&c, 0, 1.0, 1.0, 1.0);
  observe(&c, 1, 1.5, 1.0, 2.0);
  ck_assert_uint_eq(c.steps, 1);
  ck_assert_double_eq(c.gamma_min, 17.0 / 4.0);
  ck_assert_double_eq(c.sup17, 289.0 / 128.0);
  ck_assert_double_eq(c.worst_t, 1.0);
  ck_assert_int_eq(c.status, SDAE_OK);
}
END_TEST

/* W = mu_1 + mu_2, linear: (1, 0) at t = 0 (W = 1) -> (2, 0) at t = 1 (W = 2) -> (4, 0) at
 * t = 2 (W = 4). Both steps have ratio dW/(T W) = 1: gamma_min = 1, attained first on the step
 * from t = 0. (17): (1/1 / 2)^2 / 1 = 1/4, then (2/2 / 2)^2 / 2 = 1/8: sup 1/4. W(mu) = 1 is a
 * measured step like any W > 0. */
static int linear_W(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  out[0] = mu[0] + mu[1];
  return 0;
}

START_TEST(cond18_ties_keep_first_time) {
  sdae_cond18 c;
  double prev[2];
  ck_assert_int_eq(sdae_cond18_init(&c, 2, linear_W, NULL, prev), SDAE_OK);
  observe(&c, 0, 0.0, 1.0, 0.0);
  observe(&c, 1, 1.0, 2.0, 0.0);
  observe(&c, 2, 2.0, 4.0, 0.0);
  ck_assert_uint_eq(c.steps, 2);
  ck_assert_double_eq(c.gamma_min, 1.0);
  ck_assert_double_eq(c.worst_t, 0.0);
  ck_assert_double_eq(c.sup17, 0.25);
}
END_TEST

/* T <= 0 (the same time again, or back in time) has no ratio: skipped, nothing measured; the
 * next step measures from the latest observation. (1, 0) at t = 1, again at t = 1, then at
 * t = 0.5, then (2, 0) at t = 1.5: one step, T = 1, W 1 -> 2: ratio 1, (17) 1/4. */
START_TEST(cond18_nonpositive_T_skipped) {
  sdae_cond18 c;
  double prev[2];
  ck_assert_int_eq(sdae_cond18_init(&c, 2, linear_W, NULL, prev), SDAE_OK);
  observe(&c, 0, 1.0, 1.0, 0.0);
  observe(&c, 1, 1.0, 1.0, 0.0);
  observe(&c, 2, 0.5, 1.0, 0.0);
  ck_assert_uint_eq(c.steps, 0);
  ck_assert_double_eq(c.gamma_min, -INFINITY);
  ck_assert_double_eq(c.sup17, 0.0);
  observe(&c, 3, 1.5, 2.0, 0.0);
  ck_assert_uint_eq(c.steps, 1);
  ck_assert_double_eq(c.gamma_min, 1.0);
  ck_assert_double_eq(c.worst_t, 0.5);
  ck_assert_double_eq(c.sup17, 0.25);
}
END_TEST

/* W's failures: the observer returns 1 (stop) and keeps the status: < 0 fatal and > 0
 * recoverable even when W also wrote a NaN, a NaN or Inf written with success non-finite;
 * the step is not measured. */
typedef struct w_fail {
  int rc;
  double value;
} w_fail;
static int failing_W(double t, const double *mu, double *out, void *params) {
  const w_fail *f = params;
  (void)t, (void)mu;
  out[0] = f->value;
  return f->rc;
}

START_TEST(cond18_W_failures) {
  const w_fail fails[4] = {{-1, NAN}, {1, NAN}, {0, NAN}, {0, INFINITY}};
  const int want[4] = {SDAE_ERR_CALLBACK_FATAL, SDAE_ERR_CALLBACK_RECOVERABLE, SDAE_ERR_NONFINITE,
                       SDAE_ERR_NONFINITE};
  for (int k = 0; k < 4; k++) {
    sdae_cond18 c;
    double prev[2], mu[2] = {1.0, 2.0}, xi[1] = {0.0};
    w_fail f = {0, 1.0};
    ck_assert_int_eq(sdae_cond18_init(&c, 2, failing_W, &f, prev), SDAE_OK);
    ck_assert_int_eq(sdae_cond18_observe(0, 0.0, xi, mu, &c), 0);
    f = fails[k];
    ck_assert_int_eq(sdae_cond18_observe(1, 1.0, xi, mu, &c), 1);
    ck_assert_int_eq(c.status, want[k]);
    ck_assert_uint_eq(c.steps, 0);
  }
}
END_TEST

/* init: NULL pointers and n_mu = 0 refused; n_mu = 1 is a mean over one component:
 * W = mu_1, (2) -> (3) with T = 1: ratio 1/(1 2) = 1/2, (17) = (1/1)^2 / 2 = 1/2. */
static int first_W(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  out[0] = mu[0];
  return 0;
}

START_TEST(cond18_init_arguments) {
  sdae_cond18 c;
  double prev[2], xi[1] = {0.0}, a[1] = {2.0}, b[1] = {3.0};
  ck_assert_int_eq(sdae_cond18_init(NULL, 2, linear_W, NULL, prev), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_cond18_init(&c, 2, NULL, NULL, prev), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_cond18_init(&c, 2, linear_W, NULL, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_cond18_init(&c, 0, linear_W, NULL, prev), SDAE_ERR_DIM);
  ck_assert_int_eq(sdae_cond18_init(&c, 1, first_W, NULL, prev), SDAE_OK);
  ck_assert_int_eq(sdae_cond18_observe(0, 0.0, xi, a, &c), 0);
  ck_assert_int_eq(sdae_cond18_observe(1, 1.0, xi, b, &c), 0);
  ck_assert_uint_eq(c.steps, 1);
  ck_assert_double_eq(c.gamma_min, 0.5);
  ck_assert_double_eq(c.sup17, 0.5);
}
END_TEST

/* ---- sdae_certify_box ---- */

/* A model whose only gain is ours to choose: Q_apply returns ||q_1||^2 = g(xi, mu), so with
 * delta = epsilon = 1, -k_1 = g/2 + 1 (eq. 6). q0 plays no part. */
typedef double (*shape)(const double *z);
static shape current;

static int zero_q0(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  out[0] = 0.0 * mu[0];
  return 0;
}

static int shaped_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                          void *params) {
  size_t n_mu = *(const size_t *)params;
  double z[8];
  (void)t;
  z[0] = xi[0];
  for (size_t i = 0; i < n_mu; i++) z[1 + i] = mu[i], Qxi[i] = 0.0;
  qnorm2[0] = current(z);
  return 0;
}

/* 4/(1 + (z - c)^T A (z - c)), A positive definite: sup 4 at c, inside the box [-1, 1]^4 and
 * off every grid point of a 4-point grid (-1, -1/3, 1/3, 1); -k_1 = 4/2 + 1 = 3 there. */
static const double centre[4] = {0.3, -0.4, 0.15, 0.55};
static double interior_peak(const double *z) {
  static const double A[16] = {2.0, 0.5, 0.0, 0.0, 0.5, 1.0, 0.3, 0.0,
                               0.0, 0.3, 1.5, 0.2, 0.0, 0.0, 0.2, 1.0};
  double q = 0.0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) q += (z[i] - centre[i]) * A[i * 4 + j] * (z[j] - centre[j]);
  return 4.0 / (1.0 + q);
}

/* sup over the box; checks what holds whatever the search: the argmax lies in the box and
 * -k_1 there is the reported sup (it cannot exceed the true one), at least one evaluation per
 * grid point was spent (grid^n_free), and T_bar = 2/sup (eq. 14) */
static sdae_certificate certify(shape g, size_t n_mu, const double *lo, const double *hi,
                                unsigned grid, size_t n_free, double *argmax) {
  sdae_model m = {
      .n_xi = 1, .n_mu = n_mu, .q0 = zero_q0, .Q_apply = shaped_Q_apply, .params = &n_mu};
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  sdae_certificate c;
  double sup[1], k[1];
  current = g;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, grid, sup, argmax, &c), SDAE_OK);
  for (size_t j = 0; j < 1 + n_mu; j++) {
    ck_assert_double_ge(argmax[j], lo[j]);
    ck_assert_double_le(argmax[j], hi[j]);
  }
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, argmax, argmax + 1, k), SDAE_OK);
  ck_assert_double_eq(-k[0], c.sup_neg_k);
  ck_assert_double_eq(sup[0], c.sup_neg_k);
  ck_assert_double_ge((double)c.evaluations, pow(grid, (double)n_free));
  ck_assert_double_le(fabs(c.T_bar - 2.0 / c.sup_neg_k), DBL_EPSILON * c.T_bar);
  sdae_stepper_free(s);
  return c;
}

/* Four free coordinates, the sup 3 at the interior point c: to 1e-8, c to 1e-3 (the peak's
 * curvature, the eigenvalues of 8 A near c, puts a 1e-8 value error within 1e-4 of it). */
START_TEST(certify_interior_sup_in_4d) {
  double lo[4] = {-1, -1, -1, -1}, hi[4] = {1, 1, 1, 1}, argmax[4];
  sdae_certificate c = certify(interior_peak, 3, lo, hi, 4, 4, argmax);
  ck_assert_double_le(c.sup_neg_k, 3.0 + 4 * DBL_EPSILON);
  ck_assert_double_ge(c.sup_neg_k, 3.0 - 1e-8);
  for (int j = 0; j < 4; j++) ck_assert_double_le(fabs(argmax[j] - centre[j]), 1e-3);
}
END_TEST

/* A box that is a point: nothing to search, the sup is the value there (g = 4/(1 + q), q at
 * the corner (1, 1, 1, 1) by hand: d = (0.7, 1.4, 0.85, 0.45), q = d^T A d = 6.07325,
 * -k = 2/(1 + q) + 1), after at least one evaluation (grid^0). */
/* h (1 - ((x - c)/w)^2)^2 on |x - c| < w, 0 outside: C1, maximum h at c */
static double bump(double x, double c, double w, double h) {
  double u = (x - c) / w;
  return fabs(u) < 1.0 ? h * (1.0 - u * u) * (1.0 - u * u) : 0.0;
}

/* mu in [0, 1]: a broad bump of height 1 at 0.25 and a narrow one of 1.5 at 0.6. The 5-point
 * grid (0, 0.25, 0.5, 0.75, 1) sees 1 at 0.25 (the lower peak is its best point) and only
 * 1.5 (1 - (0.1/0.15)^2)^2 = 0.463 at 0.5, on the higher one's slope: the sup -k_1 = 1.5/2 + 1
 * = 1.75 at mu = 0.6 is for the refinement from the second-best point to find. */
static double two_peaks(const double *z) {
  return bump(z[1], 0.25, 0.2, 1.0) + bump(z[1], 0.6, 0.15, 1.5);
}

START_TEST(certify_finds_higher_of_two_peaks) {
  double lo[2] = {0.0, 0.0}, hi[2] = {0.0, 1.0}, argmax[2];
  sdae_certificate c = certify(two_peaks, 1, lo, hi, 5, 1, argmax);
  ck_assert_double_le(fabs(c.sup_neg_k - 1.75), 1e-8); /* the value is second order in mu */
  ck_assert_double_le(fabs(argmax[1] - 0.6), 1e-4);
}
END_TEST

START_TEST(certify_point_box) {
  double lo[4] = {1, 1, 1, 1}, argmax[4];
  sdae_certificate c = certify(interior_peak, 3, lo, lo, 3, 0, argmax);
  ck_assert_double_le(fabs(c.sup_neg_k - (2.0 / (1.0 + 6.07325) + 1.0)), 1e-14);
}
END_TEST

/* ---- sdae_check_model: Phi^-1 by Newton ---- */

/* A DAE of n = 2 with a nonlinear Phi: f = (x2, -x1), g = (1, 0), h = x1 + x2^2 (relative
 * degree 1), mu = sinh(x2) (L_g mu = 0). Phi^-1(xi, mu) = (xi - asinh(mu)^2, asinh(mu)), and
 * L_f mu = cosh(x2)(-x1) gives the normal form q0 = sqrt(1 + mu^2) asinh(mu)^2,
 * Q = [-sqrt(1 + mu^2)]. Newton from x = z needs several iterations (sinh is not linear), so
 * an inversion stopped early leaves Phi(x) - z far from 0. */
static int dae_f(double t, const double *x, double *out, void *p) {
  (void)t, (void)p;
  out[0] = x[1], out[1] = -x[0];
  return 0;
}
static int dae_g(double t, const double *x, double *out, void *p) {
  (void)t, (void)x, (void)p;
  out[0] = 1.0, out[1] = 0.0;
  return 0;
}
static int dae_Phi(double t, const double *x, double *z, void *p) {
  (void)t, (void)p;
  z[0] = x[0] + x[1] * x[1], z[1] = sinh(x[1]);
  return 0;
}
static int dae_Phi_inv(double t, const double *z, double *x, void *p) {
  (void)t, (void)p;
  x[1] = asinh(z[1]), x[0] = z[0] - x[1] * x[1];
  return 0;
}
static int nf_q0(double t, const double *mu, double *out, void *p) {
  double a = asinh(mu[0]);
  (void)t, (void)p;
  out[0] = sqrt(1.0 + mu[0] * mu[0]) * a * a;
  return 0;
}
static int nf_Q(double t, const double *xi, const double *mu, double *out, void *p) {
  (void)t, (void)xi, (void)p;
  out[0] = -sqrt(1.0 + mu[0] * mu[0]);
  return 0;
}

static sdae_check_report check_sinh(int with_inverse) {
  static const unsigned rel1[1] = {1};
  sdae_model m = {
      .n_xi = 1, .n_mu = 1, .q0 = nf_q0, .Q = nf_Q, .n_constraints = 1, .rel_degree = rel1};
  sdae_dae d = {2, 1, dae_f, dae_g, dae_Phi, with_inverse ? dae_Phi_inv : NULL, NULL, NULL};
  const double lo[2] = {-1.0, -2.0}, hi[2] = {1.0, 2.0};
  sdae_check_report r = {0};
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, lo, hi, 100, 3, 1e-6, NULL, &r), SDAE_OK);
  ck_assert_uint_eq(r.points, 100);
  return r;
}

/* Newton's inverse: Phi(x) = z to rounding (it stops at an update of 1e-15 (1 + |x|), after
 * quadratic convergence), and the dynamics then agree to the finite-difference Jacobian's
 * accuracy (about 1e-10 relative); the same with the closed-form inverse. */
START_TEST(check_model_inverts_nonlinear_Phi) {
  for (int inv = 0; inv < 2; inv++) {
    sdae_check_report r = check_sinh(inv);
    ck_assert_int_eq(r.consistent, 1);
    ck_assert_double_le(r.residual[SDAE_CHECK_INVERSE], 1e-14);
    ck_assert_double_le(r.residual[SDAE_CHECK_LG], 1e-8);
    ck_assert_double_le(r.residual[SDAE_CHECK_DYNAMICS], 1e-8);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("diagnostics");
  ADD_CASE(s, cond17_divides_by_n_mu);
  ADD_CASE(s, cond17_both_components_and_zero_W);
  ADD_CASE(s, cond18_time_dependent_W);
  ADD_CASE(s, cond18_ties_keep_first_time);
  ADD_CASE(s, cond18_nonpositive_T_skipped);
  ADD_CASE(s, cond18_W_failures);
  ADD_CASE(s, cond18_init_arguments);
  ADD_CASE(s, certify_interior_sup_in_4d);
  ADD_CASE(s, certify_finds_higher_of_two_peaks);
  ADD_CASE(s, certify_point_box);
  ADD_CASE(s, check_model_inverts_nonlinear_Phi);
  return run_suite(s);
}
