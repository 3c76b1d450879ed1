/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "ensemble.h"
#include "programs.h"

/* a new program: its cli_def here */
const cli_def *const ens_models[] = {
    &oscillator_def, &pendulum_def,     &chain_def,    &pendulum_mbs_def, &double_pendulum_def,
    &fourbar_def,    &slider_crank_def, &car_axis_def, &andrews_def,      NULL};
