/* stabdae model: the stabilized normal form (paper eq. 5) given as callbacks. */
#ifndef STABDAE_MODEL_H
#define STABDAE_MODEL_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdae_model {
  size_t n_xi, n_mu; /* p = dim xi, n - p = dim mu */
  /* q0(mu): the constrained dynamics (eq. 9), n_mu values */
  int (*q0)(double t, const double *mu, double *out, void *params);
  /* Q(xi, mu): n_mu x n_xi, row-major; column i is q_i */
  int (*Q)(double t, const double *xi, const double *mu, double *out, void *params);
  /* instead of Q, for large models: the product Q(xi, mu) xi (n_mu values) and the squared
   * column norms ||q_i||^2 (n_xi values, the gains' input) in one call; used when Q is NULL */
  int (*Q_apply)(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                 void *params);
  /* optional, for large models: 0 (dense), or b > 0 when d phi/d mu+ has at most b sub- and b
   * super-diagonals (true of the midpoint and discrete-gradient maps when q0, S and grad H
   * couple mu_i only to mu_j with |i - j| <= b). Newton then factors a band, O(n b^2), and
   * builds its matrix from 2 (2b + 1) evaluations of phi whatever n; analytic Jacobians
   * (q0_jac, user_phi_jac) are dense and are not used then. */
  size_t bandwidth;
  /* optional: dq0/dmu, n_mu x n_mu row-major (midpoint Newton); finite differences otherwise */
  int (*q0_jac)(double t, const double *mu, double *out, void *params);
  /* optional, needed by the baselines: the constraints and the relative degree of each; xi
   * holds (h_c, L_f h_c, ..., L_f^{r_c - 1} h_c) for c = 1..n_constraints, one after another */
  size_t n_constraints;
  const unsigned *rel_degree;
  void *params; /* passed to every callback, the options' ones included */
} sdae_model;

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_MODEL_H */
