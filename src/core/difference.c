/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The fourth-order central differences (difference.h): their points, weights and divisions. */
#include "difference.h"

const double sdae__fd_offset[SDAE_FD2_POINTS] = {1.0, -1.0, 2.0, -2.0, 0.0};
static const double weight[SDAE_FD_POINTS] = {8.0, -8.0, -1.0, 1.0};            /* 12 h */
static const double weight2[SDAE_FD2_POINTS] = {16.0, 16.0, -1.0, -1.0, -30.0}; /* 12 h^2 */

double sdae__fd_step(double x, double h0) {
  double xh = x + h0;
  return xh - x;
}

void sdae__fd_add(double *out, size_t stride, const double *f, size_t n, int k) {
  for (size_t i = 0; i < n; i++) out[i * stride] += weight[k] * f[i];
}

void sdae__fd_finish(double *out, size_t stride, size_t n, double h) {
  for (size_t i = 0; i < n; i++) out[i * stride] /= 12.0 * h;
}

void sdae__fd2_add(double *out, size_t stride, const double *f, size_t n, int k) {
  for (size_t i = 0; i < n; i++) out[i * stride] += weight2[k] * f[i];
}

void sdae__fd2_finish(double *out, size_t stride, size_t n, double h) {
  for (size_t i = 0; i < n; i++) out[i * stride] /= 12.0 * h * h;
}
