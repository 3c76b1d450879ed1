/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "fmu_describe.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* s with the five XML entities */
static void xml_text(FILE *out, const char *s) {
  for (; s && *s; s++) {
    switch (*s) {
    case '&': fputs("&amp;", out); break;
    case '<': fputs("&lt;", out); break;
    case '>': fputs("&gt;", out); break;
    case '"': fputs("&quot;", out); break;
    case '\'': fputs("&apos;", out); break;
    default: fputc(*s, out);
    }
  }
}

static int identifier(const char *s) {
  if (!s || !(isalpha((unsigned char)*s) || *s == '_')) return 0;
  for (; *s; s++)
    if (!(isalnum((unsigned char)*s) || *s == '_')) return 0;
  return 1;
}

/* a unit the XML can hold: none, or at most SDAE_FMU_UNIT_MAX characters, no control
 * character */
static int unit_ok(const char *u) {
  if (!u) return 1;
  if (strlen(u) > SDAE_FMU_UNIT_MAX) return 0;
  for (; *u; u++)
    if ((unsigned char)*u < 0x20 || *u == 0x7f) return 0;
  return 1;
}

/* the n units of a table's optional list: 0, or -1 with a line on err */
static int units_ok(const sdae_fmu *m, const char *what, const char *const *units, size_t n,
                    FILE *err) {
  for (size_t i = 0; units && i < n; i++)
    if (!unit_ok(units[i])) {
      fprintf(err, "%s: %s %zu: a unit of more than %d characters, or with a control character\n",
              m->name, what, i + 1, SDAE_FMU_UNIT_MAX);
      return -1;
    }
  return 0;
}

/* the DefaultExperiment's stop time: the table's, or 1000 steps of T */
static double stop_time(const sdae_fmu *m) {
  return m->stop_time > 0.0 ? m->stop_time : 1000.0 * m->T;
}

/* T positive and finite; a stop time of the table's own (0: the default) a whole number of
 * steps of T, so that an importer stepping by the XML's stepSize lands on it */
static int experiment_ok(const sdae_fmu *m, FILE *err) {
  double k = stop_time(m) / m->T;
  if (isfinite(m->T) && m->T > 0.0 && isfinite(m->stop_time) && m->stop_time >= 0.0 &&
      isfinite(k) && fabs(k - round(k)) <= 1e-9 * k)
    return 0;
  fprintf(err, "%s: T (%g) must be positive and finite, stop_time (%g) 0 or a multiple of T\n",
          m->name, m->T, m->stop_time);
  return -1;
}

int fmu_table_check(const sdae_fmu *m, const char *name, FILE *err) {
  if (!identifier(m->name) || !m->mbs || !m->map || !sdae_map_by_name(m->map) ||
      (m->n_params && !m->params)) {
    fprintf(err, "sdae_fmu_model: a name that is an identifier, mbs, a known map and the "
                 "parameters' table are needed\n");
    return -1;
  }
  if (strcmp(m->name, name) != 0) {
    fprintf(err,
            "sdae_fmu_model: its name %s is not the FMU's %s (stabdae_add_fmu's NAME is the "
            "binary's name, which modelDescription.xml must give)\n",
            m->name, name);
    return -1;
  }
  for (size_t i = 0; i < m->n_params; i++)
    if (!identifier(m->params[i].name) || strlen(m->params[i].name) >= FMU_NAME_LEN ||
        m->params[i].offset + sizeof(double) > m->params_size) {
      fprintf(err,
              "%s: parameter %zu (%s): not an identifier of at most %d characters, or its "
              "offset is past the params struct\n",
              m->name, i + 1, m->params[i].name ? m->params[i].name : "(null)", FMU_NAME_LEN - 1);
      return -1;
    }
  for (size_t i = 0; i < m->n_params; i++)
    if (units_ok(m, m->params[i].name, &m->params[i].unit, 1, err) != 0) return -1;
  return experiment_ok(m, err);
}

