/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The generic front-end (<stabdae/dae.h>, src/dae/dae_model.c, src/dae/coords.c,
 * src/model/derive.c). The derived q0 and Q xi against the hand-written normal forms of the
 * examples (the oscillator of Section IV with the corrected Q of erratum 1, the pendulum), with and
 * without the DAE's Phi^-1 and an analytic mu_dot; against closed forms for a time-dependent DAE;
 * the telescoping rule's branches on polynomial rates; an integration against the example's
 * expected CSV (the Python reference's numbers); sdae_check_model on the derived model; every
 * failure status. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_rng.h>
#include <stabdae/dae.h>

#include "dae/coords.h"
#include "model/derive.h"
#include "oscillator_model.h"
#include "pendulum_model.h"
#include "testmodels.h"

/* ---- the examples' DAEs, with a mu_dot written by hand ---- */

/* mu = (X + Y, Y + Xdot): mu_dot = (Xdot + Ydot, Ydot + (-k X^3 - d Xdot)/m) along f */
static int osc_mu_dot(double t, const double *x, double *out, void *params) {
  const osc_params *p = params;
  (void)t;
  out[0] = x[2] + x[3];
  out[1] = x[3] + (-p->k * x[0] * x[0] * x[0] - p->d * x[2]) / p->m;
  return 0;
}

/* mu = (atan2(X, -Y), X Ydot - Y Xdot): mu_dot = ((X Ydot - Y Xdot)/r^2, -ga X) along f */
static int pend_mu_dot(double t, const double *x, double *out, void *params) {
  const pend_params *p = params;
  (void)t;
  out[0] = (x[0] * x[3] - x[1] * x[2]) / (x[0] * x[0] + x[1] * x[1]);
  out[1] = -p->ga * x[0];
  return 0;
}

static osc_params osc_p = {.k = 2.0, .d = 0.03, .m = 1.0, .ga = 9.81, .q = OSC_Q_CORRECTED};
static pend_params pend_p = {.L = 1.3, .m = 0.7, .ga = 9.81};
static const double OSC_LO[4] = {-0.7, -1.0, -0.9, -0.9}, OSC_HI[4] = {0.7, 1.0, 0.9, 0.9};
static const double PEND_LO[4] = {-0.3, -1.0, -2.0, -1.0}, PEND_HI[4] = {0.3, 1.0, 2.0, 1.0};

/* the worst differences over a box: q0 and Q xi relative to the size of G's terms
 * max_r (|q0_r| + sum_i |Q_ri xi_i|), and the columns |q_i| against that size over |xi_i| (a
 * divided difference over xi_i carries G's error divided by xi_i) */
typedef struct worst {
  double q0, Qxi, col;
} worst;

static worst compare(const sdae_model *hand, const sdae_model *derived, const double *lo,
                     const double *hi, size_t npoints) {
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  worst w = {0, 0, 0};
  gsl_rng_set(rng, 12345);
  for (size_t p = 0; p < npoints; p++) {
    double z[4], q0h[2], q0d[2], Q[4], Qxi[2], qn2[2], size = 0.0;
    for (int j = 0; j < 4; j++) z[j] = lo[j] + (hi[j] - lo[j]) * gsl_rng_uniform(rng);
    ck_assert_int_eq(hand->q0(0.0, z + 2, q0h, hand->params), 0);
    ck_assert_int_eq(hand->Q(0.0, z, z + 2, Q, hand->params), 0);
    ck_assert_int_eq(derived->q0(0.0, z + 2, q0d, derived->params), 0);
    ck_assert_int_eq(derived->Q_apply(0.0, z, z + 2, Qxi, qn2, derived->params), 0);
    for (int r = 0; r < 2; r++)
      size = fmax(size, fabs(q0h[r]) + fabs(Q[2 * r] * z[0]) + fabs(Q[2 * r + 1] * z[1]));
    for (int r = 0; r < 2; r++) {
      w.q0 = fmax(w.q0, fabs(q0d[r] - q0h[r]) / size);
      w.Qxi = fmax(w.Qxi, fabs(Qxi[r] - Q[2 * r] * z[0] - Q[2 * r + 1] * z[1]) / size);
    }
    for (int i = 0; i < 2; i++) {
      double norm = hypot(Q[i], Q[2 + i]);
      w.col = fmax(w.col, fabs(sqrt(qn2[i]) - norm) * fabs(z[i]) / size);
    }
  }
  gsl_rng_free(rng);
  return w;
}

static sdae_dae_model *derive_model(const sdae_dae *dae, sdae_mu_dot_fn mu_dot,
                                    const double *x_guess) {
  sdae_dae_model *d = NULL;
  ck_assert_int_eq(sdae_dae_model_alloc(&d, dae, 2, mu_dot, x_guess), SDAE_OK);
  return d;
}

static void osc_case(int with_inverse, int with_mu_dot, double tol) {
  sdae_model hand;
  sdae_dae dae;
  osc_params p = osc_p;
  osc_model(&hand, &p);
  osc_dae_spec(&dae, &p);
  if (!with_inverse) dae.Phi_inv = NULL;
  sdae_dae_model *d = derive_model(&dae, with_mu_dot ? osc_mu_dot : NULL, NULL);
  worst w = compare(&hand, sdae_dae_model_get(d), OSC_LO, OSC_HI, 200);
  ck_assert_double_le(w.q0, tol);
  ck_assert_double_le(w.Qxi, tol);
  ck_assert_double_le(w.col, tol);
  ck_assert_int_eq(sdae_dae_model_status(d), SDAE_OK);
  sdae_dae_model_free(d);
}

static void pend_case(int with_inverse, int with_mu_dot, double tol) {
  sdae_model hand;
  sdae_dae dae;
  pend_params p = pend_p;
  const double guess[4] = {0.0, -1.3, 0.0, 0.0}; /* at rest, hanging */
  pend_model(&hand, &p);
  pend_dae_spec(&dae, &p);
  if (!with_inverse) dae.Phi_inv = NULL;
  sdae_dae_model *d = derive_model(&dae, with_mu_dot ? pend_mu_dot : NULL, guess);
  worst w = compare(&hand, sdae_dae_model_get(d), PEND_LO, PEND_HI, 200);
  ck_assert_double_le(w.q0, tol);
  ck_assert_double_le(w.Qxi, tol);
  ck_assert_double_le(w.col, tol);
  sdae_dae_model_free(d);
}

/* Exact mu_dot: the oscillator's G is a polynomial and the divided differences are its own
 * (erratum 1's corrected Q): rounding only, 1e-12. The pendulum's G holds sqrt and sin: 1e-10.
 * Newton's Phi^-1 stops at a step below 1e-15 (1 + |x|), inside those. */
START_TEST(oscillator_exact) { osc_case(1, 1, 1e-12); }
END_TEST

START_TEST(oscillator_newton) { osc_case(0, 1, 1e-12); }
END_TEST

START_TEST(pendulum_exact) { pend_case(1, 1, 1e-10); }
END_TEST

START_TEST(pendulum_newton) { pend_case(0, 1, 1e-10); }
END_TEST

/* The fourth-order difference of mu_dot: truncation s^4 |m^(5)| / 30 and rounding about
 * 3 eps |m| / (2 s) with s = eps^(1/5) = 7.4e-4 are both near 1e-13 of the terms; 1e-10 leaves
 * the margin of m's derivatives (the pendulum's atan2). */
START_TEST(oscillator_fd) { osc_case(1, 0, 1e-10); }
END_TEST

START_TEST(oscillator_fd_newton) { osc_case(0, 0, 1e-10); }
END_TEST

START_TEST(pendulum_fd) { pend_case(1, 0, 1e-10); }
END_TEST

START_TEST(pendulum_fd_newton) { pend_case(0, 0, 1e-10); }
END_TEST

/* ---- a time-dependent DAE with closed forms ----
 * x = (y, v), f = (a v, -y^3/c^2 + w cos t), g = (1, -(t + cos(y/c))), xi = y,
 * mu = v + t y + c sin(y/c) + b sin t (L_g mu = 0; c the scale of x). Phi^-1: y = xi,
 * v = mu - t xi - c sin(xi/c) - b sin t; mu_dot = y + (t + cos(y/c)) a v - y^3/c^2 + w cos t +
 * b cos t, so G(t, xi, mu) is mu_dot at that point, q0 = G(t, 0, mu),
 * Q xi = G(t, xi, mu) - G(t, 0, mu), q_1 = Q xi / xi. mu(t + s, x + s f) is not a polynomial in
 * s (the sines), so the difference's truncation is there. */
typedef struct tdae {
  double w, c, a, b;
  int jac;      /* Phi_jac given */
  int analytic; /* mu_dot given */
  int still;    /* mu follows t so that v = 0 at xi = 0: x and f of size |xi| at q0 */
} tdae;

static int td_f(double t, const double *x, double *out, void *params) {
  const tdae *p = params;
  out[0] = p->a * x[1];
  out[1] = -x[0] * x[0] * x[0] / (p->c * p->c) + p->w * cos(t);
  return 0;
}

static int td_g(double t, const double *x, double *out, void *params) {
  const tdae *p = params;
  out[0] = 1.0, out[1] = -(t + cos(x[0] / p->c));
  return 0;
}

static int td_Phi(double t, const double *x, double *z, void *params) {
  const tdae *p = params;
  z[0] = x[0], z[1] = x[1] + t * x[0] + p->c * sin(x[0] / p->c) + p->b * sin(t);
  return 0;
}

static int td_Phi_jac(double t, const double *x, double *J, void *params) {
  const tdae *p = params;
  J[0] = 1.0, J[1] = 0.0, J[2] = t + cos(x[0] / p->c), J[3] = 1.0;
  return 0;
}

static double td_rate(const tdae *p, double t, double y, double v) {
  return y + (t + cos(y / p->c)) * p->a * v - y * y * y / (p->c * p->c) + p->w * cos(t) +
         p->b * cos(t);
}

static int td_mu_dot(double t, const double *x, double *out, void *params) {
  out[0] = td_rate(params, t, x[0], x[1]);
  return 0;
}

static double td_G(const tdae *p, double t, double xi, double mu) {
  return td_rate(p, t, xi, mu - t * xi - p->c * sin(xi / p->c) - p->b * sin(t));
}

/* at t = 0, 0.37, ..., 2.96: q0, Q xi and |q_1| within tol of the terms' size */
static void td_check(tdae p, double xi, double mu, double tol) {
  sdae_dae dae = {2, 1, td_f, td_g, td_Phi, NULL, p.jac ? td_Phi_jac : NULL, &p};
  sdae_dae_model *d = NULL;
  ck_assert_int_eq(sdae_dae_model_alloc(&d, &dae, 1, p.analytic ? td_mu_dot : NULL, NULL), SDAE_OK);
  const sdae_model *m = sdae_dae_model_get(d);
  for (double t = 0.0; t < 3.0; t += 0.37) {
    double q0, Qxi, qn2, mu_t = p.still ? p.b * sin(t) : mu;
    double want_q0 = td_G(&p, t, 0.0, mu_t), want_Qxi = td_G(&p, t, xi, mu_t) - want_q0;
    double size = fabs(want_q0) + fabs(want_Qxi);
    ck_assert_int_eq(m->q0(t, &mu_t, &q0, m->params), 0);
    ck_assert_int_eq(m->Q_apply(t, &xi, &mu_t, &Qxi, &qn2, m->params), 0);
    ck_assert_double_le(fabs(q0 - want_q0), tol * size);
    ck_assert_double_le(fabs(Qxi - want_Qxi), tol * size);
    ck_assert_double_le(fabs(sqrt(qn2) - fabs(want_Qxi / xi)) * fabs(xi), tol * size);
  }
  sdae_dae_model_free(d);
}

/* the time reaches Phi, f, mu_dot and the difference in t: 1e-12 with mu_dot (rounding), 1e-10
 * with the difference as for the examples */
START_TEST(time_dependent) {
  td_check((tdae){1.0, 1.0, 1.0, 0.5, 0, 0, 0}, 0.4, -0.7, 1e-10);
  td_check((tdae){1.0, 1.0, 1.0, 0.5, 1, 0, 0}, 0.4, -0.7, 1e-10);
  td_check((tdae){1.0, 1.0, 1.0, 0.5, 1, 1, 0}, 0.4, -0.7, 1e-12);
}
END_TEST

/* The difference's step s follows the motion: y' = a v with a = 1e5 makes s 1e5 times shorter,
 * or y would move 50 units across the sine (an error of the size of the terms); x and f of
 * 1e4 with the sine's scale c = 1e4 leave s at eps^(1/5), or the rounding of x + s f (eps |x|)
 * over s would be 2e-9 of the terms. A slow motion (|f| = 1e-9) of a small x (1e-3) keeps s at
 * eps^(1/5): not 1e9 times longer across sin t, nor 1e3 times shorter (rounding 3e-10). */
START_TEST(fd_step_scaled) {
  td_check((tdae){1.0, 1.0, 1e5, 0.0, 0, 0, 0}, 0.4, -0.7, 1e-10);
  td_check((tdae){1e4, 1e4, 1.0, 0.0, 0, 0, 0}, 4e3, -7e3, 1e-10);
  td_check((tdae){0.0, 1.0, 1e-6, 1.0, 0, 0, 1}, 1e-3, 0.0, 1e-10);
}
END_TEST

/* ---- the telescoping rule (src/model/derive.c) on a polynomial rate ----
 * G(xi, mu) = (xi1 + xi1^2 + xi1 xi2 + 2 xi2 + mu1, 3 xi2^2 - xi1 + mu2 t), n_xi = n_mu = 2. */
typedef struct poly {
  int calls;
  int fail_at; /* the call that fails (1-based; 0: none), after writing 999 */
  int status;  /* its status */
} poly;

static int poly_rate(void *ctx, double t, const double *xi, const double *mu, double *out) {
  poly *p = ctx;
  p->calls++;
  out[0] = xi[0] + xi[0] * xi[0] + xi[0] * xi[1] + 2 * xi[1] + mu[0];
  out[1] = 3 * xi[1] * xi[1] - xi[0] + mu[1] * t;
  if (p->calls == p->fail_at) {
    out[0] = out[1] = 999.0;
    return p->status;
  }
  return SDAE_OK;
}

typedef struct poly_derive {
  sdae_derive d;
  double mem[64];
  poly p;
} poly_derive;

static void poly_init(poly_derive *pd) {
  sdae_arena a = {.base = (char *)pd->mem};
  memset(&pd->p, 0, sizeof pd->p);
  sdae__derive_carve(&pd->d, 2, 2, poly_rate, &pd->p, &a);
  ck_assert_uint_le(a.used, sizeof pd->mem);
}

static double G1(double a, double b) { return a + a * a + a * b + 2 * b; }
static double G2(double a, double b) { return 3 * b * b - a; }

static void expect_near(double got, double want, double tol) {
  ck_assert_msg(fabs(got - want) <= tol, "got %.17g, want %.17g", got, want);
}

/* no tiny xi: Q xi = G(xi) - G(0) and the columns (G(xi1, 0) - G(0))/xi1 = (1 + xi1, -1),
 * (G(xi) - G(xi1, 0))/xi2 = (xi1 + 2, 3 xi2) */
START_TEST(telescoping_columns) {
  poly_derive pd;
  double xi[2] = {0.3, -0.2}, mu[2] = {0.5, -1.5}, Qxi[2], qn2[2], t = 2.0;
  poly_init(&pd);
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, t, xi, mu, Qxi, qn2), SDAE_OK);
  expect_near(Qxi[0], G1(0.3, -0.2), 1e-15);
  expect_near(Qxi[1], G2(0.3, -0.2), 1e-15);
  expect_near(qn2[0], 1.3 * 1.3 + 1.0, 1e-14);
  expect_near(qn2[1], 2.3 * 2.3 + 0.36, 1e-14);
  ck_assert_int_eq(pd.p.calls, 3);
}
END_TEST

