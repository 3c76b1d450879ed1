/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Human-readable text for every status. */
#include <stabdae/stabdae.h>

const char *sdae_strerror(int status) {
  switch ((sdae_status)status) {
  case SDAE_OK: return "success";
  case SDAE_STOPPED: return "stopped by the observer";
  case SDAE_ERR_NULL: return "a required pointer is NULL";
  case SDAE_ERR_DIM: return "a dimension is zero or inconsistent";
  case SDAE_ERR_STEP: return "the step size T must be finite and > 0";
  case SDAE_ERR_PARAM:
    return "a parameter is out of range (delta, epsilon, Newton tolerance and iteration cap, "
           "Baumgarte gains, time)";
  case SDAE_ERR_OPTION: return "unknown scheme or stabilizer";
  case SDAE_ERR_STATE: return "xi or mu holds NaN or Inf";
  case SDAE_ERR_CALLBACK_FATAL: return "a model callback failed (returned < 0)";
  case SDAE_ERR_CALLBACK_RECOVERABLE:
    return "a model callback reported a recoverable failure (returned > 0); the step may be "
           "retried, e.g. with a smaller T";
  case SDAE_ERR_NONFINITE: return "a callback wrote NaN or Inf, or the new state is not finite";
  case SDAE_ERR_SINGULAR: return "the Newton matrix I - T dphi/dmu+ is singular";
  case SDAE_ERR_NEWTON: return "Newton did not converge within the iteration cap";
  case SDAE_ERR_MAP:
    return "no map, or the map needs callbacks that the model does not give (the mechanical "
           "front-end: a discrete gradient needs a potential and constraints that do not "
           "depend on t)";
  case SDAE_ERR_BUFFER: return "the memory block is smaller than sdae_stepper_size";
  case SDAE_ERR_NOMEM: return "out of memory";
  case SDAE_ERR_REL_DEGREE:
    return "the baselines need rel_degree: n_constraints values in 1..SDAE_MAX_REL_DEGREE "
           "summing to n_xi (the front-ends offer the paper's stabilizer only)";
  case SDAE_ERR_OVERFLOW: return "the workspace size overflows size_t";
  case SDAE_ERR_RANK:
    return "the constraints are dependent at this state (rank of G = dc/dq below n_c): "
           "redundant constraints or a singular configuration";
  case SDAE_ERR_CHART:
    return "no usable chart at this state: for every choice of dependent coordinates "
           "dq_D/dq_I is too large (a configuration next to a singular one)";
  case SDAE_ERR_PHI_INV:
    return "Newton for Phi^-1 (the state from its coordinates xi, mu) did not converge: the "
           "point may have no preimage in the current chart";
  case SDAE_ERR_MASS:
    return "the mass matrix is not symmetric, or not positive definite on the constraints' "
           "tangent space (the reduced mass W^T M W)";
  case SDAE_ERR_STATE_DAMAGED:
    return "the saved state is cut short or damaged (its length or checksum does not match)";
  case SDAE_ERR_STATE_FOREIGN:
    return "the saved state is of another mechanism, map, options or build of the library";
  case SDAE_ERR_PATTERN:
    return "a sparsity pattern is not one (its columns unsorted, duplicated or out of range, "
           "row_start inconsistent with nnz, a mass pattern not symmetric), or the patterns' "
           "factors (the saddle-point system's, or a chart's LU when one is chosen) need more "
           "entries than the stepper reserves";
  }
  return "unknown status";
}
