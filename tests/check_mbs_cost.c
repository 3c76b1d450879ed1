/* SPDX-License-Identifier: GPL-3.0-or-later */
/* What a mechanical step costs (docs/front-ends.md, the cost of a step), counted callback by
 * callback on mechanisms whose every callback counts its calls: the derivatives along the
 * motion a mechanism gives replace the difference stencils (no stencil runs when all are
 * given). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "mechanisms.h"
#include "testmodels.h"
#include "wire.h"

/* ---- a mechanism counting its callbacks' calls ---- */

enum { C_MASS, C_FORCE, C_C, C_G, C_CT, C_V, C_MDV, C_GDOT, C_CTDOT, C_KINDS };

typedef struct counted {
  sdae_mbs in; /* the mechanism counted */
  unsigned long calls[C_KINDS];
} counted;

static int k_mass(double t, const double *q, double *M, void *p) {
  counted *k = p;
  k->calls[C_MASS]++;
  return k->in.mass(t, q, M, k->in.params);
}

static int k_force(double t, const double *q, const double *v, double *F, void *p) {
  counted *k = p;
  k->calls[C_FORCE]++;
  return k->in.force(t, q, v, F, k->in.params);
}

static int k_constraint(double t, const double *q, double *c, void *p) {
  counted *k = p;
  k->calls[C_C]++;
  return k->in.constraint(t, q, c, k->in.params);
}

static int k_jacobian(double t, const double *q, double *G, void *p) {
  counted *k = p;
  k->calls[C_G]++;
  return k->in.jacobian(t, q, G, k->in.params);
}

static int k_constraint_t(double t, const double *q, double *ct, void *p) {
  counted *k = p;
  k->calls[C_CT]++;
  return k->in.constraint_t(t, q, ct, k->in.params);
}

static int k_potential(double t, const double *q, double *V, void *p) {
  counted *k = p;
  k->calls[C_V]++;
  return k->in.potential(t, q, V, k->in.params);
}

static int k_mass_dot_v(double t, const double *q, const double *v, double *out, void *p) {
  counted *k = p;
  k->calls[C_MDV]++;
  return k->in.mass_dot_v(t, q, v, out, k->in.params);
}

static int k_jacobian_dot(double t, const double *q, const double *v, double *out, void *p) {
  counted *k = p;
  k->calls[C_GDOT]++;
  return k->in.jacobian_dot(t, q, v, out, k->in.params);
}

static int k_constraint_t_dot(double t, const double *q, const double *v, double *out, void *p) {
  counted *k = p;
  k->calls[C_CTDOT]++;
  return k->in.constraint_t_dot(t, q, v, out, k->in.params);
}

/* the counting mechanism around k->in: a callback it leaves out stays out */
static sdae_mbs counting(counted *k) {
  const sdae_mbs *in = &k->in;
  memset(k->calls, 0, sizeof k->calls);
  return (sdae_mbs){.n_q = in->n_q,
                    .n_c = in->n_c,
                    .mass = k_mass,
                    .force = k_force,
                    .constraint = k_constraint,
                    .jacobian = in->jacobian ? k_jacobian : NULL,
                    .constraint_t = in->constraint_t ? k_constraint_t : NULL,
                    .potential = in->potential ? k_potential : NULL,
                    .params = k,
                    .mass_dot_v = in->mass_dot_v ? k_mass_dot_v : NULL,
                    .jacobian_dot = in->jacobian_dot ? k_jacobian_dot : NULL,
                    .constraint_t_dot = in->constraint_t_dot ? k_constraint_t_dot : NULL};
}

/* the pendulum's constraint does not depend on t: dc/dt = 0 and its derivative 0, given */
static int zero_ct(double t, const double *q, double *ct, void *params) {
  (void)t, (void)q, (void)params;
  ct[0] = 0.0;
  return 0;
}

static int zero_ct_dot(double t, const double *q, const double *v, double *out, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  out[0] = 0.0;
  return 0;
}

static const mech_pendulum PENDULUM = {.L = 1.0, .m = 1.0, .ga = 9.81};

/* the pendulum with every derivative given (dc/dt = 0 too) */
static sdae_mbs pendulum_all(mech_pendulum *p) {
  sdae_mbs sys;
  mech_pendulum_system(&sys, p);
  sys.constraint_t = zero_ct;
  sys.constraint_t_dot = zero_ct_dot;
  return sys;
}

