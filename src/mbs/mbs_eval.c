/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanism's callbacks, every status and value checked, and the derivatives it may leave
 * out (G = dc/dq, dc/dt, and the derivatives along the motion: each one given is called instead)
 * by the fourth-order central difference
 *
 *   f'(0) ~ [8 (f(s) - f(-s)) - (f(2s) - f(-2s))] / (12 s),   error ~ s^4 f^(5) / 30 + eps f / s,
 *
 * with s about eps^(1/5) times the scale of the variable: about 1e-13 relative, the level of
 * rounding in the quantities built from them. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_linalg.h>
#include <gsl/gsl_permutation.h>

#include "core/callback.h"
#include "core/difference.h"
#include "core/lu.h"
#include "mbs_eval.h"

int sdae__mbs_patterns_check(const sdae_mbs *sys) {
  int rc;
  if (sys->jacobian_pattern && !sys->jacobian) return SDAE_ERR_NULL;
  if (sys->mass_pattern &&
      (rc = sdae__pattern_check(sys->mass_pattern, sys->n_q, sys->n_q, 1)) != SDAE_OK)
    return rc;
  return sys->jacobian_pattern ? sdae__pattern_check(sys->jacobian_pattern, sys->n_c, sys->n_q, 0)
                               : SDAE_OK;
}

size_t sdae__mbs_rank(const sdae_mbs *sys) { return sys->rank ? sys->rank : sys->n_c; }

int sdae__mbs_redundant(const sdae_mbs_eval *e) { return e->n_c < e->n_rows; }

void sdae__mbs_eval_init(sdae_mbs_eval *e, const sdae_mbs *sys) {
  e->sys = *sys;
  e->n_q = sys->n_q;
  e->n_c = sdae__mbs_rank(sys);
  e->n_rows = sys->n_c;
  e->matrices = 1;
}

/* a pattern of the mechanism copied into the block, with room for its values; from then on the
 * mechanism's pattern is the copy (the caller's arrays may change or go) */
static void pattern_carve(const sdae_pattern **given, sdae_pattern *copy, double **values,
                          size_t rows, sdae_arena *a) {
  if (!*given) return;
  sdae__pattern_copy(copy, *given, rows, a);
  *values = sdae__take(a, copy->nnz, 1);
  if (copy->row_start) *given = copy;
}

void sdae__mbs_eval_carve(sdae_mbs_eval *e, sdae_arena *a) {
  size_t n_q = e->n_q, n_c = e->n_c, m = e->matrices ? n_q : 0;
  e->jac_q = sdae__take(a, n_q, 1);
  e->jac_c = sdae__take(a, e->n_rows, 1);
  e->ct_c = sdae__take(a, e->n_rows, 1);
  e->along_q = sdae__take(a, n_q, 1);
  e->along_G = sdae__take(a, n_c, m);
  e->along_M = sdae__take(a, m, m);
  e->along_ct = sdae__take(a, n_c, 1);
  e->along_Mv = sdae__take(a, m, 1);
  e->along_Gdot = sdae__take(a, n_c, m);
  e->along_ctdot = sdae__take(a, n_c, 1);
  e->t_Gdot = sdae__take(a, n_c, m);
  e->t_Mdv = sdae__take(a, n_q, 1);
  e->t_ctdot = sdae__take(a, n_c, 1);
  e->input = sdae__take(a, n_q, 1);
  pattern_carve(&e->sys.mass_pattern, &e->mass_pattern, &e->mass_values, n_q, a);
  pattern_carve(&e->sys.jacobian_pattern, &e->jacobian_pattern, &e->jacobian_values, e->n_rows, a);
  if (!sdae__mbs_redundant(e)) return;
  e->rows = sdae__take_indices(a, n_c);
  e->cand = sdae__take_indices(a, n_c);
  e->all_c = sdae__take(a, e->n_rows, 1);
  e->all_G = sdae__take(a, e->n_rows, n_q);
  e->all_ct = sdae__take(a, e->n_rows, 1);
  e->qr = sdae__take(a, n_q, e->n_rows);
  e->qr_tau = sdae__take(a, e->n_rows, 1);
  e->qr_norm = sdae__take(a, e->n_rows, 1);
  e->qr_perm = sdae__take_indices(a, e->n_rows);
}

