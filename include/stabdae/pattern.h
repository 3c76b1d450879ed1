/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae sparsity pattern (layer: core): where a matrix callback's nonzeros are, so that it writes
 * those alone (<stabdae/mbs.h>: mass_pattern, jacobian_pattern). */
#ifndef STABDAE_PATTERN_H
#define STABDAE_PATTERN_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A sparsity pattern in compressed rows: row i's entries are col[row_start[i]] ..
 * col[row_start[i + 1] - 1], columns ascending, no duplicates; row_start has rows + 1 entries
 * (row_start[0] = 0, row_start[rows] = nnz). A callback with a pattern writes nnz values, row by
 * row in this order; every entry outside it is zero. */
typedef struct sdae_pattern {
  size_t nnz;
  const size_t *row_start;
  const size_t *col;
} sdae_pattern;

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_PATTERN_H */
