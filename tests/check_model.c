/* SPDX-License-Identifier: GPL-3.0-or-later */
/* sdae_check_model: the oscillator's normal form against its DAE (paper Section IV, m = 1):
 * x = (X, Y, Xdot, Ydot), f = (Xdot, Ydot, -k X^3 - d Xdot, -ga), g = (0, 0, 0, -1), h = Y,
 * Phi = (Y, Ydot, X + Y, Y + Xdot) (eq. 21). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/newton.h"
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
  d.n = 4; /* relative degrees that do not make n_xi = 2: none may be 0, they must sum to 2 */
  static const unsigned zero_two[2] = {0, 2}, three[1] = {3}, one_one[2] = {1, 1};
  m.rel_degree = zero_two, m.n_constraints = 2;
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 10, 1, 1e-6, NULL, &r),
                   SDAE_ERR_REL_DEGREE);
  static const unsigned one[1] = {1};
  m.rel_degree = one, m.n_constraints = 1; /* short of n_xi = 2 */
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 10, 1, 1e-6, NULL, &r),
                   SDAE_ERR_REL_DEGREE);
  m.rel_degree = three, m.n_constraints = 1;
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 10, 1, 1e-6, NULL, &r),
                   SDAE_ERR_REL_DEGREE);
  m.rel_degree = one_one, m.n_constraints = 0;
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, LO, HI, 10, 1, 1e-6, NULL, &r),
                   SDAE_ERR_REL_DEGREE);
}
END_TEST

/* ---- a probe DAE whose every residual is known in closed form ----
 * n = 4, Phi = identity (xi = (x1, x2), mu = (x3, x4)), a(t) = 1 + t, b(t) = 2 - t:
 *   f = (x2 + ec x1, -x1 + a x3, a x4 + b x1, -a x3 + x1 + x2),
 *   g = (0, b, 0, 0)                      one constraint h = x1 of relative degree 2, or
 *   g = [[b, 0], [0, 1], [0, 0], [0, 0]]  two, h = (x1, x2), relative degrees (1, 1);
 *   q0 = (a mu2, -a mu1),  Q = [[b, 0], [1, 1 + eq]],  Q_apply its product and column norms.
 * With ec = eg = eq = ei = 0 the normal form is exact: L_f xi1 = x2 = xi2, L_g x1 = 0 and
 * L_g mu = 0, mu' = (a x4 + b x1, -a x3 + x1 + x2) = q0 + Q xi. The deliberate errors:
 * L_f xi1 - xi2 = ec x1; g's last column gets eg in row eg_row (L_g of that coordinate = eg);
 * mu2's dynamics off by eq xi2; Phi_inv adds ei to x4. Every callback counts its calls and
 * the times it was given another t than p->t; the fail_at-th call of fail_cb fails as fail_mode
 * says (returning -1 or 1 without writing, or writing NaN or -Inf into out[0]). */
enum { CB_F, CB_G, CB_PHI, CB_PHI_INV, CB_PHI_JAC, CB_Q0, CB_Q, CB_Q_APPLY, CB_COUNT };
enum { FAIL_FATAL = 1, FAIL_RECOVERABLE, FAIL_NAN, FAIL_INF };

typedef struct probe {
  double t;
  long calls[CB_COUNT], wrong_t;
  int fail_cb, fail_mode;
  long fail_at;
  int two;
  double ec, eg, eq, ei;
  int eg_row;
} probe;

static double rate_a(double t) { return 1.0 + t; }
static double rate_b(double t) { return 2.0 - t; }

static int enter(probe *p, int cb, double t) {
  if (t != p->t) p->wrong_t++;
  p->calls[cb]++;
  if (cb != p->fail_cb || p->calls[cb] != p->fail_at) return 0;
  return p->fail_mode == FAIL_FATAL ? -1 : p->fail_mode == FAIL_RECOVERABLE ? 1 : 0;
}

static int leave(const probe *p, int cb, double *out) {
  if (cb == p->fail_cb && p->calls[cb] == p->fail_at) {
    if (p->fail_mode == FAIL_NAN) out[0] = NAN;
    if (p->fail_mode == FAIL_INF) out[0] = -INFINITY;
  }
  return 0;
}

static int probe_f(double t, const double *x, double *out, void *params) {
  probe *p = params;
  double a = rate_a(t), b = rate_b(t);
  int rc = enter(p, CB_F, t);
  if (rc) return rc;
  out[0] = x[1] + p->ec * x[0], out[1] = -x[0] + a * x[2];
  out[2] = a * x[3] + b * x[0], out[3] = -a * x[2] + x[0] + x[1];
  return leave(p, CB_F, out);
}

static int probe_g(double t, const double *x, double *out, void *params) {
  probe *p = params;
  size_t m = p->two ? 2 : 1;
  int rc = enter(p, CB_G, t);
  (void)x;
  if (rc) return rc;
  memset(out, 0, 4 * m * sizeof *out);
  if (p->two)
    out[0] = rate_b(t), out[3] = 1.0;
  else
    out[1] = rate_b(t);
  out[p->eg_row * m + m - 1] += p->eg;
  return leave(p, CB_G, out);
}

