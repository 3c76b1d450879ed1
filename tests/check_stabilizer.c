/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The xi update: gains (eq. 6), scheme 15's contraction for any T (Theorem 4), scheme 11's
 * step bound (Theorem 3), and the index-reduction and Baumgarte baselines. */
#include <math.h>

#include "testmodels.h"

/* Two constraints of relative degree 1, n_mu = 3, and a Q whose columns are hand-computable:
 * Q = [[mu1, xi2], [2, mu2 xi1], [0, 3]]. */
static int two_q0(double t, const double *mu, double *out, void *params) {
  (void)t;
  (void)params;
  out[0] = mu[1];
  out[1] = -mu[0];
  out[2] = 0.0;
  return 0;
}

static int two_Q(double t, const double *xi, const double *mu, double *out, void *params) {
  (void)t;
  (void)params;
  out[0] = mu[0], out[1] = xi[1];
  out[2] = 2.0, out[3] = mu[1] * xi[0];
  out[4] = 0.0, out[5] = 3.0;
  return 0;
}

/* The same Q given as its product with xi and its column norms. */
static int two_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                       void *params) {
  double Q[6];
  two_Q(t, xi, mu, Q, params);
  for (int r = 0; r < 3; r++) Qxi[r] = Q[2 * r] * xi[0] + Q[2 * r + 1] * xi[1];
  qnorm2[0] = Q[0] * Q[0] + Q[2] * Q[2] + Q[4] * Q[4];
  qnorm2[1] = Q[1] * Q[1] + Q[3] * Q[3] + Q[5] * Q[5];
  return 0;
}

static sdae_model two_model(int apply) {
  sdae_model m = {0};
  m.n_xi = 2;
  m.n_mu = 3;
  m.q0 = two_q0;
  if (apply)
    m.Q_apply = two_Q_apply;
  else
    m.Q = two_Q;
  return m;
}

static sdae_options two_options(sdae_scheme scheme) {
  sdae_options o;
  sdae_options_default(&o);
  o.scheme = scheme;
  o.delta = 2.0;
  o.epsilon = 0.5;
  return o;
}

/* At xi = (0.5, -1), mu = (1, 2, 3): q_1 = (1, 2, 0), q_2 = (-1, 1, 3), so ||q_1||^2 = 5,
 * ||q_2||^2 = 11 and with delta = 2, epsilon = 0.5: k = (-2*5 - 0.5, -2*11 - 0.5). */
static const double XI0[2] = {0.5, -1.0}, MU0[3] = {1.0, 2.0, 3.0}, K_HAND[2] = {-10.5, -22.5};

START_TEST(gains_eq6_two_constraints) {
  for (int apply = 0; apply < 2; apply++) {
    sdae_model m = two_model(apply);
    sdae_options o = two_options(SDAE_SCHEME_SEMI_IMPLICIT);
    sdae_stepper *s;
    double k[2];
    ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
    ck_assert_int_eq(sdae_stepper_gains(s, 0.0, XI0, MU0, k), SDAE_OK);
    ck_assert_double_eq(k[0], K_HAND[0]);
    ck_assert_double_eq(k[1], K_HAND[1]);
    sdae_stepper_free(s);
  }
}
END_TEST

/* Theorem 4: xi_i+ = xi_i / (1 - T k_i) for every T, however large. */
START_TEST(scheme15_contracts_for_any_T) {
  const double Ts[3] = {1e-3, 1.0, 1e3};
  for (int apply = 0; apply < 2; apply++)
    for (int j = 0; j < 3; j++) {
      sdae_model m = two_model(apply);
      sdae_options o = two_options(SDAE_SCHEME_SEMI_IMPLICIT);
      sdae_stepper *s;
      double xi[2] = {XI0[0], XI0[1]}, mu[3] = {MU0[0], MU0[1], MU0[2]};
      ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
      ck_assert_int_eq(sdae_step(s, 0.0, Ts[j], xi, mu), SDAE_OK);
      for (int i = 0; i < 2; i++) {
        double factor = 1.0 / (1.0 - Ts[j] * K_HAND[i]);
        ck_assert_double_le(rel_diff(xi[i], XI0[i] * factor), 4e-16);
        ck_assert_double_lt(fabs(xi[i]), fabs(XI0[i]));
      }
      /* mu+ = mu + T (q0(mu) + Q xi) with the explicit map (eq. 15, mu row) */
      double Qxi[3] = {1.0 * 0.5 + -1.0 * -1.0, 2.0 * 0.5 + 1.0 * -1.0, 3.0 * -1.0};
      double q0[3] = {2.0, -1.0, 0.0};
      for (int r = 0; r < 3; r++)
        ck_assert_double_le(rel_diff(mu[r], MU0[r] + Ts[j] * (q0[r] + Qxi[r])), 4e-16);
      sdae_stepper_free(s);
    }
}
END_TEST

