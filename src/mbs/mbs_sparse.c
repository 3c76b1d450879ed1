/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The sparse back-end (mbs_sparse.h): every product through the patterns, the chart's solves
 * through core/sparse_lu.c and the saddle-point system's through core/sparse_ldl.c. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "core/callback.h"
#include "core/lu.h"
#include "maps/map.h"
#include "mbs_sparse.h"

int sdae__mbs_sparse_applies(const sdae_mbs *sys, const sdae_options *o) {
  return sdae__mbs_rank(sys) == sys->n_c && sys->mass_pattern && sys->jacobian_pattern &&
         sys->jacobian_dot && sys->mass_dot_v && o->map &&
         (!sdae__map_uses_newton(o->map) || sdae__map_slope_known(o->map));
}

static int init(void *p, sdae_mbs_eval *eval, const sdae_options *o) {
  sdae_mbs_sparse *sp = p;
  eval->matrices = 0; /* the stencils' dense matrices grow with n_q^2 */
  sp->eval = eval;
  sp->n_q = eval->n_q;
  sp->n_c = eval->n_c;
  sp->n_f = sp->n_q - sp->n_c;
  sp->implicit = sdae__map_uses_newton(o->map);
  return sdae__mbs_sparse_layout_init(&sp->ly, eval);
}

/* L's reserve: the most entries L holds in any of the orders (sdae__sparse_lu_l_bound), or U's
 * reserve where that is less */
static void l_reserve(sdae_mbs_sparse *sp, SuiteSparse_long *work) {
  size_t m = sp->n_c, u_cap = sdae__sparse_lu_reserve(m, sp->Gp->nnz), bound = 0;
  for (size_t o = 0; o < SDAE_SPARSE_LU_ORDERS; o++) {
    size_t most = sdae__sparse_lu_l_bound(sp->Gp, m, sp->n_q, sp->orders + o * m, u_cap, work);
    if (most > bound) bound = most;
  }
  sp->l_cap = bound < u_cap ? bound : u_cap;
}

/* K analysed (its L's count), the orders the chart's factorization tries found and L's reserve
 * taken, in workspace lent for it (its 9 (n_q + n_c) + 2.4 nnz(G) entries at least pass
 * sdae__sparse_lu_orders_min); nothing when only counted */
static int analyse_in_block(sdae_mbs_sparse *sp, sdae_arena *a) {
  size_t len = sdae__mbs_sparse_layout_work_len(&sp->ly), mark;
  SuiteSparse_long *work =
      sdae__arena_lend(a, len, sizeof *work, _Alignof(SuiteSparse_long), &mark);
  int rc = SDAE_OK;
  if (work) {
    sdae__mbs_sparse_layout_analyse(&sp->ly, work);
    rc = sdae__sparse_lu_orders(sp->Gp, sp->n_c, sp->n_q, work, len, sp->orders);
    if (rc == SDAE_OK) l_reserve(sp, work);
  }
  sdae__arena_reclaim(a, mark);
  return rc;
}

/* the layout's arrays and the orders, then the analysis: what the arrays after them are sized
 * by */
static int carve_analysed(sdae_mbs_sparse *sp, sdae_arena *a) {
  sdae__mbs_sparse_layout_carve(&sp->ly, a);
  sp->Gp = sp->ly.Gp;
  sp->orders = sdae__take_indices(a, SDAE_SPARSE_LU_ORDERS * sp->n_c);
  return analyse_in_block(sp, a);
}

/* the analysis run in scratch, for a block measured before it is built */
static int analyse(void *p, const sdae_scratch *scratch) {
  sdae_mbs_sparse *sp = p;
  sdae_arena a = {0};
  size_t bytes;
  void *mem;
  int rc;
  carve_analysed(sp, &a);
  if ((rc = sdae__block_bytes(&a, 0, &bytes)) != SDAE_OK) return rc;
  if ((rc = sdae__scratch_take(scratch, bytes, &mem)) != SDAE_OK) return rc;
  sdae__block_start(mem, 0, &a);
  rc = carve_analysed(sp, &a); /* the arrays lent: carved again, in the block */
  sdae__scratch_give(scratch, mem, bytes);
  return rc;
}

