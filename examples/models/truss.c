/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Point masses on rods in the plane or in space (truss.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "truss.h"

static int is_rail(const mech_truss_link *l) { return l->a == l->b; }

/* the position of mass or anchor i (i >= n_masses: an anchor) in x */
static const double *at(const mech_truss *p, const double *x, size_t i) {
  return i < p->n_masses ? x + i * p->dim : p->anchors + (i - p->n_masses) * p->dim;
}

/* Link j's row of G at x (or of Gdot at velocities x, anchors still), columns ascending, into
 * cols and vals; its count. A rod's row holds d = p_a - p_b on a's coordinates and -d on b's. */
static size_t row(const mech_truss *p, size_t j, const double *x, int velocity, size_t *cols,
                  double *vals) {
  const mech_truss_link *l = &p->links[j];
  size_t dim = p->dim, n = 0, lo, hi;
  double d[3], sign;
  if (is_rail(l)) {
    cols[0] = l->a * dim + l->axis, vals[0] = velocity ? 0.0 : 1.0;
    return 1;
  }
  for (size_t k = 0; k < dim; k++) {
    double b = l->b < p->n_masses ? at(p, x, l->b)[k] : velocity ? 0.0 : at(p, x, l->b)[k];
    d[k] = at(p, x, l->a)[k] - b;
  }
  lo = l->a < l->b ? l->a : l->b, hi = l->a < l->b ? l->b : l->a;
  for (size_t end = 0; end < 2; end++) {
    size_t i = end ? hi : lo;
    if (i >= p->n_masses) continue;
    sign = i == l->a ? 1.0 : -1.0;
    for (size_t k = 0; k < dim; k++) cols[n] = i * dim + k, vals[n++] = sign * d[k];
  }
  return n;
}

static void rows(const mech_truss *p, const double *x, int velocity, double *out) {
  size_t n_q = p->n_masses * p->dim, cols[6], k = 0;
  double vals[6];
  if (!p->sparse) memset(out, 0, p->n_links * n_q * sizeof *out);
  for (size_t j = 0; j < p->n_links; j++) {
    size_t n = row(p, j, x, velocity, cols, vals);
    for (size_t i = 0; i < n; i++)
      if (p->sparse)
        out[k++] = vals[i];
      else
        out[j * n_q + cols[i]] = vals[i];
  }
}

static int truss_mass(double t, const double *q, double *M, void *params) {
  const mech_truss *p = params;
  size_t n_q = p->n_masses * p->dim;
  (void)t, (void)q;
  if (!p->sparse) memset(M, 0, n_q * n_q * sizeof *M);
  for (size_t i = 0; i < n_q; i++) M[p->sparse ? i : i * n_q + i] = p->m;
  return 0;
}

static int truss_force(double t, const double *q, const double *v, double *F, void *params) {
  const mech_truss *p = params;
  (void)t, (void)q, (void)v;
  memset(F, 0, p->n_masses * p->dim * sizeof *F);
  for (size_t i = 0; i < p->n_masses; i++) F[i * p->dim + p->dim - 1] = -p->m * p->ga;
  return 0;
}

static int truss_potential(double t, const double *q, double *V, void *params) {
  const mech_truss *p = params;
  double h = 0.0;
  (void)t;
  for (size_t i = 0; i < p->n_masses; i++) h += q[i * p->dim + p->dim - 1];
  *V = p->m * p->ga * h;
  return 0;
}

static int truss_constraint(double t, const double *q, double *c, void *params) {
  const mech_truss *p = params;
  (void)t;
  for (size_t j = 0; j < p->n_links; j++) {
    const mech_truss_link *l = &p->links[j];
    double s = 0.0;
    if (is_rail(l)) {
      c[j] = q[l->a * p->dim + l->axis] - l->length2;
      continue;
    }
    for (size_t k = 0; k < p->dim; k++) {
      double d = at(p, q, l->a)[k] - at(p, q, l->b)[k];
      s += d * d;
    }
    c[j] = 0.5 * (s - l->length2);
  }
  return 0;
}

static int truss_jacobian(double t, const double *q, double *G, void *params) {
  (void)t;
  rows(params, q, 0, G);
  return 0;
}

static int truss_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                              void *params) {
  (void)t, (void)q;
  rows(params, v, 1, Gdot);
  return 0;
}

static int truss_zero_c(double t, const double *q, double *ct, void *params) {
  const mech_truss *p = params;
  (void)t, (void)q;
  memset(ct, 0, p->n_links * sizeof *ct);
  return 0;
}

static int truss_zero_c_along(double t, const double *q, const double *v, double *out,
                              void *params) {
  (void)v;
  return truss_zero_c(t, q, out, params);
}

