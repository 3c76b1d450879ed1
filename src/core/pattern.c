/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Sparsity patterns in compressed rows (core/pattern.h). */
#include <string.h>

#include <stabdae/stabdae.h>

#include "bytes.h"
#include "pattern.h"

/* row i's columns strictly ascending, each below cols */
static int row_ok(const sdae_pattern *p, size_t i, size_t cols) {
  for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++)
    if (p->col[k] >= cols || (k > p->row_start[i] && p->col[k] <= p->col[k - 1])) return 0;
  return 1;
}

/* (i, j) is an entry: a binary search of row i's ascending columns */
static int has(const sdae_pattern *p, size_t i, size_t j) {
  size_t lo = p->row_start[i], hi = p->row_start[i + 1];
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (p->col[mid] == j) return 1;
    if (p->col[mid] < j)
      lo = mid + 1;
    else
      hi = mid;
  }
  return 0;
}

int sdae__pattern_check(const sdae_pattern *p, size_t rows, size_t cols, int symmetric) {
  if (!p->row_start || (p->nnz > 0 && !p->col)) return SDAE_ERR_PATTERN;
  if (p->row_start[0] != 0 || p->row_start[rows] != p->nnz) return SDAE_ERR_PATTERN;
  for (size_t i = 0; i < rows; i++)
    if (p->row_start[i + 1] < p->row_start[i] || !row_ok(p, i, cols)) return SDAE_ERR_PATTERN;
  for (size_t i = 0; symmetric && i < rows; i++)
    for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++)
      if (!has(p, p->col[k], i)) return SDAE_ERR_PATTERN;
  return SDAE_OK;
}

void sdae__pattern_copy(sdae_pattern *dst, const sdae_pattern *p, size_t rows, sdae_arena *a) {
  size_t *row_start = sdae__take_indices(a, rows + 1), *col = sdae__take_indices(a, p->nnz);
  dst->nnz = p->nnz;
  dst->row_start = row_start;
  dst->col = col;
  if (!row_start) return; /* only counted */
  memcpy(row_start, p->row_start, (rows + 1) * sizeof *row_start);
  if (p->nnz > 0) memcpy(col, p->col, p->nnz * sizeof *col);
}

void sdae__pattern_scatter(const sdae_pattern *p, size_t rows, size_t cols, const double *values,
                           double *dense) {
  memset(dense, 0, rows * cols * sizeof *dense);
  for (size_t i = 0; i < rows; i++)
    for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++)
      dense[i * cols + p->col[k]] = values[k];
}

uint64_t sdae__pattern_hash(uint64_t h, const sdae_pattern *p, size_t rows) {
  h = sdae__fnv(h, p->row_start, (rows + 1) * sizeof *p->row_start);
  return p->nnz > 0 ? sdae__fnv(h, p->col, p->nnz * sizeof *p->col) : h;
}
