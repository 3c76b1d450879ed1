/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A mechanical stepper's state as bytes (sdae_mbs_get_state, sdae_mbs_set_state): a state set
 * into a fresh stepper, in this process or in another one (this program run again by
 * posix_spawn, another address space), continues bit for bit; every damaged byte, a cut or
 * lengthened state, and a state of another mechanism, map, options or build are refused by
 * their status, and a refused state changes nothing. */
#define _POSIX_C_SOURCE 200809L
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/bytes.h"
#include "mechanisms.h"
#include "testmodels.h"

extern char **environ;

/* this program, run again as the other process (argv[0]: under valgrind /proc/self/exe would
 * be valgrind's) */
static const char *self;

static const mech_fourbar FOURBAR = {
    .a = 1.0, .b = 4.0, .e = 3.0, .d = 4.5, .mB = 1.0, .mC = 1.0, .ga = 9.81};
static const double T = 0.01;

static const char *const MAPS[] = {"euler", "midpoint", "dgrad", "dg4", "midpoint4", "rk4", "rk8"};
#define N_MAPS (sizeof MAPS / sizeof *MAPS)

typedef struct run {
  mech_fourbar p;
  sdae_mbs sys;
  sdae_options o;
  sdae_mbs_stepper *s;
  double q[4], v[4];
  size_t k; /* steps taken */
} run;

/* without Check's asserts, which only a test case may call: the other process calls it too */
static int run_init(run *r, const char *map) {
  r->p = FOURBAR;
  mech_fourbar_system(&r->sys, &r->p);
  sdae_options_default(&r->o);
  r->o.map = sdae_map_by_name(map);
  r->k = 0;
  if (!r->o.map || sdae_mbs_stepper_alloc(&r->s, &r->sys, &r->o) != SDAE_OK) return -1;
  return mech_fourbar_state(&r->p, 0.3, 5.0, r->q, r->v);
}

static void run_start(run *r, const char *map) { ck_assert_int_eq(run_init(r, map), 0); }

static void run_steps(run *r, size_t n) {
  for (size_t i = 0; i < n; i++, r->k++)
    ck_assert_int_eq(sdae_mbs_step(r->s, (double)r->k * T, T, r->q, r->v), SDAE_OK);
}

/* the state's bytes, malloc'ed */
static unsigned char *state_of(const run *r, size_t *len) {
  unsigned char *buf;
  *len = sdae_mbs_state_size(r->s);
  ck_assert_uint_gt(*len, 0);
  buf = malloc(*len);
  ck_assert_ptr_nonnull(buf);
  ck_assert_int_eq(sdae_mbs_get_state(r->s, buf, *len), SDAE_OK);
  return buf;
}

/* the two runs at the same point: the state bit for bit, and every counter */
static void expect_same(const run *a, const run *b) {
  const sdae_mbs_stats *x = sdae_mbs_stepper_stats(a->s), *y = sdae_mbs_stepper_stats(b->s);
  ck_assert_mem_eq(a->q, b->q, sizeof a->q);
  ck_assert_mem_eq(a->v, b->v, sizeof a->v);
  ck_assert_uint_eq(x->step.steps, y->step.steps);
  ck_assert_uint_eq(x->step.newton_iters_total, y->step.newton_iters_total);
  ck_assert_uint_eq(x->step.phi_evals, y->step.phi_evals);
  ck_assert_uint_eq(x->chart_switches, y->chart_switches);
  ck_assert_uint_eq(x->phi_inv_iters, y->phi_inv_iters);
}

/* a fresh stepper of the same mechanism and options, set to a's state and a's (q, v) */
static void run_from(run *b, const run *a, const unsigned char *state, size_t len,
                     const char *map) {
  run_start(b, map);
  ck_assert_int_eq(sdae_mbs_set_state(b->s, state, len), SDAE_OK);
  memcpy(b->q, a->q, sizeof b->q), memcpy(b->v, a->v, sizeof b->v);
  b->k = a->k;
}

/* 60 steps (the dg and midpoint maps keep Newton's matrix, the four-bar's chart switches in the
 * first 40), the state taken, 40 more; a fresh stepper set to it takes the same 40 */
START_TEST(fresh_stepper_continues_bit_for_bit) {
  for (size_t m = 0; m < N_MAPS; m++) {
    run a, b;
    size_t len;
    unsigned char *state;
    run_start(&a, MAPS[m]);
    run_steps(&a, 60);
    state = state_of(&a, &len);
    run_from(&b, &a, state, len, MAPS[m]);
    run_steps(&a, 40);
    run_steps(&b, 40);
    expect_same(&a, &b);
    free(state);
    sdae_mbs_stepper_free(a.s);
    sdae_mbs_stepper_free(b.s);
  }
}
END_TEST

