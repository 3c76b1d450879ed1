/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The arena of src/core/arena.c: arrays counted and handed out from one block, each aligned to its
 * type, sizes that overflow size_t reported instead of wrapped; and through the public API, a
 * model too large for size_t gives SDAE_ERR_OVERFLOW. */
#include <stdalign.h>
#include <stddef.h>
#include <stdint.h>

#include "testmodels.h"

#include "core/arena.h"
#ifdef SDAE_ARENA_ASAN
#include <sanitizer/asan_interface.h>
#endif
#include "core/lu.h"
#include "maps/map.h"
#include "stepper/stepper.h"

static size_t round_up(size_t v, size_t a) { return (v + a - 1) / a * a; }

#define RZ SDAE_ARENA_REDZONE /* after each array under AddressSanitizer, else 0 */

/* The same walk twice, counted and handed out: doubles (3), pivots (3), a 2 x 5 block of
 * doubles, 5 bytes aligned for any type, 2 size_t. The offsets, by hand: each array starts at
 * the end of the previous one (and its redzone) rounded up to its alignment. */
typedef struct walk {
  double *a, *c;
  unsigned *b;
  char *d;
  size_t *e;
} walk;

static walk take_all(sdae_arena *ar) {
  walk w;
  w.a = sdae__take(ar, 3, 1);
  w.b = sdae__take_pivots(ar, 3);
  w.c = sdae__take(ar, 2, 5);
  w.d = sdae__take_array(ar, 5, 1, alignof(max_align_t));
  w.e = sdae__take_array(ar, 2, sizeof(size_t), alignof(size_t));
  return w;
}

START_TEST(counts_and_aligns) {
  static max_align_t block[32];
  sdae_arena count = {0}, hand = {.base = (char *)block};
  size_t oa = 0, ob = oa + 3 * sizeof(double) + RZ;
  size_t ob_at = round_up(ob, alignof(unsigned));
  size_t oc = round_up(ob_at + 3 * sizeof(unsigned) + RZ, alignof(double));
  size_t od = round_up(oc + 10 * sizeof(double) + RZ, alignof(max_align_t));
  size_t oe = round_up(od + 5 + RZ, alignof(size_t));
  size_t end = oe + 2 * sizeof(size_t) + RZ, bytes;
  walk w = take_all(&count);
  /* counting hands out nothing */
  ck_assert_ptr_null(w.a);
  ck_assert_ptr_null(w.b);
  ck_assert_ptr_null(w.c);
  ck_assert_ptr_null(w.d);
  ck_assert_ptr_null(w.e);
  ck_assert_int_eq(count.overflow, 0);
  ck_assert_uint_eq(count.used, end);
  ck_assert_int_eq(sdae__arena_bytes(&count, 40, &bytes), SDAE_OK);
  ck_assert_uint_eq(bytes, 40 + end); /* header + the arrays */
  ck_assert_uint_le(end, sizeof block);
  w = take_all(&hand);
  ck_assert_uint_eq(hand.used, end);
  ck_assert_ptr_eq(w.a, (double *)((char *)block + oa));
  ck_assert_ptr_eq(w.b, (unsigned *)((char *)block + ob_at));
  ck_assert_ptr_eq(w.c, (double *)((char *)block + oc));
  ck_assert_ptr_eq(w.d, (char *)block + od);
  ck_assert_ptr_eq(w.e, (size_t *)((char *)block + oe));
  /* each array aligned for its type */
  ck_assert_uint_eq((uintptr_t)w.a % alignof(double), 0);
  ck_assert_uint_eq((uintptr_t)w.b % alignof(unsigned), 0);
  ck_assert_uint_eq((uintptr_t)w.c % alignof(double), 0);
  ck_assert_uint_eq((uintptr_t)w.d % alignof(max_align_t), 0);
  ck_assert_uint_eq((uintptr_t)w.e % alignof(size_t), 0);
}
END_TEST

