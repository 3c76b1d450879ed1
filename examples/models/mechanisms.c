/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanisms of mechanisms.h. Every one is point masses under gravity: M is diagonal,
 * F = -dV/dq is constant (plus the damped pendulum's -d v), and the constraints are half
 * squared distances, whose jacobian rows are differences of positions. Along the motion
 * (q + s v) M stays constant, (d/ds M) v = 0, and those rows change by the same differences of
 * the velocities, a fixed pivot's being 0; no constraint depends on t. */
#include "mechanisms.h"

#include <math.h>
#include <string.h>

#include <gsl/gsl_sf_ellint.h>
#include <gsl/gsl_sf_elljac.h>

/* M = diag(mass[0], mass[0], mass[1], mass[1], ...): one mass per planar point */
static void point_masses(const double *mass, size_t points, double *M) {
  size_t n = 2 * points;
  memset(M, 0, n * n * sizeof *M);
  for (size_t i = 0; i < n; i++) M[i * n + i] = mass[i / 2];
}

/* F = (0, -m_i ga) per point: gravity, the negative gradient of V = ga sum m_i y_i */
static void gravity(const double *mass, size_t points, double ga, double *F) {
  for (size_t i = 0; i < points; i++) {
    F[2 * i] = 0.0;
    F[2 * i + 1] = -mass[i] * ga;
  }
}

static double gravity_potential(const double *mass, size_t points, double ga, const double *q) {
  double V = 0.0;
  for (size_t i = 0; i < points; i++) V += mass[i] * ga * q[2 * i + 1];
  return V;
}

/* (|P - R|^2 - len^2)/2 for planar points P, R */
static double half_sq(const double *P, const double *R, double len) {
  double dx = P[0] - R[0], dy = P[1] - R[1];
  return (dx * dx + dy * dy - len * len) / 2;
}

/* the jacobian row of half_sq: d/dP = P - R and d/dR = R - P, at the columns of P and R
 * (R a fixed pivot when r < 0) */
static void half_sq_row(const double *q, size_t n, size_t p, long r, const double *pivot,
                        double *row) {
  const double *R = r < 0 ? pivot : q + r;
  memset(row, 0, n * sizeof *row);
  row[p] = q[p] - R[0];
  row[p + 1] = q[p + 1] - R[1];
  if (r >= 0) {
    row[r] = -row[p];
    row[r + 1] = -row[p + 1];
  }
}

static const double origin[2] = {0.0, 0.0};

/* (d/ds M) v = 0: the point masses do not change along the motion (written, so that the
 * front-end need not difference a constant) */
static void constant_mass_dot_v(size_t n, double *out) { memset(out, 0, n * sizeof *out); }

/* dc/dt = 0 and d/ds (dc/dt) = 0: no constraint depends on t (written, so that the front-end,
 * and the index-1 RK4 of the benchmarks alike, need not difference c in t: four evaluations of
 * c at every configuration) */
static void scleronomic(size_t n_c, double *out) { memset(out, 0, n_c * sizeof *out); }

/* d/ds of half_sq_row's row along (q + s v): q_p - R changes at v_p - v_R, with v_R = 0 for a
 * fixed pivot; the row of the same form in the velocities, every pivot at the origin */
static void half_sq_row_dot(const double *v, size_t n, size_t p, long r, double *row) {
  half_sq_row(v, n, p, r, origin, row);
}

/* ---- pendulum ------------------------------------------------------------------------------ */

int mech_pendulum_mass(double t, const double *q, double *M, void *params) {
  const mech_pendulum *p = params;
  (void)t, (void)q;
  point_masses(&p->m, 1, M);
  return 0;
}

/* gravity, and the damping force -d v when there is damping (D = d I) */
int mech_pendulum_force(double t, const double *q, const double *v, double *F, void *params) {
  const mech_pendulum *p = params;
  (void)t, (void)q;
  gravity(&p->m, 1, p->ga, F);
  if (p->d != 0.0) {
    F[0] -= p->d * v[0];
    F[1] -= p->d * v[1];
  }
  return 0;
}

int mech_pendulum_constraint(double t, const double *q, double *c, void *params) {
  const mech_pendulum *p = params;
  (void)t;
  c[0] = half_sq(q, origin, p->L);
  return 0;
}

int mech_pendulum_jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  half_sq_row(q, 2, 0, -1, origin, G);
  return 0;
}

