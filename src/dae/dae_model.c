/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The generic front-end (<stabdae/dae.h>): a DAE and its coordinates Phi made into the model of
 * the normal form (eq. 5), with
 *
 *   G(t, xi, mu) = mu_dot(t, Phi^-1(t, xi, mu)),   q0 and Q xi from G by derive.c's rule.
 *
 * One block holds the object and its arrays; Phi^-1's Newton starts from the last point it
 * found, so a step's calls (nearby points) take a few iterations each. */
#include <stdalign.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <stabdae/dae.h>

#include "coords.h"
#include "core/alloc.h"
#include "core/arena.h"
#include "core/callback.h"
#include "model/derive.h"

struct sdae_dae_model {
  sdae_model model; /* what sdae_dae_model_get hands out; params = this object */
  sdae_dae dae;     /* the caller's, copied */
  sdae_mu_dot_fn mu_dot;
  int status;       /* behind the last failing callback */
  int have_x;       /* x_last holds a start for Newton (x_guess, or a point found) */
  sdae_block block; /* what sdae_dae_model_alloc_with allocated */
  sdae_coords coords;
  sdae_derive derive;
  double *z, *x, *x_last; /* n each: (xi, mu), Newton's iterate, the last point found */
  double *Qxi, *qnorm2;   /* n_mu, n_xi: Q_apply's results before they are handed out */
};

/* x = Phi^-1(t, z) from the last point found (or z), kept on success */
static int inverse(sdae_dae_model *d, double t) {
  size_t n = d->dae.n;
  memcpy(d->x, d->have_x ? d->x_last : d->z, n * sizeof *d->x);
  int rc = sdae__coords_invert(&d->coords, t, d->z, d->x);
  if (rc == SDAE_ERR_NEWTON || rc == SDAE_ERR_SINGULAR) return SDAE_ERR_PHI_INV;
  if (rc != SDAE_OK) return rc;
  memcpy(d->x_last, d->x, n * sizeof *d->x);
  d->have_x = 1;
  return SDAE_OK;
}

/* G(t, xi, mu): derive.c's rate */
static int rate(void *ctx, double t, const double *xi, const double *mu, double *out) {
  sdae_dae_model *d = ctx;
  size_t n_xi = d->model.n_xi, n_mu = d->model.n_mu;
  memcpy(d->z, xi, n_xi * sizeof *xi);
  memcpy(d->z + n_xi, mu, n_mu * sizeof *mu);
  int rc = inverse(d, t);
  if (rc != SDAE_OK) return rc;
  if (!d->mu_dot) return sdae__coords_mu_rate(&d->coords, t, d->x, out);
  return sdae__callback_checked(d->mu_dot(t, d->x, out, d->dae.params), out, n_mu);
}

/* the model callback's code for a status, which it keeps when it is a failure */
static int code(sdae_dae_model *d, int rc) {
  if (rc != SDAE_OK) d->status = rc;
  return sdae__callback_code(rc);
}

static int dm_q0(double t, const double *mu, double *out, void *params) {
  sdae_dae_model *d = params;
  return code(d, sdae__derive_q0(&d->derive, t, mu, out));
}

/* into the object's arrays first: a failure leaves Qxi and qnorm2 as they were */
static int dm_Q_apply(double t, const double *xi, const double *mu, double *Qxi, double *qnorm2,
                      void *params) {
  sdae_dae_model *d = params;
  int rc = sdae__derive_Q_apply(&d->derive, t, xi, mu, d->Qxi, d->qnorm2);
  if (rc == SDAE_OK) {
    memcpy(Qxi, d->Qxi, d->model.n_mu * sizeof *Qxi);
    memcpy(qnorm2, d->qnorm2, d->model.n_xi * sizeof *qnorm2);
  }
  return code(d, rc);
}

static int validate(const sdae_dae *dae, size_t n_xi) {
  if (!dae || !dae->f || !dae->g || !dae->Phi) return SDAE_ERR_NULL;
  if (n_xi == 0 || n_xi >= dae->n) return SDAE_ERR_DIM;
  return SDAE_OK;
}

/* ---- the block: the object, then its arrays ---- */

