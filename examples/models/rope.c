/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A rope of N point masses on rods, open or closed, dense or with patterns (rope.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rope.h"

size_t mech_rope_constraints(const mech_rope *p) { return p->N + (p->closed ? 1 : 0); }

/* Row j of G(x) (or of Gdot(v), anchor 0): link j joins mass j - 1 (none for j = 0) to mass j,
 * the closing link (j = N) mass N - 1 to the anchor; d = x_j - x_{j-1} (x_{-1} = 0, and x_N the
 * anchor). Its entries, columns ascending, into cols and vals; their count. */
static size_t row(const mech_rope *p, size_t j, const double *x, double anchor, size_t *cols,
                  double *vals) {
  size_t n = 0, a = j == p->N ? p->N - 1 : j; /* the mass of the link's far end from the anchor */
  double dx, dy;
  if (j == p->N) {
    dx = x[2 * a] - anchor, dy = x[2 * a + 1];
  } else {
    dx = x[2 * j] - (j > 0 ? x[2 * j - 2] : 0.0), dy = x[2 * j + 1] - (j > 0 ? x[2 * j - 1] : 0.0);
  }
  if (j > 0 && j < p->N) {
    cols[n] = 2 * j - 2, vals[n++] = -dx;
    cols[n] = 2 * j - 1, vals[n++] = -dy;
  }
  cols[n] = 2 * a, vals[n++] = dx;
  cols[n] = 2 * a + 1, vals[n++] = dy;
  return n;
}

/* G (anchor p->anchor_x) or Gdot (anchor 0) as p gives it: nonzeros in pattern order, or dense */
static void rows(const mech_rope *p, const double *x, double anchor, double *out) {
  size_t n_c = mech_rope_constraints(p), n_q = 2 * p->N, cols[4], k = 0;
  double vals[4];
  if (!p->sparse) memset(out, 0, n_c * n_q * sizeof *out);
  for (size_t j = 0; j < n_c; j++) {
    size_t n = row(p, j, x, anchor, cols, vals);
    for (size_t i = 0; i < n; i++)
      if (p->sparse)
        out[k++] = vals[i];
      else
        out[j * n_q + cols[i]] = vals[i];
  }
}

static int rope_mass(double t, const double *q, double *M, void *params) {
  const mech_rope *p = params;
  size_t n_q = 2 * p->N;
  (void)t, (void)q;
  if (!p->sparse) memset(M, 0, n_q * n_q * sizeof *M);
  for (size_t i = 0; i < n_q; i++) M[p->sparse ? i : i * n_q + i] = p->m;
  return 0;
}

static int rope_force(double t, const double *q, const double *v, double *F, void *params) {
  const mech_rope *p = params;
  (void)t, (void)q, (void)v;
  for (size_t i = 0; i < p->N; i++) F[2 * i] = 0.0, F[2 * i + 1] = -p->m * p->ga;
  return 0;
}

static int rope_constraint(double t, const double *q, double *c, void *params) {
  const mech_rope *p = params;
  size_t cols[4];
  double vals[4];
  (void)t;
  for (size_t j = 0; j < mech_rope_constraints(p); j++) {
    size_t n = row(p, j, q, p->anchor_x, cols, vals);
    double dx = vals[n - 2], dy = vals[n - 1]; /* the far end's entries are d itself */
    c[j] = 0.5 * (dx * dx + dy * dy - p->L * p->L);
  }
  return 0;
}

static int rope_jacobian(double t, const double *q, double *G, void *params) {
  const mech_rope *p = params;
  (void)t;
  rows(p, q, p->anchor_x, G);
  return 0;
}

static int rope_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                             void *params) {
  const mech_rope *p = params;
  (void)t, (void)q;
  rows(p, v, 0.0, Gdot);
  return 0;
}

static int rope_zero_c(double t, const double *q, double *ct, void *params) {
  (void)t, (void)q;
  memset(ct, 0, mech_rope_constraints(params) * sizeof *ct);
  return 0;
}

