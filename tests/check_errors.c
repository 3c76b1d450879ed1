/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Every bad input gets its named status, and a failed step leaves xi and mu exactly as they
 * were. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "testmodels.h"

static sdae_model model;
static sdae_options opt;
static quartic params = {1.0, 0.0, 0, 0};

static void reset(void) {
  params = (quartic){1.0, 0.0, 0, 0};
  model = quartic_model(&params);
  opt = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
}

/* alloc, init and size must agree on every invalid configuration */
static void expect_config(int want) {
  sdae_stepper *s = (sdae_stepper *)&params; /* any non-NULL value: must stay untouched */
  sdae_stepper *before = s;
  static max_align_t mem[512];
  ck_assert_int_eq(sdae_stepper_alloc(&s, &model, &opt), want);
  ck_assert_ptr_eq(s, before);
  ck_assert_int_eq(sdae_stepper_init(&s, mem, sizeof mem, &model, &opt), want);
  ck_assert_ptr_eq(s, before);
  ck_assert_uint_eq(sdae_stepper_size(&model, &opt), 0);
  reset();
}

static int overflow_Q_apply(double t, const double *xi, const double *mu, double *Qxi,
                            double *qnorm2, void *p) {
  (void)t, (void)xi, (void)mu, (void)Qxi, (void)qnorm2, (void)p;
  return -1; /* never called: the configuration is refused */
}

START_TEST(bad_model) {
  reset();
  ck_assert_int_eq(sdae_stepper_alloc(NULL, &model, &opt), SDAE_ERR_NULL);
  ck_assert_uint_eq(sdae_stepper_size(NULL, &opt), 0);
  ck_assert_uint_eq(sdae_stepper_size(&model, NULL), 0);
  model.n_xi = 0, expect_config(SDAE_ERR_DIM);
  model.n_mu = 0, expect_config(SDAE_ERR_DIM);
  model.q0 = NULL, expect_config(SDAE_ERR_NULL);
  model.Q = NULL, expect_config(SDAE_ERR_NULL);
}
END_TEST

START_TEST(bad_options) {
  const double bad[4] = {0.0, -1.0, NAN, INFINITY};
  reset();
  for (int i = 0; i < 4; i++) {
    opt.delta = bad[i], expect_config(SDAE_ERR_PARAM);
    opt.epsilon = bad[i], expect_config(SDAE_ERR_PARAM);
    opt.newton_tol = bad[i], expect_config(SDAE_ERR_PARAM);
  }
  opt.newton_max_iter = 0, expect_config(SDAE_ERR_PARAM);
  opt.scheme = (sdae_scheme)12, expect_config(SDAE_ERR_OPTION);
  opt.stabilizer = (sdae_stabilizer)7, expect_config(SDAE_ERR_OPTION);
  for (int j = 0; j < SDAE_MAX_REL_DEGREE; j++) { /* every alpha, the unused ones too */
    opt.stabilizer = SDAE_STAB_BAUMGARTE, opt.baumgarte_alpha[j] = NAN;
    expect_config(SDAE_ERR_PARAM);
    opt.stabilizer = SDAE_STAB_BAUMGARTE, opt.baumgarte_alpha[j] = -INFINITY;
    expect_config(SDAE_ERR_PARAM);
  }
}
END_TEST

START_TEST(map_without_callbacks) {
  reset();
  opt.map = NULL, expect_config(SDAE_ERR_MAP);
  opt.map = sdae_map_dgrad, model.H = NULL, expect_config(SDAE_ERR_MAP);
  opt.map = sdae_map_dgrad, model.grad_H = NULL, expect_config(SDAE_ERR_MAP);
  opt.map = sdae_map_dgrad, model.S = NULL, expect_config(SDAE_ERR_MAP);
  opt.map = sdae_map_dg4, model.S = NULL, expect_config(SDAE_ERR_MAP); /* nor S_apply */
  opt.map = sdae_map_user, model.user_phi = NULL, expect_config(SDAE_ERR_MAP);
  ck_assert_str_eq(sdae_map_name(sdae_map_dgrad), "dgrad");
}
END_TEST