int fmu_describe_check(const fmu_instance *fi, FILE *err) {
  const sdae_fmu *m = fi->model;
  const sdae_mbs sys = m->mbs(fi->params);
  size_t rank = sys.rank ? sys.rank : fi->layout.n_c; /* redundant constraints: rank < n_c */
  fmu_var a, b;
  if (fi->layout.n_q == 0 || fi->layout.n_c == 0 || sys.rank > fi->layout.n_c ||
      rank >= fi->layout.n_q) {
    fprintf(err,
            "%s: the mechanism needs 1 <= n_c, its rank at most n_c and below n_q (n_q %zu, n_c "
            "%zu, rank %zu)\n",
            m->name, fi->layout.n_q, fi->layout.n_c, rank);
    return -1;
  }
  for (size_t i = 0; fmu_var_at(&fi->layout, i, &a) == 0; i++)
    for (size_t j = i + 1; fmu_var_at(&fi->layout, j, &b) == 0; j++)
      if (strcmp(a.name, b.name) == 0) {
        fprintf(err, "%s: two variables are named %s (rename the parameter)\n", m->name, a.name);
        return -1;
      }
  if (units_ok(m, "coordinate_units", m->coordinate_units, fi->layout.n_q, err) != 0 ||
      units_ok(m, "force_units", m->force_units, fi->layout.n_q, err) != 0 ||
      units_ok(m, "multiplier_units", m->multiplier_units, fi->layout.n_c, err) != 0 ||
      units_ok(m, "energy_unit", &m->energy_unit, 1, err) != 0)
    return -1;
  return 0;
}

static const char *causality(fmu_role role) {
  static const char *const c[] = {"independent", "parameter", "parameter",
                                  "parameter",   "input",     "output"};
  return c[role];
}

static void attributes(FILE *out, const fmu_var *v) {
  fprintf(out, " name=\"%s\" valueReference=\"%zu\" description=\"", v->name, v->vr);
  xml_text(out, v->description);
  fprintf(out, "\" causality=\"%s\" variability=\"%s\"", causality(v->role),
          v->role == FMU_TIME || v->role == FMU_INPUT || v->role == FMU_OUTPUT ? "continuous"
                                                                               : "fixed");
}

/* the unit attribute (FMI 3.0's Float64, FMI 2.0's Real), when the variable has one */
static void unit_attribute(FILE *out, const fmu_var *v) {
  if (!*v->unit) return;
  fputs(" unit=\"", out);
  xml_text(out, v->unit);
  fputs("\"", out);
}

/* the SI dimensions, in the order of BaseUnit's attributes */
#define FMU_DIMS 8
static const char *const dim_name[FMU_DIMS] = {"kg", "m", "s", "A", "K", "mol", "cd", "rad"};

/* the dimensions of the symbol s[0..len): 0, or -1 when it is none of the SI units below */
static int symbol_dims(const char *s, size_t len, int dims[FMU_DIMS]) {
  static const struct {
    const char *name;
    int dims[FMU_DIMS];
  } known[] = {{"1", {0}},
               {"kg", {1}},
               {"m", {0, 1}},
               {"s", {0, 0, 1}},
               {"A", {0, 0, 0, 1}},
               {"K", {0, 0, 0, 0, 1}},
               {"mol", {0, 0, 0, 0, 0, 1}},
               {"cd", {0, 0, 0, 0, 0, 0, 1}},
               {"rad", {0, 0, 0, 0, 0, 0, 0, 1}},
               {"N", {1, 1, -2}},
               {"J", {1, 2, -2}},
               {"W", {1, 2, -3}},
               {"Pa", {1, -1, -2}},
               {"Hz", {0, 0, -1}}};
  for (size_t k = 0; k < sizeof known / sizeof *known; k++)
    if (strlen(known[k].name) == len && strncmp(s, known[k].name, len) == 0) {
      memcpy(dims, known[k].dims, sizeof known[k].dims);
      return 0;
    }
  return -1;
}

/* The dimensions of a unit written as symbols of symbol_dims joined by '*' and '/' (read from
 * the left), each with an optional integer power: "N*s/m", "kg*m^2", "m/s^2", "1/s". 0, or -1
 * when it is not written so: the unit is then a name alone. */
static int unit_dims(const char *u, int dims[FMU_DIMS]) {
  int sign = 1;
  memset(dims, 0, FMU_DIMS * sizeof *dims);
  for (;;) {
    size_t len = strcspn(u, "*/^");
    int f[FMU_DIMS];
    long power = 1;
    if (len == 0 || symbol_dims(u, len, f) != 0) return -1;
    u += len;
    if (*u == '^') {
      char *end;
      power = strtol(u + 1, &end, 10);
      if (end == u + 1 || power < -99 || power > 99) return -1;
      u = end;
    }
    for (int d = 0; d < FMU_DIMS; d++) dims[d] += sign * (int)power * f[d];
    if (*u == '\0') return 0;
    if (*u != '*' && *u != '/') return -1;
    sign = *u++ == '/' ? -1 : 1;
  }
}