/* a tiny xi1 (1e-10 < sqrt(eps)): column 1 over h = sqrt(eps) from 0, (1 + h, -1), its term
 * q_1 xi1 outside the sum, and column 2 from xi^(1) = 0: (2, 3 xi2) */
START_TEST(tiny_first_column) {
  poly_derive pd;
  double h = sqrt(DBL_EPSILON), xi[2] = {1e-10, 0.5}, mu[2] = {0.5, -1.5}, Qxi[2], qn2[2];
  poly_init(&pd);
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 1.0, xi, mu, Qxi, qn2), SDAE_OK);
  expect_near(Qxi[0], (1 + h) * 1e-10 + 2 * 0.5, 1e-16);
  expect_near(Qxi[1], -1e-10 + 3 * 0.25, 1e-15);
  expect_near(qn2[0], (1 + h) * (1 + h) + 1.0, 1e-14);
  expect_near(qn2[1], 4.0 + 9 * 0.25, 1e-14);
}
END_TEST

/* a tiny negative xi2: h = -sqrt(eps), toward xi2, so the chord from xi^(1) covers [0, xi2]:
 * with xi1 = 0 (tiny too: its term is 0 and the base stays 0), column 2 = (2, 3 h) and
 * Q xi = q_2 xi2 = (2 xi2, 3 h xi2): h = +sqrt(eps) would flip the sign of the mu2 row */
