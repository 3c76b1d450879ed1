/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The four-bar linkage of examples/fourbar.c as an FMU (build/fmus/fmi3/fourbar.fmu and
 * build/fmus/fmi2/fourbar.fmu): the mechanism of models/mechanisms.h, its parameters, the start
 * from the crank angle theta0 and speed omega0, and the example program's defaults (T 0.001,
 * delta 2, epsilon 1, map dgrad, scheme 15, tf 10). Output q = (Bx, By, Cx, Cy), in m; the units
 * SI. */
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
    {"a", 1.0, "crank length |AB|", offsetof(fourbar_params, mech.a), "m"},
    {"b", 4.0, "coupler length |BC|", offsetof(fourbar_params, mech.b), "m"},
    {"e", 3.0, "rocker length |CD|", offsetof(fourbar_params, mech.e), "m"},
    {"d", 4.5, "ground length |AD|", offsetof(fourbar_params, mech.d), "m"},
    {"mB", 1.0, "mass at B", offsetof(fourbar_params, mech.mB), "kg"},
    {"mC", 1.0, "mass at C", offsetof(fourbar_params, mech.mC), "kg"},
    {"ga", 9.81, "gravitational acceleration", offsetof(fourbar_params, mech.ga), "m/s^2"},
    {"theta0", 0.0, "start crank angle", offsetof(fourbar_params, theta0), "rad"},
    {"omega0", 5.0, "start crank speed", offsetof(fourbar_params, omega0), "rad/s"},
};

static const char *const fourbar_coordinates[] = {"Bx", "By", "Cx", "Cy"};
/* B and C in the plane: lengths, their forces in N; each constraint is (|X - Y|^2 - L^2) / 2, in
 * m^2, its row of G in m, so that G^T lambda in N takes lambda in N/m */
static const char *const fourbar_lengths[] = {"m", "m", "m", "m"};
static const char *const fourbar_forces[] = {"N", "N", "N", "N"};
static const char *const fourbar_multipliers[] = {"N/m", "N/m", "N/m"};

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
    .coordinate_units = fourbar_lengths,
    .force_units = fourbar_forces,
    .multiplier_units = fourbar_multipliers,
    .energy_unit = "J",
    .stop_time = 10.0, /* the example program's tf */
};