static void wire(sdae_dae_model *d, const sdae_dae *dae, size_t n_xi, sdae_mu_dot_fn mu_dot) {
  memset(d, 0, sizeof *d);
  d->dae = *dae;
  d->mu_dot = mu_dot;
  d->model.n_xi = n_xi;
  d->model.n_mu = dae->n - n_xi;
  d->model.q0 = dm_q0;
  d->model.Q_apply = dm_Q_apply;
  d->model.params = d;
}

static void carve(sdae_dae_model *d, sdae_arena *a) {
  size_t n = d->dae.n, n_xi = d->model.n_xi, n_mu = d->model.n_mu;
  sdae__coords_carve(&d->coords, &d->dae, n_xi, a);
  sdae__derive_carve(&d->derive, n_xi, n_mu, rate, d, a);
  d->z = sdae__take(a, n, 1), d->x = sdae__take(a, n, 1), d->x_last = sdae__take(a, n, 1);
  d->Qxi = sdae__take(a, n_mu, 1), d->qnorm2 = sdae__take(a, n_xi, 1);
}

typedef struct args {
  const sdae_dae *dae;
  size_t n_xi;
  sdae_mu_dot_fn mu_dot;
  const double *x_guess;
} args;

/* bytes for the block, with room to align a caller's */
static int measure(const void *p, const sdae_scratch *scratch, size_t *bytes) {
  (void)scratch; /* the sizes follow from the dimensions */
  const args *g = p;
  sdae_dae_model probe;
  sdae_arena a = {0};
  int rc = validate(g->dae, g->n_xi);
  if (rc != SDAE_OK) return rc;
  wire(&probe, g->dae, g->n_xi, NULL);
  carve(&probe, &a);
  return sdae__block_bytes(&a, sizeof(sdae_dae_model), bytes);
}

static int build(void *mem, const void *p, void **obj, sdae_block **block) {
  const args *g = p;
  sdae_arena a;
  sdae_dae_model *d = sdae__block_start(mem, sizeof(sdae_dae_model), &a);
  wire(d, g->dae, g->n_xi, g->mu_dot);
  carve(d, &a);
  if (g->x_guess) {
    memcpy(d->x_last, g->x_guess, g->dae->n * sizeof *g->x_guess);
    d->have_x = 1;
  }
  *obj = d, *block = &d->block;
  return SDAE_OK;
}

static const sdae_block_type dae_model_block = {measure, build};

size_t sdae_dae_model_size(const sdae_dae *dae, size_t n_xi) {
  const args g = {dae, n_xi, NULL, NULL};
  return sdae__block_size(&dae_model_block, &g, NULL);
}

int sdae_dae_model_init(sdae_dae_model **d, void *mem, size_t len, const sdae_dae *dae, size_t n_xi,
                        sdae_mu_dot_fn mu_dot, const double *x_guess) {
  const args g = {dae, n_xi, mu_dot, x_guess};
  void *obj;
  int rc;
  if (!d) return SDAE_ERR_NULL;
  if ((rc = sdae__block_init(&dae_model_block, &g, mem, len, &obj)) == SDAE_OK) *d = obj;
  return rc;
}

int sdae_dae_model_alloc_with(sdae_dae_model **d, const sdae_dae *dae, size_t n_xi,
                              sdae_mu_dot_fn mu_dot, const double *x_guess,
                              const sdae_allocator *a) {
  const args g = {dae, n_xi, mu_dot, x_guess};
  void *obj;
  int rc;
  if (!d) return SDAE_ERR_NULL;
  if ((rc = sdae__block_new(&dae_model_block, &g, a, &obj)) == SDAE_OK) *d = obj;
  return rc;
}

int sdae_dae_model_alloc(sdae_dae_model **d, const sdae_dae *dae, size_t n_xi,
                         sdae_mu_dot_fn mu_dot, const double *x_guess) {
  return sdae_dae_model_alloc_with(d, dae, n_xi, mu_dot, x_guess, NULL);
}

void sdae_dae_model_free(sdae_dae_model *d) {
  if (d) sdae__block_free(&d->block);
}

const sdae_model *sdae_dae_model_get(const sdae_dae_model *d) { return d ? &d->model : NULL; }

int sdae_dae_model_status(const sdae_dae_model *d) { return d ? d->status : SDAE_ERR_NULL; }
