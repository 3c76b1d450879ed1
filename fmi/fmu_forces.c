/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "fmu_forces.h"

#define USER(params) (&((fmu_forces *)(params))->user)

static int mass(double t, const double *q, double *M, void *params) {
  return USER(params)->mass(t, q, M, USER(params)->params);
}

static int force(double t, const double *q, const double *v, double *F, void *params) {
  return USER(params)->force(t, q, v, F, USER(params)->params);
}

/* the user's forces from outside the Lagrangian (if any) + u: the inputs enter as generalized
 * forces from outside, a port of the energy for the discrete gradients */
static int input_force(double t, const double *q, const double *v, double *F, void *params) {
  const fmu_forces *w = params;
  int rc = 0;
  if (w->user.input_force)
    rc = w->user.input_force(t, q, v, F, w->user.params);
  else
    for (size_t i = 0; i < w->user.n_q; i++) F[i] = 0.0;
  if (rc != 0) return rc;
  for (size_t i = 0; i < w->user.n_q; i++) F[i] += w->u[i];
  return 0;
}

static int constraint(double t, const double *q, double *c, void *params) {
  return USER(params)->constraint(t, q, c, USER(params)->params);
}

static int jacobian(double t, const double *q, double *G, void *params) {
  return USER(params)->jacobian(t, q, G, USER(params)->params);
}

static int constraint_t(double t, const double *q, double *ct, void *params) {
  return USER(params)->constraint_t(t, q, ct, USER(params)->params);
}

static int potential(double t, const double *q, double *V, void *params) {
  return USER(params)->potential(t, q, V, USER(params)->params);
}

static int damping(double t, const double *q, double *D, void *params) {
  return USER(params)->damping(t, q, D, USER(params)->params);
}

static int mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  return USER(params)->mass_dot_v(t, q, v, out, USER(params)->params);
}

static int jacobian_dot(double t, const double *q, const double *v, double *Gdot, void *params) {
  return USER(params)->jacobian_dot(t, q, v, Gdot, USER(params)->params);
}

static int constraint_t_dot(double t, const double *q, const double *v, double *out, void *params) {
  return USER(params)->constraint_t_dot(t, q, v, out, USER(params)->params);
}

void fmu_forces_wrap(sdae_mbs *sys, fmu_forces *w) {
  const sdae_mbs *u = &w->user;
  *sys = (sdae_mbs){
      .n_q = u->n_q,
      .n_c = u->n_c,
      .rank = u->rank,
      .mass = u->mass ? mass : NULL,
      .force = u->force ? force : NULL,
      .constraint = u->constraint ? constraint : NULL,
      .jacobian = u->jacobian ? jacobian : NULL,
      .constraint_t = u->constraint_t ? constraint_t : NULL,
      .potential = u->potential ? potential : NULL,
      .damping = u->damping ? damping : NULL,
      .params = w,
      .mass_dot_v = u->mass_dot_v ? mass_dot_v : NULL,
      .jacobian_dot = u->jacobian_dot ? jacobian_dot : NULL,
      .constraint_t_dot = u->constraint_t_dot ? constraint_t_dot : NULL,
      .input_force = input_force,
      .mass_pattern = u->mass_pattern, /* the user's callbacks write by them, as wrapped */
      .jacobian_pattern = u->jacobian_pattern,
  };
}