START_TEST(tiny_negative_column) {
  poly_derive pd;
  double h = -sqrt(DBL_EPSILON), xi[2] = {0.0, -1e-10}, mu[2] = {0.5, -1.5}, Qxi[2], qn2[2];
  poly_init(&pd);
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 1.0, xi, mu, Qxi, qn2), SDAE_OK);
  expect_near(Qxi[0], 2 * -1e-10, 1e-25);
  expect_near(Qxi[1], 3 * h * -1e-10, 1e-30);
  expect_near(qn2[1], 4.0 + 9 * h * h, 1e-15);
}
END_TEST

/* xi1 = sqrt(eps) exactly is not tiny: the base moves to xi^(1), column 2 = (xi1 + 2, 3 xi2) */
START_TEST(tiny_threshold) {
  poly_derive pd;
  double h = sqrt(DBL_EPSILON), xi[2] = {h, 0.5}, mu[2] = {0.0, 0.0}, Qxi[2], qn2[2];
  poly_init(&pd);
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 1.0, xi, mu, Qxi, qn2), SDAE_OK);
  expect_near(Qxi[0], G1(h, 0.5), 1e-16);
  expect_near(qn2[1], (h + 2) * (h + 2) + 2.25, 1e-15);
  ck_assert_double_ne(qn2[1], 4.0 + 2.25);
}
END_TEST

