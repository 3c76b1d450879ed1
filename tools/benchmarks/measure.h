/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The measurement shared by the work-precision programs (workprecision, benchmarks): process CPU
 * time, repetitions within a budget, their median, and the programs' bad-input line. */
#ifndef STABDAE_TOOLS_MEASURE_H
#define STABDAE_TOOLS_MEASURE_H

enum { WP_MAX_REPS = 15 };

/* CLOCK_PROCESS_CPUTIME_ID in seconds */
double wp_cpu_seconds(void);

/* Runs run(ctx) up to reps times (at most WP_MAX_REPS), fewer once budget CPU seconds are used
 * or as soon as a run fails (returns non-zero); *cpu is the median CPU time of the runs. Returns
 * the number of runs. */
int wp_repeat(int reps, double budget, int (*run)(void *ctx), void *ctx, double *cpu);

/* One line "PROG: what[arg]" on stderr; returns 2, the exit status of bad input. */
int wp_bad(const char *prog, const char *what, const char *arg);

/* A number in (0, max] from the value of flag; 0, or wp_bad's 2. */
int wp_parse_positive(const char *prog, const char *flag, const char *v, double max, double *out);

#endif
