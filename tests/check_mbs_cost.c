/* SPDX-License-Identifier: GPL-3.0-or-later */
/* What a mechanical step costs (DESIGN.md, the price of zero drift), counted callback by
 * callback on mechanisms whose every callback counts its calls: the derivatives along the
 * motion a mechanism gives replace the difference stencils (no stencil runs when all are
 * given). */
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

/* One euler step on the pendulum, every derivative given: 1 + n_xi = 3 evaluations of the
 * mu-dynamics (q0 and the two columns of Q), each one force, one mass_dot_v and one
 * jacobian_dot and no stencil. Their Phi^-1 and the one at t + T solve for 4 configurations
 * (the velocity column shares the configuration of xi = 0, but the base has moved to the
 * c-column's in between), each by the chord iteration with the factors of the last one (one
 * constraint per iteration, no jacobian while it converges), then one jacobian, one
 * constraint_t and one mass where it converged; the start: constraint, jacobian and
 * constraint_t for xi, mass for mu. Without the derivatives along the motion, jacobian and
 * mass at the stencil's four points per evaluation. */
START_TEST(step_calls_given_derivatives) {
  mech_pendulum p = PENDULUM;
  counted k = {.in = pendulum_all(&p)};
  sdae_mbs sys = counting(&k);
  sdae_options o = options(sdae_map_euler);
  sdae_mbs_stepper *s = stepper(&sys, &o);
  double q[2], v[2];
  unsigned long iters;
  mech_pendulum_state(&p, 0.5, 0.3, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  iters = sdae_mbs_stepper_stats(s)->phi_inv_iters;
  ck_assert_uint_eq(k.calls[C_FORCE], 3);
  ck_assert_uint_eq(k.calls[C_MDV], 3);
  ck_assert_uint_eq(k.calls[C_GDOT], 3);
  ck_assert_uint_eq(k.calls[C_CTDOT], 0);
  ck_assert_uint_eq(k.calls[C_MASS], 4 + 1);
  ck_assert_uint_eq(k.calls[C_CT], 4 + 1);
  ck_assert_uint_eq(k.calls[C_G], 4 + 1);
  ck_assert_uint_eq(k.calls[C_C], iters + 1);
  ck_assert_uint_le(iters, 4 * 3); /* one to three corrections per configuration */
  sdae_mbs_stepper_free(s);

  k.in.mass_dot_v = NULL, k.in.jacobian_dot = NULL;
  sys = counting(&k);
  s = stepper(&sys, &o);
  mech_pendulum_state(&p, 0.5, 0.3, q, v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  ck_assert_uint_eq(k.calls[C_MASS], 4 + 1 + 3 * 4);
  ck_assert_uint_eq(k.calls[C_G], 4 + 1 + 3 * 4);
  sdae_mbs_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs_cost");
  ADD_CASE(s, lambda_calls_given_derivatives);
  ADD_CASE(s, derivative_without_its_callback);
  ADD_CASE(s, step_calls_given_derivatives);
  return run_suite(s);
}
