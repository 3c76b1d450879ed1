/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Failing callbacks: every callback of the model (q0, Q, Q_apply, q0_jac, H, grad_H, S,
 * S_apply, hess_H, user_phi, user_phi_jac), at every call a step makes of it (the predictor,
 * each Newton residual, inside the Jacobian, in every stage of dg4, dg6, rk4 and rk8), fails
 * in each of the three ways of the SUNDIALS rule: returns < 0 -> SDAE_ERR_CALLBACK_FATAL, > 0 ->
 * SDAE_ERR_CALLBACK_RECOVERABLE, writes NaN -> SDAE_ERR_NONFINITE; and the step leaves xi and
 * mu bit for bit as they were. Then the overflows of the gains and of xi under scheme 11. */
#include <math.h>
#include <string.h>

#include "testmodels.h"

enum cb { Q0, QD, Q_APPLY, Q0_JAC, H, GRAD_H, S, S_APPLY, HESS_H, USER_PHI, USER_PHI_JAC, NCB };
static const char *const cb_name[NCB] = {"q0",     "Q",        "Q_apply",     "q0_jac",
                                         "H",      "grad_H",   "S",           "S_apply",
                                         "hess_H", "user_phi", "user_phi_jac"};
enum mode { FATAL, RECOVERABLE, WRITES_NAN, NMODE };
static const int expected[NMODE] = {SDAE_ERR_CALLBACK_FATAL, SDAE_ERR_CALLBACK_RECOVERABLE,
                                    SDAE_ERR_NONFINITE};

/* the fault: callback `which` fails in `mode` at its call number `at` (from 0) of the step;
 * calls[] counts every callback's calls */
static struct {
  int which, mode;
  long at, calls[NCB];
} F = {-1, 0, 0, {0}};

/* counts the call; when it is the faulty one, fails: the status, or NaN in out[0] */
static int fault(int cb, int rc, double *out) {
  long n = F.calls[cb]++;
  if (F.which != cb || n != F.at) return rc;
  if (F.mode == WRITES_NAN) {
    out[0] = NAN;
    return 0;
  }
  return F.mode == FATAL ? -1 : 1;
}

static int f_q0(double t, const double *mu, double *out, void *p) {
  return fault(Q0, rotation_q0(t, mu, out, p), out);
}
static int f_Q(double t, const double *xi, const double *mu, double *out, void *p) {
  return fault(QD, rotation_Q(t, xi, mu, out, p), out);
}
static int f_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qn2,
                     void *p) {
  return fault(Q_APPLY, rotation_Q_apply(t, xi, mu, Qxi, qn2, p), Qxi);
}
static int f_q0_jac(double t, const double *mu, double *out, void *p) {
  return fault(Q0_JAC, rotation_q0_jac(t, mu, out, p), out);
}
static int f_H(double t, const double *mu, double *out, void *p) {
  return fault(H, rotation_H(t, mu, out, p), out);
}
static int f_grad_H(double t, const double *mu, double *out, void *p) {
  return fault(GRAD_H, rotation_grad_H(t, mu, out, p), out);
}
static int f_S(double t, const double *mu, double *out, void *p) {
  return fault(S, rotation_S(t, mu, out, p), out);
}
static int f_S_apply(double t, const double *mu, const double *v, double *out, void *p) {
  return fault(S_APPLY, rotation_S_apply(t, mu, v, out, p), out);
}
static int f_hess_H(double t, const double *mu, double *out, void *p) {
  return fault(HESS_H, rotation_hess_H(t, mu, out, p), out);
}
static int f_user_phi(double t, double T, const double *mu, const double *y, double *out, void *p) {
  return fault(USER_PHI, rotation_user_phi(t, T, mu, y, out, p), out);
}
static int f_user_phi_jac(double t, double T, const double *mu, const double *y, double *out,
                          void *p) {
  return fault(USER_PHI_JAC, rotation_user_phi_jac(t, T, mu, y, out, p), out);
}

/* what a configuration gives besides q0, H, grad_H and user_phi */
enum { WITH_Q_APPLY = 1, WITH_S_APPLY = 2, WITH_Q0_JAC = 4, WITH_HESS_H = 8, WITH_PHI_JAC = 16 };

static sdae_model faulty_model(int with) {
  sdae_model m = {
      .n_xi = 1, .n_mu = 2, .q0 = f_q0, .H = f_H, .grad_H = f_grad_H, .user_phi = f_user_phi};
  if (with & WITH_Q_APPLY)
    m.Q_apply = f_Q_apply;
  else
    m.Q = f_Q;
  if (with & WITH_S_APPLY)
    m.S_apply = f_S_apply;
  else
    m.S = f_S;
  if (with & WITH_Q0_JAC) m.q0_jac = f_q0_jac;
  if (with & WITH_HESS_H) m.hess_H = f_hess_H;
  if (with & WITH_PHI_JAC) m.user_phi_jac = f_user_phi_jac;
  return m;
}