/* ---- the rows chosen among redundant constraints ---- */

/* the chosen rows of all (n_rows x cols) into out (n_c x cols) */
static void gather(const sdae_mbs_eval *e, const double *all, size_t cols, double *out) {
  for (size_t k = 0; k < e->n_c; k++)
    memcpy(out + k * cols, all + e->rows[k] * cols, cols * sizeof *out);
}

/* a callback's rows (n_rows x cols, checked) into out, the chosen ones alone where they are
 * chosen: rc is the callback's status, all where it wrote */
static int rows_out(const sdae_mbs_eval *e, int rc, const double *all, size_t cols, double *out) {
  if ((rc = sdae__callback_checked(rc, all, e->n_rows * cols)) == SDAE_OK)
    gather(e, all, cols, out);
  return rc;
}

int sdae__mbs_state_ok(const sdae_mbs_eval *e, double t, const double *q, const double *v) {
  if (!isfinite(t)) return SDAE_ERR_PARAM;
  return sdae__all_finite(q, e->n_q) && sdae__all_finite(v, e->n_q) ? SDAE_OK : SDAE_ERR_STATE;
}

/* a matrix callback's status, its values (in pattern order with a pattern) checked and put in
 * place: rows x n_q, row-major */
static int matrix_checked(int rc, const sdae_pattern *p, const double *values, size_t rows,
                          size_t n_q, double *out) {
  if (!p) return sdae__callback_checked(rc, out, rows * n_q);
  if ((rc = sdae__callback_checked(rc, values, p->nnz)) == SDAE_OK)
    sdae__pattern_scatter(p, rows, n_q, values, out);
  return rc;
}

/* where a matrix callback writes: out, or the values of its pattern */
static double *target(const sdae_pattern *p, double *values, double *out) {
  return p ? values : out;
}

int sdae__mbs_mass(sdae_mbs_eval *e, double t, const double *q, double *M) {
  const sdae_pattern *p = e->sys.mass_pattern;
  int rc = e->sys.mass(t, q, target(p, e->mass_values, M), e->sys.params);
  return matrix_checked(rc, p, e->mass_values, e->n_q, e->n_q, M);
}

int sdae__mbs_mass_values(sdae_mbs_eval *e, double t, const double *q, double *values) {
  return sdae__callback_checked(e->sys.mass(t, q, values, e->sys.params), values,
                                e->sys.mass_pattern->nnz);
}

int sdae__mbs_damping_values(sdae_mbs_eval *e, double t, const double *q, double *values) {
  return sdae__callback_checked(e->sys.damping(t, q, values, e->sys.params), values,
                                e->sys.mass_pattern->nnz);
}

int sdae__mbs_jacobian_values(sdae_mbs_eval *e, double t, const double *q, double *values) {
  return sdae__callback_checked(e->sys.jacobian(t, q, values, e->sys.params), values,
                                e->sys.jacobian_pattern->nnz);
}

int sdae__mbs_jacobian_dot_values(sdae_mbs_eval *e, double t, const double *q, const double *v,
                                  double *values) {
  return sdae__callback_checked(e->sys.jacobian_dot(t, q, v, values, e->sys.params), values,
                                e->sys.jacobian_pattern->nnz);
}

int sdae__mbs_mass_dot_v(sdae_mbs_eval *e, double t, const double *q, const double *v,
                         double *out) {
  return sdae__callback_checked(e->sys.mass_dot_v(t, q, v, out, e->sys.params), out, e->n_q);
}

int sdae__mbs_mass_symmetric(sdae_mbs_eval *e, double t, const double *q, double *M) {
  int rc = sdae__mbs_mass(e, t, q, M);
  if (rc == SDAE_OK && !sdae__symmetric(M, e->n_q)) return SDAE_ERR_MASS;
  return rc;
}

int sdae__mbs_input_force(sdae_mbs_eval *e, double t, const double *q, const double *v, double *F) {
  if (!e->sys.input_force) {
    memset(F, 0, e->n_q * sizeof *F);
    return SDAE_OK;
  }
  return sdae__callback_checked(e->sys.input_force(t, q, v, F, e->sys.params), F, e->n_q);
}

