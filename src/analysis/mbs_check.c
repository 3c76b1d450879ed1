/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanism check (<stabdae/mbs.h>): every derivative a mechanism gives against
 * fourth-order central differences of the callback it derives from,
 *
 *   f'(0) ~ [8 (f(h) - f(-h)) - (f(2h) - f(-2h))] / (12 h),   error ~ h^4 f^(5) / 30 + eps f / h,
 *
 * along a line (t + s dt, q + s dq) through the state: e_j for a column of G or a gradient, (1, 0)
 * for dc/dt, (1, v) for the derivatives along the motion. With a potential, the force is checked
 * against Lagrange's equations d/dt (M v) - dT/dq + dV/dq = -D v for T = v^T M v / 2:
 *
 *   F = -dV/dq + (1/2) (v^T (dM/dq_k) v)_k - (d/ds M(q + s v)) v - D v. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <stabdae/check.h>

#include "core/alloc.h"
#include "core/arena.h"
#include "core/callback.h"
#include "core/difference.h"
#include "core/pattern.h"
#include "mbs/mbs_eval.h"

/* what is evaluated along a line */
typedef enum quantity { C, CT, G, MV, V, KINETIC } quantity;

/* A difference carries the rounding of the values it combines, about eps max|value| / h times
 * the stencil's weights and the callbacks' own few ulps; NOISE bounds that factor, so that a
 * derivative that vanishes at the state (a force at equilibrium) is not judged by rounding. */
#define NOISE 1e3

typedef struct checker {
  const sdae_mbs *sys;
  size_t n_q, n_c;
  const double *v;         /* the state's velocity: M v, v^T M v / 2 */
  double *qs, *Mq;         /* n_q, n_q x n_q: the point on the line, M there */
  double *at;              /* width: a value on the line */
  double *fd, *nz, *given; /* width each: the difference, its noise, the derivative given */
  double *col, *col_nz;    /* max(n_q, n_c) each: one column (or gradient) and its noise */
  double *e;               /* n_q: a direction */
  double *values;          /* a matrix's nonzeros, written by a callback with a pattern */
  double *q_m, *v_m;       /* n_q each: a state moved around the one given */
  /* the rank: G^T's rows scaled (n_q x n_c), QR's tau and norms (n_c each), its pivoting */
  double *gt, *tau, *norm;
  size_t *perm;
} checker;

/* a matrix callback's status, its values put in place (rows x n_q) when it has a pattern:
 * where it writes is matrix_out's */
static double *matrix_out(checker *k, const sdae_pattern *p, double *out) {
  return p ? k->values : out;
}
static int matrix_checked(checker *k, int rc, const sdae_pattern *p, size_t rows, double *out) {
  if (!p) return sdae__callback_checked(rc, out, rows * k->n_q);
  if ((rc = sdae__callback_checked(rc, k->values, p->nnz)) == SDAE_OK)
    sdae__pattern_scatter(p, rows, k->n_q, k->values, out);
  return rc;
}

static size_t width(const checker *k) {
  return k->n_c * k->n_q > k->n_q ? k->n_c * k->n_q : k->n_q;
}

static size_t size_of(const checker *k, quantity what) {
  switch (what) {
  case C:
  case CT: return k->n_c;
  case G: return k->n_c * k->n_q;
  case MV: return k->n_q;
  default: return 1;
  }
}

/* M v (or v^T M v / 2) at (t, q) into out */
static int mass_times_v(checker *k, double t, const double *q, int kinetic, double *out) {
  const sdae_mbs *s = k->sys;
  size_t n = k->n_q;
  double e = 0.0;
  const sdae_pattern *p = s->mass_pattern;
  int rc = matrix_checked(k, s->mass(t, q, matrix_out(k, p, k->Mq), s->params), p, n, k->Mq);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) {
    double acc = 0.0;
    for (size_t j = 0; j < n; j++) acc += k->Mq[i * n + j] * k->v[j];
    if (kinetic)
      e += 0.5 * k->v[i] * acc;
    else
      out[i] = acc;
  }
  if (kinetic) *out = e;
  return SDAE_OK;
}

