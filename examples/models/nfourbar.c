/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The N-four-bar (nfourbar.h). A uniform rod of mass m between the points P and Q has the
 * kinetic energy m (|P'|^2 + P'.Q' + |Q'|^2) / 6: its mass matrix is m/3 on each end, m/6
 * between them; a rocker's P is its ground pivot, at rest. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_math.h>
#include <gsl/gsl_sf_ellint.h>
#include <gsl/gsl_sf_elljac.h>

#include "nfourbar.h"

mech_nfourbar mech_nfourbar_benchmark(void) {
  return (mech_nfourbar){.N = 40, .m = 1.0, .ga = 9.81};
}

static size_t n_q(const mech_nfourbar *p) { return 2 * (p->N + 1); }

static int nfb_mass(double t, const double *q, double *M, void *params) {
  const mech_nfourbar *p = params;
  size_t n = n_q(p);
  (void)t, (void)q;
  memset(M, 0, n * n * sizeof *M);
  for (size_t i = 0; i <= p->N; i++) {
    double ends = i == 0 || i == p->N ? 1.0 : 2.0; /* the couplers B_i ends */
    for (size_t k = 0; k < 2; k++) M[(2 * i + k) * n + 2 * i + k] = p->m * (1.0 + ends) / 3.0;
  }
  for (size_t i = 1; i <= p->N; i++)
    for (size_t k = 0; k < 2; k++)
      M[(2 * i + k) * n + 2 * (i - 1) + k] = M[(2 * (i - 1) + k) * n + 2 * i + k] = p->m / 6.0;
  return 0;
}

/* each rod's weight, half on each end (a rocker's other half on its pivot) */
static int nfb_force(double t, const double *q, const double *v, double *F, void *params) {
  const mech_nfourbar *p = params;
  (void)t, (void)q, (void)v;
  for (size_t i = 0; i <= p->N; i++) {
    double rods = i == 0 || i == p->N ? 2.0 : 3.0;
    F[2 * i] = 0.0, F[2 * i + 1] = -0.5 * rods * p->m * p->ga;
  }
  return 0;
}

static int nfb_potential(double t, const double *q, double *V, void *params) {
  const mech_nfourbar *p = params;
  double h = 0.0;
  (void)t;
  for (size_t i = 0; i <= p->N; i++) h += (i == 0 || i == p->N ? 2.0 : 3.0) * q[2 * i + 1];
  *V = 0.5 * p->m * p->ga * h;
  return 0;
}

static int nfb_constraint(double t, const double *q, double *c, void *params) {
  const mech_nfourbar *p = params;
  (void)t;
  for (size_t i = 0; i <= p->N; i++) {
    double dx = q[2 * i] - (double)i, dy = q[2 * i + 1];
    c[i] = 0.5 * (dx * dx + dy * dy - 1.0);
  }
  for (size_t i = 1; i <= p->N; i++) {
    double dx = q[2 * i] - q[2 * i - 2], dy = q[2 * i + 1] - q[2 * i - 1];
    c[p->N + i] = 0.5 * (dx * dx + dy * dy - 1.0);
  }
  return 0;
}

/* G's rows at positions x (velocity 0) or Gdot's at velocities x (velocity 1: the pivots at
 * rest) */
static void rows(const mech_nfourbar *p, const double *x, int velocity, double *G) {
  size_t n = n_q(p);
  memset(G, 0, (2 * p->N + 1) * n * sizeof *G);
  for (size_t i = 0; i <= p->N; i++) {
    G[i * n + 2 * i] = x[2 * i] - (velocity ? 0.0 : (double)i);
    G[i * n + 2 * i + 1] = x[2 * i + 1];
  }
  for (size_t i = 1; i <= p->N; i++)
    for (size_t k = 0; k < 2; k++) {
      double d = x[2 * i + k] - x[2 * i - 2 + k];
      G[(p->N + i) * n + 2 * i + k] = d;
      G[(p->N + i) * n + 2 * i - 2 + k] = -d;
    }
}

static int nfb_jacobian(double t, const double *q, double *G, void *params) {
  (void)t;
  rows(params, q, 0, G);
  return 0;
}

static int nfb_jacobian_dot(double t, const double *q, const double *v, double *Gdot,
                            void *params) {
  (void)t, (void)q;
  rows(params, v, 1, Gdot);
  return 0;
}

static int nfb_zero_q(double t, const double *q, double *out, void *params) {
  (void)t, (void)q;
  memset(out, 0, (2 * ((const mech_nfourbar *)params)->N + 1) * sizeof *out);
  return 0;
}

static int nfb_zero_qv(double t, const double *q, const double *v, double *out, void *params) {
  (void)v;
  return nfb_zero_q(t, q, out, params);
}

static int nfb_mass_dot_v(double t, const double *q, const double *v, double *out, void *params) {
  (void)t, (void)q, (void)v;
  memset(out, 0, n_q(params) * sizeof *out);
  return 0;
}

/* ---- the patterns: M's row of coordinate k of tip i holds k of tips i - 1, i, i + 1; a
 * rocker's row of G its tip's x and y, coupler i's tips i - 1's and i's ---- */

static int nfb_mass_sparse(double t, const double *q, double *M, void *params) {
  const mech_nfourbar *p = params;
  size_t e = 0;
  (void)t, (void)q;
  for (size_t i = 0; i <= p->N; i++)
    for (size_t k = 0; k < 2; k++) {
      double ends = i == 0 || i == p->N ? 1.0 : 2.0;
      if (i > 0) M[e++] = p->m / 6.0;
      M[e++] = p->m * (1.0 + ends) / 3.0;
      if (i < p->N) M[e++] = p->m / 6.0;
    }
  return 0;
}

