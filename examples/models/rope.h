/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A rope: N point masses m on massless rods of length L in the plane, the first hung from the
 * origin, in Cartesian coordinates q = (x_1, y_1, ..., x_N, y_N) (2N), gravity ga along -y; N
 * constraints c_j = (|p_j - p_{j-1}|^2 - L^2) / 2 (p_0 the origin), and with `closed` one more,
 * the last mass on a rod of length L to the anchor D = (anchor_x, 0): a closed loop. A
 * mechanism of multibody practice whose every row of M and G holds at most four nonzeros: with
 * `sparse` it gives its mass and Jacobian in patterns (<stabdae/pattern.h>), otherwise dense
 * (the same mechanism both ways). Exact derivatives along the motion: M constant, Gdot the
 * rows' differences in v, c independent of t. */
#ifndef STABDAE_EXAMPLES_ROPE_H
#define STABDAE_EXAMPLES_ROPE_H

#include <stddef.h>

#include <stabdae/mbs.h>

typedef struct mech_rope {
  size_t N;
  double L, m, ga, anchor_x;
  int closed, sparse;
  /* the patterns and their arrays (mech_rope_system allocates them; mech_rope_free) */
  sdae_pattern mass_pattern, jacobian_pattern;
  size_t *arrays;
} mech_rope;

/* The rope the suites and the benchmarks step: unit masses and rods, ga = 9.81, closed to the
 * anchor at x = (N + 1) / 2, half its length away; given by its patterns with sparse. */
mech_rope mech_rope_unit(size_t N, int closed, int sparse);
/* sys from p (p's N, L, m, ga, anchor_x, closed, sparse set): 0, or -1 when the patterns'
 * arrays cannot be allocated */
int mech_rope_system(sdae_mbs *sys, mech_rope *p);
void mech_rope_free(mech_rope *p);
/* constraints: N, or N + 1 closed */
size_t mech_rope_constraints(const mech_rope *p);
/* A start on the constraints, at rest: the rope straight from the origin at angle a below the
 * horizontal (open); closed, a symmetric V from the origin to the anchor, which needs
 * anchor_x < (N + 1) L and N odd (its middle mass the V's bottom). 0, or -1 when it cannot. */
int mech_rope_start(const mech_rope *p, double a, double *q, double *v);

#endif /* STABDAE_EXAMPLES_ROPE_H */
