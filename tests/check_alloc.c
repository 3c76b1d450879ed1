/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The library's heap use. Zero allocations inside sdae_step (and sdae_stepper_init); and every
 * allocating function, made to fail at its n-th allocation for n = 1, 2, ... until it succeeds,
 * returns SDAE_ERR_NOMEM, leaves the caller's outputs as they were and gives back all it took;
 * the call that succeeds gives what a plain call gives. Twice: through malloc (interposed here,
 * so GSL's hidden allocations would count too) and through a caller's sdae_allocator, with which
 * the library must not call malloc at all. Built without sanitizers, which interpose the
 * allocator themselves. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stabdae/dae.h>

#include "testmodels.h"

#include "core/alloc.h"

/* Valgrind replaces malloc and free, ours too, unless run with
 * --soname-synonyms=somalloc=nouserintercepts (as tools/lib/memcheck.sh does). Then nothing
 * here sees the library's mallocs: under valgrind the cases that need them say so and check
 * only what they still can; anywhere else a malloc that is not ours fails them. */
#if defined(__has_include)
#if __has_include(<valgrind/valgrind.h>)
#include <valgrind/valgrind.h>
#endif
#endif
#ifndef RUNNING_ON_VALGRIND
#define RUNNING_ON_VALGRIND 0
#endif

extern void *__libc_malloc(size_t n);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t n);
extern void __libc_free(void *p);

/* While counting is up: every malloc, calloc and realloc is counted, the fail_at-th of them
 * (1-based; 0: none) fails, and live counts the blocks taken minus the blocks given back. */
static volatile int counting;
static volatile long allocations, live, fail_at, injected;

static int take_failure(void) {
  if (!counting) return 0;
  if (++allocations != fail_at) return 0;
  injected++;
  return 1;
}

static void *taken(void *p) {
  if (p && counting) live++;
  return p;
}

void *malloc(size_t n) { return take_failure() ? NULL : taken(__libc_malloc(n)); }

void *calloc(size_t n, size_t size) {
  return take_failure() ? NULL : taken(__libc_calloc(n, size));
}

void *realloc(void *p, size_t n) {
  if (take_failure()) return NULL;
  return p ? __libc_realloc(p, n) : taken(__libc_realloc(p, n));
}

void free(void *p) {
  if (p && counting) live--;
  __libc_free(p);
}

static void start_counting(long fail) {
  allocations = 0, live = 0, injected = 0, fail_at = fail;
  counting = 1;
}

static void stop_counting(void) { counting = 0, fail_at = 0; }

static int interposed = 1; /* set by main: does the malloc above see the calls? */

static int malloc_is_interposed(void) {
  void *volatile p;
  start_counting(0);
  p = malloc(1);
  stop_counting();
  free(p);
  return allocations == 1;
}

/* the malloc count is out of reach (valgrind's malloc): the case cannot check it */
static int malloc_unseen(const char *what) {
  if (interposed || !RUNNING_ON_VALGRIND) return 0;
  fprintf(stderr,
          "check_alloc: %s not checked: valgrind replaced malloc (run valgrind with "
          "--soname-synonyms=somalloc=nouserintercepts)\n",
          what);
  return 1;
}