static sdae_options options(const sdae_map_type *map) {
  sdae_options o;
  sdae_options_default(&o);
  o.map = map;
  return o;
}

static sdae_mbs_stepper *stepper(const sdae_mbs *sys, const sdae_options *o) {
  sdae_mbs_stepper *s = NULL;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, sys, o), SDAE_OK);
  return s;
}

/* ---- the derivatives along the motion replace the stencils ---- */

/* lambda needs gamma = Gdot v + d/ds dc/dt, G, F and M at the state: with every derivative
 * given, one call each and no call of c or dc/dt; without jacobian_dot and constraint_t_dot,
 * G and dc/dt at the stencil's four points too */
START_TEST(lambda_calls_given_derivatives) {
  wire w = {.m = 1.3, .w = 0.7};
  counted k = {.in = wire_mbs(&w)};
  sdae_mbs sys = counting(&k);
  sdae_options o = options(sdae_map_euler);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  const double q[2] = {0.9, 0.4}, v[2] = {-0.3, 0.8};
  double lambda;
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.2, q, v, &lambda), SDAE_OK);
  ck_assert_uint_eq(k.calls[C_GDOT], 1);
  ck_assert_uint_eq(k.calls[C_CTDOT], 1);
  ck_assert_uint_eq(k.calls[C_G], 1);
  ck_assert_uint_eq(k.calls[C_FORCE], 1);
  ck_assert_uint_eq(k.calls[C_MASS], 1);
  ck_assert_uint_eq(k.calls[C_C], 0);
  ck_assert_uint_eq(k.calls[C_CT], 0);
  ck_assert_uint_eq(k.calls[C_MDV], 0);
  sdae_mbs_stepper_free(s);

  k.in.jacobian_dot = NULL, k.in.constraint_t_dot = NULL;
  sys = counting(&k);
  s = stepper(&sys, &o);
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.2, q, v, &lambda), SDAE_OK);
  ck_assert_uint_eq(k.calls[C_G], 1 + 4);
  ck_assert_uint_eq(k.calls[C_CT], 4);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* A derivative of a callback the mechanism leaves out cannot be used: SDAE_ERR_NULL, as
 * sdae_mbs_check says. */
START_TEST(derivative_without_its_callback) {
  wire w = {.m = 1.0, .w = 0.5};
  sdae_mbs sys = wire_mbs(&w);
  sdae_options o = options(sdae_map_euler);
  sdae_mbs_stepper *s = NULL;
  sys.jacobian = NULL;
  ck_assert_uint_eq(sdae_mbs_stepper_size(&sys, &o), 0);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_ERR_NULL);
  sys = wire_mbs(&w), sys.constraint_t = NULL;
  ck_assert_uint_eq(sdae_mbs_stepper_size(&sys, &o), 0);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_ERR_NULL);
  ck_assert_ptr_null(s);
  sys.constraint_t_dot = NULL; /* dc/dt by differences, and its derivative with it */
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* calls of `steps` euler steps of the pendulum from (theta, omega) with its radius L + dr and
 * the radial velocity vr, every derivative given or (along = 0) jacobian_dot and mass_dot_v
 * left out, counted from the last step's start; *iters: its Phi^-1's chord iterations */
static void steps_from(counted *k, int along, double dr, double vr, int steps,
                       unsigned long *iters) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  sdae_options o = options(sdae_map_euler);
  sdae_mbs_stepper *s;
  const double th = 0.5, om = 0.3, r = p.L + dr;
  double q[2] = {r * sin(th), -r * cos(th)};
  double v[2] = {om * r * cos(th) + vr * sin(th), om * r * sin(th) - vr * cos(th)};
  k->in = pendulum_all(&p);
  if (!along) k->in.mass_dot_v = NULL, k->in.jacobian_dot = NULL;
  sys = counting(k);
  s = stepper(&sys, &o);
  for (int n = 0; n < steps; n++) {
    memset(k->calls, 0, sizeof k->calls);
    sdae_mbs_stepper_reset_stats(s);
    ck_assert_int_eq(sdae_mbs_step(s, 1e-3 * n, 1e-3, q, v), SDAE_OK);
  }
  *iters = sdae_mbs_stepper_stats(s)->phi_inv_iters;
  sdae_mbs_stepper_free(s);
}

static void one_step(counted *k, int along, double dr, double vr, unsigned long *iters) {
  steps_from(k, along, dr, vr, 1, iters);
}

