/* SPDX-License-Identifier: GPL-3.0-or-later */
/* What the FMI 3.0 files share: the standard's header and the answer to a function the FMU
 * does not offer. */
#ifndef STABDAE_FMI_FMI3_GLUE_H
#define STABDAE_FMI_FMI3_GLUE_H

#include "fmi3Functions.h"

/* fmi3Error, with a message naming the function through the instance's logger */
fmi3Status fmi3_unsupported(fmi3Instance instance, const char *function);

#endif /* STABDAE_FMI_FMI3_GLUE_H */
