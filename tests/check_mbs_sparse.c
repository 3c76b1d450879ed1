/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A sparse mechanism stepped by an explicit map in its own coordinates (src/mbs/mbs_sparse.c),
 * against the mathematics: rk4 and rk8 keep their orders, the constraints stay at the rounding
 * of q on a long rope, the block and the factors grow with the nonzeros, lambda, the energy and
 * xi are the dense coordinates' (the same quantities, another algebra), the state as bytes
 * continues bit for bit, and a failed step leaves no trace. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/bytes.h"
#include "mbs/mbs_impl.h"
#include "rope.h"
#include "testmodels.h"
#include "truss.h"
#include "wire.h"

static sdae_options options(const sdae_map_type *map) {
  sdae_options o = quartic_options(map, SDAE_SCHEME_SEMI_IMPLICIT);
  o.delta = 2.0, o.epsilon = 1.0;
  return o;
}

/* a stepper of the rope (its system into sys) and the rope's start */
typedef struct roped {
  mech_rope r;
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  double *q, *v;
} roped;

static void roped_init(roped *w, size_t N, int closed, int sparse, const sdae_map_type *map) {
  sdae_options o = options(map);
  w->r = mech_rope_unit(N, closed, sparse);
  ck_assert_int_eq(mech_rope_system(&w->sys, &w->r), 0);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&w->s, &w->sys, &o), SDAE_OK);
  w->q = malloc(2 * N * sizeof *w->q), w->v = malloc(2 * N * sizeof *w->v);
  ck_assert_int_eq(mech_rope_start(&w->r, 0.3, w->q, w->v), 0);
}

static void roped_free(roped *w) {
  sdae_mbs_stepper_free(w->s);
  free(w->q), free(w->v);
  mech_rope_free(&w->r);
}

/* n steps of T */
static int steps(roped *w, size_t n, double T) {
  int rc = SDAE_OK;
  for (size_t k = 0; k < n && rc == SDAE_OK; k++)
    rc = sdae_mbs_step(w->s, (double)k * T, T, w->q, w->v);
  return rc;
}

/* q after 1 s at T (the open rope of 6 masses) */
static void q_after(const sdae_map_type *map, double T, double *q) {
  roped w;
  roped_init(&w, 6, 0, 1, map);
  ck_assert_int_eq(steps(&w, (size_t)llround(1.0 / T), T), SDAE_OK);
  memcpy(q, w.q, 12 * sizeof *q);
  roped_free(&w);
}

/* a sparse mechanism with its derivatives takes the sparse coordinates under every map of the
 * library, explicit and implicit; a mechanism without a pattern or a derivative, the dense ones */
START_TEST(the_sparse_coordinates_serve_every_map) {
  const sdae_map_type *maps[] = {sdae_map_euler,    sdae_map_rk4,       sdae_map_rk8,
                                 sdae_map_midpoint, sdae_map_dgrad,     sdae_map_dg4,
                                 sdae_map_dg6,      sdae_map_midpoint4, sdae_map_midpoint6};
  for (size_t k = 0; k < sizeof maps / sizeof *maps; k++) {
    roped w;
    roped_init(&w, 4, 0, 1, maps[k]);
    ck_assert_int_eq(w.s->coords.linalg == &sdae__mbs_sparse_linalg, 1);
    roped_free(&w);
  }
  roped w;
  sdae_options o = options(sdae_map_rk4);
  sdae_mbs_stepper *s;
  roped_init(&w, 4, 0, 0, sdae_map_rk4);
  ck_assert_int_eq(w.s->coords.linalg == &sdae__mbs_sparse_linalg, 0); /* dense */
  roped_free(&w);
  roped_init(&w, 4, 0, 1, sdae_map_rk4);
  w.sys.jacobian_dot = NULL; /* differences of G: the dense stencils */
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &w.sys, &o), SDAE_OK);
  ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, 0);
  sdae_mbs_stepper_free(s);
  roped_free(&w);
}
END_TEST

/* rk4 and rk8 through the sparse coordinates: the error against rk8 at a small step falls by
 * 2^4 and 2^8 as T halves (measured 15 to 20, and 2900 and 400) */
START_TEST(rk4_and_rk8_keep_their_orders) {
  double ref[12], q[12], e[3];
  q_after(sdae_map_rk8, 0.0025, ref);
  for (int h = 0; h < 3; h++) {
    q_after(sdae_map_rk4, 0.02 / (1 << h), q);
    e[h] = max_abs_diff(q, ref, 12);
  }
  ck_assert_double_ge(e[0] / e[1], 12.0);
  ck_assert_double_ge(e[1] / e[2], 12.0);
  for (int h = 0; h < 2; h++) {
    q_after(sdae_map_rk8, 0.04 / (1 << h), q);
    e[h] = max_abs_diff(q, ref, 12);
  }
  ck_assert_double_ge(e[0] / e[1], 100.0);
}
END_TEST

/* A rope of 512 masses (1024 coordinates, q up to 512 in size): over 100 steps max |c| stays
 * within a few ulps of q's largest coordinate, where the rounding of q itself puts c; every step
 * in the chart, though its constraints' independence is about 1 / links (a chain's least
 * singular value; 4e-3 here): steady, no singular configuration (with the rule an absolute
 * 1e-2, every step of a rope of 256 links and more was projected, at 5 times the cost) */
START_TEST(constraints_at_the_rounding_of_q_on_a_long_rope) {
  roped w;
  double *c, worst = 0.0, big = 0.0;
  roped_init(&w, 512, 0, 1, sdae_map_rk4);
  c = malloc(512 * sizeof *c);
  for (int k = 0; k < 100; k++) {
    ck_assert_int_eq(sdae_mbs_step(w.s, k * 1e-3, 1e-3, w.q, w.v), SDAE_OK);
    ck_assert_int_eq(w.sys.constraint(0.0, w.q, c, w.sys.params), 0);
    for (size_t j = 0; j < 512; j++) worst = fmax(worst, fabs(c[j]));
    for (size_t i = 0; i < 1024; i++) big = fmax(big, fabs(w.q[i]));
  }
  ck_assert_double_le(worst, 8.0 * DBL_EPSILON * big);
  ck_assert_uint_eq(sdae_mbs_stepper_stats(w.s)->projected_steps, 0);
  free(c);
  roped_free(&w);
}
END_TEST

/* the block, and the chart's and the velocity system's factors, grow with the nonzeros: twice
 * the rope, at most twice (and a little) the bytes, under an explicit map and an implicit one
 * (its Newton-Krylov's GMRES holds 41 vectors of n_mu); on a chain the chart's factors have no fill
 * (each link pivots on its outer mass, solved from the free end in), and the saddle-point
 * system's L holds G's entries and the fill of its Schur complement G M^-1 G^T alone, which is
 * tridiagonal (a mass couples the rods on either side of it): N - 1 entries */
START_TEST(the_block_grows_with_the_nonzeros) {
  const sdae_map_type *maps[] = {sdae_map_rk4, sdae_map_dgrad, sdae_map_dg4};
  for (size_t k = 0; k < 3; k++) { /* an implicit map's too: no n_mu x n_mu matrix */
    sdae_options o = options(maps[k]);
    size_t bytes[2];
    for (int h = 0; h < 2; h++) {
      mech_rope r = mech_rope_unit(h ? 4096 : 2048, 0, 1);
      sdae_mbs sys;
      ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
      bytes[h] = sdae_mbs_stepper_size(&sys, &o);
      ck_assert_uint_gt(bytes[h], 0);
      mech_rope_free(&r);
    }
    ck_assert_uint_le(bytes[1], 2 * bytes[0] + bytes[0] / 20);
  }
  roped w;
  roped_init(&w, 1024, 0, 1, sdae_map_rk4);
  ck_assert_int_eq(steps(&w, 3, 1e-3), SDAE_OK);
  const sdae_sparse_lu *lu = &w.s->sparse.lu[w.s->sparse.cur];
  ck_assert_uint_eq(lu->l_start[lu->m], 0);
  ck_assert_uint_eq(lu->u_start[lu->m], w.sys.jacobian_pattern->nnz);
  ck_assert_uint_eq((size_t)w.s->sparse.ly.ksym.Lp[w.s->sparse.ly.ksym.n],
                    w.sys.jacobian_pattern->nnz + w.sys.n_c - 1);
  roped_free(&w);
}
END_TEST

/* a rope whose every mass a spring of stiffness k pulls to the vertical x = 0: the rope's
 * callbacks read the rope, the first member */
typedef struct sprung {
  mech_rope r;
  double k;
  int (*force)(double t, const double *q, const double *v, double *F, void *params);
  int (*potential)(double t, const double *q, double *V, void *params);
} sprung;

