/* SPDX-License-Identifier: GPL-3.0-or-later */
/* One block handed out array by array: the same walk, without a base, only counts
 * (overflow-checked). Every part of an object carves its own arrays from its owner's block. */
#ifndef STABDAE_SRC_CORE_ARENA_H
#define STABDAE_SRC_CORE_ARENA_H

#include <stddef.h>

/* Under AddressSanitizer every array is followed by SDAE_ARENA_REDZONE bytes, counted and
 * poisoned: a part that writes or reads past its own array into the next is caught there, not
 * absorbed by its neighbour (the block's size includes them: size and init still agree) */
#if defined(__SANITIZE_ADDRESS__)
#define SDAE_ARENA_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SDAE_ARENA_ASAN 1
#endif
#endif
#ifdef SDAE_ARENA_ASAN
#define SDAE_ARENA_REDZONE 16
#else
#define SDAE_ARENA_REDZONE 0
#endif

typedef struct sdae_arena {
  char *base; /* NULL: count only; else aligned for any type */
  size_t used;
  size_t reach; /* the end of lent workspace (sdae__arena_lend) */
  int overflow;
} sdae_arena;

/* n elements of size bytes, aligned to align (a power of two) */
void *sdae__take_array(sdae_arena *a, size_t n, size_t size, size_t align);
double *sdae__take(sdae_arena *a, size_t n1, size_t n2); /* n1 x n2 doubles */
unsigned *sdae__take_pivots(sdae_arena *a, size_t n);
size_t *sdae__take_indices(sdae_arena *a, size_t n);
/* Workspace a part's set-up uses once (an analysis'), lent from where the arrays taken after
 * it go: n elements of size bytes, aligned to align, and *mark where they start; handed back
 * by sdae__arena_reclaim before the next take, which overlays them. The block holds the
 * larger of the two. */
void *sdae__arena_lend(sdae_arena *a, size_t n, size_t size, size_t align, size_t *mark);
void sdae__arena_reclaim(sdae_arena *a, size_t mark);
/* a block's bytes made whole again (its redzones unpoisoned) before it is given back: a
 * caller's allocator may hand them out anew */
void sdae__arena_release(void *mem, size_t bytes);
/* header + the arrays counted, in bytes; SDAE_ERR_OVERFLOW when that does not fit in size_t */
int sdae__arena_bytes(const sdae_arena *a, size_t header, size_t *bytes);
/* a block of an object (header bytes) and the arrays counted in a, in memory of any alignment:
 * its bytes (with room to align the caller's memory); and, in mem, where the object goes, with
 * a set to hand out the arrays after it */
int sdae__block_bytes(const sdae_arena *a, size_t header, size_t *bytes);
void *sdae__block_start(void *mem, size_t header, sdae_arena *a);

#endif /* STABDAE_SRC_CORE_ARENA_H */