/* a quantity evaluated only where the mechanism gives its callback (run's tests); a missing one
 * is SDAE_ERR_NULL, never called */
static int evaluate(checker *k, quantity what, double t, const double *q, double *out) {
  const sdae_mbs *s = k->sys;
  if ((what == CT && !s->constraint_t) || (what == G && !s->jacobian) ||
      (what == V && !s->potential))
    return SDAE_ERR_NULL;
  switch (what) {
  case C: return sdae__callback_checked(s->constraint(t, q, out, s->params), out, k->n_c);
  case CT: return sdae__callback_checked(s->constraint_t(t, q, out, s->params), out, k->n_c);
  case G: {
    const sdae_pattern *p = s->jacobian_pattern;
    return matrix_checked(k, s->jacobian(t, q, matrix_out(k, p, out), s->params), p, k->n_c, out);
  }
  case MV: return mass_times_v(k, t, q, 0, out);
  case V: return sdae__callback_checked(s->potential(t, q, out, s->params), out, 1);
  default: return mass_times_v(k, t, q, 1, out);
  }
}

/* The step along (dt, dq): SDAE_FD_STEP over the speed of what moves, absolute (an angle wound up
 * to 16 rad or a time of 1e3 changes no faster than at 0), but never below 2^20 ulps of the
 * largest moving variable, which beyond about 4e9 makes it relative; then exact in t, or in
 * the one coordinate that moves. */
static double line_step(const checker *k, double t, const double *q, double dt, const double *dq) {
  double big = dt != 0.0 ? fabs(t) : 0.0, speed = fabs(dt), h;
  size_t moving = 0, count = 0;
  for (size_t j = 0; j < k->n_q; j++)
    if (dq[j] != 0.0) {
      big = fmax(big, fabs(q[j])), speed = fmax(speed, fabs(dq[j]));
      moving = j, count++;
    }
  h = SDAE_FD_STEP * fmax(1.0, 0x1p20 * DBL_EPSILON * big / SDAE_FD_STEP) / speed;
  if (dt != 0.0) return (t + h) - t;
  return count == 1 && dq[moving] == 1.0 ? (q[moving] + h) - q[moving] : h;
}

/* d/ds of the quantity at (t + s dt, q + s dq), s = 0, into out, and the rounding it carries
 * into noise */
static int derivative(checker *k, quantity what, double t, const double *q, double dt,
                      const double *dq, double *out, double *noise) {
  size_t n = size_of(k, what);
  double h = line_step(k, t, q, dt, dq);
  memset(out, 0, n * sizeof *out);
  memset(noise, 0, n * sizeof *noise);
  for (int o = 0; o < SDAE_FD_POINTS; o++) {
    int rc;
    double s = sdae__fd_offset[o] * h;
    for (size_t j = 0; j < k->n_q; j++) k->qs[j] = q[j] + s * dq[j];
    if ((rc = evaluate(k, what, t + s * dt, k->qs, k->at)) != SDAE_OK) return rc;
    sdae__fd_add(out, 1, k->at, n, o);
    for (size_t i = 0; i < n; i++) noise[i] = fmax(noise[i], fabs(k->at[i]));
  }
  sdae__fd_finish(out, 1, n, h);
  for (size_t i = 0; i < n; i++) noise[i] *= NOISE * DBL_EPSILON / h;
  return SDAE_OK;
}

/* The worst mismatch of a (given) and b (differences), entry by entry: what |a - b| exceeds the
 * noise by, relative to the entry's size. Besides the differences' noise, each entry allows the
 * rounding of a closed form of its row's size (rows of `cols` entries: a matrix's rows, or one
 * row for a vector), so that a row of large entries hides no wrong small row. NaN is
 * INFINITY. */
