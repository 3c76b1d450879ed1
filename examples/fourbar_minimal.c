/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A four-bar linkage written only against <stabdae/mbs.h>: pivots A = (0, 0), D = (4.5, 0),
 * crank |AB| = 1, coupler |BC| = 4, rocker |CD| = 3, unit masses at B and C, gravity 9.81.
 * q = (Bx, By, Cx, Cy); three constraints, one degree of freedom: the crank angle. */
#include <math.h>
#include <stdio.h>

#include <stabdae/mbs.h>

static const double a = 1, b = 4, e = 3, d = 4.5, ga = 9.81;

static int mass(double t, const double *q, double *M, void *p) {
  (void)t, (void)q, (void)p;
  for (int i = 0; i < 16; i++) M[i] = i % 5 == 0; /* the 4 x 4 identity */
  return 0;
}
static int force(double t, const double *q, const double *v, double *F, void *p) {
  (void)t, (void)q, (void)v, (void)p;
  F[0] = F[2] = 0, F[1] = F[3] = -ga;
  return 0;
}
static int constraint(double t, const double *q, double *c, void *p) { /* half squares */
  double bx = q[2] - q[0], by = q[3] - q[1], ex = q[2] - d;
  (void)t, (void)p;
  c[0] = (q[0] * q[0] + q[1] * q[1] - a * a) / 2;
  c[1] = (bx * bx + by * by - b * b) / 2;
  c[2] = (ex * ex + q[3] * q[3] - e * e) / 2;
  return 0;
}
static int jacobian(double t, const double *q, double *G, void *p) { /* dc/dq, 3 x 4 */
  double bx = q[2] - q[0], by = q[3] - q[1];
  const double g[12] = {q[0], q[1], 0, 0, -bx, -by, bx, by, 0, 0, q[2] - d, q[3]};
  (void)t, (void)p;
  for (int i = 0; i < 12; i++) G[i] = g[i];
  return 0;
}
static int potential(double t, const double *q, double *V, void *p) { /* F = -dV/dq */
  (void)t, (void)p;
  *V = ga * (q[1] + q[3]);
  return 0;
}

int main(void) {
  sdae_mbs sys = {.n_q = 4,
                  .n_c = 3,
                  .mass = mass,
                  .force = force,
                  .constraint = constraint,
                  .jacobian = jacobian,
                  .potential = potential};
  sdae_options opt;
  sdae_mbs_stepper *s = NULL;
  /* the crank at angle 0 turning at 5 rad/s; C closes the loop, its velocity keeps G v = 0 */
  double h = sqrt(b * b - 2.75 * 2.75), q[4] = {a, 0, 3.75, h};
  double v[4] = {0, 5, 10 * h / 7, 15.0 / 14}, T = 1e-3, angle = 0, c[3];
  sdae_options_default(&opt);
  opt.map = sdae_map_dgrad; /* conserves v^T M v / 2 + V */
  opt.delta = 2.0;
  int rc = sdae_mbs_stepper_alloc(&s, &sys, &opt);
  printf("    t   crank angle   max|c|\n");
  for (int i = 1; i <= 5000 && rc == SDAE_OK; i++) {
    double before = atan2(q[1], q[0]);
    if ((rc = sdae_mbs_step(s, (i - 1) * T, T, q, v)) != SDAE_OK) break;
    angle += remainder(atan2(q[1], q[0]) - before, 4 * acos(0)); /* continued past +-pi */
    constraint(0, q, c, NULL);
    if (i % 500 == 0)
      printf("%5.2f  %11.6f  %.1e\n", i * T, angle, fmax(fabs(c[0]), fmax(fabs(c[1]), fabs(c[2]))));
  }
  if (rc != SDAE_OK) fprintf(stderr, "fourbar: %s\n", sdae_strerror(rc));
  sdae_mbs_stepper_free(s);
  return rc != SDAE_OK;
}
