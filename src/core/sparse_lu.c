/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A wide sparse matrix factored row by row, its pivot columns chosen by the values
 * (core/sparse_lu.h). Written here: SuiteSparse's factorizations (KLU, UMFPACK) take a square
 * matrix or choose columns by its structure before they see a value, and UMFPACK on A^T forms
 * rows equivalent to B^T, which are dense on a chain; none chooses the independent columns of a
 * wide matrix by its values in its nonzeros' time. */
#include <float.h>
#include <math.h>
#include <stdalign.h>
#include <stdint.h>
#include <string.h>

#include <stabdae/stabdae.h>

#include "sparse_lu.h"

static uint32_t *take_entries(sdae_arena *a, size_t cap) {
  return sdae__take_array(a, cap, sizeof(uint32_t), alignof(uint32_t));
}

size_t sdae__sparse_lu_reserve(size_t m, size_t nnz) { return SDAE_SPARSE_LU_FILL * nnz + m; }

void sdae__sparse_lu_carve(sdae_sparse_lu *lu, size_t m, size_t n, size_t nnz, size_t l_cap,
                           sdae_arena *a) {
  size_t cap = sdae__sparse_lu_reserve(m, nnz) + l_cap; /* U's and L's, shared */
  lu->m = m, lu->n = n, lu->cap = cap, lu->l_cap = l_cap;
  lu->order = sdae__take_indices(a, m);
  lu->pivot = sdae__take_indices(a, m);
  lu->row_of = sdae__take_indices(a, n);
  lu->u_start = sdae__take_indices(a, m + 1);
  lu->u_diag = sdae__take_indices(a, m);
  lu->u_dend = sdae__take_indices(a, m);
  lu->u_col = take_entries(a, cap);
  lu->u_step = take_entries(a, cap);
  lu->u_val = sdae__take(a, cap, 1);
  lu->l_start = sdae__take_indices(a, m + 1);
  lu->l_col = lu->u_col, lu->l_val = lu->u_val; /* none yet */
  lu->x = sdae__take(a, n, 1);
  lu->list = sdae__take_indices(a, n);
  lu->heap = sdae__take_indices(a, m);
  lu->count = sdae__take_indices(a, n);
  lu->in_row = sdae__take_array(a, n, 1, 1);
  lu->pending = sdae__take_array(a, m, 1, 1);
  lu->w = sdae__take(a, m, 1);
  lu->v = sdae__take(a, m, 1);
  lu->done = sdae__take_array(a, m, 1, 1);
}

/* ---- the elimination of one row ---- */

/* the larger of m and |x|, written out: fmax is a call (its NaN rules) on every entry's path,
 * and the values here are finite (a callback's, checked) */
static double max_abs(double m, double x) { return fabs(x) > m ? fabs(x) : m; }

/* the pending pivot rows, a binary heap with the smallest on top */
static void heap_push(sdae_sparse_lu *lu, size_t *len, size_t k) {
  size_t i = (*len)++;
  for (; i > 0 && lu->heap[(i - 1) / 2] > k; i = (i - 1) / 2) lu->heap[i] = lu->heap[(i - 1) / 2];
  lu->heap[i] = k;
}

static size_t heap_pop(sdae_sparse_lu *lu, size_t *len) {
  size_t *h = lu->heap, top = h[0], last = h[--*len], i = 0;
  for (;;) {
    size_t c = 2 * i + 1;
    if (c >= *len) break;
    if (c + 1 < *len && h[c + 1] < h[c]) c++;
    if (h[c] >= last) break;
    h[i] = h[c];
    i = c;
  }
  h[i] = last;
  return top;
}

/* column c joins row r's columns (x[c] from 0); a pivot column of an earlier row, its row to
 * be taken out */
static void touch(sdae_sparse_lu *lu, size_t r, size_t c, size_t *n_list, size_t *n_heap) {
  size_t k = lu->row_of[c];
  if (!lu->in_row[c]) {
    lu->in_row[c] = 1;
    lu->x[c] = 0.0;
    lu->list[(*n_list)++] = c;
  }
  if (k < r && !lu->pending[k]) {
    lu->pending[k] = 1;
    heap_push(lu, n_heap, k);
  }
}