/* Off the manifold (|c| = 1e-3, G v = 0.1), every derivative given: 1 + n_xi = 3 evaluations
 * of the mu-dynamics (q0 and the two columns of Q), each one force, one mass_dot_v and one
 * jacobian_dot and no stencil. Their Phi^-1 and the one at t + T solve for 3 configurations
 * (xi^(2) = xi moves the velocity alone from xi^(1) = (c, 0): v is solved for there), each by
 * the chord iteration with the factors of the last one (one constraint per iteration, no
 * jacobian while it converges), then one jacobian, one constraint_t and one mass where it
 * converged; the start: constraint, jacobian and constraint_t for xi, mass for mu. Without
 * the derivatives along the motion, jacobian and mass at the stencil's four points per
 * evaluation. */
START_TEST(step_calls_off_the_manifold) {
  counted k;
  unsigned long iters;
  one_step(&k, 1, 1e-3, 0.1, &iters);
  ck_assert_uint_eq(k.calls[C_FORCE], 3);
  ck_assert_uint_eq(k.calls[C_MDV], 3);
  ck_assert_uint_eq(k.calls[C_GDOT], 3);
  ck_assert_uint_eq(k.calls[C_CTDOT], 0);
  ck_assert_uint_eq(k.calls[C_MASS], 3 + 1);
  ck_assert_uint_eq(k.calls[C_CT], 3 + 1);
  ck_assert_uint_eq(k.calls[C_G], 3 + 1);
  ck_assert_uint_eq(k.calls[C_C], iters + 1);
  ck_assert_uint_le(iters, 3 * 5); /* a few corrections per configuration */
  one_step(&k, 0, 1e-3, 0.1, &iters);
  ck_assert_uint_eq(k.calls[C_MASS], 3 + 1 + 3 * 4);
  ck_assert_uint_eq(k.calls[C_G], 3 + 1 + 3 * 4);
}
END_TEST

/* On the manifold xi is at its floors: Q's columns are not evaluated (derive.c), and the
 * state is taken as Phi^-1(t, 0, mu) of q0's evaluation: the step's start (c, G, dc/dt for xi,
 * M for mu), the mu-dynamics there, and the configuration at t + T. */
START_TEST(step_calls_on_the_manifold) {
  counted k;
  unsigned long iters;
  one_step(&k, 1, 0.0, 0.0, &iters);
  ck_assert_uint_eq(k.calls[C_FORCE], 1);
  ck_assert_uint_eq(k.calls[C_MDV], 1);
  ck_assert_uint_eq(k.calls[C_GDOT], 1);
  ck_assert_uint_eq(k.calls[C_MASS], 1 + 1);
  ck_assert_uint_eq(k.calls[C_CT], 1 + 1);
  ck_assert_uint_eq(k.calls[C_G], 1 + 1);
  ck_assert_uint_eq(k.calls[C_C], iters + 1);
  one_step(&k, 0, 0.0, 0.0, &iters);
  ck_assert_uint_eq(k.calls[C_MASS], 1 + 1 + 4);
  ck_assert_uint_eq(k.calls[C_G], 1 + 1 + 4);
}
END_TEST

/* The next step starts where the last one's Phi^-1 ended: G, dc/dt and M kept from there, c
 * evaluated for xi (docs/front-ends.md, the cost of a step). The euler step then calls each
 * callback once but c, which its Phi^-1 at t + T calls once per chord iteration and once for the
 * Newton step that finishes the state (both counted as iterations), and the start once:
 * 6 + iters + 1 calls against the 16 of a classical RK4 step on the index-1 form. */
START_TEST(step_calls_from_the_last_end) {
  counted k;
  unsigned long iters;
  steps_from(&k, 1, 0.0, 0.0, 3, &iters);
  ck_assert_uint_eq(k.calls[C_FORCE], 1);
  ck_assert_uint_eq(k.calls[C_MDV], 1);
  ck_assert_uint_eq(k.calls[C_GDOT], 1);
  ck_assert_uint_eq(k.calls[C_MASS], 1);
  ck_assert_uint_eq(k.calls[C_CT], 1);
  ck_assert_uint_eq(k.calls[C_G], 1);
  ck_assert_uint_eq(k.calls[C_C], iters + 1);
  ck_assert_uint_le(iters, 3 + 1);
}
END_TEST

