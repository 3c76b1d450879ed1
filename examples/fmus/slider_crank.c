/* SPDX-License-Identifier: GPL-3.0-or-later */
/* SUNDIALS' slider crank of examples/slider_crank.c as an FMU (build/fmus/fmi3/slider_crank.fmu
 * and build/fmus/fmi2/slider_crank.fmu): the mechanism of models/benchmarks.h with
 * idaSlCrank_dns's constants, its start at rest, and the example program's defaults (T 0.001,
 * delta 2, epsilon 1, map dgrad, scheme 15, tf 10). Output q = (theta, x, phi), in rad, m, rad; the
 * units SI, the rod 1 m long. */
#include <stddef.h>

#include <stabdae/fmu.h>

#include "benchmarks.h"

static sdae_mbs slider_crank_mbs(void *p) {
  sdae_mbs sys;
  bench_slider_crank_system(&sys, p);
  return sys;
}

static int slider_crank_start(const void *p, double *q0, double *v0) {
  bench_slider_crank_initial(p, q0, v0);
  return 0;
}

static const sdae_fmu_param slider_crank_params[] = {
    {"a", 0.5, "crank length (< 1, the rod's)", offsetof(bench_slider_crank, a), "m"},
    {"J1", 1.0, "crank moment of inertia", offsetof(bench_slider_crank, J1), "kg*m^2"},
    {"m2", 1.0, "connecting rod mass", offsetof(bench_slider_crank, m2), "kg"},
    {"J2", 2.0, "connecting rod moment of inertia", offsetof(bench_slider_crank, J2), "kg*m^2"},
    {"k", 1.0, "spring constant", offsetof(bench_slider_crank, k), "N/m"},
    {"c", 1.0, "damper constant", offsetof(bench_slider_crank, c), "N*s/m"},
    {"l0", 1.0, "spring free length", offsetof(bench_slider_crank, l0), "m"},
    {"F", 1.0, "constant force", offsetof(bench_slider_crank, F), "N"},
};

static const char *const slider_crank_coordinates[] = {"theta", "x", "phi"};
/* two angles and a length (the rod is 1 m long); torques along the angles, a force along x; the
 * constraints are the rod's end on the slider's line, in m, their rows of G in m per rad and 1,
 * so that G^T lambda in N*m and N takes lambda in N */
static const char *const slider_crank_units[] = {"rad", "m", "rad"};
static const char *const slider_crank_forces[] = {"N*m", "N", "N*m"};
static const char *const slider_crank_multipliers[] = {"N", "N"};

const sdae_fmu sdae_fmu_model = {
    .name = "slider_crank",
    .description = "SUNDIALS' slider crank (idaSlCrank_dns): crank angle, slider position, rod "
                   "angle; a spring-damper and a constant force",
    .params_size = sizeof(bench_slider_crank),
    .params = slider_crank_params,
    .n_params = sizeof slider_crank_params / sizeof *slider_crank_params,
    .mbs = slider_crank_mbs,
    .start = slider_crank_start,
    .coordinates = slider_crank_coordinates,
    .T = 0.001,
    .delta = 2.0,
    .epsilon = 1.0,
    .map = "dgrad",
    .coordinate_units = slider_crank_units,
    .force_units = slider_crank_forces,
    .multiplier_units = slider_crank_multipliers,
    .energy_unit = "J",
    .stop_time = 10.0, /* the example program's tf */
};
