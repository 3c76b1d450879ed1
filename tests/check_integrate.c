/* SPDX-License-Identifier: GPL-3.0-or-later */
/* sdae_integrate: which steps the observer sees, a clean stop, a failure mid-run that keeps
 * the state of the last good step, caller memory against malloc'ed memory, and threads. */
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "testmodels.h"

typedef struct seen {
  size_t n, steps[16];
  double t[16];
  size_t stop_at; /* 0: never stop */
} seen;

static int observer(size_t step, double t, const double *xi, const double *mu, void *data) {
  seen *s = data;
  (void)xi, (void)mu;
  if (s->n < 16) s->steps[s->n] = step, s->t[s->n] = t, s->n++;
  return s->stop_at && step >= s->stop_at;
}

START_TEST(observer_sees_first_every_and_last) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  seen obs = {0};
  double xi[2] = {0.1, 0}, mu[2] = {1, 0};
  size_t done;
  const size_t want[5] = {0, 3, 6, 9, 10};
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 2.0, 0.1, 10, 3, xi, mu, observer, &obs, &done), SDAE_OK);
  ck_assert_uint_eq(done, 10);
  ck_assert_uint_eq(obs.n, 5);
  for (int i = 0; i < 5; i++) {
    ck_assert_uint_eq(obs.steps[i], want[i]);
    ck_assert_double_eq(obs.t[i], 2.0 + (double)want[i] * 0.1);
  }
  ck_assert_int_eq(sdae_integrate(s, 0.0, 0.1, 10, 0, xi, mu, NULL, NULL, NULL), SDAE_ERR_PARAM);
  ck_assert_int_eq(sdae_integrate(s, 0.0, -0.1, 10, 1, xi, mu, NULL, NULL, NULL), SDAE_ERR_STEP);
  sdae_stepper_free(s);
}
END_TEST

START_TEST(observer_stops_cleanly) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  seen obs = {0};
  double xi[2] = {0.1, 0}, mu[2] = {1, 0};
  size_t done;
  obs.stop_at = 4;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, 0.1, 10, 1, xi, mu, observer, &obs, &done), SDAE_STOPPED);
  ck_assert_uint_eq(done, 4);
  ck_assert_uint_eq(sdae_stepper_stats(s)->steps, 4);
  sdae_stepper_free(s);
}
END_TEST

/* q0 fails from t = 0.5 on: the run stops after step 5 with the state of step 5. */
static int q0_until(double t, const double *mu, double *out, void *params) {
  (void)params;
  out[0] = mu[1], out[1] = -mu[0] * mu[0] * mu[0];
  return t >= 0.5 - 1e-12 ? -1 : 0;
}

START_TEST(failure_keeps_last_good_state) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p), good = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s, *g;
  double xi[2] = {0.1, 0}, mu[2] = {1, 0}, gxi[2] = {0.1, 0}, gmu[2] = {1, 0};
  size_t done;
  m.q0 = q0_until;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  ck_assert_int_eq(sdae_stepper_alloc(&g, &good, &o), SDAE_OK);
  ck_assert_int_eq(sdae_integrate(s, 0.0, 0.1, 10, 1, xi, mu, NULL, NULL, &done),
                   SDAE_ERR_CALLBACK_FATAL);
  ck_assert_uint_eq(done, 5);
  ck_assert_int_eq(sdae_integrate(g, 0.0, 0.1, 5, 1, gxi, gmu, NULL, NULL, NULL), SDAE_OK);
  ck_assert_int_eq(memcmp(xi, gxi, sizeof xi), 0);
  ck_assert_int_eq(memcmp(mu, gmu, sizeof mu), 0);
  sdae_stepper_free(s);
  sdae_stepper_free(g);
}
END_TEST

/* One run of 2000 dgrad steps from an off-manifold start; the stepper is built in `mem` when
 * given, by sdae_stepper_alloc otherwise. */
typedef struct job {
  void *mem;
  size_t len;
  double xi[2], mu[2];
  int status;
} job;

static void *run_job(void *arg) {
  job *j = arg;
  quartic p = {2.0, 0.03, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_dgrad, SDAE_SCHEME_SEMI_IMPLICIT);
  sdae_stepper *s;
  o.delta = 2.0;
  j->xi[0] = 0.6, j->xi[1] = 0.0, j->mu[0] = 0.7, j->mu[1] = 0.6;
  j->status =
      j->mem ? sdae_stepper_init(&s, j->mem, j->len, &m, &o) : sdae_stepper_alloc(&s, &m, &o);
  if (j->status == SDAE_OK)
    j->status = sdae_integrate(s, 0.0, 1e-3, 2000, 1, j->xi, j->mu, NULL, NULL, NULL);
  sdae_stepper_free(s);
  return NULL;
}