int mech_pendulum_mass_dot_v(double t, const double *q, const double *v, double *out,
                             void *params) {
  (void)t, (void)q, (void)v, (void)params;
  constant_mass_dot_v(2, out);
  return 0;
}

int mech_pendulum_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                               void *params) {
  (void)t, (void)q, (void)params;
  half_sq_row_dot(v, 2, 0, -1, Gdot);
  return 0;
}

int mech_pendulum_potential(double t, const double *q, double *V, void *params) {
  const mech_pendulum *p = params;
  (void)t;
  *V = gravity_potential(&p->m, 1, p->ga, q);
  return 0;
}

int mech_pendulum_damping(double t, const double *q, double *D, void *params) {
  const mech_pendulum *p = params;
  (void)t, (void)q;
  D[0] = p->d, D[1] = 0.0, D[2] = 0.0, D[3] = p->d;
  return 0;
}

static int pendulum_constraint_t(double t, const double *q, double *ct, void *params) {
  (void)t, (void)q, (void)params;
  scleronomic(1, ct);
  return 0;
}

static int pendulum_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                     void *params) {
  (void)t, (void)q, (void)v, (void)params;
  scleronomic(1, out);
  return 0;
}

void mech_pendulum_system(sdae_mbs *sys, mech_pendulum *p) {
  *sys = (sdae_mbs){.n_q = 2,
                    .n_c = 1,
                    .mass = mech_pendulum_mass,
                    .force = mech_pendulum_force,
                    .constraint = mech_pendulum_constraint,
                    .jacobian = mech_pendulum_jacobian,
                    .potential = mech_pendulum_potential,
                    .damping = p->d != 0.0 ? mech_pendulum_damping : NULL,
                    .params = p,
                    .mass_dot_v = mech_pendulum_mass_dot_v,
                    .jacobian_dot = mech_pendulum_jacobian_dot,
                    .constraint_t = pendulum_constraint_t,
                    .constraint_t_dot = pendulum_constraint_t_dot};
}

void mech_pendulum_state(const mech_pendulum *p, double theta, double omega, double *q, double *v) {
  q[0] = p->L * sin(theta), q[1] = -p->L * cos(theta);
  v[0] = p->L * cos(theta) * omega, v[1] = p->L * sin(theta) * omega;
}

/* theta'' = -(ga/L) sin theta from (theta0, 0): sin(theta/2) = k sn(K - w t | k^2),
 * k = sin(theta0/2), w = sqrt(ga/L); theta' = -2 k w cn(K - w t) (as dn = cos(theta/2)) */
void mech_pendulum_exact(const mech_pendulum *p, double theta0, double t, double *theta,
                         double *omega) {
  double k = sin(0.5 * theta0), w = sqrt(p->ga / p->L), sn, cn, dn;
  double K = gsl_sf_ellint_Kcomp(k, GSL_PREC_DOUBLE);
  gsl_sf_elljac_e(K - w * t, k * k, &sn, &cn, &dn);
  *theta = 2.0 * asin(k * sn);
  *omega = -2.0 * k * w * cn;
}

/* -G^T lambda = -lambda q is the rod's pull, L lambda along -q/L: the tension; the radial
 * balance tension - m ga cos theta = m L omega^2 gives lambda */
double mech_pendulum_lambda(const mech_pendulum *p, double theta, double omega) {
  return p->m * (p->L * omega * omega + p->ga * cos(theta)) / p->L;
}

/* ---- double pendulum ----------------------------------------------------------------------- */

static int dpend_mass(double t, const double *q, double *M, void *params) {
  const mech_double_pendulum *p = params;
  const double mass[2] = {p->m1, p->m2};
  (void)t, (void)q;
  point_masses(mass, 2, M);
  return 0;
}

static int dpend_force(double t, const double *q, const double *v, double *F, void *params) {
  const mech_double_pendulum *p = params;
  const double mass[2] = {p->m1, p->m2};
  (void)t, (void)q, (void)v;
  gravity(mass, 2, p->ga, F);
  return 0;
}

