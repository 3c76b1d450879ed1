/* SPDX-License-Identifier: GPL-3.0-or-later */
/* q = (x, y): a mass m on a rod of length L from the origin, gravity g along -y;
 * c = (x^2 + y^2 - L^2) / 2, G = (x, y), V = m g y. */
#include "pendulum.h"

#include <math.h>

void pendulum_params_default(pendulum_params *p) { *p = (pendulum_params){1.0, 1.0, 9.81, 1.0}; }

static int mass(double t, const double *q, double *M, void *params) {
  const pendulum_params *p = params;
  (void)t, (void)q;
  M[0] = p->m, M[1] = 0.0, M[2] = 0.0, M[3] = p->m;
  return 0;
}

static int force(double t, const double *q, const double *v, double *F, void *params) {
  const pendulum_params *p = params;
  (void)t, (void)q, (void)v;
  F[0] = 0.0, F[1] = -p->m * p->g;
  return 0;
}

static int constraint(double t, const double *q, double *c, void *params) {
  const pendulum_params *p = params;
  (void)t;
  c[0] = (q[0] * q[0] + q[1] * q[1] - p->L * p->L) / 2.0;
  return 0;
}

static int jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  G[0] = q[0], G[1] = q[1];
  return 0;
}

static int potential(double t, const double *q, double *V, void *params) {
  const pendulum_params *p = params;
  (void)t;
  *V = p->m * p->g * q[1];
  return 0;
}

sdae_mbs pendulum_mbs(pendulum_params *p) {
  return (sdae_mbs){.n_q = 2,
                    .n_c = 1,
                    .mass = mass,
                    .force = force,
                    .constraint = constraint,
                    .jacobian = jacobian,
                    .potential = potential,
                    .params = p};
}

/* at rest at theta0 from the downward vertical */
void pendulum_start(const pendulum_params *p, double *q0, double *v0) {
  q0[0] = p->L * sin(p->theta0), q0[1] = -p->L * cos(p->theta0);
  v0[0] = 0.0, v0[1] = 0.0;
}