static int probe_Phi(double t, const double *x, double *z, void *params) {
  probe *p = params;
  int rc = enter(p, CB_PHI, t);
  if (rc) return rc;
  memcpy(z, x, 4 * sizeof *z);
  return leave(p, CB_PHI, z);
}

static int probe_Phi_inv(double t, const double *z, double *x, void *params) {
  probe *p = params;
  int rc = enter(p, CB_PHI_INV, t);
  if (rc) return rc;
  memcpy(x, z, 4 * sizeof *x);
  x[3] += p->ei;
  return leave(p, CB_PHI_INV, x);
}

static int probe_Phi_jac(double t, const double *x, double *J, void *params) {
  probe *p = params;
  int rc = enter(p, CB_PHI_JAC, t);
  (void)x;
  if (rc) return rc;
  for (int i = 0; i < 16; i++) J[i] = i % 5 == 0 ? 1.0 : 0.0;
  return leave(p, CB_PHI_JAC, J);
}

static int probe_q0(double t, const double *mu, double *out, void *params) {
  probe *p = params;
  int rc = enter(p, CB_Q0, t);
  if (rc) return rc;
  out[0] = rate_a(t) * mu[1], out[1] = -rate_a(t) * mu[0];
  return leave(p, CB_Q0, out);
}

static int probe_Q(double t, const double *xi, const double *mu, double *out, void *params) {
  probe *p = params;
  int rc = enter(p, CB_Q, t);
  (void)xi, (void)mu;
  if (rc) return rc;
  out[0] = rate_b(t), out[1] = 0.0, out[2] = 1.0, out[3] = 1.0 + p->eq;
  return leave(p, CB_Q, out);
}

static int probe_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                         void *params) {
  probe *p = params;
  double b = rate_b(t);
  int rc = enter(p, CB_Q_APPLY, t);
  (void)mu;
  if (rc) return rc;
  Qxi[0] = b * xi[0], Qxi[1] = xi[0] + (1.0 + p->eq) * xi[1];
  qnorm2[0] = b * b + 1.0, qnorm2[1] = (1.0 + p->eq) * (1.0 + p->eq);
  return leave(p, CB_Q_APPLY, Qxi);
}

static const unsigned DEG2[1] = {2}, DEG11[2] = {1, 1};

enum { USE_INV = 1, USE_JAC = 2, USE_APPLY = 4 };

static sdae_model probe_model(probe *p, int use) {
  sdae_model m = {.n_xi = 2, .n_mu = 2, .q0 = probe_q0, .params = p};
  if (use & USE_APPLY)
    m.Q_apply = probe_Q_apply;
  else
    m.Q = probe_Q;
  m.n_constraints = p->two ? 2 : 1;
  m.rel_degree = p->two ? DEG11 : DEG2;
  return m;
}

static sdae_dae probe_dae(probe *p, int use) {
  sdae_dae d = {4,
                p->two ? 2 : 1,
                probe_f,
                probe_g,
                probe_Phi,
                (use & USE_INV) ? probe_Phi_inv : NULL,
                (use & USE_JAC) ? probe_Phi_jac : NULL,
                p};
  return d;
}

static probe probe_at(double t) {
  probe p = {0};
  p.t = t, p.fail_cb = -1, p.eg_row = 3;
  return p;
}

/* the box [-1, 1]^4, and the point Z = (1, -1, 0, 1/2) as a box of its own, where every term
 * is a short dyadic number at t = 1/4 (a = 5/4, b = 7/4), so every residual is exact:
 * f(Z) = (-1 + ec, -1, 19/8, 0), q0 = (5/8, 0), Q xi = (7/4, 1 - (1 + eq)). Central
 * differences of the identity are exact at x1 = 1, x3 = 0, x4 = 1/2 (x +- h' both
 * representable), and column 2 (x2 = -1) reaches no checked row: J e_2 only feeds row xi2,
 * the end of the chain. */
static const double BLO[4] = {-1, -1, -1, -1}, BHI[4] = {1, 1, 1, 1};
static const double Z[4] = {1.0, -1.0, 0.0, 0.5};

static int run_probe(probe *p, int use, const double *lo, const double *hi, size_t npoints,
                     double tol, double *worst, sdae_check_report *r) {
  sdae_model m = probe_model(p, use);
  sdae_dae d = probe_dae(p, use);
  memset(r, 0xA5, sizeof *r); /* *r is written whole */
  return sdae_check_model(&m, &d, p->t, lo, hi, npoints, 11, tol, worst, r);
}

/* The exact normal form over the box, with every choice of Phi_inv (Newton or given), Phi_jac
 * (finite differences or given) and Q (dense or Q_apply), at t = 1/4 on a time-dependent DAE:
 * consistent to rounding (exact identity Jacobian, or central differences of the identity,
 * exact to a few ulps), and every callback given t itself (a time off by anything makes
 * q0(t') + Q(t) xi differ from L_f mu(t') by (b(t') - b(t)) x1 too). */
