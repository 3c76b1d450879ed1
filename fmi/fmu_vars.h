/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The FMU's variables, one list for the binary and for modelDescription.xml: the value
 * reference of each, its name, kind and role, computed from the table (<stabdae/fmu.h>) and the
 * mechanism's sizes. Value references, in this order:
 *
 *   0 time, 1 T, 2 delta, 3 epsilon, 4 map (a string), the table's parameters, q0[], v0[],
 *   u[], q[], v[], lambda[], max_abs_c, energy (with a potential) */
#ifndef STABDAE_FMI_FMU_VARS_H
#define STABDAE_FMI_FMU_VARS_H

#include <stddef.h>

#include <stabdae/fmu.h>

typedef enum fmu_role {
  FMU_TIME,   /* the independent variable */
  FMU_SOLVER, /* T, delta, epsilon, map: parameters of the method */
  FMU_PARAM,  /* the mechanism's parameters */
  FMU_START,  /* q0[], v0[]: parameters, the start state */
  FMU_INPUT,  /* u[] */
  FMU_OUTPUT  /* q[], v[], lambda[], max_abs_c, energy */
} fmu_role;

enum { FMU_VR_TIME = 0, FMU_VR_T = 1, FMU_VR_DELTA = 2, FMU_VR_EPSILON = 3, FMU_VR_MAP = 4 };

typedef struct fmu_layout {
  const sdae_fmu *model;
  size_t n_q, n_c;
  int has_energy;
  /* the first value reference of each block */
  size_t params, q0, v0, u, q, v, lambda, max_abs_c, energy, count;
} fmu_layout;

/* the longest variable name, its terminating 0 included */
#define FMU_NAME_LEN 64
/* the longest unit: a table's, "/s" appended for a velocity, the terminating 0 */
#define FMU_UNIT_LEN (SDAE_FMU_UNIT_MAX + 3)

typedef struct fmu_var {
  size_t vr;
  fmu_role role;
  int is_string;           /* map; every other variable is a double */
  char name[FMU_NAME_LEN]; /* q[3], T, ... */
  char description[160];
  char unit[FMU_UNIT_LEN]; /* "" when it has none */
} fmu_var;

/* the layout of a model whose mechanism has n_q coordinates and n_c constraints */
void fmu_layout_make(fmu_layout *L, const sdae_fmu *model, size_t n_q, size_t n_c, int has_energy);
/* the variable at value reference vr; -1 when there is none */
int fmu_var_at(const fmu_layout *L, size_t vr, fmu_var *var);

/* The instantiation token (FMI 3.0) / guid (FMI 2.0): a digest of the model's name, sizes,
 * variables and their defaults (by value reference), so that a binary and a
 * modelDescription.xml of another table never match. */
void fmu_token(const fmu_layout *L, const double *defaults, char out[40]);

#endif /* STABDAE_FMI_FMU_VARS_H */