/* Step r: A's row order[r] into x (its columns in list) with the steps before it taken out,
 * smallest pivot first (a step taken out adds its columns, among them later pivots), the
 * multipliers into L's row r; *scale the row's largest |value| in A. SDAE_ERR_PATTERN when L
 * is full. */
static int eliminate(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values, size_t r,
                     size_t u_used, size_t *n_list, size_t *l_used, double *scale) {
  size_t n_heap = 0, ar = lu->order[r];
  *n_list = 0, *scale = 0.0;
  lu->l_start[r] = *l_used;
  for (size_t e = A->row_start[ar]; e < A->row_start[ar + 1]; e++) {
    touch(lu, r, A->col[e], n_list, &n_heap);
    lu->x[A->col[e]] = values[e];
    *scale = max_abs(*scale, values[e]);
  }
  while (n_heap > 0) {
    size_t k = heap_pop(lu, &n_heap), p = lu->pivot[k];
    double l = lu->x[p] / lu->u_val[lu->u_diag[k]];
    if (*l_used + u_used == lu->cap) {
      lu->pending[k] = 0;
      while (n_heap > 0) lu->pending[heap_pop(lu, &n_heap)] = 0;
      return SDAE_ERR_PATTERN;
    }
    lu->u_col[lu->cap - 1 - *l_used] = (uint32_t)k; /* L from the reserve's back */
    lu->u_val[lu->cap - 1 - (*l_used)++] = l;
    for (size_t e = lu->u_start[k]; e < lu->u_start[k + 1]; e++) {
      size_t c = lu->u_col[e];
      touch(lu, r, c, n_list, &n_heap);
      lu->x[c] = c == p ? 0.0 : lu->x[c] - l * lu->u_val[e]; /* p taken out exactly */
    }
    lu->pending[k] = 0; /* after its own row: touching p_k must not bring it back */
  }
  lu->l_start[r + 1] = *l_used;
  return SDAE_OK;
}

/* the pivot of row r: among the columns not yet pivots with |x| >= tau max |x|, the one the
 * fewest rows to come hold, the larger |x| on a tie; SDAE_ERR_RANK when the row is gone to
 * rounding of its own values */
static int pick(const sdae_sparse_lu *lu, size_t r, size_t n_list, double scale, size_t *p) {
  double big = 0.0;
  size_t best = lu->n;
  for (size_t i = 0; i < n_list; i++)
    if (lu->row_of[lu->list[i]] >= r) big = max_abs(big, lu->x[lu->list[i]]);
  if (!(big > (double)lu->n * DBL_EPSILON * scale)) return SDAE_ERR_RANK;
  for (size_t i = 0; i < n_list; i++) {
    size_t c = lu->list[i];
    double v = fabs(lu->x[c]);
    if (lu->row_of[c] < r || !(v >= SDAE_SPARSE_LU_TAU * big)) continue;
    if (best == lu->n || lu->count[c] < lu->count[best] ||
        (lu->count[c] == lu->count[best] && v > fabs(lu->x[best])))
      best = c;
  }
  *p = best;
  return SDAE_OK;
}

/* U's row r from x, the columns not pivots of earlier rows; x and the marks cleared */
static int store(sdae_sparse_lu *lu, size_t r, size_t n_list, size_t l_used, size_t *u_used) {
  int rc = SDAE_OK;
  lu->u_start[r] = *u_used;
  for (size_t i = 0; i < n_list; i++) {
    size_t c = lu->list[i];
    lu->in_row[c] = 0;
    if (lu->row_of[c] < r || rc != SDAE_OK) continue;
    if (*u_used + l_used == lu->cap) {
      rc = SDAE_ERR_PATTERN;
      continue;
    }
    if (c == lu->pivot[r]) lu->u_diag[r] = *u_used;
    lu->u_col[*u_used] = (uint32_t)c, lu->u_val[(*u_used)++] = lu->x[c];
  }
  lu->u_start[r + 1] = *u_used;
  return rc;
}

