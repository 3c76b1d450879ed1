/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The benchmark mechanisms of benchmarks.h, written from their published equations, with the
 * derivatives along the motion (d/ds at (t + s, q + s v)) differentiated by hand from them. */
#include "benchmarks.h"

#include <math.h>
#include <string.h>

static void diagonal(const double *d, size_t n, double *M) {
  memset(M, 0, n * n * sizeof *M);
  for (size_t i = 0; i < n; i++) M[i * n + i] = d[i];
}

/* dc/dt = 0: the constraints of the slider crank and of Andrews' mechanism are fixed in time */
static int fixed_constraint_t(double t, const double *q, double *ct, void *params, size_t n_c) {
  (void)t, (void)q, (void)params;
  memset(ct, 0, n_c * sizeof *ct);
  return 0;
}

/* The derivative along the motion of a constant mass matrix: 0, written so that the front-end
 * need not difference a constant */
static void constant_mass_dot_v(size_t n, double *out) { memset(out, 0, n * sizeof *out); }

/* d/ds of dc/dt = 0: 0 */
static int fixed_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                  void *params, size_t n_c) {
  (void)t, (void)q, (void)v, (void)params;
  memset(out, 0, n_c * sizeof *out);
  return 0;
}

/* ---- slider crank ------------------------------------------------------------------------- */

/* The spring's length l = |R - P| and its gradient dl/dq, from dP/dtheta = (a/2)(-sin theta,
 * cos theta), dR/dx = (1, 0), dR/dphi = (sin phi, -cos phi)/2; 1 (recoverable) when P = R,
 * where the spring has no direction (l is set even then) */
static int crank_spring(const bench_slider_crank *p, const double *q, double *l, double *grad) {
  double st = sin(q[0]), ct = cos(q[0]), sp = sin(q[2]), cp = cos(q[2]);
  double dx = q[1] - cp / 2 - p->a * ct / 2, dy = -sp / 2 - p->a * st / 2;
  *l = hypot(dx, dy);
  if (!(*l > 0)) return 1;
  grad[0] = p->a * (dx * st - dy * ct) / (2 * *l);
  grad[1] = dx / *l;
  grad[2] = (dx * sp - dy * cp) / (2 * *l);
  return 0;
}

static int crank_mass(double t, const double *q, double *M, void *params) {
  const bench_slider_crank *p = params;
  const double d[3] = {p->J1, p->m2, p->J2};
  (void)t, (void)q;
  diagonal(d, 3, M);
  return 0;
}

/* F = -f grad l + (0, F, -F sin phi), f = k (l - l0) + c dl/dt: idaSlCrank_dns's force() */
static int crank_force(double t, const double *q, const double *v, double *F, void *params) {
  const bench_slider_crank *p = params;
  double g[3], l;
  (void)t;
  if (crank_spring(p, q, &l, g)) return 1;
  double f = p->k * (l - p->l0) + p->c * (g[0] * v[0] + g[1] * v[1] + g[2] * v[2]);
  for (int i = 0; i < 3; i++) F[i] = -f * g[i];
  F[1] += p->F;
  F[2] -= p->F * sin(q[2]);
  return 0;
}

static int crank_constraint(double t, const double *q, double *c, void *params) {
  const bench_slider_crank *p = params;
  (void)t;
  c[0] = q[1] - cos(q[2]) - p->a * cos(q[0]);
  c[1] = -sin(q[2]) - p->a * sin(q[0]);
  return 0;
}

static int crank_jacobian(double t, const double *q, double *G, void *params) {
  const bench_slider_crank *p = params;
  (void)t;
  G[0] = p->a * sin(q[0]), G[1] = 1.0, G[2] = sin(q[2]);
  G[3] = -p->a * cos(q[0]), G[4] = 0.0, G[5] = -cos(q[2]);
  return 0;
}

static int crank_constraint_t(double t, const double *q, double *ct, void *params) {
  return fixed_constraint_t(t, q, ct, params, 2);
}

static int crank_mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  constant_mass_dot_v(3, out);
  return 0;
}

