/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The four-bar linkage of examples/fourbar.c as an FMU (build/fmus/fmi3/fourbar.fmu and
 * build/fmus/fmi2/fourbar.fmu): the mechanism of models/mechanisms.h, its parameters, the start
 * from the crank angle theta0 and speed omega0, and the example program's defaults (T 0.001,
 * delta 2, epsilon 1, map dgrad, scheme 15). Output q = (Bx, By, Cx, Cy). */
#include <stddef.h>

#include <stabdae/fmu.h>

#include "mechanisms.h"

typedef struct fourbar_params {
  mech_fourbar mech;
  double theta0, omega0;
} fourbar_params;

static sdae_mbs fourbar_mbs(void *p) {
  sdae_mbs sys;
  mech_fourbar_system(&sys, &((fourbar_params *)p)->mech);
  return sys;
}

/* the assembled state at theta0; none at a dead point of the loop */
static int fourbar_start(const void *p, double *q0, double *v0) {
  const fourbar_params *f = p;
  return mech_fourbar_state(&f->mech, f->theta0, f->omega0, q0, v0);
}

static const sdae_fmu_param fourbar_params_table[] = {
    {"a", 1.0, "crank length |AB|", offsetof(fourbar_params, mech.a)},
    {"b", 4.0, "coupler length |BC|", offsetof(fourbar_params, mech.b)},
    {"e", 3.0, "rocker length |CD|", offsetof(fourbar_params, mech.e)},
    {"d", 4.5, "ground length |AD|", offsetof(fourbar_params, mech.d)},
    {"mB", 1.0, "mass at B", offsetof(fourbar_params, mech.mB)},
    {"mC", 1.0, "mass at C", offsetof(fourbar_params, mech.mC)},
    {"ga", 9.81, "gravitational acceleration", offsetof(fourbar_params, mech.ga)},
    {"theta0", 0.0, "start crank angle", offsetof(fourbar_params, theta0)},
    {"omega0", 5.0, "start crank speed", offsetof(fourbar_params, omega0)},
};

static const char *const fourbar_coordinates[] = {"Bx", "By", "Cx", "Cy"};

const sdae_fmu sdae_fmu_model = {
    .name = "fourbar",
    .description = "A four-bar linkage (crank AB, coupler BC, rocker CD) in the coordinates of "
                   "B and C, three constraints",
    .params_size = sizeof(fourbar_params),
    .params = fourbar_params_table,
    .n_params = sizeof fourbar_params_table / sizeof *fourbar_params_table,
    .mbs = fourbar_mbs,
    .start = fourbar_start,
    .coordinates = fourbar_coordinates,
    .T = 0.001,
    .delta = 2.0,
    .epsilon = 1.0,
    .map = "dgrad",
};