/* ---- the choice's counts ---- */

/* each column's count of the rows holding it */
static void column_counts(sdae_sparse_lu *lu, const sdae_pattern *A) {
  for (size_t c = 0; c < lu->n; c++) lu->count[c] = 0;
  for (size_t e = 0; e < A->nnz; e++) lu->count[A->col[e]]++;
}

/* A's row ar taken: its columns' counts of rows to come */
static void count_out(sdae_sparse_lu *lu, const sdae_pattern *A, size_t ar) {
  for (size_t e = A->row_start[ar]; e < A->row_start[ar + 1]; e++) lu->count[A->col[e]]--;
}

/* a choice's start: no column a pivot, and the elimination's Markowitz counts */
static void choice_start(sdae_sparse_lu *lu, const sdae_pattern *A) {
  for (size_t c = 0; c < lu->n; c++) lu->row_of[c] = lu->m;
  column_counts(lu, A);
}

/* L's entries, written from the reserve's back, turned to run forward where they lie: l_col
 * and l_val point at the first */
static void l_in_order(sdae_sparse_lu *lu, size_t l_used) {
  uint32_t *col = lu->u_col + lu->cap - l_used;
  double *val = lu->u_val + lu->cap - l_used;
  for (size_t i = 0; i < l_used / 2; i++) {
    size_t j = l_used - 1 - i;
    uint32_t c = col[i];
    double v = val[i];
    col[i] = col[j], val[i] = val[j], col[j] = c, val[j] = v;
  }
  lu->l_col = col, lu->l_val = val;
}

/* the factorization, the order and the pivots chosen (choose) or kept */
static int factor(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values, int choose) {
  size_t m = lu->m, l_used = 0, u_used = 0;
  int rc = SDAE_OK;
  lu->l_start[0] = lu->u_start[0] = 0;
  if (choose) choice_start(lu, A);
  for (size_t r = 0; r < m && rc == SDAE_OK; r++) {
    size_t n_list, p = lu->pivot[r];
    double scale;
    if (choose) count_out(lu, A, lu->order[r]); /* the counts: the rows to come */
    rc = eliminate(lu, A, values, r, u_used, &n_list, &l_used, &scale);
    if (rc == SDAE_OK && choose && (rc = pick(lu, r, n_list, scale, &p)) == SDAE_OK)
      lu->pivot[r] = p, lu->row_of[p] = r;
    /* a kept pivot outside its row (as bytes read may hold) has no value: refused too */
    if (rc == SDAE_OK && !choose &&
        (!lu->in_row[p] || !(fabs(lu->x[p]) > (double)lu->n * DBL_EPSILON * scale)))
      rc = SDAE_ERR_RANK;
    if (rc == SDAE_OK) {
      rc = store(lu, r, n_list, l_used, &u_used);
    } else {
      for (size_t i = 0; i < n_list; i++) lu->in_row[lu->list[i]] = 0;
    }
  }
  if (rc == SDAE_OK) l_in_order(lu, l_used);
  return rc;
}

/* U's rows laid out for the solves (sdae_sparse_lu's u_dend): each copied out to the
 * elimination's workspace, free once factored, and written back by group */
static void split(sdae_sparse_lu *lu) {
  size_t *col = lu->list;
  double *val = lu->x;
  for (size_t k = 0; k < lu->m; k++) {
    size_t a = lu->u_start[k], len = lu->u_start[k + 1] - a, d = a + 1;
    for (size_t i = 0; i < len; i++) col[i] = lu->u_col[a + i], val[i] = lu->u_val[a + i];
    lu->u_col[a] = (uint32_t)lu->pivot[k], lu->u_val[a] = val[lu->u_diag[k] - a];
    lu->u_diag[k] = a;
    for (size_t i = 0; i < len; i++) { /* later pivots' columns (none is an earlier one's) */
      size_t j = lu->row_of[col[i]];
      if (j != k && j < lu->m)
        lu->u_col[d] = (uint32_t)col[i], lu->u_val[d] = val[i], lu->u_step[d++] = (uint32_t)j;
    }
    lu->u_dend[k] = d;
    for (size_t i = 0; i < len; i++) /* q_I's */
      if (lu->row_of[col[i]] == lu->m) lu->u_col[d] = (uint32_t)col[i], lu->u_val[d++] = val[i];
  }
}