/* the jacobian's entries in theta and phi along (theta', phi'): (a sin theta)' =
 * a cos theta theta', (sin phi)' = cos phi phi', and so on; the slider's column is constant */
static int crank_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                              void *params) {
  const bench_slider_crank *p = params;
  (void)t;
  Gdot[0] = p->a * cos(q[0]) * v[0], Gdot[1] = 0.0, Gdot[2] = cos(q[2]) * v[2];
  Gdot[3] = p->a * sin(q[0]) * v[0], Gdot[4] = 0.0, Gdot[5] = sin(q[2]) * v[2];
  return 0;
}

static int crank_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                  void *params) {
  return fixed_constraint_t_dot(t, q, v, out, params, 2);
}

static int crank_potential(double t, const double *q, double *V, void *params) {
  const bench_slider_crank *p = params;
  double g[3], l;
  (void)t;
  (void)crank_spring(p, q, &l, g); /* V needs l only, defined at l = 0 too */
  *V = p->k * (l - p->l0) * (l - p->l0) / 2 - p->F * (q[1] + cos(q[2]));
  return 0;
}

static int crank_damping(double t, const double *q, double *D, void *params) {
  const bench_slider_crank *p = params;
  double g[3], l;
  (void)t;
  if (crank_spring(p, q, &l, g)) return 1;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) D[3 * i + j] = p->c * g[i] * g[j];
  return 0;
}

bench_slider_crank bench_slider_crank_default(void) {
  return (bench_slider_crank){
      .a = 0.5, .J1 = 1.0, .m2 = 1.0, .J2 = 2.0, .k = 1.0, .c = 1.0, .l0 = 1.0, .F = 1.0};
}

void bench_slider_crank_system(sdae_mbs *sys, bench_slider_crank *p) {
  *sys = (sdae_mbs){.n_q = 3,
                    .n_c = 2,
                    .mass = crank_mass,
                    .force = crank_force,
                    .constraint = crank_constraint,
                    .jacobian = crank_jacobian,
                    .constraint_t = crank_constraint_t,
                    .potential = crank_potential,
                    .damping = crank_damping,
                    .params = p,
                    .mass_dot_v = crank_mass_dot_v,
                    .jacobian_dot = crank_jacobian_dot,
                    .constraint_t_dot = crank_constraint_t_dot};
}

void bench_slider_crank_initial(const bench_slider_crank *p, double *q, double *v) {
  q[0] = 2 * atan(1.0);
  q[2] = asin(-p->a);
  q[1] = cos(q[2]);
  v[0] = v[1] = v[2] = 0.0;
}

/* ---- car axis ----------------------------------------------------------------------------- */

/* the wheel b = (sqrt(L^2 - yb^2), r sin(w t)) and its velocity */
static void car_wheel(const bench_car_axis *p, double t, double *b, double *b_t) {
  b[1] = p->r * sin(p->w * t);
  b[0] = sqrt(p->L * p->L - b[1] * b[1]);
  b_t[1] = p->r * p->w * cos(p->w * t);
  b_t[0] = -b[1] * b_t[1] / b[0];
}

/* the wheel's acceleration: yb'' = -w^2 yb, and xb'' from differentiating xb^2 + yb^2 = L^2
 * twice, xb xb'' + xb'^2 + yb yb'' + yb'^2 = 0 */
static void car_wheel_tt(const bench_car_axis *p, double t, double *b_tt) {
  double b[2], b_t[2];
  car_wheel(p, t, b, b_t);
  b_tt[1] = -p->w * p->w * b[1];
  b_tt[0] = -(b_t[0] * b_t[0] + b[1] * b_tt[1] + b_t[1] * b_t[1]) / b[0];
}

static double car_k(const bench_car_axis *p) { return p->mass * p->eps * p->eps / 2; }

static int car_mass(double t, const double *q, double *M, void *params) {
  const bench_car_axis *p = params;
  double k = car_k(p);
  const double d[4] = {k, k, k, k};
  (void)t, (void)q;
  diagonal(d, 4, M);
  return 0;
}