static int sprung_force(double t, const double *q, const double *v, double *F, void *params) {
  const sprung *p = params;
  int rc = p->force(t, q, v, F, params);
  for (size_t i = 0; i < p->r.N; i++) F[2 * i] -= p->k * q[2 * i];
  return rc;
}

static int sprung_potential(double t, const double *q, double *V, void *params) {
  const sprung *p = params;
  int rc = p->potential(t, q, V, params);
  for (size_t i = 0; i < p->r.N; i++) *V += 0.5 * p->k * q[2 * i] * q[2 * i];
  return rc;
}

static double sprung_energy(sprung *p, const double *q, const double *v) {
  double E;
  sprung_potential(0.0, q, &E, p);
  for (size_t i = 0; i < 2 * p->r.N; i++) E += 0.5 * p->r.m * v[i] * v[i];
  return E;
}

/* Stiff forces: springs of k = 1e6 on a rope of 16 unit masses (their mode 1e3 rad/s) at
 * T = 1e-2, ten times past rk4's stability bound (|R(i h w)| > 1 for h w > 2.83), hung 1e-3
 * rad from the vertical. The discrete gradients keep the energy to rounding on the sparse
 * back-end (their theorem: H(x+) = H(x) exactly; measured 6e-15), the constraints at rounding,
 * and follow the dense back-end's motion (q 1.3e-15 apart, v 3.2e-13, after 1 s); rk4's grows
 * until a step fails, by name */
START_TEST(a_stiff_rope_keeps_its_energy_on_both_back_ends) {
  const sdae_map_type *maps[] = {sdae_map_dgrad, sdae_map_dg4, sdae_map_rk4};
  const size_t N = 16;
  for (int k = 0; k < 3; k++) {
    double q[2][2 * N], v[2][2 * N], c[N], E0 = 0.0, drift = 0.0;
    int rc[2] = {SDAE_OK, SDAE_OK};
    for (int sparse = 0; sparse < 2; sparse++) {
      sprung p = {mech_rope_unit(N, 0, sparse), 1e6, NULL, NULL};
      sdae_mbs sys;
      sdae_mbs_stepper *s;
      sdae_options o = options(maps[k]);
      ck_assert_int_eq(mech_rope_system(&sys, &p.r), 0);
      p.force = sys.force, p.potential = sys.potential;
      sys.force = sprung_force, sys.potential = sprung_potential, sys.params = &p;
      ck_assert_int_eq(mech_rope_start(&p.r, 2.0 * atan(1.0) - 1e-3, q[sparse], v[sparse]), 0);
      E0 = sprung_energy(&p, q[sparse], v[sparse]);
      ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
      ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, sparse);
      for (int i = 0; i < 100 && rc[sparse] == SDAE_OK; i++) {
        rc[sparse] = sdae_mbs_step(s, 1e-2 * i, 1e-2, q[sparse], v[sparse]);
        double E = sprung_energy(&p, q[sparse], v[sparse]);
        if (sparse) drift = fmax(drift, fabs(E - E0) / fabs(E0));
      }
      sys.constraint(0.0, q[sparse], c, &p);
      if (maps[k] != sdae_map_rk4) {
        ck_assert_int_eq(rc[sparse], SDAE_OK);
        for (size_t j = 0; j < N; j++) ck_assert_double_le(fabs(c[j]), 1e-12);
      }
      sdae_mbs_stepper_free(s);
      mech_rope_free(&p.r);
    }
    if (maps[k] == sdae_map_rk4) {
      ck_assert_int_ne(rc[1], SDAE_OK);
    } else {
      ck_assert_double_le(drift, 1e-12);
      ck_assert_double_le(max_abs_diff(q[0], q[1], 2 * N), 1e-12);
      ck_assert_double_le(max_abs_diff(v[0], v[1], 2 * N), 1e-10);
    }
  }
}
END_TEST

/* lambda's query borrows the step's saddle-point factors (mbs_sparse_query.h): asked at another
 * state (the rope straight at another angle, in motion) between every two steps, under an
 * explicit map and an implicit one, the motion is the same bit for bit as without the queries
 * (the step refactors at its own point), and lambda the same as a fresh stepper's */
START_TEST(a_query_between_steps_leaves_the_motion) {
  const sdae_map_type *maps[] = {sdae_map_rk4, sdae_map_dgrad};
  for (int k = 0; k < 2; k++) {
    roped plain, asked, fresh;
    double qa[40], va[40], l[20], lf[20];
    roped_init(&plain, 20, 0, 1, maps[k]);
    roped_init(&asked, 20, 0, 1, maps[k]);
    roped_init(&fresh, 20, 0, 1, maps[k]);
    ck_assert_int_eq(mech_rope_start(&plain.r, 0.7, qa, va), 0);
    for (size_t i = 0; i < 40; i++) va[i] = 0.1 * (double)(i % 3) - 0.1;
    for (int i = 0; i < 30; i++) {
      double t = 1e-2 * i;
      ck_assert_int_eq(sdae_mbs_step(plain.s, t, 1e-2, plain.q, plain.v), SDAE_OK);
      ck_assert_int_eq(sdae_mbs_step(asked.s, t, 1e-2, asked.q, asked.v), SDAE_OK);
      ck_assert_int_eq(sdae_mbs_lambda(asked.s, t, qa, va, l), SDAE_OK);
    }
    ck_assert_mem_eq(plain.q, asked.q, sizeof qa);
    ck_assert_mem_eq(plain.v, asked.v, sizeof va);
    ck_assert_int_eq(sdae_mbs_lambda(fresh.s, 0.29, qa, va, lf), SDAE_OK);
    ck_assert_mem_eq(l, lf, sizeof l);
    roped_free(&plain), roped_free(&asked), roped_free(&fresh);
  }
}
END_TEST

/* the chart's L reserved at the most any order the chart tries can need (George and Ng's
 * bound, sparse_lu.l_stays_within_its_bound), or U's reserve where that is less, on every
 * topology of a truss: so L never outgrows its reserve in an order it is chosen in */
START_TEST(the_charts_l_is_reserved_at_its_bound) {
  int (*builds[])(mech_truss *, size_t, int) = {
      mech_truss_star, mech_truss_ladder, mech_truss_ladder, mech_truss_cloth, mech_truss_tree};
  const size_t sizes[] = {50, 8, 32, 8, 6};
  for (size_t c = 0; c < 5; c++) {
    mech_truss p;
    sdae_mbs sys;
    sdae_mbs_stepper *s;
    sdae_options o = options(sdae_map_rk4);
    ck_assert_int_eq(builds[c](&p, sizes[c], 1), 0);
    ck_assert_int_eq(mech_truss_system(&sys, &p), 0);
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    const sdae_mbs_sparse *sp = &s->sparse;
    size_t m = sys.n_c, n = sys.n_q, most = 0;
    size_t len = sdae__sparse_lu_orders_min(m, n, sys.jacobian_pattern->nnz);
    SuiteSparse_long *work = malloc(len * sizeof *work);
    for (size_t k = 0; k < SDAE_SPARSE_LU_ORDERS; k++) {
      size_t b =
          sdae__sparse_lu_l_bound(sys.jacobian_pattern, m, n, sp->orders + k * m, SIZE_MAX, work);
      most = b > most ? b : most;
    }
    size_t reserve = sdae__sparse_lu_reserve(m, sys.jacobian_pattern->nnz);
    ck_assert_uint_eq(sp->l_cap, most < reserve ? most : reserve);
    ck_assert_uint_eq(sp->lu[0].l_cap, sp->l_cap);
    free(work);
    sdae_mbs_stepper_free(s);
    mech_truss_free(&p);
  }
}
END_TEST

/* an allocator that counts what is out and its calls, and refuses the call numbered refuse
 * (from 1; 0 none) */
typedef struct counted {
  size_t out, calls, refuse;
} counted;

static void *counted_alloc(void *ud, size_t size) {
  counted *c = ud;
  if (++c->calls == c->refuse) return NULL;
  c->out += size;
  return malloc(size);
}

static void counted_free(void *ud, void *ptr, size_t size) {
  ((counted *)ud)->out -= size;
  free(ptr);
}

/* The saddle-point system's factors sized by its analysis, which the size runs in memory of
 * its own: init in the caller's block of exactly the size (the analysis in that block: no
 * allocation), one byte or the analysis' room short SDAE_ERR_BUFFER; alloc_with takes the
 * analysis' memory from its allocator too, gives it back, and keeps the block alone, as
 * _size_with does with its own (0 when there is none); an allocator with no room for the one
 * or the other SDAE_ERR_NOMEM, nothing kept. L holds a chain's count: nnz(G) + n_c - 1. */
