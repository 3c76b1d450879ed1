/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Bricard's mechanism, the IFToMM benchmark A04 (Gonzalez, Dopico, Lugris, Cuadrado, Multibody
 * System Dynamics 16, 2006): five rods of length 1 and mass m joined in a closed loop by six
 * revolute joints, at P_0 = (0, 0, 0), P_1 = (1, 0, 0), P_2 = (1, -1, 0), P_3 = (1, -1, 1), P_4 =
 * (0, -1, 1), P_5 = (0, 0, 1) with axes y, z, x, y, z, x; P_0, P_5 and their axes fixed (the
 * ground). Gruebler's count gives no degree of freedom; the axes' arrangement leaves one, so the
 * constraints are redundant all along the motion. Natural coordinates, as the benchmark's authors
 * write it: q = (P_1, P_2, P_3, P_4, u_1, u_2, u_3, u_4), n_q = 24, u_k the unit axis at P_k
 * (massless). Per rod i from P_i to P_{i+1}, d = P_{i+1} - P_i: (|d|^2 - 1) / 2, d . u_i,
 * d . u_{i+1} and u_i . u_{i+1} (each rod's two axes stay perpendicular), then (|u_k|^2 - 1) / 2
 * for k = 1..4: n_c = 24 of rank 23. Slender rods (kinetic energy m (|P_a'|^2 + P_a' . P_b' +
 * |P_b'|^2) / 6; the cross-section's inertia about the rod left out), gravity ga along -y, from
 * rest. Exact derivatives along the motion (G is affine in q), and the potential. */
#ifndef STABDAE_EXAMPLES_BRICARD_H
#define STABDAE_EXAMPLES_BRICARD_H

#include <stabdae/mbs.h>

typedef struct mech_bricard {
  double m, ga;
} mech_bricard;

#define MECH_BRICARD_NQ 24
#define MECH_BRICARD_NC 24

/* the benchmark's: m = 1, ga = 9.81 */
mech_bricard mech_bricard_benchmark(void);
/* the mechanism with all its constraints and rank = 23 */
void mech_bricard_system(sdae_mbs *sys, mech_bricard *p);
/* the benchmark's start, at rest */
void mech_bricard_start(double *q, double *v);

#endif /* STABDAE_EXAMPLES_BRICARD_H */