/* Each relative degree must be in 1..SDAE_MAX_REL_DEGREE even when they sum to n_xi: {0, 2}
 * (n_xi = 2) and {5} (n_xi = 5) are refused. */
START_TEST(baselines_need_rel_degree) {
  static const unsigned three[1] = {3}, zero[1] = {0}, five[2] = {5, 1};
  static const unsigned zero_two[2] = {0, 2}, max_plus_one[1] = {SDAE_MAX_REL_DEGREE + 1};
  static const unsigned one[1] = {1};
  const sdae_stabilizer st[2] = {SDAE_STAB_NONE, SDAE_STAB_BAUMGARTE};
  reset();
  for (int i = 0; i < 2; i++) { /* degrees short of n_xi = 2: the chain would miss a row */
    opt.stabilizer = st[i], model.n_constraints = 1, model.rel_degree = one;
    expect_config(SDAE_ERR_REL_DEGREE);
  }
  for (int i = 0; i < 2; i++) {
    opt.stabilizer = st[i], model.rel_degree = NULL, expect_config(SDAE_ERR_REL_DEGREE);
    opt.stabilizer = st[i], model.rel_degree = three, expect_config(SDAE_ERR_REL_DEGREE);
    opt.stabilizer = st[i], model.rel_degree = zero, expect_config(SDAE_ERR_REL_DEGREE);
    opt.stabilizer = st[i], model.n_constraints = 2, model.rel_degree = five;
    expect_config(SDAE_ERR_REL_DEGREE);
    opt.stabilizer = st[i], model.n_constraints = 0, expect_config(SDAE_ERR_REL_DEGREE);
    opt.stabilizer = st[i], model.n_constraints = 2, model.rel_degree = zero_two;
    expect_config(SDAE_ERR_REL_DEGREE);
    opt.stabilizer = st[i], model.n_xi = SDAE_MAX_REL_DEGREE + 1, model.rel_degree = max_plus_one;
    expect_config(SDAE_ERR_REL_DEGREE);
  }
}
END_TEST

/* The caller's block: too small by one byte is refused; exactly the size works, even at an
 * address that is not aligned for double. */
START_TEST(caller_buffer) {
  reset();
  size_t need = sdae_stepper_size(&model, &opt);
  char *mem = malloc(need + 1 + 64);
  sdae_stepper *s = NULL;
  double xi[2] = {0.1, 0.2}, mu[2] = {0.3, 0.4};
  ck_assert_uint_gt(need, 0);
  ck_assert_int_eq(sdae_stepper_init(&s, mem + 1, need - 1, &model, &opt), SDAE_ERR_BUFFER);
  ck_assert_ptr_null(s);
  ck_assert_int_eq(sdae_stepper_init(&s, NULL, need, &model, &opt), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_stepper_init(NULL, mem, need, &model, &opt), SDAE_ERR_NULL);
  memset(mem + 1 + need, 0x5A, 64); /* a canary after the block: the stepper stays inside */
  ck_assert_int_eq(sdae_stepper_init(&s, mem + 1, need, &model, &opt), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.01, xi, mu), SDAE_OK);
  for (int i = 0; i < 64; i++) ck_assert_int_eq((unsigned char)mem[1 + need + i], 0x5A);
  sdae_stepper_free(s); /* a no-op for the caller's memory */
  sdae_stepper_free(NULL);
  free(mem);
}
END_TEST

/* Every map in every shape (n_xi below, equal to and above n_mu) in a caller's block of exactly
 * sdae_stepper_size bytes, at an address aligned for nothing, between two canaries: a step
 * writes inside the block alone. The model: n_mu / 2 oscillators, q0 = J mu, H = |mu|^2 / 2,
 * S = J, the user map the midpoint rule, Q of fixed nonzero entries. */
typedef struct shape {
  size_t n_xi, n_mu;
} shape;

static int osc_q0(double t, const double *mu, double *out, void *p) {
  const shape *sh = p;
  size_t m = sh->n_mu / 2;
  (void)t;
  for (size_t i = 0; i < m; i++) out[i] = mu[m + i], out[m + i] = -mu[i];
  return 0;
}

