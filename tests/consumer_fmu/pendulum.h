/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A planar pendulum in Cartesian coordinates, declared the way the generator (tools/mbsgen)
 * declares a mechanism NAME: NAME_params, NAME_params_default, NAME_mbs, NAME_start. */
#ifndef PENDULUM_H
#define PENDULUM_H

#include <stabdae/mbs.h>

typedef struct {
  double L, m, g, theta0;
} pendulum_params;

void pendulum_params_default(pendulum_params *p);
sdae_mbs pendulum_mbs(pendulum_params *p);
void pendulum_start(const pendulum_params *p, double *q0, double *v0);

#endif /* PENDULUM_H */
