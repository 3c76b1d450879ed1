/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanical front-end's stepper (<stabdae/mbs.h>): one block holding its parts, each with
 * its own arrays, scratch and state. Data flows one way: the mechanism's callbacks (mbs_eval)
 * -> the coordinates, written once over a dense or a sparse linear-algebra back-end
 * (mbs_coords.h, mbs_linalg.h: the point, Phi^-1, the mu-dynamics; the chart and the factors)
 * -> the normal form handed to the stepper (mbs_model) -> the step in (q, v), which starts with
 * one call of the coordinates, commits the statistics when it succeeds and rolls back in one
 * place when it fails (mbs.c, mbs_state.c). */
#ifndef STABDAE_SRC_MBS_MBS_IMPL_H
#define STABDAE_SRC_MBS_MBS_IMPL_H

#include <stabdae/mbs.h>

#include "core/alloc.h"
#include "mbs_coords.h"
#include "mbs_dense.h"
#include "mbs_eval.h"
#include "mbs_model.h"
#include "mbs_project.h"
#include "mbs_sparse.h"

struct sdae_mbs_stepper {
  sdae_options opt;
  size_t n_q, n_c, n_f;
  sdae_mbs_eval eval;
  sdae_mbs_coords coords; /* over the back-end coords.linalg: &dense or &sparse */
  sdae_mbs_dense dense;   /* (the other one is never carved) */
  sdae_mbs_sparse sparse;
  sdae_mbs_model nf;        /* the normal form in the current chart */
  sdae_mbs_project project; /* the step near a singular configuration, in (q, v) */
  sdae_stepper *inner;      /* the normal form's stepper, in this block */
  sdae_block block;         /* what sdae_mbs_stepper_alloc_with allocated */
  sdae_mbs_stats stats;     /* committed by sdae_mbs_step when a step succeeds */
  double *xi, *mu;          /* 2 n_c, 2 n_f: the step's state in the chart */
  unsigned char *rollback;  /* the parts' state before the step (mbs_state.c), for a failure */
};

/* the bytes of the parts' state (mbs_state.c), known once the parts are wired */
size_t sdae__mbs_parts_bytes(const sdae_mbs_stepper *s);
/* the parts' state kept before a step, and put back after a failed one: a failed step leaves
 * the stepper as it was, bit for bit (the one place a step is rolled back) */
void sdae__mbs_rollback_save(sdae_mbs_stepper *s);
void sdae__mbs_rollback(sdae_mbs_stepper *s);

/* the state as bytes behind sdae_mbs_state_size, _get_state and _set_state (mbs_state.c), for
 * a stepper and a buffer that are there */
size_t sdae__mbs_state_size(const sdae_mbs_stepper *s);
int sdae__mbs_state_get(const sdae_mbs_stepper *s, void *buf, size_t len);
int sdae__mbs_state_set(sdae_mbs_stepper *s, const void *buf, size_t len);

/* the statistics from the normal form's stepper's and the chart's measure, beside the counters
 * the steps committed: the one place they are put together (after every step, a reset and a
 * state set) */
void sdae__mbs_stepper_gather(sdae_mbs_stepper *s);

#endif /* STABDAE_SRC_MBS_MBS_IMPL_H */