/* the arrays, counted or handed out: the layout's and the orders first, then the analysis
 * (run again in the block) in workspace the arrays after it overlay, sizing the
 * factorizations; handed out, the chart's orders may refuse G */
static int carve(void *p, sdae_arena *a) {
  sdae_mbs_sparse *sp = p;
  int rc = carve_analysed(sp, a);
  size_t n_q = sp->n_q, n_c = sp->n_c, n_k = sp->ly.n_k, gnz = sp->ly.Gp->nnz;
  sdae__sparse_lu_carve(&sp->lu[0], n_c, n_q, gnz, sp->l_cap, a);
  sdae__sparse_lu_carve(&sp->lu[1], n_c, n_q, gnz, sp->l_cap, a);
  sp->ind = sdae__take_indices(a, sp->n_f);
  sp->K = sdae__take(a, sp->ly.knz, 1);
  sdae__sparse_ldl_carve(&sp->kkt, &sp->ly.ksym, a);
  if (sp->implicit) sdae__sparse_ldl_carve(&sp->newton, &sp->ly.ksym, a);
  sp->Dv = sdae__take(a, sp->eval->sys.damping ? sp->ly.Mp->nnz : 0, 1);
  sp->G = sdae__take(a, gnz, 1), sp->M = sdae__take(a, sp->ly.Mp->nnz, 1);
  sp->Gd = sdae__take(a, gnz, 1);
  sp->nu = sdae__take(a, n_c, 1);
  sp->Mdv = sdae__take(a, n_q, 1);
  sp->rhs = sdae__take(a, n_k, 1), sp->sol = sdae__take(a, n_k, 1);
  sp->k_res = sdae__take(a, n_k, 1), sp->k_dx = sdae__take(a, n_k, 1);
  sp->zc = sdae__take(a, n_c, 1), sp->yd = sdae__take(a, n_c, 1), sp->res = sdae__take(a, n_c, 1);
  sp->est_x = sdae__take(a, n_q, 1), sp->est_z = sdae__take(a, n_q, 1);
  sp->lend = (sdae_mbs_sparse_lent){sp->K, sp->rhs, sp->sol, sp->k_res, sp->k_dx, &sp->kkt};
  sdae__mbs_sparse_query_carve(&sp->query, &sp->ly, &sp->lend, a);
  return rc;
}

/* ---- W^T ---- */

static const sdae_sparse_lu *chart(const sdae_mbs_sparse *sp) { return &sp->lu[sp->cur]; }

/* out (n_f, by q_I) = W^T y = y_I - G_I^T G_D^-T y_D */
static void wt(void *p, const double *y, double *out) {
  sdae_mbs_sparse *sp = p;
  sdae_sparse_lu *lu = &sp->lu[sp->cur];
  const sdae_pattern *G = sp->Gp;
  double *acc = sp->est_x; /* n_q */
  for (size_t k = 0; k < sp->n_c; k++) sp->yd[k] = y[lu->pivot[k]];
  sdae__sparse_lu_solve_t(lu, sp->yd, sp->zc);
  for (size_t f = 0; f < sp->n_f; f++) acc[sp->ind[f]] = 0.0;
  for (size_t j = 0; j < sp->n_c; j++)
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++)
      if (lu->row_of[G->col[e]] == sp->n_c) acc[G->col[e]] += sp->G[e] * sp->zc[j];
  for (size_t f = 0; f < sp->n_f; f++) out[f] = y[sp->ind[f]] - acc[sp->ind[f]];
}

/* ---- the chart ---- */

/* the current chart's q_I: the columns no row pivots on */
static void independents(sdae_mbs_sparse *sp) {
  const sdae_sparse_lu *lu = chart(sp);
  for (size_t c = 0, f = 0; c < sp->n_q; c++)
    if (lu->row_of[c] == sp->n_c) sp->ind[f++] = c;
}

static double estimate(sdae_mbs_sparse *sp, int which) {
  return sdae__sparse_lu_norm1(&sp->lu[which], sp->est_x, sp->est_z);
}