int sdae__mbs_force(sdae_mbs_eval *e, double t, const double *q, const double *v, double *F) {
  int rc = sdae__callback_checked(e->sys.force(t, q, v, F, e->sys.params), F, e->n_q);
  if (rc != SDAE_OK || !e->sys.input_force) return rc;
  if ((rc = sdae__mbs_input_force(e, t, q, v, e->input)) != SDAE_OK) return rc;
  for (size_t i = 0; i < e->n_q; i++) F[i] += e->input[i];
  return SDAE_OK;
}

int sdae__mbs_constraint(sdae_mbs_eval *e, double t, const double *q, double *c) {
  if (sdae__mbs_redundant(e))
    return rows_out(e, e->sys.constraint(t, q, e->all_c, e->sys.params), e->all_c, 1, c);
  return sdae__callback_checked(e->sys.constraint(t, q, c, e->sys.params), c, e->n_c);
}

int sdae__mbs_potential(sdae_mbs_eval *e, double t, const double *q, double *V) {
  return sdae__callback_checked(e->sys.potential(t, q, V, e->sys.params), V, 1);
}

int sdae__mbs_damping(sdae_mbs_eval *e, double t, const double *q, double *D) {
  const sdae_pattern *p = e->sys.mass_pattern;
  int rc = e->sys.damping(t, q, target(p, e->mass_values, D), e->sys.params);
  return matrix_checked(rc, p, e->mass_values, e->n_q, e->n_q, D);
}

/* c at (t, q): the chosen rows, or all of them (n_rows) */
static int constraint_rows(sdae_mbs_eval *e, double t, const double *q, double *c, int all) {
  if (!all) return sdae__mbs_constraint(e, t, q, c);
  return sdae__callback_checked(e->sys.constraint(t, q, c, e->sys.params), c, e->n_rows);
}

/* G column by column: d/dh c(t, q + h e_j), the chosen rows or all of them */
static int jacobian_fd_rows(sdae_mbs_eval *e, double t, const double *q, double *G, int all) {
  size_t n_q = e->n_q, n_c = all ? e->n_rows : e->n_c;
  double *qs = e->jac_q, *c = e->jac_c;
  memcpy(qs, q, n_q * sizeof *q);
  for (size_t j = 0; j < n_q; j++) {
    double h = sdae__fd_step(q[j], SDAE_FD_STEP * fmax(1.0, fabs(q[j])));
    for (size_t i = 0; i < n_c; i++) G[i * n_q + j] = 0.0;
    for (int k = 0; k < SDAE_FD_POINTS; k++) {
      int rc;
      qs[j] = q[j] + sdae__fd_offset[k] * h;
      if ((rc = constraint_rows(e, t, qs, c, all)) != SDAE_OK) return rc;
      sdae__fd_add(G + j, n_q, c, n_c, k);
    }
    qs[j] = q[j];
    sdae__fd_finish(G + j, n_q, n_c, h);
  }
  return SDAE_OK;
}

/* every row of G given (n_rows x n_q) */
static int jacobian_given(sdae_mbs_eval *e, double t, const double *q, double *G) {
  const sdae_pattern *p = e->sys.jacobian_pattern;
  int rc = e->sys.jacobian(t, q, target(p, e->jacobian_values, G), e->sys.params);
  return matrix_checked(rc, p, e->jacobian_values, e->n_rows, e->n_q, G);
}

static int jacobian_fd(sdae_mbs_eval *e, double t, const double *q, double *G) {
  return jacobian_fd_rows(e, t, q, G, 0);
}

int sdae__mbs_jacobian(sdae_mbs_eval *e, double t, const double *q, double *G) {
  int rc;
  if (!e->sys.jacobian) return jacobian_fd(e, t, q, G);
  if (!sdae__mbs_redundant(e)) return jacobian_given(e, t, q, G);
  if ((rc = jacobian_given(e, t, q, e->all_G)) == SDAE_OK) gather(e, e->all_G, e->n_q, G);
  return rc;
}

/* A difference step in t relative to max(1, |t|): where t is so large that its doubles are too
 * sparse for the absolute step (t + h rounds to more than half the step away, beyond about
 * 1e12; h would vanish at 1e15, where the spacing is 0.125). */
static double t_step(double t) { return sdae__fd_step(t, SDAE_FD_STEP * fmax(1.0, fabs(t))); }

