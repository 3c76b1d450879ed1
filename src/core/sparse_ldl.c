/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The saddle-point system's factorization by SuiteSparse's AMD and LDL (core/sparse_ldl.h).
 * amd_l2 rather than amd_l_order: amd_l_order allocates its workspace (SuiteSparse_malloc),
 * amd_l2 takes it from the caller, as LDL does every array. Their SuiteSparse_long (64-bit)
 * versions: L's size, summed by ldl_l_symbolic, is bounded only by n^2 / 2, which an int's
 * sum would overflow (a cart under 92 680 pendulums: 4.3e9 entries) past any check after it.
 * A 32-bit target's SuiteSparse_long is a 32-bit long: sdae__sparse_ldl_fits bounds n for it. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include <amd.h>
#include <ldl.h>
#include <stabdae/stabdae.h>

#include "sparse_ldl.h"

typedef SuiteSparse_long sslong;

static sslong *take_longs(sdae_arena *a, size_t n) {
  return sdae__take_array(a, n, sizeof(sslong), _Alignof(sslong));
}

/* AMD's integers: Pe, Nv, Elen, Degree, Len, Head, W (n each), its Iw (the pattern's
 * off-diagonal entries with a fifth more and n of room to work in, as amd_order gives it), and
 * after Iw, apart from it, the order found (n) */
static size_t iw_len(size_t n, size_t nnz) { return nnz + nnz / 5 + n; }
size_t sdae__sparse_ldl_work_len(size_t n, size_t nnz) { return 8 * n + iw_len(n, nnz); }

int sdae__sparse_ldl_fits(size_t n, size_t nnz) {
  /* every count below (AMD's 8 n + 1.2 nnz + n, L's at most n^2 / 2) in SuiteSparse_long:
   * n, nnz < 2^30 where it has 64 bits; where it is a 32-bit long (32-bit targets), n^2 / 2 <
   * 2^31 takes n < 2^16, and AMD's counts nnz < 2^26 */
  const int wide = sizeof(sslong) >= 8;
  return n < ((size_t)1 << (wide ? 30 : 16)) && nnz < ((size_t)1 << (wide ? 30 : 26));
}

void sdae__sparse_ldl_symbolic_carve(sdae_sparse_ldl_symbolic *s, size_t n, size_t n_pos,
                                     size_t nnz, sdae_arena *a) {
  s->n = n, s->n_pos = n_pos, s->nnz = nnz;
  s->Ap = take_longs(a, n + 1);
  s->Ai = take_longs(a, nnz);
  s->P = take_longs(a, n), s->Pinv = take_longs(a, n);
  s->Lp = take_longs(a, n + 1), s->Parent = take_longs(a, n);
  s->cls = sdae__take_array(a, n, 1, 1);
}

/* AMD's minimum-degree order of K's graph into found (n), its workspace before found */
static void minimum_degree(sdae_sparse_ldl_symbolic *s, sslong *w, sslong *found) {
  sslong n = (sslong)s->n, pfree = 0;
  sslong *Pe = w, *Nv = Pe + n, *Elen = Nv + n, *Degree = Elen + n, *Len = Degree + n;
  sslong *Head = Len + n, *W = Head + n, *Iw = W + n;
  double control[AMD_CONTROL], info[AMD_INFO];
  for (sslong i = 0; i < n; i++) {
    Pe[i] = pfree;
    for (sslong e = s->Ap[i]; e < s->Ap[i + 1]; e++)
      if (s->Ai[e] != i) Iw[pfree++] = s->Ai[e];
    Len[i] = pfree - Pe[i];
  }
  amd_l_defaults(control);
  amd_l2(n, Pe, Iw, Len, (sslong)iw_len(s->n, s->nnz), pfree, Nv, s->Pinv, found, Head, Elen,
         Degree, W, control, info);
}

/* whether coordinate row i is taken after the multipliers: held by more than
 * SDAE_SPARSE_LDL_HUB constraints (a hub), or without a mass of its own (no diagonal entry) */
static int late(const sdae_sparse_ldl_symbolic *s, sslong i) {
  size_t held = 0;
  int diagonal = 0;
  for (sslong e = s->Ap[i]; e < s->Ap[i + 1]; e++) {
    held += (size_t)s->Ai[e] >= s->n_pos;
    diagonal |= s->Ai[e] == i;
  }
  return held > SDAE_SPARSE_LDL_HUB || !diagonal;
}

