/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The pendulum as an FMU: the table of <stabdae/fmu.h> over the generator's declarations. */
#include <stddef.h>

#include <stabdae/fmu.h>

#include "pendulum.h"

SDAE_FMU_GENERATED(pendulum)

static const sdae_fmu_param params[] = {
    {"L", 1.0, "rod length", offsetof(pendulum_params, L)},
    {"m", 1.0, "mass", offsetof(pendulum_params, m)},
    {"g", 9.81, "gravitational acceleration", offsetof(pendulum_params, g)},
    {"theta0", 1.0, "start angle from the downward vertical", offsetof(pendulum_params, theta0)},
};

static const char *const coordinates[] = {"x", "y"};

const sdae_fmu sdae_fmu_model = {
    .name = "pendulum",
    .description = "A planar pendulum in Cartesian coordinates",
    .params_size = sizeof(pendulum_params),
    .params = params,
    .n_params = sizeof params / sizeof *params,
    .mbs = pendulum_fmu_mbs,
    .start = pendulum_fmu_start,
    .coordinates = coordinates,
    .T = 0.001,
    .delta = 2.0,
    .epsilon = 1.0,
    .map = "dgrad",
};
