/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "certify_cli.h"

#include <string.h>

static const char *const names[CERT_DIM] = {"xi1", "xi2", "mu1", "mu2"};

size_t cli_certify_flags(cli_flag *dst, cli_certify *c, const char *box_help) {
  const cli_flag flags[CERT_NFLAGS] = {
      {"certify", CLI_SWITCH, &c->certify, NULL, 0,
       "print the step-size bounds of Theorems 3 and 5 over --box, then exit"},
      {"check-model", CLI_SWITCH, &c->check_model, NULL, 0,
       "check q0, Q against the DAE at random points of --box; exit 0 if consistent, 1 if not"},
      {"box", CLI_TEXT, &c->box, NULL, 0, box_help},
      {"grid", CLI_COUNT, &c->grid, NULL, 0, "grid points per free coordinate of --certify"},
  };
  memcpy(dst, flags, sizeof flags);
  return CERT_NFLAGS;
}

/* one "name=lo:hi" or "name=v" item */
static int parse_item(cli_certify *c, const char *item, size_t len, char *err, size_t errlen) {
  char buf[96], *eq, *colon;
  size_t j;
  if (len == 0 || len >= sizeof buf) return cli_fail(err, errlen, "--box: empty or too long item");
  memcpy(buf, item, len);
  buf[len] = '\0';
  if (!(eq = strchr(buf, '='))) return cli_fail(err, errlen, "--box: '%s' is not name=lo:hi", buf);
  *eq = '\0';
  for (j = 0; j < CERT_DIM && strcmp(buf, names[j]) != 0; j++) continue;
  if (j == CERT_DIM)
    return cli_fail(err, errlen, "--box: unknown coordinate '%s' (expected xi1, xi2, mu1, mu2)",
                    buf);
  colon = strchr(eq + 1, ':');
  if (colon) *colon = '\0';
  if (cli_parse_double(eq + 1, &c->lo[j]) ||
      cli_parse_double(colon ? colon + 1 : eq + 1, &c->hi[j]))
    return cli_fail(err, errlen, "--box: %s: bounds must be finite numbers", names[j]);
  if (c->lo[j] > c->hi[j])
    return cli_fail(err, errlen, "--box: %s: lower bound %g above upper bound %g", names[j],
                    c->lo[j], c->hi[j]);
  return CLI_OK;
}

int cli_certify_finish(cli_certify *c, char *err, size_t errlen) {
  const char *p = c->box;
  while (p) {
    const char *comma = strchr(p, ',');
    size_t len = comma ? (size_t)(comma - p) : strlen(p);
    int rc = parse_item(c, p, len, err, errlen);
    if (rc != CLI_OK) return rc;
    p = comma ? comma + 1 : NULL;
  }
  return CLI_OK;
}

int cli_certify_run(const char *prog, const cli_certify *c, const sdae_model *m,
                    const sdae_options *o) {
  sdae_stepper *s;
  sdae_certificate cert;
  double argmax[2 * CERT_DIM];
  int rc = sdae_stepper_alloc(&s, m, o);
  if (rc == SDAE_OK) {
    rc = sdae_certify_box(s, 0.0, c->lo, c->hi, (unsigned)c->grid, NULL, argmax, &cert);
    sdae_stepper_free(s);
  }
  if (rc != SDAE_OK) {
    fprintf(stderr, "%s: --certify: %s\n", prog, sdae_strerror(rc));
    return rc == SDAE_ERR_PARAM ? CLI_EXIT_USAGE : CLI_EXIT_FAILED;
  }
  cli_certify_print(&cert, argmax);
  return CLI_EXIT_OK;
}

void cli_certify_box(const cli_certify *c, cli_certify_setup *s) {
  s->lo = c->lo;
  s->hi = c->hi;
  s->grid = (unsigned)c->grid;
}

void cli_certify_print(const sdae_certificate *cert, const double *argmax) {
  const double *at = argmax + cert->i_max * CERT_DIM;
  printf("sup_neg_k: %.10g\n", cert->sup_neg_k);
  printf("gain: k%zu\n", cert->i_max + 1);
  printf("argmax: xi1=%.10g xi2=%.10g mu1=%.10g mu2=%.10g\n", at[0], at[1], at[2], at[3]);
  printf("T_bar: %.10g\n", cert->T_bar);
  printf("T_thm5_scheme15: %.10g\n", cert->T_thm5_scheme15);
  printf("T_thm5_scheme11: %.10g\n", cert->T_thm5_scheme11);
}

int cli_check_model_run(const char *prog, const cli_certify *c, const sdae_model *m,
                        const sdae_dae *d) {
  static const char *const check_names[4] = {"inverse", "L_g", "chain", "dynamics"};
  const size_t points = 1000;
  const double tol = 1e-6;
  double worst[CERT_DIM];
  sdae_check_report r = {0};
  int rc = sdae_check_model(m, d, 0.0, c->lo, c->hi, points, 1, tol, worst, &r);
  if (rc != SDAE_OK) {
    fprintf(stderr, "%s: --check-model: %s (after %zu points)\n", prog, sdae_strerror(rc),
            r.points);
    return CLI_EXIT_FAILED;
  }
  printf("points: %zu\ntolerance: %g (relative to the size of the terms)\n", r.points, tol);
  for (int k = 0; k < 4; k++) printf("%s: %.3g\n", check_names[k], r.residual[k]);
  printf("worst: %s, component %s, at xi1=%.6g xi2=%.6g mu1=%.6g mu2=%.6g\n",
         check_names[r.worst_check], names[r.worst_index], worst[0], worst[1], worst[2], worst[3]);
  printf("consistent: %s\n", r.consistent ? "yes" : "no");
  return r.consistent ? CLI_EXIT_OK : CLI_EXIT_FAILED;
}