/* Floors (the mechanical front-end's): xi1 = 1e-3 at its floor 1e-3 is rounding: no column
 * (qn2 = 0, the gain -epsilon), no term; xi2 above its own has its column from xi^(1) = 0,
 * (G(0, xi2) - G(0))/xi2 = (2, 3 xi2), and Q xi = G(0, xi2) - G(0) = (2 xi2, 3 xi2^2): two
 * rates. Every xi_i at its floor: no rate at all, Q xi = 0. Without floors, as before. */
START_TEST(floors_skip_columns) {
  poly_derive pd;
  double xi[2] = {1e-3, -0.2}, mu[2] = {0.5, -1.5}, Qxi[2], qn2[2], floor[2] = {1e-3, 0.1};
  poly_init(&pd);
  pd.d.floor = floor;
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 2.0, xi, mu, Qxi, qn2), SDAE_OK);
  ck_assert_int_eq(pd.p.calls, 2);
  ck_assert_double_eq(qn2[0], 0.0);
  expect_near(qn2[1], 4.0 + 0.36, 1e-14);
  expect_near(Qxi[0], 2 * -0.2, 1e-15);
  expect_near(Qxi[1], 3 * 0.04, 1e-15);
  floor[1] = 0.2;
  sdae__derive_forget(&pd.d);
  Qxi[0] = Qxi[1] = qn2[0] = qn2[1] = 7.0;
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 2.0, xi, mu, Qxi, qn2), SDAE_OK);
  ck_assert_int_eq(pd.p.calls, 2);
  ck_assert(Qxi[0] == 0.0 && Qxi[1] == 0.0 && qn2[0] == 0.0 && qn2[1] == 0.0);
  pd.d.floor = NULL;
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 2.0, xi, mu, Qxi, qn2), SDAE_OK);
  ck_assert_int_eq(pd.p.calls, 2 + 3);
  expect_near(Qxi[0], G1(1e-3, -0.2), 1e-15);
  expect_near(qn2[0], 1.001 * 1.001 + 1.0, 1e-12); /* a quotient over xi1 = 1e-3 */
}
END_TEST

/* G(0, mu) is kept for the same (t, mu): q0 then Q costs 1 + n_xi rates; a new t or a new last
 * component of mu, or a forget, evaluates it again */
START_TEST(G0_cache) {
  poly_derive pd;
  double xi[2] = {0.3, -0.2}, mu[2] = {0.5, -1.5}, q0[2], Qxi[2], qn2[2];
  poly_init(&pd);
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 2.0, mu, q0), SDAE_OK);
  expect_near(q0[1], -3.0, 0.0);
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 2.0, xi, mu, Qxi, qn2), SDAE_OK);
  ck_assert_int_eq(pd.p.calls, 3);
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 3.0, mu, q0), SDAE_OK);
  expect_near(q0[1], -4.5, 0.0);
  ck_assert_int_eq(pd.p.calls, 4);
  mu[1] = -1.0;
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 3.0, mu, q0), SDAE_OK);
  expect_near(q0[1], -3.0, 0.0);
  ck_assert_int_eq(pd.p.calls, 5);
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 3.0, mu, q0), SDAE_OK);
  ck_assert_int_eq(pd.p.calls, 5);
  sdae__derive_forget(&pd.d);
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 3.0, mu, q0), SDAE_OK);
  ck_assert_int_eq(pd.p.calls, 6);
}
END_TEST

/* a failed G(0, mu) is not kept (it wrote 999): the next call evaluates it again; the failure
 * of G(0, mu) or of a column is returned, with q0's and Q_apply's outputs untouched */
START_TEST(G0_failure_not_kept) {
  poly_derive pd;
  double xi[2] = {0.3, -0.2}, mu[2] = {0.5, -1.5}, q0[2] = {7, 7}, Qxi[2], qn2[2];
  poly_init(&pd);
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 2.0, mu, q0), SDAE_OK);
  pd.p.fail_at = 2, pd.p.status = SDAE_ERR_CALLBACK_FATAL;
  q0[0] = q0[1] = 7.0;
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 3.0, mu, q0), SDAE_ERR_CALLBACK_FATAL);
  ck_assert(q0[0] == 7.0 && q0[1] == 7.0);
  ck_assert_int_eq(sdae__derive_q0(&pd.d, 2.0, mu, q0), SDAE_OK);
  expect_near(q0[0], 0.5, 0.0);
  ck_assert_int_eq(pd.p.calls, 3);
  pd.p.fail_at = 5, pd.p.status = SDAE_ERR_PHI_INV;
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 2.0, xi, mu, Qxi, qn2), SDAE_ERR_PHI_INV);
  ck_assert_int_eq(pd.p.calls, 5);
  pd.p.fail_at = 6, pd.p.status = SDAE_ERR_NONFINITE;
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 2.0, xi, mu, Qxi, qn2), SDAE_ERR_NONFINITE);
  /* G(0, mu) itself fails at a new time: Q_apply stops there, its outputs untouched */
  pd.p.fail_at = pd.p.calls + 1, pd.p.status = SDAE_ERR_CALLBACK_RECOVERABLE;
  Qxi[0] = Qxi[1] = qn2[0] = qn2[1] = 7.0;
  ck_assert_int_eq(sdae__derive_Q_apply(&pd.d, 4.0, xi, mu, Qxi, qn2),
                   SDAE_ERR_CALLBACK_RECOVERABLE);
  ck_assert(Qxi[0] == 7.0 && Qxi[1] == 7.0 && qn2[0] == 7.0 && qn2[1] == 7.0);
}
END_TEST

