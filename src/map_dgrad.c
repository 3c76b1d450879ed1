/* Gonzalez's midpoint discrete gradient (paper ref. 18) for q0 = S(mu) grad H(mu):
 *
 *   phi_T(mu, mu+) = S(m) gradbar H(mu, mu+),  m = (mu + mu+)/2,  v = mu+ - mu,
 *   gradbar H = grad H(m) + [(H(mu+) - H(mu) - grad H(m).v) / |v|^2] v,
 *
 * so that gradbar H . v = H(mu+) - H(mu) exactly: H(mu+) - H(mu) = T gradbar^T S gradbar,
 * zero when S is skew and <= 0 when S = J - R with R >= 0. */
#include <float.h>

#include "internal.h"

static int dgrad_check(const sdae_model *m, const sdae_options *o) {
  (void)m;
  return (o->H && o->grad_H && (o->S || o->S_apply)) ? SDAE_OK : SDAE_ERR_MAP;
}

/* the midpoint, grad H, the increment, and a dense S unless S_apply is given */
static size_t dgrad_scratch(const sdae_model *m, const sdae_options *o) {
  return 3 * m->n_mu + (o->S_apply ? 0 : m->n_mu * m->n_mu);
}

/* out = S(mid) g */
static int apply_S(sdae_stepper *s, double tm, const double *mid, const double *g, double *S,
                   double *out) {
  size_t n = s->model.n_mu;
  int rc;
  if (s->opt.S_apply) {
    rc = sdae__status_of_callback(s->opt.S_apply(tm, mid, g, out, s->model.params));
    if (rc != SDAE_OK) return rc;
    return sdae__all_finite(out, n) ? SDAE_OK : SDAE_ERR_NONFINITE;
  }
  if ((rc = sdae__call_checked(s->opt.S, s, tm, mid, S, n * n)) != SDAE_OK) return rc;
  for (size_t r = 0; r < n; r++) {
    double acc = 0.0;
    for (size_t j = 0; j < n; j++) acc += S[r * n + j] * g[j];
    out[r] = acc;
  }
  return SDAE_OK;
}

/* The correction along v; 0 when |v| is so small that the difference quotient is all rounding:
 * below |v|^2 = eps (1 + |m|^2) the dropped term is O(|v|^3) H''', far below rounding. */
static int correction(sdae_stepper *s, double tm, const double *mu, const double *mu_next,
                      const double *mid, const double *grad, const double *v, double *c) {
  size_t n = s->model.n_mu;
  double v2 = 0.0, m2 = 0.0, gv = 0.0, H0, H1;
  for (size_t i = 0; i < n; i++) {
    v2 += v[i] * v[i];
    m2 += mid[i] * mid[i];
    gv += grad[i] * v[i];
  }
  *c = 0.0;
  if (v2 <= DBL_EPSILON * (1.0 + m2)) return SDAE_OK;
  int rc = sdae__call_checked(s->opt.H, s, tm, mu, &H0, 1);
  if (rc == SDAE_OK) rc = sdae__call_checked(s->opt.H, s, tm, mu_next, &H1, 1);
  if (rc == SDAE_OK) *c = (H1 - H0 - gv) / v2;
  return rc;
}

static int dgrad_phi(sdae_stepper *s, double t, double T, const double *mu,
                     const double *mu_next, double *out) {
  size_t n = s->model.n_mu;
  double *mid = s->map_work, *grad = mid + n, *v = grad + n, *S = v + n, c;
  double tm = t + 0.5 * T;
  for (size_t i = 0; i < n; i++) {
    mid[i] = 0.5 * (mu[i] + mu_next[i]);
    v[i] = mu_next[i] - mu[i];
  }
  int rc = sdae__call_checked(s->opt.grad_H, s, tm, mid, grad, n);
  if (rc == SDAE_OK) rc = correction(s, tm, mu, mu_next, mid, grad, v, &c);
  if (rc != SDAE_OK) return rc;
  for (size_t i = 0; i < n; i++) grad[i] += c * v[i]; /* gradbar H */
  return apply_S(s, tm, mid, grad, S, out);
}

/* No closed form for d phi / d mu+ (it needs the Hessian of H): Newton uses finite
 * differences. */
static const sdae_map_type dgrad_type = {
    .name = "dgrad",
    .implicit = 1,
    .uses_newton = 1,
    .check = dgrad_check,
    .scratch = dgrad_scratch,
    .phi = dgrad_phi,
};

const sdae_map_type *const sdae_map_dgrad = &dgrad_type;
