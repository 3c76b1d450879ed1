/* SPDX-License-Identifier: GPL-3.0-or-later */
/* SUNDIALS' slider crank of examples/slider_crank.c as an FMU (build/fmus/fmi3/slider_crank.fmu
 * and build/fmus/fmi2/slider_crank.fmu): the mechanism of models/benchmarks.h with
 * idaSlCrank_dns's constants, its start at rest, and the example program's defaults (T 0.001,
 * delta 2, epsilon 1, map dgrad, scheme 15). Output q = (theta, x, phi). */
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
    {"a", 0.5, "crank length (< 1, the rod's)", offsetof(bench_slider_crank, a)},
    {"J1", 1.0, "crank moment of inertia", offsetof(bench_slider_crank, J1)},
    {"m2", 1.0, "connecting rod mass", offsetof(bench_slider_crank, m2)},
    {"J2", 2.0, "connecting rod moment of inertia", offsetof(bench_slider_crank, J2)},
    {"k", 1.0, "spring constant", offsetof(bench_slider_crank, k)},
    {"c", 1.0, "damper constant", offsetof(bench_slider_crank, c)},
    {"l0", 1.0, "spring free length", offsetof(bench_slider_crank, l0)},
    {"F", 1.0, "constant force", offsetof(bench_slider_crank, F)},
};

static const char *const slider_crank_coordinates[] = {"theta", "x", "phi"};

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
};