/* a spring of rest length L0 from the anchor to the end, and gravity k g: F = (L0 - len) u */
static int car_spring(const bench_car_axis *p, const double *end, const double *anchor, double *F) {
  double dx = end[0] - anchor[0], dy = end[1] - anchor[1], len = hypot(dx, dy);
  if (!(len > 0)) return 1;
  F[0] = (p->L0 - len) * dx / len;
  F[1] = (p->L0 - len) * dy / len - car_k(p) * p->g;
  return 0;
}

static int car_force(double t, const double *q, const double *v, double *F, void *params) {
  const bench_car_axis *p = params;
  const double origin[2] = {0.0, 0.0};
  double b[2], b_t[2];
  (void)v;
  car_wheel(p, t, b, b_t);
  return car_spring(p, q, origin, F) || car_spring(p, q + 2, b, F + 2);
}

static int car_constraint(double t, const double *q, double *c, void *params) {
  const bench_car_axis *p = params;
  double b[2], b_t[2], dx = q[0] - q[2], dy = q[1] - q[3];
  car_wheel(p, t, b, b_t);
  c[0] = b[0] * q[0] + b[1] * q[1];
  c[1] = dx * dx + dy * dy - p->L * p->L;
  return 0;
}

static int car_jacobian(double t, const double *q, double *G, void *params) {
  const bench_car_axis *p = params;
  double b[2], b_t[2], dx = q[0] - q[2], dy = q[1] - q[3];
  car_wheel(p, t, b, b_t);
  G[0] = b[0], G[1] = b[1], G[2] = 0.0, G[3] = 0.0;
  G[4] = 2 * dx, G[5] = 2 * dy, G[6] = -2 * dx, G[7] = -2 * dy;
  return 0;
}

static int car_constraint_t(double t, const double *q, double *ct, void *params) {
  const bench_car_axis *p = params;
  double b[2], b_t[2];
  car_wheel(p, t, b, b_t);
  ct[0] = b_t[0] * q[0] + b_t[1] * q[1];
  ct[1] = 0.0;
  return 0;
}

static int car_mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  constant_mass_dot_v(4, out);
  return 0;
}

/* along (1, v): the first row (b(t), 0) moves with the wheel, b'(t); the second, 2 (dq, -dq)
 * with dq = q_left - q_right, changes by 2 (dv, -dv) */
static int car_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                            void *params) {
  const bench_car_axis *p = params;
  double b[2], b_t[2], dvx = v[0] - v[2], dvy = v[1] - v[3];
  (void)q;
  car_wheel(p, t, b, b_t);
  Gdot[0] = b_t[0], Gdot[1] = b_t[1], Gdot[2] = 0.0, Gdot[3] = 0.0;
  Gdot[4] = 2 * dvx, Gdot[5] = 2 * dvy, Gdot[6] = -2 * dvx, Gdot[7] = -2 * dvy;
  return 0;
}

/* dc/dt = (b'(t) . q_left, 0) along (1, v): b''(t) . q_left + b'(t) . v_left */
static int car_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                void *params) {
  const bench_car_axis *p = params;
  double b[2], b_t[2], b_tt[2];
  car_wheel(p, t, b, b_t);
  car_wheel_tt(p, t, b_tt);
  out[0] = b_tt[0] * q[0] + b_tt[1] * q[1] + b_t[0] * v[0] + b_t[1] * v[1];
  out[1] = 0.0;
  return 0;
}

bench_car_axis bench_car_axis_default(void) {
  return (bench_car_axis){
      .eps = 1e-2, .mass = 10.0, .L = 1.0, .L0 = 0.5, .r = 0.1, .w = 10.0, .g = 1.0};
}

void bench_car_axis_system(sdae_mbs *sys, bench_car_axis *p) {
  *sys = (sdae_mbs){.n_q = 4,
                    .n_c = 2,
                    .mass = car_mass,
                    .force = car_force,
                    .constraint = car_constraint,
                    .jacobian = car_jacobian,
                    .constraint_t = car_constraint_t,
                    .params = p,
                    .mass_dot_v = car_mass_dot_v,
                    .jacobian_dot = car_jacobian_dot,
                    .constraint_t_dot = car_constraint_t_dot};
}