START_TEST(probe_exact_normal_form) {
  for (int use = 0; use < 8; use++) {
    probe p = probe_at(0.25);
    sdae_check_report r;
    ck_assert_int_eq(run_probe(&p, use, BLO, BHI, 40, 1e-9, NULL, &r), SDAE_OK);
    ck_assert_uint_eq(r.points, 40);
    ck_assert_int_eq(r.consistent, 1);
    for (int k = 0; k < 4; k++) ck_assert_double_le(r.residual[k], 1e-10);
    ck_assert_int_eq(p.wrong_t, 0); /* the time given to sdae_check_model, to every callback */
    ck_assert_int_gt(p.calls[CB_F] * p.calls[CB_G] * p.calls[CB_PHI] * p.calls[CB_Q0], 0);
    ck_assert_int_eq(p.calls[CB_PHI_INV] > 0, (use & USE_INV) != 0);
    ck_assert_int_eq(p.calls[CB_PHI_JAC] > 0, (use & USE_JAC) != 0);
    ck_assert_int_eq(p.calls[CB_Q] > 0, !(use & USE_APPLY));
    ck_assert_int_eq(p.calls[CB_Q_APPLY] > 0, (use & USE_APPLY) != 0);
  }
}
END_TEST

/* At Z every residual is exactly 0 (dyadic arithmetic, see Z), so even tol = DBL_TRUE_MIN is
 * met; no check is worse than another, so the report names the first, the inverse, at
 * component 0, and the worst point is Z. */
START_TEST(probe_exact_point_all_zero) {
  for (int use = 0; use < 8; use++) {
    probe p = probe_at(0.25);
    sdae_check_report r;
    double worst[4] = {9, 9, 9, 9};
    ck_assert_int_eq(run_probe(&p, use, Z, Z, 3, DBL_TRUE_MIN, worst, &r), SDAE_OK);
    for (int k = 0; k < 4; k++) ck_assert_double_eq(r.residual[k], 0.0);
    ck_assert_int_eq(r.consistent, 1);
    ck_assert_int_eq(r.worst_check, SDAE_CHECK_INVERSE);
    ck_assert_uint_eq(r.worst_index, 0);
    for (int j = 0; j < 4; j++) ck_assert_double_eq(worst[j], Z[j]);
  }
}
END_TEST

/* Q_22 = 1 + eq with eq = 2: at Z the dynamics of mu2 miss by L_f mu2 - q0_2 - (Q xi)_2 =
 * 0 - 0 - (1 - 3) = 2, relative to its terms: |J_4. f| = 0, |q0_2| = 0 and, for a dense Q,
 * |Q_21 xi1| + |Q_22 xi2| = 1 + 3, so 2/4 = 1/2 exactly; with Q_apply the library sees only
 * (Q xi)_2 = -2, so 2/2 = 1. Everything else is exact. tol at the residual itself passes
 * ("every residual <= tol"), the next double below it does not. */
START_TEST(probe_wrong_Q_residual_and_tol) {
  for (int use = 0; use < 8; use++) {
    probe p = probe_at(0.25);
    sdae_check_report r;
    double worst[4], want = (use & USE_APPLY) ? 1.0 : 0.5;
    p.eq = 2.0;
    ck_assert_int_eq(run_probe(&p, use, Z, Z, 2, want, worst, &r), SDAE_OK);
    ck_assert_double_eq(r.residual[SDAE_CHECK_DYNAMICS], want);
    ck_assert_double_eq(r.residual[SDAE_CHECK_INVERSE], 0.0);
    ck_assert_double_eq(r.residual[SDAE_CHECK_LG], 0.0);
    ck_assert_double_eq(r.residual[SDAE_CHECK_CHAIN], 0.0);
    ck_assert_int_eq(r.worst_check, SDAE_CHECK_DYNAMICS);
    ck_assert_uint_eq(r.worst_index, 3); /* mu2 is z's component 3 */
    ck_assert_int_eq(r.consistent, 1);   /* residual == tol */
    ck_assert_int_eq(run_probe(&p, use, Z, Z, 2, nextafter(want, 0.0), worst, &r), SDAE_OK);
    ck_assert_int_eq(r.consistent, 0);
  }
}
END_TEST

/* f1 = x2 + ec x1 with ec = -2: at Z, L_f xi1 - xi2 = -3 - (-1) = -2, relative to
 * |J_1. f| + |xi2| = 3 + 1: 1/2 exactly, at component 0. */
START_TEST(probe_wrong_chain_residual) {
  for (int use = 0; use < 8; use++) {
    probe p = probe_at(0.25);
    sdae_check_report r;
    p.ec = -2.0;
    ck_assert_int_eq(run_probe(&p, use, Z, Z, 1, 0.5, NULL, &r), SDAE_OK);
    ck_assert_double_eq(r.residual[SDAE_CHECK_CHAIN], 0.5);
    ck_assert_double_eq(r.residual[SDAE_CHECK_DYNAMICS], 0.0);
    ck_assert_int_eq(r.worst_check, SDAE_CHECK_CHAIN);
    ck_assert_uint_eq(r.worst_index, 0);
    ck_assert_int_eq(r.consistent, 1);
  }
}
END_TEST