/* d/dh c(t + h, q): exactly 0 when c does not depend on t, the four values being equal. The step
 * is absolute while t can hold it: a driver's time scale (a road's period) does not grow with t,
 * so a step relative to t would lose its accuracy on the way (1 relative at t = 1e3 for a
 * period of 2). */
static int constraint_t_fd(sdae_mbs_eval *e, double t, const double *q, double *ct, int all) {
  size_t n = all ? e->n_rows : e->n_c;
  double h = sdae__fd_step(t, SDAE_FD_STEP), *c = e->ct_c;
  if (!(fabs(h - SDAE_FD_STEP) <= 0.5 * SDAE_FD_STEP)) h = t_step(t);
  memset(ct, 0, n * sizeof *ct);
  for (int k = 0; k < SDAE_FD_POINTS; k++) {
    int rc = constraint_rows(e, t + sdae__fd_offset[k] * h, q, c, all);
    if (rc != SDAE_OK) return rc;
    sdae__fd_add(ct, 1, c, n, k);
  }
  sdae__fd_finish(ct, 1, n, h);
  return SDAE_OK;
}

int sdae__mbs_constraint_t(sdae_mbs_eval *e, double t, const double *q, double *ct) {
  if (!e->sys.constraint_t) return constraint_t_fd(e, t, q, ct, 0);
  if (sdae__mbs_redundant(e))
    return rows_out(e, e->sys.constraint_t(t, q, e->all_ct, e->sys.params), e->all_ct, 1, ct);
  return sdae__callback_checked(e->sys.constraint_t(t, q, ct, e->sys.params), ct, e->n_c);
}

/* d/ds (dc/dt) given, the chosen rows */
static int ct_dot_given(sdae_mbs_eval *e, double t, const double *q, const double *v, double *out) {
  const sdae_mbs *s = &e->sys;
  if (sdae__mbs_redundant(e))
    return rows_out(e, s->constraint_t_dot(t, q, v, e->all_ct, s->params), e->all_ct, 1, out);
  return sdae__callback_checked(s->constraint_t_dot(t, q, v, out, s->params), out, e->n_c);
}

static double inf_norm(const double *x, size_t n) {
  double m = 0.0;
  for (size_t i = 0; i < n; i++) m = fabs(x[i]) > m ? fabs(x[i]) : m;
  return m;
}

/* What the stencil differences along (1, v): G (into Gdot), M v (into Mdv) and dc/dt (into
 * ctdot), each NULL when it is given or not wanted. */
typedef struct along_parts {
  double *Gdot, *Mdv, *ctdot;
} along_parts;

/* the sums of the stencil at offset k at (t + k ht, q + k hq v): G, M v and dc/dt there */
static int along_point(sdae_mbs_eval *e, double t, const double *q, const double *v, double ht,
                       double hq, int k, const along_parts *p) {
  size_t n_q = e->n_q, n_c = e->n_c;
  double ts = t + sdae__fd_offset[k] * ht;
  int rc;
  for (size_t j = 0; j < n_q; j++) e->along_q[j] = q[j] + sdae__fd_offset[k] * hq * v[j];
  if (p->Gdot) {
    if ((rc = sdae__mbs_jacobian(e, ts, e->along_q, e->along_G)) != SDAE_OK) return rc;
    sdae__fd_add(p->Gdot, 1, e->along_G, n_c * n_q, k);
  }
  if (p->Mdv) {
    if ((rc = sdae__mbs_mass(e, ts, e->along_q, e->along_M)) != SDAE_OK) return rc;
    /* each term M_ij v_j added in turn (stride 0: one sum per row) */
    for (size_t i = 0; i < n_q; i++) {
      for (size_t j = 0; j < n_q; j++) e->along_Mv[j] = e->along_M[i * n_q + j] * v[j];
      sdae__fd_add(p->Mdv + i, 0, e->along_Mv, n_q, k);
    }
  }
  if (p->ctdot) {
    if ((rc = sdae__mbs_constraint_t(e, ts, e->along_q, e->along_ct)) != SDAE_OK) return rc;
    sdae__fd_add(p->ctdot, 1, e->along_ct, n_c, k);
  }
  return SDAE_OK;
}