static int rope_zero_c_along(double t, const double *q, const double *v, double *out,
                             void *params) {
  (void)v;
  return rope_zero_c(t, q, out, params);
}

static int rope_mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  const mech_rope *p = params;
  (void)t, (void)q, (void)v;
  memset(out, 0, 2 * p->N * sizeof *out);
  return 0;
}

static int rope_potential(double t, const double *q, double *V, void *params) {
  const mech_rope *p = params;
  double y = 0.0;
  (void)t;
  for (size_t i = 0; i < p->N; i++) y += q[2 * i + 1];
  *V = p->m * p->ga * y;
  return 0;
}

/* the patterns: M diagonal, G's rows as row() writes them */
static int patterns(mech_rope *p) {
  size_t n_q = 2 * p->N, n_c = mech_rope_constraints(p), cols[4], k = 0;
  size_t *a = malloc((2 * (n_q + 1) + (n_c + 1) + 4 * n_c) * sizeof *a);
  double vals[4], *zero = calloc(n_q, sizeof *zero);
  size_t *m_start = a, *m_col = a + n_q + 1, *g_start = m_col + n_q, *g_col = g_start + n_c + 1;
  if (!a || !zero) {
    free(a), free(zero);
    return -1;
  }
  for (size_t i = 0; i <= n_q; i++) m_start[i] = i;
  for (size_t i = 0; i < n_q; i++) m_col[i] = i;
  g_start[0] = 0;
  for (size_t j = 0; j < n_c; j++) {
    size_t n = row(p, j, zero, 0.0, cols, vals);
    memcpy(g_col + k, cols, n * sizeof *cols);
    g_start[j + 1] = k += n;
  }
  free(zero);
  p->arrays = a;
  p->mass_pattern = (sdae_pattern){n_q, m_start, m_col};
  p->jacobian_pattern = (sdae_pattern){k, g_start, g_col};
  return 0;
}

mech_rope mech_rope_unit(size_t N, int closed, int sparse) {
  return (mech_rope){.N = N,
                     .L = 1.0,
                     .m = 1.0,
                     .ga = 9.81,
                     .anchor_x = 0.5 * (double)(N + 1),
                     .closed = closed,
                     .sparse = sparse};
}

int mech_rope_system(sdae_mbs *sys, mech_rope *p) {
  p->arrays = NULL;
  if (p->sparse && patterns(p) != 0) return -1;
  *sys = (sdae_mbs){.n_q = 2 * p->N,
                    .n_c = mech_rope_constraints(p),
                    .mass = rope_mass,
                    .force = rope_force,
                    .constraint = rope_constraint,
                    .jacobian = rope_jacobian,
                    .constraint_t = rope_zero_c,
                    .potential = rope_potential,
                    .params = p,
                    .mass_dot_v = rope_mass_dot_v,
                    .jacobian_dot = rope_jacobian_dot,
                    .constraint_t_dot = rope_zero_c_along,
                    .mass_pattern = p->sparse ? &p->mass_pattern : NULL,
                    .jacobian_pattern = p->sparse ? &p->jacobian_pattern : NULL};
  return 0;
}

void mech_rope_free(mech_rope *p) {
  free(p->arrays);
  p->arrays = NULL;
}

int mech_rope_start(const mech_rope *p, double a, double *q, double *v) {
  size_t N = p->N, k = (N + 1) / 2;
  double ca = cos(a), sa = sin(a);
  if (p->closed) {
    if (N % 2 == 0 || !(p->anchor_x > 0.0 && p->anchor_x < (double)(N + 1) * p->L)) return -1;
    ca = p->anchor_x / ((double)(N + 1) * p->L), sa = sqrt(1.0 - ca * ca);
  }
  for (size_t j = 1; j <= N; j++) {
    double down = (double)(!p->closed || j <= k ? j : 2 * k - j);
    q[2 * j - 2] = (double)j * p->L * ca;
    q[2 * j - 1] = -down * p->L * sa;
  }
  memset(v, 0, 2 * N * sizeof *v);
  return 0;
}
