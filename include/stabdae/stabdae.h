/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae: fixed-step integration of constrained mechanical systems without constraint drift.
 *
 * Implements Di Franco, Scarciotti, Astolfi, "Discretization schemes for constraint
 * stabilization in nonlinear differential-algebraic systems". A DAE xdot = f + g lambda,
 * 0 = h (eq. 1) written in coordinates (xi, mu) (eq. 2-3) is replaced by the stabilized
 * system (eq. 5)
 *
 *     xi_i' = k_i xi_i,   k_i = -(delta^2/2) ||q_i(xi, mu)||^2 - epsilon        (eq. 6)
 *     mu'   = q0(mu) + Q(xi, mu) xi,  Q = [q_1 ... q_p]
 *
 * and discretized with a fixed step T by scheme 11 (explicit) or scheme 15 (semi-implicit),
 * with a map phi_T(mu, mu+) -> q0 (eq. 13) for the constrained motion.
 *
 * Conventions: every call returns an sdae_status (0 success, negative error, positive
 * information); matrices are row-major flat arrays; callbacks return 0 on success, > 0 for a
 * recoverable failure and < 0 for a fatal one. The library keeps no global state, never
 * prints, never aborts, and sdae_step never allocates.
 */
#ifndef STABDAE_STABDAE_H
#define STABDAE_STABDAE_H

#include <stddef.h>

#include <stabdae/alloc.h>
#include <stabdae/certify.h>
#include <stabdae/check.h>
#include <stabdae/dae.h>
#include <stabdae/export.h>
#include <stabdae/model.h>
#include <stabdae/version.h>

