/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The callback rule, one place for the whole library: a user callback returns 0 on success,
 * > 0 for a recoverable failure, < 0 for a fatal one (the SUNDIALS rule), and every value it
 * writes must be finite before the library uses it. */
#ifndef STABDAE_SRC_CORE_CALLBACK_H
#define STABDAE_SRC_CORE_CALLBACK_H

#include <math.h>
#include <stddef.h>
#include <string.h>

#include <stabdae/stabdae.h>

/* Inline, as the checks below: they run on every callback, a few values each for small
 * models. */
static inline int sdae__status_of_callback(int rc) {
  if (rc == 0) return SDAE_OK;
  return rc > 0 ? SDAE_ERR_CALLBACK_RECOVERABLE : SDAE_ERR_CALLBACK_FATAL;
}

static inline int sdae__all_finite(const double *v, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (!isfinite(v[i])) return 0;
  return 1;
}

/* The status of a callback that returned rc and wrote n values into out: the callback's own
 * failure, SDAE_ERR_NONFINITE for a NaN or Inf among its values, SDAE_OK otherwise. */
static inline int sdae__callback_checked(int rc, const double *out, size_t n) {
  rc = sdae__status_of_callback(rc);
  if (rc != SDAE_OK) return rc;
  return sdae__all_finite(out, n) ? SDAE_OK : SDAE_ERR_NONFINITE;
}

/* The other way, for the callbacks a front-end hands the stepper: a status as a callback's
 * return, 0, > 0 when a smaller step may help (Phi^-1's Newton, a recoverable callback), < 0
 * otherwise. */
int sdae__callback_code(int status);

/* dst = src. A small model's state, just written a double at a time by the step, is read back
 * the same way: memcpy's 16-byte loads would wait for those stores to reach the cache (a load
 * spanning two stores is not forwarded). A large one goes to memcpy, whose wide loads then win
 * (docs/performance.md). */
enum { SDAE_COPY_BY_LOOP = 8 };
static inline void sdae__copy(double *dst, const double *src, size_t n) {
  if (n > SDAE_COPY_BY_LOOP) {
    memcpy(dst, src, n * sizeof *dst);
    return;
  }
  for (size_t i = 0; i < n; i++) dst[i] = src[i];
}

#endif /* STABDAE_SRC_CORE_CALLBACK_H */
