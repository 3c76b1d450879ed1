/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Step-size certificates (Theorems 3 and 5) and condition (18). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "testmodels.h"

/* The paper's box B with xi2 fixed at 0 (k_1 does not depend on it). */
static const double LO[4] = {-0.7, 0.0, -0.9, -0.9}, HI[4] = {0.7, 0.0, 0.9, 0.9};

static sdae_certificate certify(int printed, double *argmax) {
  quartic p = {2.0, 0.03, 0, printed};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  sdae_certificate c;
  double sup[2];
  o.delta = 2.0;
  o.epsilon = 1.0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, LO, HI, 11, sup, argmax, &c), SDAE_OK);
  ck_assert_double_eq(sup[1], 4.0 / 2.0 * 2.0 + 1.0); /* ||q_2||^2 = 2: -k_2 = delta^2 + eps */
  sdae_stepper_free(s);
  return c;
}

/* -k_1 = (delta^2/2)(1 + c^2) + eps is largest where |c| is; by hand, at the corners:
 * printed: c(-0.7, 0.9) = 2(3(0.9)(-0.7) - 3(0.81) - 0.49) + 0.03(-0.7) = -9.641 -> 188.898;
 * corrected: c(0.7, -0.9) = 2(3(0.81) + 3(0.63) + 0.49) + 0.03 = 9.65 -> 189.245. */
START_TEST(eq24_printed_Q_gives_188_9) {
  double argmax[2 * 4];
  sdae_certificate c = certify(1, argmax);
  ck_assert_double_le(fabs(c.sup_neg_k - (2.0 * (1.0 + 9.641 * 9.641) + 1.0)), 1e-9);
  ck_assert_double_le(fabs(c.sup_neg_k - 188.9), 0.05);
  ck_assert_uint_eq(c.i_max, 0);
  ck_assert_double_le(fabs(argmax[0] - -0.7), 1e-6);
  ck_assert_double_le(fabs(argmax[2] - 0.9), 1e-6);
}
END_TEST

START_TEST(eq24_corrected_Q_gives_189_245) {
  double argmax[2 * 4];
  sdae_certificate c = certify(0, argmax);
  ck_assert_double_le(fabs(c.sup_neg_k - 189.245), 1e-9);
  ck_assert_double_le(fabs(argmax[0] - 0.7), 1e-6);
  ck_assert_double_le(fabs(argmax[2] - -0.9), 1e-6);
  ck_assert_double_le(fabs(c.T_bar - 2.0 / 189.245), 1e-15);
  ck_assert_double_le(fabs(c.T_thm5_scheme15 - (sqrt(5.0) - 1.0) / 4.0 * 2.0 / 189.245), 1e-15);
  ck_assert_double_le(fabs(c.T_thm5_scheme11 - 1.0 / 189.245), 1e-15);
}
END_TEST

/* A sup strictly inside the box, between grid points: with k = 2, d = -1, mu1 = 0.5 fixed,
 * c = 2 (0.75 - 1.5 xi1 + xi1^2) - 1 on xi1 in [0.2, 1.2] has c(0.2) = -0.02, c(1.2) = -0.22
 * and its extremum c(0.75) = -0.625 (dc/dxi1 = 2 (2 xi1 - 1.5) = 0); the 4-point grid sees
 * xi1 = 0.867 at best, where c = -0.598. */
START_TEST(refinement_finds_interior_sup) {
  quartic p = {2.0, -1.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  sdae_certificate c;
  double lo[4] = {0.2, 0.0, 0.5, 0.0}, hi[4] = {1.2, 0.0, 0.5, 0.0}, argmax[8], sup[2];
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 4, sup, argmax, &c), SDAE_OK);
  ck_assert_double_le(fabs(sup[0] - (0.5 * (1.0 + 0.625 * 0.625) + 1.0)), 1e-12);
  ck_assert_double_le(fabs(argmax[0] - 0.75), 1e-5);
  sdae_stepper_free(s);
}
END_TEST

/* Constant gain k = -3 (Q = [[2, 0], [0, 0]], delta = epsilon = 1): T_bar = 2/3 by hand, and
 * scheme 11 is bounded just below it and divergent just above. */