/* Without the state a fresh stepper from the same (t, q, v) builds its own Newton matrix and
 * takes the step's start anew: the discrete gradient's motion then differs at rounding. So
 * the test above sees the state's contents, not only (q, v). */
START_TEST(without_the_state_the_motion_differs) {
  run a, b;
  run_start(&a, "dgrad");
  run_steps(&a, 60);
  run_start(&b, "dgrad");
  memcpy(b.q, a.q, sizeof b.q), memcpy(b.v, a.v, sizeof b.v);
  b.k = a.k;
  run_steps(&a, 40);
  run_steps(&b, 40);
  ck_assert(memcmp(a.q, b.q, sizeof a.q) != 0 || memcmp(a.v, b.v, sizeof a.v) != 0);
  sdae_mbs_stepper_free(a.s);
  sdae_mbs_stepper_free(b.s);
}
END_TEST

/* ---- another process ---- */

static int write_bytes(const char *path, const void *p, size_t n) {
  FILE *f = fopen(path, "wb");
  int ok = f && fwrite(p, 1, n, f) == n;
  return f && fclose(f) == 0 && ok;
}

static void write_file(const char *path, const void *p, size_t n) {
  ck_assert(write_bytes(path, p, n));
}

static size_t read_file(const char *path, void *p, size_t cap) {
  FILE *f = fopen(path, "rb");
  size_t n;
  if (!f) return 0;
  n = fread(p, 1, cap, f);
  fclose(f);
  return n;
}

/* the other process: argv = (self, "continue", map, state file, out file); reads (q, v, k)
 * and the state, takes 40 steps, writes (q, v) */
static int continue_elsewhere(char **argv) {
  static unsigned char buf[1 << 16];
  run b;
  size_t n = read_file(argv[3], buf, sizeof buf), head = sizeof b.q + sizeof b.v + sizeof b.k;
  if (run_init(&b, argv[2]) != 0 || n < head) return 3;
  memcpy(b.q, buf, sizeof b.q);
  memcpy(b.v, buf + sizeof b.q, sizeof b.v);
  memcpy(&b.k, buf + sizeof b.q + sizeof b.v, sizeof b.k);
  if (sdae_mbs_set_state(b.s, buf + head, n - head) != SDAE_OK) return 4;
  for (size_t i = 0; i < 40; i++, b.k++)
    if (sdae_mbs_step(b.s, (double)b.k * T, T, b.q, b.v) != SDAE_OK) return 5;
  memcpy(buf, b.q, sizeof b.q);
  memcpy(buf + sizeof b.q, b.v, sizeof b.v);
  sdae_mbs_stepper_free(b.s);
  return write_bytes(argv[4], buf, sizeof b.q + sizeof b.v) ? 0 : 6;
}

START_TEST(another_process_continues_bit_for_bit) {
  char in[] = "/tmp/sdae_state_in_XXXXXX", out[] = "/tmp/sdae_state_out_XXXXXX";
  int fd_in = mkstemp(in), fd_out = mkstemp(out);
  ck_assert(fd_in >= 0 && fd_out >= 0);
  close(fd_in), close(fd_out);
  for (size_t m = 0; m < N_MAPS; m++) {
    static unsigned char buf[1 << 16];
    run a;
    size_t len, head = sizeof a.q + sizeof a.v + sizeof a.k;
    unsigned char *state;
    /* under a cross build's emulator (STABDAE_EMULATOR, one program name) when there is one */
    const char *emulator = getenv("STABDAE_EMULATOR");
    char *with[] = {(char *)emulator, (char *)self, "continue", (char *)MAPS[m], in, out, NULL};
    char **args = emulator && *emulator ? with : with + 1;
    pid_t pid;
    int status;
    double qv[8];
    run_start(&a, MAPS[m]);
    run_steps(&a, 60);
    state = state_of(&a, &len);
    ck_assert_uint_le(head + len, sizeof buf);
    memcpy(buf, a.q, sizeof a.q), memcpy(buf + sizeof a.q, a.v, sizeof a.v);
    memcpy(buf + sizeof a.q + sizeof a.v, &a.k, sizeof a.k);
    memcpy(buf + head, state, len);
    write_file(in, buf, head + len);
    ck_assert_int_eq(posix_spawnp(&pid, args[0], NULL, NULL, args, environ), 0);
    ck_assert_int_eq(waitpid(pid, &status, 0), pid);
    ck_assert_msg(WIFEXITED(status) && WEXITSTATUS(status) == 0, "%s: the other process: %d",
                  MAPS[m], status);
    run_steps(&a, 40);
    ck_assert_uint_eq(read_file(out, qv, sizeof qv), sizeof qv);
    ck_assert_mem_eq(qv, a.q, sizeof a.q);
    ck_assert_mem_eq(qv + 4, a.v, sizeof a.v);
    free(state);
    sdae_mbs_stepper_free(a.s);
  }
  unlink(in), unlink(out);
}
END_TEST