void bench_car_axis_initial(const bench_car_axis *p, double *q, double *v) {
  q[0] = 0.0, q[1] = p->L0, q[2] = p->L, q[3] = p->L0;
  /* xb xl' + yb' yl = 0 at t = 0 (xb = L, yb' = r w), and xr' = xl' keeps the axis' length */
  v[0] = v[2] = -p->r * p->w * p->L0 / p->L;
  v[1] = v[3] = 0.0;
}

/* ---- Andrews' squeezing mechanism ---------------------------------------------------------- */

void bench_andrews_default(bench_andrews *p) {
  *p = (bench_andrews){.m1 = 0.04325,
                       .m2 = 0.00365,
                       .m3 = 0.02373,
                       .m4 = 0.00706,
                       .m5 = 0.07050,
                       .m6 = 0.00706,
                       .m7 = 0.05498,
                       .xa = -0.06934,
                       .ya = -0.00227,
                       .xb = -0.03635,
                       .yb = 0.03273,
                       .xc = 0.014,
                       .yc = 0.072,
                       .c0 = 4530,
                       .i1 = 2.194e-6,
                       .i2 = 4.410e-7,
                       .i3 = 5.255e-6,
                       .i4 = 5.667e-7,
                       .i5 = 1.169e-5,
                       .i6 = 5.667e-7,
                       .i7 = 1.912e-5,
                       .d = 28e-3,
                       .da = 115e-4,
                       .e = 2e-2,
                       .ea = 1421e-5,
                       .rr = 7e-3,
                       .ra = 92e-5,
                       .l0 = 7785e-5,
                       .ss = 35e-3,
                       .sa = 1874e-5,
                       .sb = 1043e-5,
                       .sc = 18e-3,
                       .sd = 2e-2,
                       .ta = 2308e-5,
                       .tb = 916e-5,
                       .u = 4e-2,
                       .ua = 1228e-5,
                       .ub = 449e-5,
                       .zf = 2e-2,
                       .zt = 4e-2,
                       .fa = 1421e-5,
                       .mom = 33e-3};
}

static int andrews_mass(double t, const double *q, double *M, void *params) {
  const bench_andrews *p = params;
  double e4 = p->e - p->ea, f6 = p->zf - p->fa, coth = cos(q[1]);
  double siph = sin(q[3]), siom = sin(q[5]);
  (void)t;
  memset(M, 0, 49 * sizeof *M);
  M[0] = p->m1 * p->ra * p->ra +
         p->m2 * (p->rr * p->rr - 2 * p->da * p->rr * coth + p->da * p->da) + p->i1 + p->i2;
  M[1] = M[7] = p->m2 * (p->da * p->da - p->da * p->rr * coth) + p->i2;
  M[8] = p->m2 * p->da * p->da + p->i2;
  M[16] = p->m3 * (p->sa * p->sa + p->sb * p->sb) + p->i3;
  M[24] = p->m4 * e4 * e4 + p->i4;
  M[25] = M[31] = p->m4 * (e4 * e4 + p->zt * e4 * siph) + p->i4;
  M[32] = p->m4 * (p->zt * p->zt + 2 * p->zt * e4 * siph + e4 * e4) +
          p->m5 * (p->ta * p->ta + p->tb * p->tb) + p->i4 + p->i5;
  M[40] = p->m6 * f6 * f6 + p->i6;
  M[41] = M[47] = p->m6 * (f6 * f6 - p->u * f6 * siom) + p->i6;
  M[48] = p->m6 * (f6 * f6 - 2 * p->u * f6 * siom + p->u * p->u) +
          p->m7 * (p->ua * p->ua + p->ub * p->ub) + p->i6 + p->i7;
  return 0;
}

