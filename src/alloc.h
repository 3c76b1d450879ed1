/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The library's only way to the heap: the caller's allocator, or malloc and free. */
#ifndef STABDAE_SRC_ALLOC_H
#define STABDAE_SRC_ALLOC_H

#include <stddef.h>

#include <stabdae/alloc.h>

/* size bytes (size > 0), or NULL; a NULL allocator, or one without alloc, is malloc */
void *sdae__alloc(const sdae_allocator *a, size_t size);
/* gives back what sdae__alloc returned with the same allocator and size; NULL is fine */
void sdae__free(const sdae_allocator *a, void *ptr, size_t size);
/* n elements of size bytes each, or NULL when n * size overflows or there is no room */
void *sdae__alloc_array(const sdae_allocator *a, size_t n, size_t size);

#endif /* STABDAE_SRC_ALLOC_H */