START_TEST(the_block_is_what_the_analysis_counts) {
  const sdae_map_type *maps[] = {sdae_map_rk4, sdae_map_dgrad};
  mech_rope r = mech_rope_unit(1024, 0, 1);
  sdae_mbs sys;
  ck_assert_int_eq(mech_rope_system(&sys, &r), 0);
  for (int k = 0; k < 2; k++) {
    sdae_options o = options(maps[k]);
    size_t len = sdae_mbs_stepper_size(&sys, &o);
    counted c = {0, 0, 0};
    size_t calls;
    sdae_allocator a = {counted_alloc, counted_free, &c};
    int marker;
    sdae_mbs_stepper *s = (sdae_mbs_stepper *)&marker;
    void *mem = malloc(len);
    ck_assert_uint_gt(len, 0);
    ck_assert_int_eq(sdae_mbs_stepper_init(&s, mem, 64, &sys, &o), SDAE_ERR_BUFFER);
    ck_assert_int_eq(sdae_mbs_stepper_init(&s, mem, len - 1, &sys, &o), SDAE_ERR_BUFFER);
    ck_assert_ptr_eq(s, (sdae_mbs_stepper *)&marker);
    ck_assert_int_eq(sdae_mbs_stepper_init(&s, mem, len, &sys, &o), SDAE_OK);
    ck_assert_uint_eq(s->sparse.ly.ksym.lnz, sys.jacobian_pattern->nnz + sys.n_c - 1);
    sdae_mbs_stepper_free(s);
    ck_assert_int_eq(sdae_mbs_stepper_alloc_with(&s, &sys, &o, &a), SDAE_OK);
    ck_assert_uint_ge(c.calls, 2); /* the analysis' memory, then the block */
    ck_assert_uint_eq(c.out, len);
    sdae_mbs_stepper_free(s);
    ck_assert_uint_eq(c.out, 0);
    calls = c.calls;
    c = (counted){0, 0, 0};
    ck_assert_uint_eq(sdae_mbs_stepper_size_with(&sys, &o, &a), len);
    ck_assert_uint_eq(c.calls, 1); /* the analysis' memory alone, given back */
    ck_assert_uint_eq(c.out, 0);
    c = (counted){0, 0, 1};
    ck_assert_uint_eq(sdae_mbs_stepper_size_with(&sys, &o, &a), 0); /* none to analyse in */
    for (size_t r = 1; r <= calls; r++) { /* the analysis' memory refused, then the block */
      c = (counted){0, 0, r}, s = (sdae_mbs_stepper *)&marker;
      ck_assert_int_eq(sdae_mbs_stepper_alloc_with(&s, &sys, &o, &a), SDAE_ERR_NOMEM);
      ck_assert_ptr_eq(s, (sdae_mbs_stepper *)&marker);
      ck_assert_uint_eq(c.out, 0);
    }
    free(mem);
  }
  mech_rope_free(&r);
}
END_TEST

/* lambda, the energy and xi at a state are the same quantities in either coordinates: the
 * sparse saddle-point solve against the dense null-space one, to rounding */
START_TEST(lambda_energy_and_xi_as_the_dense_ones) {
  roped sp, de;
  double ls[6], ld[6], xs[12], xd[12], Es, Ed;
  roped_init(&sp, 5, 1, 1, sdae_map_rk4);
  roped_init(&de, 5, 1, 0, sdae_map_rk4);
  ck_assert_int_eq(sp.s->coords.linalg == &sdae__mbs_sparse_linalg, 1);
  ck_assert_int_eq(steps(&sp, 40, 1e-2), SDAE_OK); /* a state in motion */
  ck_assert_int_eq(sdae_mbs_lambda(sp.s, 0.4, sp.q, sp.v, ls), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_lambda(de.s, 0.4, sp.q, sp.v, ld), SDAE_OK);
  ck_assert_double_le(max_abs_diff(ls, ld, 6), 1e-10 * (1.0 + fabs(ld[0])));
  ck_assert_double_gt(fabs(ld[0]), 1.0); /* the rods pull */
  ck_assert_int_eq(sdae_mbs_energy(sp.s, 0.4, sp.q, sp.v, &Es), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_energy(de.s, 0.4, sp.q, sp.v, &Ed), SDAE_OK);
  ck_assert_double_le(fabs(Es - Ed), 1e-13 * fabs(Ed));
  ck_assert_int_eq(sdae_mbs_xi(sp.s, 0.4, sp.q, sp.v, xs), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_xi(de.s, 0.4, sp.q, sp.v, xd), SDAE_OK);
  ck_assert_double_le(max_abs_diff(xs, xd, 12), 1e-14);
  roped_free(&sp), roped_free(&de);
}
END_TEST

/* a state taken after some steps and set into a fresh stepper, or into one that has stepped
 * elsewhere (its factors at a point of its own), continues bit for bit, under an explicit map
 * and under an implicit one (Newton-Krylov's factors set up at each step's first solve) */
START_TEST(the_state_continues_bit_for_bit) {
  for (int elsewhere = 0; elsewhere < 4; elsewhere++) {
    const sdae_map_type *map = elsewhere < 2 ? sdae_map_rk4 : sdae_map_dgrad;
    roped a, b;
    unsigned char *state;
    size_t len;
    roped_init(&a, 7, 1, 1, map);
    roped_init(&b, 7, 1, 1, map);
    if (elsewhere % 2) ck_assert_int_eq(steps(&b, 13, 7e-3), SDAE_OK);
    ck_assert_int_eq(steps(&a, 30, 1e-2), SDAE_OK);
    len = sdae_mbs_state_size(a.s);
    state = malloc(len);
    ck_assert_int_eq(sdae_mbs_get_state(a.s, state, len), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_set_state(b.s, state, len), SDAE_OK);
    memcpy(b.q, a.q, 14 * sizeof *b.q), memcpy(b.v, a.v, 14 * sizeof *b.v);
    for (int k = 30; k < 60; k++) {
      ck_assert_int_eq(sdae_mbs_step(a.s, k * 1e-2, 1e-2, a.q, a.v), SDAE_OK);
      ck_assert_int_eq(sdae_mbs_step(b.s, k * 1e-2, 1e-2, b.q, b.v), SDAE_OK);
    }
    ck_assert_mem_eq(a.q, b.q, 14 * sizeof *a.q);
    ck_assert_mem_eq(a.v, b.v, 14 * sizeof *a.v);
    free(state);
    roped_free(&a), roped_free(&b);
  }
}
END_TEST

/* a constraint that fails at one call: the step fails, the state bytes are as before it, and
 * the step retried (the callback healthy again) is a fresh stepper's from the same state */
typedef struct flaky {
  mech_rope r; /* first: the rope's callbacks read their params from a flaky */
  int (*constraint)(double t, const double *q, double *c, void *params); /* the rope's */
  long calls, fail_at;
} flaky;

static int flaky_constraint(double t, const double *q, double *c, void *params) {
  flaky *f = params;
  if (++f->calls == f->fail_at) return 1;
  return f->constraint(t, q, c, &f->r);
}

static void failed_step_leaves_no_trace(const sdae_map_type *map) {
  flaky f = {.r = mech_rope_unit(5, 0, 1)};
  sdae_mbs sys;
  sdae_options o = options(map);
  sdae_mbs_stepper *s, *fresh;
  double q[10], v[10], q2[10], v2[10];
  unsigned char *before, *after, *state;
  size_t len;
  ck_assert_int_eq(mech_rope_system(&sys, &f.r), 0);
  f.constraint = sys.constraint;
  sys.params = &f, sys.constraint = flaky_constraint;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&fresh, &sys, &o), SDAE_OK);
  ck_assert_int_eq(mech_rope_start(&f.r, 0.3, q, v), 0);
  for (int k = 0; k < 10; k++) ck_assert_int_eq(sdae_mbs_step(s, k * 1e-2, 1e-2, q, v), SDAE_OK);
  len = sdae_mbs_state_size(s);
  before = malloc(len), after = malloc(len), state = malloc(len);
  ck_assert_int_eq(sdae_mbs_get_state(s, before, len), SDAE_OK);
  memcpy(q2, q, sizeof q), memcpy(v2, v, sizeof v);
  f.fail_at = f.calls + 3; /* inside the step's Phi^-1 */
  ck_assert_int_eq(sdae_mbs_step(s, 0.1, 1e-2, q, v), SDAE_ERR_CALLBACK_RECOVERABLE);
  ck_assert_mem_eq(q, q2, sizeof q);
  ck_assert_mem_eq(v, v2, sizeof v);
  ck_assert_int_eq(sdae_mbs_get_state(s, after, len), SDAE_OK);
  ck_assert_mem_eq(before, after, len);
  ck_assert_int_eq(sdae_mbs_set_state(fresh, before, len), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_step(s, 0.1, 1e-2, q, v), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_step(fresh, 0.1, 1e-2, q2, v2), SDAE_OK);
  ck_assert_mem_eq(q, q2, sizeof q);
  ck_assert_mem_eq(v, v2, sizeof v);
  free(before), free(after), free(state);
  sdae_mbs_stepper_free(s), sdae_mbs_stepper_free(fresh);
  mech_rope_free(&f.r);
}