int sdae__sparse_lu_choose(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values) {
  int rc = factor(lu, A, values, 1);
  if (rc == SDAE_OK) split(lu);
  return rc;
}

/* a later order's chart better than the one kept (measure, entries): its measure smaller by
 * factor, or the same to rounding with fewer entries */
static int better(double measure, size_t entries, double best, size_t least, double by) {
  double tie = 1e-9 * best;
  return measure * by < best || (fabs(measure - best) <= tie && entries < least);
}

int sdae__sparse_lu_choose_best(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values,
                                const size_t *orders, size_t k, double by, double *x, double *z) {
  size_t m = lu->m, best = k, least = SIZE_MAX;
  double top = HUGE_VAL;
  int rc = SDAE_ERR_PATTERN;
  for (size_t i = 0; i < k; i++) {
    int got;
    memcpy(lu->order, orders + i * m, m * sizeof *lu->order);
    if ((got = factor(lu, A, values, 1)) == SDAE_OK) {
      size_t entries = lu->l_start[m] + lu->u_start[m];
      double measure;
      split(lu);
      measure = sdae__sparse_lu_norm1(lu, x, z);
      if (best == k || better(measure, entries, top, least, by))
        best = i, top = measure, least = entries;
    }
    if (got == SDAE_ERR_RANK) rc = got;
  }
  if (best == k) return rc;
  if (best == k - 1) return SDAE_OK; /* the last one tried: its factors in place */
  memcpy(lu->order, orders + best * m, m * sizeof *lu->order);
  return sdae__sparse_lu_choose(lu, A, values);
}

int sdae__sparse_lu_refactor(sdae_sparse_lu *lu, const sdae_pattern *A, const double *values) {
  int rc = factor(lu, A, values, 0);
  if (rc == SDAE_OK) split(lu);
  return rc;
}

/* ---- solves ---- */

/* x = U_D^-1 y (both by pivot), row by row from the last */
static void back(const sdae_sparse_lu *lu, const double *y, double *x) {
  const uint32_t *step = lu->u_step;
  const double *u = lu->u_val;
  for (size_t k = lu->m; k-- > 0;) {
    double s = y[k];
    for (size_t e = lu->u_start[k] + 1; e < lu->u_dend[k]; e++) s -= u[e] * x[step[e]];
    x[k] = s / u[lu->u_start[k]];
  }
}

/* w = U_D^-T w in place (by pivot), each row's part pushed to the later rows */
static void forward_t(const sdae_sparse_lu *lu, double *w) {
  const uint32_t *step = lu->u_step;
  const double *u = lu->u_val;
  for (size_t k = 0; k < lu->m; k++) {
    w[k] /= u[lu->u_start[k]];
    for (size_t e = lu->u_start[k] + 1; e < lu->u_dend[k]; e++) w[step[e]] -= u[e] * w[k];
  }
}

void sdae__sparse_lu_solve(sdae_sparse_lu *lu, const double *b, double *x) {
  double *y = lu->w;
  for (size_t r = 0; r < lu->m; r++) { /* y = L^-1 b, b's rows in the steps' order */
    double s = b[lu->order[r]];
    for (size_t e = lu->l_start[r]; e < lu->l_start[r + 1]; e++)
      s -= lu->l_val[e] * y[lu->l_col[e]];
    y[r] = s;
  }
  back(lu, y, x);
}

void sdae__sparse_lu_solve_t(sdae_sparse_lu *lu, const double *c, double *y) {
  double *w = lu->w;
  memcpy(w, c, lu->m * sizeof *w);
  forward_t(lu, w);
  for (size_t r = lu->m; r-- > 0;) /* y = L^-T w in place, from the last row */
    for (size_t e = lu->l_start[r]; e < lu->l_start[r + 1]; e++)
      w[lu->l_col[e]] -= lu->l_val[e] * w[r];
  for (size_t r = 0; r < lu->m; r++) y[lu->order[r]] = w[r]; /* by A's rows */
}

