/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The export macro (layer: core): SDAE_API marks the public symbols: the library is built with
 * hidden visibility, so only what carries this macro is exported from the shared object. */
#ifndef STABDAE_EXPORT_H
#define STABDAE_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define SDAE_API __attribute__((visibility("default")))
#else
#define SDAE_API
#endif

#endif /* STABDAE_EXPORT_H */