START_TEST(a_failed_step_leaves_no_trace) {
  for (int implicit = 0; implicit < 2; implicit++)
    failed_step_leaves_no_trace(implicit ? sdae_map_dgrad : sdae_map_rk4);
}
END_TEST

/* The bead on the rotating wire (wire.h: c(t, q) = -sin(w t) x + cos(w t) y, a constraint that
 * depends on t) given by full patterns, which its dense callbacks write in their order: in the
 * sparse coordinates it follows the exact motion, its lambda is the exact -2 m w r', and its xi
 * at the state's own t is zero while the wire has turned away from it at t + 1 */
static sdae_mbs full_wire(wire *p);

START_TEST(a_constraint_in_time_in_sparse_coordinates) {
  wire p = {.m = 1.5, .w = 1.3};
  sdae_mbs sys = full_wire(&p);
  sdae_options o = options(sdae_map_rk4);
  sdae_mbs_stepper *s;
  double q[2], v[2], qe[2], ve[2], lambda, lambda_exact, xi[2];
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, 1);
  wire_exact(&p, 0.5, 0.0, 0.0, q, v, &lambda);
  for (int k = 0; k < 500; k++) ck_assert_int_eq(sdae_mbs_step(s, k * 1e-3, 1e-3, q, v), SDAE_OK);
  wire_exact(&p, 0.5, 0.0, 0.5, qe, ve, &lambda_exact);
  ck_assert_double_le(max_abs_diff(q, qe, 2), 1e-10);
  ck_assert_double_le(max_abs_diff(v, ve, 2), 1e-10);
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.5, q, v, &lambda), SDAE_OK);
  ck_assert_double_le(fabs(lambda - lambda_exact), 1e-8 * fabs(lambda_exact));
  ck_assert_int_eq(sdae_mbs_xi(s, 0.5, q, v, xi), SDAE_OK);
  ck_assert_double_le(fabs(xi[0]) + fabs(xi[1]), 1e-12);
  ck_assert_int_eq(sdae_mbs_xi(s, 1.5, q, v, xi), SDAE_OK);
  ck_assert_double_ge(fabs(xi[0]), 0.1); /* the wire a radian ahead: the bead off it */
  sdae_mbs_stepper_free(s);
}
END_TEST

/* a cart on a line (coordinate 0) carrying k pendulums of unit length (pendulum i at
 * coordinates 1 + 2i, 2 + 2i), unit masses, gravity: every constraint holds the cart's
 * coordinate, so the saddle-point factor's constraints block fills, k (k - 1) / 2 entries
 * (check_sparse_ldl.c); given densely (patterns NULL) or by its patterns */
typedef struct cart {
  size_t k;
  sdae_pattern mp, jp;
  size_t *m_start, *m_col, *j_start, *j_col;
} cart;

static int cart_mass(double t, const double *q, double *M, void *p) {
  const cart *c = p;
  size_t n = 1 + 2 * c->k;
  (void)t, (void)q;
  if (c->mp.row_start) {
    for (size_t i = 0; i < n; i++) M[i] = 1.0;
  } else {
    memset(M, 0, n * n * sizeof *M);
    for (size_t i = 0; i < n; i++) M[i * n + i] = 1.0;
  }
  return 0;
}

static int cart_force(double t, const double *q, const double *v, double *F, void *p) {
  const cart *c = p;
  (void)t, (void)q, (void)v;
  F[0] = 0.0;
  for (size_t i = 0; i < c->k; i++) F[1 + 2 * i] = 0.0, F[2 + 2 * i] = -9.81;
  return 0;
}

static int cart_constraint(double t, const double *q, double *out, void *p) {
  const cart *c = p;
  (void)t;
  for (size_t i = 0; i < c->k; i++) {
    double dx = q[1 + 2 * i] - q[0], y = q[2 + 2 * i];
    out[i] = 0.5 * (dx * dx + y * y - 1.0);
  }
  return 0;
}

/* row i of G at x (q for G, v for Gdot: the rows are linear in q) */
static void cart_rows(const cart *c, const double *x, double *out) {
  size_t n = 1 + 2 * c->k;
  if (!c->jp.row_start) memset(out, 0, c->k * n * sizeof *out);
  for (size_t i = 0; i < c->k; i++) {
    double dx = x[1 + 2 * i] - x[0], y = x[2 + 2 * i];
    if (c->jp.row_start) {
      out[3 * i] = -dx, out[3 * i + 1] = dx, out[3 * i + 2] = y;
    } else {
      out[i * n] = -dx, out[i * n + 1 + 2 * i] = dx, out[i * n + 2 + 2 * i] = y;
    }
  }
}

static int cart_jacobian(double t, const double *q, double *G, void *p) {
  (void)t;
  cart_rows(p, q, G);
  return 0;
}

static int cart_jacobian_dot(double t, const double *q, const double *v, double *G, void *p) {
  (void)t, (void)q;
  cart_rows(p, v, G);
  return 0;
}

static int cart_mass_dot_v(double t, const double *q, const double *v, double *out, void *p) {
  const cart *c = p;
  (void)t, (void)q, (void)v;
  memset(out, 0, (1 + 2 * c->k) * sizeof *out);
  return 0;
}

static void cart_init(cart *c, size_t k, int sparse, sdae_mbs *sys) {
  size_t n = 1 + 2 * k;
  *c = (cart){.k = k};
  *sys = (sdae_mbs){.n_q = n,
                    .n_c = k,
                    .mass = cart_mass,
                    .force = cart_force,
                    .constraint = cart_constraint,
                    .jacobian = cart_jacobian,
                    .jacobian_dot = cart_jacobian_dot,
                    .mass_dot_v = cart_mass_dot_v,
                    .params = c};
  if (!sparse) return;
  c->m_start = malloc((n + 1) * sizeof(size_t)), c->m_col = malloc(n * sizeof(size_t));
  c->j_start = malloc((k + 1) * sizeof(size_t)), c->j_col = malloc(3 * k * sizeof(size_t));
  for (size_t i = 0; i <= n; i++) c->m_start[i] = i;
  for (size_t i = 0; i < n; i++) c->m_col[i] = i;
  for (size_t i = 0; i <= k; i++) c->j_start[i] = 3 * i;
  for (size_t i = 0; i < k; i++)
    c->j_col[3 * i] = 0, c->j_col[3 * i + 1] = 1 + 2 * i, c->j_col[3 * i + 2] = 2 + 2 * i;
  c->mp = (sdae_pattern){n, c->m_start, c->m_col};
  c->jp = (sdae_pattern){3 * k, c->j_start, c->j_col};
  sys->mass_pattern = &c->mp, sys->jacobian_pattern = &c->jp;
}

static void cart_free(cart *c) {
  free(c->m_start), free(c->m_col), free(c->j_start), free(c->j_col);
}

/* the cart's coordinate, held by every constraint, is taken after the multipliers (a hub,
 * core/sparse_ldl.c): forty pendulums step as the dense cart does, to truncation (the charts
 * differ: rk4 at T = 1e-3 leaves 5e-11 between them), and L holds
 * each bob coordinate's entry in its multiplier's column and each multiplier's in the cart's,
 * 3 k entries and no fill (every coordinate first: k (k - 1) / 2 more, past the reserve at a
 * hundred), at k = 40, 100 and 1000 */
START_TEST(a_shared_coordinate_steps_at_the_cost_of_its_nonzeros) {
  sdae_options o = options(sdae_map_rk4);
  double q[2][81], v[2][81];
  for (int sparse = 0; sparse < 2; sparse++) {
    cart c;
    sdae_mbs sys;
    sdae_mbs_stepper *s;
    cart_init(&c, 40, sparse, &sys);
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, sparse);
    q[sparse][0] = v[sparse][0] = 0.0;
    for (size_t i = 0; i < 40; i++) { /* pendulum i at angle 0.03 i from the vertical, at rest */
      q[sparse][1 + 2 * i] = sin(0.03 * (double)i), q[sparse][2 + 2 * i] = -cos(0.03 * (double)i);
      v[sparse][1 + 2 * i] = v[sparse][2 + 2 * i] = 0.0;
    }
    for (int k = 0; k < 100; k++)
      ck_assert_int_eq(sdae_mbs_step(s, k * 1e-3, 1e-3, q[sparse], v[sparse]), SDAE_OK);
    sdae_mbs_stepper_free(s);
    cart_free(&c);
  }
  ck_assert_double_le(max_abs_diff(q[0], q[1], 81), 1e-9);
  const size_t ks[] = {40, 100, 1000};
  for (size_t i = 0; i < 3; i++) {
    cart c;
    sdae_mbs sys;
    sdae_mbs_stepper *s;
    cart_init(&c, ks[i], 1, &sys);
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    ck_assert_uint_eq((size_t)s->sparse.ly.ksym.Lp[s->sparse.ly.ksym.n], 3 * ks[i]);
    sdae_mbs_stepper_free(s);
    cart_free(&c);
  }
}
END_TEST