/* whether multiplier row j holds a late coordinate (cls set for the coordinates): a multiplier's
 * row of [M G^T; G 0] holds coordinates and at most its diagonal, its block of K empty but for
 * that */
static int holds_late(const sdae_sparse_ldl_symbolic *s, const unsigned char *cls, size_t j) {
  for (sslong e = s->Ap[j]; e < s->Ap[j + 1]; e++)
    if (s->Ai[e] != (sslong)j && cls[s->Ai[e]] == 2) return 1; /* the diagonal's class unset */
  return 0;
}

/* The classes of the rows, in the order they are taken: 0 the coordinates taken first, 1 the
 * multipliers matched each to a coordinate of its own among those (greedily, the one the
 * fewest constraints hold; first the multipliers that hold a late coordinate, which a late
 * coordinate without mass needs eliminated before it), 2 the late coordinates, 3 the
 * multipliers left. With every coordinate taken before every multiplier (no late one), a hub
 * of k constraints couples all k multipliers (k (k - 1) / 2 of fill: a cart under k
 * pendulums); taken after them, its constraints are eliminated through their own coordinates
 * first. Every pivot keeps its sign: the leading block [M_00 G_10^T; G_10 0] is regular when
 * G_10 has full row rank (its rows have a matching into its columns; the factor's pivot test
 * says when it is rank-deficient in value), a late coordinate's pivot is then a Schur
 * complement of the positive definite M, and the multipliers left come last, as in the order
 * of every coordinate first. */
/* multiplier row j's class: 1, matched to the free coordinate of class 0 in it that the fewest
 * constraints hold (taken), or 3 where there is none */
static unsigned char match(const sdae_sparse_ldl_symbolic *s, const unsigned char *cls,
                           sslong *taken, const sslong *held, size_t j) {
  sslong best = -1;
  for (sslong e = s->Ap[j]; e < s->Ap[j + 1]; e++) {
    sslong i = s->Ai[e];
    if ((size_t)i < s->n_pos && cls[i] == 0 && !taken[i] && (best < 0 || held[i] < held[best]))
      best = i;
  }
  if (best < 0) return 3;
  taken[best] = 1;
  return 1;
}

static void classify(sdae_sparse_ldl_symbolic *s, unsigned char *cls, sslong *taken, sslong *held) {
  for (size_t i = 0; i < s->n_pos; i++) {
    cls[i] = late(s, (sslong)i) ? 2 : 0;
    taken[i] = 0, held[i] = 0;
    for (sslong e = s->Ap[i]; e < s->Ap[i + 1]; e++) held[i] += (size_t)s->Ai[e] >= s->n_pos;
  }
  for (int pass = 0; pass < 2; pass++) /* first the multipliers that hold a late coordinate */
    for (size_t j = s->n_pos; j < s->n; j++)
      if (holds_late(s, cls, j) == (pass == 0)) cls[j] = match(s, cls, taken, held, j);
}

/* the order: AMD's, its rows taken class by class (classify), in AMD's order within each.
 * The constrained minimum degree (CAMD's) would choose them together, but Debian's libcamd.a
 * is not position-independent and so cannot be linked into an FMU. */
static void order(sdae_sparse_ldl_symbolic *s, sslong *work) {
  sslong *found = work + 7 * s->n + iw_len(s->n, s->nnz), k = 0;
  minimum_degree(s, work, found);
  classify(s, s->cls, work, work + s->n); /* AMD's workspace, done with */
  for (unsigned char pass = 0; pass < 4; pass++)
    for (size_t r = 0; r < s->n; r++)
      if (s->cls[found[r]] == pass) s->P[k++] = found[r];
  for (k = 0; k < (sslong)s->n; k++) s->Pinv[s->P[k]] = k;
}

void sdae__sparse_ldl_analyse(sdae_sparse_ldl_symbolic *s, sslong *work) {
  sslong *Lnz = work, *Flag = Lnz + s->n; /* AMD's workspace, done with */
  order(s, work);
  ldl_l_symbolic((sslong)s->n, s->Ap, s->Ai, s->Lp, s->Parent, Lnz, Flag, s->P, s->Pinv);
  s->lnz = (size_t)s->Lp[s->n];
}