static long allocations_in_run(const sdae_map_type *map, sdae_stabilizer stabilizer) {
  static max_align_t mem[256];
  quartic p = {2.0, 0.03, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  double xi[2] = {0.5, 0.1}, mu[2] = {0.7, 0.6};
  o.stabilizer = stabilizer;
  start_counting(0);
  int rc = sdae_stepper_init(&s, mem, sizeof mem, &m, &o);
  for (int n = 0; rc == SDAE_OK && n < 1000; n++) rc = sdae_step(s, n * 1e-2, 1e-2, xi, mu);
  stop_counting();
  ck_assert_int_eq(rc, SDAE_OK);
  return allocations;
}

/* the interposition itself: it counts, it fails the chosen allocation only, it sees frees */
START_TEST(counter_sees_allocations) {
  void *volatile p, *volatile q, *volatile r;
  if (malloc_unseen("the interposed malloc")) return;
  start_counting(2);
  p = malloc(16);
  q = calloc(2, 8);
  r = realloc(NULL, 8);
  stop_counting();
  ck_assert_int_eq(allocations, 3);
  ck_assert_int_eq(injected, 1);
  ck_assert_ptr_nonnull(p);
  ck_assert_ptr_null(q);
  ck_assert_ptr_nonnull(r);
  ck_assert_int_eq(live, 2);
  counting = 1;
  free(p), free(r);
  stop_counting();
  ck_assert_int_eq(live, 0);
}
END_TEST

START_TEST(no_allocation_in_step) {
  const sdae_map_type *maps[9] = {sdae_map_euler,     sdae_map_midpoint, sdae_map_dgrad,
                                  sdae_map_dg4,       sdae_map_dg6,      sdae_map_midpoint4,
                                  sdae_map_midpoint6, sdae_map_rk4,      sdae_map_rk8};
  if (malloc_unseen("no malloc in sdae_step")) return;
  for (int i = 0; i < 9; i++) {
    ck_assert_int_eq(allocations_in_run(maps[i], SDAE_STAB_PAPER), 0);
    ck_assert_int_eq(allocations_in_run(maps[i], SDAE_STAB_BAUMGARTE), 0);
  }
}
END_TEST

/* ---- a caller's allocator that counts, fails its fail_at-th call, and checks the sizes ---- */

#define MAX_BLOCKS 16

typedef struct counting_allocator {
  long calls, live, fail_at, injected;
  int bad_free; /* a free of an unknown block, or with another size than it was asked for */
  void *ptr[MAX_BLOCKS];
  size_t size[MAX_BLOCKS];
} counting_allocator;

static void *ca_alloc(void *ud, size_t size) {
  counting_allocator *a = ud;
  if (++a->calls == a->fail_at) {
    a->injected++;
    return NULL;
  }
  for (int b = 0; b < MAX_BLOCKS; b++)
    if (!a->ptr[b]) {
      if (!(a->ptr[b] = __libc_malloc(size))) return NULL; /* not malloc: the count stays 0 */
      a->size[b] = size;
      a->live++;
      return a->ptr[b];
    }
  return NULL;
}

static void ca_free(void *ud, void *ptr, size_t size) {
  counting_allocator *a = ud;
  for (int b = 0; b < MAX_BLOCKS; b++)
    if (a->ptr[b] == ptr) {
      a->bad_free |= a->size[b] != size;
      a->ptr[b] = NULL;
      a->live--;
      __libc_free(ptr);
      return;
    }
  a->bad_free = 1;
}

static sdae_allocator allocator_of(counting_allocator *a) {
  sdae_allocator h = {ca_alloc, ca_free, a};
  return h;
}

/* ---- the sweep ---- */

/* One allocating call of the library and its outputs. reset() puts the outputs in a known
 * state before every attempt, untouched() says whether they are still in it, attempt() makes
 * the call. With a counting allocator (ca != NULL) its calls are the ones failed, and the
 * interposed malloc must not be called at all. */
typedef struct sweep {
  void (*reset)(struct sweep *);
  int (*untouched)(struct sweep *);
  int (*attempt)(struct sweep *);
  counting_allocator *ca;
  void *ctx;
} sweep;

/* allocations of one attempt whose n-th allocation fails (fail = 0: none) */
static long attempt(sweep *w, long fail, int *rc) {
  long taken_before = w->ca ? w->ca->calls : 0;
  w->reset(w);
  if (w->ca) w->ca->fail_at = taken_before + fail, w->ca->injected = 0;
  start_counting(w->ca ? 0 : fail);
  *rc = w->attempt(w);
  stop_counting();
  if (!w->ca) return allocations;
  ck_assert_int_eq(allocations, 0); /* a caller's allocator: never malloc */
  w->ca->fail_at = 0;
  return w->ca->calls - taken_before;
}

/* Fails the n-th allocation for n = 1, 2, ... until the call succeeds: every failure is
 * SDAE_ERR_NOMEM with the outputs untouched and nothing kept; the call that succeeds makes
 * `made_ok` allocations (the library's one block, after a sparse mechanism's analysis memory)
 * and keeps `kept` blocks for the caller. */
static void run_sweep_making(sweep *w, long kept, long made_ok) {
  long live_before = w->ca ? w->ca->live : 0;
  int rc;
  if (!w->ca && malloc_unseen("failing mallocs")) {
    attempt(w, 0, &rc); /* valgrind still sees the successful call */
    ck_assert_int_eq(rc, SDAE_OK);
    return;
  }
  for (long n = 1; n < 1000; n++) {
    long made = attempt(w, n, &rc);
    long hits = w->ca ? w->ca->injected : injected;
    long now_live = w->ca ? w->ca->live - live_before : live;
    if (w->ca) ck_assert(!w->ca->bad_free);
    if (rc == SDAE_OK) {
      ck_assert_int_eq(hits, 0);
      ck_assert_int_eq(made, n - 1); /* the previous attempt failed its last allocation */
      ck_assert_int_eq(made, made_ok);
      ck_assert_int_eq(now_live, kept);
      return;
    }
    ck_assert_int_eq(hits, 1);
    ck_assert_int_eq(rc, SDAE_ERR_NOMEM);
    ck_assert(w->untouched(w));
    ck_assert_int_eq(now_live, 0);
  }
  ck_abort_msg("no success within 1000 allocations");
}

static void run_sweep(sweep *w, long kept) { run_sweep_making(w, kept, 1); }

/* ---- sdae_stepper_alloc and sdae_stepper_alloc_with ---- */

typedef struct stepper_call {
  sdae_model m;
  sdae_options o;
  sdae_stepper *s;
} stepper_call;

static int sentinel; /* where *s points before each attempt: a failed call must not move it */

static void stepper_reset(sweep *w) { ((stepper_call *)w->ctx)->s = (sdae_stepper *)&sentinel; }

static int stepper_untouched(sweep *w) {
  return ((stepper_call *)w->ctx)->s == (sdae_stepper *)&sentinel;
}

static int stepper_attempt(sweep *w) {
  stepper_call *c = w->ctx;
  if (!w->ca) return sdae_stepper_alloc(&c->s, &c->m, &c->o);
  sdae_allocator h = allocator_of(w->ca);
  return sdae_stepper_alloc_with(&c->s, &c->m, &c->o, &h);
}

/* after the free of what a sweep's successful call made, counted: that block went back to the
 * allocator that made it (nothing through malloc for a custom one) */
static void expect_freed(const counting_allocator *ca) {
  if (ca) {
    ck_assert_int_eq(allocations, 0);
    ck_assert_int_eq(ca->live, 0);
    ck_assert(!ca->bad_free);
  } else if (interposed) {
    ck_assert_int_eq(live, -1); /* the block of the sweep's successful call */
  }
}

/* the stepper the sweep made steps like one from sdae_stepper_alloc, and its free gives the
 * block back through the allocator that made it */
static void stepper_sweep(counting_allocator *ca) {
  quartic p = {2.0, 0.03, 0, 0};
  stepper_call c = {quartic_model(&p),
                    quartic_options(sdae_map_midpoint, SDAE_SCHEME_SEMI_IMPLICIT), NULL};
  sweep w = {stepper_reset, stepper_untouched, stepper_attempt, ca, &c};
  sdae_stepper *plain;
  double xi[2] = {0.5, 0.1}, mu[2] = {0.7, 0.6}, xi2[2] = {0.5, 0.1}, mu2[2] = {0.7, 0.6};
  run_sweep(&w, 1);
  ck_assert_int_eq(sdae_stepper_alloc(&plain, &c.m, &c.o), SDAE_OK);
  for (int n = 0; n < 10; n++) {
    ck_assert_int_eq(sdae_step(c.s, n * 1e-2, 1e-2, xi, mu), SDAE_OK);
    ck_assert_int_eq(sdae_step(plain, n * 1e-2, 1e-2, xi2, mu2), SDAE_OK);
  }
  ck_assert_mem_eq(xi, xi2, sizeof xi);
  ck_assert_mem_eq(mu, mu2, sizeof mu);
  sdae_stepper_free(plain);
  start_counting(0);
  sdae_stepper_free(c.s);
  stop_counting();
  expect_freed(ca);
}

START_TEST(stepper_alloc_sweep) { stepper_sweep(NULL); }
END_TEST

START_TEST(stepper_alloc_with_sweep) {
  counting_allocator ca = {0};
  stepper_sweep(&ca);
}
END_TEST

/* ---- sdae_certify_box, with the stepper's allocator ---- */

/* the paper's box B (xi2 fixed at 0), on a coarse grid */
static const double LO[4] = {-0.7, 0.0, -0.9, -0.9}, HI[4] = {0.7, 0.0, 0.9, 0.9};

typedef struct certificate_out {
  sdae_certificate c;
  double sup[2], argmax[8];
} certificate_out;

typedef struct certify_call {
  sdae_stepper *s;
  certificate_out out;
} certify_call;

/* a failed call leaves these bytes as they were */
static int all_bytes_are(const void *p, size_t n, unsigned char byte) {
  for (size_t i = 0; i < n; i++)
    if (((const unsigned char *)p)[i] != byte) return 0;
  return 1;
}

static void certify_reset(sweep *w) {
  certify_call *c = w->ctx;
  memset(&c->out, 0xA5, sizeof c->out);
}

static int certify_untouched(sweep *w) {
  certify_call *c = w->ctx;
  return all_bytes_are(&c->out, sizeof c->out, 0xA5);
}

static int certify_box(sdae_stepper *s, certificate_out *o) {
  return sdae_certify_box(s, 0.0, LO, HI, 5, o->sup, o->argmax, &o->c);
}

static int certify_attempt(sweep *w) {
  certify_call *c = w->ctx;
  return certify_box(c->s, &c->out);
}

static void same_certificate(const certificate_out *a, const certificate_out *b) {
  ck_assert_double_eq(a->c.sup_neg_k, b->c.sup_neg_k);
  ck_assert_uint_eq(a->c.i_max, b->c.i_max);
  ck_assert_double_eq(a->c.T_bar, b->c.T_bar);
  ck_assert_double_eq(a->c.T_thm5_scheme15, b->c.T_thm5_scheme15);
  ck_assert_double_eq(a->c.T_thm5_scheme11, b->c.T_thm5_scheme11);
  ck_assert_uint_eq(a->c.evaluations, b->c.evaluations);
  ck_assert_mem_eq(a->sup, b->sup, sizeof a->sup);
  ck_assert_mem_eq(a->argmax, b->argmax, sizeof a->argmax);
}

/* ca: the allocator of the stepper, and so of sdae_certify_box; NULL: malloc */
static void certify_sweep(counting_allocator *ca) {
  quartic p = {2.0, 0.03, 0, 1};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_allocator h = allocator_of(ca);
  certify_call c;
  sweep w = {certify_reset, certify_untouched, certify_attempt, ca, &c};
  sdae_stepper *plain;
  certificate_out ref;
  ck_assert_int_eq(sdae_stepper_alloc(&plain, &m, &o), SDAE_OK);
  ck_assert_int_eq(certify_box(plain, &ref), SDAE_OK);
  sdae_stepper_free(plain);
  ck_assert_int_eq(sdae_stepper_alloc_with(&c.s, &m, &o, ca ? &h : NULL), SDAE_OK);
  run_sweep(&w, 0);
  same_certificate(&c.out, &ref);
  sdae_stepper_free(c.s);
  if (ca) {
    ck_assert_int_eq(ca->live, 0);
    ck_assert(!ca->bad_free);
  }
}

START_TEST(certify_box_sweep) { certify_sweep(NULL); }
END_TEST

START_TEST(certify_box_with_allocator_sweep) {
  counting_allocator ca = {0};
  certify_sweep(&ca);
}
END_TEST

/* ---- sdae_check_model and sdae_check_model_with ---- */

/* The oscillator's DAE (paper Section IV, m = 1): x = (X, Y, Xdot, Ydot),
 * f = (Xdot, Ydot, -k X^3 - d Xdot, -ga), g = (0, 0, 0, -1), Phi = (Y, Ydot, X + Y, Y + Xdot);
 * Phi^-1 left to the library's Newton. */
static int dae_f(double t, const double *x, double *out, void *params) {
  const quartic *p = params;
  (void)t;
  out[0] = x[2], out[1] = x[3];
  out[2] = -p->k * x[0] * x[0] * x[0] - p->d * x[2];
  out[3] = -9.81;
  return 0;
}

static int dae_g(double t, const double *x, double *out, void *params) {
  (void)t, (void)x, (void)params;
  out[0] = 0.0, out[1] = 0.0, out[2] = 0.0, out[3] = -1.0;
  return 0;
}

static int dae_Phi(double t, const double *x, double *z, void *params) {
  (void)t, (void)params;
  z[0] = x[1], z[1] = x[3], z[2] = x[0] + x[1], z[3] = x[1] + x[2];
  return 0;
}

typedef struct report_out {
  sdae_check_report r;
  double worst_z[4];
} report_out;

typedef struct check_call {
  sdae_model m;
  sdae_dae d;
  report_out out, pattern;
} check_call;

static void report_init(report_out *o, unsigned char byte) { memset(o, byte, sizeof *o); }

static void check_reset(sweep *w) {
  check_call *c = w->ctx;
  report_init(&c->out, 0xA5);
  report_init(&c->pattern, 0xA5);
}

static int check_untouched(sweep *w) {
  check_call *c = w->ctx;
  return memcmp(&c->out, &c->pattern, sizeof c->out) == 0 ? 1 : 0;
}

static int check_model(check_call *c, const sdae_allocator *a, report_out *o) {
  return sdae_check_model_with(&c->m, &c->d, 0.0, LO, HI, 20, 7, 1e-6, o->worst_z, a, &o->r);
}

static int check_attempt(sweep *w) {
  check_call *c = w->ctx;
  sdae_allocator h = allocator_of(w->ca);
  if (!w->ca)
    return sdae_check_model(&c->m, &c->d, 0.0, LO, HI, 20, 7, 1e-6, c->out.worst_z, &c->out.r);
  return check_model(c, &h, &c->out);
}

static void same_report(const report_out *a, const report_out *b) {
  ck_assert_uint_eq(a->r.points, b->r.points);
  ck_assert_mem_eq(a->r.residual, b->r.residual, sizeof a->r.residual);
  ck_assert_int_eq(a->r.worst_check, b->r.worst_check);
  ck_assert_uint_eq(a->r.worst_index, b->r.worst_index);
  ck_assert_int_eq(a->r.consistent, b->r.consistent);
  ck_assert_mem_eq(a->worst_z, b->worst_z, sizeof a->worst_z);
}

/* the plain call (sdae_check_model_with and NULL) is the reference; the oscillator's normal
 * form is consistent with its DAE (the model suite checks the residuals themselves) */
static void check_sweep(counting_allocator *ca) {
  quartic p = {2.0, 0.03, 0, 0};
  check_call c = {.m = quartic_model(&p), .d = {4, 1, dae_f, dae_g, dae_Phi, NULL, NULL, &p}};
  sweep w = {check_reset, check_untouched, check_attempt, ca, &c};
  report_out ref;
  report_init(&ref, 0);
  ck_assert_int_eq(check_model(&c, NULL, &ref), SDAE_OK);
  ck_assert_uint_eq(ref.r.points, 20);
  ck_assert(ref.r.consistent);
  run_sweep(&w, 0);
  same_report(&c.out, &ref);
}

START_TEST(check_model_sweep) { check_sweep(NULL); }
END_TEST

START_TEST(check_model_with_sweep) {
  counting_allocator ca = {0};
  check_sweep(&ca);
}
END_TEST

/* ---- sdae_dae_model_alloc_with: the generic front-end on the oscillator's DAE above ---- */

typedef struct dae_model_call {
  sdae_dae d;
  sdae_dae_model *dm;
} dae_model_call;

static void dae_model_reset(sweep *w) {
  ((dae_model_call *)w->ctx)->dm = (sdae_dae_model *)&sentinel;
}

static int dae_model_untouched(sweep *w) {
  return ((dae_model_call *)w->ctx)->dm == (sdae_dae_model *)&sentinel;
}

static int dae_model_attempt(sweep *w) {
  dae_model_call *c = w->ctx;
  if (!w->ca) return sdae_dae_model_alloc(&c->dm, &c->d, 2, NULL, NULL);
  sdae_allocator h = allocator_of(w->ca);
  return sdae_dae_model_alloc_with(&c->dm, &c->d, 2, NULL, NULL, &h);
}

/* the model the sweep made gives the q0 of a plain one, and its free gives the block back
 * through the allocator that made it */
static void dae_model_sweep(counting_allocator *ca) {
  quartic p = {2.0, 0.03, 0, 0};
  dae_model_call c = {.d = {4, 1, dae_f, dae_g, dae_Phi, NULL, NULL, &p}};
  sweep w = {dae_model_reset, dae_model_untouched, dae_model_attempt, ca, &c};
  sdae_dae_model *plain;
  double mu[2] = {0.7, 0.6}, a[2], b[2];
  run_sweep(&w, 1);
  ck_assert_int_eq(sdae_dae_model_alloc(&plain, &c.d, 2, NULL, NULL), SDAE_OK);
  const sdae_model *m = sdae_dae_model_get(c.dm), *mp = sdae_dae_model_get(plain);
  ck_assert_int_eq(m->q0(0.0, mu, a, m->params), 0);
  ck_assert_int_eq(mp->q0(0.0, mu, b, mp->params), 0);
  ck_assert_mem_eq(a, b, sizeof a);
  sdae_dae_model_free(plain);
  start_counting(0);
  sdae_dae_model_free(c.dm);
  stop_counting();
  expect_freed(ca);
}

START_TEST(dae_model_alloc_sweep) { dae_model_sweep(NULL); }
END_TEST

START_TEST(dae_model_alloc_with_sweep) {
  counting_allocator ca = {0};
  dae_model_sweep(&ca);
}
END_TEST

/* ---- the hook itself (src/core/alloc.c) ---- */

/* counts its calls and remembers the sizes; blocks from __libc_malloc, so not counted above */
typedef struct tally {
  long allocs, frees;
  size_t asked, freed;
} tally;

static void *tally_alloc(void *ud, size_t size) {
  tally *t = ud;
  t->allocs++, t->asked = size;
  return __libc_malloc(size);
}

static void tally_free(void *ud, void *ptr, size_t size) {
  tally *t = ud;
  t->frees++, t->freed = size;
  __libc_free(ptr);
}

/* alloc.h: size > 0 only, NULL for 0; the caller's pair when it has both functions, malloc
 * and free otherwise (a pair with a half missing is no pair); free gets the size asked for and
 * never NULL; n x size that overflows size_t is NULL without asking anyone. */
START_TEST(hook_guards) {
  tally t = {0};
  sdae_allocator both = {tally_alloc, tally_free, &t}, no_free = {tally_alloc, NULL, &t},
                 no_alloc = {NULL, tally_free, &t};
  const sdae_allocator *halves[3] = {NULL, &no_free, &no_alloc};
  int seen = !malloc_unseen("malloc behind the hook");
  void *p;
  /* the caller's pair */
  ck_assert_ptr_null(sdae__alloc(&both, 0));
  ck_assert_int_eq(t.allocs, 0);
  p = sdae__alloc(&both, 24);
  ck_assert_ptr_nonnull(p);
  ck_assert_int_eq(t.allocs, 1);
  ck_assert_uint_eq(t.asked, 24);
  sdae__free(&both, p, 24);
  ck_assert_int_eq(t.frees, 1);
  ck_assert_uint_eq(t.freed, 24); /* the size it was asked for */
  sdae__free(&both, NULL, 24);    /* NULL is fine, and never reaches the caller's free */
  ck_assert_int_eq(t.frees, 1);
  p = sdae__alloc_array(&both, 5, 3);
  ck_assert_uint_eq(t.asked, 15); /* 5 x 3 bytes */
  sdae__free(&both, p, 15);
  /* n x size past SIZE_MAX: (SIZE_MAX / 8 + 2) x 8 would wrap to 8 bytes */
  ck_assert_ptr_null(sdae__alloc_array(&both, SIZE_MAX / 8 + 2, 8));
  ck_assert_ptr_null(sdae__alloc_array(&both, 2, SIZE_MAX / 2 + 1));
  ck_assert_ptr_null(sdae__alloc_array(&both, 5, 0)); /* 0 bytes */
  ck_assert_ptr_null(sdae__alloc_array(&both, 0, 5));
  ck_assert_int_eq(t.allocs, 2);
  /* malloc: no allocator, or half of one */
  for (int h = 0; h < 3; h++) {
    void *zero, *wrapped, *empty;
    long before, after, live_mid;
    t = (tally){0};
    /* no assertion while counting: Check's own may allocate */
    start_counting(0);
    zero = sdae__alloc(halves[h], 0);
    wrapped = sdae__alloc_array(halves[h], SIZE_MAX / 8 + 2, 8);
    empty = sdae__alloc_array(halves[h], 5, 0);
    before = allocations;
    p = sdae__alloc(halves[h], 1);
    after = allocations, live_mid = live;
    sdae__free(halves[h], p, 1);
    sdae__free(halves[h], NULL, 1);
    stop_counting();
    ck_assert_ptr_null(zero);
    ck_assert_ptr_null(wrapped);
    ck_assert_ptr_null(empty);
    ck_assert_ptr_nonnull(p);
    if (seen) {
      ck_assert_int_eq(before, 0); /* nothing asked of malloc for those */
      ck_assert_int_eq(after, 1);  /* one byte from malloc */
      ck_assert_int_eq(live_mid, 1);
      ck_assert_int_eq(live, 0); /* given back to free */
    }
    ck_assert_int_eq(t.allocs, 0);
    ck_assert_int_eq(t.frees, 0);
  }
}
END_TEST

/* ---- the mechanical stepper (<stabdae/mbs.h>) ---- */

#include "mechanisms.h"

typedef struct mbs_call {
  sdae_mbs sys;
  sdae_options o;
  sdae_mbs_stepper *s;
} mbs_call;

static void mbs_reset(sweep *w) { ((mbs_call *)w->ctx)->s = (sdae_mbs_stepper *)&sentinel; }

static int mbs_untouched(sweep *w) {
  return ((mbs_call *)w->ctx)->s == (sdae_mbs_stepper *)&sentinel;
}

static int mbs_attempt(sweep *w) {
  mbs_call *c = w->ctx;
  sdae_allocator h = allocator_of(w->ca);
  return sdae_mbs_stepper_alloc_with(&c->s, &c->sys, &c->o, w->ca ? &h : NULL);
}

/* 50 dgrad steps of the double pendulum from both arms raised (through its chart choice); no
 * assertion here: Check's own may allocate while the count is up */
static int mbs_run(sdae_mbs_stepper *s, double *q, double *v) {
  int rc = SDAE_OK;
  for (int n = 0; n < 50 && rc == SDAE_OK; n++) rc = sdae_mbs_step(s, n * 1e-2, 1e-2, q, v);
  return rc;
}

/* The sweep through malloc and through a caller's allocator; a stepper built in a caller's block
 * of sdae_mbs_stepper_size bytes steps bitwise like the allocated one; and the steps take no
 * allocation, neither from malloc nor from the stepper's allocator. */
START_TEST(mbs_stepper_alloc_sweep) {
  mech_double_pendulum p = {.L1 = 1.0, .L2 = 1.0, .m1 = 1.0, .m2 = 1.0, .ga = 9.81};
  const double theta[2] = {2.2, 2.7}, omega[2] = {0.0, 0.0};
  static max_align_t mem[4096];
  counting_allocator ca = {0};
  sdae_mbs_stepper *in_block;
  double q[4], v[4], q2[4], v2[4];
  mbs_call c = {.o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT), .s = NULL};
  mech_double_pendulum_system(&c.sys, &p);
  sweep w = {mbs_reset, mbs_untouched, mbs_attempt, NULL, &c};
  size_t len = sdae_mbs_stepper_size(&c.sys, &c.o);
  run_sweep(&w, 1);
  sdae_mbs_stepper_free(c.s);
  w.ca = &ca;
  run_sweep(&w, 1);
  ck_assert_uint_gt(len, 0);
  ck_assert_uint_le(len, sizeof mem);
  ck_assert_int_eq(sdae_mbs_stepper_init(&in_block, mem, len, &c.sys, &c.o), SDAE_OK);
  mech_double_pendulum_state(&p, theta, omega, q, v);
  mech_double_pendulum_state(&p, theta, omega, q2, v2);
  long calls_before = ca.calls;
  start_counting(0);
  int rc1 = mbs_run(c.s, q, v), rc2 = mbs_run(in_block, q2, v2);
  stop_counting();
  ck_assert_int_eq(rc1, SDAE_OK);
  ck_assert_int_eq(rc2, SDAE_OK);
  if (!malloc_unseen("no malloc in sdae_mbs_step")) ck_assert_int_eq(allocations, 0);
  ck_assert_int_eq(ca.calls, calls_before);
  ck_assert_mem_eq(q, q2, sizeof q);
  ck_assert_mem_eq(v, v2, sizeof v);
  sdae_mbs_stepper_free(in_block);
  sdae_mbs_stepper_free(c.s);
  ck_assert_int_eq(ca.live, 0);
  ck_assert(!ca.bad_free);
}
END_TEST