/* a pendulum (the rope of one mass) at its pivot, G = 0: no chart, SDAE_ERR_RANK, at the first
 * step and after steps in a chart (its refactoring fails, and so does a new choice), and from
 * sdae_mbs_lambda there (the saddle-point system singular), lambda unwritten */
START_TEST(a_zero_jacobian_is_rank) {
  roped w;
  double q0[2] = {0.0, 0.0}, v0[2] = {0.0, 0.0};
  for (int after = 0; after <= 1; after++) {
    roped_init(&w, 1, 0, 1, sdae_map_rk4);
    ck_assert_int_eq(w.s->coords.linalg == &sdae__mbs_sparse_linalg, 1);
    if (after) ck_assert_int_eq(steps(&w, 5, 1e-2), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_step(w.s, 0.05, 1e-2, q0, v0), SDAE_ERR_RANK);
    ck_assert_double_eq(q0[0], 0.0);
    double lambda = 7.0; /* the query's saddle-point factorization refuses it alike */
    ck_assert_int_eq(sdae_mbs_lambda(w.s, 0.05, q0, v0, &lambda), SDAE_ERR_RANK);
    ck_assert_double_eq(lambda, 7.0);
    roped_free(&w);
  }
}
END_TEST

/* the quantities at a state report a failing callback and write nothing */
typedef struct failing {
  mech_rope r; /* first: the rope's callbacks read their params from a failing */
  int (*jacobian)(double t, const double *q, double *G, void *params);
  int (*mass)(double t, const double *q, double *M, void *params);
  int fail;
} failing;

static int failing_jacobian(double t, const double *q, double *G, void *params) {
  failing *f = params;
  return f->fail ? 1 : f->jacobian(t, q, G, &f->r);
}

static int failing_mass(double t, const double *q, double *M, void *params) {
  failing *f = params;
  return f->fail ? -1 : f->mass(t, q, M, &f->r);
}

START_TEST(a_failing_callback_in_a_query_is_reported) {
  failing f = {.r = mech_rope_unit(4, 0, 1)};
  sdae_mbs sys;
  sdae_options o = options(sdae_map_rk4);
  sdae_mbs_stepper *s;
  double q[8], v[8], lambda[4] = {7, 7, 7, 7}, xi[8] = {7, 7, 7, 7, 7, 7, 7, 7}, E = 7.0;
  ck_assert_int_eq(mech_rope_system(&sys, &f.r), 0);
  f.jacobian = sys.jacobian, f.mass = sys.mass;
  sys.params = &f, sys.jacobian = failing_jacobian, sys.mass = failing_mass;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(mech_rope_start(&f.r, 0.3, q, v), 0);
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.0, q, v, lambda), SDAE_OK);
  f.fail = 1;
  for (int i = 0; i < 4; i++) lambda[i] = 7.0;
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.0, q, v, lambda), SDAE_ERR_CALLBACK_FATAL); /* M first */
  sys.mass = f.mass; /* only the Jacobian failing now: a stepper of that */
  sdae_mbs_stepper_free(s);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.0, q, v, lambda), SDAE_ERR_CALLBACK_RECOVERABLE);
  ck_assert_int_eq(sdae_mbs_xi(s, 0.0, q, v, xi), SDAE_ERR_CALLBACK_RECOVERABLE);
  for (int i = 0; i < 4; i++) ck_assert_double_eq(lambda[i], 7.0);
  for (int i = 0; i < 8; i++) ck_assert_double_eq(xi[i], 7.0);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E), SDAE_OK); /* needs no Jacobian */
  ck_assert_double_ne(E, 7.0);
  sdae_mbs_stepper_free(s);
  mech_rope_free(&f.r);
}
END_TEST

/* the wire by full patterns, its mass skewed (M = [[m, a], [0, m]]: a pattern symmetric, values
 * not): refused at the step with SDAE_ERR_MASS, as the dense coordinates refuse it */
static int skewed_mass(double t, const double *q, double *M, void *params) {
  const wire *p = params;
  (void)t, (void)q;
  M[0] = M[3] = p->m, M[1] = 0.5, M[2] = 0.0;
  return 0;
}

static sdae_mbs full_wire(wire *p) {
  static const size_t m_start[] = {0, 2, 4}, m_col[] = {0, 1, 0, 1}, g_start[] = {0, 2},
                      g_col[] = {0, 1};
  static const sdae_pattern full_m = {4, m_start, m_col}, full_g = {2, g_start, g_col};
  sdae_mbs sys = wire_mbs(p);
  sys.mass_pattern = &full_m, sys.jacobian_pattern = &full_g;
  return sys;
}

START_TEST(a_mass_not_symmetric_is_refused) {
  wire p = {.m = 1.0, .w = 1.0};
  sdae_mbs sys = full_wire(&p);
  sdae_options o = options(sdae_map_rk4);
  sdae_mbs_stepper *s;
  double q[2], v[2], lambda;
  sys.mass = skewed_mass;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, 1);
  wire_exact(&p, 0.5, 0.0, 0.0, q, v, &lambda);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_ERR_MASS);
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &lambda), SDAE_ERR_MASS);
  sdae_mbs_stepper_free(s);
}
END_TEST

/* A step from the last step's end (q, v) but at another t: the point kept (G and dc/dt there)
 * is not the state's, which must be evaluated anew: the step equals a fresh stepper's from
 * (t, q, v) bit for bit (the wire's constraint turns with t) */
START_TEST(the_kept_point_serves_its_own_t_only) {
  wire p = {.m = 1.0, .w = 1.3};
  sdae_mbs sys = full_wire(&p);
  sdae_options o = options(sdae_map_rk4);
  sdae_mbs_stepper *s, *fresh;
  double q[2], v[2], q2[2], v2[2], lambda;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&fresh, &sys, &o), SDAE_OK);
  wire_exact(&p, 0.5, 0.0, 0.0, q, v, &lambda);
  ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), SDAE_OK);
  memcpy(q2, q, sizeof q), memcpy(v2, v, sizeof v);
  ck_assert_int_eq(sdae_mbs_step(s, 0.25, 1e-3, q, v), SDAE_OK);
  ck_assert_int_eq(sdae_mbs_step(fresh, 0.25, 1e-3, q2, v2), SDAE_OK);
  ck_assert_mem_eq(q, q2, sizeof q);
  ck_assert_mem_eq(v, v2, sizeof v);
  sdae_mbs_stepper_free(s), sdae_mbs_stepper_free(fresh);
}
END_TEST

/* xi's floors at a step's start are the dense coordinates' (the same rule, through the
 * patterns) */
START_TEST(floors_as_the_dense_ones) {
  roped sp, de;
  double xi[12], fs[12], fd[12];
  roped_init(&sp, 5, 1, 1, sdae_map_rk4);
  roped_init(&de, 5, 1, 0, sdae_map_rk4);
  ck_assert_int_eq(steps(&sp, 20, 1e-2), SDAE_OK);
  for (size_t i = 0; i < 10; i++) sp.v[i] += 0.1 * (double)i; /* off the velocity constraint */
  ck_assert_int_eq(sdae__mbs_coords_xi(&sp.s->coords, 0.2, sp.q, sp.v, xi), SDAE_OK);
  ck_assert_int_eq(sdae__mbs_coords_xi(&de.s->coords, 0.2, sp.q, sp.v, xi), SDAE_OK);
  sdae__mbs_coords_floors(&sp.s->coords, sp.q, sp.v, fs);
  sdae__mbs_coords_floors(&de.s->coords, sp.q, sp.v, fd);
  for (size_t i = 0; i < 12; i++) {
    ck_assert_double_gt(fd[i], 0.0);
    ck_assert_double_le(fabs(fs[i] - fd[i]), 1e-14 * fd[i]);
  }
  roped_free(&sp), roped_free(&de);
}
END_TEST

/* the rope's callbacks failing (or M turning singular) at their n-th call, inside a step: the
 * step reports it (SDAE_ERR_MASS for a saddle-point system with no reduced mass) and keeps
 * nothing; and the queries report their callbacks' failures */
typedef struct broken {
  mech_rope r; /* first: the rope's callbacks read their params from a broken */
  int (*mass)(double t, const double *q, double *M, void *params);
  int (*constraint_t)(double t, const double *q, double *ct, void *params);
  int (*jacobian_dot)(double t, const double *q, const double *v, double *Gd, void *params);
  long mass_calls, mass_at, ct_calls, ct_at, gd_calls, gd_at;
  int zero_mass; /* from mass_at on, M = 0 instead of a failure */
} broken;