static int truss_mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  const mech_truss *p = params;
  (void)t, (void)q, (void)v;
  memset(out, 0, p->n_masses * p->dim * sizeof *out);
  return 0;
}

/* ---- building a truss ---- */

static int reserve(mech_truss *p, size_t dim, size_t masses, size_t anchors, size_t links,
                   int sparse) {
  memset(p, 0, sizeof *p);
  p->dim = dim, p->m = 1.0, p->ga = 9.81, p->sparse = sparse;
  p->start = malloc((masses ? masses : 1) * dim * sizeof *p->start);
  p->anchors = malloc((anchors ? anchors : 1) * dim * sizeof *p->anchors);
  p->links = malloc((links ? links : 1) * sizeof *p->links);
  return p->start && p->anchors && p->links ? 0 : -1;
}

static size_t mass_at(mech_truss *p, double x, double y, double z) {
  double *s = p->start + p->n_masses * p->dim, xyz[3] = {x, y, z};
  memcpy(s, xyz, p->dim * sizeof *s);
  return p->n_masses++;
}

/* an anchor's index as a link names it: n_masses + k, fixed once every mass is placed */
static size_t anchor_at(mech_truss *p, double x, double y, double z) {
  double *s = p->anchors + p->n_anchors * p->dim, xyz[3] = {x, y, z};
  memcpy(s, xyz, p->dim * sizeof *s);
  return p->n_anchors++;
}

/* a rod from mass a to mass b, or to anchor k with b = (size_t)-1 - k; its length the start's */
static void rod(mech_truss *p, size_t a, size_t b) {
  mech_truss_link *l = &p->links[p->n_links++];
  l->a = a, l->b = b, l->axis = 0;
}

static void rail(mech_truss *p, size_t a, size_t axis) {
  mech_truss_link *l = &p->links[p->n_links++];
  l->a = l->b = a, l->axis = axis;
  l->length2 = p->start[a * p->dim + axis];
}

/* anchors renamed n_masses + k, the rods' lengths taken at the start */
static void finish(mech_truss *p) {
  for (size_t j = 0; j < p->n_links; j++) {
    mech_truss_link *l = &p->links[j];
    double s = 0.0;
    if (is_rail(l)) continue;
    if (l->b > p->n_masses + p->n_anchors) l->b = p->n_masses + ((size_t)-1 - l->b);
    for (size_t k = 0; k < p->dim; k++) {
      double d = at(p, p->start, l->a)[k] - at(p, p->start, l->b)[k];
      s += d * d;
    }
    l->length2 = s;
  }
}

static size_t anchor_ref(size_t k) { return (size_t)-1 - k; }

int mech_truss_star(mech_truss *p, size_t k, int sparse) {
  size_t cart;
  if (reserve(p, 2, k + 1, 0, k + 1, sparse) != 0) return -1;
  cart = mass_at(p, 0.0, 0.0, 0.0);
  rail(p, cart, 1);
  for (size_t j = 0; j < k; j++) { /* the pendulums spread over angles 0.2 to 1.2 from below */
    double a = 0.2 + (k > 1 ? (double)j / (double)(k - 1) : 0.0);
    rod(p, mass_at(p, sin(a), -cos(a), 0.0), cart);
  }
  finish(p);
  return 0;
}

int mech_truss_ladder(mech_truss *p, size_t n, int sparse) {
  size_t top = 0, bot = 0, wall_t, wall_b, end_t, end_b;
  if (reserve(p, 2, 2 * n, 4, 3 * n + 2, sparse) != 0) return -1;
  wall_t = anchor_at(p, 0.0, 1.0, 0.0), wall_b = anchor_at(p, 0.0, 0.0, 0.0);
  end_t = anchor_at(p, (double)n + 0.6, 1.9, 0.0), end_b = anchor_at(p, (double)n + 0.6, -0.9, 0.0);
  /* cells of unit width, the nodes moved off the grid by a tenth: squares and straight runs
   * hold a self-stress (rank G < n_c), a generic cell none */
  for (size_t i = 1; i <= n; i++) {
    double x = (double)i;
    size_t t = mass_at(p, x + 0.1 * sin(1.7 * x), 1.0 + 0.12 * sin(2.3 * x + 1.0), 0.0);
    size_t b = mass_at(p, x + 0.1 * sin(1.1 * x + 2.0), 0.12 * sin(0.7 * x + 3.0), 0.0);
    rod(p, t, i == 1 ? anchor_ref(wall_t) : top);
    rod(p, b, i == 1 ? anchor_ref(wall_b) : bot);
    rod(p, t, b);
    top = t, bot = b;
  }
  rod(p, top, anchor_ref(end_t));
  rod(p, bot, anchor_ref(end_b));
  finish(p);
  return 0;
}