static int osc_Q(double t, const double *xi, const double *mu, double *out, void *p) {
  const shape *sh = p;
  (void)t, (void)xi, (void)mu;
  for (size_t r = 0; r < sh->n_mu; r++)
    for (size_t c = 0; c < sh->n_xi; c++) out[r * sh->n_xi + c] = 1.0 / (double)(1 + r + c);
  return 0;
}

static int osc_H(double t, const double *mu, double *out, void *p) {
  const shape *sh = p;
  (void)t;
  *out = 0.0;
  for (size_t i = 0; i < sh->n_mu; i++) *out += 0.5 * mu[i] * mu[i];
  return 0;
}

static int osc_grad_H(double t, const double *mu, double *out, void *p) {
  const shape *sh = p;
  (void)t;
  memcpy(out, mu, sh->n_mu * sizeof *out);
  return 0;
}

static int osc_S(double t, const double *mu, double *out, void *p) {
  const shape *sh = p;
  size_t n = sh->n_mu, m = n / 2;
  (void)t, (void)mu;
  memset(out, 0, n * n * sizeof *out);
  for (size_t i = 0; i < m; i++) out[i * n + m + i] = 1.0, out[(m + i) * n + i] = -1.0;
  return 0;
}

static int osc_user_phi(double t, double T, const double *mu, const double *mu_next, double *out,
                        void *p) {
  const shape *sh = p;
  size_t m = sh->n_mu / 2;
  (void)t, (void)T;
  for (size_t i = 0; i < m; i++) {
    out[i] = 0.5 * (mu[m + i] + mu_next[m + i]);
    out[m + i] = -0.5 * (mu[i] + mu_next[i]);
  }
  return 0;
}

#define CANARY 64
START_TEST(every_map_and_shape_stays_inside_its_block) {
  const char *maps[] = {"euler", "midpoint",  "dgrad",     "user", "dg4",
                        "dg6",   "midpoint4", "midpoint6", "rk4",  "rk8"};
  const shape shapes[] = {{1, 4}, {2, 2}, {5, 2}, {3, 6}};
  for (size_t k = 0; k < sizeof shapes / sizeof *shapes; k++)
    for (size_t i = 0; i < sizeof maps / sizeof *maps; i++) {
      shape sh = shapes[k];
      sdae_model m = {.n_xi = sh.n_xi,
                      .n_mu = sh.n_mu,
                      .q0 = osc_q0,
                      .Q = osc_Q,
                      .H = osc_H,
                      .grad_H = osc_grad_H,
                      .S = osc_S,
                      .user_phi = osc_user_phi,
                      .params = &sh};
      sdae_options o;
      sdae_stepper *s = NULL;
      double xi[5] = {1e-3, -2e-3, 3e-3, -1e-3, 2e-3}, mu[6] = {1.0, 0.5, -0.25, 0.0, 0.5, 1.0};
      sdae_options_default(&o);
      o.map = sdae_map_by_name(maps[i]);
      size_t need = sdae_stepper_size(&m, &o);
      ck_assert_uint_gt(need, 0);
      unsigned char *mem = malloc(need + 2 * CANARY + 1), *block = mem + CANARY + 1;
      memset(mem, 0x5A, need + 2 * CANARY + 1);
      ck_assert_int_eq(sdae_stepper_init(&s, block, need, &m, &o), SDAE_OK);
      for (int n = 0; n < 5; n++) ck_assert_int_eq(sdae_step(s, 0.1 * n, 0.1, xi, mu), SDAE_OK);
      for (size_t b = 0; b < CANARY + 1; b++) ck_assert_uint_eq(mem[b], 0x5A);
      for (size_t b = 0; b < CANARY; b++) ck_assert_uint_eq(block[need + b], 0x5A);
      free(mem);
    }
}
END_TEST

/* ---- failing steps: the state must be bit-for-bit what it was ---- */

typedef enum { OK, Q0_FATAL, Q0_RECOVER, Q0_NAN, Q_FATAL, Q_INF, H_NAN, PHI_NAN } fault;
static fault inject;

