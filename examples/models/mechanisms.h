/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Three mechanisms in the multibody convention of <stabdae/mbs.h> (M v' = F - G^T lambda,
 * c(q) = 0): a pendulum and a double pendulum in Cartesian coordinates, and a four-bar
 * linkage (a closed loop). Point masses, gravity ga along -y, each with its potential so that
 * the discrete-gradient maps conserve the energy, and with the exact derivatives along the
 * motion (mass_dot_v = 0, jacobian_dot the rows' differences in v). The one definition of
 * these mechanisms: the example programs, the unit suites (tests/) and the tools (IDA,
 * benchmarks) all link it. */
#ifndef STABDAE_EXAMPLES_MECHANISMS_H
#define STABDAE_EXAMPLES_MECHANISMS_H

#include <stabdae/mbs.h>

/* q = (x, y): a mass m on a massless rod of length L from the origin;
 * c = (x^2 + y^2 - L^2)/2, V = m ga y; with d != 0 also the damping D = d I (F gains -d v).
 * theta is the angle from the downward vertical: x = L sin theta, y = -L cos theta. */
typedef struct mech_pendulum {
  double L, m, ga, d; /* d: damping coefficient (0: none) */
} mech_pendulum;
/* mass, force, constraint, jacobian, potential and the derivatives along the motion
 * (mass_dot_v = 0, jacobian_dot = (v_x, v_y)) set; damping when p->d != 0 */
void mech_pendulum_system(sdae_mbs *sys, mech_pendulum *p);
/* The callbacks one by one (params: a mech_pendulum), for a system built around them. */
int mech_pendulum_mass(double t, const double *q, double *M, void *params);
int mech_pendulum_force(double t, const double *q, const double *v, double *F, void *params);
int mech_pendulum_constraint(double t, const double *q, double *c, void *params);
int mech_pendulum_jacobian(double t, const double *q, double *G, void *params);
int mech_pendulum_mass_dot_v(double t, const double *q, const double *v, double *out, void *params);
int mech_pendulum_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                               void *params);
int mech_pendulum_potential(double t, const double *q, double *V, void *params);
int mech_pendulum_damping(double t, const double *q, double *D, void *params);
/* (q, v) at the angle theta turning at omega: on the circle, v tangent to it. */
void mech_pendulum_state(const mech_pendulum *p, double theta, double omega, double *q, double *v);
/* The exact undamped swing from rest at theta0 (Jacobi elliptic functions): theta(t), omega(t). */
void mech_pendulum_exact(const mech_pendulum *p, double theta0, double t, double *theta,
                         double *omega);
/* The multiplier at (theta, omega), the rod's tension: m (L omega^2 + ga cos theta) / L. */
double mech_pendulum_lambda(const mech_pendulum *p, double theta, double omega);

/* q = (x1, y1, x2, y2): m1 on a rod L1 from the origin, m2 on a rod L2 from m1;
 * c = ((|p1|^2 - L1^2)/2, (|p2 - p1|^2 - L2^2)/2), V = ga (m1 y1 + m2 y2). */
typedef struct mech_double_pendulum {
  double L1, L2, m1, m2, ga;
} mech_double_pendulum;
void mech_double_pendulum_system(sdae_mbs *sys, mech_double_pendulum *p);
/* The state at the angles a (from the downward vertical) and their rates w. */
void mech_double_pendulum_state(const mech_double_pendulum *p, const double *a, const double *w,
                                double *q, double *v);

/* q = (Bx, By, Cx, Cy): ground pivots A = (0, 0) and D = (d, 0), crank AB of length a,
 * coupler BC of length b, rocker CD of length e; point masses mB at B and mC at C (the bars
 * massless), M = diag(mB, mB, mC, mC); c = ((|B|^2 - a^2)/2, (|C - B|^2 - b^2)/2,
 * (|C - D|^2 - e^2)/2), V = ga (mB By + mC Cy). One degree of freedom, the crank angle
 * atan2(By, Bx). */
typedef struct mech_fourbar {
  double a, b, e, d, mB, mC, ga;
} mech_fourbar;
void mech_fourbar_system(sdae_mbs *sys, mech_fourbar *p);
/* The assembled state at crank angle theta turning at omega, C on the branch above the line
 * B-D (to its left seen from B); -1 when the loop does not close at theta. */
int mech_fourbar_state(const mech_fourbar *p, double theta, double omega, double *q, double *v);
/* Grashof's condition s + l <= p + q (shortest plus longest link at most the other two) with
 * the crank the shortest link: then the crank makes full turns. */
int mech_fourbar_crank_rocker(const mech_fourbar *p);

/* max_j |c_j(q)| of a system; < 0 when its constraint callback fails. */
double mech_max_abs_c(const sdae_mbs *sys, double t, const double *q);

#endif /* STABDAE_EXAMPLES_MECHANISMS_H */