/* the two factorizations split q alike (the same dependent coordinates) */
static int same_chart(const sdae_mbs_sparse *sp) {
  const size_t *a = sp->lu[0].row_of, *b = sp->lu[1].row_of, m = sp->n_c;
  for (size_t c = 0; c < sp->n_q; c++)
    if ((a[c] == m) != (b[c] == m)) return 0;
  return 1;
}

/* the best chart into factorization which: in the current chart's order, or where there is
 * none or its factors outgrow their reserve, the best of every order's (choose_best's rule) */
static int propose(sdae_mbs_sparse *sp, int which) {
  sdae_sparse_lu *lu = &sp->lu[which];
  int rc = SDAE_ERR_PATTERN;
  if (sp->have) {
    memcpy(lu->order, chart(sp)->order, sp->n_c * sizeof *lu->order);
    rc = sdae__sparse_lu_choose(lu, sp->Gp, sp->G);
  }
  return rc == SDAE_ERR_PATTERN
             ? sdae__sparse_lu_choose_best(lu, sp->Gp, sp->G, sp->orders, SDAE_SPARSE_LU_ORDERS,
                                           SDAE_MBS_CHART_FACTOR, sp->est_x, sp->est_z)
             : rc;
}

/* The rule of both back-ends (sdae__mbs_chart_keeps): the best chart (sdae__sparse_lu_choose's,
 * measured by the estimate of ||G_D^-1 G_I||_1) sought at every start, the current one, where
 * it is still regular, kept unless worse by SDAE_MBS_CHART_FACTOR (or force_best). Kept only
 * until its refactoring grows by that factor, as before, a chart was stepped close to its fold:
 * on a ladder of 16 four-bar cells rk4 lost 90 times the dense path's accuracy at a crossing. */
static int choose_chart(sdae_mbs_sparse *sp, int force_best, int reuse) {
  double now = HUGE_VAL, best;
  int other = 1 - sp->cur, current, same, rc;
  sp->kept = sp->switched = 0;
  current =
      sp->have && (reuse || sdae__sparse_lu_refactor(&sp->lu[sp->cur], sp->Gp, sp->G) == SDAE_OK);
  if (current) now = estimate(sp, sp->cur);
  if ((rc = propose(sp, other)) != SDAE_OK) {
    if (!current) return rc;
    sp->measure = now; /* the current one serves */
    return SDAE_OK;
  }
  best = estimate(sp, other);
  same = sp->have && same_chart(sp);
  if (current && (same || sdae__mbs_chart_keeps(force_best, now, best))) {
    sp->kept = !same, sp->measure = now;
    return SDAE_OK;
  }
  sp->switched = sp->have && !same;
  sp->cur = other, sp->have = 1, sp->measure = best;
  independents(sp);
  return SDAE_OK;
}

/* K at the stored M and G, factored (it does not depend on the chart: reused where the factors
 * are the point's, and not lent to a query since; a step's first solve follows this, at its
 * start's choice of the chart or a configuration, so a query between steps is undone here) */
static int velocity_factor(void *p, int reuse) {
  sdae_mbs_sparse *sp = p;
  if (reuse && !sp->lent) return SDAE_OK;
  sp->lent = 0;
  sdae__mbs_sparse_kkt_values(&sp->ly, sp->M, sp->G, sp->K);
  return sdae__sparse_ldl_factor(&sp->kkt, sp->K);
}

/* ||M||_inf at the stored M */
static double mass_norm(const sdae_mbs_sparse *sp) {
  const sdae_pattern *Mp = sp->ly.Mp;
  double big = 0.0;
  for (size_t i = 0; i < sp->n_q; i++) {
    double row = 0.0;
    for (size_t e = Mp->row_start[i]; e < Mp->row_start[i + 1]; e++) row += fabs(sp->M[e]);
    big = fmax(big, row);
  }
  return big;
}

static void kkt_solve(sdae_mbs_sparse *sp);