static int faulty_q0(double t, const double *mu, double *out, void *p) {
  (void)t, (void)p;
  out[0] = inject == Q0_NAN ? NAN : mu[1];
  out[1] = -mu[0];
  return inject == Q0_FATAL ? -1 : inject == Q0_RECOVER ? 1 : 0;
}

static int faulty_Q(double t, const double *xi, const double *mu, double *out, void *p) {
  (void)t, (void)xi, (void)mu, (void)p;
  out[0] = inject == Q_INF ? INFINITY : -1.0, out[1] = 1.0, out[2] = 1.0, out[3] = 1.0;
  return inject == Q_FATAL ? -3 : 0;
}

static int faulty_H(double t, const double *mu, double *out, void *p) {
  (void)t, (void)p;
  out[0] = inject == H_NAN ? NAN : 0.5 * (mu[0] * mu[0] + mu[1] * mu[1]);
  return 0;
}

static int faulty_phi(double t, double T, const double *mu, const double *y, double *out, void *p) {
  (void)t, (void)T, (void)y, (void)p;
  out[0] = mu[1], out[1] = inject == PHI_NAN ? NAN : -mu[0];
  return 0;
}

static void expect_step(const sdae_map_type *map, fault f, double t, double T, double xi0,
                        double mu0, int want) {
  sdae_stepper *s;
  double xi[2] = {xi0, 0.25}, mu[2] = {mu0, -0.5};
  double xi_copy[2], mu_copy[2];
  reset();
  model.q0 = faulty_q0, model.Q = faulty_Q;
  opt.map = map, model.H = faulty_H, model.user_phi = faulty_phi;
  memcpy(xi_copy, xi, sizeof xi), memcpy(mu_copy, mu, sizeof mu);
  ck_assert_int_eq(sdae_stepper_alloc(&s, &model, &opt), SDAE_OK);
  inject = f;
  ck_assert_int_eq(sdae_step(s, t, T, xi, mu), want);
  inject = OK;
  ck_assert_int_eq(memcmp(xi, xi_copy, sizeof xi), 0);
  ck_assert_int_eq(memcmp(mu, mu_copy, sizeof mu), 0);
  sdae_stepper_free(s);
}

START_TEST(bad_step_arguments) {
  const double badT[4] = {0.0, -1.0, NAN, INFINITY};
  double xi[2] = {0, 0}, mu[2] = {0, 0};
  sdae_stepper *s;
  reset();
  ck_assert_int_eq(sdae_stepper_alloc(&s, &model, &opt), SDAE_OK);
  ck_assert_int_eq(sdae_step(NULL, 0.0, 0.1, xi, mu), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.1, NULL, mu), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.1, xi, NULL), SDAE_ERR_NULL);
  sdae_stepper_free(s);
  for (int i = 0; i < 4; i++)
    expect_step(sdae_map_euler, OK, 0.0, badT[i], 0.1, 0.2, SDAE_ERR_STEP);
  expect_step(sdae_map_euler, OK, NAN, 0.1, 0.1, 0.2, SDAE_ERR_PARAM);
  expect_step(sdae_map_euler, OK, 0.0, 0.1, NAN, 0.2, SDAE_ERR_STATE);
  expect_step(sdae_map_euler, OK, 0.0, 0.1, 0.1, -INFINITY, SDAE_ERR_STATE);
}
END_TEST