START_TEST(T_bar_on_constant_gain) {
  quartic p = {0.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_EXPLICIT);
  sdae_stepper *s;
  sdae_certificate c;
  double lo[4] = {-1, -1, -1, -1}, hi[4] = {1, 1, 1, 1};
  m.Q = quartic_const_Q;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 3, NULL, NULL, &c), SDAE_OK);
  ck_assert_double_eq_tol(c.T_bar, 2.0 / 3.0, 1e-15);
  for (int side = 0; side < 2; side++) {
    double T = c.T_bar * (side ? 1.01 : 0.99), xi[2] = {1.0, 0.0}, mu[2] = {0.0, 0.0};
    ck_assert_int_eq(sdae_integrate(s, 0.0, T, 400, 1, xi, mu, NULL, NULL, NULL), SDAE_OK);
    if (side)
      ck_assert_double_gt(fabs(xi[0]), 1e3);
    else
      ck_assert_double_lt(fabs(xi[0]), 1e-3);
  }
  sdae_stepper_free(s);
}
END_TEST

START_TEST(bad_box_is_refused) {
  quartic p = {2.0, 0.03, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  sdae_certificate c;
  double lo[4] = {-0.7, 0, -0.9, -0.9}, hi[4] = {0.7, 0, 0.9, 0.9};
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 1, NULL, NULL, &c), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, hi, lo, 5, NULL, NULL, &c), SDAE_ERR_PARAM);
  hi[2] = NAN;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 5, NULL, NULL, &c), SDAE_ERR_PARAM);
  hi[2] = INFINITY;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 5, NULL, NULL, &c), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, NULL, hi, 5, NULL, NULL, &c), SDAE_ERR_NULL);
  sdae_stepper_free(s);
}
END_TEST

/* ---- condition (18) ---- */

static int W(double t, const double *mu, double *out, void *params) {
  (void)t, (void)params;
  out[0] = 0.5 * mu[1] * mu[1] + 0.25 * 2.0 * mu[0] * mu[0] * mu[0] * mu[0];
  return 0;
}

/* By hand: the paper's map makes W's difference quotient gradbar W = (k (x1^3 + x1^2 y1 +
 * x1 y1^2 + y1^3)/4, (x2 + y2)/2), so on the manifold W(mu+) - W(mu) = T gradbar . phi
 * = -T d x2 (x2 + y2)/2: the ratio of (18) is -d x2 (x2 + y2) / (2 W(x)). */
typedef struct both {
  sdae_cond18 c;
  double prev[2], worst;
  int have;
} both;

static int observe_both(size_t step, double t, const double *xi, const double *mu, void *data) {
  both *b = data;
  if (b->have) {
    double Wx;
    W(0.0, b->prev, &Wx, NULL);
    b->worst = fmax(b->worst, -0.03 * b->prev[1] * (b->prev[1] + mu[1]) / (2.0 * Wx));
  }
  b->prev[0] = mu[0], b->prev[1] = mu[1], b->have = 1;
  return sdae_cond18_observe(step, t, xi, mu, &b->c);
}

START_TEST(cond18_matches_energy_balance) {
  quartic p = {2.0, 0.03, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_user, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0, 0}, mu[2] = {0.7, 0.0}, store[2];
  both b = {.worst = -INFINITY};
  o.delta = 2.0;
  ck_assert_int_eq(sdae_cond18_init(&b.c, 2, W, NULL, store), SDAE_OK);
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, 1e-3, 20000, 1, xi, mu, observe_both, &b, NULL), SDAE_OK);
  ck_assert_uint_eq(b.c.steps, 20000);
  ck_assert_double_le(fabs(b.c.gamma_min - b.worst), 1e-8 * fabs(b.worst) + 1e-12);
  /* dissipation: W never grows by more than the sign change of x2 allows, so the least gamma
   * is near 0 and the paper's gamma = 1e-5 is not negative, as Theorem 2 would need */
  ck_assert_double_le(b.c.gamma_min, 1e-3);
  ck_assert_double_gt(b.c.sup17, 0.0);
  sdae_stepper_free(s);
}
END_TEST

/* ---- the search itself, on gains designed with a known sup ---- */

/* A model whose gains are ours: Q_apply gives ||q_i||^2 = g_i(z), z = (xi, mu), so with
 * delta = epsilon = 1, -k_i = g_i/2 + 1 (eq. 6). Every evaluation's point is recorded; the
 * fail_at-th (1-based) returns fail_rc. */