void sdae__sparse_lu_times_b(sdae_sparse_lu *lu, const double *x, double *out) {
  double *t = lu->w;
  for (size_t k = 0; k < lu->m; k++) { /* t = U_I x */
    double s = 0.0;
    for (size_t e = lu->u_dend[k]; e < lu->u_start[k + 1]; e++) s += lu->u_val[e] * x[lu->u_col[e]];
    t[k] = s;
  }
  back(lu, t, out);
}

void sdae__sparse_lu_times_bt(sdae_sparse_lu *lu, const double *y, double *out) {
  double *w = lu->w;
  memcpy(w, y, lu->m * sizeof *w);
  forward_t(lu, w);
  memset(out, 0, lu->n * sizeof *out);
  for (size_t k = 0; k < lu->m; k++) /* out = U_I^T w */
    for (size_t e = lu->u_dend[k]; e < lu->u_start[k + 1]; e++)
      out[lu->u_col[e]] += lu->u_val[e] * w[k];
}

/* ---- ||B||_1 ---- */

static double norm1_of(const double *v, size_t n) {
  double s = 0.0;
  for (size_t i = 0; i < n; i++) s += fabs(v[i]);
  return s;
}

/* Higham's last test (dlacn2): B applied to the alternating ramp b_j = (-1)^j (1 + j / (n_I - 1))
 * over the columns of B, whose 2 ||B b||_1 / (3 n_I) catches what the iteration missed */
static double ramp(sdae_sparse_lu *lu, double *x) {
  size_t n_i = lu->n - lu->m, j = 0;
  for (size_t c = 0; c < lu->n; c++) {
    x[c] = 0.0;
    if (lu->row_of[c] != lu->m) continue;
    x[c] = (j % 2 ? -1.0 : 1.0) * (1.0 + (n_i > 1 ? (double)j / (double)(n_i - 1) : 0.0));
    j++;
  }
  sdae__sparse_lu_times_b(lu, x, lu->v);
  return 2.0 * norm1_of(lu->v, lu->m) / (3.0 * (double)n_i);
}

/* the column of B's largest |z_j| (z = B^T sign(B x)), and z^T x */
static size_t steepest(const sdae_sparse_lu *lu, const double *z, const double *x, double *zx) {
  size_t j = lu->n;
  *zx = 0.0;
  for (size_t c = 0; c < lu->n; c++) {
    if (lu->row_of[c] != lu->m) continue;
    *zx += z[c] * x[c];
    if (j == lu->n || fabs(z[c]) > fabs(z[j])) j = c;
  }
  return j;
}

double sdae__sparse_lu_norm1(sdae_sparse_lu *lu, double *x, double *z) {
  size_t m = lu->m, n = lu->n, n_i = n - m, last = n;
  double est = 0.0, *v = lu->v;
  if (n_i == 0) return 0.0;
  for (size_t c = 0; c < n; c++) x[c] = lu->row_of[c] == m ? 1.0 / (double)n_i : 0.0;
  for (int it = 0; it < 5; it++) {
    double next, zx;
    size_t j;
    sdae__sparse_lu_times_b(lu, x, v);
    next = norm1_of(v, m);
    if (it > 0 && next <= est) break; /* no gain: the estimate stands */
    est = next;
    for (size_t k = 0; k < m; k++) v[k] = v[k] >= 0.0 ? 1.0 : -1.0;
    sdae__sparse_lu_times_bt(lu, v, z);
    j = steepest(lu, z, x, &zx);
    if (fabs(z[j]) <= zx || j == last) break; /* a local maximum of ||B x||_1 */
    for (size_t c = 0; c < n; c++) x[c] = 0.0;
    x[j] = 1.0, last = j;
  }
  return fmax(est, ramp(lu, x));
}
