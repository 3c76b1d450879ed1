/* SPDX-License-Identifier: GPL-3.0-or-later */
/* CBLAS's error handler, for the CBLAS linked into each FMU's binary. stabdae_add_fmu links GSL's
 * CBLAS from Debian's libgslcblas.a, so that GSL's calls bind inside the binary and never to a
 * cblas_* the importer's process loaded first. The archive's objects are position-independent
 * code (built as PIE), all but its handler xerbla.o, which reads libc's stderr through a copy
 * relocation a shared object cannot have, prints and aborts. This handler, in the archives the
 * binary takes whole (stabdae_fmi3, stabdae_fmi2), comes before libgslcblas.a, so the linker
 * never takes xerbla.o. It does nothing: GSL's gsl_blas_* functions check every size and flag
 * before they call CBLAS, so stabdae never reaches it, and an FMU never prints or aborts. */
#include <gsl/gsl_cblas.h>

void cblas_xerbla(int p, const char *rout, const char *form, ...) {
  (void)p, (void)rout, (void)form;
}