#define MAX_RECORDED 20000
typedef struct designed {
  size_t n_xi, n_mu;
  double (*g)(size_t i, const double *z);
  long calls, fail_at;
  int fail_rc;
  double pts[MAX_RECORDED][3];
} designed;

static designed D;

static int designed_q0(double t, const double *mu, double *out, void *params) {
  designed *d = params;
  (void)t, (void)mu;
  for (size_t j = 0; j < d->n_mu; j++) out[j] = 0.0;
  return 0;
}

static int designed_Q_apply(double t, const double *xi, const double *mu, double *Qxi,
                            double *qnorm2, void *params) {
  designed *d = params;
  double z[3] = {0.0, 0.0, 0.0};
  (void)t;
  memcpy(z, xi, d->n_xi * sizeof *z);
  memcpy(z + d->n_xi, mu, d->n_mu * sizeof *z);
  if (d->calls < MAX_RECORDED) memcpy(d->pts[d->calls], z, sizeof z);
  if (++d->calls == d->fail_at) return d->fail_rc;
  for (size_t j = 0; j < d->n_mu; j++) Qxi[j] = 0.0;
  for (size_t i = 0; i < d->n_xi; i++) qnorm2[i] = d->g(i, z);
  return 0;
}

static sdae_stepper *designed_stepper(size_t n_xi, size_t n_mu, double (*g)(size_t, const double *),
                                      const sdae_allocator *a) {
  sdae_model m = {
      .n_xi = n_xi, .n_mu = n_mu, .q0 = designed_q0, .Q_apply = designed_Q_apply, .params = &D};
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  D.n_xi = n_xi, D.n_mu = n_mu, D.g = g, D.calls = 0, D.fail_at = 0;
  ck_assert_int_eq(sdae_stepper_alloc_with(&s, &m, &o, a), SDAE_OK);
  return s;
}

static int near(const double *p, double a, double b, double c) {
  return fabs(p[0] - a) <= 1e-14 && fabs(p[1] - b) <= 1e-14 && fabs(p[2] - c) <= 1e-14;
}

/* z_j = lo_j + (hi_j - lo_j)(1 + sin u_j)/2 on [0, 1] at the start u = asin(2 z - 1) plus the
 * first simplex step 0.2 (src/analysis/certify.c's coordinates and SIMPLEX_STEP) */
static double stepped(double z) { return 0.5 * (1.0 + sin(asin(2.0 * z - 1.0) + 0.2)); }

/* first index >= from where a refinement starts at (a, b, c): the start itself, then the
 * simplex's first vertex moved by 0.2 in the first free coordinate (xi here) */
static long refinement_from(long from, double a, double b, double c) {
  for (long p = from; p + 1 < D.calls && p + 1 < MAX_RECORDED; p++)
    if (near(D.pts[p], a, b, c) && near(D.pts[p + 1], stepped(a), b, c)) return p;
  return -1;
}

/* One gain of peak 4 at (xi, mu2) = (0.7, 0.32): 4/(1 + 10 r^2), r^2 = (xi - 0.7)^2 +
 * (mu2 - 0.32)^2; mu1 plays no part. */
static double peak(size_t i, const double *z) {
  double a = z[0] - 0.7, b = z[2] - 0.32;
  (void)i;
  return 4.0 / (1.0 + 10.0 * (a * a + b * b));
}

/* The box xi in [0, 1], mu1 = 0.5 fixed (a fixed coordinate between free ones), mu2 in [0, 1],
 * grid 5: the first 25 evaluations are the lattice {0, 1/4, 1/2, 3/4, 1}^2 x {0.5}, each point
 * once. By hand, r^2 at the lattice points nearest the peak: (3/4, 1/4) 0.0074, (3/4, 1/2)
 * 0.0349, (1/2, 1/4) 0.0449, the rest 0.0724 or more: the refinements start from these three,
 * in this order, the first right after the grid. The sup: 4/2 + 1 = 3 at (0.7, 0.5, 0.32). */
