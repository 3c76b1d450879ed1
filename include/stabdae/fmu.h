/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae co-simulation FMUs (layer: fmi, above the library: fmi/ compiles it into each FMU):
 * a mechanism of <stabdae/mbs.h> described by one table, which the
 * CMake function stabdae_add_fmu (docs/fmi.md) turns into an FMI 3.0 and an FMI 2.0
 * co-simulation FMU. The user writes no FMI code: the table names the mechanism's parameters
 * (where each lives in the user's params struct), a function giving the sdae_mbs at those
 * parameters, the start state and the solver's defaults. The FMU's variables are then
 *
 *   outputs     q[1..n_q], v[1..n_q], lambda[1..n_c], max_abs_c, energy (with a potential)
 *   inputs      u[1..n_q], generalized forces added to F, held over a communication step
 *   parameters  the table's, q0[1..n_q] and v0[1..n_q] (the start state), and the solver's
 *               T (the internal fixed step), delta, epsilon and map (a name of sdae_map_by_name)
 *
 * A file defines the one table of its FMU under the name sdae_fmu_model:
 *
 *     const sdae_fmu sdae_fmu_model = {"fourbar", "A four-bar linkage", ...};
 */
#ifndef STABDAE_FMU_H
#define STABDAE_FMU_H

#include <stddef.h>

#include <stabdae/mbs.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One parameter of the mechanism: a double at byte offset `offset` of the params struct
 * (offsetof(my_params, name)). */
typedef struct sdae_fmu_param {
  const char *name;        /* the FMU's variable name: letters, digits, '_' */
  double start;            /* its default (unused when the table gives params_default) */
  const char *description; /* one line, or NULL */
  size_t offset;           /* offsetof in the params struct */
  const char *unit;        /* optional: its unit, "m", "kg*m^2", "N/m"; NULL or "": none */
} sdae_fmu_param;

typedef struct sdae_fmu {
  const char *name;        /* the model's name (stabdae_add_fmu's NAME) */
  const char *description; /* one line, or NULL */
  size_t params_size;      /* sizeof the params struct; its doubles are set from the table */
  const sdae_fmu_param *params;
  size_t n_params;
  /* optional: the defaults written into a zeroed params struct (the generator's
   * NAME_params_default); then the table's start values are not used, the parameters'
   * defaults are read from the struct at their offsets */
  void (*params_default)(void *p);
  /* the mechanism at the parameters p (a params struct, kept alive by the FMU while it runs):
   * every callback's params must be p or point into it */
  sdae_mbs (*mbs)(void *p);
  /* the start state at the parameters p: n_q positions and velocities; non-zero when there is
   * none at these parameters. NULL: q0 = v0 = 0. The FMU's parameters q0, v0 start from it at
   * the table's defaults; an importer that sets none of them gets it at its own parameters. */
  int (*start)(const void *p, double *q0, double *v0);
  /* optional: n_q names of the coordinates, shown in the variables' descriptions */
  const char *const *coordinates;
  /* the solver's defaults: the internal step T, the stabilization's delta and epsilon, a map's
   * name (scheme 15 always) */
  double T, delta, epsilon;
  const char *map;
  /* Optional, the units in modelDescription.xml (NULL, or a NULL or "" entry: none; at most
   * SDAE_FMU_UNIT_MAX characters each). Time is in s. coordinate_units: n_q, those of q and q0;
   * v's and v0's are these per s ("m" gives "m/s"). force_units: n_q, those of the inputs u,
   * the generalized force along each coordinate ("N" along a length, "N*m" along an angle).
   * multiplier_units: n_c, those of lambda (the generalized force per unit of the constraint:
   * "N/m" for a constraint in m^2 on coordinates in m). energy_unit: the energy's ("J"). */
  const char *const *coordinate_units;
  const char *const *force_units;
  const char *const *multiplier_units;
  const char *energy_unit;
  /* optional: the DefaultExperiment's stop time, a multiple of T; 0: 1000 steps of T */
  double stop_time;
} sdae_fmu;

/* the longest unit a table may give */
#define SDAE_FMU_UNIT_MAX 40

/* A parameter that is the field FIELD of the params struct TYPE, its default from the table's
 * params_default, and optionally its unit: SDAE_FMU_PARAM(pendulum_params, L, "rod length") or
 * SDAE_FMU_PARAM(pendulum_params, L, "rod length", "m"). */
#define SDAE_FMU_PARAM(TYPE, FIELD, ...)                                                           \
  SDAE_FMU_PARAM_(#FIELD, 0.0, offsetof(TYPE, FIELD), __VA_ARGS__, NULL, NULL)
/* one entry from the description and the unit, which may be left out (NULL): the NULLs appended
 * fill it in, and leave the ... an argument at least, as C before C23 needs */
#define SDAE_FMU_PARAM_(NAME, START, OFFSET, DESCRIPTION, UNIT, ...)                               \
  { NAME, START, DESCRIPTION, OFFSET, UNIT }

/* The table of the FMU being built, defined by the user's file. */
extern const sdae_fmu sdae_fmu_model;

/* The adapters for a mechanism written by the generator (tools/mbsgen), which declares
 * NAME_params, NAME_params_default, NAME_mbs and NAME_start: SDAE_FMU_GENERATED(NAME) defines
 * NAME_fmu_default, NAME_fmu_mbs and NAME_fmu_start for the table's params_default, mbs and
 * start. */
#define SDAE_FMU_GENERATED(NAME)                                                                   \
  static void NAME##_fmu_default(void *p) { NAME##_params_default((NAME##_params *)p); }           \
  static sdae_mbs NAME##_fmu_mbs(void *p) { return NAME##_mbs((NAME##_params *)p); }               \
  static int NAME##_fmu_start(const void *p, double *q0, double *v0) {                             \
    NAME##_start((const NAME##_params *)p, q0, v0);                                                \
    return 0;                                                                                      \
  }

/* The parameters of a mechanism written by the generator, from its header's table (the X-macro
 * NAME_PARAMETERS: field, default, description, unit; a table of three columns works too):
 * SDAE_FMU_GENERATED_PARAMS(fourbar, FOURBAR_PARAMETERS) defines the array
 * fourbar_fmu_params of FOURBAR_N_PARAMS entries (at least one: C has no empty initializer).
 * One per file. */
#define SDAE_FMU_GENERATED_PARAMS(NAME, TABLE)                                                     \
  typedef NAME##_params sdae_fmu_generated_params;                                                 \
  static const sdae_fmu_param NAME##_fmu_params[] = {TABLE(SDAE_FMU_GENERATED_PARAM)}
#define SDAE_FMU_GENERATED_PARAM(FIELD, VALUE, ...)                                                \
  SDAE_FMU_PARAM_(#FIELD, VALUE, offsetof(sdae_fmu_generated_params, FIELD), __VA_ARGS__, NULL,    \
                  NULL),

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_FMU_H */
