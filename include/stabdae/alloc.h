/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae allocator hook (layer: core): a user without a heap (or with an arena of its own) gives
 * the library an allocate/free pair, as Lua's lua_Alloc. Every allocating function of the library
 * has a form that takes one; NULL (or an allocator without alloc or free) means malloc and free. */
#ifndef STABDAE_ALLOC_H
#define STABDAE_ALLOC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdae_allocator {
  /* size > 0 bytes aligned for any type, or NULL when there is no room (never aborts) */
  void *(*alloc)(void *ud, size_t size);
  /* gives back a block of alloc with the size it was asked for; ptr is never NULL */
  void (*free)(void *ud, void *ptr, size_t size);
  void *ud; /* passed to both */
} sdae_allocator;

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_ALLOC_H */