static void zero(double *x, size_t n) {
  if (x) memset(x, 0, n * sizeof *x);
}

static void finish(double *x, size_t n, double h) {
  if (x) sdae__fd_finish(x, 1, n, h);
}

/* the fourth-order difference in s of the parts at (t + s ht / h, q + s hq v / h), step h: the
 * derivative along (ht, hq v) / h */
static int stencil(sdae_mbs_eval *e, double t, const double *q, const double *v, double ht,
                   double hq, double h, const along_parts *p) {
  size_t n_q = e->n_q, n_c = e->n_c;
  zero(p->Gdot, n_c * n_q);
  zero(p->Mdv, n_q);
  zero(p->ctdot, n_c);
  for (int k = 0; k < SDAE_FD_POINTS; k++) {
    int rc = along_point(e, t, q, v, ht, hq, k, p);
    if (rc != SDAE_OK) return rc;
  }
  finish(p->Gdot, n_c * n_q, h);
  finish(p->Mdv, n_q, h);
  finish(p->ctdot, n_c, h);
  return SDAE_OK;
}

static void add(double *x, const double *y, size_t n) {
  if (x)
    for (size_t i = 0; i < n; i++) x[i] += y[i];
}

/* One step s along (1, v) moves q by s v and t by s: s about SDAE_FD_STEP relative to q and to v's
 * time scale, exact in t + s. Where t is so large that its doubles are too sparse for such an
 * s (t + s rounds to more than half the step away from it), the derivative is taken in two
 * parts, d/ds at (t, q + s v) and d/ds at (t + s, q) with a step in t relative to |t|. */
static int differenced(sdae_mbs_eval *e, double t, const double *q, const double *v,
                       const along_parts *p) {
  size_t n_q = e->n_q, n_c = e->n_c;
  double nq = inf_norm(q, n_q), h0 = SDAE_FD_STEP * (1.0 + nq) / (1.0 + nq + inf_norm(v, n_q));
  double h = sdae__fd_step(t, h0), ht;
  along_parts in_t = {p->Gdot ? e->t_Gdot : NULL, p->Mdv ? e->t_Mdv : NULL,
                      p->ctdot ? e->t_ctdot : NULL};
  int rc;
  if (fabs(h - h0) <= 0.5 * h0) return stencil(e, t, q, v, h, h, h, p);
  if ((rc = stencil(e, t, q, v, 0.0, h0, h0, p)) != SDAE_OK) return rc;
  ht = t_step(t);
  if ((rc = stencil(e, t, q, v, ht, 0.0, ht, &in_t)) != SDAE_OK) return rc;
  add(p->Gdot, e->t_Gdot, n_c * n_q);
  add(p->Mdv, e->t_Mdv, n_q);
  add(p->ctdot, e->t_ctdot, n_c);
  return SDAE_OK;
}

int sdae__mbs_ct_dot(sdae_mbs_eval *e, double t, const double *q, const double *v, double *out) {
  const sdae_mbs *s = &e->sys;
  along_parts p = {NULL, NULL, out};
  if (s->constraint_t_dot) return ct_dot_given(e, t, q, v, out);
  return differenced(e, t, q, v, &p);
}

/* Gdot given, the chosen rows */
static int jacobian_dot_given(sdae_mbs_eval *e, double t, const double *q, const double *v,
                              double *Gd) {
  const sdae_pattern *p = e->sys.jacobian_pattern;
  double *all = sdae__mbs_redundant(e) ? e->all_G : Gd;
  int rc = e->sys.jacobian_dot(t, q, v, target(p, e->jacobian_values, all), e->sys.params);
  if ((rc = matrix_checked(rc, p, e->jacobian_values, e->n_rows, e->n_q, all)) == SDAE_OK &&
      all != Gd)
    gather(e, all, e->n_q, Gd);
  return rc;
}

/* Each derivative the mechanism gives replaces its stencil (docs/front-ends.md, the cost of a
 * step); gamma = Gdot v + d/ds dc/dt, Gdot into scratch when only gamma is wanted. */