/* a sparse mechanism in its own coordinates (a rope of 64 masses, rk4, through chart switches
 * of its swing): its steps take no allocation either, its block from the caller's allocator */
#include "rope.h"
START_TEST(mbs_sparse_steps_take_no_allocation) {
  mech_rope r = mech_rope_unit(64, 0, 1);
  counting_allocator ca = {0};
  sdae_allocator h = allocator_of(&ca);
  sdae_options o = quartic_options(sdae_map_rk4, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  double q[128], v[128];
  int rc = SDAE_OK;
  ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
  ck_assert_int_eq(sdae_mbs_stepper_alloc_with(&s, &sys, &o, &h), SDAE_OK);
  ck_assert_int_eq(mech_rope_start(&r, 0.3, q, v), 0);
  long calls_before = ca.calls;
  start_counting(0);
  for (int k = 0; k < 200 && rc == SDAE_OK; k++) rc = sdae_mbs_step(s, k * 1e-2, 1e-2, q, v);
  stop_counting();
  ck_assert_int_eq(rc, SDAE_OK);
  if (!malloc_unseen("no malloc in a sparse sdae_mbs_step")) ck_assert_int_eq(allocations, 0);
  ck_assert_int_eq(ca.calls, calls_before);
  sdae_mbs_stepper_free(s);
  ck_assert_int_eq(ca.live, 0);
  mech_rope_free(&r);
}
END_TEST

/* A sparse mechanism (a rope of 64 masses, dgrad) is analysed in memory of its own before its
 * block is taken: the sweep through malloc and through a caller's allocator, two allocations
 * when it succeeds, the first given back; in a caller's block of sdae_mbs_stepper_size bytes
 * the analysis runs in that block, and init calls malloc not at all */
START_TEST(mbs_sparse_analysis_memory_sweep) {
  mech_rope r = mech_rope_unit(64, 0, 1);
  counting_allocator ca = {0};
  mbs_call c = {.o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT), .s = NULL};
  sdae_mbs_stepper *in_block;
  ck_assert_int_eq(mech_rope_system(&c.sys, &r), 0);
  sweep w = {mbs_reset, mbs_untouched, mbs_attempt, NULL, &c};
  size_t len = sdae_mbs_stepper_size(&c.sys, &c.o);
  void *mem = malloc(len);
  run_sweep_making(&w, 1, 2);
  sdae_mbs_stepper_free(c.s);
  w.ca = &ca;
  run_sweep_making(&w, 1, 2);
  sdae_mbs_stepper_free(c.s);
  ck_assert_int_eq(ca.live, 0);
  ck_assert(!ca.bad_free);
  start_counting(0);
  int rc = sdae_mbs_stepper_init(&in_block, mem, len, &c.sys, &c.o);
  stop_counting();
  ck_assert_int_eq(rc, SDAE_OK);
  if (!malloc_unseen("no malloc in sdae_mbs_stepper_init")) ck_assert_int_eq(allocations, 0);
  sdae_mbs_stepper_free(in_block);
  free(mem);
  mech_rope_free(&r);
}
END_TEST

int main(void) {
  Suite *s = suite_create("alloc");
  interposed = malloc_is_interposed();
  ADD_CASE(s, counter_sees_allocations);
  ADD_CASE(s, no_allocation_in_step);
  ADD_CASE(s, stepper_alloc_sweep);
  ADD_CASE(s, stepper_alloc_with_sweep);
  ADD_CASE(s, certify_box_sweep);
  ADD_CASE(s, certify_box_with_allocator_sweep);
  ADD_CASE(s, check_model_sweep);
  ADD_CASE(s, check_model_with_sweep);
  ADD_CASE(s, hook_guards);
  ADD_CASE(s, mbs_stepper_alloc_sweep);
  ADD_CASE(s, mbs_sparse_steps_take_no_allocation);
  ADD_CASE(s, mbs_sparse_analysis_memory_sweep);
  ADD_CASE(s, dae_model_alloc_sweep);
  ADD_CASE(s, dae_model_alloc_with_sweep);
  return run_suite(s);
}
