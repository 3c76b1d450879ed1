/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The three standard index-3 benchmark mechanisms in the multibody convention of
 * <stabdae/mbs.h> (M(t, q) v' = F(t, q, v) - G^T lambda, c(t, q) = 0), each with its analytic
 * jacobian and dc/dt and their derivatives along the motion (mass_dot_v, jacobian_dot,
 * constraint_t_dot), and with its potential (and damping) where the forces are a gradient, so
 * that the discrete-gradient maps apply. Every constant is the published one; the sources:
 *
 *   slider crank  SUNDIALS, examples/ida/serial/idaSlCrank_dns.c (R. Serban, after E. J. Haug,
 *                 Computer-Aided Kinematics and Dynamics of Mechanical Systems, 1989)
 *   car axis      Test Set for IVP Solvers (Bari), problem caraxis; Hairer and Wanner, Solving
 *                 ODEs II, Section VII.7 (after Rentrop)
 *   Andrews       Test Set for IVP Solvers, problem andrews; Hairer and Wanner II, VII.7 */
#ifndef STABDAE_EXAMPLES_BENCHMARKS_H
#define STABDAE_EXAMPLES_BENCHMARKS_H

#include <stabdae/mbs.h>

/* Slider crank, q = (theta, x, phi): crank angle, slider position, connecting-rod angle;
 * M = diag(J1, m2, J2); c = (x - cos phi - a cos theta, -sin phi - a sin theta) (rod length 1);
 * a spring-damper between the crank's midpoint P = (a/2)(cos theta, sin theta) and the rod's
 * R = (x - cos phi / 2, -sin phi / 2), of length l = |R - P|, and the constant force F with
 * the generalized force (0, F, -F sin phi):
 *   V = k (l - l0)^2 / 2 - F (x + cos phi),   D = c grad l grad l^T,   F(q, v) = -grad V - D v.
 * idaSlCrank_dns: a 0.5, J1 1, m2 1, J2 2, k 1, c 1, l0 1, F 1, t in [0, 10]. */
typedef struct bench_slider_crank {
  double a, J1, m2, J2, k, c, l0, F;
} bench_slider_crank;
bench_slider_crank bench_slider_crank_default(void); /* idaSlCrank_dns's constants */
void bench_slider_crank_system(sdae_mbs *sys, bench_slider_crank *p);
/* idaSlCrank_dns's start, at rest: theta = pi/2, phi = asin(-a), x = cos phi (needs a < 1) */
void bench_slider_crank_initial(const bench_slider_crank *p, double *q, double *v);

/* Car axis, q = (xl, yl, xr, yr): the axis' two ends, each on a spring of rest length L0, the
 * left one to the origin and the right one to the wheel (xb, yb) = (sqrt(L^2 - yb^2),
 * r sin(w t)) rolling over a bump; M = k I with k = mass eps^2 / 2 (the Test Set's first-order
 * form k v' = f); c = (xb xl + yb yl, (xl - xr)^2 + (yl - yr)^2 - L^2);
 * F = (L0 - Ll) (xl, yl)/Ll - (0, k g) and (L0 - Lr) (xr - xb, yr - yb)/Lr - (0, k g).
 * The Test Set writes k v' = f + G^T lambda: its multipliers are minus these. V would depend
 * on t through the wheel: no potential, so the discrete-gradient maps do not apply.
 * Test Set: eps 1e-2, mass 10, L 1, L0 0.5, r 0.1, w 10, g 1, t in [0, 3]. */
typedef struct bench_car_axis {
  double eps, mass, L, L0, r, w, g;
} bench_car_axis;
bench_car_axis bench_car_axis_default(void); /* the Test Set's constants */
void bench_car_axis_system(sdae_mbs *sys, bench_car_axis *p);
/* The Test Set's start q = (0, L0, L, L0), v = (-L0/L, 0, -L0/L, 0), written with
 * xl' = xr' = -r w L0 / L so that it stays on c = 0, G v + dc/dt = 0 for any r w (1 there) */
void bench_car_axis_initial(const bench_car_axis *p, double *q, double *v);
/* The Test Set's reference solution at t = 3 for the published constants: q, v (4 each) and
 * lambda (2) in our sign (minus the Test Set's) */
void bench_car_axis_reference(double *q, double *v, double *lambda);

/* Andrews' squeezing mechanism, q = (beta, theta, gamma, phi, delta, omega, epsilon): seven
 * rigid bodies, six constraints (three loops closed at the fixed points A, B), M(q) and c(q) as
 * in the Test Set; the driving torque mom on beta and a spring c0 of rest length l0 between the
 * fixed point C and the point D of body 3:
 *   V = -mom beta + c0 (|D(gamma) - C| - l0)^2 / 2,
 *   F = -grad V - (dM/dt) v + (1/2) d/dq (v^T M v)   (the Test Set's f, the Lagrangian's force).
 * The Test Set's multipliers are these (M w = f - G^T lambda there too). Its 42 constants, in
 * its order; bench_andrews_default fills them. t in [0, 0.03]. */
typedef struct bench_andrews {
  double m1, m2, m3, m4, m5, m6, m7, xa, ya, xb, yb, xc, yc, c0;
  double i1, i2, i3, i4, i5, i6, i7, d, da, e, ea, rr, ra, l0;
  double ss, sa, sb, sc, sd, ta, tb, u, ua, ub, zf, zt, fa, mom;
} bench_andrews;
void bench_andrews_default(bench_andrews *p);
void bench_andrews_system(sdae_mbs *sys, bench_andrews *p);
/* The Test Set's consistent start, at rest (for the default geometry) */
void bench_andrews_initial(double *q, double *v);
/* The Test Set's reference solution at t = 0.03 for the published constants: q, v (7 each)
 * and lambda (6); good to about 1e-10 in positions and 3e-8 in velocities */
void bench_andrews_reference(double *q, double *v, double *lambda);

#endif /* STABDAE_EXAMPLES_BENCHMARKS_H */
