/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The four-bar linkage written by the generator by its nonzeros, from
 * examples/models/sym/fourbar_sparse.py (the library sym_fourbar_sparse), as an FMU of a sparse
 * mechanism, build/fmus/fmi3|fmi2/fourbar_sparse.fmu: the table of
 * <stabdae/fmu.h> from the generated header's, nothing written by hand but the solver's
 * defaults, the example program's (T 0.001, delta 2, epsilon 1, map dgrad, tf 10). The units of
 * the parameters and coordinates come from the header too; the generator writes none for the
 * inputs, the multipliers and the energy, which then have none. */
#include <stddef.h>

#include <stabdae/fmu.h>

#include "fourbar_sparse.h"

SDAE_FMU_GENERATED(fourbar_sparse)
SDAE_FMU_GENERATED_PARAMS(fourbar_sparse, FOURBAR_SPARSE_PARAMETERS);

static const char *const coordinates[] = FOURBAR_SPARSE_COORDINATE_NAMES;
static const char *const coordinate_units[] = FOURBAR_SPARSE_COORDINATE_UNITS;

const sdae_fmu sdae_fmu_model = {
    .name = "fourbar_sparse",
    .description =
        "A four-bar linkage in the coordinates of B and C, written by stabdae_gen by its nonzeros",
    .params_size = sizeof(fourbar_sparse_params),
    .params = fourbar_sparse_fmu_params,
    .n_params = FOURBAR_SPARSE_N_PARAMS,
    .params_default = fourbar_sparse_fmu_default,
    .mbs = fourbar_sparse_fmu_mbs,
    .start = fourbar_sparse_fmu_start,
    .coordinates = coordinates,
    .coordinate_units = coordinate_units,
    .T = 0.001,
    .delta = 2.0,
    .epsilon = 1.0,
    .map = "dgrad",
    .stop_time = 10.0, /* the example program's tf, as the hand-written four-bar's */
};