/* ---- refusals ---- */

/* a (the stepper refused at) and its twin (never offered anything) take 30 more steps alike */
static void expect_untouched(run *a, run *twin) {
  run_steps(a, 30);
  run_steps(twin, 30);
  expect_same(a, twin);
}

/* every byte changed in turn (one xor), the state cut short by one and lengthened by one:
 * SDAE_ERR_STATE_DAMAGED each time, and the stepper as it was */
START_TEST(every_damaged_byte_is_refused) {
  run a, twin, donor;
  size_t len;
  unsigned char *state, *bad;
  run_start(&a, "dgrad"), run_start(&twin, "dgrad"), run_start(&donor, "dgrad");
  run_steps(&a, 50), run_steps(&twin, 50), run_steps(&donor, 70);
  state = state_of(&donor, &len);
  bad = malloc(len + 1);
  ck_assert_ptr_nonnull(bad);
  for (size_t i = 0; i < len; i++) {
    memcpy(bad, state, len);
    bad[i] ^= 0x5a;
    ck_assert_msg(sdae_mbs_set_state(a.s, bad, len) == SDAE_ERR_STATE_DAMAGED, "byte %zu", i);
  }
  memcpy(bad, state, len), bad[len] = 0;
  ck_assert_int_eq(sdae_mbs_set_state(a.s, bad, len - 1), SDAE_ERR_STATE_DAMAGED);
  ck_assert_int_eq(sdae_mbs_set_state(a.s, bad, len + 1), SDAE_ERR_STATE_DAMAGED);
  ck_assert_int_eq(sdae_mbs_set_state(a.s, bad, 3), SDAE_ERR_STATE_DAMAGED);
  expect_untouched(&a, &twin);
  ck_assert_str_ne(sdae_strerror(SDAE_ERR_STATE_DAMAGED), "unknown status");
  free(bad), free(state);
  sdae_mbs_stepper_free(a.s), sdae_mbs_stepper_free(twin.s), sdae_mbs_stepper_free(donor.s);
}
END_TEST

/* states of another mechanism (the pendulum), another map, other options: FOREIGN */
START_TEST(a_foreign_state_is_refused) {
  run a, twin, other;
  mech_pendulum pend = {.L = 1.0, .m = 1.0, .ga = 9.81};
  sdae_mbs psys;
  sdae_mbs_stepper *ps;
  double pq[2], pv[2];
  size_t len;
  unsigned char *state;
  run_start(&a, "dgrad"), run_start(&twin, "dgrad");
  run_steps(&a, 20), run_steps(&twin, 20);
  /* another mechanism */
  mech_pendulum_system(&psys, &pend);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&ps, &psys, &a.o), SDAE_OK);
  mech_pendulum_state(&pend, 0.3, 0.0, pq, pv);
  ck_assert_int_eq(sdae_mbs_step(ps, 0.0, T, pq, pv), SDAE_OK);
  len = sdae_mbs_state_size(ps);
  state = malloc(len);
  ck_assert_int_eq(sdae_mbs_get_state(ps, state, len), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_set_state(a.s, state, len), SDAE_ERR_STATE_FOREIGN);
  free(state);
  sdae_mbs_stepper_free(ps);
  /* another map, then other options: the same sizes where the map keeps the same parts */
  run_start(&other, "midpoint");
  run_steps(&other, 20);
  state = state_of(&other, &len);
  ck_assert_uint_eq(len, sdae_mbs_state_size(a.s));
  ck_assert_int_eq(sdae_mbs_set_state(a.s, state, len), SDAE_ERR_STATE_FOREIGN);
  free(state);
  sdae_mbs_stepper_free(other.s);
  run_start(&other, "dgrad");
  sdae_mbs_stepper_free(other.s);
  other.o.delta = 3.0;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&other.s, &other.sys, &other.o), SDAE_OK);
  run_steps(&other, 20);
  state = state_of(&other, &len);
  ck_assert_int_eq(sdae_mbs_set_state(a.s, state, len), SDAE_ERR_STATE_FOREIGN);
  free(state);
  sdae_mbs_stepper_free(other.s);
  expect_untouched(&a, &twin);
  sdae_mbs_stepper_free(a.s), sdae_mbs_stepper_free(twin.s);
}
END_TEST

/* the header: magic (8 bytes), format (4), build (8), identity (8), length (8); a field
 * changed and the checksum made anew is no longer damaged but another build or format */
