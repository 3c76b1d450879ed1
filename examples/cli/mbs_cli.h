/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The driver of the mechanical programs (pendulum_mbs, double_pendulum, fourbar, slider_crank,
 * car_axis, andrews): the shared run settings and maps, and the integration through
 * <stabdae/mbs.h> writing t,q1..qn,v1..vn,lambda1..lambdam,max_abs_c,E,switches with the exit
 * codes of cli.h. */
#ifndef STABDAE_EXAMPLES_MBS_CLI_H
#define STABDAE_EXAMPLES_MBS_CLI_H

#include <stabdae/mbs.h>

#include "cli.h"

/* every map but the user map; the discrete-gradient ones (dgrad, dg4, dg6) need a potential,
 * which the library checks (the car axis has none: SDAE_ERR_MAP, bad input) */
extern const char *const mbs_map_choices[];

/* The defaults of the mechanical programs: delta 2, epsilon 1, T 0.001, tf 10, scheme 15,
 * map dgrad, a row every step. */
cli_run mbs_run_defaults(void);

/* The program's n model flags, then the shared ones (cli_run_flags with mbs_map_choices), into
 * flags (room for n + CLI_RUN_NFLAGS; *nflags set), parsed by cli_parse: its CLI_OK, CLI_HELP
 * or CLI_BAD (err set). */
int mbs_parse(int argc, char *const *argv, const cli_flag *model, size_t n, cli_flag *flags,
              size_t *nflags, cli_run *run, char *err, size_t errlen);

typedef struct mbs_program {
  const char *name; /* for messages */
  const sdae_mbs *sys;
  double *q, *v; /* the initial state (n_q each), updated in place */
} mbs_program;

/* Builds the stepper and integrates run->nsteps steps, writing rows to sink (NULL: the run's
 * --out, opened here), as cli_execute_to. Returns the exit code: 2 (no file left) when the
 * library rejects the settings, 1 with the rows so far kept and one line naming the step when a
 * step or a row fails, else 0. */
int mbs_execute_to(const mbs_program *p, const cli_run *run, cli_sink *sink);

#endif /* STABDAE_EXAMPLES_MBS_CLI_H */
