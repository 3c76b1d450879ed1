/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A truss: point masses m on massless rods, in the plane or in space, the topologies multibody
 * codes are tried on (truss.c): a cart on a rail carrying k pendulums (one coordinate in k
 * constraints), a ladder of four-bar cells between two walls (a closed loop per cell), a cloth
 * of n x n masses on rods pinned at two opposite corners (loops in 3D), a binary tree of
 * pendulums. Each starts at rest off every singular configuration (no straight run of rods
 * between two anchors). The
 * coordinates are the masses' positions (dim each), gravity ga along the last axis; a rod joins
 * two masses or a mass and a fixed anchor, c = (|p_a - p_b|^2 - L^2) / 2 with L its length at
 * the start, and a rail holds one coordinate of a mass, c = x_a,k - its start. With `sparse` the
 * mass and the Jacobian are given by their patterns (<stabdae/pattern.h>), otherwise dense (the
 * same mechanism both ways). Exact derivatives along the motion: M constant, Gdot the rods'
 * rows in v, c independent of t. */
#ifndef STABDAE_EXAMPLES_TRUSS_H
#define STABDAE_EXAMPLES_TRUSS_H

#include <stddef.h>

#include <stabdae/mbs.h>

typedef struct mech_truss_link {
  size_t a, b; /* masses; b >= n_masses names anchor b - n_masses; a rail: b == a, axis k */
  size_t axis;
  double length2; /* a rod's squared length; a rail's coordinate */
} mech_truss_link;

typedef struct mech_truss {
  size_t dim, n_masses, n_anchors, n_links;
  double m, ga;
  int sparse;
  double *start;          /* n_masses x dim: the start, at rest */
  double *anchors;        /* n_anchors x dim */
  mech_truss_link *links; /* the constraints, in order */
  /* the patterns and their arrays (mech_truss_system allocates them; mech_truss_free) */
  sdae_pattern mass_pattern, jacobian_pattern;
  size_t *arrays;
} mech_truss;

/* the topologies, unit masses and ga = 9.81, given by their patterns with sparse; 0, or -1 when
 * memory runs out (mech_truss_free in either case) */
int mech_truss_star(mech_truss *p, size_t k, int sparse);     /* 2 + 2 k coordinates */
int mech_truss_ladder(mech_truss *p, size_t n, int sparse);   /* n >= 3 cells, 4 n coordinates */
int mech_truss_cloth(mech_truss *p, size_t n, int sparse);    /* n >= 2, 3 (n^2 - 2) coordinates */
int mech_truss_tree(mech_truss *p, size_t depth, int sparse); /* 2 (2^depth - 1) coordinates */
/* sys from p: 0, or -1 when the patterns' arrays cannot be allocated */
int mech_truss_system(sdae_mbs *sys, mech_truss *p);
void mech_truss_free(mech_truss *p);
/* the start (on the constraints, at rest) into q, v (dim n_masses each) */
void mech_truss_start(const mech_truss *p, double *q, double *v);

#endif /* STABDAE_EXAMPLES_TRUSS_H */