#ifdef __cplusplus
extern "C" {
#endif

/* "MAJOR.MINOR.PATCH" of the library linked at run time (a static string); SDAE_VERSION_MAJOR,
 * _MINOR, _PATCH and SDAE_VERSION_STRING (<stabdae/version.h>) are those of the headers. */
SDAE_API const char *sdae_version(void);

/* Highest relative degree of one constraint the baselines (none, Baumgarte) accept. */
#define SDAE_MAX_REL_DEGREE 4

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

/* ---- options ------------------------------------------------------------------------------ */

typedef enum sdae_scheme {
  SDAE_SCHEME_EXPLICIT = 11,     /* eq. 11: xi+ = (I + T K) xi */
  SDAE_SCHEME_SEMI_IMPLICIT = 15 /* eq. 15: xi+ = (I - T K)^-1 xi */
} sdae_scheme;

typedef enum sdae_stabilizer {
  SDAE_STAB_PAPER = 0,    /* eq. 6: xi_i' = k_i xi_i */
  SDAE_STAB_NONE = 1,     /* index reduction: xi_j' = xi_{j+1}, last = 0 (drifts) */
  SDAE_STAB_BAUMGARTE = 2 /* as none, last = -sum_j alpha_j xi_j */
} sdae_stabilizer;

/* A map phi_T(mu, mu+) for the constrained motion: a static table of functions (src/maps/map.h),
 * one file per map. Each needs of the model what its comment says. */
typedef struct sdae_map_type sdae_map_type;

SDAE_API extern const sdae_map_type *const sdae_map_euler;    /* "euler": q0(mu), explicit */
SDAE_API extern const sdae_map_type *const sdae_map_midpoint; /* "midpoint": q0((mu + mu+)/2) */
/* "dgrad": S(mid) gradbar H, Gonzalez's discrete gradient (H, grad_H, S or S_apply) */
SDAE_API extern const sdae_map_type *const sdae_map_dgrad;
SDAE_API extern const sdae_map_type *const sdae_map_user; /* "user": the model's user_phi */
/* dgrad composed symmetrically, H conserved for skew S (dgrad's callbacks): "dg4" by Yoshida's
 * triple jump (order 4, 3 stages), "dg6" by Kahan and Li's s9odr6a (order 6, 9 stages) */
SDAE_API extern const sdae_map_type *const sdae_map_dg4;
SDAE_API extern const sdae_map_type *const sdae_map_dg6;
/* midpoint composed the same ways, for any forces and time-dependent models (q0 only):
 * "midpoint4" (order 4, 3 stages) and "midpoint6" (order 6, 9 stages) */
SDAE_API extern const sdae_map_type *const sdae_map_midpoint4;
SDAE_API extern const sdae_map_type *const sdae_map_midpoint6;
/* "rk4": the classical Runge-Kutta method on mu' = q0(t, mu), explicit, order 4 (q0 only) */
SDAE_API extern const sdae_map_type *const sdae_map_rk4;
/* "rk8": DOP853's eighth-order Runge-Kutta solution, explicit, order 8, 12 stages (q0 only) */
SDAE_API extern const sdae_map_type *const sdae_map_rk8;

/* The map's name ("(none)" for NULL), and the map of a name (NULL when there is none). */
SDAE_API const char *sdae_map_name(const sdae_map_type *map);
SDAE_API const sdae_map_type *sdae_map_by_name(const char *name);
/* The map's order of accuracy as T -> 0 (0 for sdae_map_user: the user's map decides). */
SDAE_API unsigned sdae_map_order(const sdae_map_type *map);

/* The method: how the model is solved. The problem itself is the sdae_model. */
typedef struct sdae_options {
  sdae_scheme scheme;       /* default SDAE_SCHEME_SEMI_IMPLICIT */
  double delta, epsilon;    /* eq. 6, both > 0; default 1, 1 */
  const sdae_map_type *map; /* default sdae_map_euler */

  /* Newton on R(mu+) = mu+ - mu - T (phi_T + Q xi): stop when the update is at most
   * newton_tol * (1 + ||mu+||_inf); at most newton_max_iter iterations */
  double newton_tol;        /* default 1e-14 */
  unsigned newton_max_iter; /* default 20 */
  /* 0 (default: dense), or b > 0 when d phi/d mu+ has at most b sub- and b super-diagonals
   * (true of the midpoint and discrete-gradient maps when q0, S and grad H couple mu_i only to
   * mu_j with |i - j| <= b). Newton then factors a band, O(n b^2), and builds its matrix from
   * 2 (2b + 1) evaluations of phi whatever n; the analytic Jacobians (q0_jac, hess_H,
   * user_phi_jac) are dense and are not used then. */
  size_t bandwidth;

  sdae_stabilizer stabilizer; /* default SDAE_STAB_PAPER */
  /* Baumgarte: L_f^{r} h_c = -sum_{j<r} baumgarte_alpha[j] L_f^j h_c for every constraint;
   * the default {1, 2} makes a relative-degree-2 constraint critically damped at rate 1 */
  double baumgarte_alpha[SDAE_MAX_REL_DEGREE];
} sdae_options;

SDAE_API void sdae_options_default(sdae_options *o);

/* ---- stepper ------------------------------------------------------------------------------ */

typedef struct sdae_stepper sdae_stepper;

typedef struct sdae_stats {
  unsigned long steps;        /* successful steps */
  unsigned newton_iters_last; /* Newton iterations of the last step (0: explicit) */
  unsigned long newton_iters_total;
  double newton_residual_last; /* ||R||_inf at the last Newton iterate evaluated */
  unsigned long phi_evals;     /* evaluations of phi_T */
} sdae_stats;

/* Bytes sdae_stepper_init needs; 0 when the model or options are invalid or overflow. */
SDAE_API size_t sdae_stepper_size(const sdae_model *m, const sdae_options *o);
/* Builds a stepper inside the caller's block mem[0..len) (any alignment: the stepper aligns
 * itself within it); no malloc. The model and options are copied. On failure *s is left as it
 * was, here and in sdae_stepper_alloc: only a stepper they returned SDAE_OK for may be freed. */
SDAE_API int sdae_stepper_init(sdae_stepper **s, void *mem, size_t len, const sdae_model *m,
                               const sdae_options *o);
SDAE_API int sdae_stepper_alloc(sdae_stepper **s, const sdae_model *m, const sdae_options *o);
/* As sdae_stepper_alloc, the block from the allocator a (NULL: malloc); the stepper keeps a copy
 * of a, frees its block with it and lends it to sdae_certify_box. */
SDAE_API int sdae_stepper_alloc_with(sdae_stepper **s, const sdae_model *m, const sdae_options *o,
                                     const sdae_allocator *a);
/* Gives back an allocated stepper's block; for an init'ed one gives nothing back, and makes the
 * caller's block plain bytes again (built with AddressSanitizer, the library poisons the gaps
 * between its arrays: free before filling the block anew). NULL is fine. */
SDAE_API void sdae_stepper_free(sdae_stepper *s);

/* One step of scheme 11 or 15 from time t: xi, mu are updated in place. On error they are left
 * exactly as they were. */
SDAE_API int sdae_step(sdae_stepper *s, double t, double T, double *xi, double *mu);

/* The gains k_i of eq. 6 at (xi, mu): n_xi values. */
SDAE_API int sdae_stepper_gains(sdae_stepper *s, double t, const double *xi, const double *mu,
                                double *k);

SDAE_API const sdae_stats *sdae_stepper_stats(const sdae_stepper *s);
SDAE_API void sdae_stepper_reset_stats(sdae_stepper *s);

/* ---- integrate ---------------------------------------------------------------------------- */

/* Called with the state after step `step` (0: the initial state); non-zero stops the run. */
typedef int (*sdae_observer)(size_t step, double t, const double *xi, const double *mu, void *data);

/* nsteps fixed steps of size T from t0. The observer (may be NULL) sees step 0, every
 * `every`-th step and the last one. On failure xi, mu hold the state after the last good step
 * and *steps_done (may be NULL) says how many were taken. Returns SDAE_STOPPED when the
 * observer stopped the run. */
SDAE_API int sdae_integrate(sdae_stepper *s, double t0, double T, size_t nsteps, size_t every,
                            double *xi, double *mu, sdae_observer obs, void *data,
                            size_t *steps_done);

SDAE_API const char *sdae_strerror(int status);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_STABDAE_H */