static double mismatch(const double *a, const double *b, const double *noise, size_t n, size_t cols,
                       size_t *where) {
  double worst = 0.0;
  *where = 0;
  for (size_t r = 0; r < n; r += cols) {
    double row = 0.0;
    for (size_t i = r; i < r + cols; i++) row = fmax(row, fmax(fabs(a[i]), fabs(b[i])));
    for (size_t i = r; i < r + cols; i++) {
      double floor = noise[i] + 64.0 * DBL_EPSILON * row, d = fabs(a[i] - b[i]) - floor, m;
      m = d > 0.0 ? d / fmax(fmax(fabs(a[i]), fabs(b[i])), floor) : 0.0;
      if (!(m <= DBL_MAX)) m = INFINITY; /* a NaN or Inf anywhere */
      if (m > worst || (m == INFINITY && worst < INFINITY)) worst = m, *where = i;
    }
  }
  return worst;
}

static void record(sdae_mbs_check_report *r, sdae_mbs_derivative d, double m, size_t where) {
  r->checked |= 1U << d;
  r->mismatch[d] = m;
  if (r->worst < 0 || m > r->mismatch[r->worst]) r->worst = (int)d, r->worst_index = where;
}

/* G by differences of c, column by column, into k->fd (its noise in k->nz) */
static int differenced_jacobian(checker *k, double t, const double *q) {
  size_t n_q = k->n_q, n_c = k->n_c;
  memset(k->e, 0, n_q * sizeof *k->e);
  for (size_t j = 0; j < n_q; j++) {
    int rc;
    k->e[j] = 1.0;
    rc = derivative(k, C, t, q, 0.0, k->e, k->col, k->col_nz);
    k->e[j] = 0.0;
    if (rc != SDAE_OK) return rc;
    for (size_t i = 0; i < n_c; i++)
      k->fd[i * n_q + j] = k->col[i], k->nz[i * n_q + j] = k->col_nz[i];
  }
  return SDAE_OK;
}

/* G column by column, against c */
static int check_jacobian(checker *k, double t, const double *q, sdae_mbs_check_report *r) {
  size_t where;
  double m;
  int rc = evaluate(k, G, t, q, k->given);
  if (rc != SDAE_OK || (rc = differenced_jacobian(k, t, q)) != SDAE_OK) return rc;
  m = mismatch(k->given, k->fd, k->nz, k->n_c * k->n_q, k->n_q, &where);
  record(r, SDAE_MBS_JACOBIAN, m, where);
  return SDAE_OK;
}

/* ---- the constraints' rank ---- */

/* G (n_c x n_q, row-major) ranked into k->perm (sdae__mbs_rows_qr); *rank down to the first
 * sine below SDAE_MBS_CHART_MIN (a zero row is dependent on any), *independence the least sine
 * above it */
static void rank_of(checker *k, const double *Gm, size_t *rank, double *independence) {
  size_t n_q = k->n_q, n_c = k->n_c, r = 0;
  double least = 1.0, sine;
  sdae__mbs_rows_qr(Gm, n_q, NULL, n_c, k->gt, k->tau, k->norm, k->perm);
  while ((sine = sdae__mbs_rows_sine(k->gt, n_q, n_c, r)) >= SDAE_MBS_CHART_MIN) {
    least = sine < least ? sine : least;
    r++;
  }
  *rank = r;
  *independence = r > 0 ? least : 0.0;
}

/* G at (t, q), given or differenced, ranked */
static int rank_at(checker *k, double t, const double *q, size_t *rank, double *independence) {
  int rc = k->sys->jacobian ? evaluate(k, G, t, q, k->given) : differenced_jacobian(k, t, q);
  if (rc == SDAE_OK) rank_of(k, k->sys->jacobian ? k->given : k->fd, rank, independence);
  return rc;
}

/* a derivative given (its values already in k->given) against the difference of a quantity
 * along (dt, dq) */
static int compare(checker *k, sdae_mbs_derivative d, quantity what, double t, const double *q,
                   double dt, const double *dq, sdae_mbs_check_report *r) {
  size_t where, n = size_of(k, what);
  int rc = derivative(k, what, t, q, dt, dq, k->fd, k->nz);
  if (rc == SDAE_OK) {
    double m = mismatch(k->given, k->fd, k->nz, n, what == G ? k->n_q : n, &where);
    record(r, d, m, where);
  }
  return rc;
}