START_TEST(callback_failures) {
  const sdae_map_type *maps[3] = {sdae_map_euler, sdae_map_midpoint, sdae_map_dgrad};
  for (int i = 0; i < 3; i++) {
    int dg = maps[i] == sdae_map_dgrad; /* dgrad calls S grad H, not q0 */
    expect_step(maps[i], Q_FATAL, 0.0, 0.1, 0.1, 0.2, SDAE_ERR_CALLBACK_FATAL);
    expect_step(maps[i], Q_INF, 0.0, 0.1, 0.1, 0.2, SDAE_ERR_NONFINITE);
    if (dg) continue;
    expect_step(maps[i], Q0_FATAL, 0.0, 0.1, 0.1, 0.2, SDAE_ERR_CALLBACK_FATAL);
    expect_step(maps[i], Q0_RECOVER, 0.0, 0.1, 0.1, 0.2, SDAE_ERR_CALLBACK_RECOVERABLE);
    expect_step(maps[i], Q0_NAN, 0.0, 0.1, 0.1, 0.2, SDAE_ERR_NONFINITE);
  }
  expect_step(sdae_map_user, PHI_NAN, 0.0, 0.1, 0.1, 0.2, SDAE_ERR_NONFINITE);
}
END_TEST

/* The H callback writing NaN is caught inside the discrete gradient's difference quotient. */
static int unit_grad(double t, const double *mu, double *out, void *p) {
  (void)t, (void)p;
  out[0] = mu[0], out[1] = mu[1];
  return 0;
}

static int skew(double t, const double *mu, double *out, void *p) {
  (void)t, (void)mu, (void)p;
  out[0] = 0.0, out[1] = 1.0, out[2] = -1.0, out[3] = 0.0;
  return 0;
}

START_TEST(energy_callback_nan) {
  sdae_stepper *s;
  double xi[2] = {0.1, 0.25}, mu[2] = {0.2, -0.5};
  reset();
  model.q0 = faulty_q0, model.Q = faulty_Q;
  opt.map = sdae_map_dgrad, model.H = faulty_H, model.grad_H = unit_grad, model.S = skew;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &model, &opt), SDAE_OK);
  inject = H_NAN;
  ck_assert_int_eq(sdae_step(s, 0.0, 0.1, xi, mu), SDAE_ERR_NONFINITE);
  inject = OK;
  ck_assert_double_eq(xi[0], 0.1);
  ck_assert_double_eq(mu[1], -0.5);
  sdae_stepper_free(s);
}
END_TEST

/* Finite callbacks, but a state that overflows: the new state is refused. */
START_TEST(overflowing_state) {
  expect_step(sdae_map_euler, OK, 0.0, 1e300, 0.1, 1e300, SDAE_ERR_NONFINITE);
}
END_TEST

/* Dimensions whose workspace does not fit in size_t: the product n_mu x n_xi of a dense Q, and
 * (with Q_apply, no product) the byte count of n_mu-long arrays. Nothing is allocated. */
START_TEST(workspace_overflow) {
  reset();
  model.n_mu = SIZE_MAX / 2 + 1, expect_config(SDAE_ERR_OVERFLOW);
  model.n_mu = SIZE_MAX / 8, model.Q = NULL, model.Q_apply = overflow_Q_apply;
  expect_config(SDAE_ERR_OVERFLOW);
}
END_TEST

/* Baumgarte with scheme 15 solves (I - T A) xi+ = xi for the chain of a relative-degree-2
 * constraint, A = [[0, 1], [-alpha0, -alpha1]]: det = 1 + T alpha1 + T^2 alpha0 = 0 for
 * T = 1, alpha = (-1, 0). A named status and the state untouched. */
START_TEST(baumgarte_singular_chain) {
  sdae_stepper *s;
  double xi[2] = {0.1, 0.25}, mu[2] = {0.2, -0.5};
  reset();
  opt.stabilizer = SDAE_STAB_BAUMGARTE;
  opt.baumgarte_alpha[0] = -1.0, opt.baumgarte_alpha[1] = 0.0;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &model, &opt), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 1.0, xi, mu), SDAE_ERR_SINGULAR);
  ck_assert_double_eq(xi[0], 0.1);
  ck_assert_double_eq(xi[1], 0.25);
  ck_assert_double_eq(mu[0], 0.2);
  ck_assert_double_eq(mu[1], -0.5);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.5, xi, mu), SDAE_OK); /* det = 0.75 */
  sdae_stepper_free(s);
}
END_TEST

/* Condition (18)'s observer: bad arguments to its init, and a W that fails or writes NaN stops
 * the run (SDAE_STOPPED) with the reason in the status. */
