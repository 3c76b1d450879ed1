/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Fuzz target for sdae_step: arbitrary bytes choose the scheme, map, stabilizer and options
 * and give every number (state, T, t, delta, epsilon, Newton tolerance, Baumgarte gains, the
 * model's stiffness and damping) as raw IEEE doubles, so NaN, Inf, huge, tiny and negative
 * values all come up. The model is the unit suites' (tests/fixtures/quartic.h): the paper's
 * oscillator (Section IV, corrected Q) with its discrete-gradient callbacks and the paper's
 * map. The target checks the library's contract itself and aborts on a breach:
 *   - the stepper is created exactly when the options are valid, and sdae_stepper_size agrees;
 *   - a step with a bad t, state or T gets SDAE_ERR_PARAM, SDAE_ERR_STATE, SDAE_ERR_STEP in
 *     that order; any other failure is one a step can meet (non-finite, singular, Newton);
 *   - a failed step leaves xi and mu bit for bit as they were, a successful one gives finite
 *     values;
 *   - the gains satisfy k_i <= -epsilon (eq. 6), scheme 15 never lets |xi_i| grow (Theorem 4:
 *     xi+ = xi / (1 - T k), 1 - T k >= 1) and scheme 11 gives xi+ = (1 + T k) xi (eq. 11);
 *   - a stepper built in a caller's block full of stale bytes steps bit for bit like a
 *     malloc'ed one.
 *
 * Input layout: byte 0 = choice bits (see `choice`), byte 1 = steps - 1 (low 3 bits) and
 * newton_max_iter (high 5 bits), byte 2 = more choice bits (`choice2`), then the doubles of
 * `numbers` in order, 8 bytes each, native byte order; missing bytes read as zero.
 * tests/fuzz/seeds.py writes the seed corpus. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "quartic.h"

#define REQUIRE(cond)                                                                              \
  do {                                                                                             \
    if (!(cond)) {                                                                                 \
      fprintf(stderr, "fuzz_step: contract broken at line %d: %s\n", __LINE__, #cond);             \
      abort();                                                                                     \
    }                                                                                              \
  } while (0)

enum choice {
  EXPLICIT = 1 << 0,     /* scheme 11 instead of 15 */
  MAP = 3 << 1,          /* euler, midpoint, dgrad, user */
  STABILIZER = 3 << 3,   /* paper, none, Baumgarte, paper */
  JACOBIAN = 1 << 5,     /* q0_jac (midpoint) and user_phi_jac (user) given */
  CALLER_BLOCK = 1 << 6, /* also step a stepper in a stale caller's block and compare */
  Q_APPLY = 1 << 7       /* the model gives Q_apply instead of Q */
};

enum choice2 {
  DG4 = 1 << 0,     /* the dgrad choice of MAP means dg4 */
  S_APPLY = 1 << 1, /* the model gives S_apply instead of S */
  DG6 = 1 << 2,     /* the dgrad choice of MAP means dg6 (before DG4) */
  HESSIAN = 1 << 3, /* the model gives hess_H */
  RK4 = 1 << 4,     /* the euler choice of MAP means rk4 */
  RK8 = 1 << 5      /* the euler choice of MAP means rk8 (before RK4) */
};

typedef struct numbers {
  double T, t, delta, epsilon, newton_tol, alpha0, alpha1, k, d, xi[2], mu[2];
} numbers;
#define N_NUMBERS 13

/* ---- reading the input ---- */

static double take_double(const uint8_t **p, size_t *n) {
  double v = 0.0;
  size_t k = *n < sizeof v ? *n : sizeof v;
  if (k == 0) return v;
  memcpy(&v, *p, k);
  *p += k, *n -= k;
  return v;
}

static void read_numbers(const uint8_t *p, size_t n, numbers *x) {
  double v[N_NUMBERS];
  for (int i = 0; i < N_NUMBERS; i++) v[i] = take_double(&p, &n);
  *x = (numbers){v[0], v[1], v[2], v[3],          v[4],          v[5],
                 v[6], v[7], v[8], {v[9], v[10]}, {v[11], v[12]}};
}

static int positive_finite(double v) { return isfinite(v) && v > 0.0; }

static int all_finite(const double *v, int n) {
  for (int i = 0; i < n; i++)
    if (!isfinite(v[i])) return 0;
  return 1;
}

static void configure(uint8_t c, uint8_t c2, unsigned max_iter, const numbers *x, quartic *osc,
                      sdae_model *m, sdae_options *o) {
  static const sdae_stabilizer stabilizers[4] = {SDAE_STAB_PAPER, SDAE_STAB_NONE,
                                                 SDAE_STAB_BAUMGARTE, SDAE_STAB_PAPER};
  const sdae_map_type *maps[4] = {sdae_map_euler, sdae_map_midpoint, sdae_map_dgrad, sdae_map_user};
  *osc = (quartic){x->k, x->d, 0, 0};
  *m = quartic_model(osc);
  if (c & Q_APPLY) m->Q = NULL, m->Q_apply = quartic_Q_apply;
  if (!(c & JACOBIAN)) m->q0_jac = NULL;
  if (c & JACOBIAN) m->user_phi_jac = quartic_paper_phi_jac;
  if (c2 & HESSIAN) m->hess_H = quartic_hess_H;
  if (c2 & S_APPLY) m->S = NULL, m->S_apply = quartic_S_apply;
  sdae_options_default(o);
  o->scheme = (c & EXPLICIT) ? SDAE_SCHEME_EXPLICIT : SDAE_SCHEME_SEMI_IMPLICIT;
  o->map = maps[(c & MAP) >> 1];
  if (o->map == sdae_map_dgrad && (c2 & (DG4 | DG6)))
    o->map = (c2 & DG6) ? sdae_map_dg6 : sdae_map_dg4;
  if (o->map == sdae_map_euler && (c2 & (RK4 | RK8)))
    o->map = (c2 & RK8) ? sdae_map_rk8 : sdae_map_rk4;
  o->stabilizer = stabilizers[(c & STABILIZER) >> 3];
  o->delta = x->delta;
  o->epsilon = x->epsilon;
  o->newton_tol = x->newton_tol;
  o->newton_max_iter = max_iter;
  o->baumgarte_alpha[0] = x->alpha0;
  o->baumgarte_alpha[1] = x->alpha1;
}

/* Every option the model and map need is given, so only the numbers can be invalid. */
static int options_valid(const sdae_options *o) {
  if (!positive_finite(o->delta) || !positive_finite(o->epsilon)) return 0;
  if (!positive_finite(o->newton_tol) || o->newton_max_iter == 0) return 0;
  if (o->stabilizer == SDAE_STAB_BAUMGARTE)
    for (int j = 0; j < SDAE_MAX_REL_DEGREE; j++)
      if (!isfinite(o->baumgarte_alpha[j])) return 0;
  return 1;
}

/* The status a step must get from its arguments alone, SDAE_OK when they are good. */
static int argument_status(double t, double T, const double *xi, const double *mu) {
  if (!isfinite(t)) return SDAE_ERR_PARAM;
  if (!all_finite(xi, 2) || !all_finite(mu, 2)) return SDAE_ERR_STATE;
  if (!positive_finite(T)) return SDAE_ERR_STEP;
  return SDAE_OK;
}

/* The xi rows of eq. 11 and 15 against the gains the stepper reports at the old state. */
static void check_xi_update(const sdae_options *o, const double *k, double T, const double *xi_old,
                            const double *xi) {
  for (int i = 0; i < 2; i++) {
    REQUIRE(k[i] <= -o->epsilon); /* eq. 6 */
    if (o->scheme == SDAE_SCHEME_SEMI_IMPLICIT) {
      REQUIRE(fabs(xi[i]) <= fabs(xi_old[i])); /* Theorem 4 */
    } else {
      double want = (1.0 + T * k[i]) * xi_old[i]; /* eq. 11 */
      REQUIRE(fabs(xi[i] - want) <= 4.0 * 2.220446049250313e-16 * fabs(want));
    }
  }
}

static void one_step(sdae_stepper *s, sdae_stepper *twin, const sdae_options *o, double t, double T,
                     double *xi, double *mu, unsigned long *good) {
  double xi_old[2], mu_old[2], xi_twin[2], mu_twin[2], k[2];
  int want = argument_status(t, T, xi, mu);
  int gains_ok = want == SDAE_OK && o->stabilizer == SDAE_STAB_PAPER &&
                 sdae_stepper_gains(s, t, xi, mu, k) == SDAE_OK;
  memcpy(xi_old, xi, sizeof xi_old), memcpy(mu_old, mu, sizeof mu_old);
  memcpy(xi_twin, xi, sizeof xi_twin), memcpy(mu_twin, mu, sizeof mu_twin);
  int rc = sdae_step(s, t, T, xi, mu);
  if (want != SDAE_OK)
    REQUIRE(rc == want);
  else
    REQUIRE(rc == SDAE_OK || rc == SDAE_ERR_NONFINITE || rc == SDAE_ERR_SINGULAR ||
            rc == SDAE_ERR_NEWTON);
  if (rc != SDAE_OK) {
    REQUIRE(memcmp(xi, xi_old, sizeof xi_old) == 0 && memcmp(mu, mu_old, sizeof mu_old) == 0);
  } else {
    REQUIRE(all_finite(xi, 2) && all_finite(mu, 2));
    if (gains_ok) check_xi_update(o, k, T, xi_old, xi);
    ++*good;
  }
  REQUIRE(sdae_stepper_stats(s)->steps == *good);
  if (twin) {
    REQUIRE(sdae_step(twin, t, T, xi_twin, mu_twin) == rc);
    REQUIRE(memcmp(xi, xi_twin, sizeof xi_twin) == 0 && memcmp(mu, mu_twin, sizeof mu_twin) == 0);
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static max_align_t block[512];
  uint8_t c = size > 0 ? data[0] : 0, b = size > 1 ? data[1] : 0, c2 = size > 2 ? data[2] : 0;
  unsigned steps = (b & 7u) + 1u, max_iter = b >> 3;
  numbers x;
  quartic osc;
  sdae_model m;
  sdae_options o;
  sdae_stepper *s = NULL, *twin = NULL;
  unsigned long good = 0;

  read_numbers(size > 3 ? data + 3 : data, size > 3 ? size - 3 : 0, &x);
  configure(c, c2, max_iter, &x, &osc, &m, &o);
  int valid = options_valid(&o), rc = sdae_stepper_alloc(&s, &m, &o);
  REQUIRE(valid ? rc == SDAE_OK : rc == SDAE_ERR_PARAM);
  REQUIRE((sdae_stepper_size(&m, &o) > 0) == valid);
  if (!valid) return 0;
  if (c & CALLER_BLOCK) {
    REQUIRE(sdae_stepper_size(&m, &o) <= sizeof block);
    memset(block, 0x7f, sizeof block); /* stale doubles near 1.4e306, never to be read */
    REQUIRE(sdae_stepper_init(&twin, block, sizeof block, &m, &o) == SDAE_OK);
  }
  for (unsigned i = 0; i < steps; i++)
    one_step(s, twin, &o, x.t + (double)i * x.T, x.T, x.xi, x.mu, &good);
  sdae_stepper_free(s);
  sdae_stepper_free(twin); /* the caller's block its own again */
  return 0;
}