/* The discrete gradient's Newton evaluates phi(mu, mu+) at one mu and many mu+: H(mu) is
 * evaluated once per step and kept (map_dgrad.c), H(mu+) once per evaluation but the
 * predictor's (mu+ = mu, no correction term). The pendulum's H calls its potential once. */
START_TEST(dgrad_keeps_H_at_the_start) {
  mech_pendulum p = PENDULUM;
  counted k;
  sdae_mbs sys;
  sdae_options o = options(sdae_map_dgrad);
  sdae_mbs_stepper *s;
  double q[2], v[2];
  mech_pendulum_system(&k.in, &p);
  sys = counting(&k);
  s = stepper(&sys, &o);
  mech_pendulum_state(&p, 0.5, 0.3, q, v);
  for (int n = 0; n < 3; n++) {
    unsigned long phi;
    memset(k.calls, 0, sizeof k.calls);
    sdae_mbs_stepper_reset_stats(s);
    ck_assert_int_eq(sdae_mbs_step(s, 1e-3 * n, 1e-3, q, v), SDAE_OK);
    phi = sdae_mbs_stepper_stats(s)->step.phi_evals;
    ck_assert_uint_ge(phi, 4);
    ck_assert_uint_eq(k.calls[C_V], 1 + (phi - 1));
  }
  sdae_mbs_stepper_free(s);
}
END_TEST

/* The implicit map's Newton matrix, by differences (2 n_mu evaluations of the mu-dynamics, a
 * Phi^-1 each), is kept across steps (core/newton.h, keep): built at the first step, at
 * every chart switch (mu is then other coordinates) and after 20 steps at most. Over 2000
 * midpoint steps of the pendulum swinging through 1.2 rad: a step builds one (its evaluations
 * beyond the predictor and one per iteration are 2 n_mu = 4 per matrix; Newton with a fresh
 * matrix builds another while its update exceeds 1e-5) at each switch, and about one in 21
 * steps besides; the others evaluate no difference. */
START_TEST(newton_matrix_kept_across_steps) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  sdae_options o = options(sdae_map_midpoint);
  sdae_mbs_stepper *s;
  double q[2], v[2];
  unsigned long built = 0, switched = 0;
  const unsigned long steps = 2000;
  mech_pendulum_system(&sys, &p);
  s = stepper(&sys, &o);
  mech_pendulum_state(&p, 1.2, 0.0, q, v);
  for (unsigned long n = 0; n < steps; n++) {
    const sdae_mbs_stats *st = sdae_mbs_stepper_stats(s);
    unsigned long phi = st->step.phi_evals, it = st->step.newton_iters_total;
    unsigned long sw = st->chart_switches, extra;
    ck_assert_int_eq(sdae_mbs_step(s, 1e-3 * (double)n, 1e-3, q, v), SDAE_OK);
    extra = st->step.phi_evals - phi - (st->step.newton_iters_total - it) - 1;
    ck_assert_msg(extra % 4 == 0, "step %lu: %lu evaluations for differences", n, extra);
    built += extra > 0;
    if (st->chart_switches != sw) {
      switched++;
      ck_assert_uint_ge(extra, 4);
    }
  }
  ck_assert_uint_ge(switched, 2);
  ck_assert_uint_le(built, switched + steps / 20 + 1);
  ck_assert_uint_ge(built, steps / 21);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* ---- what the floors of xi keep: the paper's decay off the manifold, no drift on it ---- */

/* The pendulum's normal form in the chart q_I = x, q_D = y < 0, in closed form: Phi^-1 is
 * y = -sqrt(L^2 + 2 xi_1 - x^2) and (x v_x + y v_y = xi_2, m (v_x - (x / y) v_y) = p); the
 * mu-dynamics (x', p') = (v_x, Wdot^T M v + W^T F) with W = (1, -x / y), Wdot^T M v =
 * -m v_y (v_x y - x v_y) / y^2 and W^T F = m ga x / y. */
static void pendulum_rate(const mech_pendulum *P, const double *xi, const double *mu, double *out) {
  double x = mu[0], p = mu[1], y = -sqrt(P->L * P->L + 2.0 * xi[0] - x * x);
  double a = (xi[1] - x * p / P->m) / (x * x + y * y), vy = y * a, vx = p / P->m + x * a;
  out[0] = vx;
  out[1] = -P->m * vy * (vx * y - x * vy) / (y * y) + P->m * P->ga * x / y;
}

