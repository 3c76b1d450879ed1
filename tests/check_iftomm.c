/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The IFToMM benchmark problems (examples/models/nfourbar.h): the N-four-bar (A02) against its
 * one-angle reduction, which the parallelogram geometry gives in closed form, and the library's
 * steps across its singular configurations. */
#include <math.h>
#include <stdlib.h>

#include <stabdae/mbs.h>

#include "nfourbar.h"
#include "testmodels.h"

/* the reduction's constants: J theta'' = K ga sin theta */
static void reduction(const mech_nfourbar *p, double *J, double *K) {
  double N = (double)p->N;
  *J = (N + 1.0) * p->m / 3.0 + N * p->m;
  *K = (N + 1.0) * p->m / 2.0 + N * p->m;
}

/* every rocker at theta from the upright turning at omega: B_i = A_i + (sin, cos) theta */
static void parallelogram(const mech_nfourbar *p, double theta, double omega, double *q,
                          double *v) {
  for (size_t i = 0; i <= p->N; i++) {
    q[2 * i] = (double)i + sin(theta), q[2 * i + 1] = cos(theta);
    v[2 * i] = omega * cos(theta), v[2 * i + 1] = -omega * sin(theta);
  }
}

/* The elliptic reference against classical RK4 on theta'' = (K ga / J) sin theta from (0, 1),
 * h = 1e-4 (its error about 1e-13 over 3 s): B_0 agrees to 1e-10 at every output, through the
 * first flat positions (t = 0.72, 1.24) and a whole turn (its period 1.97 s). */
START_TEST(the_reference_is_the_reduced_pendulum) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  double J, K, w2, x[2] = {0.0, 1.0}, h = 1e-4;
  reduction(&p, &J, &K);
  w2 = K * p.ga / J;
  for (int i = 1; i <= 30000; i++) {
    double k1[2], k2[2], k3[2], k4[2];
    k1[0] = x[1], k1[1] = w2 * sin(x[0]);
    k2[0] = x[1] + 0.5 * h * k1[1], k2[1] = w2 * sin(x[0] + 0.5 * h * k1[0]);
    k3[0] = x[1] + 0.5 * h * k2[1], k3[1] = w2 * sin(x[0] + 0.5 * h * k2[0]);
    k4[0] = x[1] + h * k3[1], k4[1] = w2 * sin(x[0] + h * k3[0]);
    for (int j = 0; j < 2; j++) x[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    if (i % 2500 == 0) {
      double b[2];
      mech_nfourbar_reference(&p, i * h, b);
      ck_assert_double_eq_tol(b[0], sin(x[0]), 1e-10);
      ck_assert_double_eq_tol(b[1], cos(x[0]), 1e-10);
    }
  }
}
END_TEST

/* The mechanism is the reduction: on the parallelogram every constraint holds and G v = 0 (c
 * to rounding), the energy is (1/2) J omega^2 + K ga cos theta (its potential counted from the
 * pivots' height), and every derivative it gives agrees with differences. */
START_TEST(the_mechanism_is_the_parallelogram) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[82], v[82], c[81], *G = malloc(81 * 82 * sizeof *G), J, K;
  mech_nfourbar_system(&sys, &p);
  reduction(&p, &J, &K);
  sdae_options_default(&o);
  o.map = sdae_map_rk4;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  for (double theta = 0.1; theta < 6.2; theta += 0.7) {
    double omega = 1.0 + theta, E;
    sdae_mbs_check_report r;
    parallelogram(&p, theta, omega, q, v);
    ck_assert_int_eq(sys.constraint(0.0, q, c, sys.params), 0);
    ck_assert_int_eq(sys.jacobian(0.0, q, G, sys.params), 0);
    for (size_t j = 0; j < sys.n_c; j++) {
      double gv = 0.0;
      for (size_t k = 0; k < sys.n_q; k++) gv += G[j * sys.n_q + k] * v[k];
      ck_assert_double_le(fabs(c[j]), 1e-15 * (double)(p.N + 1));
      ck_assert_double_le(fabs(gv), 1e-13 * omega * (double)(p.N + 1));
    }
    ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E), SDAE_OK);
    ck_assert_double_eq_tol(E, 0.5 * J * omega * omega + K * p.ga * cos(theta), 1e-12 * fabs(E));
    ck_assert_int_eq(sdae_mbs_check(&sys, 0.0, q, v, 1e-6, &r), SDAE_OK);
    ck_assert(r.consistent);
  }
  sdae_mbs_stepper_free(s);
  free(G);
}
END_TEST

/* rk8 at T = 1e-2 from the benchmark's start to t = 2, across the first two flat positions:
 * within the benchmark's high-precision criterion (1e-3 in B_0) at every output (each 0.05 s),
 * the energy to 1e-6, every constraint at rounding after every step. */
START_TEST(rk8_crosses_the_first_flat_positions) {
  mech_nfourbar p = mech_nfourbar_benchmark();
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o;
  double q[82], v[82], c[81], E0, E;
  mech_nfourbar_system(&sys, &p);
  sdae_options_default(&o);
  o.map = sdae_map_rk8;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  mech_nfourbar_start(&p, q, v);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E0), SDAE_OK);
  for (int i = 0; i < 200; i++) {
    double t = (i + 1) * 1e-2;
    ck_assert_int_eq(sdae_mbs_step(s, i * 1e-2, 1e-2, q, v), SDAE_OK);
    ck_assert_int_eq(sys.constraint(t, q, c, sys.params), 0);
    for (size_t j = 0; j < sys.n_c; j++) ck_assert_double_le(fabs(c[j]), 1e-13);
    if ((i + 1) % 5 == 0) {
      double b[2];
      mech_nfourbar_reference(&p, t, b);
      ck_assert_double_le(hypot(q[0] - b[0], q[1] - b[1]), 1e-3);
    }
  }
  ck_assert_int_eq(sdae_mbs_energy(s, 2.0, q, v, &E), SDAE_OK);
  ck_assert_double_le(fabs(E - E0), 1e-6 * fabs(E0));
  sdae_mbs_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("iftomm");
  ADD_CASE(s, the_reference_is_the_reduced_pendulum);
  ADD_CASE(s, the_mechanism_is_the_parallelogram);
  ADD_CASE(s, rk8_crosses_the_first_flat_positions);
  return run_suite(s);
}