/* a step from a state off the manifold, so that every term is live */
static int step_from(sdae_stepper *s, double *xi, double *mu) {
  xi[0] = 0.3, mu[0] = 0.6, mu[1] = -0.8;
  memset(F.calls, 0, sizeof F.calls);
  return sdae_step(s, 0.5, 0.1, xi, mu);
}

/* Every call of every callback of one configuration, failing each way; returns in injected[]
 * how many faults each callback received. */
static void every_fault(const sdae_map_type *map, sdae_scheme scheme, int with, long *injected) {
  sdae_model m = faulty_model(with);
  sdae_options o = quartic_options(map, scheme);
  sdae_stepper *s;
  double xi[1], mu[2];
  long clean[NCB];
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  F.which = -1;
  ck_assert_int_eq(step_from(s, xi, mu), SDAE_OK);
  memcpy(clean, F.calls, sizeof clean);
  for (int cb = 0; cb < NCB; cb++)
    for (long at = 0; at < clean[cb]; at++)
      for (int mode = 0; mode < NMODE; mode++) {
        F.which = cb, F.mode = mode, F.at = at;
        int rc = step_from(s, xi, mu);
        ck_assert_msg(rc == expected[mode], "%s: %s call %ld mode %d gave %d", sdae_map_name(map),
                      cb_name[cb], at, mode, rc);
        ck_assert_msg(xi[0] == 0.3 && mu[0] == 0.6 && mu[1] == -0.8, "%s: %s moved the state",
                      sdae_map_name(map), cb_name[cb]);
        injected[cb]++;
      }
  F.which = -1;
  sdae_stepper_free(s);
}

static void expect_covered(const long *injected, const int *which, int n) {
  for (int i = 0; i < n; i++)
    ck_assert_msg(injected[which[i]] > 0, "%s never called", cb_name[which[i]]);
}

/* euler calls q0 once and Q (or Q_apply) once */
START_TEST(euler_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT, 0, inj);
  every_fault(sdae_map_euler, SDAE_SCHEME_EXPLICIT, WITH_Q_APPLY, inj);
  expect_covered(inj, (const int[]){Q0, QD, Q_APPLY}, 3);
}
END_TEST

/* the midpoint map: q0 in the predictor, the residuals and the finite differences; q0_jac */
START_TEST(midpoint_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT, 0, inj);
  every_fault(sdae_map_midpoint, SDAE_SCHEME_EXPLICIT, WITH_Q_APPLY | WITH_Q0_JAC, inj);
  expect_covered(inj, (const int[]){Q0, QD, Q_APPLY, Q0_JAC}, 4);
}
END_TEST

/* midpoint4 and midpoint6: the same callbacks, in every stage */
START_TEST(midpoint_composed_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault(sdae_map_midpoint4, SDAE_SCHEME_SEMI_IMPLICIT, 0, inj);
  every_fault(sdae_map_midpoint6, SDAE_SCHEME_EXPLICIT, WITH_Q_APPLY | WITH_Q0_JAC, inj);
  expect_covered(inj, (const int[]){Q0, QD, Q_APPLY, Q0_JAC}, 4);
}
END_TEST

/* the explicit Runge-Kutta maps: q0 once per stage (4 for rk4, 12 for rk8), each call failing
 * each way; a failure in the last stage leaves the state as surely as one in the first */
START_TEST(rk_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault(sdae_map_rk4, SDAE_SCHEME_SEMI_IMPLICIT, 0, inj);
  ck_assert_int_eq(inj[Q0], 4 * NMODE);
  every_fault(sdae_map_rk8, SDAE_SCHEME_EXPLICIT, WITH_Q_APPLY, inj);
  ck_assert_int_eq(inj[Q0], (4 + 12) * NMODE);
  expect_covered(inj, (const int[]){Q0, QD, Q_APPLY}, 3);
}
END_TEST

/* the discrete gradient: H, grad_H, S or S_apply in phi; grad_H, hess_H and S or S_apply in
 * its Jacobian */
START_TEST(dgrad_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT, 0, inj);
  every_fault(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT, WITH_S_APPLY | WITH_HESS_H, inj);
  every_fault(sdae_map_dgrad, SDAE_SCHEME_EXPLICIT, WITH_Q_APPLY | WITH_HESS_H, inj);
  expect_covered(inj, (const int[]){QD, Q_APPLY, H, GRAD_H, S, S_APPLY, HESS_H}, 7);
}
END_TEST