START_TEST(caller_memory_same_as_alloc) {
  static max_align_t mem[256];
  job a = {0}, b = {mem, sizeof mem, {0}, {0}, 0};
  run_job(&a);
  run_job(&b);
  ck_assert_int_eq(a.status, SDAE_OK);
  ck_assert_int_eq(b.status, SDAE_OK);
  ck_assert_int_eq(memcmp(a.xi, b.xi, sizeof a.xi), 0);
  ck_assert_int_eq(memcmp(a.mu, b.mu, sizeof a.mu), 0);
  /* and the run did move: xi contracted by Theorem 4, mu changed */
  ck_assert_double_lt(fabs(a.xi[0]), 1e-6);
}
END_TEST

/* No global state: two threads with their own steppers reproduce the serial run bit for bit. */
START_TEST(threads_bit_identical) {
  job serial = {0}, t1 = {0}, t2 = {0};
  pthread_t h1, h2;
  run_job(&serial);
  ck_assert_int_eq(pthread_create(&h1, NULL, run_job, &t1), 0);
  ck_assert_int_eq(pthread_create(&h2, NULL, run_job, &t2), 0);
  pthread_join(h1, NULL);
  pthread_join(h2, NULL);
  ck_assert_int_eq(t1.status, SDAE_OK);
  ck_assert_int_eq(t2.status, SDAE_OK);
  ck_assert_int_eq(memcmp(t1.mu, serial.mu, sizeof serial.mu), 0);
  ck_assert_int_eq(memcmp(t2.mu, serial.mu, sizeof serial.mu), 0);
  ck_assert_int_eq(memcmp(t1.xi, serial.xi, sizeof serial.xi), 0);
  ck_assert_int_eq(memcmp(t2.xi, serial.xi, sizeof serial.xi), 0);
}
END_TEST

static int count_calls(size_t step, double t, const double *xi, const double *mu, void *data) {
  (void)step, (void)t, (void)xi, (void)mu;
  (*(int *)data)++;
  return 0;
}

/* sdae_integrate checks its own arguments before anything else, even with no step to take
 * (nsteps = 0, where sdae_step's checks never run): a NULL stepper or state is SDAE_ERR_NULL,
 * a step T <= 0 (0 included) or not finite SDAE_ERR_STEP (stabdae.h), the observer is never
 * called and no step is done; the same call with valid arguments observes step 0 once. */
START_TEST(bad_arguments_refused_before_observing) {
  quartic p = {1.0, 0.0, 0, 0};
  sdae_model m = quartic_model(&p);
  sdae_options o = quartic_options(sdae_map_euler, SDAE_SCHEME_SEMI_IMPLICIT);
  const double badT[4] = {0.0, -1.0, NAN, INFINITY};
  sdae_stepper *s;
  double xi[2] = {0.1, 0}, mu[2] = {1, 0};
  int calls = 0;
  size_t done = 99;
  ck_assert_int_eq(sdae_stepper_alloc(&s, &m, &o), SDAE_OK);
  for (size_t nsteps = 0; nsteps <= 3; nsteps += 3) {
    ck_assert_int_eq(sdae_integrate(NULL, 0.0, 0.1, nsteps, 1, xi, mu, count_calls, &calls, &done),
                     SDAE_ERR_NULL);
    ck_assert_int_eq(sdae_integrate(s, 0.0, 0.1, nsteps, 1, NULL, mu, count_calls, &calls, &done),
                     SDAE_ERR_NULL);
    ck_assert_int_eq(sdae_integrate(s, 0.0, 0.1, nsteps, 1, xi, NULL, count_calls, &calls, &done),
                     SDAE_ERR_NULL);
    for (int i = 0; i < 4; i++)
      ck_assert_int_eq(
          sdae_integrate(s, 0.0, badT[i], nsteps, 1, xi, mu, count_calls, &calls, &done),
          SDAE_ERR_STEP);
    ck_assert_int_eq(calls, 0);
    ck_assert_uint_eq(done, 0);
  }
  ck_assert_double_eq(xi[0], 0.1);
  ck_assert_double_eq(mu[0], 1.0);
  ck_assert_int_eq(sdae_integrate(s, 0.0, 0.1, 0, 1, xi, mu, count_calls, &calls, &done), SDAE_OK);
  ck_assert_int_eq(calls, 1);
  sdae_stepper_free(s);
}
END_TEST

int main(void) {
  Suite *s = suite_create("integrate");
  ADD_CASE(s, observer_sees_first_every_and_last);
  ADD_CASE(s, observer_stops_cleanly);
  ADD_CASE(s, failure_keeps_last_good_state);
  ADD_CASE(s, caller_memory_same_as_alloc);
  ADD_CASE(s, threads_bit_identical);
  ADD_CASE(s, bad_arguments_refused_before_observing);
  return run_suite(s);
}