/* A constant-gain model: Q = [[2, 0], [0, 0]] gives k_1 = -(1/2)*4 - 1 = -3 with delta =
 * epsilon = 1, so Theorem 3's bound is T < 2/3. Scheme 11 multiplies xi_1 by (1 + T k_1). */

static double scheme11_after(double T, int n) {
  quartic p = {0.0, 0.0, 0, 0}; /* linear q0: mu stays bounded over the run */
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_EXPLICIT);
  sdae_stepper *s;
  double xi[2] = {1.0, 0.0}, mu[2] = {0.0, 0.0};
  m.Q = quartic_const_Q;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, T, (size_t)n, 1, xi, mu, NULL, NULL, NULL), SDAE_OK);
  sdae_stepper_free(s);
  return xi[0];
}

START_TEST(scheme11_bound_of_theorem3) {
  const double k = -3.0, Tbar = 2.0 / -k;
  const int n = 200;
  double below = scheme11_after(0.99 * Tbar, n), above = scheme11_after(1.01 * Tbar, n);
  ck_assert_double_le(rel_diff(below, pow(1.0 + 0.99 * Tbar * k, n)), 1e-12);
  ck_assert_double_le(rel_diff(above, pow(1.0 + 1.01 * Tbar * k, n)), 1e-12);
  ck_assert_double_lt(fabs(below), 0.02); /* 0.98^200 */
  ck_assert_double_gt(fabs(above), 50.0); /* 1.02^200 */
}
END_TEST

/* Index reduction integrates xi1' = xi2, xi2' = 0: xi1(t) = xi1(0) + t xi2(0), the drift. */
START_TEST(none_drifts_linearly) {
  const sdae_scheme schemes[2] = {SDAE_SCHEME_EXPLICIT, SDAE_SCHEME_SEMI_IMPLICIT};
  for (int j = 0; j < 2; j++) {
    quartic p = {1.0, 0.0, 0, 0};
    sdae_model m = quartic_model(&p);
    sdae_options o = quartic_options(sdae_map_euler, schemes[j]);
    sdae_stepper *s;
    double xi[2] = {0.1, 0.3}, mu[2] = {0.2, 0.0}, T = 1e-3;
    o.stabilizer = SDAE_STAB_NONE;
    ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
    ck_assert_int_eq(sdae_integrate(s, 0.0, T, 5000, 1, xi, mu, NULL, NULL, NULL), SDAE_OK);
    ck_assert_double_le(rel_diff(xi[0], 0.1 + 5.0 * 0.3), 1e-12);
    ck_assert_double_eq(xi[1], 0.3);
    sdae_stepper_free(s);
  }
}
END_TEST

/* Baumgarte with alpha = (1, 2): xi1'' = -xi1 - 2 xi1', exact xi1 = (a + (b + a) t) e^-t.
 * The discretization is first order: the error at t = 5 halves with T. */
static double baumgarte_error(sdae_scheme scheme, double T) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, scheme);
  sdae_stepper *s;
  double a = 0.1, b = 0.3, xi[2] = {a, b}, mu[2] = {0.2, 0.0}, t = 5.0;
  o.stabilizer = SDAE_STAB_BAUMGARTE;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, T, (size_t)lround(t / T), 1, xi, mu, NULL, NULL, NULL),
                   SDAE_OK);
  sdae_stepper_free(s);
  return fabs(xi[0] - (a + (b + a) * t) * exp(-t));
}

START_TEST(baumgarte_decays_with_order_1) {
  const sdae_scheme schemes[2] = {SDAE_SCHEME_EXPLICIT, SDAE_SCHEME_SEMI_IMPLICIT};
  for (int j = 0; j < 2; j++) {
    double e1 = baumgarte_error(schemes[j], 1e-3), e2 = baumgarte_error(schemes[j], 5e-4);
    double exact = (0.1 + 0.4 * 5.0) * exp(-5.0);
    ck_assert_double_lt(e1, 0.01 * exact);
    ck_assert_double_gt(e1 / e2, 1.9);
    ck_assert_double_lt(e1 / e2, 2.1);
  }
}
END_TEST

/* The paper's stabilizer on the oscillator: after each step of scheme 15 every |xi_i| has
 * shrunk exactly by 1/(1 - T k_i) with the gains at the step's start. */