int sdae__mbs_along(sdae_mbs_eval *e, double t, const double *q, const double *v, double *Gdot,
                    double *Mdv, double *gdot) {
  const sdae_mbs *s = &e->sys;
  size_t n_q = e->n_q, n_c = e->n_c;
  double *Gd = Gdot ? Gdot : e->along_Gdot, *ctd = e->along_ctdot;
  int want_G = Gdot || gdot, fd_G = want_G && !s->jacobian_dot, fd_M = Mdv && !s->mass_dot_v;
  int fd_ct = gdot && !s->constraint_t_dot, rc;
  along_parts fd = {fd_G ? Gd : NULL, fd_M ? Mdv : NULL, fd_ct ? ctd : NULL};
  if ((fd_G || fd_M || fd_ct) && (rc = differenced(e, t, q, v, &fd)) != SDAE_OK) return rc;
  if (want_G && s->jacobian_dot && (rc = jacobian_dot_given(e, t, q, v, Gd)) != SDAE_OK) return rc;
  if (Mdv && s->mass_dot_v &&
      (rc = sdae__callback_checked(s->mass_dot_v(t, q, v, Mdv, s->params), Mdv, n_q)) != SDAE_OK)
    return rc;
  if (!gdot) return SDAE_OK;
  if (s->constraint_t_dot && (rc = ct_dot_given(e, t, q, v, ctd)) != SDAE_OK) return rc;
  for (size_t i = 0; i < n_c; i++) { /* gamma = Gdot v + d/ds dc/dt (docs/front-ends.md, lambda) */
    double g = ctd[i];
    for (size_t j = 0; j < n_q; j++) g += Gd[i * n_q + j] * v[j];
    gdot[i] = g;
  }
  return SDAE_OK;
}

void sdae__mbs_xi_compose(const sdae_mbs_eval *e, const double *v, const double *c, const double *G,
                          const double *ct, double *xi) {
  for (size_t j = 0; j < e->n_c; j++) {
    double cdot = ct[j];
    for (size_t i = 0; i < e->n_q; i++) cdot += G[j * e->n_q + i] * v[i];
    xi[2 * j] = c[j];
    xi[2 * j + 1] = cdot;
  }
}

int sdae__mbs_xi_of(sdae_mbs_eval *e, double t, const double *q, const double *v, double *c,
                    double *G, double *ct, double *xi) {
  int rc;
  if ((rc = sdae__mbs_constraint(e, t, q, c)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian(e, t, q, G)) != SDAE_OK ||
      (rc = sdae__mbs_constraint_t(e, t, q, ct)) != SDAE_OK)
    return rc;
  sdae__mbs_xi_compose(e, v, c, G, ct, xi);
  return SDAE_OK;
}

int sdae__mbs_energy_of(sdae_mbs_eval *e, double t, const double *q, const double *v,
                        const double *M, double *E) {
  size_t n = e->n_q;
  double V = 0.0, kinetic = 0.0;
  int rc;
  if (e->sys.potential && (rc = sdae__mbs_potential(e, t, q, &V)) != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) kinetic += v[i] * M[i * n + j] * v[j];
  *E = 0.5 * kinetic + V;
  return SDAE_OK;
}

/* ---- the choice of rows ---- */

static int ascending(const void *a, const void *b) {
  size_t x = *(const size_t *)a, y = *(const size_t *)b;
  return (x > y) - (x < y);
}

void sdae__mbs_rows_qr(const double *G, size_t n_q, const size_t *list, size_t n, double *qr,
                       double *tau, double *norm, size_t *perm) {
  size_t diag = n_q < n ? n_q : n;
  gsl_matrix_view A = gsl_matrix_view_array(qr, n_q, n);
  gsl_vector_view t = gsl_vector_view_array(tau, diag);
  gsl_vector_view nv = gsl_vector_view_array(norm, n);
  gsl_permutation p = {n, perm};
  int signum;
  for (size_t i = 0; i < n; i++) {
    const double *row = G + (list ? list[i] : i) * n_q;
    double len = 0.0;
    for (size_t j = 0; j < n_q; j++) len = hypot(len, row[j]);
    for (size_t j = 0; j < n_q; j++) qr[j * n + i] = len > 0.0 ? row[j] / len : 0.0;
  }
  gsl_linalg_QRPT_decomp(&A.matrix, &t.vector, &p, &signum, &nv.vector);
}

