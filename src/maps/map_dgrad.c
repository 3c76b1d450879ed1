/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Gonzalez's midpoint discrete gradient (paper ref. 18) for q0 = S(mu) grad H(mu) + B u(mu):
 *
 *   phi_T(mu, mu+) = S(m) gradbar H(mu, mu+) + B u(m),  m = (mu + mu+)/2,  v = mu+ - mu,
 *   gradbar H = grad H(m) + [(H(mu+) - H(mu) - grad H(m).v) / |v|^2] v,
 *
 * so that gradbar H . v = H(mu+) - H(mu) exactly: H(mu+) - H(mu) = T gradbar^T S gradbar
 * + T gradbar^T B u(m), the discrete power balance of a port-Hamiltonian system (the input B u
 * the model's optional port, taken at the midpoint); without input zero when S is skew and
 * <= 0 when S = J - R with R >= 0. */
#include <float.h>
#include <string.h>

#include "map.h"
#include "model/model.h"

static int dgrad_needs(const sdae_model *m) {
  return (m->H && m->grad_H && (m->S || m->S_apply)) ? SDAE_OK : SDAE_ERR_MAP;
}

/* hess_H gives the Jacobian */
static int dgrad_jac_given(const sdae_model *m) { return m->hess_H != NULL; }

/* The scratch: the midpoint, grad H there, the increment, the correction c and |v|^2 (0 in
 * the small-increment branch), H at the step's mu kept, a dense S unless S_apply is given, B u
 * at the midpoint with an input; with hess_H the Hessian (then d gradbar / d mu+ in its place)
 * and two vectors. phi leaves them all for the Jacobian at the same point. */
typedef struct parts {
  double *mid, *grad, *v, *inc, *S, *Bu, *D, *w, *col;
  double *kept; /* H(t_m, mu) kept within a step: 1 (0: none), t_m, H, then mu */
} parts;

/* a banded Newton uses finite differences whatever the model gives (and must not be charged n^2
 * doubles for a Jacobian) */
static size_t dgrad_scratch(const sdae_model *m, const sdae_options *o) {
  size_t n = m->n_mu;
  int jac = dgrad_jac_given(m) && !sdae__banded(m, o);
  return 3 * n + 2 + (3 + n) + (m->S_apply ? 0 : n * n) + (m->input ? n : 0) +
         (jac ? n * n + 2 * n : 0);
}

static parts layout(sdae_map_ctx *c) {
  size_t n = c->model->n_mu;
  parts P;
  P.mid = c->work;
  P.grad = P.mid + n;
  P.v = P.grad + n;
  P.inc = P.v + n;
  P.kept = P.inc + 2;
  P.S = P.kept + 3 + n;
  P.Bu = P.S + (c->model->S_apply ? 0 : n * n);
  P.D = P.Bu + (c->model->input ? n : 0);
  P.w = P.D + n * n;
  P.col = P.w + n;
  return P;
}

/* out = S(mid) g; a dense S is evaluated into P->S first when load */
static int apply_S(const sdae_model *m, double tm, const parts *P, int load, const double *g,
                   double *out) {
  size_t n = m->n_mu;
  int rc;
  if (m->S_apply) return sdae__callback_checked(m->S_apply(tm, P->mid, g, out, m->params), out, n);
  if (load && (rc = sdae__call_checked(m->S, m, tm, P->mid, P->S, n * n)) != SDAE_OK) return rc;
  for (size_t r = 0; r < n; r++) {
    double acc = 0.0;
    for (size_t j = 0; j < n; j++) acc += P->S[r * n + j] * g[j];
    out[r] = acc;
  }
  return SDAE_OK;
}

/* H(tm, mu) into *H, kept for the next call at the same tm and mu within the step: a step's
 * Newton evaluates phi at one mu and many mu+ (a front-end's H may cost a Phi^-1) */
static int H_start(const sdae_model *m, double tm, const double *mu, const parts *P, double *H) {
  size_t n = m->n_mu;
  double *kept = P->kept;
  int rc;
  if (kept[0] != 0.0 && kept[1] == tm && memcmp(kept + 3, mu, n * sizeof *mu) == 0) {
    *H = kept[2];
    return SDAE_OK;
  }
  kept[0] = 0.0;
  if ((rc = sdae__call_checked(m->H, m, tm, mu, H, 1)) != SDAE_OK) return rc;
  kept[0] = 1.0, kept[1] = tm, kept[2] = *H;
  memcpy(kept + 3, mu, n * sizeof *mu);
  return SDAE_OK;
}

/* a new step: nothing kept */
static void dgrad_begin(sdae_map_ctx *c) { layout(c).kept[0] = 0.0; }

/* The correction c along v into P->inc, with |v|^2. c = 0 (and |v|^2 is kept as 0) when |v| is
 * so small that the difference quotient is all rounding: below |v|^2 = eps (1 + |m|^2) the
 * dropped term is O(|v|^3) H''', far below rounding. */
static int correction(const sdae_model *m, double tm, const double *mu, const double *mu_next,
                      const parts *P) {
  size_t n = m->n_mu;
  double v2 = 0.0, m2 = 0.0, gv = 0.0, H0, H1;
  int rc;
  P->inc[0] = P->inc[1] = 0.0;
  for (size_t i = 0; i < n; i++) {
    v2 += P->v[i] * P->v[i];
    m2 += P->mid[i] * P->mid[i];
    gv += P->grad[i] * P->v[i];
  }
  if (v2 <= DBL_EPSILON * (1.0 + m2)) return SDAE_OK;
  rc = H_start(m, tm, mu, P, &H0);
  if (rc == SDAE_OK) rc = sdae__call_checked(m->H, m, tm, mu_next, &H1, 1);
  if (rc != SDAE_OK) return rc;
  P->inc[0] = (H1 - H0 - gv) / v2;
  P->inc[1] = v2;
  return SDAE_OK;
}

/* S(mid) gradbar H + B u(mid), gradbar H = grad H(mid) + c v: leaves mid, v, c and gradbar H
 * in the scratch */
static int dgrad_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                     double *out) {
  const sdae_model *m = c->model;
  size_t n = m->n_mu;
  parts P = layout(c);
  double tm = t + 0.5 * T;
  int rc;
  for (size_t i = 0; i < n; i++) {
    P.mid[i] = 0.5 * (mu[i] + mu_next[i]);
    P.v[i] = mu_next[i] - mu[i];
  }
  rc = sdae__call_checked(m->grad_H, m, tm, P.mid, P.grad, n);
  /* the input at the midpoint beside grad H, before the correction's H moves elsewhere (a
   * front-end may keep what the two share at one point) */
  if (rc == SDAE_OK && m->input) rc = sdae__call_checked(m->input, m, tm, P.mid, P.Bu, n);
  if (rc == SDAE_OK) rc = correction(m, tm, mu, mu_next, &P);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) P.grad[i] += P.inc[0] * P.v[i]; /* gradbar H */
  if ((rc = apply_S(m, tm, &P, 1, P.grad, out)) != SDAE_OK || !m->input) return rc;
  for (size_t i = 0; i < n; i++) out[i] += P.Bu[i];
  return SDAE_OK;
}

