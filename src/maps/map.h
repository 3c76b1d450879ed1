/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The map interface: what a map type (one file, map_*.c) implements and what it receives.
 * A map sees the model, its own scratch and a Newton solver, never the stepper; it writes only
 * its output and its scratch. Data flows one way: model -> map -> stepper, Newton below them all.
 */
#ifndef STABDAE_SRC_MAPS_MAP_H
#define STABDAE_SRC_MAPS_MAP_H

#include <stabdae/stabdae.h>

#include "core/newton.h"

/* What a map is handed at every call. */
typedef struct sdae_map_ctx {
  const sdae_model *model;
  double *work;            /* the map's scratch: scratch(model, options) doubles */
  sdae_newton *newton;     /* the solver a composed map solves its stages with */
  unsigned long phi_evals; /* every evaluation of phi, counted by sdae__map_phi alone */
  double *mid; /* n_mu where the model solves (sdae__map_model_solves): Newton's midpoint */
} sdae_map_ctx;

typedef int (*sdae_map_fn)(sdae_map_ctx *c, double t, double T, const double *mu,
                           const double *mu_next, double *out);

struct sdae_map_type {
  const char *name;
  unsigned order; /* of accuracy as T -> 0; 0: the user's map decides */
  int implicit;   /* phi depends on mu+: the step solves for mu+ by Newton */
  /* phi evaluates the model's energy H (a discrete gradient): what it conserves is H at a fixed
   * t, so a front-end whose H would depend on t must refuse it */
  int uses_H;
  /* optional (NULL: nothing beyond q0 and Q): SDAE_OK when the model gives every callback the
   * map needs, SDAE_ERR_MAP otherwise */
  int (*needs)(const sdae_model *m);
  /* optional (NULL: none): doubles of scratch the map needs */
  size_t (*scratch)(const sdae_model *m, const sdae_options *o);
  /* optional (NULL: nothing kept): called at the start of every step, forgets what the map
   * keeps of the model's values within a step (the model may change between steps) */
  void (*begin)(sdae_map_ctx *c);
  /* phi_T(mu, mu+): n_mu values into out, which is the caller's */
  sdae_map_fn phi;
  /* optional: d phi_T / d mu+ (n_mu x n_mu), used by a dense Newton when jac_given (or, without
   * jac_given, always). Newton calls it right after phi at the same arguments (as IDA hands its
   * Jacobian the residual just computed), so it may reuse what phi left in the scratch. */
  sdae_map_fn jac;
  int (*jac_given)(const sdae_model *m);
  /* d phi_T / d mu+ is about slope times dq0/dmu at the midpoint (mu + mu+)/2, t + T/2 (0: not
   * so): a model's own linear solve (q0_lsetup) then serves its Newton */
  double slope;
  /* a composed map: the symmetric stages base_{gamma_s T} o ... o base_{gamma_1 T} */
  const sdae_map_type *base;
  const double *gamma;
  size_t stages;
};

/* the discrete gradient's and the midpoint map's tables, the bases of the composed maps
 * (map_compose.c) */
extern const sdae_map_type sdae__dgrad_type;
extern const sdae_map_type sdae__midpoint_type;

/* The one door to a map's phi: evaluates and counts. */
static inline int sdae__map_phi(const sdae_map_type *map, sdae_map_ctx *c, double t, double T,
                                const double *mu, const double *mu_next, double *out) {
  c->phi_evals++;
  return map->phi(c, t, T, mu, mu_next, out);
}

/* the map's Newton solves need a Newton workspace (implicit maps and compositions of them) */
static inline int sdae__map_uses_newton(const sdae_map_type *map) {
  return map->implicit || (map->base && map->base->implicit);
}

/* the map evaluates H: its own property, or its base's for a composed map */
static inline int sdae__map_uses_H(const sdae_map_type *map) {
  return map->uses_H || (map->base && map->base->uses_H);
}

/* the map's Newton solves an equation whose matrix a model's q0_lsetup approximates: an implicit
 * map, or a composition of one, with a slope */
static inline int sdae__map_slope_known(const sdae_map_type *map) {
  const sdae_map_type *solved = map->base ? map->base : map;
  return solved->implicit && solved->slope > 0.0;
}

/* the map's Newton solves with the model's q0_lsetup and q0_lsolve (no matrix of its own) */
static inline int sdae__map_model_solves(const sdae_map_type *map, const sdae_model *m) {
  return m->q0_lsetup && sdae__map_slope_known(map);
}

/* Newton on a step's or a stage's equation y = x + h (phi_T(x, y) + shift) (shift may be NULL),
 * from y (map_solve.c): the model's linear solve where it gives one for the map, else the map's
 * own Jacobian when it has one for this model and Newton is dense, differences otherwise */
int sdae__map_solve(const sdae_map_type *map, sdae_map_ctx *c, double t, double h, const double *x,
                    const double *shift, double *y);

#endif /* STABDAE_SRC_MAPS_MAP_H */