static int dpend_constraint(double t, const double *q, double *c, void *params) {
  const mech_double_pendulum *p = params;
  (void)t;
  c[0] = half_sq(q, origin, p->L1);
  c[1] = half_sq(q + 2, q, p->L2);
  return 0;
}

static int dpend_jacobian(double t, const double *q, double *G, void *params) {
  (void)t, (void)params;
  half_sq_row(q, 4, 0, -1, origin, G);
  half_sq_row(q, 4, 2, 0, NULL, G + 4);
  return 0;
}

static int dpend_mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  constant_mass_dot_v(4, out);
  return 0;
}

static int dpend_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                              void *params) {
  (void)t, (void)q, (void)params;
  half_sq_row_dot(v, 4, 0, -1, Gdot);
  half_sq_row_dot(v, 4, 2, 0, Gdot + 4);
  return 0;
}

static int dpend_potential(double t, const double *q, double *V, void *params) {
  const mech_double_pendulum *p = params;
  const double mass[2] = {p->m1, p->m2};
  (void)t;
  *V = gravity_potential(mass, 2, p->ga, q);
  return 0;
}

static int dpend_constraint_t(double t, const double *q, double *ct, void *params) {
  (void)t, (void)q, (void)params;
  scleronomic(2, ct);
  return 0;
}

static int dpend_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                  void *params) {
  (void)t, (void)q, (void)v, (void)params;
  scleronomic(2, out);
  return 0;
}

void mech_double_pendulum_system(sdae_mbs *sys, mech_double_pendulum *p) {
  *sys = (sdae_mbs){.n_q = 4,
                    .n_c = 2,
                    .mass = dpend_mass,
                    .force = dpend_force,
                    .constraint = dpend_constraint,
                    .jacobian = dpend_jacobian,
                    .potential = dpend_potential,
                    .params = p,
                    .mass_dot_v = dpend_mass_dot_v,
                    .jacobian_dot = dpend_jacobian_dot,
                    .constraint_t = dpend_constraint_t,
                    .constraint_t_dot = dpend_constraint_t_dot};
}

void mech_double_pendulum_state(const mech_double_pendulum *p, const double *a, const double *w,
                                double *q, double *v) {
  /* each arm points at angle a_i from the downward vertical: (sin a_i, -cos a_i) */
  q[0] = p->L1 * sin(a[0]);
  q[1] = -p->L1 * cos(a[0]);
  q[2] = q[0] + p->L2 * sin(a[1]);
  q[3] = q[1] - p->L2 * cos(a[1]);
  v[0] = p->L1 * w[0] * cos(a[0]);
  v[1] = p->L1 * w[0] * sin(a[0]);
  v[2] = v[0] + p->L2 * w[1] * cos(a[1]);
  v[3] = v[1] + p->L2 * w[1] * sin(a[1]);
}

/* ---- four-bar linkage ---------------------------------------------------------------------- */

static int fourbar_mass(double t, const double *q, double *M, void *params) {
  const mech_fourbar *p = params;
  const double mass[2] = {p->mB, p->mC};
  (void)t, (void)q;
  point_masses(mass, 2, M);
  return 0;
}

static int fourbar_force(double t, const double *q, const double *v, double *F, void *params) {
  const mech_fourbar *p = params;
  const double mass[2] = {p->mB, p->mC};
  (void)t, (void)q, (void)v;
  gravity(mass, 2, p->ga, F);
  return 0;
}

static int fourbar_constraint(double t, const double *q, double *c, void *params) {
  const mech_fourbar *p = params;
  const double D[2] = {p->d, 0.0};
  (void)t;
  c[0] = half_sq(q, origin, p->a); /* crank AB */
  c[1] = half_sq(q + 2, q, p->b);  /* coupler BC */
  c[2] = half_sq(q + 2, D, p->e);  /* rocker CD */
  return 0;
}

static int fourbar_jacobian(double t, const double *q, double *G, void *params) {
  const mech_fourbar *p = params;
  const double D[2] = {p->d, 0.0};
  (void)t;
  half_sq_row(q, 4, 0, -1, origin, G);
  half_sq_row(q, 4, 2, 0, NULL, G + 4);
  half_sq_row(q, 4, 2, -1, D, G + 8);
  return 0;
}

