/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae's floor (layer: core): the statuses every call returns and their messages, the
 * library's version, the allocator a caller may lend (<stabdae/alloc.h>) and the export macro.
 * Every other public header stands on this one. */
#ifndef STABDAE_BASE_H
#define STABDAE_BASE_H

#include <stabdae/alloc.h>
#include <stabdae/export.h>
#include <stabdae/version.h>

#ifdef __cplusplus
extern "C" {
#endif

/* "MAJOR.MINOR.PATCH" of the library linked at run time (a static string); SDAE_VERSION_MAJOR,
 * _MINOR, _PATCH and SDAE_VERSION_STRING (<stabdae/version.h>) are those of the headers. */
SDAE_API const char *sdae_version(void);

typedef enum sdae_status {
  SDAE_OK = 0,
  SDAE_STOPPED = 1,                   /* sdae_integrate: the observer asked to stop */
  SDAE_ERR_NULL = -1,                 /* a required pointer is NULL */
  SDAE_ERR_DIM = -2,                  /* a dimension is zero or inconsistent */
  SDAE_ERR_STEP = -3,                 /* T <= 0 or not finite */
  SDAE_ERR_PARAM = -4,                /* delta, epsilon, a tolerance or a gain out of range */
  SDAE_ERR_OPTION = -5,               /* unknown scheme or stabilizer */
  SDAE_ERR_STATE = -6,                /* xi or mu holds NaN or Inf on entry */
  SDAE_ERR_CALLBACK_FATAL = -7,       /* a user callback returned < 0 */
  SDAE_ERR_CALLBACK_RECOVERABLE = -8, /* a user callback returned > 0 */
  SDAE_ERR_NONFINITE = -9,            /* a callback wrote NaN/Inf, or the new state is not finite */
  SDAE_ERR_SINGULAR = -10,            /* the Newton matrix I - T dphi/dmu+ is singular */
  SDAE_ERR_NEWTON = -11,              /* Newton did not converge within the iteration cap */
  SDAE_ERR_MAP = -12,        /* no map, or the map needs callbacks the model does not give */
  SDAE_ERR_BUFFER = -13,     /* the caller's memory block is too small */
  SDAE_ERR_NOMEM = -14,      /* an allocation failed */
  SDAE_ERR_REL_DEGREE = -15, /* the baselines need rel_degree, summing to n_xi */
  SDAE_ERR_OVERFLOW = -16,   /* the workspace size does not fit in size_t */
  /* the front-ends (<stabdae/dae.h>, <stabdae/mbs.h>) */
  SDAE_ERR_RANK = -17,    /* the constraints are dependent here: rank G < n_c */
  SDAE_ERR_CHART = -18,   /* no usable chart: every choice of q_D is nearly singular */
  SDAE_ERR_PHI_INV = -19, /* Newton for Phi^-1 (x from (xi, mu)) did not converge */
  SDAE_ERR_MASS = -20,    /* the mass matrix is not symmetric, or W^T M W not positive definite */
  /* a stepper's state as bytes (sdae_mbs_set_state) */
  SDAE_ERR_STATE_DAMAGED = -21, /* the bytes are cut short or damaged (checksum) */
  SDAE_ERR_STATE_FOREIGN = -22, /* the bytes are of another mechanism, map, options or build */
  /* a sparsity pattern (<stabdae/pattern.h>) unsorted, out of range, duplicated, inconsistent
   * with its nnz, or (a mass's) not symmetric; or the patterns' saddle-point factor (a sparse
   * mechanism's, docs/front-ends.md) needs more entries than the stepper reserves */
  SDAE_ERR_PATTERN = -23
} sdae_status;

/* A status's name and meaning, a static string ("unknown status" for one the library never
 * returns). */
SDAE_API const char *sdae_strerror(int status);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_BASE_H */