static int W_nan(double t, const double *mu, double *out, void *p) {
  (void)t, (void)mu, (void)p;
  out[0] = NAN;
  return 0;
}

static int W_fails(double t, const double *mu, double *out, void *p) {
  (void)t, (void)mu, (void)p;
  out[0] = 1.0;
  return -2;
}

static void expect_cond18_stop(int (*W)(double, const double *, double *, void *), int want) {
  sdae_stepper *s;
  sdae_cond18 c;
  double xi[2] = {0.1, 0.25}, mu[2] = {0.2, -0.5}, prev[2];
  size_t done = 99;
  reset();
  ck_assert_int_eq(sdae_stepper_alloc(&s, &model, &opt), SDAE_OK);
  ck_assert_int_eq(sdae_cond18_init(&c, 2, W, &params, prev), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, 0.1, 10, 1, xi, mu, sdae_cond18_observe, &c, &done),
                   SDAE_STOPPED);
  ck_assert_uint_eq(done, 0);
  ck_assert_int_eq(c.status, want);
  sdae_stepper_free(s);
}

START_TEST(cond18_bad_input) {
  sdae_cond18 c;
  double prev[2];
  ck_assert_int_eq(sdae_cond18_init(NULL, 2, quartic_H, &params, prev), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_cond18_init(&c, 2, NULL, &params, prev), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_cond18_init(&c, 2, quartic_H, &params, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_cond18_init(&c, 0, quartic_H, &params, prev), SDAE_ERR_DIM);
  expect_cond18_stop(W_nan, SDAE_ERR_NONFINITE);
  expect_cond18_stop(W_fails, SDAE_ERR_CALLBACK_FATAL);
}
END_TEST

START_TEST(strerror_names_every_status) {
  for (int st = SDAE_ERR_PATTERN; st <= SDAE_STOPPED; st++) {
    const char *msg = sdae_strerror(st);
    ck_assert_ptr_nonnull(msg);
    ck_assert_str_ne(msg, "unknown status");
    for (int other = SDAE_ERR_PATTERN; other < st; other++)
      ck_assert_str_ne(msg, sdae_strerror(other));
  }
  ck_assert_str_eq(sdae_strerror(-999), "unknown status");
  /* each message names its own status (docs/errors.md) */
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_SINGULAR), "singular"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_NEWTON), "did not converge"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_NOMEM), "memory"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_STEP), "step size"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_BUFFER), "block"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_REL_DEGREE), "rel_degree"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_RANK), "rank"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_CHART), "chart"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_PHI_INV), "Phi^-1"));
  ck_assert_ptr_nonnull(strstr(sdae_strerror(SDAE_ERR_MASS), "mass matrix"));
}
END_TEST

/* xi and mu of different sizes (n_xi = 1, n_mu = 2): a NaN in mu's last entry is found by the
 * step and by the gains, which check n_mu values of mu and n_xi of xi */
static int q0_two(double t, const double *mu, double *out, void *p) {
  (void)t, (void)p;
  out[0] = mu[1], out[1] = -mu[0];
  return 0;
}

static int Q_two_by_one(double t, const double *xi, const double *mu, double *out, void *p) {
  (void)t, (void)xi, (void)mu, (void)p;
  out[0] = 1.0, out[1] = 0.0;
  return 0;
}

START_TEST(state_checked_in_its_own_sizes) {
  sdae_model m = {.n_xi = 1, .n_mu = 2, .q0 = q0_two, .Q = Q_two_by_one};
  sdae_options o;
  sdae_stepper *s;
  double xi[1] = {0.1}, mu[2] = {0.2, NAN}, k[1];
  sdae_options_default(&o);
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_step(s, 0.0, 0.01, xi, mu), SDAE_ERR_STATE);
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, xi, mu, k), SDAE_ERR_STATE);
  sdae_stepper_free(s);
}
END_TEST

/* The defaults stabdae.h documents: scheme 15, delta = epsilon = 1, the euler map, Newton's
 * tolerance 1e-14 and 20 iterations, dense (bandwidth 0), the paper's stabilizer, Baumgarte's
 * alpha = (1, 2) (critically damped at rate 1), the rest 0; and NULL is ignored. */