/* the force (into k->given) against Lagrange's equations, every term by differences (into
 * k->fd, their noises added in k->nz) */
static int check_force(checker *k, double t, const double *q, sdae_mbs_check_report *r) {
  const sdae_mbs *s = k->sys;
  size_t n = k->n_q, where;
  double dV, dT, nV, nT, m;
  int rc = sdae__callback_checked(s->force(t, q, k->v, k->given, s->params), k->given, n);
  if (rc != SDAE_OK || (rc = derivative(k, MV, t, q, 1.0, k->v, k->col, k->col_nz)) != SDAE_OK)
    return rc;
  memset(k->e, 0, n * sizeof *k->e);
  for (size_t j = 0; j < n; j++) { /* k->col holds Mdot v */
    k->e[j] = 1.0;
    if ((rc = derivative(k, V, t, q, 0.0, k->e, &dV, &nV)) == SDAE_OK)
      rc = derivative(k, KINETIC, t, q, 0.0, k->e, &dT, &nT);
    k->e[j] = 0.0;
    if (rc != SDAE_OK) return rc;
    k->fd[j] = -dV + dT - k->col[j];
    k->nz[j] = nV + nT + k->col_nz[j];
  }
  if (s->damping) {
    const sdae_pattern *p = s->mass_pattern;
    rc = s->damping(t, q, matrix_out(k, p, k->Mq), s->params);
    if ((rc = matrix_checked(k, rc, p, n, k->Mq)) != SDAE_OK) return rc;
    for (size_t i = 0; i < n; i++)
      for (size_t j = 0; j < n; j++) k->fd[i] -= k->Mq[i * n + j] * k->v[j];
  }
  m = mismatch(k->given, k->fd, k->nz, n, n, &where);
  record(r, SDAE_MBS_FORCE, m, where);
  return SDAE_OK;
}

/* the derivative a callback gives along (1, v), into k->given, checked finite */
static int along(checker *k, int (*cb)(double, const double *, const double *, double *, void *),
                 double t, const double *q, size_t n) {
  return sdae__callback_checked(cb(t, q, k->v, k->given, k->sys->params), k->given, n);
}

/* every derivative given at (t, q, k->v); with patterns only, those a pattern's entries shape:
 * G and Gdot by jacobian_pattern, Mdot v and the force by mass_pattern */
static int run(checker *k, double t, const double *q, int patterns_only, sdae_mbs_check_report *r) {
  const sdae_mbs *s = k->sys;
  size_t n_q = k->n_q, n_c = k->n_c;
  int rc = SDAE_OK, all = !patterns_only, g = all || s->jacobian_pattern,
      m = all || s->mass_pattern;
  double *zero = k->e; /* the direction (1, 0) of dc/dt */
  if (s->jacobian && g) rc = check_jacobian(k, t, q, r);
  memset(zero, 0, n_q * sizeof *zero);
  if (rc == SDAE_OK && all && s->constraint_t && (rc = evaluate(k, CT, t, q, k->given)) == SDAE_OK)
    rc = compare(k, SDAE_MBS_CONSTRAINT_T, C, t, q, 1.0, zero, r);
  if (rc == SDAE_OK && m && s->mass_dot_v && (rc = along(k, s->mass_dot_v, t, q, n_q)) == SDAE_OK)
    rc = compare(k, SDAE_MBS_MASS_DOT_V, MV, t, q, 1.0, k->v, r);
  if (rc == SDAE_OK && g && s->jacobian_dot) {
    const sdae_pattern *p = s->jacobian_pattern;
    rc = s->jacobian_dot(t, q, k->v, matrix_out(k, p, k->given), s->params);
    if ((rc = matrix_checked(k, rc, p, n_c, k->given)) == SDAE_OK)
      rc = compare(k, SDAE_MBS_JACOBIAN_DOT, G, t, q, 1.0, k->v, r);
  }
  if (rc == SDAE_OK && all && s->constraint_t_dot &&
      (rc = along(k, s->constraint_t_dot, t, q, n_c)) == SDAE_OK)
    rc = compare(k, SDAE_MBS_CONSTRAINT_T_DOT, CT, t, q, 1.0, k->v, r);
  if (rc == SDAE_OK && m && s->potential) rc = check_force(k, t, q, r);
  return rc;
}

