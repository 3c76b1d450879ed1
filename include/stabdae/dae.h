/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae generic front-end (layer: dae): the library derives the normal form (paper eq. 5) of a
 * DAE xdot = f(t, x) + g(t, x) lambda, 0 = h(t, x) (eq. 1) from its coordinates z = Phi(t, x) =
 * (xi, mu), doing Proposition 1 itself. With
 *
 *     G(t, xi, mu) = mu_dot(t, Phi^-1(t, xi, mu))     (the mu-dynamics; lambda drops out as
 *                                                       L_g mu = 0)
 *     q0(t, mu) = G(t, 0, mu)
 *     q_i(t, xi, mu) = (G(xi^(i)) - G(xi^(i-1))) / xi_i,   xi^(i) = (xi_1..xi_i, 0..0)
 *
 * the telescoping divided differences give sum_i q_i xi_i = G(xi) - G(0) exactly, so
 * q0 + Q xi is the DAE's own mu-dynamics wherever Phi^-1 is defined. */
#ifndef STABDAE_DAE_H
#define STABDAE_DAE_H

#include <stddef.h>

#include <stabdae/base.h>
#include <stabdae/model.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The DAE of eq. 1 and its coordinates, as the generic front-end and the model check
 * (<stabdae/check.h>) take it. */
typedef struct sdae_dae {
  size_t n; /* dim x = n_xi + n_mu */
  size_t m; /* multipliers, one per constraint */
  int (*f)(double t, const double *x, double *out, void *params); /* n values */
  int (*g)(double t, const double *x, double *out, void *params); /* n x m, row-major */
  /* z = Phi(x) = (xi, mu): xi the constraints' Lie chains (h, L_f h, ...), as in the model */
  int (*Phi)(double t, const double *x, double *z, void *params);
  int (*Phi_inv)(double t, const double *z, double *x, void *params); /* optional: Newton */
  int (*Phi_jac)(double t, const double *x, double *J, void *params); /* optional: n x n */
  void *params;
} sdae_dae;

/* d/dt mu(t, x) along xdot = f(t, x): n_mu values (the dae's params). Optional: without it, a
 * fourth-order central difference of mu(t + s, x + s f) in s (about 3e-12 relative). */
typedef int (*sdae_mu_dot_fn)(double t, const double *x, double *mu_dot, void *params);

/* The derived model: an sdae_model whose q0 and Q_apply are the rule above. Its callbacks work
 * in this object's memory (Phi^-1's Newton is warm-started from the last point it found), so one
 * derived model serves one stepper at a time. */
typedef struct sdae_dae_model sdae_dae_model;

/* Bytes sdae_dae_model_init needs for a DAE with n_xi constraint coordinates (n_mu = n - n_xi);
 * 0 when the DAE is invalid (a NULL f, g or Phi, n_xi = 0 or n_xi >= n) or the size overflows. */
SDAE_API size_t sdae_dae_model_size(const sdae_dae *dae, size_t n_xi);
/* Builds the derived model in the caller's block mem[0..len) (no malloc). dae is copied.
 * x_guess (n values, or NULL: x = z) starts the first Newton for Phi^-1 when the DAE has no
 * Phi_inv. On failure *d is left as it was. */
SDAE_API int sdae_dae_model_init(sdae_dae_model **d, void *mem, size_t len, const sdae_dae *dae,
                                 size_t n_xi, sdae_mu_dot_fn mu_dot, const double *x_guess);
SDAE_API int sdae_dae_model_alloc(sdae_dae_model **d, const sdae_dae *dae, size_t n_xi,
                                  sdae_mu_dot_fn mu_dot, const double *x_guess);
/* As sdae_dae_model_alloc, the block from the allocator a (NULL: malloc). */
SDAE_API int sdae_dae_model_alloc_with(sdae_dae_model **d, const sdae_dae *dae, size_t n_xi,
                                       sdae_mu_dot_fn mu_dot, const double *x_guess,
                                       const sdae_allocator *a);
/* as sdae_stepper_free: NULL and init'ed ones are fine */
SDAE_API void sdae_dae_model_free(sdae_dae_model *d);

/* The model to hand to sdae_stepper_alloc or sdae_check_model: n_xi, n_mu, q0 and Q_apply, with
 * n_constraints = 0 (set them in a copy for the baselines). Valid as long as d is. */
SDAE_API const sdae_model *sdae_dae_model_get(const sdae_dae_model *d);

/* The status behind the last failing callback of the derived model (a model callback can only
 * say recoverable or fatal): SDAE_ERR_PHI_INV when Phi^-1's Newton did not converge, or the
 * status of the DAE's own callback; SDAE_OK when none failed. */
SDAE_API int sdae_dae_model_status(const sdae_dae_model *d);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_DAE_H */
