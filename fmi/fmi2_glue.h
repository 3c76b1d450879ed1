/* SPDX-License-Identifier: GPL-3.0-or-later */
/* What the FMI 2.0 files share: the standard's header and the answer to a function the FMU
 * does not offer. */
#ifndef STABDAE_FMI_FMI2_GLUE_H
#define STABDAE_FMI_FMI2_GLUE_H

#include "fmi2Functions.h"

/* fmi2Error, with a message naming the function through the instance's logger */
fmi2Status fmi2_unsupported(fmi2Component c, const char *function);

#endif /* STABDAE_FMI_FMI2_GLUE_H */
