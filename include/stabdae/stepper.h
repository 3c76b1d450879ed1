/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae's stepper (layer: stepper): the options (scheme, gains, map, Newton, stabilizer), a
 * stepper of a model (<stabdae/model.h>), one step of scheme 11 or 15, the gains and the fixed-step
 * run with an observer. */
#ifndef STABDAE_STEPPER_H
#define STABDAE_STEPPER_H

#include <stddef.h>

#include <stabdae/base.h>
#include <stabdae/maps.h>
#include <stabdae/model.h>

#ifdef __cplusplus
extern "C" {
#endif

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

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_STEPPER_H */