static int broken_mass(double t, const double *q, double *M, void *params) {
  broken *b = params;
  int rc = b->mass(t, q, M, &b->r);
  if (b->mass_at && ++b->mass_calls >= b->mass_at) {
    if (!b->zero_mass) return -1;
    memset(M, 0, b->r.mass_pattern.nnz * sizeof *M);
  }
  return rc;
}

static int broken_ct(double t, const double *q, double *ct, void *params) {
  broken *b = params;
  if (b->ct_at && ++b->ct_calls >= b->ct_at) return 1;
  return b->constraint_t(t, q, ct, &b->r);
}

static int broken_gd(double t, const double *q, const double *v, double *Gd, void *params) {
  broken *b = params;
  if (b->gd_at && ++b->gd_calls >= b->gd_at) return 1;
  return b->jacobian_dot(t, q, v, Gd, &b->r);
}

static void broken_init(broken *b, sdae_mbs *sys, sdae_mbs_stepper **s, double *q, double *v) {
  sdae_options o = options(sdae_map_rk4);
  b->r = mech_rope_unit(4, 0, 1);
  ck_assert_int_eq(mech_rope_system(sys, &b->r), 0);
  b->mass = sys->mass, b->constraint_t = sys->constraint_t, b->jacobian_dot = sys->jacobian_dot;
  sys->params = b, sys->mass = broken_mass, sys->constraint_t = broken_ct;
  sys->jacobian_dot = broken_gd;
  ck_assert_int_eq(sdae_mbs_stepper_alloc(s, sys, &o), SDAE_OK);
  ck_assert_int_eq(mech_rope_start(&b->r, 0.3, q, v), 0);
  for (int k = 0; k < 3; k++) ck_assert_int_eq(sdae_mbs_step(*s, k * 1e-2, 1e-2, q, v), SDAE_OK);
}

START_TEST(a_failure_inside_a_configuration_is_the_steps) {
  for (int zero = 0; zero <= 1; zero++) {
    broken b = {0};
    sdae_mbs sys;
    sdae_mbs_stepper *s;
    double q[8], v[8], q0[8];
    broken_init(&b, &sys, &s, q, v);
    memcpy(q0, q, sizeof q);
    b.zero_mass = zero;
    b.mass_calls = 0, b.mass_at = 2; /* the first Phi^-1's configuration, after the start's */
    ck_assert_int_eq(sdae_mbs_step(s, 0.03, 1e-2, q, v),
                     zero ? SDAE_ERR_MASS : SDAE_ERR_CALLBACK_FATAL);
    ck_assert_mem_eq(q, q0, sizeof q);
    sdae_mbs_stepper_free(s);
    mech_rope_free(&b.r);
  }
}
END_TEST

START_TEST(a_failure_inside_a_query_is_reported) {
  broken b = {0};
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  double q[8], v[8], xi[8] = {7, 7, 7, 7, 7, 7, 7, 7}, lambda[4] = {7, 7, 7, 7};
  broken_init(&b, &sys, &s, q, v);
  b.ct_calls = 0, b.ct_at = 1;
  ck_assert_int_eq(sdae_mbs_xi(s, 0.03, q, v, xi), SDAE_ERR_CALLBACK_RECOVERABLE);
  b.ct_at = 0;
  b.gd_calls = 0, b.gd_at = 1;
  ck_assert_int_eq(sdae_mbs_lambda(s, 0.03, q, v, lambda), SDAE_ERR_CALLBACK_RECOVERABLE);
  for (int i = 0; i < 8; i++) ck_assert_double_eq(xi[i], 7.0);
  for (int i = 0; i < 4; i++) ck_assert_double_eq(lambda[i], 7.0);
  sdae_mbs_stepper_free(s);
  mech_rope_free(&b.r);
}
END_TEST

/* a state whose current factorization has an independent coordinate claim the first row (whose
 * pivot is another column), the checksum made anew: whole, yet no chart. The chart follows the
 * header and the statistics' four counters: have, cur, measure, then each factorization's
 * order (n_c), pivots (n_c) and rows of the columns (n_q); q_I is derived from them */
START_TEST(a_state_with_no_chart_is_damaged) {
  roped w;
  unsigned char *state;
  size_t len, at = 36 + 4 * sizeof(unsigned long) + 2 * sizeof(int) + sizeof(double), m, n, c;
  uint64_t sum;
  roped_init(&w, 5, 0, 1, sdae_map_rk4);
  ck_assert_int_eq(steps(&w, 5, 1e-2), SDAE_OK);
  m = w.s->sparse.n_c, n = w.s->sparse.n_q, c = w.s->sparse.ind[0];
  at += (size_t)w.s->sparse.cur * (2 * m + n) * sizeof(size_t) + 2 * m * sizeof(size_t);
  len = sdae_mbs_state_size(w.s);
  state = malloc(len);
  ck_assert_int_eq(sdae_mbs_get_state(w.s, state, len), SDAE_OK);
  ck_assert_mem_eq(state + at, w.s->sparse.lu[w.s->sparse.cur].row_of,
                   n * sizeof(size_t));                       /* found where said */
  memset(state + at + c * sizeof(size_t), 0, sizeof(size_t)); /* row 0 */
  sum = sdae__fnv(SDAE_FNV_START, state, len - sizeof sum);
  memcpy(state + len - sizeof sum, &sum, sizeof sum);
  ck_assert_int_eq(sdae_mbs_set_state(w.s, state, len), SDAE_ERR_STATE_DAMAGED);
  free(state);
  roped_free(&w);
}
END_TEST

/* the truss's topology by name, sparse or dense: 0, or -1 */
static int truss_of(mech_truss *p, int kind, int sparse) {
  switch (kind) {
  case 0: return mech_truss_star(p, 12, sparse); /* the cart a hub (12 > 8 constraints) */
  case 1: return mech_truss_ladder(p, 8, sparse);
  case 2: return mech_truss_cloth(p, 4, sparse);
  default: return mech_truss_tree(p, 4, sparse);
  }
}

/* the truss stepped n times by map at T from its start into q (n_q), and the largest change of
 * its energy over the run relative to its size into drift (unless NULL): SDAE_OK or the status */
static int truss_run_energy(int kind, int sparse, const sdae_map_type *map, double T, size_t n,
                            double *q, double *drift) {
  mech_truss p;
  sdae_mbs sys;
  sdae_mbs_stepper *s;
  sdae_options o = options(map);
  double v[64];
  int rc;
  ck_assert_int_eq(truss_of(&p, kind, sparse), 0);
  ck_assert_int_eq(mech_truss_system(&sys, &p), 0);
  ck_assert_uint_le(sys.n_q, 64);
  mech_truss_start(&p, q, v);
  ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
  ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, sparse);
  double E0, E, size;
  ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q, v, &E0), SDAE_OK);
  size = fmax(1.0, fabs(E0));
  rc = SDAE_OK;
  if (drift) *drift = 0.0;
  for (size_t k = 0; k < n && rc == SDAE_OK; k++) {
    rc = sdae_mbs_step(s, (double)k * T, T, q, v);
    if (rc == SDAE_OK && drift) {
      ck_assert_int_eq(sdae_mbs_energy(s, (double)(k + 1) * T, q, v, &E), SDAE_OK);
      *drift = fmax(*drift, fabs(E - E0) / size);
    }
  }
  sdae_mbs_stepper_free(s);
  mech_truss_free(&p);
  return rc;
}

static int truss_run(int kind, int sparse, const sdae_map_type *map, double T, size_t n,
                     double *q) {
  return truss_run_energy(kind, sparse, map, T, n, q, NULL);
}

/* the truss of kind by the dense rk8 at T = 2.5e-4 over 0.2 s into ref: its coordinates */
static size_t truss_reference(int kind, double *ref) {
  mech_truss p;
  size_t n_q;
  ck_assert_int_eq(truss_of(&p, kind, 0), 0);
  n_q = p.n_masses * p.dim;
  mech_truss_free(&p);
  ck_assert_int_eq(truss_run(kind, 0, sdae_map_rk8, 2.5e-4, 800, ref), SDAE_OK);
  return n_q;
}

/* max_i |a_i - ref_i| */
static double truss_error(const double *a, const double *ref, size_t n_q) {
  double e = 0.0;
  for (size_t i = 0; i < n_q; i++) e = fmax(e, fabs(a[i] - ref[i]));
  return e;
}