START_TEST(paper_stabilizer_factor_along_run) {
  quartic p = {2.0, 0.03, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.6, 0.0}, mu[2] = {0.7, 0.6}, k[2], T = 0.01;
  o.delta = 2.0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  xi[1] = -0.4;
  for (int n = 0; n < 300; n++) {
    double before[2] = {xi[0], xi[1]};
    ck_assert_int_eq(sdae_stepper_gains(s, n * T, xi, mu, k), SDAE_OK);
    ck_assert_double_eq(k[1], -(4.0 / 2.0) * 2.0 - 1.0); /* ||q_2||^2 = 2 */
    ck_assert_int_eq(sdae_step(s, n * T, T, xi, mu), SDAE_OK);
    for (int i = 0; i < 2; i++)
      ck_assert_double_le(rel_diff(xi[i], before[i] / (1.0 - T * k[i])), 4e-16);
  }
  sdae_stepper_free(s);
}
END_TEST

/* Relative degree 1, the smallest: two constraints {1, 1} on the oscillator (n_xi = 2), each
 * chain the scalar xi_c' = 0 (index reduction) or -alpha_0 xi_c (Baumgarte, alpha_0 = 1). One
 * step of T = 1/4: none keeps xi; Baumgarte's scheme 15 gives xi / (1 + T alpha_0) = 0.8 xi and
 * scheme 11 (1 - T alpha_0) xi = 0.75 xi, each one rounding. */
START_TEST(relative_degree_one_chains) {
  static const unsigned ones[2] = {1, 1};
  const sdae_stabilizer st[3] = {SDAE_STAB_NONE, SDAE_STAB_BAUMGARTE, SDAE_STAB_BAUMGARTE};
  const sdae_scheme sc[3] = {SDAE_SCHEME_SEMI_IMPLICIT, SDAE_SCHEME_SEMI_IMPLICIT,
                             SDAE_SCHEME_EXPLICIT};
  const double T = 0.25;
  for (int k = 0; k < 3; k++) {
    quartic p = {1.0, 0.0, 0, 0};
    sdae_model m = quartic_model(&p);
    sdae_options o = quartic_options(sdae_map_euler, sc[k]);
    sdae_stepper *s;
    double xi[2] = {0.1, -0.3}, mu[2] = {0.2, 0.0}, want[2];
    m.n_constraints = 2, m.rel_degree = ones;
    o.stabilizer = st[k];
    ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
    for (int i = 0; i < 2; i++)
      want[i] = k == 0 ? xi[i] : k == 1 ? xi[i] / (1.0 + T * 1.0) : (1.0 - T * 1.0) * xi[i];
    ck_assert_int_eq(sdae_step(s, 0.0, T, xi, mu), SDAE_OK);
    for (int i = 0; i < 2; i++) ck_assert_double_le(fabs(xi[i] - want[i]), 2e-16 * fabs(want[i]));
    sdae_stepper_free(s);
  }
}
END_TEST

/* delta = 1e200: delta^2 / 2 = 5e399 overflows, so the gains of eq. 6 are -inf, which no step
 * can use. Both schemes say so (SDAE_ERR_NONFINITE), xi and mu left as they were: scheme 15
 * must not turn xi / (1 - T k) = xi / inf into a silent 0. */
START_TEST(overflowing_gains_refused_by_both_schemes) {
  const sdae_scheme schemes[2] = {SDAE_SCHEME_EXPLICIT, SDAE_SCHEME_SEMI_IMPLICIT};
  for (int apply = 0; apply < 2; apply++)
    for (int j = 0; j < 2; j++) {
      sdae_model m = two_model(apply);
      sdae_options o = two_options(schemes[j]);
      sdae_stepper *s;
      double xi[2] = {XI0[0], XI0[1]}, mu[3] = {MU0[0], MU0[1], MU0[2]};
      o.delta = 1e200;
      ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
      ck_assert_int_eq(sdae_step(s, 0.0, 0.01, xi, mu), SDAE_ERR_NONFINITE);
      ck_assert_mem_eq(xi, XI0, sizeof xi);
      ck_assert_mem_eq(mu, MU0, sizeof mu);
      ck_assert_uint_eq(sdae_stepper_stats(s)->steps, 0);
      sdae_stepper_free(s);
    }
}
END_TEST

int main(void) {
  Suite *s = suite_create("stabilizer");
  ADD_CASE(s, gains_eq6_two_constraints);
  ADD_CASE(s, scheme15_contracts_for_any_T);
  ADD_CASE(s, scheme11_bound_of_theorem3);
  ADD_CASE(s, none_drifts_linearly);
  ADD_CASE(s, baumgarte_decays_with_order_1);
  ADD_CASE(s, paper_stabilizer_factor_along_run);
  ADD_CASE(s, relative_degree_one_chains);
  ADD_CASE(s, overflowing_gains_refused_by_both_schemes);
  return run_suite(s);
}