static void carve(checker *k, sdae_arena *a) {
  size_t n_q = k->n_q, n_rows = k->n_c > n_q ? k->n_c : n_q; /* a column of G, or a vector */
  k->qs = sdae__take(a, n_q, 1);
  k->Mq = sdae__take(a, n_q, n_q);
  k->at = sdae__take(a, width(k), 1);
  k->fd = sdae__take(a, width(k), 1);
  k->nz = sdae__take(a, width(k), 1);
  k->given = sdae__take(a, width(k), 1);
  k->col = sdae__take(a, n_rows, 1);
  k->col_nz = sdae__take(a, n_rows, 1);
  k->e = sdae__take(a, n_q, 1);
  k->values = sdae__take(a, n_q, n_rows); /* no pattern has more entries than its matrix */
  k->q_m = sdae__take(a, n_q, 1);
  k->v_m = sdae__take(a, n_q, 1);
  k->gt = sdae__take(a, n_q, k->n_c);
  k->tau = sdae__take(a, k->n_c, 1);
  k->norm = sdae__take(a, k->n_c, 1);
  k->perm = sdae__take_indices(a, k->n_c);
}

/* The states checked: the one given, every derivative; then, for a mechanism with patterns,
 * SDAE_MBS_CHECK_STATES - 1 around it, q and v moved by MOVE (1 + |x_i|) in directions of
 * Weyl's sequence (frac(i phi_s), deterministic and far from the symmetries a state is chosen
 * on), the derivatives a pattern shapes alone, so that an entry a pattern leaves out, zero at
 * the given state alone (a rod upright, its x entries), shows as a mismatch; a mechanism without
 * patterns is checked at the state given alone, as sharply as before (the rounding drawn at
 * other states, at late times, would add to its noise) */
#define MOVE 1e-3
static void moved(const double *x, size_t n, int state, double *out) {
  const double phi = state == 1 ? 0.6180339887498949 : 0.4142135623730951; /* golden, silver */
  for (size_t i = 0; i < n; i++) {
    double u = (double)(i + 1) * phi;
    out[i] = x[i] + MOVE * (1.0 + fabs(x[i])) * (2.0 * (u - floor(u)) - 1.0);
  }
}

/* the worst of each derivative over the states, and the worst of all where it is first: into
 * total */
static void merge(sdae_mbs_check_report *total, const sdae_mbs_check_report *r, int state) {
  double worst = total->worst < 0 ? 0.0 : total->mismatch[total->worst];
  if (r->worst >= 0 && (total->worst < 0 || !(r->mismatch[r->worst] <= worst)))
    total->worst = r->worst, total->worst_index = r->worst_index, total->state = state;
  total->checked |= r->checked;
  for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++)
    if (!(r->mismatch[d] <= total->mismatch[d])) total->mismatch[d] = r->mismatch[d];
}

/* run at every state, the worst kept */
static int run_states(checker *k, double t, const double *q, const double *v,
                      sdae_mbs_check_report *total) {
  int states = k->sys->mass_pattern || k->sys->jacobian_pattern ? SDAE_MBS_CHECK_STATES : 1;
  for (int state = 0; state < states; state++) {
    sdae_mbs_check_report r = {.worst = -1};
    int rc;
    if (state > 0) moved(q, k->n_q, state, k->q_m), moved(v, k->n_q, state, k->v_m);
    k->v = state > 0 ? k->v_m : v;
    const double *at = state > 0 ? k->q_m : q;
    double independence;
    if ((rc = run(k, t, at, state > 0, &r)) != SDAE_OK ||
        (rc = rank_at(k, t, at, &total->rank[state], &independence)) != SDAE_OK)
      return rc;
    if (state == 0 || independence < total->independence) total->independence = independence;
    merge(total, &r, state);
  }
  return SDAE_OK;
}