/* w = dc/dmu+ = (grad H(mu+) - g - Hm v/2 - 2 c v) / |v|^2 (0 in the small-increment
 * branch), with g = grad H(mid) = gradbar H - c v and the Hessian Hm = hess H(mid) in P->D */
static int correction_gradient(const sdae_model *m, double tm, const double *mu_next,
                               const parts *P) {
  size_t n = m->n_mu;
  double c = P->inc[0], v2 = P->inc[1];
  int rc = SDAE_OK;
  if (v2 == 0.0)
    for (size_t i = 0; i < n; i++) P->w[i] = 0.0;
  else
    rc = sdae__call_checked(m->grad_H, m, tm, mu_next, P->w, n);
  for (size_t i = 0; i < n && v2 != 0.0; i++) {
    double Hv = 0.0;
    for (size_t j = 0; j < n; j++) Hv += P->D[i * n + j] * P->v[j];
    P->w[i] = (P->w[i] - P->grad[i] - 0.5 * Hv - c * P->v[i]) / v2;
  }
  return rc;
}

/* d phi / d mu+ = S(mid) D, D = d gradbar / d mu+ = Hm/2 + c I + v w^T; the derivatives of S
 * and of an input are left out (zero for a constant S and input): Newton then converges
 * linearly. mid, v, c, gradbar H and S come from phi at this point. */
static int dgrad_jac(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                     double *out) {
  const sdae_model *m = c->model;
  size_t n = m->n_mu;
  parts P = layout(c);
  double tm = t + 0.5 * T;
  int rc = sdae__call_checked(m->hess_H, m, tm, P.mid, P.D, n * n);
  (void)mu;
  if (rc == SDAE_OK) rc = correction_gradient(m, tm, mu_next, &P);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++)
      P.D[i * n + j] = 0.5 * P.D[i * n + j] + (i == j ? P.inc[0] : 0.0) + P.v[i] * P.w[j];
  for (size_t j = 0; j < n && rc == SDAE_OK; j++) { /* column by column, as S_apply works */
    for (size_t i = 0; i < n; i++) P.col[i] = P.D[i * n + j];
    rc = apply_S(m, tm, &P, 0, P.col, P.w);
    for (size_t i = 0; i < n; i++) out[i * n + j] = P.w[i];
  }
  return rc;
}

/* Newton uses dgrad_jac when the model gives hess_H, finite differences otherwise. */
const sdae_map_type sdae__dgrad_type = {
    .name = "dgrad",
    .order = 2,
    .implicit = 1,
    .uses_H = 1,
    .needs = dgrad_needs,
    .scratch = dgrad_scratch,
    .begin = dgrad_begin,
    .phi = dgrad_phi,
    .jac = dgrad_jac,
    .jac_given = dgrad_jac_given,
    .slope = 0.5, /* q0's derivative at the midpoint, halved */
};

const sdae_map_type *const sdae_map_dgrad = &sdae__dgrad_type;
