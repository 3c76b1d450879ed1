/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae step-size certificates (layer: analysis): Theorem 3's and Theorem 5's bounds over a
 * box, and condition (18) measured along a trajectory. */
#ifndef STABDAE_CERTIFY_H
#define STABDAE_CERTIFY_H

#include <stddef.h>

#include <stabdae/base.h>
#include <stabdae/stepper.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sdae_certificate {
  double sup_neg_k;       /* max_i sup_B (-k_i(xi, mu)), eq. 14's denominator */
  size_t i_max;           /* the gain attaining it (the first one, on a tie) */
  double T_bar;           /* 2 / sup_neg_k: scheme 11 drives xi to 0 for T < T_bar (Theorem 3) */
  double T_thm5_scheme15; /* (sqrt(5) - 1)/4 T_bar (Theorem 5, scheme 15) */
  double T_thm5_scheme11; /* T_bar / 2 (Theorem 5, scheme 11) */
  size_t evaluations;     /* gain evaluations spent */
} sdae_certificate;

/* sup over the box lo <= (xi, mu) <= hi (n_xi + n_mu bounds each; lo = hi fixes a coordinate)
 * of -k_i for every i, by a grid of `grid` >= 2 points per free coordinate and a Nelder-Mead
 * refinement from the best grid points. sup_i (n_xi values) and argmax (n_xi rows of
 * n_xi + n_mu: where each sup is attained) may be NULL. The gains use the stepper's model,
 * delta and epsilon at time t. A reversed or non-finite bound is SDAE_ERR_PARAM. The search's
 * workspace comes from the stepper's allocator (sdae_stepper_alloc_with; malloc otherwise) and
 * is given back before the call returns; SDAE_ERR_NOMEM when there is none, and then *c, sup_i
 * and argmax are untouched (as on every failure). */
SDAE_API int sdae_certify_box(struct sdae_stepper *s, double t, const double *lo, const double *hi,
                              unsigned grid, double *sup_i, double *argmax, sdae_certificate *c);

/* Condition (18), (W(mu+) - W(mu))/T <= gamma W(mu), and the left side of (17), measured along
 * a trajectory by the observer sdae_cond18_observe (data: the sdae_cond18). */
typedef struct sdae_cond18 {
  size_t n_mu;
  int (*W)(double t, const double *mu, double *out, void *params);
  void *params;
  double *mu_prev; /* caller's storage, n_mu values */
  /* results */
  double gamma_min; /* max over steps of (W(mu+) - W(mu)) / (T W(mu)): (18) holds iff gamma >= it */
  double sup17;     /* max over steps of (mean_i (W(mu+) - W(mu)) / (mu_i+ - mu_i))^2 / W(mu) */
  size_t steps;     /* steps measured (W(mu) = 0 is skipped: the ratio is undefined there) */
  double worst_t;   /* the time at which gamma_min was attained (start of the step) */
  int status;       /* SDAE_OK, or the W callback's failure, which also stops the run */
  /* internal */
  double t_prev, W_prev;
  int have_prev;
} sdae_cond18;

SDAE_API int sdae_cond18_init(sdae_cond18 *c, size_t n_mu,
                              int (*W)(double t, const double *mu, double *out, void *params),
                              void *params, double *mu_prev);
SDAE_API int sdae_cond18_observe(size_t step, double t, const double *xi, const double *mu,
                                 void *cond18);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_CERTIFY_H */