/* 0 for success; > 0 where a smaller step may help (Phi^-1's Newton, a recoverable callback);
 * < 0 for every other status */
START_TEST(callback_codes) {
  ck_assert_int_eq(sdae__callback_code(SDAE_OK), 0);
  ck_assert_int_gt(sdae__callback_code(SDAE_ERR_PHI_INV), 0);
  ck_assert_int_gt(sdae__callback_code(SDAE_ERR_CALLBACK_RECOVERABLE), 0);
  for (int s = SDAE_ERR_NULL; s >= SDAE_ERR_MASS; s--)
    if (s != SDAE_ERR_PHI_INV && s != SDAE_ERR_CALLBACK_RECOVERABLE)
      ck_assert_int_lt(sdae__callback_code(s), 0);
}
END_TEST

/* ---- the derived model in use ---- */

/* the expected CSV beside this file: examples/expected/<name>.csv */
static FILE *open_expected(const char *name) {
  char path[4096];
  const char *here = __FILE__, *cut = strstr(here, "tests/check_dae_model.c");
  ck_assert_ptr_nonnull(cut);
  snprintf(path, sizeof path, "%.*sexamples/expected/%s.csv", (int)(cut - here), here, name);
  FILE *f = fopen(path, "r");
  ck_assert_msg(f != NULL, "cannot open %s", path);
  return f;
}

typedef struct rows {
  double v[32][5]; /* t, xi1, xi2, mu1, mu2 */
  size_t n;
} rows;

static int record(size_t step, double t, const double *xi, const double *mu, void *data) {
  rows *r = data;
  (void)step;
  if (r->n < 32) {
    double *v = r->v[r->n++];
    v[0] = t, v[1] = xi[0], v[2] = xi[1], v[3] = mu[0], v[4] = mu[1];
  }
  return 0;
}

/* The example's run --tf 0.2 --every 10 --scheme 11 --map euler (examples/tests/CMakeLists.txt:
 * k 2, d 0.03, m 1, delta 2, epsilon 1, T 0.001 from (0.1, 0.6, 0, 0)) with the derived model:
 * the rows of the Python reference to 1e-10. xi2 stays 0 there, the rule's tiny branch. */
static void integrate_case(sdae_mu_dot_fn mu_dot, int with_inverse) {
  sdae_dae dae;
  osc_params p = osc_p;
  sdae_options o;
  sdae_stepper *s;
  rows got = {.n = 0};
  double x0[4] = {0.1, 0.6, 0.0, 0.0}, xi[2], mu[2];
  char line[1024];
  osc_dae_spec(&dae, &p);
  if (!with_inverse) dae.Phi_inv = NULL;
  sdae_dae_model *d = derive_model(&dae, mu_dot, NULL);
  sdae_options_default(&o);
  o.scheme = SDAE_SCHEME_EXPLICIT, o.map = sdae_map_euler, o.delta = 2.0, o.epsilon = 1.0;
  osc_to_coords(&p, x0, xi, mu);
  ck_assert_int_eq(sdae_stepper_alloc(&s, sdae_dae_model_get(d), &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, 0.001, 200, 10, xi, mu, record, &got, NULL), SDAE_OK);
  ck_assert_uint_eq(got.n, 21);
  FILE *f = open_expected("oscillator_s11_euler");
  ck_assert_ptr_nonnull(fgets(line, sizeof line, f)); /* the header */
  for (size_t r = 0; r < got.n; r++) {
    double v[12];
    ck_assert_ptr_nonnull(fgets(line, sizeof line, f));
    ck_assert_int_eq(sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", v, v + 1, v + 2, v + 3,
                            v + 4, v + 5, v + 6, v + 7, v + 8),
                     9);
    const double want[5] = {v[0], v[5], v[6], v[7], v[8]};
    for (int c = 0; c < 5; c++)
      ck_assert_msg(fabs(got.v[r][c] - want[c]) <= 1e-10 * fmax(1.0, fabs(want[c])),
                    "row %zu column %d: %.17g, expected %.17g", r, c, got.v[r][c], want[c]);
  }
  fclose(f);
  sdae_stepper_free(s);
  sdae_dae_model_free(d);
}

START_TEST(integrate_expected_csv) {
  integrate_case(osc_mu_dot, 1);
  integrate_case(NULL, 0);
}
END_TEST

/* sdae_check_model (Phi's Jacobian by differences) finds the derived model consistent with the
 * DAE: residuals of about 1e-10 of the terms; 1e-8 */
START_TEST(check_model_passes) {
  sdae_dae osc, pend;
  osc_params op = osc_p;
  pend_params pp = pend_p;
  const double guess[4] = {0.0, -1.3, 0.0, 0.0};
  sdae_check_report r;
  osc_dae_spec(&osc, &op);
  pend_dae_spec(&pend, &pp);
  sdae_dae_model *d = derive_model(&osc, NULL, NULL);
  ck_assert_int_eq(
      sdae_check_model(sdae_dae_model_get(d), &osc, 0.0, OSC_LO, OSC_HI, 50, 3, 1e-8, NULL, &r),
      SDAE_OK);
  ck_assert(r.consistent);
  sdae_dae_model_free(d);
  d = derive_model(&pend, NULL, guess);
  ck_assert_int_eq(
      sdae_check_model(sdae_dae_model_get(d), &pend, 0.0, PEND_LO, PEND_HI, 50, 3, 1e-8, NULL, &r),
      SDAE_OK);
  ck_assert(r.consistent);
  sdae_dae_model_free(d);
}
END_TEST

/* ---- Phi^-1's Newton: the start, and its failure ----
 * x = (y, v), xi = y, mu = v^2 (two preimages +-sqrt(mu)), f = (1, 1): G = 2 v = +-2 sqrt(mu),
 * the sign that of the root Newton finds. Phi fails (recoverable) at v > 10. */