static void rows_sparse(const mech_nfourbar *p, const double *x, int velocity, double *G) {
  size_t e = 0;
  for (size_t i = 0; i <= p->N; i++) {
    G[e++] = x[2 * i] - (velocity ? 0.0 : (double)i);
    G[e++] = x[2 * i + 1];
  }
  for (size_t i = 1; i <= p->N; i++) {
    double dx = x[2 * i] - x[2 * i - 2], dy = x[2 * i + 1] - x[2 * i - 1];
    G[e++] = -dx, G[e++] = -dy, G[e++] = dx, G[e++] = dy;
  }
}

static int nfb_jacobian_sparse(double t, const double *q, double *G, void *params) {
  (void)t;
  rows_sparse(params, q, 0, G);
  return 0;
}

static int nfb_jacobian_dot_sparse(double t, const double *q, const double *v, double *Gdot,
                                   void *params) {
  (void)t, (void)q;
  rows_sparse(params, v, 1, Gdot);
  return 0;
}

static int patterns(mech_nfourbar *p) {
  size_t N = p->N, n = n_q(p), n_c = 2 * N + 1, m_nz = 3 * n - 4, g_nz = 2 * (N + 1) + 4 * N;
  size_t *a = malloc((n + 1 + m_nz + n_c + 1 + g_nz) * sizeof *a), e = 0;
  size_t *m_start = a, *m_col = m_start + n + 1, *g_start = m_col + m_nz,
         *g_col = g_start + n_c + 1;
  if (!a) return -1;
  for (size_t i = 0; i <= N; i++)
    for (size_t k = 0; k < 2; k++) {
      m_start[2 * i + k] = e;
      if (i > 0) m_col[e++] = 2 * (i - 1) + k;
      m_col[e++] = 2 * i + k;
      if (i < N) m_col[e++] = 2 * (i + 1) + k;
    }
  m_start[n] = e, e = 0;
  for (size_t i = 0; i <= N; i++) g_start[i] = e, g_col[e++] = 2 * i, g_col[e++] = 2 * i + 1;
  for (size_t i = 1; i <= N; i++) {
    g_start[N + i] = e;
    for (size_t c = 2 * i - 2; c < 2 * i + 2; c++) g_col[e++] = c;
  }
  g_start[n_c] = e;
  p->arrays = a;
  p->mass_pattern = (sdae_pattern){m_nz, m_start, m_col};
  p->jacobian_pattern = (sdae_pattern){g_nz, g_start, g_col};
  return 0;
}

void mech_nfourbar_free(mech_nfourbar *p) {
  free(p->arrays);
  p->arrays = NULL;
}

int mech_nfourbar_system(sdae_mbs *sys, mech_nfourbar *p) {
  p->arrays = NULL;
  if (p->sparse && patterns(p) != 0) return -1;
  *sys = (sdae_mbs){.n_q = n_q(p),
                    .n_c = 2 * p->N + 1,
                    .mass = nfb_mass,
                    .force = nfb_force,
                    .constraint = nfb_constraint,
                    .jacobian = nfb_jacobian,
                    .constraint_t = nfb_zero_q,
                    .potential = nfb_potential,
                    .params = p,
                    .mass_dot_v = nfb_mass_dot_v,
                    .jacobian_dot = nfb_jacobian_dot,
                    .constraint_t_dot = nfb_zero_qv};
  if (p->sparse) {
    sys->mass = nfb_mass_sparse, sys->jacobian = nfb_jacobian_sparse;
    sys->jacobian_dot = nfb_jacobian_dot_sparse;
    sys->mass_pattern = &p->mass_pattern, sys->jacobian_pattern = &p->jacobian_pattern;
  }
  return 0;
}

void mech_nfourbar_start(const mech_nfourbar *p, double *q, double *v) {
  for (size_t i = 0; i <= p->N; i++) {
    q[2 * i] = (double)i, q[2 * i + 1] = 1.0;
    v[2 * i] = 1.0, v[2 * i + 1] = 0.0;
  }
}

/* psi = theta + pi turns over as a pendulum psi'' = -w^2 sin psi, w^2 = K ga / J, with the
 * speed s at the bottom, s^2 = 1 + 4 w^2 (the energy of theta'(0) = 1 at the top): psi(t) =
 * 2 am(s t / 2 + K(k), k), k = 2 w / s, am(u) = atan2(sn u, cn u) + n pi on u = 2 n K + r. */
void mech_nfourbar_reference(const mech_nfourbar *p, double t, double *b0) {
  double N = (double)p->N, J = (N + 1.0) * p->m / 3.0 + N * p->m;
  double w = sqrt(((N + 1.0) * p->m / 2.0 + N * p->m) * p->ga / J), s = sqrt(1.0 + 4.0 * w * w);
  double k = 2.0 * w / s, K = gsl_sf_ellint_Kcomp(k, GSL_PREC_DOUBLE), u = 0.5 * s * t + K;
  double turns = floor((u + K) / (2.0 * K)), sn, cn, dn, theta;
  gsl_sf_elljac_e(u - 2.0 * K * turns, k * k, &sn, &cn, &dn);
  theta = 2.0 * (turns * M_PI + atan2(sn, cn)) - M_PI;
  b0[0] = sin(theta), b0[1] = cos(theta);
}
