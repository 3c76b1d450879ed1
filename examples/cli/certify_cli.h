/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The certification flags of the oscillator and the pendulum: --certify (Theorems 3 and 5 over
 * a box), --check-model (the normal form against the DAE), --box and --grid. */
#ifndef STABDAE_EXAMPLES_CERTIFY_CLI_H
#define STABDAE_EXAMPLES_CERTIFY_CLI_H

#include "cli.h"

#define CERT_DIM 4 /* xi1, xi2, mu1, mu2 */
#define CERT_NFLAGS 4

typedef struct cli_certify {
  int certify, check_model;
  const char *box; /* "name=lo:hi,..." or "name=v"; names xi1 xi2 mu1 mu2; NULL: the default */
  size_t grid;
  double lo[CERT_DIM], hi[CERT_DIM]; /* the box: the program's default, then --box */
} cli_certify;

/* Appends --certify --check-model --box --grid to dst (room for CERT_NFLAGS); the program's
 * default box must be in c->lo, c->hi and described in box_help. */
size_t cli_certify_flags(cli_flag *dst, cli_certify *c, const char *box_help);
/* Parses --box over the defaults: unknown names, non-numbers, NaN/Inf and lo > hi are bad
 * input (CLI_BAD with err set). */
int cli_certify_finish(cli_certify *c, char *err, size_t errlen);

/* The box and grid of c into a --certify's setup (the ensemble runner's). */
void cli_certify_box(const cli_certify *c, cli_certify_setup *s);
/* The lines of --certify from the certificate and argmax (n_xi rows of CERT_DIM). */
void cli_certify_print(const sdae_certificate *cert, const double *argmax);
/* --certify: prints sup_neg_k, argmax, T_bar, T_thm5_scheme15, T_thm5_scheme11; exit code. */
int cli_certify_run(const char *prog, const cli_certify *c, const sdae_model *m,
                    const sdae_options *o);
/* --check-model: prints the residual of each check; exit 0 when consistent, 1 when not. */
int cli_check_model_run(const char *prog, const cli_certify *c, const sdae_model *m,
                        const sdae_dae *d);

#endif /* STABDAE_EXAMPLES_CERTIFY_CLI_H */