START_TEST(options_default_as_documented) {
  sdae_options o;
  memset(&o, 0x55, sizeof o);
  sdae_options_default(NULL);
  sdae_options_default(&o);
  ck_assert_int_eq(o.scheme, SDAE_SCHEME_SEMI_IMPLICIT);
  ck_assert_double_eq(o.delta, 1.0);
  ck_assert_double_eq(o.epsilon, 1.0);
  ck_assert_ptr_eq(o.map, sdae_map_euler);
  ck_assert_double_eq(o.newton_tol, 1e-14);
  ck_assert_uint_eq(o.newton_max_iter, 20);
  ck_assert_uint_eq(o.bandwidth, 0);
  ck_assert_int_eq(o.stabilizer, SDAE_STAB_PAPER);
  ck_assert_double_eq(o.baumgarte_alpha[0], 1.0);
  ck_assert_double_eq(o.baumgarte_alpha[1], 2.0);
  ck_assert_double_eq(o.baumgarte_alpha[2], 0.0);
  ck_assert_double_eq(o.baumgarte_alpha[3], 0.0);
}
END_TEST

/* sdae_stepper_gains refuses what sdae_step refuses, and a NULL k, writing nothing to k: a NULL
 * stepper or state or k is SDAE_ERR_NULL, a time not finite SDAE_ERR_PARAM, a state with NaN or
 * Inf SDAE_ERR_STATE (the Q callback, which ignores t, is never reached). */
START_TEST(gains_bad_arguments) {
  sdae_stepper *s;
  double xi[2] = {0.1, 0.2}, mu[2] = {0.3, 0.4}, bad_xi[2] = {0.1, NAN}, bad_mu[2] = {INFINITY, 0};
  double k[2] = {5.0, 5.0};
  reset();
  ck_assert_int_eq(sdae_stepper_alloc(&s, &model, &opt), SDAE_OK);
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, xi, mu, NULL), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_stepper_gains(NULL, 0.0, xi, mu, k), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, NULL, mu, k), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, xi, NULL, k), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_stepper_gains(s, NAN, xi, mu, k), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_stepper_gains(s, INFINITY, xi, mu, k), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, bad_xi, mu, k), SDAE_ERR_STATE);
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, xi, bad_mu, k), SDAE_ERR_STATE);
  ck_assert_double_eq(k[0], 5.0);
  ck_assert_double_eq(k[1], 5.0);
  /* and the good call: ||q_1||^2 = 1 + c^2 with c = 3 mu1^2 - 3 mu1 xi1 + xi1^2 = 0.19,
   * ||q_2||^2 = 2 (quartic.h, k = 1, d = 0): k = -(1/2) ||q||^2 - 1 */
  ck_assert_int_eq(sdae_stepper_gains(s, 0.0, xi, mu, k), SDAE_OK);
  ck_assert_double_le(fabs(k[0] - (-0.5 * (1.0 + 0.19 * 0.19) - 1.0)), 1e-15);
  ck_assert_double_eq(k[1], -2.0);
  sdae_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("errors");
  ADD_CASE(s, bad_model);
  ADD_CASE(s, bad_options);
  ADD_CASE(s, map_without_callbacks);
  ADD_CASE(s, baselines_need_rel_degree);
  ADD_CASE(s, caller_buffer);
  ADD_CASE(s, every_map_and_shape_stays_inside_its_block);
  ADD_CASE(s, bad_step_arguments);
  ADD_CASE(s, callback_failures);
  ADD_CASE(s, energy_callback_nan);
  ADD_CASE(s, overflowing_state);
  ADD_CASE(s, workspace_overflow);
  ADD_CASE(s, baumgarte_singular_chain);
  ADD_CASE(s, cond18_bad_input);
  ADD_CASE(s, strerror_names_every_status);
  ADD_CASE(s, state_checked_in_its_own_sizes);
  ADD_CASE(s, options_default_as_documented);
  ADD_CASE(s, gains_bad_arguments);
  return run_suite(s);
}
