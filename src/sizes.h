/* Workspace sizes that cannot wrap around. */
#ifndef STABDAE_SRC_SIZES_H
#define STABDAE_SRC_SIZES_H

#include <stddef.h>
#include <stdint.h>

/* a + b c, or SIZE_MAX (which no allocator can give) when it does not fit in size_t; SIZE_MAX
 * as a, or as b with c > 0, stays SIZE_MAX */
static inline size_t sdae__size_mad(size_t a, size_t b, size_t c) {
  if (a == SIZE_MAX || (c != 0 && b > (SIZE_MAX - a) / c)) return SIZE_MAX;
  return a + b * c;
}

/* n rounded up to a multiple of align (a power of two), or SIZE_MAX */
static inline size_t sdae__size_align(size_t n, size_t align) {
  if (n == SIZE_MAX || n > SIZE_MAX - (align - 1)) return SIZE_MAX;
  return (n + align - 1) & ~(align - 1);
}

#endif /* STABDAE_SRC_SIZES_H */