/* The constraints' independence at the stored G and M, the velocity's system factored there:
 * the least singular value of G_s M^-1/2 (G_s = D G, its rows at unit length) by POWER_STEPS
 * steps of the power method on D S^-1 D, S = G M^-1 G^T (a solve of the system with the
 * right-hand side (0, D y) each: its multipliers are -S^-1 D y), times sqrt(||M||_inf) and over
 * G_s's largest column norm, so that with M = m I it is sigma_min(G_s) on the scale of the dense
 * back-end's R_last / R_00. Where rank G drops, the few small singular values stand apart from
 * the others and three steps find their size: on the N-four-bar it follows the dense measure
 * within a factor 1.9 through a crossing (the rest, M's metric), where the least pivot of the
 * factorization (the least sine of a row to those before it in its order, sdae_sparse_ldl's
 * least) was 4.2 times it near the crossing and 2.9 times it far from it. */
#define POWER_STEPS 3
static double independence(sdae_mbs_sparse *sp) {
  size_t n_q = sp->n_q, n_c = sp->n_c;
  const sdae_pattern *Gp = sp->Gp;
  double lam = 0.0, column = 0.0, *y = sp->yd, *d = sp->zc, *col = sp->est_x;
  memset(col, 0, n_q * sizeof *col);
  for (size_t j = 0; j < n_c; j++) {
    double g = 0.0;
    for (size_t e = Gp->row_start[j]; e < Gp->row_start[j + 1]; e++) g += sp->G[e] * sp->G[e];
    d[j] = 1.0 / sqrt(g); /* not 0: the factorization refuses a zero row (SDAE_ERR_RANK) */
    for (size_t e = Gp->row_start[j]; e < Gp->row_start[j + 1]; e++)
      col[Gp->col[e]] += sp->G[e] * sp->G[e] / g;
    y[j] = 1.0 + 0.5 * sin((double)j); /* a start without the mechanism's symmetries */
  }
  for (size_t i = 0; i < n_q; i++) column = fmax(column, col[i]);
  for (int it = 0; it < POWER_STEPS; it++) {
    double ny = 0.0, nz = 0.0;
    memset(sp->rhs, 0, n_q * sizeof *sp->rhs);
    for (size_t j = 0; j < n_c; j++) sp->rhs[n_q + j] = d[j] * y[j], ny += y[j] * y[j];
    kkt_solve(sp);
    for (size_t j = 0; j < n_c; j++) y[j] = -d[j] * sp->sol[n_q + j], nz += y[j] * y[j];
    if (!(nz > 0.0 && isfinite(nz))) return 0.0;
    lam = sqrt(nz / ny);
    for (size_t j = 0; j < n_c; j++) y[j] /= sqrt(nz);
  }
  return sqrt(mass_norm(sp) / lam / column);
}

/* The chart, and the constraints' independence (above) from the velocity's system factored at
 * the start, which the start's seed then solves with. No sparse factorization reveals rank as
 * a pivoted QR does; a rank lost to rounding in the chart or in the velocity's system is CHART
 * or RANK, after which the step is projected as well. */
static int choose(void *p, int force_best, int reuse, sdae_mbs_choice *choice) {
  sdae_mbs_sparse *sp = p;
  int rc = choose_chart(sp, force_best, reuse);
  choice->independence = 0.0;
  if (rc != SDAE_OK) return rc;
  choice->switched = sp->switched, choice->kept = sp->kept;
  if ((rc = velocity_factor(p, reuse)) != SDAE_OK) return rc;
  choice->independence = independence(sp);
  return SDAE_OK;
}

/* G_D's factors at the stored G in the current chart: the chart's and Newton's alike */
static int factor(void *p) {
  sdae_mbs_sparse *sp = p;
  return sdae__sparse_lu_refactor(&sp->lu[sp->cur], sp->Gp, sp->G);
}

static void split(const void *p, const size_t **dep, const size_t **ind) {
  const sdae_mbs_sparse *sp = p;
  *dep = chart(sp)->pivot, *ind = sp->ind;
}

static void gd_solve(void *p, const double *rhs, double *x) {
  sdae_mbs_sparse *sp = p;
  sdae__sparse_lu_solve(&sp->lu[sp->cur], rhs, x);
}

/* G_D^-1 G_I dq_I by the factors' B */
static void move(void *p, const double *dxi, const double *dq, double *dq_D) {
  sdae_mbs_sparse *sp = p;
  sdae_sparse_lu *lu = &sp->lu[sp->cur];
  sdae__sparse_lu_solve(lu, dxi, dq_D);
  sdae__sparse_lu_times_b(lu, dq, sp->zc);
  for (size_t k = 0; k < sp->n_c; k++) dq_D[k] = dq_D[k] - sp->zc[k];
}