void sdae__sparse_ldl_carve(sdae_sparse_ldl *f, const sdae_sparse_ldl_symbolic *sym,
                            sdae_arena *a) {
  size_t n = sym->n;
  f->sym = sym;
  f->Lnz = take_longs(a, n), f->Flag = take_longs(a, n), f->Pattern = take_longs(a, n);
  f->Li = take_longs(a, sym->lnz);
  f->Lx = sdae__take(a, sym->lnz, 1);
  f->D = sdae__take(a, n, 1), f->Y = sdae__take(a, n, 1), f->x = sdae__take(a, n, 1);
}

/* ||M||_inf, M the coordinates' block of K */
static double mass_norm(const sdae_sparse_ldl_symbolic *s, const double *values) {
  double big = 0.0;
  for (size_t i = 0; i < s->n_pos; i++) {
    double row = 0.0;
    for (sslong e = s->Ap[i]; e < s->Ap[i + 1]; e++)
      if ((size_t)s->Ai[e] < s->n_pos) row += fabs(values[e]);
    big = fmax(big, row);
  }
  return big;
}

/* the scale below which row i's pivot is rounding (n eps times it): a coordinate's, ||M||_inf,
 * the size of M's rounding, whatever that coordinate's own mass (a mass at eps of M's largest
 * is refused: docs/front-ends.md); a multiplier's, ||G_i||^2 / ||M||_inf (its row's diagonal
 * entry summed with it: zero, or a softening whose square is below |G_i|^2's rounding), the least
 * the diagonal of G M^-1 G^T can be (M's largest eigenvalue at most ||M||_inf), of which its pivot,
 * the Schur complement's, is the part the earlier constraints leave */
static double pivot_scale(const sdae_sparse_ldl_symbolic *s, const double *values, sslong i,
                          double m_norm) {
  double g = 0.0;
  if ((size_t)i < s->n_pos) return m_norm;
  for (sslong e = s->Ap[i]; e < s->Ap[i + 1]; e++) g += values[e] * values[e];
  return m_norm > 0.0 ? g / m_norm : 0.0;
}

int sdae__sparse_ldl_factor(sdae_sparse_ldl *f, const double *values) {
  const sdae_sparse_ldl_symbolic *s = f->sym;
  sslong n = (sslong)s->n;
  double tol = (double)s->n * DBL_EPSILON, m_norm = mass_norm(s, values);
  /* a zero pivot stops LDL at its step; the steps before it are checked the same way */
  sslong done = ldl_l_numeric(n, s->Ap, s->Ai, (double *)values, s->Lp, s->Parent, f->Lnz, f->Li,
                              f->Lx, f->D, f->Y, f->Pattern, f->Flag, s->P, s->Pinv);
  for (sslong k = 0; k < n; k++) {
    sslong i = s->P[k];
    int coordinate = (size_t)i < s->n_pos;
    double d = k < done ? (coordinate ? f->D[k] : -f->D[k]) : 0.0, scale;
    scale = pivot_scale(s, values, i, m_norm);
    if (!(d > tol * scale)) return coordinate ? SDAE_ERR_MASS : SDAE_ERR_RANK;
  }
  return SDAE_OK;
}

void sdae__sparse_ldl_copy(sdae_sparse_ldl *dst, const sdae_sparse_ldl *src) {
  size_t n = src->sym->n, nz = (size_t)src->sym->Lp[n];
  memcpy(dst->Li, src->Li, nz * sizeof *dst->Li);
  memcpy(dst->Lx, src->Lx, nz * sizeof *dst->Lx);
  memcpy(dst->D, src->D, n * sizeof *dst->D);
}

void sdae__sparse_ldl_solve(sdae_sparse_ldl *f, const double *b, double *x) {
  const sdae_sparse_ldl_symbolic *s = f->sym;
  sslong n = (sslong)s->n;
  ldl_l_perm(n, f->x, (double *)b, s->P);
  ldl_l_lsolve(n, f->x, s->Lp, f->Li, f->Lx);
  ldl_l_dsolve(n, f->x, f->D);
  ldl_l_ltsolve(n, f->x, s->Lp, f->Li, f->Lx);
  ldl_l_permt(n, x, f->x, s->P);
}