/* dg4 and dg6: the same callbacks, in every stage */
START_TEST(composed_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault(sdae_map_dg4, SDAE_SCHEME_SEMI_IMPLICIT, WITH_HESS_H, inj);
  every_fault(sdae_map_dg4, SDAE_SCHEME_SEMI_IMPLICIT, WITH_S_APPLY, inj);
  every_fault(sdae_map_dg6, SDAE_SCHEME_EXPLICIT, WITH_S_APPLY | WITH_HESS_H | WITH_Q_APPLY, inj);
  expect_covered(inj, (const int[]){QD, Q_APPLY, H, GRAD_H, S, S_APPLY, HESS_H}, 7);
}
END_TEST

/* the user map: user_phi everywhere phi is, user_phi_jac for Newton's matrix */
START_TEST(user_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault(sdae_map_user, SDAE_SCHEME_SEMI_IMPLICIT, 0, inj);
  every_fault(sdae_map_user, SDAE_SCHEME_EXPLICIT, WITH_Q_APPLY | WITH_PHI_JAC, inj);
  expect_covered(inj, (const int[]){QD, Q_APPLY, USER_PHI, USER_PHI_JAC}, 4);
}
END_TEST

/* ---- the banded Newton: a chain of n_mu = 6, mu' = a(t) K mu with K tridiagonal and skew
 * (K_{i,i+1} = 1, K_{i+1,i} = -1), H = |mu|^2/2, S = a(t) K by S_apply: d phi/d mu+ has band 1,
 * so bandwidth 1 builds Newton's matrix from 2 (2 + 1) evaluations in GSL's band storage ---- */
enum { CHAIN = 6 };

static void chain_apply(double t, const double *v, double *out) {
  for (int i = 0; i < CHAIN; i++)
    out[i] = (1.0 + t) * ((i + 1 < CHAIN ? v[i + 1] : 0.0) - (i > 0 ? v[i - 1] : 0.0));
}
static int c_q0(double t, const double *mu, double *out, void *p) {
  (void)p;
  chain_apply(t, mu, out);
  return fault(Q0, 0, out);
}
static int c_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qn2,
                     void *p) {
  (void)mu, (void)p;
  for (int i = 0; i < CHAIN; i++) Qxi[i] = i == 0 ? (1.0 + t) * xi[0] : 0.0;
  qn2[0] = (1.0 + t) * (1.0 + t);
  return fault(Q_APPLY, 0, Qxi);
}
static int c_H(double t, const double *mu, double *out, void *p) {
  double h = 0.0;
  (void)t, (void)p;
  for (int i = 0; i < CHAIN; i++) h += 0.5 * mu[i] * mu[i];
  out[0] = h;
  return fault(H, 0, out);
}
static int c_grad_H(double t, const double *mu, double *out, void *p) {
  (void)t, (void)p;
  memcpy(out, mu, CHAIN * sizeof *mu);
  return fault(GRAD_H, 0, out);
}
static int c_S_apply(double t, const double *mu, const double *v, double *out, void *p) {
  (void)mu, (void)p;
  chain_apply(t, v, out);
  return fault(S_APPLY, 0, out);
}

/* every call of every callback failing each way, the state bit for bit as it was */
static void every_fault_banded(const sdae_map_type *map, long *injected) {
  sdae_model m = {.n_xi = 1,
                  .n_mu = CHAIN,
                  .q0 = c_q0,
                  .Q_apply = c_Q_apply,
                  .H = c_H,
                  .grad_H = c_grad_H,
                  .S_apply = c_S_apply};
  sdae_options o = quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  const double mu0[CHAIN] = {0.6, -0.8, 0.3, 0.1, -0.2, 0.5};
  sdae_stepper *s;
  double xi[1], mu[CHAIN];
  long clean[NCB] = {0};
  o.bandwidth = 1;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  F.which = -1;
  for (int cb = -1; cb < NCB; cb++)
    for (long at = 0; at < (cb < 0 ? 1 : clean[cb]); at++)
      for (int mode = 0; mode < (cb < 0 ? 1 : NMODE); mode++) {
        F.which = cb, F.mode = mode, F.at = at;
        xi[0] = 0.3, memcpy(mu, mu0, sizeof mu);
        memset(F.calls, 0, sizeof F.calls);
        int rc = sdae_step(s, 0.5, 0.1, xi, mu);
        if (cb < 0) { /* the clean step: count the calls */
          ck_assert_int_eq(rc, SDAE_OK);
          memcpy(clean, F.calls, sizeof clean);
          continue;
        }
        ck_assert_msg(rc == expected[mode], "%s banded: %s call %ld mode %d gave %d",
                      sdae_map_name(map), cb_name[cb], at, mode, rc);
        ck_assert_int_eq(xi[0] == 0.3 && memcmp(mu, mu0, sizeof mu) == 0, 1);
        injected[cb]++;
      }
  F.which = -1;
  sdae_stepper_free(s);
}