START_TEST(grid_then_refinements_from_best_three) {
  sdae_stepper *s = designed_stepper(1, 2, peak, NULL);
  const double lo[3] = {0.0, 0.5, 0.0}, hi[3] = {1.0, 0.5, 1.0};
  double sup[1], argmax[3];
  int seen[5][5] = {{0}};
  sdae_certificate c;
  long p1, p2, p3;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 5, sup, argmax, &c), SDAE_OK);
  ck_assert_int_gt(D.calls, 25);
  ck_assert_uint_eq(c.evaluations, (size_t)D.calls); /* every evaluation counted */
  for (long e = 0; e < 25; e++) {
    double a = D.pts[e][0] * 4.0, b = D.pts[e][2] * 4.0;
    ck_assert_double_eq(D.pts[e][1], 0.5);
    ck_assert_double_eq(a, floor(a));
    ck_assert_double_eq(b, floor(b));
    ck_assert(a >= 0.0 && a <= 4.0 && b >= 0.0 && b <= 4.0);
    seen[(int)a][(int)b]++;
  }
  for (int i = 0; i < 5; i++)
    for (int j = 0; j < 5; j++) ck_assert_int_eq(seen[i][j], 1);
  /* the first refinement from the best grid point, its simplex u, u + 0.2 e_j */
  ck_assert(near(D.pts[25], 0.75, 0.5, 0.25));
  ck_assert(near(D.pts[26], stepped(0.75), 0.5, 0.25));
  ck_assert(near(D.pts[27], 0.75, 0.5, stepped(0.25)));
  ck_assert_int_lt(D.calls, MAX_RECORDED);
  p1 = refinement_from(25, 0.75, 0.5, 0.25);
  p2 = refinement_from(p1 + 1, 0.75, 0.5, 0.5);
  ck_assert_int_eq(p1, 25);
  ck_assert_int_gt(p2, p1);
  p3 = refinement_from(p2 + 1, 0.5, 0.5, 0.25);
  ck_assert_int_gt(p3, p2);
  ck_assert(near(D.pts[p3 + 2], 0.5, 0.5, stepped(0.25)));
  /* the sup, to what the size 1e-12 of the simplex allows; T_bar by eq. 14 */
  ck_assert_double_le(fabs(sup[0] - 3.0), 1e-9);
  ck_assert_double_le(fabs(argmax[0] - 0.7), 1e-4);
  ck_assert_double_eq(argmax[1], 0.5);
  ck_assert_double_le(fabs(argmax[2] - 0.32), 1e-4);
  ck_assert_double_eq(c.sup_neg_k, sup[0]);
  ck_assert_double_le(fabs(c.T_bar - 2.0 / 3.0), 1e-9);
  sdae_stepper_free(s);
}
END_TEST

/* Two gains on mu in [0, 1] (xi = (0, 0) fixed): g_0 = 2/(1 + 10 (mu - 0.2)^2), g_1 =
 * 4/(1 + 10 (mu - 0.9)^2): sups -k = 2, 3 (eq. 6), the larger the last gain's. On the 4-point
 * grid (0, 1/3, 2/3, 1) g_1 is best at 1, where its refinement must start (u = pi/2, the
 * simplex's second vertex at (1 + cos 0.2)/2): the grid's best points of one gain are not
 * displaced by the other's refinement. */
static double two_gains(size_t i, const double *z) {
  double a = z[2] - (i ? 0.9 : 0.2);
  return (i ? 4.0 : 2.0) / (1.0 + 10.0 * a * a);
}

static const double LO2[3] = {0.0, 0.0, 0.0}, HI2[3] = {0.0, 0.0, 1.0};

START_TEST(two_gains_each_sup) {
  sdae_stepper *s = designed_stepper(2, 1, two_gains, NULL);
  double sup[2], argmax[6];
  sdae_certificate c;
  long p;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, LO2, HI2, 4, sup, argmax, &c), SDAE_OK);
  ck_assert_double_le(fabs(sup[0] - 2.0), 1e-9);
  ck_assert_double_le(fabs(sup[1] - 3.0), 1e-9);
  ck_assert_double_le(fabs(argmax[2] - 0.2), 1e-4); /* rows of (xi1, xi2, mu) */
  ck_assert_double_le(fabs(argmax[5] - 0.9), 1e-4);
  ck_assert_uint_eq(c.i_max, 1);
  ck_assert_double_eq(c.sup_neg_k, sup[1]);
  ck_assert_uint_eq(c.evaluations, (size_t)D.calls);
  ck_assert_int_lt(D.calls, MAX_RECORDED);
  for (p = 4; p + 1 < D.calls; p++)
    if (D.pts[p][2] == 1.0 && fabs(D.pts[p + 1][2] - 0.5 * (1.0 + cos(0.2))) <= 1e-14) break;
  ck_assert_int_lt(p + 1, D.calls);
  sdae_stepper_free(s);
}
END_TEST

