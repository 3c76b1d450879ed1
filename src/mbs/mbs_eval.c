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
#include <string.h>

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

void sdae__mbs_eval_init(sdae_mbs_eval *e, const sdae_mbs *sys) {
  e->sys = *sys;
  e->n_q = sys->n_q;
  e->n_c = sys->n_c;
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
  e->jac_c = sdae__take(a, n_c, 1);
  e->ct_c = sdae__take(a, n_c, 1);
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
  pattern_carve(&e->sys.jacobian_pattern, &e->jacobian_pattern, &e->jacobian_values, n_c, a);
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

/* G column by column: d/dh c(t, q + h e_j) */
static int jacobian_fd(sdae_mbs_eval *e, double t, const double *q, double *G) {
  size_t n_q = e->n_q, n_c = e->n_c;
  double *qs = e->jac_q, *c = e->jac_c;
  memcpy(qs, q, n_q * sizeof *q);
  for (size_t j = 0; j < n_q; j++) {
    double h = sdae__fd_step(q[j], SDAE_FD_STEP * fmax(1.0, fabs(q[j])));
    for (size_t i = 0; i < n_c; i++) G[i * n_q + j] = 0.0;
    for (int k = 0; k < SDAE_FD_POINTS; k++) {
      int rc;
      qs[j] = q[j] + sdae__fd_offset[k] * h;
      if ((rc = sdae__mbs_constraint(e, t, qs, c)) != SDAE_OK) return rc;
      sdae__fd_add(G + j, n_q, c, n_c, k);
    }
    qs[j] = q[j];
    sdae__fd_finish(G + j, n_q, n_c, h);
  }
  return SDAE_OK;
}

int sdae__mbs_jacobian(sdae_mbs_eval *e, double t, const double *q, double *G) {
  const sdae_pattern *p = e->sys.jacobian_pattern;
  int rc;
  if (!e->sys.jacobian) return jacobian_fd(e, t, q, G);
  rc = e->sys.jacobian(t, q, target(p, e->jacobian_values, G), e->sys.params);
  return matrix_checked(rc, p, e->jacobian_values, e->n_c, e->n_q, G);
}

/* A difference step in t relative to max(1, |t|): where t is so large that its doubles are too
 * sparse for the absolute step (t + h rounds to more than half the step away, beyond about
 * 1e12; h would vanish at 1e15, where the spacing is 0.125). */
static double t_step(double t) { return sdae__fd_step(t, SDAE_FD_STEP * fmax(1.0, fabs(t))); }

/* d/dh c(t + h, q): exactly 0 when c does not depend on t, the four values being equal. The step
 * is absolute while t can hold it: a driver's time scale (a road's period) does not grow with t,
 * so a step relative to t would lose its accuracy on the way (1 relative at t = 1e3 for a
 * period of 2). */
static int constraint_t_fd(sdae_mbs_eval *e, double t, const double *q, double *ct) {
  double h = sdae__fd_step(t, SDAE_FD_STEP), *c = e->ct_c;
  if (!(fabs(h - SDAE_FD_STEP) <= 0.5 * SDAE_FD_STEP)) h = t_step(t);
  memset(ct, 0, e->n_c * sizeof *ct);
  for (int k = 0; k < SDAE_FD_POINTS; k++) {
    int rc = sdae__mbs_constraint(e, t + sdae__fd_offset[k] * h, q, c);
    if (rc != SDAE_OK) return rc;
    sdae__fd_add(ct, 1, c, e->n_c, k);
  }
  sdae__fd_finish(ct, 1, e->n_c, h);
  return SDAE_OK;
}

int sdae__mbs_constraint_t(sdae_mbs_eval *e, double t, const double *q, double *ct) {
  if (!e->sys.constraint_t) return constraint_t_fd(e, t, q, ct);
  return sdae__callback_checked(e->sys.constraint_t(t, q, ct, e->sys.params), ct, e->n_c);
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
  if (s->constraint_t_dot)
    return sdae__callback_checked(s->constraint_t_dot(t, q, v, out, s->params), out, e->n_c);
  return differenced(e, t, q, v, &p);
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
  if (want_G && s->jacobian_dot) {
    const sdae_pattern *p = s->jacobian_pattern;
    rc = s->jacobian_dot(t, q, v, target(p, e->jacobian_values, Gd), s->params);
    if ((rc = matrix_checked(rc, p, e->jacobian_values, n_c, n_q, Gd)) != SDAE_OK) return rc;
  }
  if (Mdv && s->mass_dot_v &&
      (rc = sdae__callback_checked(s->mass_dot_v(t, q, v, Mdv, s->params), Mdv, n_q)) != SDAE_OK)
    return rc;
  if (!gdot) return SDAE_OK;
  if (s->constraint_t_dot &&
      (rc = sdae__callback_checked(s->constraint_t_dot(t, q, v, ctd, s->params), ctd, n_c)) !=
          SDAE_OK)
    return rc;
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