/* (d/ds M(q + s v)) v: M depends on theta = q[1] (through cos), phi = q[3] and omega = q[5]
 * (through sin), each in one 2 x 2 block with the off-diagonal entry changing at half the rate
 * of the second diagonal one (of the first, for theta's block):
 *   d/ds M_00 = 2 a, d/ds M_01 = a,  a = m2 da rr sin(theta) theta'
 *   d/ds M_34 = b,   d/ds M_44 = 2 b, b = m4 zt (e - ea) cos(phi) phi'
 *   d/ds M_56 = w,   d/ds M_66 = 2 w, w = -m6 u (zf - fa) cos(omega) omega'
 * the Test Set's force carries the same terms (its r2, r4, r6). */
static int andrews_mass_dot_v(double t, const double *q, const double *v, double *out,
                              void *params) {
  const bench_andrews *p = params;
  double a = p->m2 * p->da * p->rr * sin(q[1]) * v[1];
  double b = p->m4 * p->zt * (p->e - p->ea) * cos(q[3]) * v[3];
  double w = -p->m6 * p->u * (p->zf - p->fa) * cos(q[5]) * v[5];
  (void)t;
  out[0] = a * (2 * v[0] + v[1]);
  out[1] = a * v[0];
  out[2] = 0.0;
  out[3] = b * v[4];
  out[4] = b * (v[3] + 2 * v[4]);
  out[5] = w * v[6];
  out[6] = w * (v[5] + 2 * v[6]);
  return 0;
}

/* The spring's length |D - C| and d|D - C|/dgamma, D = (sd cos gamma + sc sin gamma + xb,
 * sd sin gamma - sc cos gamma + yb) the spring's end on body 3 */
static double andrews_spring(const bench_andrews *p, double gamma, double *dlen) {
  double sg = sin(gamma), cg = cos(gamma);
  double dx = p->sd * cg + p->sc * sg + p->xb - p->xc, dy = p->sd * sg - p->sc * cg + p->yb - p->yc;
  double len = hypot(dx, dy);
  *dlen = (dx * (p->sc * cg - p->sd * sg) + dy * (p->sd * cg + p->sc * sg)) / len;
  return len;
}

/* the Test Set's f: the torque, the spring, and the Lagrangian's velocity terms of M(q) */
static int andrews_force(double t, const double *q, const double *v, double *F, void *params) {
  const bench_andrews *p = params;
  double dlen, len = andrews_spring(p, q[2], &dlen);
  double r2 = p->m2 * p->da * p->rr * sin(q[1]);
  double r4 = p->m4 * p->zt * (p->e - p->ea) * cos(q[3]);
  double r6 = p->m6 * p->u * (p->zf - p->fa) * cos(q[5]);
  (void)t;
  F[0] = p->mom - r2 * v[1] * (v[1] + 2 * v[0]);
  F[1] = r2 * v[0] * v[0];
  F[2] = -p->c0 * (len - p->l0) * dlen;
  F[3] = r4 * v[4] * v[4];
  F[4] = -r4 * v[3] * (v[3] + 2 * v[4]);
  F[5] = -r6 * v[6] * v[6];
  F[6] = r6 * v[5] * (v[5] + 2 * v[6]);
  return 0;
}

/* the three loops from the joint of bodies 1 and 2, (rr cos beta - d cos(beta + theta), ...):
 * to B over body 3, and to A over bodies 4-5 and over bodies 6-7 */
static int andrews_constraint(double t, const double *q, double *c, void *params) {
  const bench_andrews *p = params;
  double bx = p->rr * cos(q[0]) - p->d * cos(q[0] + q[1]);
  double by = p->rr * sin(q[0]) - p->d * sin(q[0] + q[1]);
  (void)t;
  c[0] = bx - p->ss * sin(q[2]) - p->xb;
  c[1] = by + p->ss * cos(q[2]) - p->yb;
  c[2] = bx - p->e * sin(q[3] + q[4]) - p->zt * cos(q[4]) - p->xa;
  c[3] = by + p->e * cos(q[3] + q[4]) - p->zt * sin(q[4]) - p->ya;
  c[4] = bx - p->zf * cos(q[5] + q[6]) - p->u * sin(q[6]) - p->xa;
  c[5] = by - p->zf * sin(q[5] + q[6]) + p->u * cos(q[6]) - p->ya;
  return 0;
}