int mech_truss_cloth(mech_truss *p, size_t n, int sparse) {
  size_t *id = malloc(n * n * sizeof *id), pin[2];
  if (!id || reserve(p, 3, n * n - 2, 2, 2 * n * (n - 1), sparse) != 0) {
    free(id);
    return -1;
  }
  pin[0] = anchor_at(p, 0.0, 0.0, 0.0);
  pin[1] = anchor_at(p, (double)(n - 1), (double)(n - 1), 0.0);
  for (size_t i = 0; i < n; i++) /* flat in z = 0, pinned at two opposite corners */
    for (size_t j = 0; j < n; j++)
      id[i * n + j] = (i == 0 && j == 0)           ? anchor_ref(pin[0])
                      : (i == n - 1 && j == n - 1) ? anchor_ref(pin[1])
                                                   : mass_at(p, (double)i, (double)j, 0.0);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) {
      size_t a = id[i * n + j];
      for (int right = 0; right < 2; right++) {
        size_t ii = i + (size_t)right, jj = j + (size_t)!right, b;
        if (ii >= n || jj >= n) continue;
        b = id[ii * n + jj];
        if (a >= n * n && b >= n * n) continue; /* two anchors: no rod */
        rod(p, a < n * n ? a : b, a < n * n ? b : a);
      }
    }
  free(id);
  finish(p);
  return 0;
}

/* node at depth l spreads its children by 2^-l */
static void branch(mech_truss *p, size_t parent, double x, double y, size_t level, size_t depth) {
  for (int side = -1; side <= 1; side += 2) {
    double cx = x + side * ldexp(1.0, -(int)level), cy = y - 1.0;
    size_t child = mass_at(p, cx, cy, 0.0);
    rod(p, child, parent);
    if (level + 1 < depth) branch(p, child, cx, cy, level + 1, depth);
  }
}

int mech_truss_tree(mech_truss *p, size_t depth, int sparse) {
  size_t n = ((size_t)1 << depth) - 1, root;
  if (reserve(p, 2, n, 1, n, sparse) != 0) return -1;
  rod(p, root = mass_at(p, 0.3, -1.0, 0.0), anchor_ref(anchor_at(p, 0.0, 0.0, 0.0)));
  if (depth > 1) branch(p, root, 0.3, -1.0, 1, depth);
  finish(p);
  return 0;
}

/* the patterns: M diagonal, G's rows as row() writes them */
static int patterns(mech_truss *p) {
  size_t n_q = p->n_masses * p->dim, n_c = p->n_links, cols[6], k = 0;
  size_t *a = malloc((2 * (n_q + 1) + (n_c + 1) + 6 * n_c) * sizeof *a);
  size_t *m_start = a, *m_col = a + n_q + 1, *g_start = m_col + n_q, *g_col = g_start + n_c + 1;
  double vals[6];
  if (!a) return -1;
  for (size_t i = 0; i <= n_q; i++) m_start[i] = i;
  for (size_t i = 0; i < n_q; i++) m_col[i] = i;
  g_start[0] = 0;
  for (size_t j = 0; j < n_c; j++) {
    size_t n = row(p, j, p->start, 0, cols, vals);
    memcpy(g_col + k, cols, n * sizeof *cols);
    g_start[j + 1] = k += n;
  }
  p->arrays = a;
  p->mass_pattern = (sdae_pattern){n_q, m_start, m_col};
  p->jacobian_pattern = (sdae_pattern){k, g_start, g_col};
  return 0;
}

int mech_truss_system(sdae_mbs *sys, mech_truss *p) {
  p->arrays = NULL;
  if (p->sparse && patterns(p) != 0) return -1;
  *sys = (sdae_mbs){.n_q = p->n_masses * p->dim,
                    .n_c = p->n_links,
                    .mass = truss_mass,
                    .force = truss_force,
                    .constraint = truss_constraint,
                    .jacobian = truss_jacobian,
                    .constraint_t = truss_zero_c,
                    .potential = truss_potential,
                    .params = p,
                    .mass_dot_v = truss_mass_dot_v,
                    .jacobian_dot = truss_jacobian_dot,
                    .constraint_t_dot = truss_zero_c_along,
                    .mass_pattern = p->sparse ? &p->mass_pattern : NULL,
                    .jacobian_pattern = p->sparse ? &p->jacobian_pattern : NULL};
  return 0;
}

void mech_truss_free(mech_truss *p) {
  free(p->start), free(p->anchors), free(p->links), free(p->arrays);
  memset(p, 0, sizeof *p);
}

void mech_truss_start(const mech_truss *p, double *q, double *v) {
  memcpy(q, p->start, p->n_masses * p->dim * sizeof *q);
  memset(v, 0, p->n_masses * p->dim * sizeof *v);
}
