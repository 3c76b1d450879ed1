/* SPDX-License-Identifier: GPL-3.0-or-later */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include "measure.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

double wp_cpu_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int wp_repeat(int reps, double budget, int (*run)(void *ctx), void *ctx, double *cpu) {
  double t[WP_MAX_REPS], used = 0.0;
  int n = 0, failed = 0;
  if (reps > WP_MAX_REPS) reps = WP_MAX_REPS;
  while (n < reps && (n == 0 || used < budget) && !failed) {
    double t0 = wp_cpu_seconds();
    failed = run(ctx);
    t[n] = wp_cpu_seconds() - t0;
    used += t[n++];
  }
  *cpu = median(t, n);
  return n;
}

int wp_bad(const char *prog, const char *what, const char *arg) {
  fprintf(stderr, "%s: %s%s\n", prog, what, arg ? arg : "");
  return 2;
}

int wp_parse_positive(const char *prog, const char *flag, const char *v, double max, double *out) {
  char *end;
  errno = 0;
  *out = strtod(v, &end);
  if (errno || end == v || *end || !(*out > 0.0) || *out > max) {
    char msg[96];
    snprintf(msg, sizeof msg, "%s must be a number in (0, %g], not ", flag, max);
    return wp_bad(prog, msg, v);
  }
  return 0;
}
