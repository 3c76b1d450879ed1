/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Sparsity patterns in compressed rows (<stabdae/pattern.h>): checked where a stepper is built,
 * copied into its block, and the values a callback writes in pattern order put in place. */
#ifndef STABDAE_SRC_CORE_PATTERN_H
#define STABDAE_SRC_CORE_PATTERN_H

#include <stddef.h>
#include <stdint.h>

#include <stabdae/pattern.h>

#include "arena.h"

/* SDAE_OK for a pattern of a rows x cols matrix as <stabdae/pattern.h> defines it (and, when
 * symmetric, with (j, i) wherever (i, j)); SDAE_ERR_PATTERN otherwise */
int sdae__pattern_check(const sdae_pattern *p, size_t rows, size_t cols, int symmetric);
/* a copy of p (rows rows) with its arrays from a, written when a hands them out */
void sdae__pattern_copy(sdae_pattern *dst, const sdae_pattern *p, size_t rows, sdae_arena *a);
/* the rows x cols dense matrix (row-major) of the values in pattern order, zero elsewhere */
void sdae__pattern_scatter(const sdae_pattern *p, size_t rows, size_t cols, const double *values,
                           double *dense);
/* the pattern folded into a running FNV-1a hash (core/bytes.h): its identity */
uint64_t sdae__pattern_hash(uint64_t h, const sdae_pattern *p, size_t rows);

#endif /* STABDAE_SRC_CORE_PATTERN_H */