/* the gains of eq. 6, k_i = -(delta^2 / 2) |q_i|^2 - epsilon, with the columns q_i of Q by the
 * telescoping sum q_i = (G(xi^(i)) - G(xi^(i-1))) / xi_i of the closed form */
static void pendulum_gains(const mech_pendulum *P, const sdae_options *o, const double *xi,
                           const double *mu, double *k) {
  const double zero[2] = {0.0, 0.0}, first[2] = {xi[0], 0.0};
  double G0[2], G1[2], G2[2], n1 = 0.0, n2 = 0.0;
  pendulum_rate(P, zero, mu, G0);
  pendulum_rate(P, first, mu, G1);
  pendulum_rate(P, xi, mu, G2);
  for (int r = 0; r < 2; r++) {
    double q1 = (G1[r] - G0[r]) / xi[0], q2 = (G2[r] - G1[r]) / xi[1];
    n1 += q1 * q1, n2 += q2 * q2;
  }
  k[0] = -0.5 * o->delta * o->delta * n1 - o->epsilon;
  k[1] = -0.5 * o->delta * o->delta * n2 - o->epsilon;
}

/* From |c| = 1e-2 and a radial velocity 0.5 (G v = 0.505), scheme 15 contracts each xi_i by the
 * paper's 1 / (1 - T k_i) per step, k_i of the step's start by the closed form: measured from
 * the state after each step, within 2e-7 of 1 - 1 / (1 - T k_i) while |xi_i| > 1e-6 (where
 * the library's column of xi_2 is taken from xi^(1) = 0 once |xi_1| < sqrt(eps): 5e-8
 * measured). The floors never touch a xi this large; a gain of -epsilon would be off by a
 * third and more. */
START_TEST(off_manifold_decay_is_the_papers) {
  mech_pendulum p = PENDULUM;
  sdae_mbs sys;
  sdae_options o = options(sdae_map_midpoint);
  sdae_mbs_stepper *s;
  const double T = 1e-3, th = 0.5, r = sqrt(p.L * p.L + 2e-2), vr = 0.5, om = 1.0;
  double q[2] = {r * sin(th), -r * cos(th)};
  double v[2] = {om * r * cos(th) + vr * sin(th), om * r * sin(th) - vr * cos(th)};
  double xi[2], next[2];
  size_t compared[2] = {0, 0}, dep;
  mech_pendulum_system(&sys, &p);
  s = stepper(&sys, &o);
  ck_assert_int_eq(sdae_mbs_xi(s, 0.0, q, v, xi), SDAE_OK);
  ck_assert_double_eq_tol(xi[0], 1e-2, 1e-15);
  for (size_t n = 0; n < 20000 && (fabs(xi[0]) > 1e-6 || fabs(xi[1]) > 1e-6); n++) {
    double mu[2] = {q[0], p.m * (v[0] - q[0] / q[1] * v[1])}, k[2];
    pendulum_gains(&p, &o, xi, mu, k);
    ck_assert_int_eq(sdae_mbs_step(s, (double)n * T, T, q, v), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_chart(s, &dep), SDAE_OK);
    ck_assert_uint_eq(dep, 1); /* the closed form's chart */
    ck_assert_int_eq(sdae_mbs_xi(s, (double)(n + 1) * T, q, v, next), SDAE_OK);
    for (int i = 0; i < 2; i++) {
      double paper = 1.0 / (1.0 - T * k[i]);
      if (fabs(xi[i]) <= 1e-6) continue;
      ck_assert_msg(fabs(next[i] / xi[i] - paper) <= 2e-7 * (1.0 - paper),
                    "step %zu, xi_%d = %g: contracted by %.12f, the paper's %.12f", n, i + 1, xi[i],
                    next[i] / xi[i], paper);
      compared[i]++;
    }
    memcpy(xi, next, sizeof xi);
  }
  ck_assert_double_le(fabs(xi[0]), 1e-6);
  ck_assert_double_le(fabs(xi[1]), 1e-6);
  ck_assert_uint_gt(compared[0], 150);  /* xi_1: k about -50, down in some 200 steps */
  ck_assert_uint_gt(compared[1], 5000); /* xi_2: k near -epsilon, the slow one */
  sdae_mbs_stepper_free(s);
}
END_TEST

/* max |c| over steps of T from (theta0, omega0) on the manifold, and the mu-dynamics'
 * evaluations (force calls) per step */
