/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The saddle-point system's factorization by SuiteSparse's AMD and LDL (core/sparse_ldl.h).
 * amd_2 rather than amd_order: amd_order allocates its workspace (SuiteSparse_malloc), amd_2
 * takes it from the caller, as LDL does every array. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

#include <amd.h>
#include <ldl.h>
#include <stabdae/stabdae.h>

#include "sparse_ldl.h"

static int *take_ints(sdae_arena *a, size_t n) {
  return sdae__take_array(a, n, sizeof(int), _Alignof(int));
}

/* AMD's ints beyond the pattern it consumes: Pe, Nv, Elen, Degree, Len, Head, W and the order
 * found (n each); the pattern (its off-diagonal entries) with a fifth more and n of room to
 * work in, as amd_order gives it */
static size_t amd_ints(size_t n, size_t nnz) { return 8 * n + nnz + nnz / 5 + n; }

int sdae__sparse_ldl_fits(size_t n, size_t nnz) {
  return n < (size_t)INT_MAX / 16 && nnz < (size_t)INT_MAX / 16;
}

void sdae__sparse_ldl_symbolic_carve(sdae_sparse_ldl_symbolic *s, size_t n, size_t n_pos,
                                     size_t nnz, sdae_arena *a) {
  s->n = n, s->n_pos = n_pos;
  s->cap = SDAE_SPARSE_LDL_FILL * nnz + n; /* nnz, n < INT_MAX / 16: no overflow */
  s->Ap = take_ints(a, n + 1);
  s->Ai = take_ints(a, nnz);
  s->P = take_ints(a, n), s->Pinv = take_ints(a, n);
  s->Lp = take_ints(a, n + 1), s->Parent = take_ints(a, n);
  s->amd_len = amd_ints(n, nnz);
  s->amd_work = take_ints(a, s->amd_len);
}

/* AMD's minimum-degree order of K's graph into found (n) */
static void minimum_degree(sdae_sparse_ldl_symbolic *s, int *found) {
  int n = (int)s->n, *w = s->amd_work, pfree = 0;
  int *Pe = w, *Nv = Pe + n, *Elen = Nv + n, *Degree = Elen + n, *Len = Degree + n;
  int *Head = Len + n, *W = Head + n, *Iw = W + n, iwlen = (int)(s->amd_len - (size_t)(Iw - w));
  double control[AMD_CONTROL], info[AMD_INFO];
  for (int i = 0; i < n; i++) {
    Pe[i] = pfree;
    for (int e = s->Ap[i]; e < s->Ap[i + 1]; e++)
      if (s->Ai[e] != i) Iw[pfree++] = s->Ai[e];
    Len[i] = pfree - Pe[i];
  }
  amd_defaults(control);
  amd_2(n, Pe, Iw, Len, iwlen, pfree, Nv, s->Pinv, found, Head, Elen, Degree, W, control, info);
}

/* the order: AMD's, its coordinates taken first (in AMD's order among them), then its
 * multipliers. The constrained minimum degree (CAMD's) would choose the two together, but
 * Debian's libcamd.a is not position-independent and so cannot be linked into an FMU. */
static void order(sdae_sparse_ldl_symbolic *s) {
  int *found = s->amd_work + s->amd_len - s->n, k = 0; /* AMD's last n ints: the room left */
  minimum_degree(s, found);
  for (int pass = 0; pass < 2; pass++)
    for (size_t r = 0; r < s->n; r++)
      if (((size_t)found[r] < s->n_pos) == (pass == 0)) s->P[k++] = found[r];
  for (k = 0; k < (int)s->n; k++) s->Pinv[s->P[k]] = k;
}

int sdae__sparse_ldl_analyse(sdae_sparse_ldl_symbolic *s, const sdae_pattern *K) {
  int *Lnz = s->amd_work, *Flag = Lnz + s->n; /* AMD's workspace, done with */
  for (size_t i = 0; i <= s->n; i++) s->Ap[i] = (int)K->row_start[i];
  for (size_t e = 0; e < K->nnz; e++) s->Ai[e] = (int)K->col[e];
  order(s);
  ldl_symbolic((int)s->n, s->Ap, s->Ai, s->Lp, s->Parent, Lnz, Flag, s->P, s->Pinv);
  return (size_t)s->Lp[s->n] <= s->cap ? SDAE_OK : SDAE_ERR_PATTERN;
}

void sdae__sparse_ldl_carve(sdae_sparse_ldl *f, const sdae_sparse_ldl_symbolic *sym,
                            sdae_arena *a) {
  size_t n = sym->n;
  f->sym = sym;
  f->Lnz = take_ints(a, n), f->Flag = take_ints(a, n), f->Pattern = take_ints(a, n);
  f->Li = take_ints(a, sym->cap);
  f->Lx = sdae__take(a, sym->cap, 1);
  f->D = sdae__take(a, n, 1), f->Y = sdae__take(a, n, 1), f->x = sdae__take(a, n, 1);
}

/* ||M||_inf, M the coordinates' block of K */
static double mass_norm(const sdae_sparse_ldl_symbolic *s, const double *values) {
  double big = 0.0;
  for (size_t i = 0; i < s->n_pos; i++) {
    double row = 0.0;
    for (int e = s->Ap[i]; e < s->Ap[i + 1]; e++)
      if ((size_t)s->Ai[e] < s->n_pos) row += fabs(values[e]);
    big = fmax(big, row);
  }
  return big;
}

/* the least size of row i's pivot were it not at rounding: a coordinate's, ||M||; a
 * multiplier's, the diagonal of G M^-1 G^T, at least ||G_i||^2 / ||M|| (M's largest eigenvalue
 * at most ||M||_inf) */
static double pivot_scale(const sdae_sparse_ldl_symbolic *s, const double *values, int i,
                          double m_norm) {
  double g = 0.0;
  if ((size_t)i < s->n_pos) return m_norm;
  for (int e = s->Ap[i]; e < s->Ap[i + 1]; e++) g += values[e] * values[e];
  return m_norm > 0.0 ? g / m_norm : 0.0;
}

int sdae__sparse_ldl_factor(sdae_sparse_ldl *f, const double *values) {
  const sdae_sparse_ldl_symbolic *s = f->sym;
  int n = (int)s->n;
  double tol = (double)s->n * DBL_EPSILON, m_norm = mass_norm(s, values);
  /* a zero pivot stops LDL at its step; the steps before it are checked the same way */
  int done = ldl_numeric(n, s->Ap, s->Ai, (double *)values, s->Lp, s->Parent, f->Lnz, f->Li, f->Lx,
                         f->D, f->Y, f->Pattern, f->Flag, s->P, s->Pinv);
  for (int k = 0; k < n; k++) {
    int i = s->P[k], coordinate = (size_t)i < s->n_pos;
    double d = k < done ? (coordinate ? f->D[k] : -f->D[k]) : 0.0;
    if (!(d > tol * pivot_scale(s, values, i, m_norm)))
      return coordinate ? SDAE_ERR_MASS : SDAE_ERR_RANK;
  }
  return SDAE_OK;
}

void sdae__sparse_ldl_solve(sdae_sparse_ldl *f, const double *b, double *x) {
  const sdae_sparse_ldl_symbolic *s = f->sym;
  int n = (int)s->n;
  ldl_perm(n, f->x, (double *)b, s->P);
  ldl_lsolve(n, f->x, s->Lp, f->Li, f->Lx);
  ldl_dsolve(n, f->x, f->D);
  ldl_ltsolve(n, f->x, s->Lp, f->Li, f->Lx);
  ldl_permt(n, x, f->x, s->P);
}