/* ---- G and M at the point ---- */

static int jacobian(void *p, double t, const double *q) {
  sdae_mbs_sparse *sp = p;
  return sdae__mbs_jacobian_values(sp->eval, t, q, sp->G);
}

static int mass(void *p, double t, const double *q) {
  sdae_mbs_sparse *sp = p;
  return sdae__mbs_mass_values(sp->eval, t, q, sp->M);
}

static int mass_symmetric(const void *p) {
  const sdae_mbs_sparse *sp = p;
  return sdae__mbs_sparse_mass_symmetric(&sp->ly, sp->M);
}

static void g_times(const void *p, const double *x, const double *add, double *out) {
  const sdae_mbs_sparse *sp = p;
  sdae__mbs_sparse_g_times(&sp->ly, sp->G, x, add, out);
}

static void m_times(const void *p, const double *x, double *out) {
  const sdae_mbs_sparse *sp = p;
  sdae__mbs_sparse_m_times(&sp->ly, sp->M, x, out);
}

static double row_size(const void *p, size_t j) {
  const sdae_mbs_sparse *sp = p;
  double g = 0.0;
  for (size_t e = sp->Gp->row_start[j]; e < sp->Gp->row_start[j + 1]; e++) g += fabs(sp->G[e]);
  return g;
}

/* ---- the velocity: [M G^T; G 0] [v; nu] = [P^T (0, p); g] ---- */

/* K x = b by the factors, then one step of iterative refinement against K itself (the residual
 * b - K x solved for by the same factors). The order of the coordinates before the multipliers
 * solves like the normal equations (G M^-1 G^T formed): its error in v grows as eps / sin^2 of
 * the least angle between the constraints' gradients, where the dense back-end's G_D^-1 grows as
 * eps / sin, though its residual is at rounding (a test on it would not refine). A particle on
 * two spheres whose gradients are 1e-4 rad apart was 1.4e-6 off after 1 s of rk8 (the dense
 * back-end 4e-12), refined 2e-12; 1e-6 apart 5e-3 off, refined 6e-6 (the dense 2.6e-10).
 * Refined only below a least pivot of 1e-2 of its scale, the N-four-bar given its patterns was
 * 37 times (10 four-bars, rk4, T = 1e-4, 5 s) and 115 times (40, rk8, T = 1e-2) farther from
 * its reference than on the dense back-end, refined at every solve as close; a rope's pivots
 * (1 / links of their scales) were refined from 100 links on already. */
static void kkt_solve(sdae_mbs_sparse *sp) {
  const SuiteSparse_long *start = sp->ly.ksym.Ap, *col = sp->ly.ksym.Ai;
  size_t n = sp->ly.n_k;
  sdae__sparse_ldl_solve(&sp->kkt, sp->rhs, sp->sol);
  for (size_t i = 0; i < n; i++) {
    double acc = sp->rhs[i];
    for (SuiteSparse_long e = start[i]; e < start[i + 1]; e++) acc -= sp->K[e] * sp->sol[col[e]];
    sp->k_res[i] = acc;
  }
  sdae__sparse_ldl_solve(&sp->kkt, sp->k_res, sp->k_dx);
  for (size_t i = 0; i < n; i++) sp->sol[i] += sp->k_dx[i];
}

/* v and nu from p and g. The saddle-point solve leaves G v - g at its own accuracy, which the
 * chain's condition makes grow with its length (N^2): v_D is then moved by G_D^-1 (g - G v), as
 * the dense back-end forms v = z + W v_I with G_D z_D = g, so that xi's velocity part stays at
 * rounding (and Q's columns are skipped) */