/* Every topology of a truss (examples/models/truss.h: a cart under 12 pendulums, a ladder of 8
 * four-bar cells between two walls, a 4 x 4 cloth in space pinned at two corners, a binary
 * tree of 15 pendulums), given by its patterns and stepped on the sparse back-end by rk4 at
 * T = 1e-3 for 0.2 s, is as accurate as the same mechanism on the dense back-end: its error
 * against the dense rk8 at T / 4 at most twice the dense rk4's (truncation, the charts
 * differing), above rounding. The ladder crosses a configuration where the chart kept by a
 * hysteresis of its own was 18 times less accurate. */
START_TEST(every_topology_as_accurate_as_the_dense_path) {
  for (int kind = 0; kind < 4; kind++) {
    double ref[64], dense[64], sparse[64];
    size_t n_q = truss_reference(kind, ref);
    ck_assert_int_eq(truss_run(kind, 0, sdae_map_rk4, 1e-3, 200, dense), SDAE_OK);
    ck_assert_int_eq(truss_run(kind, 1, sdae_map_rk4, 1e-3, 200, sparse), SDAE_OK);
    ck_assert_double_le(truss_error(sparse, ref, n_q), 2.0 * truss_error(dense, ref, n_q) + 1e-13);
  }
}
END_TEST

/* The implicit maps as the explicit ones: every topology of a truss stepped on the sparse back-end
 * (Newton-Krylov on its linear solve) by midpoint and dgrad at T = 1e-3 for 0.2 s is as
 * accurate as on the dense back-end (its Newton matrix by differences): the error against the
 * dense rk8 at T / 4 at most twice the dense one's, above rounding; dgrad and dg4 keep the
 * energy to Newton's tolerance (the discrete gradients conserve H exactly at Newton's solution;
 * the truss moves under gravity alone, so no power enters). */
START_TEST(every_topology_implicit_as_accurate_as_the_dense_path) {
  const sdae_map_type *maps[] = {sdae_map_midpoint, sdae_map_dgrad, sdae_map_dg4};
  for (int kind = 0; kind < 4; kind++) {
    double ref[64];
    size_t n_q = truss_reference(kind, ref);
    for (size_t k = 0; k < sizeof maps / sizeof *maps; k++) {
      double dense[64], sparse[64], drift = 0.0;
      ck_assert_int_eq(truss_run_energy(kind, 1, maps[k], 1e-3, 200, sparse, &drift), SDAE_OK);
      /* the discrete gradients conserve H at Newton's exact solution; Newton-Krylov stops
       * within SDAE_MBS_NEWTON_TOL of it, so each of the 200 steps may move H by that much
       * (relative), where the midpoint map's changes by its truncation error */
      if (maps[k] == sdae_map_midpoint)
        ck_assert_double_ge(drift, 1e-8);
      else
        ck_assert_double_le(drift, 200 * SDAE_MBS_NEWTON_TOL);
      if (maps[k] == sdae_map_dg4) continue; /* the dense composition's matrices: too slow here */
      ck_assert_int_eq(truss_run(kind, 0, maps[k], 1e-3, 200, dense), SDAE_OK);
      ck_assert_double_le(truss_error(sparse, ref, n_q),
                          2.0 * truss_error(dense, ref, n_q) + 1e-13);
    }
  }
}
END_TEST

/* A particle of unit mass on the unit circle, q = (x, y, s), and a coordinate s of no mass of
 * its own held to x (c_2 = s - x): M = diag(1, 1, 0) is semidefinite, the reduced mass on the
 * circle 1. With patterns (M's without s's diagonal entry) s is taken after the multipliers
 * (core/sparse_ldl.c) and the sparse back-end steps it as the dense one does, to truncation, and
 * keeps the particle's energy v^T M v / 2 + y g to rounding over the run. */
typedef struct massless {
  int sparse;
} massless;
static int ml_mass(double t, const double *q, double *M, void *p) {
  const massless *m = p;
  (void)t, (void)q;
  if (m->sparse) {
    M[0] = M[1] = 1.0;
  } else {
    memset(M, 0, 9 * sizeof *M);
    M[0] = M[4] = 1.0;
  }
  return 0;
}
static int ml_force(double t, const double *q, const double *v, double *F, void *p) {
  (void)t, (void)q, (void)v, (void)p;
  F[0] = 0.0, F[1] = -9.81, F[2] = 0.0;
  return 0;
}
static int ml_potential(double t, const double *q, double *V, void *p) {
  (void)t, (void)p;
  *V = 9.81 * q[1];
  return 0;
}
static int ml_constraint(double t, const double *q, double *c, void *p) {
  (void)t, (void)p;
  c[0] = 0.5 * (q[0] * q[0] + q[1] * q[1] - 1.0);
  c[1] = q[2] - q[0];
  return 0;
}
/* G's rows (x, y, 0) and (-1, 0, 1), or Gdot's (vx, vy, 0) and 0 */
static void ml_rows(const massless *m, const double *x, int dot, double *G) {
  const double g[6] = {x[0], x[1], 0.0, dot ? 0.0 : -1.0, 0.0, dot ? 0.0 : 1.0};
  if (m->sparse) {
    G[0] = g[0], G[1] = g[1], G[2] = g[3], G[3] = g[5];
  } else {
    memcpy(G, g, sizeof g);
  }
}
static int ml_jacobian(double t, const double *q, double *G, void *p) {
  (void)t;
  ml_rows(p, q, 0, G);
  return 0;
}
static int ml_jacobian_dot(double t, const double *q, const double *v, double *G, void *p) {
  (void)t, (void)q;
  ml_rows(p, v, 1, G);
  return 0;
}
static int ml_mass_dot_v(double t, const double *q, const double *v, double *out, void *p) {
  (void)t, (void)q, (void)v, (void)p;
  out[0] = out[1] = out[2] = 0.0;
  return 0;
}

START_TEST(a_coordinate_without_mass_steps_on_both_back_ends) {
  static const size_t m_start[] = {0, 1, 2, 2}, m_col[] = {0, 1};
  static const size_t g_start[] = {0, 2, 4}, g_col[] = {0, 1, 0, 2};
  const sdae_pattern mp = {2, m_start, m_col}, gp = {4, g_start, g_col};
  sdae_options o = options(sdae_map_rk4);
  double q[2][3], v[2][3], E0 = 0.0;
  for (int sparse = 0; sparse < 2; sparse++) {
    massless m = {sparse};
    sdae_mbs sys = {.n_q = 3,
                    .n_c = 2,
                    .mass = ml_mass,
                    .force = ml_force,
                    .constraint = ml_constraint,
                    .jacobian = ml_jacobian,
                    .jacobian_dot = ml_jacobian_dot,
                    .mass_dot_v = ml_mass_dot_v,
                    .potential = ml_potential,
                    .params = &m};
    sdae_mbs_stepper *s;
    double E;
    if (sparse) sys.mass_pattern = &mp, sys.jacobian_pattern = &gp;
    q[sparse][0] = q[sparse][2] = 0.6, q[sparse][1] = -0.8; /* at rest, 37 degrees out */
    v[sparse][0] = v[sparse][1] = v[sparse][2] = 0.0;
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, sparse);
    ck_assert_int_eq(sdae_mbs_energy(s, 0.0, q[sparse], v[sparse], &E0), SDAE_OK);
    for (int k = 0; k < 500; k++)
      ck_assert_int_eq(sdae_mbs_step(s, k * 1e-3, 1e-3, q[sparse], v[sparse]), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_energy(s, 0.5, q[sparse], v[sparse], &E), SDAE_OK);
    ck_assert_double_le(fabs(E - E0), 1e-9 * fabs(E0)); /* rk4's truncation at T = 1e-3 */
    ck_assert_double_le(fabs(q[sparse][2] - q[sparse][0]), 4.0 * DBL_EPSILON); /* s = x */
    sdae_mbs_stepper_free(s);
  }
  ck_assert_double_le(max_abs_diff(q[0], q[1], 3), 1e-12);
}
END_TEST

/* A chart's LU whose fill outgrows its reserve (U's 4 nnz(G) + n_c and L's, one array) in every
 * order it tries is found when the chart is chosen, at the first step: SDAE_ERR_PATTERN, named
 * as the reserve's, not SDAE_ERR_CHART (a configuration next to a singular one, which the dense
 * back-end shows it is not), and the state as it was. The cloth of 64 x 64 fills 9.4 nnz(G) in
 * U and 1.0 in L by minimum degree, 24.9 and 2.5 by dissection, more the leaves first. The
 * cloth of 32 x 32 steps, its rods at rounding 20 steps on: minimum degree's U (5.1 nnz(G))
 * outgrows U's own reserve, but its L (0.8) leaves it the room (with U's and L's reserves apart
 * it overflowed); so does a ladder of 32 cells, which overflows the leaves' order, in the
 * dissection's (U: 1.65 nnz(G)) */
