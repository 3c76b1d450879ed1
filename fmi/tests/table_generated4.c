/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A generated mechanism's table of parameters with units, the X-macro's fourth argument (the
 * generator that writes units), for fmi_table_macros: SDAE_FMU_GENERATED_PARAMS is one per
 * file. */
#include <stabdae/fmu.h>

typedef struct gen4_params {
  double L, m;
} gen4_params;

#define GEN4_PARAMETERS(X) X(L, 1.5, "rod length", "m") X(m, 2.0, "mass", "kg")

SDAE_FMU_GENERATED_PARAMS(gen4, GEN4_PARAMETERS);

const sdae_fmu_param *table_generated4(void) { return gen4_fmu_params; }
