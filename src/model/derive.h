/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The front-ends' common rule (Proposition 1 done numerically): from the mu-dynamics
 * G(t, xi, mu) of a DAE, q0(t, mu) = G(t, 0, mu) and the columns q_i of Q by telescoping divided
 * differences (<stabdae/dae.h>). Used by the generic front-end (dae_model.c) and the mechanical
 * one (mbs_model.c), which differ only in how they evaluate G. */
#ifndef STABDAE_SRC_MODEL_DERIVE_H
#define STABDAE_SRC_MODEL_DERIVE_H

#include <stddef.h>

#include "core/arena.h"
#include "core/callback.h"

/* G(t, xi, mu) into out (n_mu values): an sdae_status */
typedef int (*sdae__rate_fn)(void *ctx, double t, const double *xi, const double *mu, double *out);

typedef struct sdae_derive {
  size_t n_xi, n_mu;
  sdae__rate_fn rate;
  void *ctx;
  double *xi_b;         /* n_xi: the point xi^(i) of the telescoping sum */
  double *G0, *Gb, *Gn; /* n_mu each: G(0, mu), G at xi^(i-1), G at xi^(i) */
  double *q;            /* n_mu: one column q_i */
  double *key_mu;       /* n_mu: the (t, mu) where G0 was evaluated */
  double key_t;
  int have_G0;
  /* optional (NULL: every column evaluated): n_xi floors set by the front-end; a |xi_i| at or
   * below floor_i is rounding, its column not evaluated (q_i taken as 0, the term q_i xi_i
   * dropped: the gain k_i = -epsilon) */
  const double *floor;
} sdae_derive;

/* its arrays (counted, or handed out), wired to the rate G */
void sdae__derive_carve(sdae_derive *d, size_t n_xi, size_t n_mu, sdae__rate_fn rate, void *ctx,
                        sdae_arena *a);
/* forgets the G(0, mu) kept from the last call: after anything that changes G (a chart) */
void sdae__derive_forget(sdae_derive *d);
/* q0(t, mu) = G(t, 0, mu) */
int sdae__derive_q0(sdae_derive *d, double t, const double *mu, double *out);
/* Q(t, xi, mu) xi and the squared column norms ||q_i||^2, as the model's Q_apply; no evaluation
 * at all when every xi_i is at its floor */
int sdae__derive_Q_apply(sdae_derive *d, double t, const double *xi, const double *mu, double *Qxi,
                         double *qnorm2);

#endif /* STABDAE_SRC_MODEL_DERIVE_H */
