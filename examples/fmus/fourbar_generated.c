/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The four-bar linkage written by the generator from examples/models/sym/fourbar.py (the library
 * sym_fourbar) as an FMU, build/fmus/fmi3|fmi2/fourbar_generated.fmu: the table of
 * <stabdae/fmu.h> from the generated header's, nothing written by hand but the solver's
 * defaults, the example program's (T 0.001, delta 2, epsilon 1, map dgrad, tf 10). The units of
 * the parameters and coordinates come from the header too; the generator writes none for the
 * inputs, the multipliers and the energy, which then have none. */
#include <stddef.h>

#include <stabdae/fmu.h>

#include "fourbar.h"

SDAE_FMU_GENERATED(fourbar)
SDAE_FMU_GENERATED_PARAMS(fourbar, FOURBAR_PARAMETERS);

static const char *const coordinates[] = FOURBAR_COORDINATE_NAMES;
static const char *const coordinate_units[] = FOURBAR_COORDINATE_UNITS;

const sdae_fmu sdae_fmu_model = {
    .name = "fourbar_generated",
    .description = "A four-bar linkage in the coordinates of B and C, written by stabdae_gen",
    .params_size = sizeof(fourbar_params),
    .params = fourbar_fmu_params,
    .n_params = FOURBAR_N_PARAMS,
    .params_default = fourbar_fmu_default,
    .mbs = fourbar_fmu_mbs,
    .start = fourbar_fmu_start,
    .coordinates = coordinates,
    .coordinate_units = coordinate_units,
    .T = 0.001,
    .delta = 2.0,
    .epsilon = 1.0,
    .map = "dgrad",
    .stop_time = 10.0, /* the example program's tf, as the hand-written four-bar's */
};