static int velocity(void *p, const double *g, const double *mom, double *v) {
  sdae_mbs_sparse *sp = p;
  sdae_sparse_lu *lu = &sp->lu[sp->cur];
  memset(sp->rhs, 0, sp->n_q * sizeof *sp->rhs);
  for (size_t f = 0; f < sp->n_f; f++) sp->rhs[sp->ind[f]] = mom[f];
  memcpy(sp->rhs + sp->n_q, g, sp->n_c * sizeof *g);
  kkt_solve(sp);
  memcpy(v, sp->sol, sp->n_q * sizeof *v);
  memcpy(sp->nu, sp->sol + sp->n_q, sp->n_c * sizeof *sp->nu);
  sdae__mbs_sparse_g_times(&sp->ly, sp->G, v, NULL, sp->res);
  for (size_t j = 0; j < sp->n_c; j++) sp->res[j] = g[j] - sp->res[j];
  sdae__sparse_lu_solve(lu, sp->res, sp->zc);
  for (size_t k = 0; k < sp->n_c; k++) v[lu->pivot[k]] += sp->zc[k];
  return sdae__all_finite(sp->sol, sp->ly.n_k) && sdae__all_finite(v, sp->n_q) ? SDAE_OK
                                                                               : SDAE_ERR_NONFINITE;
}

/* the momentum rate needs the multipliers nu at the start: solved for (v then the caller's)
 * with the factors the chart's choice made at the start */
static int seed(void *p, int reuse, const double *g, const double *mom, double *v) {
  (void)reuse;
  return velocity(p, g, mom, v);
}

/* W^T (F + (dM/dt) v + (dG/dt)^T nu) at the point */
static int momentum_rate(void *p, double t, const double *q, const double *v, double *F,
                         double *out) {
  sdae_mbs_sparse *sp = p;
  const sdae_pattern *G = sp->Gp;
  int rc;
  if ((rc = sdae__mbs_mass_dot_v(sp->eval, t, q, v, sp->Mdv)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian_dot_values(sp->eval, t, q, v, sp->Gd)) != SDAE_OK)
    return rc;
  for (size_t i = 0; i < sp->n_q; i++) F[i] += sp->Mdv[i];
  for (size_t j = 0; j < sp->n_c; j++)
    for (size_t e = G->row_start[j]; e < G->row_start[j + 1]; e++)
      F[G->col[e]] += sp->Gd[e] * sp->nu[j];
  wt(sp, F, out);
  return SDAE_OK;
}

/* ---- the energy structure and the implicit maps' Newton ---- */

static int energy(void *p, double t, const double *q, const double *v, double *E) {
  sdae_mbs_sparse *sp = p;
  double V = 0.0, kinetic = 0.0;
  int rc;
  if (sp->eval->sys.potential && (rc = sdae__mbs_potential(sp->eval, t, q, &V)) != SDAE_OK)
    return rc;
  m_times(sp, v, sp->Mdv);
  for (size_t i = 0; i < sp->n_q; i++) kinetic += v[i] * sp->Mdv[i];
  *E = 0.5 * kinetic + V;
  return SDAE_OK;
}

static int damping_times(void *p, double t, const double *q, const double *x, double *out) {
  sdae_mbs_sparse *sp = p;
  int rc = sdae__mbs_damping_values(sp->eval, t, q, sp->Dv);
  if (rc == SDAE_OK) sdae__mbs_sparse_m_times(&sp->ly, sp->Dv, x, out);
  return rc;
}

static void newton_keep(void *p) {
  sdae_mbs_sparse *sp = p;
  sdae__sparse_ldl_copy(&sp->newton, &sp->kkt);
}

