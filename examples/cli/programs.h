/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The example programs as definitions (cli.h's cli_def), for the ensemble runner. Each program's
 * source defines its own; compiled with CLI_NO_MAIN it leaves its main out, so the runner
 * links them all. A new program: its cli_def here, in the runner's table
 * (examples/ensemble/models.c) and in examples/CMakeLists.txt's list of programs. */
#ifndef STABDAE_EXAMPLES_PROGRAMS_H
#define STABDAE_EXAMPLES_PROGRAMS_H

#include "cli.h"

extern const cli_def oscillator_def, pendulum_def, chain_def;
extern const cli_def pendulum_mbs_def, double_pendulum_def, fourbar_def;
extern const cli_def slider_crank_def, car_axis_def, andrews_def;

#endif /* STABDAE_EXAMPLES_PROGRAMS_H */