/* empty arrays take no room (but their alignment) and never overflow */
START_TEST(empty_arrays) {
  sdae_arena a = {0};
  size_t bytes;
  sdae__take(&a, 0, 5);
  sdae__take(&a, 5, 0);
  sdae__take_array(&a, 0, 8, 8);
  sdae__take_array(&a, 7, 0, 1);
  ck_assert_int_eq(a.overflow, 0);
  ck_assert_uint_eq(a.used, 0);
  sdae__take_array(&a, 1, 1, 1);
  sdae__take_array(&a, 0, 8, 8); /* aligns: 1 -> 8 (1 + RZ rounded up) */
  ck_assert_uint_eq(a.used, round_up(1 + RZ, 8));
  ck_assert_int_eq(sdae__arena_bytes(&a, 0, &bytes), SDAE_OK);
  ck_assert_uint_eq(bytes, round_up(1 + RZ, 8));
}
END_TEST

static void overflowed(sdae_arena *a) {
  size_t bytes = 12345;
  ck_assert_int_eq(a->overflow, 1);
  ck_assert_int_eq(sdae__arena_bytes(a, 0, &bytes), SDAE_ERR_OVERFLOW);
  ck_assert_uint_eq(bytes, 12345); /* untouched */
}

/* each overflow check, just past its limit, and the largest size that still fits */
START_TEST(overflow_each_check) {
  sdae_arena a = {0};
  size_t bytes;
  /* n1 x n2 doubles: the element count overflows */
  ck_assert_ptr_null(sdae__take(&a, SIZE_MAX / 2 + 1, 2));
  overflowed(&a);
  /* n x size bytes */
  a = (sdae_arena){0};
  sdae__take_array(&a, SIZE_MAX / 8 + 1, 8, 8);
  overflowed(&a);
  a = (sdae_arena){0};
  sdae__take(&a, SIZE_MAX / 8 + 1, 1); /* fits as a count, not as bytes */
  overflowed(&a);
  /* rounding used up to the alignment: SIZE_MAX - 7 = 2^N - 8 is aligned to 8, one more is
   * not and rounds past SIZE_MAX */
  a = (sdae_arena){.used = SIZE_MAX - 7};
  sdae__take_array(&a, 0, 8, 8);
  ck_assert_int_eq(a.overflow, 0);
  ck_assert_uint_eq(a.used, SIZE_MAX - 7);
  a = (sdae_arena){.used = SIZE_MAX - 6};
  sdae__take_array(&a, 0, 8, 8);
  overflowed(&a);
  /* the array past the end: 8 + (SIZE_MAX - 8) = SIZE_MAX fits (with its redzone), one byte
   * more does not */
  a = (sdae_arena){.used = 8};
  sdae__take_array(&a, SIZE_MAX - 8 - RZ, 1, 1);
  ck_assert_int_eq(a.overflow, 0);
  ck_assert_uint_eq(a.used, SIZE_MAX);
  a = (sdae_arena){.used = 8};
  sdae__take_array(&a, SIZE_MAX - 7 - RZ, 1, 1);
  overflowed(&a);
  a = (sdae_arena){.used = 0};
  sdae__take_array(&a, SIZE_MAX - RZ, 1, 1); /* the whole of size_t, from 0 */
  ck_assert_int_eq(a.overflow, 0);
  ck_assert_uint_eq(a.used, SIZE_MAX);
  /* the header: used + header must fit */
  a = (sdae_arena){.used = 10};
  ck_assert_int_eq(sdae__arena_bytes(&a, SIZE_MAX - 10, &bytes), SDAE_OK);
  ck_assert_uint_eq(bytes, SIZE_MAX);
  ck_assert_int_eq(sdae__arena_bytes(&a, SIZE_MAX - 9, &bytes), SDAE_ERR_OVERFLOW);
  /* an overflow sticks: a later small array is neither counted nor handed out */
  {
    static max_align_t block[4];
    sdae_arena b = {.base = (char *)block};
    sdae__take(&b, SIZE_MAX, SIZE_MAX);
    ck_assert_ptr_null(sdae__take(&b, 1, 1));
    ck_assert_ptr_null(sdae__take_pivots(&b, 1));
    ck_assert_uint_eq(b.used, 0);
    overflowed(&b);
  }
}
END_TEST

/* The stepper's workspace through the public API: n_mu doubles several times over, with n_mu
 * = SIZE_MAX / 16 (each array fits, their sum does not) or SIZE_MAX / 4 (one array's bytes do
 * not fit), and a dense n_mu x n_xi Q whose element count overflows. */
