/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The fourth-order central difference, the one rule every derivative by differences of the
 * library and its tools follows (difference.c):
 *
 *   f'(x) ~ (8 (f(x + h) - f(x - h)) - (f(x + 2h) - f(x - 2h))) / (12 h),
 *
 * error h^4 |f^(5)| / 30 plus about 3 eps |f| / (2 h): a step of SDAE_FD_STEP (eps^(1/5))
 * relative to the variable's scale balances the two, both near 1e-13 relative for f of unit
 * scale. A caller evaluates f at x + sdae__fd_offset[k] h for k = 0 .. SDAE_FD_POINTS - 1,
 * adds each value with sdae__fd_add and divides once with sdae__fd_finish. The second
 * derivative on the same points and x itself (the tools' IDA reference alone needs it):
 *
 *   f''(x) ~ (16 (f(x + h) + f(x - h)) - (f(x + 2h) + f(x - 2h)) - 30 f(x)) / (12 h^2),
 *
 * with a step of SDAE_FD2_STEP (eps^(1/6)). */
#ifndef STABDAE_SRC_CORE_DIFFERENCE_H
#define STABDAE_SRC_CORE_DIFFERENCE_H

#include <stddef.h>

#define SDAE_FD_STEP 7.4e-4 /* DBL_EPSILON^(1/5) */
#define SDAE_FD_POINTS 4
#define SDAE_FD2_STEP 2.5e-3 /* DBL_EPSILON^(1/6) */
#define SDAE_FD2_POINTS 5    /* sdae__fd_offset's four, then x itself (offset 0) */

/* the k-th point's offset, in steps h (the fifth, 0, the second derivative's alone) */
extern const double sdae__fd_offset[SDAE_FD2_POINTS];
/* a step near h0 that x + h represents exactly, so that the points are where the combination
 * assumes them */
double sdae__fd_step(double x, double h0);
/* out[i * stride] += the k-th weight times f[i], i < n */
void sdae__fd_add(double *out, size_t stride, const double *f, size_t n, int k);
/* out[i * stride] /= 12 h, i < n: the derivative */
void sdae__fd_finish(double *out, size_t stride, size_t n, double h);
/* the same for the second derivative: its k-th weight, and the division by 12 h^2 */
void sdae__fd2_add(double *out, size_t stride, const double *f, size_t n, int k);
void sdae__fd2_finish(double *out, size_t stride, size_t n, double h);

#endif /* STABDAE_SRC_CORE_DIFFERENCE_H */