static void run_on_manifold(const sdae_map_type *map, size_t steps, double *max_c, double *evals) {
  mech_pendulum p = PENDULUM;
  counted k;
  sdae_mbs sys;
  sdae_options o = options(map);
  sdae_mbs_stepper *s;
  double q[2], v[2], c;
  mech_pendulum_system(&k.in, &p);
  sys = counting(&k);
  s = stepper(&sys, &o);
  mech_pendulum_state(&p, 1.2, 0.0, q, v);
  *max_c = 0.0;
  for (size_t n = 0; n < steps; n++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)n * 1e-3, 1e-3, q, v), SDAE_OK);
    mech_pendulum_constraint(0.0, q, &c, &p);
    *max_c = fmax(*max_c, fabs(c));
  }
  *evals = (double)k.calls[C_FORCE] / (double)steps;
  sdae_mbs_stepper_free(s);
}

/* 20000 steps on the manifold through 36 chart switches (a swing of 1.2 rad): max |c| within
 * 32 ulps of the size of c's terms (x^2, y^2 and L^2 over 2: L^2 = 1); measured 8 to 9 ulps
 * with the floors, 9 to 15 with every column of Q evaluated (18 and 16 at most over the
 * swings of 0.5 and 2.5 rad, either way). The floors at work: euler evaluates the
 * mu-dynamics 1.85 times per step (q0, and Q's columns where xi_2 has walked above its
 * floor), 3 times with every column. */
START_TEST(on_manifold_no_drift) {
  const sdae_map_type *maps[3] = {sdae_map_euler, sdae_map_midpoint, sdae_map_dgrad};
  for (int m = 0; m < 3; m++) {
    double max_c, evals;
    run_on_manifold(maps[m], 20000, &max_c, &evals);
    ck_assert_msg(max_c <= 32.0 * DBL_EPSILON, "%s: max |c| %g", sdae_map_name(maps[m]), max_c);
    if (m == 0) ck_assert_double_lt(evals, 2.0);
  }
}
END_TEST

/* At small steps the scheme's xi_c remembers 1 / (T |k|) steps, 1e5 at T = 1e-5 with gains
 * near -epsilon: what each step's Phi^-1 leaves in c adds up, an unbiased rounding as a random
 * walk (sqrt(n) ulps), a rounding of one sign linearly. 2e5 euler steps of the double
 * pendulum at T = 1e-5: max |c_j| within 1e-13 (450 ulps of the terms of c); measured
 * 2.5e-14 (2.3e-14 with Newton from the step's start each time), 3.8e-13 when the state's q_D
 * is left where the chord iteration converged, its last corrections computed within an ulp of
 * the root (mbs_coords.c, finish). */
START_TEST(small_steps_no_bias) {
  mech_double_pendulum p = {.L1 = 1.0, .L2 = 1.0, .m1 = 1.0, .m2 = 1.0, .ga = 9.81};
  const double a[2] = {1.0, 1.5}, w[2] = {0.0, 0.0}, T = 1e-5;
  sdae_mbs sys;
  sdae_options o = options(sdae_map_euler);
  sdae_mbs_stepper *s;
  double q[4], v[4], c[2], max_c = 0.0;
  mech_double_pendulum_system(&sys, &p);
  mech_double_pendulum_state(&p, a, w, q, v);
  o.delta = 2.0;
  s = stepper(&sys, &o);
  for (size_t n = 0; n < 200000; n++) {
    ck_assert_int_eq(sdae_mbs_step(s, (double)n * T, T, q, v), SDAE_OK);
    ck_assert_int_eq(sys.constraint(0.0, q, c, sys.params), 0);
    max_c = fmax(max_c, fmax(fabs(c[0]), fabs(c[1])));
  }
  ck_assert_msg(max_c <= 1e-13, "max |c| %g", max_c);
  sdae_mbs_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs_cost");
  ADD_CASE(s, lambda_calls_given_derivatives);
  ADD_CASE(s, derivative_without_its_callback);
  ADD_CASE(s, step_calls_off_the_manifold);
  ADD_CASE(s, step_calls_on_the_manifold);
  ADD_CASE(s, step_calls_from_the_last_end);
  ADD_CASE(s, dgrad_keeps_H_at_the_start);
  ADD_CASE(s, newton_matrix_kept_across_steps);
  ADD_CASE(s, off_manifold_decay_is_the_papers);
  ADD_CASE(s, on_manifold_no_drift);
  ADD_CASE(s, small_steps_no_bias);
  return run_suite(s);
}
