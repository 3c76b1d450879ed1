/* SPDX-License-Identifier: GPL-3.0-or-later */
/* sdae_version: the library's version at run time, "MAJOR.MINOR.PATCH" as the project() line
 * of CMakeLists.txt gives it (through the generated <stabdae/version.h>). */
#include <stabdae/stabdae.h>

const char *sdae_version(void) { return SDAE_VERSION_STRING; }