static int fourbar_mass_dot_v(double t, const double *q, const double *v, double *out,
                              void *params) {
  (void)t, (void)q, (void)v, (void)params;
  constant_mass_dot_v(4, out);
  return 0;
}

/* the pivots A and D do not move: the crank's and the rocker's rows change with B', C' alone */
static int fourbar_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                                void *params) {
  (void)t, (void)q, (void)params;
  half_sq_row_dot(v, 4, 0, -1, Gdot);
  half_sq_row_dot(v, 4, 2, 0, Gdot + 4);
  half_sq_row_dot(v, 4, 2, -1, Gdot + 8);
  return 0;
}

static int fourbar_potential(double t, const double *q, double *V, void *params) {
  const mech_fourbar *p = params;
  const double mass[2] = {p->mB, p->mC};
  (void)t;
  *V = gravity_potential(mass, 2, p->ga, q);
  return 0;
}

static int fourbar_constraint_t(double t, const double *q, double *ct, void *params) {
  (void)t, (void)q, (void)params;
  scleronomic(3, ct);
  return 0;
}

static int fourbar_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                    void *params) {
  (void)t, (void)q, (void)v, (void)params;
  scleronomic(3, out);
  return 0;
}

void mech_fourbar_system(sdae_mbs *sys, mech_fourbar *p) {
  *sys = (sdae_mbs){.n_q = 4,
                    .n_c = 3,
                    .mass = fourbar_mass,
                    .force = fourbar_force,
                    .constraint = fourbar_constraint,
                    .jacobian = fourbar_jacobian,
                    .potential = fourbar_potential,
                    .params = p,
                    .mass_dot_v = fourbar_mass_dot_v,
                    .jacobian_dot = fourbar_jacobian_dot,
                    .constraint_t = fourbar_constraint_t,
                    .constraint_t_dot = fourbar_constraint_t_dot};
}

int mech_fourbar_state(const mech_fourbar *p, double theta, double omega, double *q, double *v) {
  double Bx = p->a * cos(theta), By = p->a * sin(theta);
  double ux = p->d - Bx, uy = -By, r = hypot(ux, uy);
  /* C on both circles |C - B| = b, |C - D| = e: along B->D by s, then h to the left */
  double s = (p->b * p->b - p->e * p->e + r * r) / (2 * r), h2 = p->b * p->b - s * s;
  if (!(r > 0) || !(h2 > 0)) return -1;
  double h = sqrt(h2), Cx = Bx + (s * ux - h * uy) / r, Cy = By + (s * uy + h * ux) / r;
  /* G v = 0: vB along the crank circle, vC from (C - B).(vC - vB) = 0, (C - D).vC = 0 */
  double vBx = -omega * By, vBy = omega * Bx;
  double r1x = Cx - Bx, r1y = Cy - By, r2x = Cx - p->d, r2y = Cy;
  double det = r1x * r2y - r1y * r2x, rhs = r1x * vBx + r1y * vBy;
  if (det == 0.0) return -1; /* coupler and rocker aligned: a dead point */
  q[0] = Bx, q[1] = By, q[2] = Cx, q[3] = Cy;
  v[0] = vBx, v[1] = vBy, v[2] = rhs * r2y / det, v[3] = -rhs * r2x / det;
  return 0;
}

int mech_fourbar_crank_rocker(const mech_fourbar *p) {
  double len[4] = {p->a, p->b, p->e, p->d}, lo = len[0], hi = len[0], sum = 0.0;
  for (int i = 0; i < 4; i++) {
    lo = fmin(lo, len[i]);
    hi = fmax(hi, len[i]);
    sum += len[i];
  }
  return p->a == lo && lo + hi <= sum - lo - hi;
}

/* ---- helpers ------------------------------------------------------------------------------- */

double mech_max_abs_c(const sdae_mbs *sys, double t, const double *q) {
  double c[8], worst = 0.0;
  if (sys->n_c > 8 || sys->constraint(t, q, c, sys->params) != 0) return -1.0;
  for (size_t j = 0; j < sys->n_c; j++) worst = fmax(worst, fabs(c[j]));
  return worst;
}
