/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae model (layer: model): the whole problem, the stabilized normal form (paper eq. 5) given
 * as callbacks, with the energy structure its discrete gradients use and an optional user map. How
 * it is solved (scheme, gains, map, Newton) is in sdae_options. */
#ifndef STABDAE_MODEL_H
#define STABDAE_MODEL_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Highest relative degree of one constraint the baselines (none, Baumgarte) accept. */
#define SDAE_MAX_REL_DEGREE 4

/* Every callback returns 0 on success, > 0 for a recoverable failure and < 0 for a fatal one
 * (the SUNDIALS rule), and receives the model's params. Matrices are row-major flat arrays. */
typedef struct sdae_model {
  size_t n_xi, n_mu; /* p = dim xi, n - p = dim mu */
  /* q0(mu): the constrained dynamics (eq. 9), n_mu values */
  int (*q0)(double t, const double *mu, double *out, void *params);
  /* Q(xi, mu): n_mu x n_xi; column i is q_i */
  int (*Q)(double t, const double *xi, const double *mu, double *out, void *params);
  /* instead of Q, for large models: the product Q(xi, mu) xi (n_mu values) and the squared
   * column norms ||q_i||^2 (n_xi values, the gains' input) in one call; used when Q is NULL */
  int (*Q_apply)(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                 void *params);
  /* optional: dq0/dmu, n_mu x n_mu (the midpoint map's Newton); finite differences otherwise */
  int (*q0_jac)(double t, const double *mu, double *out, void *params);
  /* optional, for large models, both or neither: the linear solve of the implicit maps' Newton
   * (midpoint, dgrad and their compositions), as CVODE's preconditioner setup and solve.
   * q0_lsetup factors an approximation A of I - a dq0/dmu at (t, mu) (a > 0), q0_lsolve writes
   * z = A^-1 r (n_mu values); no n_mu x n_mu matrix is formed or kept. Newton is then a chord,
   * converging at the rate of what A leaves out of the exact matrix; the factors serve within a
   * step and are set up anew at its first solve. The user's map keeps a dense Newton. */
  int (*q0_lsetup)(double t, const double *mu, double a, void *params);
  int (*q0_lsolve)(const double *r, double *z, void *params);

  /* The energy structure q0 = S(mu) grad H(mu), for the discrete-gradient maps (sdae_map_dgrad,
   * sdae_map_dg4, sdae_map_dg6): H conserved when S is skew, dissipated when S = J - R, R >= 0 */
  int (*H)(double t, const double *mu, double *out, void *params);      /* 1 value */
  int (*grad_H)(double t, const double *mu, double *out, void *params); /* n_mu values */
  int (*S)(double t, const double *mu, double *out, void *params);      /* n_mu x n_mu */
  /* instead of S, for large models: out = S(mu) v (n_mu values) */
  int (*S_apply)(double t, const double *mu, const double *v, double *out, void *params);
  /* optional, n_mu x n_mu: the Hessian of H gives Newton the map's Jacobian in closed form
   * instead of finite differences (dense Newton; exact when S is constant, otherwise the
   * derivative of S is left out and Newton converges linearly) */
  int (*hess_H)(double t, const double *mu, double *out, void *params);

  /* A map of the user's own, for sdae_map_user: phi(T, mu, mu+) -> q0 as T -> 0 (eq. 13), and
   * optionally d phi / d mu+ (n_mu x n_mu) */
  int (*user_phi)(double t, double T, const double *mu, const double *mu_next, double *out,
                  void *params);
  int (*user_phi_jac)(double t, double T, const double *mu, const double *mu_next, double *out,
                      void *params);

  /* optional, needed by the baselines: the constraints and the relative degree of each; xi
   * holds (h_c, L_f h_c, ..., L_f^{r_c - 1} h_c) for c = 1..n_constraints, one after another */
  size_t n_constraints;
  const unsigned *rel_degree;
  void *params; /* passed to every callback */

  /* optional, with the energy structure: a port's input B u (n_mu values), forces from outside
   * the energy (actuators, control inputs), q0 = S grad H + B u, q0 including it. Read by the
   * discrete gradients alone (every other map reads q0), which take it at the midpoint m,
   * phi = S(m) gradbar H + B u(m), and so keep the discrete power balance H(mu+) - H(mu) =
   * T gradbar^T S(m) gradbar + T gradbar^T B u(m) (on the manifold: T gradbar^T Q xi more off
   * it) */
  int (*input)(double t, const double *mu, double *out, void *params);
} sdae_model;

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_MODEL_H */