/* one Unit, with its BaseUnit when its name is written in SI symbols (unit_dims) */
static void unit_definition(FILE *out, const char *unit) {
  int dims[FMU_DIMS];
  fputs("    <Unit name=\"", out);
  xml_text(out, unit);
  if (unit_dims(unit, dims) != 0) {
    fputs("\"/>\n", out);
    return;
  }
  fputs("\">\n      <BaseUnit", out);
  for (int d = 0; d < FMU_DIMS; d++)
    if (dims[d]) fprintf(out, " %s=\"%d\"", dim_name[d], dims[d]);
  fputs("/>\n    </Unit>\n", out);
}

/* UnitDefinitions: every unit a variable has, once, in the order of the value references */
static void unit_definitions(FILE *out, const fmu_layout *L) {
  fmu_var v, w;
  int any = 0;
  for (size_t vr = 0; fmu_var_at(L, vr, &v) == 0; vr++) {
    int seen = !*v.unit;
    for (size_t k = 0; !seen && k < vr && fmu_var_at(L, k, &w) == 0; k++)
      seen = strcmp(v.unit, w.unit) == 0;
    if (seen) continue;
    fputs(any++ ? "" : "  <UnitDefinitions>\n", out);
    unit_definition(out, v.unit);
  }
  if (any) fputs("  </UnitDefinitions>\n", out);
}

static void variable3(FILE *out, const fmu_instance *fi, const fmu_var *v) {
  if (v->is_string) {
    fputs("    <String", out);
    attributes(out, v);
    fprintf(out, ">\n      <Start value=\"%s\"/>\n    </String>\n", fi->model->map);
    return;
  }
  fputs("    <Float64", out);
  attributes(out, v);
  unit_attribute(out, v);
  if (v->role != FMU_TIME && v->role != FMU_OUTPUT)
    fprintf(out, " start=\"%.17g\"", fi->values[v->vr]);
  fputs("/>\n", out);
}

static void variable2(FILE *out, const fmu_instance *fi, const fmu_var *v) {
  fputs("    <ScalarVariable", out);
  attributes(out, v);
  if (v->role == FMU_OUTPUT) fputs(" initial=\"calculated\"", out);
  if (v->role == FMU_SOLVER || v->role == FMU_PARAM || v->role == FMU_START)
    fputs(" initial=\"exact\"", out);
  fputs(">\n", out);
  if (v->is_string) {
    fprintf(out, "      <String start=\"%s\"/>\n", fi->model->map);
  } else {
    fputs("      <Real", out);
    unit_attribute(out, v);
    if (v->role != FMU_TIME && v->role != FMU_OUTPUT)
      fprintf(out, " start=\"%.17g\"", fi->values[v->vr]);
    fputs("/>\n", out);
  }
  fputs("    </ScalarVariable>\n", out);
}

/* An output's direct dependencies on the inputs at a communication point: lambda depends on
 * every u (the constraint forces balance the applied ones), q, v, max_abs_c and energy on none
 * (u moves them only through the steps). References by value reference (3.0) or by index in
 * the list (2.0, 1-based: the list is in value reference order). */
static void dependencies(FILE *out, const fmu_layout *L, size_t vr, size_t base) {
  fputs(" dependencies=\"", out);
  if (vr >= L->lambda && vr < L->max_abs_c)
    for (size_t i = 0; i < L->n_q; i++) fprintf(out, "%s%zu", i ? " " : "", L->u + i + base);
  fputs("\"", out);
}

/* the outputs and initial unknowns (these depending on every known: no dependencies given) */
static void structure(FILE *out, const fmu_instance *fi, int version) {
  const fmu_layout *L = &fi->layout;
  fputs("  <ModelStructure>\n", out);
  if (version == 3) {
    for (size_t vr = L->q; vr < L->count; vr++) {
      fprintf(out, "    <Output valueReference=\"%zu\"", vr);
      dependencies(out, L, vr, 0);
      fputs("/>\n", out);
    }
    for (size_t vr = L->q; vr < L->count; vr++)
      fprintf(out, "    <InitialUnknown valueReference=\"%zu\"/>\n", vr);
  } else {
    fputs("    <Outputs>\n", out);
    for (size_t vr = L->q; vr < L->count; vr++) {
      fprintf(out, "      <Unknown index=\"%zu\"", vr + 1);
      dependencies(out, L, vr, 1);
      fputs("/>\n", out);
    }
    fputs("    </Outputs>\n    <InitialUnknowns>\n", out);
    for (size_t vr = L->q; vr < L->count; vr++)
      fprintf(out, "      <Unknown index=\"%zu\"/>\n", vr + 1);
    fputs("    </InitialUnknowns>\n", out);
  }
  fputs("  </ModelStructure>\n", out);
}

