/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The library's only way to the heap: the caller's allocator, or malloc and free. */
#ifndef STABDAE_SRC_CORE_ALLOC_H
#define STABDAE_SRC_CORE_ALLOC_H

#include <stddef.h>

#include <stabdae/alloc.h>

/* size bytes (size > 0), or NULL; a NULL allocator, or one without alloc or free, is malloc */
void *sdae__alloc(const sdae_allocator *a, size_t size);
/* gives back what sdae__alloc returned with the same allocator and size, its bytes unpoisoned
 * first (core/arena.h: a block carved under AddressSanitizer); NULL is fine */
void sdae__free(const sdae_allocator *a, void *ptr, size_t size);
/* n elements of size bytes each, or NULL when n * size overflows or there is no room */
void *sdae__alloc_array(const sdae_allocator *a, size_t n, size_t size);

/* The one block an object lives in: when the library allocated it, what to give back and to
 * whom. An object in the caller's memory has mem NULL and its block in caller: freeing it
 * gives nothing back, and makes the caller's bytes whole again (core/arena.h's redzones). */
typedef struct sdae_block {
  void *mem;
  size_t bytes;
  sdae_allocator allocator; /* zero: malloc and free */
  void *caller;             /* the caller's block (bytes long), or NULL */
} sdae_block;

/* bytes from the allocator a (NULL: malloc), recorded in *b; NULL when there is no room */
void *sdae__block_alloc(sdae_block *b, const sdae_allocator *a, size_t bytes);
/* the caller's memory (len bytes) recorded in *b as the block an object lives in */
void sdae__block_caller(sdae_block *b, void *mem, size_t len);
/* gives back the block *b describes (which may hold *b itself); nothing for mem NULL */
void sdae__block_free(const sdae_block *b);

/* Where a measure works out what its sizes depend on (a sparse mechanism's analysis): the
 * caller's memory when the object goes there (mem, len bytes: what the work needs is part of
 * the block, so a short block is short for it too), else bytes from the allocator (NULL:
 * malloc), given back before the measure returns. */
typedef struct sdae_scratch {
  void *mem;
  size_t len;
  const sdae_allocator *allocator;
} sdae_scratch;

/* bytes of scratch (bytes > 0) into *p: SDAE_OK, SDAE_ERR_BUFFER when the caller's memory is
 * shorter, SDAE_ERR_NOMEM when the allocator has no room */
int sdae__scratch_take(const sdae_scratch *s, size_t bytes, void **p);
/* gives back what sdae__scratch_take gave, bytes long, whole again (core/arena.h) */
void sdae__scratch_give(const sdae_scratch *s, void *p, size_t bytes);

/* An object that lives in one block (a stepper, a DAE's model, a mechanical stepper): what its
 * public size, init, alloc_with and free share, written once (alloc.c). measure validates the
 * arguments and gives the block's bytes (with room to align a caller's block), working in
 * scratch where it must; build makes the object in mem (measure's bytes long) and says where
 * it and its sdae_block are. A failed build leaves nothing behind but the block. */
typedef struct sdae_block_type {
  int (*measure)(const void *args, const sdae_scratch *scratch, size_t *bytes);
  int (*build)(void *mem, const void *args, void **obj, sdae_block **block);
} sdae_block_type;

/* the bytes an object needs, measured with scratch from the allocator a (NULL: malloc); 0 when
 * measure refuses its arguments or has no scratch */
size_t sdae__block_size(const sdae_block_type *t, const void *args, const sdae_allocator *a);
/* the object in the caller's memory mem[0..len): SDAE_ERR_NULL, measure's or build's refusal,
 * SDAE_ERR_BUFFER when len is short; *obj set on success alone */
int sdae__block_init(const sdae_block_type *t, const void *args, void *mem, size_t len, void **obj);
/* the object in a block from the allocator a (NULL: malloc): SDAE_ERR_NOMEM when there is no
 * room; *obj set on success alone */
int sdae__block_new(const sdae_block_type *t, const void *args, const sdae_allocator *a,
                    void **obj);

#endif /* STABDAE_SRC_CORE_ALLOC_H */
