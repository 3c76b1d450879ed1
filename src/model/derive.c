/* SPDX-License-Identifier: GPL-3.0-or-later */
/* q0 and Q from the mu-dynamics G by telescoping divided differences (<stabdae/dae.h>):
 *
 *   q0(mu) = G(0, mu),   q_i = (G(xi^(i)) - G(xi^(i-1))) / xi_i,   sum_i q_i xi_i = G(xi) - G(0).
 *
 * A tiny |xi_i| (below sqrt(eps), at rounding on the manifold) would divide rounding noise by
 * itself: its column is then the difference quotient over sqrt(eps) from xi^(i-1) (a derivative
 * good to about sqrt(eps), all the gains need), and xi^(i) is taken as xi^(i-1). The product
 * Q xi is then off by at most about sqrt(eps) |xi_i| |d2G|, below rounding.
 *
 * A front-end that knows the rounding of each xi_i (the mechanical one: |c_j| against the size
 * of c's terms) sets floors: a |xi_i| at or below its floor is rounding, and its column is not
 * evaluated at all. Its term q_i xi_i is a rounding-level term and is dropped, its gain is the
 * paper's with q_i taken as 0, k_i = -epsilon, under which xi_i still contracts (by
 * 1 / (1 + T epsilon) per step with scheme 15); xi^(i) is xi^(i-1) as for a tiny xi_i. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "derive.h"

void sdae__derive_carve(sdae_derive *d, size_t n_xi, size_t n_mu, sdae__rate_fn rate, void *ctx,
                        sdae_arena *a) {
  d->n_xi = n_xi;
  d->n_mu = n_mu;
  d->rate = rate;
  d->ctx = ctx;
  d->xi_b = sdae__take(a, n_xi, 1);
  d->G0 = sdae__take(a, n_mu, 1);
  d->Gb = sdae__take(a, n_mu, 1);
  d->Gn = sdae__take(a, n_mu, 1);
  d->q = sdae__take(a, n_mu, 1);
  d->key_mu = sdae__take(a, n_mu, 1);
  d->have_G0 = 0;
  d->floor = NULL;
}

void sdae__derive_forget(sdae_derive *d) { d->have_G0 = 0; }

/* G(t, 0, mu), kept for the next call at the same (t, mu): the map asks for q0 and the stepper
 * for Q at the same point */
static int G_at_zero(sdae_derive *d, double t, const double *mu) {
  int rc;
  if (d->have_G0 && d->key_t == t && memcmp(d->key_mu, mu, d->n_mu * sizeof *mu) == 0)
    return SDAE_OK;
  d->have_G0 = 0;
  memset(d->xi_b, 0, d->n_xi * sizeof *d->xi_b);
  if ((rc = d->rate(d->ctx, t, d->xi_b, mu, d->G0)) != SDAE_OK) return rc;
  memcpy(d->key_mu, mu, d->n_mu * sizeof *mu);
  d->key_t = t;
  d->have_G0 = 1;
  return SDAE_OK;
}

int sdae__derive_q0(sdae_derive *d, double t, const double *mu, double *out) {
  int rc = G_at_zero(d, t, mu);
  if (rc == SDAE_OK) memcpy(out, d->G0, d->n_mu * sizeof *out);
  return rc;
}

/* column i into d->q and its squared norm; moves the base to xi^(i) unless xi_i is tiny */
static int column(sdae_derive *d, double t, const double *xi, const double *mu, size_t i,
                  double *qnorm2) {
  const double tiny = sqrt(DBL_EPSILON);
  int small = !(fabs(xi[i]) >= tiny);
  double h = small ? copysign(tiny, xi[i]) : xi[i], norm2 = 0.0;
  int rc;
  d->xi_b[i] = h;
  if ((rc = d->rate(d->ctx, t, d->xi_b, mu, d->Gn)) != SDAE_OK) return rc;
  for (size_t r = 0; r < d->n_mu; r++) {
    d->q[r] = (d->Gn[r] - d->Gb[r]) / h;
    norm2 += d->q[r] * d->q[r];
  }
  qnorm2[i] = norm2;
  if (small) {
    d->xi_b[i] = 0.0;
  } else {
    double *swap = d->Gb;
    d->Gb = d->Gn;
    d->Gn = swap;
  }
  return SDAE_OK;
}

/* xi_i is rounding by the front-end's floor: its column is not wanted */
static int at_floor(const sdae_derive *d, const double *xi, size_t i) {
  return d->floor && fabs(xi[i]) <= d->floor[i];
}

int sdae__derive_Q_apply(sdae_derive *d, double t, const double *xi, const double *mu, double *Qxi,
                         double *qnorm2) {
  size_t first = 0;
  int rc;
  while (first < d->n_xi && at_floor(d, xi, first)) first++;
  if (first < d->n_xi) { /* G(0, mu), the telescoping sum's start, when a column is wanted */
    if ((rc = G_at_zero(d, t, mu)) != SDAE_OK) return rc;
    memcpy(d->Gb, d->G0, d->n_mu * sizeof *d->Gb);
    memset(d->xi_b, 0, d->n_xi * sizeof *d->xi_b);
  }
  memset(Qxi, 0, d->n_mu * sizeof *Qxi);
  for (size_t i = 0; i < d->n_xi; i++) {
    if (at_floor(d, xi, i)) { /* q_i taken as 0: the paper's gain is -epsilon */
      qnorm2[i] = 0.0;
      continue;
    }
    if ((rc = column(d, t, xi, mu, i, qnorm2)) != SDAE_OK) return rc;
    if (d->xi_b[i] == 0.0) /* a tiny xi_i: its term q_i xi_i, outside the telescoping sum */
      for (size_t r = 0; r < d->n_mu; r++) Qxi[r] += d->q[r] * xi[i];
  }
  if (first < d->n_xi)
    for (size_t r = 0; r < d->n_mu; r++) Qxi[r] += d->Gb[r] - d->G0[r];
  return SDAE_OK;
}
