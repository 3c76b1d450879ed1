/* The stepper's workspace: one block, handed out array by array. Each module (map, Newton,
 * stabilizer, stepper) takes its own arrays; the same walk, without a base, counts them. */
#include <stdint.h>

#include "internal.h"

static int add_ok(size_t *acc, size_t a) {
  if (a > SIZE_MAX - *acc) return 0;
  *acc += a;
  return 1;
}

static int mul_ok(size_t a, size_t b, size_t *out) {
  if (a != 0 && b > SIZE_MAX / a) return 0;
  *out = a * b;
  return 1;
}

double *sdae__take(sdae_arena *a, size_t n1, size_t n2) {
  size_t n;
  if (!mul_ok(n1, n2, &n) || !add_ok(&a->nd, n)) {
    a->overflow = 1;
    return NULL;
  }
  return a->dbase ? a->dbase + (a->nd - n) : NULL;
}

unsigned *sdae__take_pivots(sdae_arena *a, size_t n) {
  if (!add_ok(&a->nu, n)) {
    a->overflow = 1;
    return NULL;
  }
  return a->ubase ? a->ubase + (a->nu - n) : NULL;
}

int sdae__arena_bytes(const sdae_arena *a, size_t header, size_t *bytes) {
  size_t db, ub;
  *bytes = header;
  if (a->overflow || !mul_ok(a->nd, sizeof(double), &db) || !add_ok(bytes, db) ||
      !mul_ok(a->nu, sizeof(unsigned), &ub) || !add_ok(bytes, ub))
    return SDAE_ERR_OVERFLOW;
  return SDAE_OK;
}