double sdae__mbs_rows_sine(const double *qr, size_t n_q, size_t n, size_t k) {
  double first = fabs(qr[0]);
  if (k >= (n_q < n ? n_q : n) || !(first > 0.0)) return 0.0;
  return fabs(qr[k * n + k]) / first;
}

/* the rows listed of all_G (NULL: every row) ranked in e->qr: the sine of the n_c-th into
 * *least, of the next into *next */
static void pivoted_qr(sdae_mbs_eval *e, const size_t *list, size_t n, double *least,
                       double *next) {
  sdae__mbs_rows_qr(e->all_G, e->n_q, list, n, e->qr, e->qr_tau, e->qr_norm, e->qr_perm);
  *least = sdae__mbs_rows_sine(e->qr, e->n_q, n, e->n_c - 1);
  *next = sdae__mbs_rows_sine(e->qr, e->n_q, n, e->n_c);
}

int sdae__mbs_jacobian_all(sdae_mbs_eval *e, double t, const double *q) {
  return e->sys.jacobian ? jacobian_given(e, t, q, e->all_G)
                         : jacobian_fd_rows(e, t, q, e->all_G, 1);
}

int sdae__mbs_select(sdae_mbs_eval *e, double t, const double *q, int force_best, int *changed,
                     int *kept) {
  double best, next, now, unused;
  int rc;
  *changed = *kept = 0;
  if (!sdae__mbs_redundant(e)) return SDAE_OK;
  if ((rc = sdae__mbs_jacobian_all(e, t, q)) != SDAE_OK) return rc;
  pivoted_qr(e, NULL, e->n_rows, &best, &next);
  if (!(best >= SDAE_MBS_CHART_MIN) || next >= SDAE_MBS_CHART_MIN) return SDAE_ERR_RANK;
  memcpy(e->cand, e->qr_perm, e->n_c * sizeof *e->cand);
  qsort(e->cand, e->n_c, sizeof *e->cand, ascending);
  if (e->have && !force_best) {
    pivoted_qr(e, e->rows, e->n_c, &now, &unused); /* the current rows' own least sine */
    if (now >= SDAE_MBS_CHART_MIN && !(best > SDAE_MBS_CHART_FACTOR * now)) {
      *kept = memcmp(e->rows, e->cand, e->n_c * sizeof *e->rows) != 0; /* over a better one */
      return SDAE_OK;
    }
  }
  *changed = !e->have || memcmp(e->rows, e->cand, e->n_c * sizeof *e->rows) != 0;
  memcpy(e->rows, e->cand, e->n_c * sizeof *e->rows);
  e->have = 1;
  return SDAE_OK;
}

void sdae__mbs_eval_state(sdae_mbs_eval *e, sdae_bytes *b) {
  if (!sdae__mbs_redundant(e)) return;
  sdae__bytes_flag(b, &e->have);
  sdae__bytes_sizes(b, e->rows, e->n_c);
}

int sdae__mbs_eval_valid(const sdae_mbs_eval *e) {
  if (!sdae__mbs_redundant(e) || !e->have) return 1;
  for (size_t k = 0; k < e->n_c; k++)
    if (e->rows[k] >= e->n_rows || (k > 0 && e->rows[k] <= e->rows[k - 1])) return 0;
  return 1;
}

int sdae__mbs_xi_all(sdae_mbs_eval *e, double t, const double *q, const double *v, double *xi) {
  size_t n_q = e->n_q;
  int rc;
  if ((rc = constraint_rows(e, t, q, e->all_c, 1)) != SDAE_OK ||
      (rc = sdae__mbs_jacobian_all(e, t, q)) != SDAE_OK)
    return rc;
  if (e->sys.constraint_t)
    rc = sdae__callback_checked(e->sys.constraint_t(t, q, e->all_ct, e->sys.params), e->all_ct,
                                e->n_rows);
  else
    rc = constraint_t_fd(e, t, q, e->all_ct, 1);
  if (rc != SDAE_OK) return rc;
  for (size_t j = 0; j < e->n_rows; j++) {
    double cdot = e->all_ct[j];
    for (size_t i = 0; i < n_q; i++) cdot += e->all_G[j * n_q + i] * v[i];
    xi[2 * j] = e->all_c[j], xi[2 * j + 1] = cdot;
  }
  return SDAE_OK;
}