/* [M G^T; G 0] [w; nu] = [P^T (0, b); 0] by the kept factors */
static int newton_velocity(void *p, const double *b, double *w) {
  sdae_mbs_sparse *sp = p;
  memset(sp->rhs, 0, sp->ly.n_k * sizeof *sp->rhs);
  for (size_t f = 0; f < sp->n_f; f++) sp->rhs[sp->ind[f]] = b[f];
  sdae__sparse_ldl_solve(&sp->newton, sp->rhs, sp->sol);
  memcpy(w, sp->sol, sp->n_q * sizeof *w);
  return sdae__all_finite(w, sp->n_q) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

/* ---- the chart's and the state's ---- */

static int chart_dependent(const void *p, size_t *dep) {
  const sdae_mbs_sparse *sp = p;
  const sdae_sparse_lu *lu = chart(sp);
  if (!sp->have) return SDAE_ERR_CHART;
  for (size_t c = 0, k = 0; c < sp->n_q; c++)
    if (lu->row_of[c] != sp->n_c) dep[k++] = c;
  return SDAE_OK;
}

static double measure(const void *p) { return ((const sdae_mbs_sparse *)p)->measure; }

static void lu_pivots(sdae_sparse_lu *lu, sdae_bytes *b) {
  sdae__bytes(b, lu->order, lu->m * sizeof *lu->order);
  sdae__bytes(b, lu->pivot, lu->m * sizeof *lu->pivot);
  sdae__bytes(b, lu->row_of, lu->n * sizeof *lu->row_of);
}

/* pivots that are a permutation's: pivot[k] a column whose row is k, every other column none;
 * the order a permutation of the rows */
static int lu_valid(sdae_sparse_lu *lu) {
  size_t rows = 0;
  memset(lu->done, 0, lu->m); /* the order's scratch: each row once */
  for (size_t k = 0; k < lu->m; k++) {
    if (lu->order[k] >= lu->m || lu->done[lu->order[k]]) return 0;
    lu->done[lu->order[k]] = 1;
  }
  for (size_t c = 0; c < lu->n; c++) {
    if (lu->row_of[c] == lu->m) continue;
    if (lu->row_of[c] > lu->m || lu->pivot[lu->row_of[c]] != c) return 0;
    rows++;
  }
  return rows == lu->m;
}

/* The chart as its factorizations' pivots (q_I, the columns no row pivots on, derived from
 * them where they are a permutation's), then G, M and nu at the point */
static void state(void *p, sdae_bytes *b) {
  sdae_mbs_sparse *sp = p;
  sdae__bytes_flag(b, &sp->have);
  sdae__bytes_flag(b, &sp->cur);
  sdae__bytes_doubles(b, &sp->measure, 1);
  lu_pivots(&sp->lu[0], b);
  lu_pivots(&sp->lu[1], b);
  sdae__bytes_doubles(b, sp->G, sp->Gp->nnz);
  sdae__bytes_doubles(b, sp->M, sp->ly.Mp->nnz);
  sdae__bytes_doubles(b, sp->nu, sp->n_c);
  if (b->in && sp->have && lu_valid(&sp->lu[sp->cur])) independents(sp);
}

/* bytes read hold pivots that index the mechanism's columns */
static int state_read(void *p) {
  sdae_mbs_sparse *sp = p;
  return !sp->have || lu_valid(&sp->lu[sp->cur]);
}

static int query_xi(void *p, double t, const double *q, const double *v, double *out) {
  return sdae__mbs_sparse_query_xi(&((sdae_mbs_sparse *)p)->query, t, q, v, out);
}

static int query_energy(void *p, double t, const double *q, const double *v, double *E) {
  return sdae__mbs_sparse_query_energy(&((sdae_mbs_sparse *)p)->query, t, q, v, E);
}

static int query_lambda(void *p, double t, const double *q, const double *v, double *out) {
  sdae_mbs_sparse *sp = p;
  sp->lent = 1; /* the factors are the query's after it */
  return sdae__mbs_sparse_query_lambda(&sp->query, t, q, v, out);
}

const sdae_mbs_linalg sdae__mbs_sparse_linalg = {
    .name = "sparse",
    .init = init,
    .analyse = analyse,
    .carve = carve,
    .jacobian = jacobian,
    .mass = mass,
    .mass_symmetric = mass_symmetric,
    .g_times = g_times,
    .m_times = m_times,
    .row_size = row_size,
    .choose = choose,
    .factor = factor,
    .gd_factor = factor,
    .split = split,
    .gd_solve = gd_solve,
    .move = move,
    .wt = wt,
    .velocity_factor = velocity_factor,
    .velocity = velocity,
    .seed = seed,
    .momentum_rate = momentum_rate,
    .energy = energy,
    .damping_times = damping_times,
    .newton_keep = newton_keep,
    .newton_velocity = newton_velocity,
    .chart = chart_dependent,
    .measure = measure,
    .state = state,
    .state_read = state_read,
    .query_xi = query_xi,
    .query_energy = query_energy,
    .query_lambda = query_lambda,
};
