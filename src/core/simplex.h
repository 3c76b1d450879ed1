/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A compact Nelder-Mead minimizer working in memory the caller hands it. */
#ifndef STABDAE_SRC_CORE_SIMPLEX_H
#define STABDAE_SRC_CORE_SIMPLEX_H

#include <stddef.h>

/* the objective at u (n values): writes *value and returns 0, or a non-zero status that stops
 * the search and is returned by sdae__simplex_minimize */
typedef int (*sdae__simplex_fn)(const double *u, double *value, void *data);

/* doubles of work sdae__simplex_minimize needs for n unknowns, (n + 1)^2 + 3 n (0 for n = 0),
 * or SIZE_MAX when that overflows size_t */
size_t sdae__simplex_work(size_t n);

/* Minimizes f from the simplex u, u + step e_j (j < n) until the vertices' RMS distance from
 * their center is below size_tol or after max_iter iterations. u gets the best vertex found.
 * Returns 0, or the first non-zero status of f. */
int sdae__simplex_minimize(sdae__simplex_fn f, void *data, size_t n, double *u, double step,
                           double size_tol, int max_iter, double *work);

#endif /* STABDAE_SRC_CORE_SIMPLEX_H */