/* Two gains with the same sup: g_i = 2/(1 + 10 (mu - 0.2)^2) for both, so both sups are
 * 2/2 + 1 = 2 at mu = 0.2 (eq. 6) and the certificate names the first (certify.h). */
static double twin_gains(size_t i, const double *z) {
  double a = z[2] - 0.2;
  (void)i;
  return 2.0 / (1.0 + 10.0 * a * a);
}

START_TEST(tied_gains_name_the_first) {
  sdae_stepper *s = designed_stepper(2, 1, twin_gains, NULL);
  double sup[2];
  sdae_certificate c;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, LO2, HI2, 4, sup, NULL, &c), SDAE_OK);
  ck_assert_double_eq(sup[0], sup[1]); /* the same function, the same search */
  ck_assert_double_le(fabs(sup[0] - 2.0), 1e-9);
  ck_assert_uint_eq(c.i_max, 0);
  sdae_stepper_free(s);
}
END_TEST

/* A box that is a point: the grid has grid^0 = 1 point and nothing is free to refine, so the
 * search spends exactly one evaluation, whatever the grid; the sup is -k there. */
START_TEST(point_box_one_evaluation) {
  sdae_stepper *s = designed_stepper(1, 2, peak, NULL);
  const double pt[3] = {0.7, 0.1, 0.32};
  double sup[1], argmax[3];
  sdae_certificate c;
  for (unsigned grid = 2; grid <= 7; grid += 5) {
    D.calls = 0;
    ck_assert_int_eq(sdae_certify_box(s, 0.0, pt, pt, grid, sup, argmax, &c), SDAE_OK);
    ck_assert_uint_eq(c.evaluations, 1);
    ck_assert_int_eq(D.calls, 1);
    ck_assert_double_eq(sup[0], 3.0); /* 4/2 + 1, at the peak itself */
    ck_assert_mem_eq(argmax, pt, sizeof pt);
  }
  sdae_stepper_free(s);
}
END_TEST

/* The gain failing at its k-th evaluation, for k over a whole search (grid, refinements of
 * both gains: every k up to 40, then every 41st, and the last four, which keeps it fast under
 * valgrind): the callback's status comes back (> 0 recoverable, < 0 fatal), nothing is
 * evaluated after it, and the outputs are untouched. */
START_TEST(gain_failure_at_every_evaluation) {
  sdae_stepper *s = designed_stepper(2, 1, two_gains, NULL);
  sdae_certificate c;
  double sup[2], argmax[6];
  unsigned char pattern[sizeof c];
  long total;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, LO2, HI2, 4, sup, argmax, &c), SDAE_OK);
  total = D.calls;
  memset(pattern, 0xA5, sizeof pattern);
  ck_assert_int_gt(total, 100);
  for (long k = 1; k <= total; k += k < 40 || k > total - 4 ? 1 : 41) {
    int fatal = k % 2 == 0;
    memset(&c, 0xA5, sizeof c), memset(sup, 0xA5, sizeof sup), memset(argmax, 0xA5, sizeof argmax);
    D.calls = 0, D.fail_at = k, D.fail_rc = fatal ? -1 : 1;
    ck_assert_int_eq(sdae_certify_box(s, 0.0, LO2, HI2, 4, sup, argmax, &c),
                     fatal ? SDAE_ERR_CALLBACK_FATAL : SDAE_ERR_CALLBACK_RECOVERABLE);
    ck_assert_int_eq(D.calls, k);
    ck_assert_mem_eq(&c, pattern, sizeof c);
    ck_assert_mem_eq(sup, pattern, sizeof sup);
    ck_assert_mem_eq(argmax, pattern, sizeof argmax);
  }
  D.fail_at = 0;
  sdae_stepper_free(s);
}
END_TEST

/* The arguments: each NULL, grid 1 (a grid needs both ends) refused and 2 accepted, a
 * non-finite time, the last coordinate's bound reversed or not finite; the outputs untouched. */
