/* SPDX-License-Identifier: GPL-3.0-or-later */
/* modelDescription.xml (FMI 3.0 or 2.0) and the page on the variables of the FMU in
 * documentation/, from the same variable list the binary answers with (fmu_vars.h) and the
 * defaults of a fresh instance: what the XML says and what the binary does cannot differ. */
#ifndef STABDAE_FMI_FMU_DESCRIBE_H
#define STABDAE_FMI_FMU_DESCRIBE_H

#include <stdio.h>

#include "fmu_instance.h"

/* The table alone, before an instance reads it: 0, or -1 with a line on err when it is
 * incomplete, a name is not an identifier (or too long), an offset is past the params struct,
 * a parameter's unit is too long or holds a control character, T is not positive and finite or
 * stop_time not 0 or a multiple of T, or its name is not `name`, the FMU's (stabdae_add_fmu's
 * NAME). */
int fmu_table_check(const sdae_fmu *m, const char *name, FILE *err);
/* The instance's variables: 0, or -1 with a line on err when the sizes are not
 * 1 <= n_c with the mechanism's rank (n_c, or its rank where some constraints are redundant)
 * at most n_c and below n_q, two variables have one name, or a unit of the coordinates, forces,
 * multipliers or energy is too long or holds a control character. */
int fmu_describe_check(const fmu_instance *fi, FILE *err);
/* version 3 or 2; 0, or -1 when a write fails */
int fmu_describe_xml(const fmu_instance *fi, int version, const char *generator, FILE *out);
/* the documentation page (HTML): the model, its variables with their defaults */
int fmu_describe_page(const fmu_instance *fi, FILE *out);

#endif /* STABDAE_FMI_FMU_DESCRIBE_H */
