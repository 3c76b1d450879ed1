/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The pendulum as an FMU: the table of <stabdae/fmu.h> over the generator's declarations. */
#include <stddef.h>

#include <stabdae/fmu.h>

#include "pendulum.h"

/* pendulum_fmu_default, pendulum_fmu_mbs, pendulum_fmu_start over the generator's shape */
SDAE_FMU_GENERATED(pendulum)

/* the defaults are pendulum_params_default's; the units SI */
static const sdae_fmu_param params[] = {
    SDAE_FMU_PARAM(pendulum_params, L, "rod length", "m"),
    SDAE_FMU_PARAM(pendulum_params, m, "mass", "kg"),
    SDAE_FMU_PARAM(pendulum_params, g, "gravitational acceleration", "m/s^2"),
    SDAE_FMU_PARAM(pendulum_params, theta0, "start angle from the downward vertical", "rad"),
};

static const char *const coordinates[] = {"x", "y"};
static const char *const lengths[] = {"m", "m"}; /* q in m, v in m/s */
static const char *const forces[] = {"N", "N"};
static const char *const multipliers[] = {"N/m"}; /* c = (x^2 + y^2 - L^2) / 2 in m^2 */

const sdae_fmu sdae_fmu_model = {
    .name = "pendulum",
    .description = "A planar pendulum in Cartesian coordinates",
    .params_size = sizeof(pendulum_params),
    .params = params,
    .n_params = sizeof params / sizeof *params,
    .params_default = pendulum_fmu_default,
    .mbs = pendulum_fmu_mbs,
    .start = pendulum_fmu_start,
    .coordinates = coordinates,
    .T = 0.001,
    .delta = 2.0,
    .epsilon = 1.0,
    .map = "dgrad",
    .coordinate_units = lengths,
    .force_units = forces,
    .multiplier_units = multipliers,
    .energy_unit = "J",
};