static int sq_f(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 1.0, out[1] = 1.0;
  return 0;
}

static int sq_Phi(double t, const double *x, double *z, void *params) {
  (void)t, (void)params;
  z[0] = x[0], z[1] = x[1] * x[1];
  return x[1] > 10.0 ? 1 : 0;
}

static int sq_mu_dot(double t, const double *x, double *out, void *params) {
  (void)t, (void)params;
  out[0] = 2.0 * x[1];
  return 0;
}

static double sq_q0(sdae_dae_model *d, double mu, int *rc) {
  const sdae_model *m = sdae_dae_model_get(d);
  double out = 0.0;
  *rc = m->q0(0.0, &mu, &out, m->params);
  return out;
}

START_TEST(newton_start) {
  sdae_dae dae = {2, 1, sq_f, sq_f, sq_Phi, NULL, NULL, NULL};
  const double below[2] = {0.0, -1.0};
  sdae_dae_model *d;
  int rc;
  /* from x = z = (0, 4): the root +2 */
  ck_assert_int_eq(sdae_dae_model_alloc(&d, &dae, 1, sq_mu_dot, NULL), SDAE_OK);
  expect_near(sq_q0(d, 4.0, &rc), 4.0, 1e-12);
  sdae_dae_model_free(d);
  /* from the guess (0, -1): -2, then from the last root found: -3, not +3 as from z */
  ck_assert_int_eq(sdae_dae_model_alloc(&d, &dae, 1, sq_mu_dot, below), SDAE_OK);
  expect_near(sq_q0(d, 4.0, &rc), -4.0, 1e-12);
  expect_near(sq_q0(d, 9.0, &rc), -6.0, 1e-12);
  /* mu = -100 has no root: Newton from -3 jumps to v = (-3 + 100/3)/2 > 10, where Phi fails;
   * that point is not kept */
  sq_q0(d, -100.0, &rc);
  ck_assert_int_gt(rc, 0);
  ck_assert_int_eq(sdae_dae_model_status(d), SDAE_ERR_CALLBACK_RECOVERABLE);
  expect_near(sq_q0(d, 1.0, &rc), -2.0, 1e-12);
  ck_assert_int_eq(sdae_dae_model_status(d), SDAE_ERR_CALLBACK_RECOVERABLE); /* the last failure */
  sdae_dae_model_free(d);
}
END_TEST

/* x = (y, v), xi = y, mu = v^2 + 1 - 2 (always >= -1): at mu = -1.5 Newton cannot converge.
 * From the guess (0, 0.5) it wanders (SDAE_ERR_NEWTON inside), from x = z = (0, -1.5) too; from
 * (0, 0) the Jacobian is singular at once. Each is SDAE_ERR_PHI_INV, code > 0 (a smaller step
 * may help), and the output untouched. */
static int nr_Phi(double t, const double *x, double *z, void *params) {
  (void)t, (void)params;
  z[0] = x[0], z[1] = x[1] * x[1] - 1.0;
  return 0;
}

static void no_root_from(const double *guess) {
  sdae_dae dae = {2, 1, sq_f, sq_f, nr_Phi, NULL, NULL, NULL};
  sdae_dae_model *d;
  double out = 42.0, mu = -1.5;
  ck_assert_int_eq(sdae_dae_model_alloc(&d, &dae, 1, sq_mu_dot, guess), SDAE_OK);
  const sdae_model *m = sdae_dae_model_get(d);
  ck_assert_int_gt(m->q0(0.0, &mu, &out, m->params), 0);
  ck_assert_double_eq(out, 42.0);
  ck_assert_int_eq(sdae_dae_model_status(d), SDAE_ERR_PHI_INV);
  sdae_dae_model_free(d);
}

START_TEST(phi_inv_failure) {
  const double wander[2] = {0.0, 0.5}, flat[2] = {0.0, 0.0};
  no_root_from(wander);
  no_root_from(NULL);
  no_root_from(flat);
}
END_TEST

/* ---- a failing callback of the DAE: the oscillator with a switch ---- */
enum { FAIL_NONE, FAIL_F, FAIL_PHI, FAIL_PHI_INV, FAIL_MU_DOT, FAIL_PHI_JAC };

typedef struct faulty {
  osc_params p;
  sdae_dae inner;
  int which, rc; /* the callback that fails, and its return code (0: writes a NaN) */
  int after;     /* calls of it that succeed first */
} faulty;

static int fails(faulty *q, int which, double *out) {
  if (q->which != which || q->after-- > 0) return 0;
  if (q->rc == 0) out[0] = NAN;
  return q->rc;
}

static int fy_f(double t, const double *x, double *out, void *params) {
  faulty *q = params;
  q->inner.f(t, x, out, &q->p);
  return fails(q, FAIL_F, out);
}

static int fy_g(double t, const double *x, double *out, void *params) {
  faulty *q = params;
  return q->inner.g(t, x, out, &q->p);
}

static int fy_Phi(double t, const double *x, double *z, void *params) {
  faulty *q = params;
  q->inner.Phi(t, x, z, &q->p);
  return fails(q, FAIL_PHI, z + 1);
}

static int fy_Phi_inv(double t, const double *z, double *x, void *params) {
  faulty *q = params;
  q->inner.Phi_inv(t, z, x, &q->p);
  return fails(q, FAIL_PHI_INV, x + 3);
}

static int fy_Phi_jac(double t, const double *x, double *J, void *params) {
  faulty *q = params;
  (void)t, (void)x;
  static const double Jo[16] = {0, 1, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0, 1, 1, 0};
  memcpy(J, Jo, sizeof Jo);
  return fails(q, FAIL_PHI_JAC, J + 5);
}

static int fy_mu_dot(double t, const double *x, double *out, void *params) {
  faulty *q = params;
  osc_mu_dot(t, x, out, &q->p);
  return fails(q, FAIL_MU_DOT, out + 1);
}