START_TEST(arguments_checked) {
  sdae_stepper *s = designed_stepper(1, 2, peak, NULL);
  double lo[3] = {0.0, 0.5, 0.0}, hi[3] = {1.0, 0.5, 1.0}, sup[1] = {-7.0};
  sdae_certificate c = {.T_bar = -7.0};
  ck_assert_int_eq(sdae_certify_box(NULL, 0.0, lo, hi, 3, sup, NULL, &c), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, NULL, hi, 3, sup, NULL, &c), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, NULL, 3, sup, NULL, &c), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 3, sup, NULL, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 1, sup, NULL, &c), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 0, sup, NULL, &c), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_certify_box(s, NAN, lo, hi, 3, sup, NULL, &c), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_certify_box(s, INFINITY, lo, hi, 3, sup, NULL, &c), SDAE_ERR_PARAM);
  lo[2] = 1.5; /* the last coordinate reversed */
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 3, sup, NULL, &c), SDAE_ERR_PARAM);
  lo[2] = -INFINITY;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 3, sup, NULL, &c), SDAE_ERR_PARAM);
  lo[2] = 0.0, hi[2] = NAN;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 3, sup, NULL, &c), SDAE_ERR_PARAM);
  ck_assert_int_eq(D.calls, 0); /* nothing evaluated */
  ck_assert_double_eq(sup[0], -7.0);
  ck_assert_double_eq(c.T_bar, -7.0);
  hi[2] = 1.0;
  /* grid 2: the box's corners, then the refinement */
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 2, sup, NULL, &c), SDAE_OK);
  ck_assert_double_le(fabs(sup[0] - 3.0), 1e-9);
  sdae_stepper_free(s);
}
END_TEST

/* The search's block comes from the stepper's allocator; one that hands out blocks full of
 * 0x7F bytes (finite doubles near 3.4e306, as reused memory may hold) must give the same sup:
 * the search writes every value before it reads it. */
static void *dirty_alloc(void *ud, size_t size) {
  void *p = malloc(size);
  (void)ud;
  if (p) memset(p, 0x7F, size);
  return p;
}

static void dirty_free(void *ud, void *ptr, size_t size) {
  (void)ud, (void)size;
  free(ptr);
}

START_TEST(dirty_block_same_certificate) {
  sdae_allocator a = {dirty_alloc, dirty_free, NULL};
  double sup[2], argmax[6], sup_d[2], argmax_d[6];
  sdae_certificate c, c_d;
  for (unsigned grid = 2; grid <= 4; grid++) {
    sdae_stepper *s = designed_stepper(2, 1, two_gains, NULL);
    ck_assert_int_eq(sdae_certify_box(s, 0.0, LO2, HI2, grid, sup, argmax, &c), SDAE_OK);
    sdae_stepper_free(s);
    s = designed_stepper(2, 1, two_gains, &a);
    ck_assert_int_eq(sdae_certify_box(s, 0.0, LO2, HI2, grid, sup_d, argmax_d, &c_d), SDAE_OK);
    sdae_stepper_free(s);
    ck_assert_double_le(fabs(sup_d[0] - 2.0), 1e-9); /* the sups of two_gains, by hand */
    ck_assert_double_le(fabs(sup_d[1] - 3.0), 1e-9);
    ck_assert_mem_eq(sup_d, sup, sizeof sup);
    ck_assert_mem_eq(argmax_d, argmax, sizeof argmax);
    ck_assert_uint_eq(c_d.evaluations, c.evaluations);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("certify");
  ADD_CASE(s, eq24_printed_Q_gives_188_9);
  ADD_CASE(s, eq24_corrected_Q_gives_189_245);
  ADD_CASE(s, refinement_finds_interior_sup);
  ADD_CASE(s, T_bar_on_constant_gain);
  ADD_CASE(s, bad_box_is_refused);
  ADD_CASE(s, cond18_matches_energy_balance);
  ADD_CASE(s, grid_then_refinements_from_best_three);
  ADD_CASE(s, two_gains_each_sup);
  ADD_CASE(s, tied_gains_name_the_first);
  ADD_CASE(s, point_box_one_evaluation);
  ADD_CASE(s, gain_failure_at_every_evaluation);
  ADD_CASE(s, arguments_checked);
  ADD_CASE(s, dirty_block_same_certificate);
  return run_suite(s);
}