START_TEST(a_chart_past_its_reserve_is_named) {
  int (*builds[])(mech_truss *, size_t, int) = {mech_truss_ladder, mech_truss_cloth,
                                                mech_truss_cloth};
  const size_t sizes[] = {32, 32, 64};
  for (int i = 0; i < 3; i++) {
    int big = i == 2;
    mech_truss p;
    sdae_mbs sys;
    sdae_mbs_stepper *s;
    sdae_options o = options(sdae_map_rk4);
    ck_assert_int_eq(builds[i](&p, sizes[i], 1), 0);
    ck_assert_int_eq(mech_truss_system(&sys, &p), 0);
    double *q = malloc(3 * sys.n_q * sizeof *q), *v = q + sys.n_q, *q0 = v + sys.n_q;
    mech_truss_start(&p, q, v);
    memcpy(q0, q, sys.n_q * sizeof *q);
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    ck_assert_int_eq(sdae_mbs_step(s, 0.0, 1e-3, q, v), big ? SDAE_ERR_PATTERN : SDAE_OK);
    for (int k = 1; k < 20 && !big; k++)
      ck_assert_int_eq(sdae_mbs_step(s, k * 1e-3, 1e-3, q, v), SDAE_OK);
    if (big) {
      ck_assert_mem_eq(q, q0, sys.n_q * sizeof *q);
    } else { /* 20 steps on, |d|^2 - 1 of every unit rod at the rounding of coordinates to 31 */
      double *c = malloc(sys.n_c * sizeof *c), worst = 0.0;
      ck_assert_int_eq(sys.constraint(0.02, q, c, sys.params), 0);
      for (size_t j = 0; j < sys.n_c; j++) worst = fmax(worst, fabs(c[j]));
      ck_assert_double_le(worst, 32 * 32 * DBL_EPSILON);
      free(c);
    }
    sdae_mbs_stepper_free(s);
    mech_truss_free(&p);
    free(q);
  }
}
END_TEST

/* A particle of unit mass on two spheres, |p|^2 = 1 and |p - (0, 0, d)|^2 = 1 + d^2 - 2 d z0:
 * their intersection the circle z = z0 = -0.6, their gradients at an angle of about d. At rate
 * 2 along it (gravity along -z held by the two) the motion is p = (R cos 2t, R sin 2t, z0).
 * With d = 1e-2 and 1e-4, rk8 at T = 1e-3 to t = 1 on the sparse back-end keeps it within
 * 1e-10 (the dense back-end: 3e-14 and 4e-12); before the refinement of nearly dependent
 * constraints' solves (mbs_sparse.c), 6.5e-11 and 1.4e-6, silently. On both back-ends the
 * steps stay in the chart: the constraints are as dependent all along, no singular
 * configuration (SDAE_MBS_SINGULAR_NEAR is relative to the largest independence seen); with
 * the rule an absolute 1e-2, every step was projected, the rows of sine below 1e-4 dropped,
 * and d = 1e-4 ended 1.6e-3 (dense) and 7e-4 (sparse) off with SDAE_OK. */
typedef struct spheres {
  double d, r2;
} spheres;
static int sp_mass(double t, const double *q, double *M, void *p) {
  (void)t, (void)q, (void)p;
  M[0] = M[1] = M[2] = 1.0;
  return 0;
}
static int sp_mass_dense(double t, const double *q, double *M, void *p) {
  (void)t, (void)q, (void)p;
  for (int i = 0; i < 9; i++) M[i] = i % 4 == 0 ? 1.0 : 0.0;
  return 0;
}
static int sp_force(double t, const double *q, const double *v, double *F, void *p) {
  (void)t, (void)q, (void)v, (void)p;
  F[0] = F[1] = 0.0, F[2] = -9.81;
  return 0;
}
static int sp_constraint(double t, const double *q, double *c, void *p) {
  const spheres *s = p;
  double z = q[2] - s->d;
  (void)t;
  c[0] = 0.5 * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - 1.0);
  c[1] = 0.5 * (q[0] * q[0] + q[1] * q[1] + z * z - s->r2);
  return 0;
}
static void sp_rows(const spheres *s, const double *x, int dot, double *G) {
  G[0] = G[3] = x[0], G[1] = G[4] = x[1], G[2] = x[2], G[5] = x[2] - (dot ? 0.0 : s->d);
}
static int sp_jacobian(double t, const double *q, double *G, void *p) {
  (void)t;
  sp_rows(p, q, 0, G);
  return 0;
}
static int sp_jacobian_dot(double t, const double *q, const double *v, double *G, void *p) {
  (void)t, (void)q;
  sp_rows(p, v, 1, G);
  return 0;
}

START_TEST(nearly_dependent_constraints_keep_the_motion) {
  static const size_t m_start[] = {0, 1, 2, 3}, m_col[] = {0, 1, 2};
  static const size_t g_start[] = {0, 3, 6}, g_col[] = {0, 1, 2, 0, 1, 2};
  const sdae_pattern mp = {3, m_start, m_col}, gp = {6, g_start, g_col};
  const double ds[] = {1e-2, 1e-4}, z0 = -0.6, R = 0.8, w = 2.0;
  sdae_options o = options(sdae_map_rk8);
  for (int i = 0; i < 4; i++) {
    int sparse = i < 2;
    spheres sph = {ds[i % 2], 1.0 + ds[i % 2] * ds[i % 2] - 2.0 * ds[i % 2] * z0};
    sdae_mbs sys = {.n_q = 3,
                    .n_c = 2,
                    .mass = sp_mass,
                    .force = sp_force,
                    .constraint = sp_constraint,
                    .jacobian = sp_jacobian,
                    .jacobian_dot = sp_jacobian_dot,
                    .mass_dot_v = ml_mass_dot_v,
                    .mass_pattern = sparse ? &mp : NULL,
                    .jacobian_pattern = sparse ? &gp : NULL,
                    .params = &sph};
    sdae_mbs_stepper *s;
    double q[3] = {R, 0.0, z0}, v[3] = {0.0, R * w, 0.0};
    if (!sparse) sys.mass = sp_mass_dense;
    ck_assert_int_eq(sdae_mbs_stepper_alloc(&s, &sys, &o), SDAE_OK);
    ck_assert_int_eq(s->coords.linalg == &sdae__mbs_sparse_linalg, sparse);
    for (int k = 0; k < 1000; k++)
      ck_assert_int_eq(sdae_mbs_step(s, k * 1e-3, 1e-3, q, v), SDAE_OK);
    ck_assert_uint_eq(sdae_mbs_stepper_stats(s)->projected_steps, 0);
    ck_assert_double_le(fabs(q[0] - R * cos(w)), 1e-10);
    ck_assert_double_le(fabs(q[1] - R * sin(w)), 1e-10);
    ck_assert_double_le(fabs(q[2] - z0), 1e-10);
    sdae_mbs_stepper_free(s);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("mbs_sparse");
  ADD_CASE(s, a_mass_not_symmetric_is_refused);
  ADD_CASE(s, the_kept_point_serves_its_own_t_only);
  ADD_CASE(s, floors_as_the_dense_ones);
  ADD_CASE(s, a_failure_inside_a_configuration_is_the_steps);
  ADD_CASE(s, a_failure_inside_a_query_is_reported);
  ADD_CASE(s, a_state_with_no_chart_is_damaged);
  ADD_CASE(s, a_constraint_in_time_in_sparse_coordinates);
  ADD_CASE(s, a_shared_coordinate_steps_at_the_cost_of_its_nonzeros);
  ADD_CASE(s, every_topology_as_accurate_as_the_dense_path);
  ADD_CASE(s, every_topology_implicit_as_accurate_as_the_dense_path);
  ADD_CASE(s, a_coordinate_without_mass_steps_on_both_back_ends);
  ADD_CASE(s, a_chart_past_its_reserve_is_named);
  ADD_CASE(s, nearly_dependent_constraints_keep_the_motion);
  ADD_CASE(s, a_zero_jacobian_is_rank);
  ADD_CASE(s, a_failing_callback_in_a_query_is_reported);
  ADD_CASE(s, the_sparse_coordinates_serve_every_map);
  ADD_CASE(s, rk4_and_rk8_keep_their_orders);
  ADD_CASE(s, constraints_at_the_rounding_of_q_on_a_long_rope);
  ADD_CASE(s, the_block_grows_with_the_nonzeros);
  ADD_CASE(s, the_block_is_what_the_analysis_counts);
  ADD_CASE(s, the_charts_l_is_reserved_at_its_bound);
  ADD_CASE(s, a_query_between_steps_leaves_the_motion);
  ADD_CASE(s, a_stiff_rope_keeps_its_energy_on_both_back_ends);
  ADD_CASE(s, lambda_energy_and_xi_as_the_dense_ones);
  ADD_CASE(s, the_state_continues_bit_for_bit);
  ADD_CASE(s, a_failed_step_leaves_no_trace);
  return run_suite(s);
}