static int andrews_jacobian(double t, const double *q, double *G, void *params) {
  const bench_andrews *p = params;
  double sbt = sin(q[0] + q[1]), cbt = cos(q[0] + q[1]);
  double spd = sin(q[3] + q[4]), cpd = cos(q[3] + q[4]);
  double soe = sin(q[5] + q[6]), coe = cos(q[5] + q[6]);
  /* d(bx, by)/d(beta, theta), shared by the three loops */
  double bx_b = -p->rr * sin(q[0]) + p->d * sbt, bx_t = p->d * sbt;
  double by_b = p->rr * cos(q[0]) - p->d * cbt, by_t = -p->d * cbt;
  (void)t;
  memset(G, 0, 42 * sizeof *G);
  for (int k = 0; k < 3; k++) {
    G[14 * k] = bx_b, G[14 * k + 1] = bx_t;
    G[14 * k + 7] = by_b, G[14 * k + 8] = by_t;
  }
  G[2] = -p->ss * cos(q[2]);
  G[9] = -p->ss * sin(q[2]);
  G[17] = -p->e * cpd, G[18] = -p->e * cpd + p->zt * sin(q[4]);
  G[24] = -p->e * spd, G[25] = -p->e * spd - p->zt * cos(q[4]);
  G[33] = p->zf * soe, G[34] = p->zf * soe - p->u * cos(q[6]);
  G[40] = -p->zf * coe, G[41] = -p->zf * coe - p->u * sin(q[6]);
  return 0;
}

/* Gdot = sum_k dG/dq_k v_k, entry by entry from andrews_jacobian: every entry is a sum of
 * sin or cos of one angle or of a sum of two, whose derivative along v is the cos or -sin of it
 * times that angle's rate (beta' + theta', phi' + delta', omega' + epsilon' for the sums) */
static int andrews_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                                void *params) {
  const bench_andrews *p = params;
  double sbt = sin(q[0] + q[1]), cbt = cos(q[0] + q[1]), wbt = v[0] + v[1];
  double spd = sin(q[3] + q[4]), cpd = cos(q[3] + q[4]), wpd = v[3] + v[4];
  double soe = sin(q[5] + q[6]), coe = cos(q[5] + q[6]), woe = v[5] + v[6];
  /* d/ds of bx_b = -rr sin beta + d sin(beta + theta), bx_t = d sin(beta + theta),
   * by_b = rr cos beta - d cos(beta + theta), by_t = -d cos(beta + theta) */
  double bx_b = -p->rr * cos(q[0]) * v[0] + p->d * cbt * wbt, bx_t = p->d * cbt * wbt;
  double by_b = -p->rr * sin(q[0]) * v[0] + p->d * sbt * wbt, by_t = p->d * sbt * wbt;
  (void)t;
  memset(Gdot, 0, 42 * sizeof *Gdot);
  for (int k = 0; k < 3; k++) {
    Gdot[14 * k] = bx_b, Gdot[14 * k + 1] = bx_t;
    Gdot[14 * k + 7] = by_b, Gdot[14 * k + 8] = by_t;
  }
  Gdot[2] = p->ss * sin(q[2]) * v[2];
  Gdot[9] = -p->ss * cos(q[2]) * v[2];
  Gdot[17] = p->e * spd * wpd, Gdot[18] = p->e * spd * wpd + p->zt * cos(q[4]) * v[4];
  Gdot[24] = -p->e * cpd * wpd, Gdot[25] = -p->e * cpd * wpd + p->zt * sin(q[4]) * v[4];
  Gdot[33] = p->zf * coe * woe, Gdot[34] = p->zf * coe * woe + p->u * sin(q[6]) * v[6];
  Gdot[40] = p->zf * soe * woe, Gdot[41] = p->zf * soe * woe - p->u * cos(q[6]) * v[6];
  return 0;
}