/* the model of the faulty oscillator: Phi^-1 by the DAE's (inverse) or Newton with or without
 * Phi_jac, mu_dot analytic or by differences */
static sdae_dae_model *faulty_model(faulty *q, int inverse, int jac, int analytic) {
  sdae_dae_model *d;
  q->p = osc_p;
  osc_dae_spec(&q->inner, &q->p);
  sdae_dae dae = {4, 1, fy_f, fy_g, fy_Phi, inverse ? fy_Phi_inv : NULL, jac ? fy_Phi_jac : NULL,
                  q};
  ck_assert_int_eq(sdae_dae_model_alloc(&d, &dae, 2, analytic ? fy_mu_dot : NULL, NULL), SDAE_OK);
  return d;
}

/* one failure: q0 and Q_apply return the code of want, leave their outputs, and the model's
 * status names want; a stepper's step fails with xi and mu untouched */
static void failure_case(int which, int rc, int after, int inverse, int jac, int analytic,
                         int want) {
  faulty q = {.which = FAIL_NONE};
  sdae_dae_model *d = faulty_model(&q, inverse, jac, analytic);
  const sdae_model *m = sdae_dae_model_get(d);
  double xi[2] = {0.1, -0.2}, mu[2] = {0.3, 0.4}, out[2] = {5, 5}, qn2[2] = {6, 6};
  int code = want == SDAE_ERR_CALLBACK_RECOVERABLE ? 1 : -1;
  ck_assert_int_eq(sdae_dae_model_status(d), SDAE_OK);
  q.which = which, q.rc = rc, q.after = after;
  ck_assert_int_eq(m->q0(0.0, mu, out, m->params), code);
  ck_assert(out[0] == 5 && out[1] == 5);
  ck_assert_int_eq(sdae_dae_model_status(d), want);
  q.after = after;
  ck_assert_int_eq(m->Q_apply(0.5, xi, mu, out, qn2, m->params), code);
  ck_assert(out[0] == 5 && out[1] == 5 && qn2[0] == 6 && qn2[1] == 6);
  ck_assert_int_eq(sdae_dae_model_status(d), want);
  sdae_dae_model_free(d);
}

START_TEST(failing_callbacks) {
  /* fatal, recoverable and NaN from each callback, at its first call */
  const int which[5] = {FAIL_F, FAIL_PHI, FAIL_PHI_INV, FAIL_MU_DOT, FAIL_PHI_JAC};
  for (int k = 0; k < 5; k++) {
    int inverse = which[k] == FAIL_PHI_INV, analytic = which[k] == FAIL_MU_DOT;
    int jac = which[k] == FAIL_PHI_JAC;
    failure_case(which[k], -1, 0, inverse, jac, analytic, SDAE_ERR_CALLBACK_FATAL);
    failure_case(which[k], 1, 0, inverse, jac, analytic, SDAE_ERR_CALLBACK_RECOVERABLE);
    failure_case(which[k], 0, 0, inverse, jac, analytic, SDAE_ERR_NONFINITE);
  }
  /* later calls of Phi: inside Newton's differences (the second of a pair, then a later
   * column), inside mu_dot's differences (its second and fourth points) */
  failure_case(FAIL_PHI, 0, 2, 0, 0, 1, SDAE_ERR_NONFINITE);
  failure_case(FAIL_PHI, -1, 4, 0, 0, 1, SDAE_ERR_CALLBACK_FATAL);
  failure_case(FAIL_PHI, 0, 1, 1, 0, 0, SDAE_ERR_NONFINITE);
  failure_case(FAIL_PHI, 1, 3, 1, 0, 0, SDAE_ERR_CALLBACK_RECOVERABLE);
}
END_TEST

/* A failure inside sdae_step: the step fails and leaves xi and mu; the model names the status */
START_TEST(failure_in_step) {
  faulty q = {.which = FAIL_NONE};
  sdae_dae_model *d = faulty_model(&q, 1, 0, 1);
  sdae_options o;
  sdae_stepper *s;
  double xi[2] = {0.1, -0.2}, mu[2] = {0.3, 0.4};
  sdae_options_default(&o);
  o.map = sdae_map_midpoint;
  ck_assert_int_eq(sdae_stepper_alloc(&s, sdae_dae_model_get(d), &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.01, xi, mu), SDAE_OK);
  double xi0[2] = {xi[0], xi[1]}, mu0[2] = {mu[0], mu[1]};
  q.which = FAIL_MU_DOT, q.rc = 0, q.after = 3;
  ck_assert_int_eq(sdae_step(s, 0.01, 0.01, xi, mu), SDAE_ERR_CALLBACK_FATAL);
  ck_assert_mem_eq(xi, xi0, sizeof xi);
  ck_assert_mem_eq(mu, mu0, sizeof mu);
  ck_assert_int_eq(sdae_dae_model_status(d), SDAE_ERR_NONFINITE);
  sdae_stepper_free(s);
  sdae_dae_model_free(d);
}
END_TEST

/* ---- construction ---- */

static int sentinel;