/* L_g of one coordinate = eg = 3/4, its only term: relative residual 1, at that coordinate;
 * for mu1 (component 2, the first after xi), mu2 (the last), and in the last column of g with
 * two constraints. The check reads nothing past its block: an allocator whose blocks are
 * followed by 0xFF bytes changes nothing. */
static void *poisoned_alloc(void *ud, size_t size) {
  unsigned char *b = malloc(size + 64);
  (void)ud;
  if (b) memset(b, 0xFF, size + 64);
  return b;
}
static void poisoned_free(void *ud, void *ptr, size_t size) {
  (void)ud, (void)size;
  free(ptr);
}

START_TEST(probe_Lg_residual) {
  const sdae_allocator al = {poisoned_alloc, poisoned_free, NULL};
  for (int two = 0; two < 2; two++)
    for (int row = 2; row < 4; row++) {
      probe p = probe_at(0.25);
      sdae_check_report r;
      p.two = two, p.eg = 0.75, p.eg_row = row;
      sdae_model m = probe_model(&p, USE_JAC);
      sdae_dae d = probe_dae(&p, USE_JAC);
      ck_assert_int_eq(sdae_check_model_with(&m, &d, 0.25, BLO, BHI, 5, 3, 1e-6, NULL, &al, &r),
                       SDAE_OK);
      ck_assert_double_eq(r.residual[SDAE_CHECK_LG], 1.0);
      ck_assert_int_eq(r.worst_check, SDAE_CHECK_LG);
      ck_assert_uint_eq(r.worst_index, (size_t)row);
      ck_assert_int_eq(r.consistent, 0);
    }
}
END_TEST

/* Phi_inv adds ei to x4: at Zs = (1/2, -1/2, 0, 1/4), Phi(Phi_inv(z)) - z = ei e_4, relative
 * to the largest |z_i|, |Phi(x)_i|: ei = 1/4 gives 1/4 / 1/2 = 1/2, ei = 1 gives 1 / 5/4 =
 * 4/5. The dynamics at x = z + ei e_4 then miss by a ei in mu1, relative 5/16 / 43/16 and
 * 5/4 / 29/8, below those, so the inverse is the worst check. */
START_TEST(probe_wrong_inverse_residual) {
  static const double Zs[4] = {0.5, -0.5, 0.0, 0.25};
  const double ei[2] = {0.25, 1.0}, want[2] = {0.5, 0.8}, dyn[2] = {5.0 / 43.0, 10.0 / 29.0};
  for (int k = 0; k < 2; k++) {
    probe p = probe_at(0.25);
    sdae_check_report r;
    p.ei = ei[k];
    ck_assert_int_eq(run_probe(&p, USE_INV | USE_JAC, Zs, Zs, 1, 1e-6, NULL, &r), SDAE_OK);
    ck_assert_double_eq_tol(r.residual[SDAE_CHECK_INVERSE], want[k], 2 * DBL_EPSILON);
    ck_assert_double_eq_tol(r.residual[SDAE_CHECK_DYNAMICS], dyn[k], 2 * DBL_EPSILON);
    ck_assert_int_eq(r.worst_check, SDAE_CHECK_INVERSE);
    ck_assert_uint_eq(r.worst_index, 3); /* "the component of z where it was found": x4 */
    ck_assert_int_eq(r.consistent, 0);
  }
}
END_TEST

/* Relative degrees decide which rows are checked. With two constraints h = (x1, x2) of
 * relative degree 1 each, L_g x1 = (b, 0) and L_g x2 = (0, 1) are allowed and there is no
 * chain: consistent, even with f1 = x2 + x1 (no chain to break). Declared as one chain (2) the
 * same DAE has L_g xi1 = (b, 0) != 0: relative residual 1 at component 0, and the chain
 * L_f xi1 - xi2 = x1. Without rel_degree (n_constraints 0) xi is one chain of n_xi: the
 * one-constraint probe is consistent. */
START_TEST(probe_relative_degrees) {
  static const unsigned one_chain[1] = {2};
  for (int use = 0; use < 8; use++) {
    probe p = probe_at(0.25);
    sdae_check_report r;
    p.two = 1, p.ec = 1.0;
    sdae_model m = probe_model(&p, use);
    sdae_dae d = probe_dae(&p, use);
    ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, BLO, BHI, 20, 5, 1e-9, NULL, &r), SDAE_OK);
    ck_assert_int_eq(r.consistent, 1);
    for (int k = 0; k < 4; k++) ck_assert_double_le(r.residual[k], 1e-10);
    m.n_constraints = 1, m.rel_degree = one_chain;
    ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, Z, Z, 1, 5, 1e-9, NULL, &r), SDAE_OK);
    ck_assert_double_eq(r.residual[SDAE_CHECK_LG], 1.0);
    ck_assert_int_eq(r.worst_check, SDAE_CHECK_LG);
    ck_assert_uint_eq(r.worst_index, 0);
    /* L_f xi1 - xi2 = x1 = 1 against |f1| + |xi2| = 0 + 1 at Z */
    ck_assert_double_eq(r.residual[SDAE_CHECK_CHAIN], 1.0);

    p = probe_at(0.25);
    m = probe_model(&p, use), d = probe_dae(&p, use);
    m.n_constraints = 0, m.rel_degree = NULL;
    ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, BLO, BHI, 20, 5, 1e-9, NULL, &r), SDAE_OK);
    ck_assert_int_eq(r.consistent, 1);
  }
}
END_TEST

