/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The explicit Runge-Kutta evaluation shared by the tableaus of map_rk4.c and map_rk8.c: s
 * evaluations of q0, no Newton, no allocation (the scratch is the stepper's). */
#include <stdint.h>

#include "core/callback.h"
#include "map_rk.h"
#include "model/model.h"

size_t sdae__rk_scratch(const sdae_rk_tableau *tab, const sdae_model *m) {
  size_t per_state = tab->stages + 1;
  /* an absurd n_mu: a size the arena cannot give, so the stepper reports the overflow */
  if (m->n_mu > SIZE_MAX / per_state) return SIZE_MAX;
  return per_state * m->n_mu;
}

/* y = mu + T sum_{j<i} a_ij k_j (the stage state of stage i), the sum in the order of j; the
 * zeros of a sparse tableau (DOP853's) are skipped, which changes no value */
static void stage_state(const double *a_row, size_t i, const double *k, size_t n, double T,
                        const double *mu, double *y) {
  for (size_t r = 0; r < n; r++) y[r] = 0.0;
  for (size_t j = 0; j < i; j++) {
    if (a_row[j] == 0.0) continue;
    for (size_t r = 0; r < n; r++) y[r] += a_row[j] * k[j * n + r];
  }
  for (size_t r = 0; r < n; r++) y[r] = mu[r] + T * y[r];
}

int sdae__rk_phi(const sdae_rk_tableau *tab, sdae_map_ctx *c, double t, double T, const double *mu,
                 double *out) {
  const sdae_model *m = c->model;
  size_t n = m->n_mu, s = tab->stages;
  double *k = c->work, *y = k + s * n;
  /* k_1 = q0(t, mu): c_1 = 0 and the first row of A is empty */
  int rc = sdae__eval_q0(m, t, mu, k);
  for (size_t i = 1; i < s && rc == SDAE_OK; i++) {
    stage_state(tab->a + i * (i - 1) / 2, i, k, n, T, mu, y);
    /* an overflowing stage (a step far past the method's stability limit): the step fails
     * here, as the new state would not be finite either */
    if (!sdae__all_finite(y, n)) return SDAE_ERR_NONFINITE;
    rc = sdae__eval_q0(m, t + tab->c[i] * T, y, k + i * n);
  }
  if (rc != SDAE_OK) return rc;
  /* phi_T = sum_i b_i k_i, so that eq. 11/15's mu + T phi_T is the method's step for xi = 0 */
  for (size_t r = 0; r < n; r++) out[r] = 0.0;
  for (size_t i = 0; i < s; i++) {
    if (tab->b[i] == 0.0) continue;
    for (size_t r = 0; r < n; r++) out[r] += tab->b[i] * k[i * n + r];
  }
  return SDAE_OK;
}
