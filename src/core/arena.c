/* SPDX-License-Identifier: GPL-3.0-or-later */
/* One block of memory, handed out array by array: the stepper's workspace, certify's search and
 * the model check's arrays. The same walk serves twice: without a base it only counts
 * (overflow-checked), with a base it hands out the pointers, each array zeroed: a part's state
 * before its first use is defined bytes (a fresh stepper's state as bytes is the same every
 * time). Only a part's set-up carves, never a step. */
#include <stdalign.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "arena.h"

#ifdef SDAE_ARENA_ASAN
#include <sanitizer/asan_interface.h>
#define POISON(p, n) ASAN_POISON_MEMORY_REGION((p), (n))
#define UNPOISON(p, n) ASAN_UNPOISON_MEMORY_REGION((p), (n))
#else
#define POISON(p, n) ((void)(p), (void)(n))
#define UNPOISON(p, n) ((void)(p), (void)(n))
#endif

static int mul_ok(size_t a, size_t b, size_t *out) {
  if (a != 0 && b > SIZE_MAX / a) return 0;
  *out = a * b;
  return 1;
}

void *sdae__take_array(sdae_arena *a, size_t n, size_t size, size_t align) {
  size_t bytes, at = (a->used + align - 1) / align * align, zone;
  if (a->overflow || a->used > SIZE_MAX - (align - 1) || !mul_ok(n, size, &bytes) ||
      bytes > SIZE_MAX - at) {
    a->overflow = 1;
    return NULL;
  }
  zone = (size_t)SDAE_ARENA_REDZONE * (bytes > 0); /* none after an empty array */
  if (zone > SIZE_MAX - at - bytes) {
    a->overflow = 1;
    return NULL;
  }
  a->used = at + bytes + zone;
  if (!a->base) return NULL;
  UNPOISON(a->base + at, bytes);
  memset(a->base + at, 0, bytes);
  POISON(a->base + at + bytes, zone);
  return a->base + at;
}

void sdae__arena_release(void *mem, size_t bytes) { UNPOISON(mem, bytes); }

void *sdae__arena_lend(sdae_arena *a, size_t n, size_t size, size_t align, size_t *mark) {
  *mark = a->used;
  return sdae__take_array(a, n, size, align);
}

void sdae__arena_reclaim(sdae_arena *a, size_t mark) {
  if (a->used > a->reach) a->reach = a->used;
  if (a->base) UNPOISON(a->base + mark, a->used - mark); /* the redzones lent with it */
  a->used = mark;
}

double *sdae__take(sdae_arena *a, size_t n1, size_t n2) {
  size_t n;
  if (!mul_ok(n1, n2, &n)) {
    a->overflow = 1;
    return NULL;
  }
  return sdae__take_array(a, n, sizeof(double), _Alignof(double));
}

unsigned *sdae__take_pivots(sdae_arena *a, size_t n) {
  return sdae__take_array(a, n, sizeof(unsigned), _Alignof(unsigned));
}

size_t *sdae__take_indices(sdae_arena *a, size_t n) {
  return sdae__take_array(a, n, sizeof(size_t), _Alignof(size_t));
}

int sdae__arena_bytes(const sdae_arena *a, size_t header, size_t *bytes) {
  size_t end = a->used > a->reach ? a->used : a->reach;
  if (a->overflow || end > SIZE_MAX - header) return SDAE_ERR_OVERFLOW;
  *bytes = header + end;
  return SDAE_OK;
}

/* A block holding an object (header bytes) and then its arrays, in memory of any alignment: the
 * object at the first max_align_t boundary, the arrays after it rounded to one. */
static size_t header_room(size_t header) {
  size_t al = alignof(max_align_t);
  return (header + al - 1) / al * al;
}

int sdae__block_bytes(const sdae_arena *a, size_t header, size_t *bytes) {
  return sdae__arena_bytes(a, header_room(header) + alignof(max_align_t) - 1, bytes);
}

/* The object's place is found by an offset from mem, never by turning an integer back into a
 * pointer: the pointer keeps its provenance. */
void *sdae__block_start(void *mem, size_t header, sdae_arena *a) {
  size_t al = alignof(max_align_t), pad = (al - (size_t)((uintptr_t)mem % al)) % al;
  char *at = (char *)mem + pad;
  a->base = at + header_room(header);
  a->used = a->reach = 0;
  a->overflow = 0;
  return at;
}