static void categories(FILE *out) {
  fputs("  <LogCategories>\n"
        "    <Category name=\"logStatusError\" description=\"errors: bad input, a failed step\"/>\n"
        "    <Category name=\"logStatusWarning\" description=\"warnings\"/>\n"
        "    <Category name=\"logInfo\" description=\"what the FMU does (with logging on)\"/>\n"
        "  </LogCategories>\n",
        out);
}

int fmu_describe_xml(const fmu_instance *fi, int version, const char *generator, FILE *out) {
  const sdae_fmu *m = fi->model;
  const char *token = fi->token;
  fmu_var v;
  fprintf(out,
          "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription\n"
          "  fmiVersion=\"%s\"\n  modelName=\"%s\"\n  %s=\"%s\"\n  description=\"",
          version == 3 ? "3.0" : "2.0", m->name, version == 3 ? "instantiationToken" : "guid",
          token);
  xml_text(out, m->description);
  fprintf(out, "\"\n  generationTool=\"");
  xml_text(out, generator);
  fprintf(out, "\"\n  variableNamingConvention=\"structured\"%s>\n",
          version == 2 ? "\n  numberOfEventIndicators=\"0\"" : "");
  fprintf(out,
          "  <CoSimulation\n    modelIdentifier=\"%s\"\n"
          "    canHandleVariableCommunicationStepSize=\"true\"\n"
          "    %s=\"true\"\n    %s=\"true\"%s/>\n",
          m->name, version == 3 ? "canGetAndSetFMUState" : "canGetAndSetFMUstate",
          version == 3 ? "canSerializeFMUState" : "canSerializeFMUstate",
          version == 3 ? "\n    hasEventMode=\"false\"" : "");
  unit_definitions(out, &fi->layout);
  categories(out);
  fprintf(out, "  <DefaultExperiment startTime=\"0\" stopTime=\"%.17g\" stepSize=\"%.17g\"/>\n",
          stop_time(m), m->T);
  fputs("  <ModelVariables>\n", out);
  for (size_t vr = 0; fmu_var_at(&fi->layout, vr, &v) == 0; vr++)
    (version == 3 ? variable3 : variable2)(out, fi, &v);
  fputs("  </ModelVariables>\n", out);
  structure(out, fi, version);
  fputs("</fmiModelDescription>\n", out);
  return ferror(out) ? -1 : 0;
}

int fmu_describe_page(const fmu_instance *fi, FILE *out) {
  static const char *const role[] = {
      "independent", "solver parameter", "parameter", "start state", "input", "output"};
  const sdae_fmu *m = fi->model;
  fmu_var v;
  fputs("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>", out);
  xml_text(out, m->name);
  fputs("</title></head><body>\n<h1>", out);
  xml_text(out, m->name);
  fputs("</h1>\n<p>", out);
  xml_text(out, m->description);
  fprintf(out,
          "</p>\n<p>A mechanism with %zu coordinates q and %zu constraints c(t, q) = 0, "
          "integrated by stabdae with a fixed internal step T and no constraint drift. A "
          "communication step h is cut into steps of T when it is a multiple of T (exactly the "
          "fixed-step run), else into ceil(h/T) equal steps. The inputs u are generalized forces "
          "added to F, held over a communication step. The parameters are fixed: set them "
          "before exitInitializationMode. Setting any of q0, v0 replaces the start state the "
          "model computes from its parameters.</p>\n",
          fi->layout.n_q, fi->layout.n_c);
  fputs("<table border=\"1\">\n<tr><th>value reference</th><th>name</th><th>role</th>"
        "<th>default</th><th>unit</th><th>description</th></tr>\n",
        out);
  for (size_t vr = 0; fmu_var_at(&fi->layout, vr, &v) == 0; vr++) {
    fprintf(out, "<tr><td>%zu</td><td>%s</td><td>%s</td><td>", vr, v.name, role[v.role]);
    if (v.is_string)
      xml_text(out, m->map);
    else if (v.role != FMU_TIME && v.role != FMU_OUTPUT)
      fprintf(out, "%.17g", fi->values[vr]);
    fputs("</td><td>", out);
    xml_text(out, v.unit);
    fputs("</td><td>", out);
    xml_text(out, v.description);
    fputs("</td></tr>\n", out);
  }
  fputs("</table>\n<p>Licences: licenses/ (stabdae: GPL-3.0-or-later; the FMI headers: "
        "BSD-2-Clause).</p>\n</body></html>\n",
        out);
  return ferror(out) ? -1 : 0;
}
