/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The allocator hook: every allocation of the library goes through here; and the one block an
 * object lives in, made in the caller's memory or the allocator's. */
#include <stdint.h>
#include <stdlib.h>

#include <stabdae/base.h>

#include "alloc.h"
#include "arena.h"

static int custom(const sdae_allocator *a) { return a && a->alloc && a->free; }

void *sdae__alloc(const sdae_allocator *a, size_t size) {
  if (size == 0) return NULL;
  return custom(a) ? a->alloc(a->ud, size) : malloc(size);
}

void sdae__free(const sdae_allocator *a, void *ptr, size_t size) {
  if (!ptr) return;
  sdae__arena_release(ptr, size); /* carved or not, whole again for the allocator */
  if (custom(a))
    a->free(a->ud, ptr, size);
  else
    free(ptr);
}

void *sdae__alloc_array(const sdae_allocator *a, size_t n, size_t size) {
  if (size != 0 && n > SIZE_MAX / size) return NULL;
  return sdae__alloc(a, n * size);
}

void *sdae__block_alloc(sdae_block *b, const sdae_allocator *a, size_t bytes) {
  b->mem = sdae__alloc(a, bytes);
  b->bytes = bytes;
  b->caller = NULL;
  if (a)
    b->allocator = *a;
  else
    b->allocator = (sdae_allocator){0};
  return b->mem;
}

void sdae__block_caller(sdae_block *b, void *mem, size_t len) {
  *b = (sdae_block){NULL, len, {0}, mem};
}

void sdae__block_free(const sdae_block *b) {
  sdae_block copy = *b; /* b may live in the block it describes */
  if (copy.caller) {
    sdae__arena_release(copy.caller, copy.bytes);
    return;
  }
  sdae__free(&copy.allocator, copy.mem, copy.bytes);
}

int sdae__scratch_take(const sdae_scratch *s, size_t bytes, void **p) {
  if (s->mem) {
    *p = s->mem;
    return bytes <= s->len ? SDAE_OK : SDAE_ERR_BUFFER;
  }
  *p = sdae__alloc(s->allocator, bytes);
  return *p ? SDAE_OK : SDAE_ERR_NOMEM;
}

void sdae__scratch_give(const sdae_scratch *s, void *p, size_t bytes) {
  if (s->mem)
    sdae__arena_release(p, bytes);
  else
    sdae__free(s->allocator, p, bytes);
}

size_t sdae__block_size(const sdae_block_type *t, const void *args, const sdae_allocator *a) {
  const sdae_scratch from_a = {NULL, 0, a};
  size_t bytes;
  return t->measure(args, &from_a, &bytes) == SDAE_OK ? bytes : 0;
}

int sdae__block_init(const sdae_block_type *t, const void *args, void *mem, size_t len,
                     void **obj) {
  size_t bytes;
  sdae_block *block;
  void *o;
  int rc;
  if (!mem) return SDAE_ERR_NULL;
  const sdae_scratch in_place = {mem, len, NULL};
  if ((rc = t->measure(args, &in_place, &bytes)) != SDAE_OK) return rc;
  if (len < bytes) return SDAE_ERR_BUFFER;
  if ((rc = t->build(mem, args, &o, &block)) != SDAE_OK) {
    sdae__arena_release(mem, len); /* the caller's bytes as they were lent */
    return rc;
  }
  sdae__block_caller(block, mem, len);
  *obj = o;
  return SDAE_OK;
}

int sdae__block_new(const sdae_block_type *t, const void *args, const sdae_allocator *a,
                    void **obj) {
  sdae_block given;
  sdae_block *block;
  size_t bytes;
  void *mem, *o;
  const sdae_scratch from_a = {NULL, 0, a};
  int rc;
  if ((rc = t->measure(args, &from_a, &bytes)) != SDAE_OK) return rc;
  if (!(mem = sdae__block_alloc(&given, a, bytes))) return SDAE_ERR_NOMEM;
  if ((rc = t->build(mem, args, &o, &block)) != SDAE_OK) {
    sdae__block_free(&given);
    return rc;
  }
  *block = given;
  *obj = o;
  return SDAE_OK;
}