static int andrews_constraint_t_dot(double t, const double *q, const double *v, double *out,
                                    void *params) {
  return fixed_constraint_t_dot(t, q, v, out, params, 6);
}

static int andrews_constraint_t(double t, const double *q, double *ct, void *params) {
  return fixed_constraint_t(t, q, ct, params, 6);
}

static int andrews_potential(double t, const double *q, double *V, void *params) {
  const bench_andrews *p = params;
  double dlen, len = andrews_spring(p, q[2], &dlen);
  (void)t;
  *V = -p->mom * q[0] + p->c0 * (len - p->l0) * (len - p->l0) / 2;
  return 0;
}

void bench_andrews_system(sdae_mbs *sys, bench_andrews *p) {
  *sys = (sdae_mbs){.n_q = 7,
                    .n_c = 6,
                    .mass = andrews_mass,
                    .force = andrews_force,
                    .constraint = andrews_constraint,
                    .jacobian = andrews_jacobian,
                    .constraint_t = andrews_constraint_t,
                    .potential = andrews_potential,
                    .params = p,
                    .mass_dot_v = andrews_mass_dot_v,
                    .jacobian_dot = andrews_jacobian_dot,
                    .constraint_t_dot = andrews_constraint_t_dot};
}

void bench_andrews_initial(double *q, double *v) {
  /* the Test Set's init (Hairer and Wanner II, VII.7): a consistent position at rest */
  static const double q0[7] = {
      -0.0617138900142764496358948458001, 0.0,
      0.455279819163070380255912382449,   0.222668390165885884674473185609,
      0.487364979543842550225598953530,   -0.222668390165885884674473185609,
      1.23054744454982119249735015568};
  memcpy(q, q0, sizeof q0);
  memset(v, 0, 7 * sizeof *v);
}

/* ---- the Test Set's reference solutions (subroutine solut), as published, in its signs ---- */

/* car axis at t = 3: xl, yl, xr, yr, their velocities, lam1, lam2 (RADAU5 at tight
 * tolerances) */
static const double car_axis_ref[10] = {0.493455784275402809122e-1,  0.496989460230171153861,
                                        0.104174252488542151681e1,   0.373911027265361256927,
                                        -0.770583684040972357970e-1, 0.744686658723778553466e-2,
                                        0.175568157537232222276e-1,  0.770341043779251976443,
                                        -0.473688659084893324729e-2, -0.110468033125734368808e-2};

void bench_car_axis_reference(double *q, double *v, double *lambda) {
  memcpy(q, car_axis_ref, 4 * sizeof *q);
  memcpy(v, car_axis_ref + 4, 4 * sizeof *v);
  for (size_t j = 0; j < 2; j++) lambda[j] = -car_axis_ref[8 + j]; /* + G^T lambda there */
}

/* Andrews at t = 0.03: the 7 angles, 7 rates, then (after the 7 accelerations, left out) the 6
 * multipliers; PSIDE at tolerances 1e-14 (Cray C90), good to about 1e-10 in positions and 3e-8
 * in velocities */
static const double andrews_ref[20] = {
    0.1581077119629904e+2,  -0.1575637105984298e+2, 0.4082224013073101e-1, -0.5347301163226948e+0,
    0.5244099658805304e+0,  0.5347301163226948e+0,  0.1048080741042263e+1, 0.1139920302151208e+4,
    -0.1424379294994111e+4, 0.1103291221937134e+2,  0.1929337464421385e+2, 0.5735699284790808e+0,
    -0.1929337464421385e+2, 0.3231791658026955e+0,  0.1991753333731910e+3, -0.2975531228015052e+2,
    0.2306654119098399e+2,  0.3145271365475927e+2,  0.2264249232082739e+2, 0.1161740700019673e+2};

void bench_andrews_reference(double *q, double *v, double *lambda) {
  memcpy(q, andrews_ref, 7 * sizeof *q);
  memcpy(v, andrews_ref + 7, 7 * sizeof *v);
  memcpy(lambda, andrews_ref + 14, 6 * sizeof *lambda); /* the same sign as ours */
}
