/* sdae_check_model: the oscillator's normal form against its DAE (paper Section IV, m = 1):
 * x = (X, Y, Xdot, Ydot), f = (Xdot, Ydot, -k X^3 - d Xdot, -ga), g = (0, 0, 0, -1), h = Y,
 * Phi = (Y, Ydot, X + Y, Y + Xdot) (eq. 21). */
#include <math.h>

#include "testmodels.h"

typedef struct dae_params {
  quartic q;
  double ga;
  int wrong_inverse; /* Phi^-1 forgets the -xi1 in X */
  int wrong_mu;      /* mu2 = Y + Xdot + Ydot: L_g mu2 = -1, not 0 */
} dae_params;

static int f(double t, const double *x, double *out, void *params) {
  const dae_params *p = params;
  (void)t;
  out[0] = x[2], out[1] = x[3];
  out[2] = -p->q.k * x[0] * x[0] * x[0] - p->q.d * x[2];
  out[3] = -p->ga;
  return 0;
}

static int g(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 0.0, out[1] = 0.0, out[2] = 0.0, out[3] = -1.0;
  return 0;
}

static int Phi(double t, const double *x, double *z, void *params) {
  const dae_params *p = params;
  (void)t;
  z[0] = x[1], z[1] = x[3], z[2] = x[0] + x[1], z[3] = x[1] + x[2] + (p->wrong_mu ? x[3] : 0.0);
  return 0;
}

static int Phi_inv(double t, const double *z, double *x, void *params) {
  const dae_params *p = params;
  (void)t;
  x[0] = z[2] - (p->wrong_inverse ? 0.0 : z[0]), x[1] = z[0];
  x[2] = z[3] - z[0] - (p->wrong_mu ? z[1] : 0.0), x[3] = z[1];
  return 0;
}

static const double LO[4] = {-0.7, -1.0, -0.9, -0.9}, HI[4] = {0.7, 1.0, 0.9, 0.9};

static sdae_check_report check(dae_params *p, int with_inverse) {
  sdae_model m = quartic_model(&p->q);
  sdae_dae d = {4, 1, f, g, Phi, with_inverse ? Phi_inv : NULL, NULL, p};
  sdae_check_report r = {0};
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 200, 7, 1e-6, NULL, &r), SDAE_OK);
  ck_assert_uint_eq(r.points, 200);
  return r;
}

START_TEST(corrected_Q_is_consistent) {
  for (int inv = 0; inv < 2; inv++) {
    dae_params p = {{2.0, 0.03, 0, 0}, 9.81, 0, 0};
    sdae_check_report r = check(&p, inv);
    ck_assert_int_eq(r.consistent, 1);
    for (int k = 0; k < 4; k++) ck_assert_double_le(r.residual[k], 1e-8);
  }
}
END_TEST

/* The printed Q differs from the true one by O(1) over the box. */
START_TEST(printed_Q_is_flagged) {
  dae_params p = {{2.0, 0.03, 0, 1}, 9.81, 0, 0};
  double worst[4];
  sdae_model m = quartic_model(&p.q);
  sdae_dae d = {4, 1, f, g, Phi, Phi_inv, NULL, &p};
  sdae_check_report r;
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 200, 7, 1e-6, worst, &r), SDAE_OK);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_int_eq(r.worst_check, SDAE_CHECK_DYNAMICS);
  ck_assert_uint_eq(r.worst_index, 3); /* mu2 */
  ck_assert_double_gt(r.residual[SDAE_CHECK_DYNAMICS], 1e-2);
  ck_assert_double_le(r.residual[SDAE_CHECK_INVERSE], 1e-12);
  for (int j = 0; j < 4; j++) {
    ck_assert_double_ge(worst[j], LO[j]);
    ck_assert_double_le(worst[j], HI[j]);
  }
}
END_TEST

START_TEST(wrong_inverse_is_flagged) {
  dae_params p = {{2.0, 0.03, 0, 0}, 9.81, 1, 0};
  sdae_check_report r = check(&p, 1);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_double_gt(r.residual[SDAE_CHECK_INVERSE], 1e-3);
}
END_TEST

START_TEST(coordinate_with_Lg_is_flagged) {
  dae_params p = {{2.0, 0.03, 0, 0}, 9.81, 0, 1};
  sdae_check_report r = check(&p, 1);
  ck_assert_int_eq(r.consistent, 0);
  ck_assert_double_gt(r.residual[SDAE_CHECK_LG], 0.5);
  ck_assert_double_le(r.residual[SDAE_CHECK_INVERSE], 1e-12);
}
END_TEST

START_TEST(bad_arguments) {
  dae_params p = {{2.0, 0.03, 0, 0}, 9.81, 0, 0};
  sdae_model m = quartic_model(&p.q);
  sdae_dae d = {4, 1, f, g, Phi, Phi_inv, NULL, &p};
  sdae_check_report r = {0};
  double hi[4] = {0.7, 1.0, -1.0, 0.9};
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, hi, 10, 1, 1e-6, NULL, &r), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 10, 1, 0.0, NULL, &r), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_check_model(&m, NULL, 0.0, LO, HI, 10, 1, 1e-6, NULL, &r), SDAE_ERR_NULL);
  d.n = 5;
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 10, 1, 1e-6, NULL, &r), SDAE_ERR_DIM);
}
END_TEST

int main(void) {
  Suite *s = suite_create("model");
  ADD_CASE(s, corrected_Q_is_consistent);
  ADD_CASE(s, printed_Q_is_flagged);
  ADD_CASE(s, wrong_inverse_is_flagged);
  ADD_CASE(s, coordinate_with_Lg_is_flagged);
  ADD_CASE(s, bad_arguments);
  return run_suite(s);
}
