/* Zero heap allocations inside sdae_step (and inside sdae_stepper_init): malloc, calloc and
 * realloc are interposed and counted while the flag is up. Built without sanitizers, which
 * interpose the allocator themselves. */
#include <stddef.h>
#include <stdlib.h>

#include "testmodels.h"

extern void *__libc_malloc(size_t n);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t n);

static volatile int counting, fail_next;
static volatile long allocations;

/* fail_next: the next malloc or calloc fails, once */
static int take_failure(void) {
  int fail = fail_next;
  fail_next = 0;
  return fail;
}

void *malloc(size_t n) {
  if (counting) allocations++;
  return take_failure() ? NULL : __libc_malloc(n);
}

void *calloc(size_t n, size_t size) {
  if (counting) allocations++;
  return take_failure() ? NULL : __libc_calloc(n, size);
}

void *realloc(void *p, size_t n) {
  if (counting) allocations++;
  return __libc_realloc(p, n);
}

static long allocations_in_run(const sdae_map_type *map, sdae_stabilizer stabilizer) {
  static max_align_t mem[256];
  quartic p = {2.0, 0.03, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.5, 0.1}, mu[2] = {0.7, 0.6};
  o.stabilizer = stabilizer;
  allocations = 0;
  counting = 1;
  int rc = sdae_stepper_init(&s, mem, sizeof mem, &m, &o);
  for (int n = 0; rc == SDAE_OK && n < 1000; n++) rc = sdae_step(s, n * 1e-2, 1e-2, xi, mu);
  counting = 0;
  ck_assert_int_eq(rc, SDAE_OK);
  return allocations;
}

START_TEST(counter_sees_allocations) {
  counting = 1;
  allocations = 0;
  void *volatile p = malloc(16);
  counting = 0;
  free(p);
  ck_assert_int_eq(allocations, 1);
}
END_TEST

START_TEST(no_allocation_in_step) {
  const sdae_map_type *maps[5] = {sdae_map_euler, sdae_map_midpoint, sdae_map_dgrad,
                                  sdae_map_dg4, sdae_map_dg6};
  for (int i = 0; i < 5; i++) {
    ck_assert_int_eq(allocations_in_run(maps[i], SDAE_STAB_PAPER), 0);
    ck_assert_int_eq(allocations_in_run(maps[i], SDAE_STAB_BAUMGARTE), 0);
  }
}
END_TEST

/* The first allocation of sdae_stepper_alloc, sdae_certify_box and sdae_check_model fails:
 * SDAE_ERR_NOMEM, nothing returned, nothing leaked (the memcheck run sees to that). */
static int never_called(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)out, (void)params;
  return -1;
}

START_TEST(out_of_memory_is_reported) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_dae dae = {4, 1, never_called, never_called, never_called, NULL, NULL, &p};
  sdae_stepper *s = NULL;
  sdae_certificate cert;
  sdae_check_report report;
  const double lo[4] = {-1, -1, -1, -1}, hi[4] = {1, 1, 1, 1};
  fail_next = 1;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_ERR_NOMEM);
  ck_assert_int_eq(fail_next, 0); /* the failure was the library's malloc */
  ck_assert_ptr_null(s);
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  fail_next = 1;
  ck_assert_int_eq(sdae_certify_box(s, 0.0, lo, hi, 3, NULL, NULL, &cert), SDAE_ERR_NOMEM);
  fail_next = 1;
  ck_assert_int_eq(sdae_check_model(&m, &dae, 0.0, lo, hi, 5, 1, 1e-9, &report), SDAE_ERR_NOMEM);
  ck_assert_int_eq(fail_next, 0);
  sdae_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("alloc");
  ADD_CASE(s, counter_sees_allocations);
  ADD_CASE(s, no_allocation_in_step);
  ADD_CASE(s, out_of_memory_is_reported);
  return run_suite(s);
}
