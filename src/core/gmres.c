/* SPDX-License-Identifier: GPL-3.0-or-later */
/* GMRES from x = 0 (core/gmres.h): Saad, Iterative Methods for Sparse Linear Systems, 2nd ed.,
 * Algorithm 9.6 (flexible GMRES), the rotations of Section 6.5.3. */
#include <math.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "gmres.h"

void sdae__gmres_carve(sdae_gmres *g, size_t n, size_t m, sdae_arena *a) {
  g->n = n, g->m = m;
  g->V = sdae__take(a, m + 1, n);
  g->Z = sdae__take(a, m, n);
  g->H = sdae__take(a, m + 1, m);
  g->cs = sdae__take(a, m, 1), g->sn = sdae__take(a, m, 1);
  g->g = sdae__take(a, m + 1, 1), g->y = sdae__take(a, m, 1);
  g->iters = 0;
}

static double dot(const double *a, const double *b, size_t n) {
  double s = 0.0;
  for (size_t i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* w -= (v_i . w) v_i for the basis so far (modified Gram-Schmidt), into column j of H */
static double orthogonalize(sdae_gmres *g, size_t j, double *w) {
  size_t n = g->n, m = g->m;
  for (size_t i = 0; i <= j; i++) {
    const double *v = g->V + i * n;
    double h = dot(v, w, n);
    for (size_t k = 0; k < n; k++) w[k] -= h * v[k];
    g->H[i * m + j] = h;
  }
  return sqrt(dot(w, w, n));
}

/* the earlier rotations applied to column j, then the one that zeroes H[j + 1][j] */
static void rotate(sdae_gmres *g, size_t j) {
  size_t m = g->m;
  double *H = g->H, a, b, r;
  for (size_t i = 0; i < j; i++) {
    a = H[i * m + j], b = H[(i + 1) * m + j];
    H[i * m + j] = g->cs[i] * a + g->sn[i] * b;
    H[(i + 1) * m + j] = -g->sn[i] * a + g->cs[i] * b;
  }
  a = H[j * m + j], b = H[(j + 1) * m + j];
  r = hypot(a, b);
  /* a zero column (A z_j in the space so far): the rotation that leaves the residual where it
   * was, not one that would report it solved */
  g->cs[j] = r > 0.0 ? a / r : 0.0, g->sn[j] = r > 0.0 ? b / r : 1.0;
  H[j * m + j] = r, H[(j + 1) * m + j] = 0.0;
  g->g[j + 1] = -g->sn[j] * g->g[j];
  g->g[j] = g->cs[j] * g->g[j];
}

/* x = Z y, y from the triangular k x k system H y = g */
static void combine(sdae_gmres *g, size_t k, double *x) {
  size_t n = g->n, m = g->m;
  for (size_t i = k; i-- > 0;) {
    double s = g->g[i];
    for (size_t l = i + 1; l < k; l++) s -= g->H[i * m + l] * g->y[l];
    g->y[i] = g->H[i * m + i] != 0.0 ? s / g->H[i * m + i] : 0.0;
  }
  memset(x, 0, n * sizeof *x);
  for (size_t i = 0; i < k; i++)
    for (size_t l = 0; l < n; l++) x[l] += g->y[i] * g->Z[i * n + l];
}

int sdae__gmres_solve(sdae_gmres *g, const sdae_gmres_ops *ops, const double *b, double *x,
                      double rtol) {
  size_t n = g->n, k = 0;
  double beta = sqrt(dot(b, b, n));
  int rc = SDAE_OK;
  g->iters = 0;
  g->reached = 1;
  memset(x, 0, n * sizeof *x);
  if (beta == 0.0) return SDAE_OK;
  for (size_t l = 0; l < n; l++) g->V[l] = b[l] / beta;
  g->g[0] = beta;
  while (k < g->m) {
    double *z = g->Z + k * n, *w = g->V + (k + 1) * n, h;
    if ((rc = ops->precond(ops->ctx, g->V + k * n, z)) != SDAE_OK ||
        (rc = ops->apply(ops->ctx, z, w)) != SDAE_OK)
      break;
    h = orthogonalize(g, k, w);
    g->H[(k + 1) * g->m + k] = h;
    rotate(g, k);
    k++;
    /* h = 0: the Krylov space is invariant under A, no further step can do better */
    if (fabs(g->g[k]) <= rtol * beta || h == 0.0) break;
    for (size_t l = 0; l < n; l++) w[l] /= h;
  }
  g->iters = (unsigned)k;
  g->reached = fabs(g->g[k]) <= rtol * beta;
  if (rc == SDAE_OK) combine(g, k, x);
  return rc;
}
