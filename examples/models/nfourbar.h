/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The N-four-bar of the IFToMM benchmark library (problem A02; Gonzalez, Dopico, Lugris,
 * Cuadrado, Multibody System Dynamics 16, 2006): N four-bars in a row, 2N + 1 uniform rods of
 * length 1 and mass m, in natural coordinates (the benchmark authors' own: a constant mass
 * matrix). The rockers turn about the ground pivots A_i = (i, 0), i = 0..N; the couplers join
 * their tips B_{i-1} and B_i. q = (x_0, y_0, ..., x_N, y_N), n_q = 2N + 2; constraints, the
 * rockers first: c_i = (|B_i - A_i|^2 - 1) / 2, then c_{N+i} = (|B_i - B_{i-1}|^2 - 1) / 2,
 * n_c = 2N + 1; gravity ga along -y. One degree of freedom, but where the rockers are
 * horizontal (flat) the rank of G drops from 2N + 1 to N + 1: a singular configuration the
 * motion crosses twice a turn. Exact derivatives along the motion (M constant, c independent of
 * t), and the potential, so that every map of the library runs it. */
#ifndef STABDAE_EXAMPLES_NFOURBAR_H
#define STABDAE_EXAMPLES_NFOURBAR_H

#include <stddef.h>

#include <stabdae/mbs.h>

typedef struct mech_nfourbar {
  size_t N;
  double m, ga;
  /* sparse: M and G given by their patterns (the sparse back-end), their arrays allocated by
   * mech_nfourbar_system (mech_nfourbar_free): M's nonzeros couple each coordinate with the
   * same one of the neighbouring tips (6 N + 2 of them), a rocker's row of G holds its tip's
   * two coordinates, a coupler's its two tips' four (6 N + 2) */
  int sparse;
  sdae_pattern mass_pattern, jacobian_pattern;
  size_t *arrays;
} mech_nfourbar;

/* the benchmark's: N = 40, m = 1, ga = 9.81, dense */
mech_nfourbar mech_nfourbar_benchmark(void);
/* 0, or -1 when the patterns' arrays cannot be allocated */
int mech_nfourbar_system(sdae_mbs *sys, mech_nfourbar *p);
void mech_nfourbar_free(mech_nfourbar *p);
/* the benchmark's start: the rockers upright (B_i = (i, 1)), every B_i at (1, 0) m/s */
void mech_nfourbar_start(const mech_nfourbar *p, double *q, double *v);
/* B_0 (2 values) at t on the benchmark's motion, from the parallelogram it keeps: every rocker
 * at the angle theta from the upright, J theta'' = K ga sin theta with J = (N + 1) m / 3 + N m
 * (the rockers turning about their pivots, the couplers translating) and K = (N + 1) m / 2 + N m,
 * theta(0) = 0, theta'(0) = 1: a pendulum turning over, solved by Jacobi's elliptic functions
 * (GSL). */
void mech_nfourbar_reference(const mech_nfourbar *p, double t, double *b0);

#endif /* STABDAE_EXAMPLES_NFOURBAR_H */
