/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The table's macros (<stabdae/fmu.h>) and the describer's check of units and the stop time
 * (fmu_table_check), ctest fmi.table_macros:
 *   - SDAE_FMU_GENERATED_PARAMS over the generator's X-macro of today, X(field, default,
 *     "description"), gives no unit, and over the one with units, X(field, default,
 *     "description", "unit"), gives the unit (table_generated4.c);
 *   - SDAE_FMU_PARAM with and without a unit;
 *   - a unit too long or with a control character, T not positive, a stop time that is not a
 *     multiple of T are refused with a line naming the problem; the table with units accepted.
 * Exit status 0 when every check holds. */
#include <stdio.h>
#include <string.h>

#include <stabdae/fmu.h>

#include "fmu_describe.h"

static int failures;
#define CHECK(cond)                                                                                \
  do {                                                                                             \
    if (!(cond)) {                                                                                 \
      fprintf(stderr, "table_macros:%d: check failed: %s\n", __LINE__, #cond);                     \
      failures++;                                                                                  \
    }                                                                                              \
  } while (0)

const sdae_fmu_param *table_generated4(void);

typedef struct gen3_params {
  double a, b;
} gen3_params;

#define GEN3_PARAMETERS(X) X(a, 0.5, "first") X(b, -2.0, "second")

SDAE_FMU_GENERATED_PARAMS(gen3, GEN3_PARAMETERS);

static const sdae_fmu_param by_hand[] = {
    SDAE_FMU_PARAM(gen3_params, a, "first"),
    SDAE_FMU_PARAM(gen3_params, b, "second", "N*m"),
};

static int same(const char *a, const char *b) { return a && b && strcmp(a, b) == 0; }

static void macros(void) {
  const sdae_fmu_param *g4 = table_generated4();
  CHECK(same(gen3_fmu_params[0].name, "a") && gen3_fmu_params[0].start == 0.5 &&
        same(gen3_fmu_params[0].description, "first") && gen3_fmu_params[0].unit == NULL);
  CHECK(same(gen3_fmu_params[1].name, "b") && gen3_fmu_params[1].start == -2.0 &&
        gen3_fmu_params[1].offset == offsetof(gen3_params, b) && gen3_fmu_params[1].unit == NULL);
  CHECK(same(g4[0].name, "L") && g4[0].start == 1.5 && same(g4[0].description, "rod length") &&
        same(g4[0].unit, "m") && g4[0].offset == 0);
  CHECK(same(g4[1].name, "m") && g4[1].start == 2.0 && same(g4[1].description, "mass") &&
        same(g4[1].unit, "kg") && g4[1].offset == sizeof(double));
  CHECK(same(by_hand[0].description, "first") && by_hand[0].unit == NULL);
  CHECK(same(by_hand[1].description, "second") && same(by_hand[1].unit, "N*m") &&
        by_hand[1].offset == offsetof(gen3_params, b));
}

static sdae_mbs no_mbs(void *p) {
  (void)p;
  return (sdae_mbs){0};
}

/* fmu_table_check's answer on m, and whether its line on err holds `word` (NULL: no line) */
static int checked(const sdae_fmu *m, const char *word) {
  char line[512] = "";
  FILE *err = tmpfile();
  int rc;
  if (!err) return -2;
  rc = fmu_table_check(m, "gen", err);
  rewind(err);
  if (!fgets(line, sizeof line, err)) line[0] = '\0';
  fclose(err);
  if (word ? !strstr(line, word) : line[0] != '\0') {
    fprintf(stderr, "table_macros: the line \"%s\" does not say %s\n", line,
            word ? word : "nothing");
    return -3;
  }
  return rc;
}

static void checks(void) {
  sdae_fmu_param p[2] = {by_hand[0], by_hand[1]};
  const sdae_fmu good = {.name = "gen",
                         .params_size = sizeof(gen3_params),
                         .params = p,
                         .n_params = 2,
                         .mbs = no_mbs,
                         .T = 1e-3,
                         .delta = 2.0,
                         .epsilon = 1.0,
                         .map = "dgrad",
                         .stop_time = 2.5};
  sdae_fmu m = good;
  CHECK(checked(&good, NULL) == 0);
  p[1].unit = "0123456789012345678901234567890123456789x"; /* SDAE_FMU_UNIT_MAX + 1 */
  CHECK(checked(&m, "unit") == -1);
  p[1].unit = "N\nm";
  CHECK(checked(&m, "control character") == -1);
  p[1].unit = "0123456789012345678901234567890123456789"; /* SDAE_FMU_UNIT_MAX: taken */
  CHECK(checked(&m, NULL) == 0);
  m.stop_time = 2.5005; /* not a multiple of T */
  CHECK(checked(&m, "stop_time") == -1);
  m.stop_time = -1.0;
  CHECK(checked(&m, "stop_time") == -1);
  m.stop_time = 0.0; /* the default */
  CHECK(checked(&m, NULL) == 0);
  m.T = 0.0;
  CHECK(checked(&m, "T (0)") == -1);
}

int main(void) {
  macros();
  checks();
  if (failures) fprintf(stderr, "table_macros: %d checks failed\n", failures);
  return failures ? 1 : 0;
}