/* Every callback failing at each of its calls, in every configuration: the status says how
 * (< 0 fatal, > 0 recoverable, NaN or Inf non-finite), the check stops there (that callback
 * is not called again), the points finished before it are counted, and the report says
 * inconsistent. */
START_TEST(probe_every_failure_is_reported) {
  static const int uses[4] = {USE_INV | USE_JAC, 0, USE_JAC | USE_APPLY, USE_INV | USE_APPLY};
  static const int want[5] = {0, SDAE_ERR_CALLBACK_FATAL, SDAE_ERR_CALLBACK_RECOVERABLE,
                              SDAE_ERR_NONFINITE, SDAE_ERR_NONFINITE};
  const size_t npoints = 3;
  for (int u = 0; u < 4; u++)
    for (int cb = 0; cb < CB_COUNT; cb++) {
      probe clean = probe_at(0.25);
      sdae_check_report r;
      ck_assert_int_eq(run_probe(&clean, uses[u], BLO, BHI, npoints, 1e-9, NULL, &r), SDAE_OK);
      long n = clean.calls[cb], per_point = n / (long)npoints;
      ck_assert_int_eq(n, per_point * (long)npoints); /* every point makes the same calls */
      for (int mode = FAIL_FATAL; mode <= FAIL_INF; mode++)
        for (long k = 1; k <= n; k++) {
          probe p = probe_at(0.25);
          p.fail_cb = cb, p.fail_mode = mode, p.fail_at = k;
          ck_assert_int_eq(run_probe(&p, uses[u], BLO, BHI, npoints, 1e-9, NULL, &r), want[mode]);
          ck_assert_int_eq(p.calls[cb], k);
          ck_assert_uint_eq(r.points, (size_t)((k - 1) / per_point));
          ck_assert_int_eq(r.consistent, 0);
        }
    }
}
END_TEST

/* Bad arguments, each alone: a NULL pointer or callback, a zero or inconsistent dimension, a
 * tolerance not > 0 or not finite, a bound not finite or reversed (in the last coordinate
 * too); lo = hi is a box (a point). An m so large that the workspace (n m doubles for g) does
 * not fit in size_t is an overflow. */
