/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The describer, run by stabdae_add_fmu at build time, linked with the model's own table:
 *   NAME_describe VERSION XML PAGE NAME
 * checks the table (its name must be NAME, the FMU's), then writes modelDescription.xml for FMI
 * VERSION (3 or 2) to XML and the variables' page to PAGE.
 * Exit status 0, or 1 with a line on stderr. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "fmu_describe.h"

static int write_file(const char *path, const fmu_instance *fi, int version) {
  FILE *f = fopen(path, "w");
  int rc;
  char generator[64];
  if (!f) {
    fprintf(stderr, "describe: cannot write %s\n", path);
    return -1;
  }
  snprintf(generator, sizeof generator, "stabdae %s", SDAE_VERSION_STRING);
  rc = version ? fmu_describe_xml(fi, version, generator, f) : fmu_describe_page(fi, f);
  if (fclose(f) != 0 || rc != 0) {
    fprintf(stderr, "describe: cannot write %s\n", path);
    return -1;
  }
  return 0;
}

int main(int argc, char **argv) {
  fmu_instance *fi;
  int version, rc = 0;
  if (argc != 5 || (strcmp(argv[1], "3") != 0 && strcmp(argv[1], "2") != 0)) {
    fprintf(stderr, "usage: %s 3|2 modelDescription.xml page.html NAME\n", argv[0]);
    return 1;
  }
  version = argv[1][0] - '0'; /* "3" or "2" */
  if (fmu_table_check(&sdae_fmu_model, argv[4], stderr) != 0) return 1;
  if (!(fi = fmu_instantiate(NULL, NULL, NULL, NULL, NULL, 0))) {
    fprintf(stderr, "describe: cannot instantiate the model\n");
    return 1;
  }
  if (fmu_describe_check(fi, stderr) != 0 || write_file(argv[2], fi, version) != 0 ||
      write_file(argv[3], fi, 0) != 0)
    rc = 1;
  fmu_free(fi);
  return rc;
}
