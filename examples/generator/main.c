/* SPDX-License-Identifier: GPL-3.0-or-later */
/* cart: the cart with a pendulum of cart_pendulum.py (cart_pendulum.h and .c are generated at
 * build time by stabdae_generate_mbs), integrated for 10 s in steps of 1e-3 s from the start
 * state of the description. Writes CSV, a row every 10 steps:
 *
 *     t,x,y,px,py,vx,vy,vpx,vpy,energy,max_abs_c
 *
 * to stdout, or to OUT.csv. The map is the discrete gradient ("dgrad"), which conserves the
 * energy v^T M v / 2 + V(q) to Newton's tolerance; --map=NAME takes any other map of the
 * library (midpoint, rk4, dg4, ...).
 * A line on stderr tells the work done: steps, Newton iterations, chart switches.
 * Usage: cart [--map=NAME] [OUT.csv]; exit 0 on success, 1 when the run fails, 2 on bad
 * arguments. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <stabdae/mbs.h>

#include "cart_pendulum.h"

#define STEP 1e-3
#define STEPS 10000 /* 10 s: several swings of the pendulum and of the cart on its spring */
#define EVERY 10

/* what the observer writes with, and the first failure it met */
typedef struct output {
  FILE *f;
  sdae_mbs_stepper *s;
  const sdae_mbs *sys;
  int rc;
} output;

static void header(FILE *f) {
  fputs("t", f);
  for (size_t i = 0; i < CART_PENDULUM_N_Q; i++)
    fprintf(f, ",%s", cart_pendulum_coordinate_name(i));
  for (size_t i = 0; i < CART_PENDULUM_N_Q; i++)
    fprintf(f, ",v%s", cart_pendulum_coordinate_name(i));
  fputs(",energy,max_abs_c\n", f);
}

/* one row: the state, its energy, and the largest constraint residual, computed by the
 * mechanism's own constraint callback (the quantity the library keeps at zero) */
static int row(size_t step, double t, const double *q, const double *v, void *data) {
  output *o = data;
  double E, c[CART_PENDULUM_N_C], worst = 0;
  (void)step;
  if ((o->rc = sdae_mbs_energy(o->s, t, q, v, &E)) != SDAE_OK) return 1;
  int cb = o->sys->constraint(t, q, c, o->sys->params);
  if (cb != 0) {
    o->rc = cb < 0 ? SDAE_ERR_CALLBACK_FATAL : SDAE_ERR_CALLBACK_RECOVERABLE;
    return 1;
  }
  for (size_t j = 0; j < CART_PENDULUM_N_C; j++) worst = fmax(worst, fabs(c[j]));
  /* 17 digits: the energy's changes are near rounding, and the plot shows them */
  fprintf(o->f, "%.17g", t);
  for (size_t i = 0; i < CART_PENDULUM_N_Q; i++) fprintf(o->f, ",%.17g", q[i]);
  for (size_t i = 0; i < CART_PENDULUM_N_Q; i++) fprintf(o->f, ",%.17g", v[i]);
  fprintf(o->f, ",%.17g,%.3e\n", E, worst);
  return 0;
}

static int usage(const char *why) {
  fprintf(stderr, "cart: %s\nusage: cart [--map=NAME] [OUT.csv]\n", why);
  return 2;
}

int main(int argc, char **argv) {
  const char *path = NULL, *map = "dgrad";
  for (int i = 1; i < argc; i++) {
    if (strncmp(argv[i], "--map=", 6) == 0)
      map = argv[i] + 6;
    else if (argv[i][0] == '-' && argv[i][1] != '\0')
      return usage("unknown option");
    else if (path)
      return usage("more than one output file");
    else
      path = argv[i];
  }

  sdae_options opt;
  sdae_options_default(&opt); /* the semi-implicit scheme 15: attractive for every step */
  opt.map = sdae_map_by_name(map);
  if (!opt.map) return usage("unknown map (euler, midpoint, dgrad, dg4, rk4, ...)");

  cart_pendulum_params p;
  cart_pendulum_params_default(&p);
  sdae_mbs sys = cart_pendulum_mbs(&p);
  double q[CART_PENDULUM_N_Q], v[CART_PENDULUM_N_Q];
  cart_pendulum_start(&p, q, v);

  sdae_mbs_stepper *s = NULL;
  int rc = sdae_mbs_stepper_alloc(&s, &sys, &opt);
  if (rc != SDAE_OK) {
    fprintf(stderr, "cart: the stepper: %s\n", sdae_strerror(rc));
    return 1;
  }
  FILE *f = path ? fopen(path, "w") : stdout;
  if (!f) {
    sdae_mbs_stepper_free(s);
    fprintf(stderr, "cart: cannot write %s: %s\n", path, strerror(errno));
    return 2;
  }

  output o = {f, s, &sys, SDAE_OK};
  size_t done = 0;
  header(f);
  rc = sdae_mbs_integrate(s, 0.0, STEP, STEPS, EVERY, q, v, row, &o, &done);
  if (rc == SDAE_STOPPED) rc = o.rc; /* the observer stopped the run: its reason */
  if (rc != SDAE_OK) {
    fprintf(stderr, "cart: stopped after %zu steps (t = %g): %s\n", done, (double)done * STEP,
            sdae_strerror(rc));
  } else { /* the work, on stderr: the CSV stays the data alone */
    const sdae_mbs_stats *st = sdae_mbs_stepper_stats(s);
    fprintf(stderr, "cart: %lu steps with %s, %.2f Newton iterations a step, %lu chart switches\n",
            st->step.steps, sdae_map_name(opt.map),
            (double)st->step.newton_iters_total / (double)st->step.steps, st->chart_switches);
  }
  sdae_mbs_stepper_free(s);
  /* a write that failed on the way (a full disk, a closed pipe) leaves the error flag set */
  int failed = ferror(f) != 0;
  if (path ? fclose(f) != 0 : fflush(f) != 0) failed = 1;
  if (failed) {
    fprintf(stderr, "cart: writing %s failed\n", path ? path : "stdout");
    return 1;
  }
  return rc != SDAE_OK;
}