START_TEST(argument_statuses) {
  osc_params p = osc_p;
  sdae_dae dae, bad;
  sdae_dae_model *d = (sdae_dae_model *)&sentinel;
  static max_align_t mem[256];
  osc_dae_spec(&dae, &p);
  ck_assert_int_eq(sdae_dae_model_alloc(&d, NULL, 2, NULL, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_dae_model_alloc(NULL, &dae, 2, NULL, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_dae_model_init(NULL, mem, sizeof mem, &dae, 2, NULL, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_dae_model_init(&d, NULL, sizeof mem, &dae, 2, NULL, NULL), SDAE_ERR_NULL);
  for (int k = 0; k < 3; k++) {
    bad = dae;
    if (k == 0) bad.f = NULL;
    if (k == 1) bad.g = NULL;
    if (k == 2) bad.Phi = NULL;
    ck_assert_int_eq(sdae_dae_model_alloc(&d, &bad, 2, NULL, NULL), SDAE_ERR_NULL);
    ck_assert_int_eq(sdae_dae_model_init(&d, mem, sizeof mem, &bad, 2, NULL, NULL), SDAE_ERR_NULL);
    ck_assert_uint_eq(sdae_dae_model_size(&bad, 2), 0);
  }
  ck_assert_uint_eq(sdae_dae_model_size(NULL, 2), 0);
  for (size_t n_xi = 0; n_xi <= 5; n_xi += (n_xi == 0 ? 4 : 1)) {
    ck_assert_int_eq(sdae_dae_model_alloc(&d, &dae, n_xi, NULL, NULL), SDAE_ERR_DIM);
    ck_assert_int_eq(sdae_dae_model_init(&d, mem, sizeof mem, &dae, n_xi, NULL, NULL),
                     SDAE_ERR_DIM);
    ck_assert_uint_eq(sdae_dae_model_size(&dae, n_xi), 0);
  }
  bad = dae;
  bad.n = SIZE_MAX / 2;
  ck_assert_int_eq(sdae_dae_model_alloc(&d, &bad, 2, NULL, NULL), SDAE_ERR_OVERFLOW);
  ck_assert_int_eq(sdae_dae_model_init(&d, mem, sizeof mem, &bad, 2, NULL, NULL),
                   SDAE_ERR_OVERFLOW);
  ck_assert_uint_eq(sdae_dae_model_size(&bad, 2), 0);
  ck_assert_ptr_eq(d, (sdae_dae_model *)&sentinel);
  ck_assert_ptr_null(sdae_dae_model_get(NULL));
  ck_assert_int_eq(sdae_dae_model_status(NULL), SDAE_ERR_NULL);
  sdae_dae_model_free(NULL);
}
END_TEST

/* the block: its size exactly (one byte less is SDAE_ERR_BUFFER), at any alignment of the
 * caller's memory; the model built there gives the numbers of an allocated one */
START_TEST(caller_block) {
  osc_params p = osc_p;
  sdae_dae dae;
  sdae_dae_model *d = (sdae_dae_model *)&sentinel, *ref;
  static max_align_t mem[512];
  double mu[2] = {0.3, -0.4}, a[2], b[2];
  osc_dae_spec(&dae, &p);
  size_t need = sdae_dae_model_size(&dae, 2);
  ck_assert_uint_gt(need, 0);
  ck_assert_uint_le(need + 8, sizeof mem);
  ck_assert_int_eq(sdae_dae_model_alloc(&ref, &dae, 2, osc_mu_dot, NULL), SDAE_OK);
  ck_assert_int_eq(sdae_dae_model_get(ref)->q0(0.0, mu, a, sdae_dae_model_get(ref)->params), 0);
  for (size_t off = 0; off < 8; off += 7) {
    char *at = (char *)mem + off;
    memset(mem, 0xA5, sizeof mem);
    ck_assert_int_eq(sdae_dae_model_init(&d, at, need - 1, &dae, 2, osc_mu_dot, NULL),
                     SDAE_ERR_BUFFER);
    ck_assert_ptr_eq(d, (sdae_dae_model *)&sentinel);
    ck_assert_int_eq(sdae_dae_model_init(&d, at, need, &dae, 2, osc_mu_dot, NULL), SDAE_OK);
    const sdae_model *m = sdae_dae_model_get(d);
    ck_assert_uint_eq(m->n_xi, 2);
    ck_assert_uint_eq(m->n_mu, 2);
    ck_assert(m->Q == NULL && m->q0 != NULL && m->Q_apply != NULL);
    ck_assert_int_eq(m->q0(0.0, mu, b, m->params), 0);
    ck_assert_mem_eq(a, b, sizeof a);
    ck_assert_int_eq(sdae_dae_model_status(d), SDAE_OK);
    sdae_dae_model_free(d); /* a caller's block: nothing to give back */
    d = (sdae_dae_model *)&sentinel;
  }
  sdae_dae_model_free(ref);
}
END_TEST

static void *no_room(void *ud, size_t size) {
  (void)ud, (void)size;
  return NULL;
}

static void no_free(void *ud, void *ptr, size_t size) { (void)ud, (void)ptr, (void)size; }

START_TEST(no_memory) {
  osc_params p = osc_p;
  sdae_dae dae;
  sdae_dae_model *d = (sdae_dae_model *)&sentinel;
  sdae_allocator a = {no_room, no_free, NULL};
  osc_dae_spec(&dae, &p);
  ck_assert_int_eq(sdae_dae_model_alloc_with(&d, &dae, 2, NULL, NULL, &a), SDAE_ERR_NOMEM);
  ck_assert_ptr_eq(d, (sdae_dae_model *)&sentinel);
}
END_TEST

int main(void) {
  Suite *s = suite_create("dae_model");
  ADD_CASE(s, oscillator_exact);
  ADD_CASE(s, oscillator_newton);
  ADD_CASE(s, pendulum_exact);
  ADD_CASE(s, pendulum_newton);
  ADD_CASE(s, oscillator_fd);
  ADD_CASE(s, oscillator_fd_newton);
  ADD_CASE(s, pendulum_fd);
  ADD_CASE(s, pendulum_fd_newton);
  ADD_CASE(s, time_dependent);
  ADD_CASE(s, fd_step_scaled);
  ADD_CASE(s, telescoping_columns);
  ADD_CASE(s, tiny_first_column);
  ADD_CASE(s, tiny_negative_column);
  ADD_CASE(s, tiny_threshold);
  ADD_CASE(s, floors_skip_columns);
  ADD_CASE(s, G0_cache);
  ADD_CASE(s, G0_failure_not_kept);
  ADD_CASE(s, callback_codes);
  ADD_CASE(s, integrate_expected_csv);
  ADD_CASE(s, check_model_passes);
  ADD_CASE(s, newton_start);
  ADD_CASE(s, phi_inv_failure);
  ADD_CASE(s, failing_callbacks);
  ADD_CASE(s, failure_in_step);
  ADD_CASE(s, argument_statuses);
  ADD_CASE(s, caller_block);
  ADD_CASE(s, no_memory);
  return run_suite(s);
}
