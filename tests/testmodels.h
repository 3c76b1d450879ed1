/* Models with known answers, shared by the unit suites. */
#ifndef STABDAE_TESTMODELS_H
#define STABDAE_TESTMODELS_H

#include <check.h>
#include <stabdae/stabdae.h>

/* The oscillator of the paper's Section IV with m = 1 and unit stiffness:
 * q0 = (mu2, -k mu1^3 - d mu2), Q = [[-1, 1], [c, 1]], c = k(3 mu1^2 - 3 mu1 xi1 + xi1^2) + d;
 * H = mu2^2/2 + k mu1^4/4, S = [[0, 1], [-1, -d]]. */
typedef struct quartic {
  double k, d;
  long H_calls; /* counts the H callback, to see the discrete gradient's branches */
  int printed;  /* Q as printed in the paper: c = k(3 mu1 xi1 - 3 mu1^2 - xi1^2) + d xi1 */
} quartic;

sdae_model quartic_model(quartic *p);
/* options with the dgrad callbacks set, map and scheme as given */
sdae_options quartic_options(const sdae_map_type *map, sdae_scheme scheme);
int quartic_H(double t, const double *mu, double *out, void *params);
/* hess H = diag(3 k mu1^2, 1): not set by quartic_options (the suites choose) */
int quartic_hess_H(double t, const double *mu, double *out, void *params);
int quartic_q0_jac(double t, const double *mu, double *out, void *params);

/* A constant Q = [[2, 0], [0, 0]]: with delta = epsilon = 1 the gain k_1 = -(1/2) 4 - 1 = -3
 * everywhere, so Theorem 3's bound is T < 2/3. */
int quartic_const_Q(double t, const double *xi, const double *mu, double *out, void *params);

/* Exact solution of x'' = -k x^3 from x(0) = A, x'(0) = 0: x = A cn(A sqrt(k) t | 1/2). */
void quartic_exact(double k, double A, double t, double *x, double *v);

/* Integrates the quartic on the manifold (xi = 0) from (A, 0) to tf with step T; returns the
 * max-norm error of mu against the exact solution at tf. */
double quartic_error(const sdae_options *o, double A, double tf, double T);

double rel_diff(double a, double b);

/* One test case per behaviour; tests/CMakeLists.txt reads the ADD_CASE lines to register
 * every case as its own ctest test. */
#define ADD_CASE(suite, fn) add_case((suite), #fn, fn)
void add_case(Suite *s, const char *name, const TTest *test);

/* Runs one suite; main of every test program. */
int run_suite(Suite *s);

#endif