static int valid(const sdae_mbs *sys, double t, const double *q, const double *v, double tol) {
  int rc;
  if (!sys || !q || !v || !sys->mass || !sys->force || !sys->constraint) return SDAE_ERR_NULL;
  if (sys->n_c == 0 || sys->n_q == 0) return SDAE_ERR_DIM;
  /* the derivatives of G and dc/dt are checked against the callbacks themselves */
  if ((sys->jacobian_dot && !sys->jacobian) || (sys->constraint_t_dot && !sys->constraint_t))
    return SDAE_ERR_NULL;
  if ((rc = sdae__mbs_patterns_check(sys)) != SDAE_OK) return rc;
  if (!(tol > 0.0) || !isfinite(t) || !sdae__all_finite(q, sys->n_q) ||
      !sdae__all_finite(v, sys->n_q))
    return SDAE_ERR_PARAM;
  return SDAE_OK;
}

int sdae_mbs_check_with(const sdae_mbs *sys, double t, const double *q, const double *v, double tol,
                        const sdae_allocator *a, sdae_mbs_check_report *r) {
  checker k = {0};
  sdae_arena count = {0}, take = {0};
  sdae_mbs_check_report rep = {.worst = -1, .state = -1};
  size_t bytes;
  int rc;
  if (!r) return SDAE_ERR_NULL;
  if ((rc = valid(sys, t, q, v, tol)) != SDAE_OK) return rc;
  k.sys = sys, k.n_q = sys->n_q, k.n_c = sys->n_c;
  carve(&k, &count);
  if (sdae__arena_bytes(&count, 0, &bytes) != SDAE_OK) return SDAE_ERR_OVERFLOW;
  if (!(take.base = sdae__alloc(a, bytes))) return SDAE_ERR_NOMEM;
  carve(&k, &take);
  rc = run_states(&k, t, q, v, &rep);
  sdae__free(a, take.base, bytes);
  if (rc != SDAE_OK) return rc;
  rep.consistent = 1;
  for (int d = 0; d < SDAE_MBS_DERIVATIVES; d++)
    if (!(rep.mismatch[d] <= tol)) rep.consistent = 0;
  *r = rep;
  return SDAE_OK;
}

int sdae_mbs_check(const sdae_mbs *sys, double t, const double *q, const double *v, double tol,
                   sdae_mbs_check_report *r) {
  return sdae_mbs_check_with(sys, t, q, v, tol, NULL, r);
}

int sdae_mbs_redundant_with(const sdae_mbs *sys, double t, const double *q, const sdae_allocator *a,
                            size_t *rank, size_t *rows, double *independence) {
  checker k = {0};
  sdae_arena count = {0}, take = {0};
  size_t bytes, r;
  double least;
  int rc;
  if (!sys || !q || !rank || !sys->constraint) return SDAE_ERR_NULL;
  if (sys->n_c == 0 || sys->n_q == 0) return SDAE_ERR_DIM;
  if ((rc = sdae__mbs_patterns_check(sys)) != SDAE_OK) return rc;
  if (!isfinite(t) || !sdae__all_finite(q, sys->n_q)) return SDAE_ERR_PARAM;
  k.sys = sys, k.n_q = sys->n_q, k.n_c = sys->n_c;
  carve(&k, &count);
  if (sdae__arena_bytes(&count, 0, &bytes) != SDAE_OK) return SDAE_ERR_OVERFLOW;
  if (!(take.base = sdae__alloc(a, bytes))) return SDAE_ERR_NOMEM;
  carve(&k, &take);
  if ((rc = rank_at(&k, t, q, &r, &least)) == SDAE_OK) {
    *rank = r;
    if (rows) memcpy(rows, k.perm, k.n_c * sizeof *rows);
    if (independence) *independence = least;
  }
  sdae__free(a, take.base, bytes);
  return rc;
}

int sdae_mbs_redundant(const sdae_mbs *sys, double t, const double *q, size_t *rank, size_t *rows,
                       double *independence) {
  return sdae_mbs_redundant_with(sys, t, q, NULL, rank, rows, independence);
}