START_TEST(probe_bad_arguments) {
  probe p = probe_at(0.25);
  sdae_model m = probe_model(&p, 0), m2;
  sdae_dae d = probe_dae(&p, 0), d2;
  sdae_check_report r;
  double lo[4], hi[4];
  ck_assert_int_eq(sdae_check_model(NULL, &d, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, NULL, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, BLO, NULL, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, NULL), SDAE_ERR_NULL);
  m2 = m, m2.q0 = NULL;
  ck_assert_int_eq(sdae_check_model(&m2, &d, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  m2 = m, m2.Q = NULL;
  ck_assert_int_eq(sdae_check_model(&m2, &d, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  m2.Q_apply = probe_Q_apply; /* either form of Q will do */
  ck_assert_int_eq(sdae_check_model(&m2, &d, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_OK);
  d2 = d, d2.f = NULL;
  ck_assert_int_eq(sdae_check_model(&m, &d2, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  d2 = d, d2.g = NULL;
  ck_assert_int_eq(sdae_check_model(&m, &d2, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  d2 = d, d2.Phi = NULL;
  ck_assert_int_eq(sdae_check_model(&m, &d2, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_NULL);
  m2 = m, m2.n_xi = 0;
  ck_assert_int_eq(sdae_check_model(&m2, &d, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_DIM);
  m2 = m, m2.n_mu = 0;
  ck_assert_int_eq(sdae_check_model(&m2, &d, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_DIM);
  d2 = d, d2.m = 0;
  ck_assert_int_eq(sdae_check_model(&m, &d2, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_DIM);
  d2 = d, d2.n = 3;
  ck_assert_int_eq(sdae_check_model(&m, &d2, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r), SDAE_ERR_DIM);
  d2 = d, d2.m = SIZE_MAX / 2;
  ck_assert_int_eq(sdae_check_model(&m, &d2, 0.25, BLO, BHI, 2, 1, 1e-9, NULL, &r),
                   SDAE_ERR_OVERFLOW);
  const double bad_tol[4] = {0.0, -1e-9, NAN, INFINITY};
  for (int k = 0; k < 4; k++)
    ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, BLO, BHI, 2, 1, bad_tol[k], NULL, &r),
                     SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, BLO, BHI, 2, 1, DBL_TRUE_MIN, NULL, &r), SDAE_OK);
  for (int j = 0; j < 4; j++) {
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++) {
      memcpy(lo, BLO, sizeof lo), memcpy(hi, BHI, sizeof hi);
      lo[j] = bad[k];
      ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, lo, hi, 2, 1, 1e-9, NULL, &r),
                       SDAE_ERR_PARAM);
      memcpy(lo, BLO, sizeof lo), hi[j] = bad[k];
      ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, lo, hi, 2, 1, 1e-9, NULL, &r),
                       SDAE_ERR_PARAM);
    }
    memcpy(lo, BLO, sizeof lo), memcpy(hi, BHI, sizeof hi);
    lo[j] = 0.5, hi[j] = 0.25;
    ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, lo, hi, 2, 1, 1e-9, NULL, &r), SDAE_ERR_PARAM);
    hi[j] = 0.5; /* lo = hi: that coordinate fixed */
    ck_assert_int_eq(sdae_check_model(&m, &d, 0.25, lo, hi, 2, 1, 1e-9, NULL, &r), SDAE_OK);
  }
}
END_TEST

/* The worst point is one of the box's and the chain residual there, recomputed from it (the
 * box lo = hi = worst), is the reported worst: f1 = x2 + x1 gives L_f xi1 - xi2 = x1,
 * relative |x1| / (|x1 + x2| + |x2|), the only residual. */
START_TEST(probe_worst_point) {
  for (int use = 0; use < 8; use++) {
    probe p = probe_at(0.25);
    sdae_check_report r, again;
    double worst[4], w2[4];
    p.ec = 1.0;
    ck_assert_int_eq(run_probe(&p, use, BLO, BHI, 30, 1e-6, worst, &r), SDAE_OK);
    ck_assert_int_eq(r.worst_check, SDAE_CHECK_CHAIN);
    ck_assert_uint_eq(r.worst_index, 0);
    for (int j = 0; j < 4; j++) {
      ck_assert_double_ge(worst[j], BLO[j]);
      ck_assert_double_le(worst[j], BHI[j]);
    }
    double x1 = worst[0], x2 = worst[1];
    ck_assert_double_eq_tol(r.residual[SDAE_CHECK_CHAIN], fabs(x1) / (fabs(x1 + x2) + fabs(x2)),
                            1e-9);
    ck_assert_int_eq(run_probe(&p, use, worst, worst, 1, 1e-6, w2, &again), SDAE_OK);
    ck_assert_double_eq_tol(again.residual[SDAE_CHECK_CHAIN], r.residual[SDAE_CHECK_CHAIN], 1e-9);
  }
}
END_TEST

/* ---- Newton's iteration for Phi^-1, with Phi_jac given ----
 * n = 2, xi = x1, mu = Phi_2(x); f = 0, g = (1, 0), q0 = 0, Q = 0 (no check but the inverse
 * matters here). Newton solves Phi(x) = z from x = z: x <- x - J^-1 (Phi(x) - z). */
enum { NEWTON_LADDER, NEWTON_CYCLE, NEWTON_SINGULAR };
typedef struct newton_dae {
  int kind;
  long phi_calls, jac_calls;
} newton_dae;

/* the stopping rule: an update of at most SDAE_NEWTON_TOL (1 + max_i |x_i|); with x1 = 1024
 * (and |x2| < 2) that is SDAE_NEWTON_TOL * 1025 at every iteration */
static const double LADDER_X1 = 1024.0;
static double ladder_thr(void) { return SDAE_NEWTON_TOL * (1.0 + LADDER_X1); }

/* Phi_2 for the ladder, with J = I given: from x2 = 0 Newton's updates are exactly 1, then
 * 5 thr (above the threshold, below 10 thr), then thr (at it), then 0 */
static double ladder(double x) {
  double thr = ladder_thr();
  if (x < 0.5) return -1.0;
  if (x < 1.0 + 2.5 * thr) return -5.0 * thr;
  if (x < 1.0 + 5.5 * thr) return -thr;
  return 0.0;
}

static int nd_Phi(double t, const double *x, double *z, void *params) {
  newton_dae *p = params;
  (void)t;
  p->phi_calls++;
  z[0] = x[0];
  if (p->kind == NEWTON_LADDER) z[1] = ladder(x[1]);
  if (p->kind == NEWTON_CYCLE) z[1] = x[1] * x[1] * x[1] - 2.0 * x[1] + 2.0;
  if (p->kind == NEWTON_SINGULAR) z[1] = x[1] * x[1] * x[1] + 1.0;
  return 0;
}

static int nd_Phi_jac(double t, const double *x, double *J, void *params) {
  newton_dae *p = params;
  (void)t;
  p->jac_calls++;
  J[0] = 1.0, J[1] = 0.0, J[2] = 0.0;
  J[3] = p->kind == NEWTON_LADDER  ? 1.0
         : p->kind == NEWTON_CYCLE ? 3.0 * x[1] * x[1] - 2.0
                                   : 3.0 * x[1] * x[1];
  return 0;
}

static int zero_f(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 0.0, out[1] = 0.0;
  return 0;
}
static int e1_g(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 1.0, out[1] = 0.0;
  return 0;
}
static int zero_q0(double t, const double *mu, double *out, void *params) {
  (void)t, (void)mu, (void)params;
  out[0] = 0.0;
  return 0;
}
static int zero_Q(double t, const double *xi, const double *mu, double *out, void *params) {
  (void)t, (void)xi, (void)mu, (void)params;
  out[0] = 0.0;
  return 0;
}

static int run_newton(newton_dae *p, const double *z, sdae_check_report *r) {
  sdae_model m = {.n_xi = 1, .n_mu = 1, .q0 = zero_q0, .Q = zero_Q};
  sdae_dae d = {2, 1, zero_f, e1_g, nd_Phi, NULL, nd_Phi_jac, p};
  return sdae_check_model(&m, &d, 0.0, z, z, 1, 1, 1e-9, NULL, r);
}

/* Updates 1, 5 thr, thr: Newton stops after the third (an update equal to the threshold
 * passes), having evaluated Phi three times, plus once for the inverse check at its answer,
 * where Phi(x) = z exactly; its matrix built at the first two iterates only (the update 5 thr
 * is below Newton's 1e-5 (1 + |x|): the matrix kept for the last one). */
START_TEST(newton_stops_at_threshold) {
  const double z[2] = {LADDER_X1, 0.0};
  newton_dae p = {NEWTON_LADDER, 0, 0};
  sdae_check_report r;
  ck_assert_int_eq(run_newton(&p, z, &r), SDAE_OK);
  ck_assert_int_eq(p.phi_calls, 3 + 1);
  ck_assert_int_eq(p.jac_calls, 2 + 1);
  ck_assert_double_eq(r.residual[SDAE_CHECK_INVERSE], 0.0);
  ck_assert_int_eq(r.consistent, 1);
}
END_TEST

/* Phi_2 = x^3 - 2x + 2 and z2 = 0: Newton from 0 goes to 1 (update 2/(-2)) and back to 0
 * (update 1/1), exactly, forever. It gives up at its cap, the library's SDAE_NEWTON_MAX_ITER
 * iterations (issue 16), with SDAE_ERR_NEWTON, no point checked. */
START_TEST(newton_gives_up_at_the_cap) {
  const double z[2] = {0.5, 0.0};
  newton_dae p = {NEWTON_CYCLE, 0, 0};
  sdae_check_report r;
  ck_assert_int_eq(run_newton(&p, z, &r), SDAE_ERR_NEWTON);
  ck_assert_int_eq(p.phi_calls, SDAE_NEWTON_MAX_ITER);
  ck_assert_int_eq(p.jac_calls, SDAE_NEWTON_MAX_ITER);
  ck_assert_uint_eq(r.points, 0);
  ck_assert_int_eq(r.consistent, 0);
}
END_TEST

/* Phi_2 = x^3 + 1 at z2 = 0, from x2 = 0: Newton's first matrix diag(1, 0) is singular */
START_TEST(newton_singular_jacobian) {
  const double z[2] = {0.5, 0.0};
  newton_dae p = {NEWTON_SINGULAR, 0, 0};
  sdae_check_report r;
  ck_assert_int_eq(run_newton(&p, z, &r), SDAE_ERR_SINGULAR);
  ck_assert_int_eq(p.phi_calls, 1);
  ck_assert_uint_eq(r.points, 0);
}
END_TEST

/* ---- the smallest scale ----
 * Phi = I (n = 2, xi = x1, mu = x2), f = (0, 1), g = (1, 0), q0 = 1: Q = 0 is exact, and this
 * Q = [2 DBL_TRUE_MIN] misses at z = (1, 0) by 2 DBL_TRUE_MIN against terms |J f| = 1,
 * |q0| = 1 (and |Q xi|, absorbed in rounding): a relative dynamics residual of exactly
 * DBL_TRUE_MIN (subnormal arithmetic is exact), the only one, so the smallest tolerance there
 * is, DBL_TRUE_MIN itself, accepts it ("every residual <= tol"). */
static int id2_Phi(double t, const double *x, double *z, void *params) {
  (void)t, (void)params;
  z[0] = x[0], z[1] = x[1];
  return 0;
}
static int id2_jac(double t, const double *x, double *J, void *params) {
  (void)t, (void)x, (void)params;
  J[0] = 1.0, J[1] = 0.0, J[2] = 0.0, J[3] = 1.0;
  return 0;
}
static int f01(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 0.0, out[1] = 1.0;
  return 0;
}
static int one_q0(double t, const double *mu, double *out, void *params) {
  (void)t, (void)mu, (void)params;
  out[0] = 1.0;
  return 0;
}
static int tiny_Q(double t, const double *xi, const double *mu, double *out, void *params) {
  (void)t, (void)xi, (void)mu, (void)params;
  out[0] = 2.0 * DBL_TRUE_MIN;
  return 0;
}

START_TEST(smallest_residual_meets_smallest_tol) {
  const double z[2] = {1.0, 0.0};
  sdae_model m = {.n_xi = 1, .n_mu = 1, .q0 = one_q0, .Q = tiny_Q};
  sdae_dae d = {2, 1, f01, e1_g, id2_Phi, id2_Phi, id2_jac, NULL};
  sdae_check_report r;
  ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, z, z, 1, 1, DBL_TRUE_MIN, NULL, &r), SDAE_OK);
  ck_assert_double_eq(r.residual[SDAE_CHECK_DYNAMICS], DBL_TRUE_MIN);
  ck_assert_double_eq(r.residual[SDAE_CHECK_INVERSE], 0.0);
  ck_assert_double_eq(r.residual[SDAE_CHECK_LG], 0.0);
  ck_assert_int_eq(r.worst_check, SDAE_CHECK_DYNAMICS);
  ck_assert_int_eq(r.consistent, 1);
}
END_TEST

/* ---- the finite-difference Jacobian's error ----
 * n = 2: xi = x1, mu = x1 + (x2 - s)^3, Phi^-1(z) = (z1, s + cbrt(z2 - z1)); f = (1, 1),
 * g = 0, q0(mu) = 1 + 3 cbrt(mu)^2, Q = 0: L_f mu = 1 + 3 (x2 - s)^2 = q0 on xi = 0. At
 * z = (0, 0), x = (0, s), the exact Jacobian row of mu is (1, 0); central differences with
 * step h give (1, ((h)^3 - (-h)^3) / 2h) = (1, h^2) exactly (a cubic's truncation error,
 * h^2 f'''/6), with h = eps^(1/3) max(1, |x2|) (the step that balances truncation and rounding,
 * as taken by the library: h' = (x + h) - x). So the dynamics residual is
 * h^2 / (|1| + |h^2| + |q0| = 2 + h^2), to the rounding of 1 + h^2 (1e-16, 1e-5 of it). */
static double cubic_s;
static int cu_f(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 1.0, out[1] = 1.0;
  return 0;
}
static int cu_g(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 0.0, out[1] = 0.0;
  return 0;
}
static int cu_Phi(double t, const double *x, double *z, void *params) {
  double u = x[1] - cubic_s;
  (void)t, (void)params;
  z[0] = x[0], z[1] = x[0] + u * u * u;
  return 0;
}
static int cu_Phi_inv(double t, const double *z, double *x, void *params) {
  (void)t, (void)params;
  x[0] = z[0], x[1] = cubic_s + cbrt(z[1] - z[0]);
  return 0;
}
static int cu_q0(double t, const double *mu, double *out, void *params) {
  double c = cbrt(mu[0]);
  (void)t, (void)params;
  out[0] = 1.0 + 3.0 * c * c;
  return 0;
}

START_TEST(fd_jacobian_error_is_h_squared) {
  const double s[2] = {2.0, 0.5}, z[2] = {0.0, 0.0};
  for (int k = 0; k < 2; k++) {
    sdae_model m = {.n_xi = 1, .n_mu = 1, .q0 = cu_q0, .Q = zero_Q};
    sdae_dae d = {2, 1, cu_f, cu_g, cu_Phi, cu_Phi_inv, NULL, NULL};
    sdae_check_report r;
    volatile double xp = s[k] + cbrt(DBL_EPSILON) * fmax(1.0, fabs(s[k]));
    double h = xp - s[k], want = h * h / (2.0 + h * h);
    cubic_s = s[k];
    ck_assert_int_eq(sdae_check_model(&m, &d, 0.0, z, z, 1, 1, 1e-9, NULL, &r), SDAE_OK);
    ck_assert_double_eq(r.residual[SDAE_CHECK_INVERSE], 0.0);
    ck_assert_double_eq(r.residual[SDAE_CHECK_LG], 0.0);
    ck_assert_double_le(fabs(r.residual[SDAE_CHECK_DYNAMICS] - want), 1e-4 * want);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("model");
  ADD_CASE(s, corrected_Q_is_consistent);
  ADD_CASE(s, printed_Q_is_flagged);
  ADD_CASE(s, wrong_inverse_is_flagged);
  ADD_CASE(s, coordinate_with_Lg_is_flagged);
  ADD_CASE(s, bad_arguments);
  ADD_CASE(s, probe_exact_normal_form);
  ADD_CASE(s, probe_exact_point_all_zero);
  ADD_CASE(s, probe_wrong_Q_residual_and_tol);
  ADD_CASE(s, probe_wrong_chain_residual);
  ADD_CASE(s, probe_Lg_residual);
  ADD_CASE(s, probe_wrong_inverse_residual);
  ADD_CASE(s, probe_relative_degrees);
  ADD_CASE(s, probe_every_failure_is_reported);
  ADD_CASE(s, probe_bad_arguments);
  ADD_CASE(s, probe_worst_point);
  ADD_CASE(s, newton_stops_at_threshold);
  ADD_CASE(s, newton_gives_up_at_the_cap);
  ADD_CASE(s, newton_singular_jacobian);
  ADD_CASE(s, fd_jacobian_error_is_h_squared);
  ADD_CASE(s, smallest_residual_meets_smallest_tol);
  return run_suite(s);
}
