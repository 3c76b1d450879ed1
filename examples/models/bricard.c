/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Bricard's mechanism (bricard.h) in natural coordinates. */
#include <string.h>

#include "bricard.h"

#define RODS 5

static const double ground_point[2][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}}; /* P_0, P_5 */
static const double ground_axis[2][3] = {{0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}};  /* u_0, u_5 */

mech_bricard mech_bricard_benchmark(void) { return (mech_bricard){.m = 1.0, .ga = 9.81}; }

/* P_k and u_k (k = 0..5) in x: the coordinates of the moving ones, the ground's otherwise (their
 * velocities zero: velocity) */
static const double zero3[3] = {0.0, 0.0, 0.0};
static const double *point(const double *x, int k, int velocity) {
  if (k > 0 && k < RODS) return x + 3 * (k - 1);
  return velocity ? zero3 : ground_point[k == RODS];
}
static const double *axis(const double *x, int k, int velocity) {
  if (k > 0 && k < RODS) return x + 12 + 3 * (k - 1);
  return velocity ? zero3 : ground_axis[k == RODS];
}
/* the column of P_k's or u_k's first coordinate, -1 for the ground's */
static int point_col(int k) { return k > 0 && k < RODS ? 3 * (k - 1) : -1; }
static int axis_col(int k) { return k > 0 && k < RODS ? 12 + 3 * (k - 1) : -1; }

static double dot(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static int bricard_constraint(double t, const double *q, double *c, void *params) {
  (void)t, (void)params;
  for (int i = 0; i < RODS; i++) {
    const double *a = point(q, i, 0), *b = point(q, i + 1, 0);
    const double *ua = axis(q, i, 0), *ub = axis(q, i + 1, 0);
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    c[4 * i] = 0.5 * (dot(d, d) - 1.0);
    c[4 * i + 1] = dot(d, ua);
    c[4 * i + 2] = dot(d, ub);
    c[4 * i + 3] = dot(ua, ub);
  }
  for (int k = 1; k < RODS; k++) c[20 + k - 1] = 0.5 * (dot(axis(q, k, 0), axis(q, k, 0)) - 1.0);
  return 0;
}

/* out[row][col..col+2] += s x (col < 0: the ground's, no column) */
static void put(double *G, int row, int col, double s, const double *x) {
  if (col < 0) return;
  for (int j = 0; j < 3; j++) G[row * MECH_BRICARD_NQ + col + j] += s * x[j];
}

/* G at positions x, or Gdot at velocities x (velocity: the ground's at rest): each row is
 * bilinear in the vectors it joins, so Gdot is G's formula at the velocities */
static void rows(const double *x, int velocity, double *G) {
  memset(G, 0, MECH_BRICARD_NC * MECH_BRICARD_NQ * sizeof *G);
  for (int i = 0; i < RODS; i++) {
    const double *a = point(x, i, velocity), *b = point(x, i + 1, velocity);
    const double *ua = axis(x, i, velocity), *ub = axis(x, i + 1, velocity);
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    int pa = point_col(i), pb = point_col(i + 1), ca = axis_col(i), cb = axis_col(i + 1);
    put(G, 4 * i, pb, 1.0, d), put(G, 4 * i, pa, -1.0, d);
    put(G, 4 * i + 1, pb, 1.0, ua), put(G, 4 * i + 1, pa, -1.0, ua), put(G, 4 * i + 1, ca, 1.0, d);
    put(G, 4 * i + 2, pb, 1.0, ub), put(G, 4 * i + 2, pa, -1.0, ub), put(G, 4 * i + 2, cb, 1.0, d);
    put(G, 4 * i + 3, ca, 1.0, ub), put(G, 4 * i + 3, cb, 1.0, ua);
  }
  for (int k = 1; k < RODS; k++) put(G, 20 + k - 1, axis_col(k), 1.0, axis(x, k, velocity));
}

static int bricard_jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  rows(q, 0, G);
  return 0;
}

static int bricard_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                                void *params) {
  (void)t, (void)q, (void)params;
  rows(v, 1, Gdot);
  return 0;
}

/* each rod m/3 on its ends' own coordinates, m/6 between them; the axes massless */
static int bricard_mass(double t, const double *q, double *M, void *params) {
  const mech_bricard *p = params;
  (void)t, (void)q;
  memset(M, 0, MECH_BRICARD_NQ * MECH_BRICARD_NQ * sizeof *M);
  for (int i = 0; i < RODS; i++) {
    int a = point_col(i), b = point_col(i + 1);
    for (int j = 0; j < 3; j++) {
      if (a >= 0) M[(a + j) * MECH_BRICARD_NQ + a + j] += p->m / 3.0;
      if (b >= 0) M[(b + j) * MECH_BRICARD_NQ + b + j] += p->m / 3.0;
      if (a >= 0 && b >= 0)
        M[(a + j) * MECH_BRICARD_NQ + b + j] = M[(b + j) * MECH_BRICARD_NQ + a + j] = p->m / 6.0;
    }
  }
  return 0;
}

/* each rod's weight, half on each end */
static int bricard_force(double t, const double *q, const double *v, double *F, void *params) {
  const mech_bricard *p = params;
  (void)t, (void)q, (void)v;
  memset(F, 0, MECH_BRICARD_NQ * sizeof *F);
  for (int k = 1; k < RODS; k++) F[point_col(k) + 1] = -p->m * p->ga; /* two rods' halves */
  return 0;
}

static int bricard_potential(double t, const double *q, double *V, void *params) {
  const mech_bricard *p = params;
  double h = 0.0;
  (void)t;
  for (int k = 1; k < RODS; k++) h += q[point_col(k) + 1];
  *V = p->m * p->ga * h;
  return 0;
}

static int zero_rows(double t, const double *q, double *out, void *params) {
  (void)t, (void)q, (void)params;
  memset(out, 0, MECH_BRICARD_NC * sizeof *out);
  return 0;
}

static int zero_rows_along(double t, const double *q, const double *v, double *out, void *params) {
  (void)v;
  return zero_rows(t, q, out, params);
}

static int bricard_mass_dot_v(double t, const double *q, const double *v, double *out,
                              void *params) {
  (void)t, (void)q, (void)v, (void)params;
  memset(out, 0, MECH_BRICARD_NQ * sizeof *out);
  return 0;
}

void mech_bricard_system(sdae_mbs *sys, mech_bricard *p) {
  *sys = (sdae_mbs){.n_q = MECH_BRICARD_NQ,
                    .n_c = MECH_BRICARD_NC,
                    .rank = MECH_BRICARD_NC - 1,
                    .mass = bricard_mass,
                    .force = bricard_force,
                    .constraint = bricard_constraint,
                    .jacobian = bricard_jacobian,
                    .constraint_t = zero_rows,
                    .potential = bricard_potential,
                    .params = p,
                    .mass_dot_v = bricard_mass_dot_v,
                    .jacobian_dot = bricard_jacobian_dot,
                    .constraint_t_dot = zero_rows_along};
}

void mech_bricard_start(double *q, double *v) {
  static const double start[MECH_BRICARD_NQ] = {
      1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 1.0, -1.0, 1.0, 0.0, -1.0, 1.0,  /* P_1 .. P_4 */
      0.0, 0.0, 1.0, 1.0, 0.0,  0.0, 0.0, 1.0,  0.0, 0.0, 0.0,  1.0}; /* u_1 .. u_4: z, x, y, z */
  memcpy(q, start, sizeof start);
  memset(v, 0, MECH_BRICARD_NQ * sizeof *v);
}