/* midpoint, dgrad and dg4 on the band: q0 (midpoint) or H, grad_H, S_apply inside the
 * finite-difference columns, and Q_apply */
START_TEST(banded_callbacks_fail_cleanly) {
  long inj[NCB] = {0};
  every_fault_banded(sdae_map_midpoint, inj);
  every_fault_banded(sdae_map_dgrad, inj);
  every_fault_banded(sdae_map_dg4, inj);
  expect_covered(inj, (const int[]){Q0, Q_APPLY, H, GRAD_H, S_APPLY}, 5);
}
END_TEST

/* A fault in sdae_stepper_gains' only callback (Q or Q_apply) is its status too. */
START_TEST(gains_callback_fails_cleanly) {
  for (int with = 0; with <= WITH_Q_APPLY; with += WITH_Q_APPLY)
    for (int mode = 0; mode < NMODE; mode++) {
      sdae_model m = faulty_model(with);
      sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
      sdae_stepper *s;
      double xi[1] = {0.3}, mu[2] = {0.6, -0.8}, k[1];
      ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
      F.which = with ? Q_APPLY : QD, F.mode = mode, F.at = 0;
      memset(F.calls, 0, sizeof F.calls);
      ck_assert_int_eq(sdae_stepper_gains(s, 0.5, xi, mu, k), expected[mode]);
      F.which = -1;
      sdae_stepper_free(s);
    }
}
END_TEST

/* ---- overflows ---- */

static void expect_step(sdae_options *o, double t, double T, double xi0, int want) {
  sdae_model m = rotation_model(NULL);
  sdae_stepper *s;
  double xi[1] = {xi0}, mu[2] = {0.0, 0.0};
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, t, T, xi, mu), want);
  if (want != SDAE_OK) {
    ck_assert_double_eq(xi[0], xi0);
    ck_assert_double_eq(mu[0], 0.0);
    ck_assert_double_eq(mu[1], 0.0);
  } else {
    ck_assert_double_le(fabs(xi[0]), fabs(xi0)); /* scheme 15 contracts for every T */
  }
  sdae_stepper_free(s);
}

/* delta = 1e200 is finite, but delta^2/2 overflows: k = -inf. The gains are refused as
 * non-finite, and scheme 11's (1 + T k) xi = -inf too. */
START_TEST(infinite_gain_is_refused) {
  sdae_model m = rotation_model(NULL);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_EXPLICIT);
  sdae_stepper *s;
  double xi[1] = {0.3}, mu[2] = {0.6, -0.8}, k[1];
  o.delta = 1e200;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_stepper_gains(s, 0.5, xi, mu, k), SDAE_ERR_NONFINITE);
  sdae_stepper_free(s);
  expect_step(&o, 0.5, 0.1, 0.3, SDAE_ERR_NONFINITE);
}
END_TEST

/* Scheme 11 at T = 1e308 from t = 1 (||q_1||^2 = 4, k = -3): 1 + T k = -3e308 overflows to
 * -inf, so xi+ is not finite, while mu+ = mu + T (q0(0) + Q xi) = (2e305, 0) is: the new xi
 * alone is refused. Scheme 15 at the same T is fine (Theorem 4: any T > 0). */
START_TEST(overflowing_xi_scheme11) {
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_EXPLICIT);
  expect_step(&o, 1.0, 1e308, 1e-3, SDAE_ERR_NONFINITE);
  o.scheme = SDAE_SCHEME_SEMI_IMPLICIT;
  expect_step(&o, 1.0, 1e308, 1e-3, SDAE_OK);
}
END_TEST

int main(void) {
  Suite *s = suite_create("failures");
  ADD_CASE(s, euler_callbacks_fail_cleanly);
  ADD_CASE(s, midpoint_callbacks_fail_cleanly);
  ADD_CASE(s, midpoint_composed_callbacks_fail_cleanly);
  ADD_CASE(s, rk_callbacks_fail_cleanly);
  ADD_CASE(s, dgrad_callbacks_fail_cleanly);
  ADD_CASE(s, composed_callbacks_fail_cleanly);
  ADD_CASE(s, user_callbacks_fail_cleanly);
  ADD_CASE(s, banded_callbacks_fail_cleanly);
  ADD_CASE(s, gains_callback_fails_cleanly);
  ADD_CASE(s, infinite_gain_is_refused);
  ADD_CASE(s, overflowing_xi_scheme11);
  return run_suite(s);
}
