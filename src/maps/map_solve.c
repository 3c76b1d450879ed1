/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The implicit step of a map as a system for Newton (core/newton.h), in its implicit form
 * (phi_T its f, Newton forms R):
 *   R(y) = y - x - h (phi_T(x, y) + shift) = 0,   dR/dy = I - h dphi_T/dy
 *
 * (a step of eq. 11/15: x = mu, h = T, shift = Q(xi, mu) xi; a stage of a composed map: no
 * shift). */
#include <stddef.h>
#include <string.h>

#include "core/callback.h"
#include "map.h"

typedef struct step_eq {
  const sdae_map_type *map;
  sdae_map_ctx *c;
  double t, h;
  const double *x;
} step_eq;

/* f of R(y) = y - x - h (phi_T(x, y) + shift): phi_T(x, y) */
static int phi_of(void *ctx, const double *y, double *out) {
  const step_eq *e = ctx;
  return sdae__map_phi(e->map, e->c, e->t, e->h, e->x, y, out);
}

/* dphi_T/dy: dR/dy = I - h dphi_T/dy, formed by Newton (its coefficient h) */
static int jacobian(void *ctx, const double *y, double *J) {
  const step_eq *e = ctx;
  return e->map->jac(e->c, e->t, e->h, e->x, y, J);
}

/* the model's approximation of dR/dy = I - h slope dq0/dmu at the midpoint (maps/map.h) */
static int model_setup(void *ctx, const double *y) {
  const step_eq *e = ctx;
  const sdae_model *m = e->c->model;
  double *mid = e->c->mid;
  for (size_t i = 0; i < m->n_mu; i++) mid[i] = 0.5 * (e->x[i] + y[i]);
  return sdae__status_of_callback(
      m->q0_lsetup(e->t + 0.5 * e->h, mid, e->map->slope * e->h, m->params));
}

static int model_solve(void *ctx, const double *R, double *dy) {
  const sdae_model *m = ((const step_eq *)ctx)->c->model;
  return sdae__callback_checked(m->q0_lsolve(R, dy, m->params), dy, m->n_mu);
}

/* the map's own Jacobian, for a model it has one for */
static int analytic(const sdae_map_type *map, const sdae_model *m) {
  return map->jac && (!map->jac_given || map->jac_given(m));
}

/* A matrix by differences (2 n residuals dense, 2 (2 b + 1) banded) is kept across steps and
 * stages while it serves when the owner of Newton asks for it (keep; the coefficient h); the
 * map's own Jacobian costs one call and is rebuilt as Newton needs it (core/newton.h). */
int sdae__map_solve(const sdae_map_type *map, sdae_map_ctx *c, double t, double h, const double *x,
                    const double *shift, double *y) {
  step_eq e = {map, c, t, h, x};
  int own = analytic(map, c->model) && c->newton->J;
  sdae_newton_system sys = {
      .f = phi_of, .x = x, .shift = shift, .jacobian = own ? jacobian : NULL, .ctx = &e};
  if (sdae__map_model_solves(map, c->model)) sys.setup = model_setup, sys.solve = model_solve;
  int rc = sdae__newton_solve(c->newton, &sys, h, y);
  if (rc != SDAE_ERR_NEWTON) return rc;
  /* no root found from the predictor, even with a matrix built there: the same equation from
   * the step's start x (R(x) = -h (phi_T(x, x) + shift)), a matrix built there */
  memcpy(y, x, c->model->n_mu * sizeof *y);
  return sdae__newton_solve(c->newton, &sys, h, y);
}