/* where the coordinates' fields start: after the header and the statistics' four counters */
#define CHART_AT (36 + 4 * sizeof(unsigned long))

static void reseal(unsigned char *state, size_t len) {
  uint64_t sum = sdae__fnv(SDAE_FNV_START, state, len - sizeof sum);
  memcpy(state + len - sizeof sum, &sum, sizeof sum);
}

static void rewrite(unsigned char *state, size_t len, size_t at) {
  state[at] ^= 1;
  reseal(state, len);
}

START_TEST(another_build_or_format_is_foreign) {
  const size_t fields[] = {0, 8, 12, 20}; /* magic, format, build, identity */
  run a, twin;
  size_t len;
  unsigned char *state, *bad;
  run_start(&a, "rk4"), run_start(&twin, "rk4");
  run_steps(&a, 20), run_steps(&twin, 20);
  state = state_of(&a, &len);
  bad = malloc(len);
  for (size_t f = 0; f < sizeof fields / sizeof *fields; f++) {
    memcpy(bad, state, len);
    rewrite(bad, len, fields[f]);
    ck_assert_int_eq(sdae_mbs_set_state(a.s, bad, len), SDAE_ERR_STATE_FOREIGN);
  }
  /* the first dependent coordinate made out of range (the chart follows the header and the three
   * counters), the checksum made anew: whole, yet no split of q */
  memcpy(bad, state, len);
  memset(bad + CHART_AT + sizeof(int), 0xff, sizeof(size_t));
  rewrite(bad, len, CHART_AT + sizeof(int) + 1);
  ck_assert_int_eq(sdae_mbs_set_state(a.s, bad, len), SDAE_ERR_STATE_DAMAGED);
  ck_assert_str_ne(sdae_strerror(SDAE_ERR_STATE_FOREIGN), "unknown status");
  expect_untouched(&a, &twin);
  free(bad), free(state);
  sdae_mbs_stepper_free(a.s), sdae_mbs_stepper_free(twin.s);
}
END_TEST

/* dgrad's kept Newton matrix (2 x 2 on the four-bar's mu) ends the state with its two pivots,
 * before the checksum: one made to index far outside, the checksum made anew, is refused and
 * nothing is changed (a solve with it would write outside the factors) */
START_TEST(a_pivot_out_of_range_is_refused) {
  run a, twin;
  size_t len;
  unsigned pivot = 1000;
  unsigned char *state;
  run_start(&a, "dgrad"), run_start(&twin, "dgrad");
  run_steps(&a, 20), run_steps(&twin, 20);
  state = state_of(&a, &len);
  memcpy(state + len - sizeof(uint64_t) - 2 * sizeof pivot, &pivot, sizeof pivot);
  reseal(state, len);
  ck_assert_int_eq(sdae_mbs_set_state(a.s, state, len), SDAE_ERR_STATE_DAMAGED);
  expect_untouched(&a, &twin);
  free(state);
  sdae_mbs_stepper_free(a.s), sdae_mbs_stepper_free(twin.s);
}
END_TEST

START_TEST(bad_arguments) {
  run a;
  unsigned char buf[8];
  size_t len;
  run_start(&a, "euler");
  len = sdae_mbs_state_size(a.s);
  ck_assert_uint_eq(sdae_mbs_state_size(NULL), 0);
  ck_assert_int_eq(sdae_mbs_get_state(NULL, buf, sizeof buf), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_get_state(a.s, NULL, len), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_get_state(a.s, buf, sizeof buf), SDAE_ERR_BUFFER);
  ck_assert_int_eq(sdae_mbs_set_state(NULL, buf, sizeof buf), SDAE_ERR_NULL);
  ck_assert_int_eq(sdae_mbs_set_state(a.s, NULL, len), SDAE_ERR_NULL);
  sdae_mbs_stepper_free(a.s);
}
END_TEST

int main(int argc, char **argv) {
  Suite *s;
  self = argv[0];
  if (argc == 5 && strcmp(argv[1], "continue") == 0) return continue_elsewhere(argv);
  s = suite_create("mbs_state");
  ADD_CASE(s, fresh_stepper_continues_bit_for_bit);
  ADD_CASE(s, without_the_state_the_motion_differs);
  ADD_CASE(s, another_process_continues_bit_for_bit);
  ADD_CASE(s, every_damaged_byte_is_refused);
  ADD_CASE(s, a_foreign_state_is_refused);
  ADD_CASE(s, another_build_or_format_is_foreign);
  ADD_CASE(s, a_pivot_out_of_range_is_refused);
  ADD_CASE(s, bad_arguments);
  return run_suite(s);
}
