/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The reference for the FMUs' inputs: the example programs' four-bar or slider crank with a
 * constant generalized force u as its forces from outside the Lagrangian (input_force),
 * integrated by sdae_mbs_integrate from the programs'
 * start with their settings (scheme 15, delta 2, epsilon 1, map dgrad), written as CSV
 * t,q1..qn,v1..vn every `every` steps (and the last). Its own force wrapper, not the FMU's.
 *   fmi_reference_u fourbar|slider_crank T nsteps every u1 ... un */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stabdae/mbs.h>

#include "benchmarks.h"
#include "mechanisms.h"

#define NMAX 8

/* the program's one mechanism's constant u (a test program may keep these) */
static double u[NMAX];
static size_t n_q;

static int push(double t, const double *q, const double *v, double *F, void *params) {
  (void)t, (void)q, (void)v, (void)params;
  memcpy(F, u, n_q * sizeof *F);
  return 0;
}

static int observe(size_t step, double t, const double *q, const double *v, void *data) {
  const double *T = data;
  (void)t;
  printf("%.17g", (double)step * *T);
  for (size_t i = 0; i < n_q; i++) printf(",%.17g", q[i]);
  for (size_t i = 0; i < n_q; i++) printf(",%.17g", v[i]);
  printf("\n");
  return 0;
}

int main(int argc, char **argv) {
  mech_fourbar fb = {1.0, 4.0, 3.0, 4.5, 1.0, 1.0, 9.81};
  bench_slider_crank sc = bench_slider_crank_default();
  sdae_mbs sys;
  double q[NMAX], v[NMAX], T;
  sdae_options o;
  sdae_mbs_stepper *s;
  int rc;
  if (argc < 5) return 2;
  if (strcmp(argv[1], "fourbar") == 0) {
    mech_fourbar_system(&sys, &fb);
    mech_fourbar_state(&fb, 0.0, 5.0, q, v);
  } else {
    bench_slider_crank_system(&sys, &sc);
    bench_slider_crank_initial(&sc, q, v);
  }
  n_q = sys.n_q;
  if ((size_t)argc != 5 + n_q) {
    fprintf(stderr, "usage: fmi_reference_u fourbar|slider_crank T nsteps every u1 ... u%zu\n",
            n_q);
    return 2;
  }
  for (size_t i = 0; i < n_q; i++) u[i] = strtod(argv[5 + i], NULL);
  sys.input_force = push;
  T = strtod(argv[2], NULL);
  sdae_options_default(&o);
  o.scheme = SDAE_SCHEME_SEMI_IMPLICIT;
  o.delta = 2.0;
  o.epsilon = 1.0;
  o.map = sdae_map_dgrad;
  if ((rc = sdae_mbs_stepper_alloc(&s, &sys, &o)) != SDAE_OK) return 1;
  rc = sdae_mbs_integrate(s, 0.0, T, strtoul(argv[3], NULL, 10), strtoul(argv[4], NULL, 10), q, v,
                          observe, &T, NULL);
  sdae_mbs_stepper_free(s);
  if (rc != SDAE_OK) fprintf(stderr, "fmi_reference_u: %s\n", sdae_strerror(rc));
  return rc == SDAE_OK ? 0 : 1;
}