START_TEST(stepper_too_large_for_size_t) {
  quartic p = {2.0, 0.03, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s = NULL;
  const size_t sizes[3] = {SIZE_MAX / 16, SIZE_MAX / 4, SIZE_MAX / 2 + 1};
  ck_assert_uint_gt(sdae_stepper_size(&m, &o), 0); /* the model as it is fits */
  for (int i = 0; i < 3; i++) {
    m.n_mu = sizes[i];
    ck_assert_uint_eq(sdae_stepper_size(&m, &o), 0);
    ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_ERR_OVERFLOW);
    ck_assert_ptr_null(s);
  }
}
END_TEST

/* The arrays lie end to end but for the redzones; under AddressSanitizer the bytes between two
 * carved arrays are poisoned, every byte of an array is not, and a block given back is whole
 * again.
 * A part that carves one double short and writes its last entry is then caught at that write,
 * not absorbed by the next array. */
START_TEST(the_gaps_between_arrays_are_poisoned) {
  static max_align_t block[16];
  sdae_arena a = {.base = (char *)block};
  double *x = sdae__take(&a, 3, 1);
  unsigned char *flags = sdae__take_array(&a, 5, 1, 1);
  double *y = sdae__take(&a, 2, 1);
  ck_assert_ptr_eq(x, (double *)block);
  ck_assert_ptr_eq(flags, (unsigned char *)block + 3 * sizeof(double) + RZ);
  ck_assert_ptr_eq(y, (double *)((char *)block + round_up(3 * sizeof(double) + 5 + 2 * RZ, 8)));
#ifdef SDAE_ARENA_ASAN
  for (size_t b = 0; b < 3 * sizeof(double); b++)
    ck_assert(!__asan_address_is_poisoned((char *)x + b));
  for (size_t b = 0; b < RZ; b++) ck_assert(__asan_address_is_poisoned((char *)(x + 3) + b));
  ck_assert(__asan_address_is_poisoned(flags + 5));
  ck_assert(!__asan_address_is_poisoned(y + 1));
  ck_assert(__asan_address_is_poisoned(y + 2));
  sdae__arena_release(block, sizeof block);
  ck_assert(!__asan_address_is_poisoned(x + 3));
#endif
}
END_TEST

/* Workspace lent and reclaimed: the next array starts where it did, zeroed whatever the
 * workspace held and, under AddressSanitizer, readable where the workspace's redzone was; the
 * block is the larger of the workspace's end and the arrays', counted as handed out. */
START_TEST(lent_workspace_is_overlaid) {
  static max_align_t block[32];
  size_t mark, bytes, first = round_up(2 * sizeof(double) + RZ, 8);
  sdae_arena count = {0}, a = {.base = (char *)block};
  for (int pass = 0; pass < 2; pass++) {
    sdae_arena *b = pass ? &a : &count;
    sdae__take(b, 2, 1);
    double *w = sdae__arena_lend(b, 10, sizeof(double), alignof(double), &mark);
    ck_assert_uint_eq(mark, first);
    for (int i = 0; pass && i < 10; i++) w[i] = 1.0;
    sdae__arena_reclaim(b, mark);
    double *x = sdae__take(b, 3, 1);
    ck_assert_int_eq(sdae__arena_bytes(b, 0, &bytes), SDAE_OK);
    ck_assert_uint_eq(bytes, first + 10 * sizeof(double) + RZ); /* the workspace's end */
    if (pass) {
      ck_assert_ptr_eq(x, w);
      for (int i = 0; i < 3; i++) ck_assert(x[i] == 0.0);
#ifdef SDAE_ARENA_ASAN
      ck_assert(!__asan_address_is_poisoned(x + 3 + RZ / sizeof(double)));
#endif
    }
    sdae__take(b, 20, 1); /* past the workspace: the arrays' end */
    ck_assert_int_eq(sdae__arena_bytes(b, 0, &bytes), SDAE_OK);
    ck_assert_uint_eq(bytes, b->used);
  }
  ck_assert_uint_eq(count.used, a.used);
  sdae__arena_release(block, sizeof block);
}
END_TEST

int main(void) {
  Suite *s = suite_create("arena");
  ADD_CASE(s, lent_workspace_is_overlaid);
  ADD_CASE(s, counts_and_aligns);
  ADD_CASE(s, empty_arrays);
  ADD_CASE(s, overflow_each_check);
  ADD_CASE(s, the_gaps_between_arrays_are_poisoned);
  ADD_CASE(s, stepper_too_large_for_size_t);
  return run_suite(s);
}
