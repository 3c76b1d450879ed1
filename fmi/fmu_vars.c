/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "fmu_vars.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

void fmu_layout_make(fmu_layout *L, const sdae_fmu *model, size_t n_q, size_t n_c, int has_energy) {
  L->model = model;
  L->n_q = n_q;
  L->n_c = n_c;
  L->has_energy = has_energy;
  L->params = FMU_VR_MAP + 1;
  L->q0 = L->params + model->n_params;
  L->v0 = L->q0 + n_q;
  L->u = L->v0 + n_q;
  L->q = L->u + n_q;
  L->v = L->q + n_q;
  L->lambda = L->v + n_q;
  L->max_abs_c = L->lambda + n_c;
  L->energy = L->max_abs_c + 1;
  L->count = L->energy + (has_energy ? 1 : 0);
}

/* the coordinate's name for a description, or "" */
static const char *coordinate(const fmu_layout *L, size_t i) {
  return L->model->coordinates && L->model->coordinates[i] ? L->model->coordinates[i] : "";
}

/* entry i of a table's optional list of units, or "" */
static const char *unit_of(const char *const *units, size_t i) {
  return units && units[i] ? units[i] : "";
}

/* the unit u, per s when per_s (a velocity's, from its coordinate's); none stays none */
static void set_unit(fmu_var *var, const char *u, int per_s) {
  snprintf(var->unit, sizeof var->unit, "%s%s", u ? u : "", u && *u && per_s ? "/s" : "");
}

/* an array element: name[i + 1], its role and a description naming the coordinate */
static void element(fmu_var *var, const fmu_layout *L, const char *name, size_t i, fmu_role role,
                    const char *what, int per_coordinate) {
  snprintf(var->name, sizeof var->name, "%s[%zu]", name, i + 1);
  var->role = role;
  if (per_coordinate && *coordinate(L, i))
    snprintf(var->description, sizeof var->description, "%s of coordinate %zu (%s)", what, i + 1,
             coordinate(L, i));
  else
    snprintf(var->description, sizeof var->description, "%s %zu", what, i + 1);
}

static void named(fmu_var *var, const char *name, fmu_role role, const char *description) {
  snprintf(var->name, sizeof var->name, "%s", name);
  snprintf(var->description, sizeof var->description, "%s", description ? description : "");
  var->role = role;
}

static void solver_var(fmu_var *var, size_t vr) {
  static const char *const names[] = {"time", "T", "delta", "epsilon", "map"};
  /* epsilon is a rate (T epsilon is a number); delta's unit depends on the mechanism's */
  static const char *const units[] = {"s", "s", "", "1/s", ""};
  static const char *const what[] = {
      "simulation time", "the internal fixed step (a communication step is cut into steps of T)",
      "the stabilization's delta (gains k_i = -(delta^2/2) |q_i|^2 - epsilon)",
      "the stabilization's epsilon (each constraint decays at least as 1/(1 + T epsilon))",
      "the mu-map by name: euler, midpoint, dgrad, dg4, dg6, midpoint4, midpoint6, rk4, rk8"};
  named(var, names[vr], vr == FMU_VR_TIME ? FMU_TIME : FMU_SOLVER, what[vr]);
  set_unit(var, units[vr], 0);
  var->is_string = vr == FMU_VR_MAP;
}

/* the outputs: q[], v[], lambda[], max_abs_c (no unit: the constraints' may differ), energy */
static void output_var(const fmu_layout *L, size_t vr, fmu_var *var) {
  const sdae_fmu *m = L->model;
  if (vr < L->v) {
    element(var, L, "q", vr - L->q, FMU_OUTPUT, "position", 1);
    set_unit(var, unit_of(m->coordinate_units, vr - L->q), 0);
  } else if (vr < L->lambda) {
    element(var, L, "v", vr - L->v, FMU_OUTPUT, "velocity", 1);
    set_unit(var, unit_of(m->coordinate_units, vr - L->v), 1);
  } else if (vr < L->max_abs_c) {
    element(var, L, "lambda", vr - L->lambda, FMU_OUTPUT, "constraint force (multiplier)", 0);
    set_unit(var, unit_of(m->multiplier_units, vr - L->lambda), 0);
  } else if (vr == L->max_abs_c) {
    named(var, "max_abs_c", FMU_OUTPUT, "the largest |c_j(t, q)|: the constraints' drift");
  } else {
    named(var, "energy", FMU_OUTPUT, "the energy v^T M v / 2 + V(q)");
    set_unit(var, m->energy_unit, 0);
  }
}

int fmu_var_at(const fmu_layout *L, size_t vr, fmu_var *var) {
  if (vr >= L->count) return -1;
  memset(var, 0, sizeof *var);
  var->vr = vr;
  if (vr < L->params) {
    solver_var(var, vr);
  } else if (vr < L->q0) {
    const sdae_fmu_param *p = &L->model->params[vr - L->params];
    named(var, p->name, FMU_PARAM, p->description);
    set_unit(var, p->unit, 0);
  } else if (vr < L->v0) {
    element(var, L, "q0", vr - L->q0, FMU_START, "start position", 1);
    set_unit(var, unit_of(L->model->coordinate_units, vr - L->q0), 0);
  } else if (vr < L->u) {
    element(var, L, "v0", vr - L->v0, FMU_START, "start velocity", 1);
    set_unit(var, unit_of(L->model->coordinate_units, vr - L->v0), 1);
  } else if (vr < L->q) {
    element(var, L, "u", vr - L->u, FMU_INPUT, "generalized force added to F", 1);
    set_unit(var, unit_of(L->model->force_units, vr - L->u), 0);
  } else {
    output_var(L, vr, var);
  }
  return 0;
}

/* FNV-1a, 64 bits */
static uint64_t fnv(uint64_t h, const char *s) {
  for (; *s; s++) {
    h ^= (unsigned char)*s;
    h *= 1099511628211U;
  }
  return h;
}

void fmu_token(const fmu_layout *L, const double *defaults, char out[40]) {
  uint64_t h1 = 14695981039346656037U, h2 = 0x6a09e667f3bcc908U;
  char buf[96];
  fmu_var var;
  snprintf(buf, sizeof buf, "%s %zu %zu %d %s", L->model->name, L->n_q, L->n_c, L->has_energy,
           L->model->map ? L->model->map : "");
  h1 = fnv(h1, buf);
  h2 = fnv(h2, buf);
  for (size_t vr = 0; fmu_var_at(L, vr, &var) == 0; vr++) {
    h1 = fnv(h1, var.name);
    h2 = fnv(h2, var.description);
    h2 = fnv(h2, var.unit);
    if (var.role == FMU_SOLVER || var.role == FMU_PARAM || var.role == FMU_START) {
      snprintf(buf, sizeof buf, "%.17g", defaults[vr]);
      h1 = fnv(h1, buf);
    }
  }
  snprintf(out, 40, "{%08x-%04x-%04x-%04x-%012llx}", (unsigned)(h1 >> 32),
           (unsigned)(h1 >> 16) & 0xffffU, (unsigned)h1 & 0xffffU, (unsigned)(h2 >> 48),
           (unsigned long long)(h2 & 0xffffffffffffULL));
}
