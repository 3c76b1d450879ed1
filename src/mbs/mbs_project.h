/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The projection step (mbs_project.c): where the constraints' gradients are nearly dependent
 * along the motion (a singular configuration, where rank G drops for an instant and no chart
 * holds), the step is taken in (q, v) instead of the chart's (xi, mu). The index-1 motion
 * q' = v, M v' = F - G^T lambda, G v' + gamma = 0 (the acceleration by the null-space method on
 * G's rank-revealing QR, mbs_nullspace.h, rows nearly dependent on the others dropped) by one step
 * of the explicit rk8 map, then q projected M-orthogonally onto c = 0 (Gauss-Newton, least M-norm
 * corrections) and v onto G v + dc/dt = 0: the constraints at rounding at the step's end, as a
 * chart step leaves them, and the branch kept (the smallest correction). On either back-end
 * (mbs_project_linalg.h); a mechanism with redundant rows declared is never projected. */
#ifndef STABDAE_SRC_MBS_MBS_PROJECT_H
#define STABDAE_SRC_MBS_MBS_PROJECT_H

#include <stabdae/stabdae.h>

#include "core/arena.h"
#include "core/bytes.h"
#include "maps/map.h"
#include "mbs_eval.h"
#include "mbs_project_linalg.h"
#include "mbs_sparse_layout.h"

typedef struct sdae_mbs_project {
  sdae_mbs_eval *eval;
  size_t n_q, n_c;
  int on;                   /* the mechanism may be projected (no redundant rows declared) */
  unsigned max_iter;        /* the projection's Gauss-Newton: the options' cap */
  sdae_model model;         /* y = (q, v) (2 n_q), y' = (v, a): the index-1 motion */
  const sdae_map_type *map; /* rk8 */
  sdae_map_ctx ctx;         /* the map's scratch */
  /* the saddle-point system over the coordinates' back-end (one of the two, as la points) */
  const sdae_mbs_project_linalg *linalg;
  void *la;
  sdae_mbs_project_dense dense;
  sdae_mbs_project_sparse sparse;
  double *y, *phi, *ys; /* 2 n_q each: the state, the map's phi, a stage projected */
  double *F, *gamma;    /* at a point: n_q, n_c */
  double *c, *ct, *dx;  /* n_c, n_c, n_q: c or G v + dc/dt, dc/dt, a correction */
  int status;           /* the front-end's status inside the map's call of the motion */
  /* the constraints' independence (the chart's least sine) at the last step's start and the
   * largest at any step's start, -1 before the first: the next step's is compared with them
   * (in the state's bytes) */
  double last, largest;
} sdae_mbs_project;

/* wired to the callbacks and the options, over the sparse back-end's layout and what its step
 * lends where the coordinates' are sparse (else NULL: dense); on: may project (else carves
 * nothing) */
void sdae__mbs_project_init(sdae_mbs_project *p, sdae_mbs_eval *eval, const sdae_options *o,
                            const sdae_mbs_sparse_layout *sparse, const sdae_mbs_sparse_lent *lent,
                            int on);
void sdae__mbs_project_carve(sdae_mbs_project *p, sdae_arena *a);
/* A step from (t, q) whose start found the independence s (start: the start's status; CHART or
 * RANK where no chart holds) is projected: after a step (not the first, where a mechanism with
 * dependent constraints is refused as before), when s is below SDAE_MBS_SINGULAR_NEAR of the
 * largest seen, or falling toward that within one more step as it fell over the last (2 s -
 * last below it): a singular configuration is where the independence falls by orders of
 * magnitude, whatever it is on the mechanism's regular configurations (a long chain's, or
 * constraints nearly dependent all along, are stepped in the chart) */
int sdae__mbs_project_wanted(const sdae_mbs_project *p, int start, double s);
/* the independence at this step's start, for the next one */
void sdae__mbs_project_seen(sdae_mbs_project *p, double s);
/* One projection step from (t, q, v) to t + T, written into q and v when it succeeds (SDAE_OK).
 * SDAE_ERR_NEWTON when the projection of q does not converge within the cap, SDAE_ERR_CHART when
 * the step left the constraints by more than SDAE_MBS_PROJECT_DRIFT of its own motion (it
 * cannot be taken accurately: rk8 past its stability, or a configuration it cannot resolve),
 * SDAE_ERR_MASS, SDAE_ERR_NONFINITE or a callback's failure; q and v untouched then. */
int sdae__mbs_project_step(sdae_mbs_project *p, double t, double T, double *q, double *v);
/* what the next step depends on (last), counted, written or read */
void sdae__mbs_project_state(sdae_mbs_project *p, sdae_bytes *b);

#endif /* STABDAE_SRC_MBS_MBS_PROJECT_H */
