/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Check suite of the IDA reference: the residuals against their derivatives, IDA against the
 * exact solutions (Jacobi elliptic functions from GSL), energy, constraints, projection, output
 * times and failures. Every bound comes from the mathematics or the requested tolerance. */
#include "ida_models.h"
#include "ida_solve.h"

#include <check.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_sf_ellint.h>
#include <gsl/gsl_sf_elljac.h>
#include <ida/ida.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- exact solutions ---------------------------------------------------------------------- */

/* Oscillator with d = 0 on the manifold: X'' = -(k/m) X^3, X(0) = A, X'(0) = 0 is solved by
 * X = A cn(w t | 1/2), w = A sqrt(k/m) (parameter m = 1/2); X' = -A w sn dn. */
static void oscillator_exact(const idaref_model *p, double A, double t, double *X, double *Xdot) {
  double w = A * sqrt(p->k / p->m), sn, cn, dn;
  ck_assert_int_eq(gsl_sf_elljac_e(w * t, 0.5, &sn, &cn, &dn), GSL_SUCCESS);
  *X = A * cn;
  *Xdot = -A * w * sn * dn;
}

/* Pendulum from rest at theta0: sin(theta/2) = s sn(K(s) - w t; s), s = sin(theta0/2),
 * w = sqrt(ga/L). GSL: ellint_Kcomp takes the modulus s, elljac the parameter s^2.
 * theta' = -2 s w cn dn / cos(theta/2). */
static void pendulum_exact(const idaref_model *p, double theta0, double t, double *theta,
                           double *thetadot) {
  double s = sin(0.5 * theta0), w = sqrt(p->ga / p->L), sn, cn, dn;
  double K = gsl_sf_ellint_Kcomp(s, GSL_PREC_DOUBLE);
  ck_assert_int_eq(gsl_sf_elljac_e(K - w * t, s * s, &sn, &cn, &dn), GSL_SUCCESS);
  *theta = 2.0 * asin(s * sn);
  *thetadot = -2.0 * s * w * cn * dn / cos(0.5 * *theta);
}

/* ---- a recorder of the output rows --------------------------------------------------------- */

typedef struct recorder {
  const idaref_model *p;
  double A, theta0; /* the starts of the exact solutions */
  size_t rows;
  double t_first, t_last;
  double err_pos, err_vel; /* max |position error|, max |velocity error| */
  double lambda_first, err_lambda;
  double max_h, max_hdot;      /* max |h| (pendulum: |X^2 + Y^2 - L^2| = 2|h|), max |hdot| */
  double E0, max_dE, max_rise; /* energy drift, largest increase between outputs */
  double E_prev;
  int fail_at_row; /* make the row callback fail at this row (0: never) */
} recorder;

static void record_energy(recorder *r, const double *y) {
  double E = idaref_energy(r->p, y);
  if (r->rows == 1) {
    r->E0 = r->E_prev = E;
    return;
  }
  r->max_dE = fmax(r->max_dE, fabs(E - r->E0));
  r->max_rise = fmax(r->max_rise, E - r->E_prev);
  r->E_prev = E;
}

static void record_exact(recorder *r, double t, const double *y) {
  const idaref_model *p = r->p;
  double lambda_exact;
  if (p->kind == IDAREF_OSCILLATOR) {
    double X, Xdot;
    oscillator_exact(p, r->A, t, &X, &Xdot);
    r->err_pos = fmax(r->err_pos, fmax(fabs(y[IDAREF_X] - X), fabs(y[IDAREF_Y])));
    r->err_vel = fmax(r->err_vel, fmax(fabs(y[IDAREF_XDOT] - Xdot), fabs(y[IDAREF_YDOT])));
    lambda_exact = -p->m * p->ga; /* Ydd = -ga - lambda/m = 0 */
  } else {
    double th, thd;
    pendulum_exact(p, r->theta0, t, &th, &thd);
    r->err_pos = fmax(r->err_pos,
                      fmax(fabs(y[IDAREF_X] - p->L * sin(th)), fabs(y[IDAREF_Y] + p->L * cos(th))));
    r->err_vel = fmax(r->err_vel, fmax(fabs(y[IDAREF_XDOT] - p->L * cos(th) * thd),
                                       fabs(y[IDAREF_YDOT] - p->L * sin(th) * thd)));
    /* tension lambda L = m (L theta'^2 + ga cos theta), theta'^2 = 2 (ga/L)(cos th - cos th0) */
    lambda_exact = p->m * p->ga / p->L * (3.0 * cos(th) - 2.0 * cos(r->theta0));
  }
  r->err_lambda = fmax(r->err_lambda, fabs(y[IDAREF_LAMBDA] - lambda_exact));
}

static int record(double t, const double *y, void *ctx) {
  recorder *r = ctx;
  r->rows++;
  if (r->fail_at_row && (int)r->rows == r->fail_at_row) return -1;
  if (r->rows == 1) {
    r->t_first = t;
    r->lambda_first = y[IDAREF_LAMBDA];
  }
  r->t_last = t;
  r->max_h = fmax(r->max_h, fabs(idaref_h(r->p, y)));
  r->max_hdot = fmax(r->max_hdot, fabs(idaref_hdot(r->p, y)));
  record_energy(r, y);
  if (r->A != 0.0 || r->theta0 != 0.0) record_exact(r, t, y);
  return 0;
}

static idaref_options options(double rtol, double tf, double dt) {
  idaref_options o = {.rtol = rtol, .atol = rtol / 100.0, .tf = tf, .dt = dt, .max_steps = 100000};
  return o;
}

static void solve_ok(const idaref_model *p, idaref_form form, const double *x0,
                     const idaref_options *o, recorder *r, idaref_result *res) {
  int status = idaref_solve(p, form, x0, o, record, r, res);
  ck_assert_msg(status == IDAREF_OK, "%s failed with %s at t = %g: %s", res->function,
                res->flag_name, res->t_reached, res->message);
}

static const char *form_name(idaref_form form) { return form == IDAREF_GGL ? "ggl" : "index1"; }

/* ---- residual and iteration matrix ---------------------------------------------------------- */

/* dF/dy + cj dF/dy' against central differences of the residual at an arbitrary point. */
START_TEST(jacobian_matches_differences) {
  idaref_kind kind = _i / 2 ? IDAREF_PENDULUM : IDAREF_OSCILLATOR;
  idaref_form form = _i % 2 ? IDAREF_GGL : IDAREF_INDEX1;
  idaref_model p = idaref_model_default(kind);
  const double y[6] = {0.7, -0.9, 0.3, -0.4, 2.1, 0.05}, yp[6] = {0.1, 0.2, -0.3, 0.4, 0.5, 0.6};
  const double cj = 37.0, e = 1e-6;
  size_t n = idaref_dim(form);
  double J[36];
  p.d = 0.3, p.m = 1.7, p.L = 1.3;
  idaref_jacobian(&p, form, cj, y, J);
  for (size_t j = 0; j < n; j++) {
    double ya[6], yb[6], ypa[6], ypb[6], ra[6], rb[6];
    memcpy(ya, y, sizeof ya), memcpy(yb, y, sizeof yb);
    memcpy(ypa, yp, sizeof ypa), memcpy(ypb, yp, sizeof ypb);
    ya[j] += e, yb[j] -= e, ypa[j] += cj * e, ypb[j] -= cj * e;
    idaref_residual(&p, form, ya, ypa, ra);
    idaref_residual(&p, form, yb, ypb, rb);
    for (size_t i = 0; i < n; i++) {
      double fd = (ra[i] - rb[i]) / (2.0 * e);
      ck_assert_msg(fabs(fd - J[i * n + j]) <= 1e-7 * (1.0 + fabs(fd)),
                    "%s J[%zu][%zu] = %g, differences %g", form_name(form), i, j, J[i * n + j], fd);
    }
  }
}
END_TEST

/* The index-1 residual vanishes on the pendulum's exact motion (checks hdd and lambda). */
START_TEST(index1_residual_zero_on_exact_motion) {
  idaref_model p = idaref_model_default(IDAREF_PENDULUM);
  p.L = 1.4, p.m = 0.6;
  for (double t = 0.0; t < 3.0; t += 0.37) {
    double th, thd, r[5];
    pendulum_exact(&p, 0.9, t, &th, &thd);
    double thdd = -(p.ga / p.L) * sin(th);
    double lambda = p.m * p.ga / p.L * (3.0 * cos(th) - 2.0 * cos(0.9));
    const double y[5] = {p.L * sin(th), -p.L * cos(th), p.L * cos(th) * thd, p.L * sin(th) * thd,
                         lambda};
    const double yp[5] = {y[2], y[3], p.L * (cos(th) * thdd - sin(th) * thd * thd),
                          p.L * (sin(th) * thdd + cos(th) * thd * thd), 0.0};
    idaref_residual(&p, IDAREF_INDEX1, y, yp, r);
    for (int i = 0; i < 5; i++) ck_assert_msg(fabs(r[i]) < 1e-12, "t = %g: r[%d] = %g", t, i, r[i]);
  }
}
END_TEST

/* ---- IDA against the exact solutions ------------------------------------------------------- */

START_TEST(oscillator_matches_cn) {
  idaref_form form = _i ? IDAREF_GGL : IDAREF_INDEX1;
  idaref_model p = idaref_model_default(IDAREF_OSCILLATOR);
  const double A = 0.8, x0[4] = {A, 0.0, 0.0, 0.0};
  idaref_options o = options(1e-10, 10.0, 0.05);
  recorder r = {.p = &p, .A = A};
  idaref_result res;
  p.d = 0.0, p.m = 1.5;
  solve_ok(&p, form, x0, &o, &r, &res);
  printf("oscillator %-6s rtol 1e-10: max |X - A cn| %.2e, |Xdot - exact| %.2e, "
         "|lambda + m ga| %.2e; steps %ld, res %ld, jac %ld, etf %ld, ncf %ld\n",
         form_name(form), r.err_pos, r.err_vel, r.err_lambda, res.stats.steps, res.stats.res_evals,
         res.stats.jac_evals, res.stats.err_test_fails, res.stats.nonlin_conv_fails);
  ck_assert_double_eq(r.t_last, 10.0);
  ck_assert_double_le(r.err_pos, 1e-6);
  ck_assert_double_le(r.err_vel, 1e-6);
  ck_assert_double_le(r.err_lambda, 1e-8 * p.m * p.ga);
  ck_assert_double_le(fabs(r.lambda_first + p.m * p.ga), 1e-12 * p.m * p.ga); /* IDACalcIC */
}
END_TEST

START_TEST(pendulum_matches_sn) {
  idaref_form form = _i ? IDAREF_GGL : IDAREF_INDEX1;
  idaref_model p = idaref_model_default(IDAREF_PENDULUM);
  const double theta0 = 0.5;
  idaref_options o = options(1e-10, 10.0, 0.05);
  recorder r = {.p = &p, .theta0 = theta0};
  idaref_result res;
  p.L = 1.5, p.m = 2.0;
  const double x0[4] = {p.L * sin(theta0), -p.L * cos(theta0), 0.0, 0.0};
  solve_ok(&p, form, x0, &o, &r, &res);
  printf("pendulum   %-6s rtol 1e-10: max position error %.2e, velocity %.2e, lambda %.2e, "
         "|X^2+Y^2-L^2| %.2e; steps %ld, res %ld, jac %ld, etf %ld, ncf %ld\n",
         form_name(form), r.err_pos, r.err_vel, r.err_lambda, 2.0 * r.max_h, res.stats.steps,
         res.stats.res_evals, res.stats.jac_evals, res.stats.err_test_fails,
         res.stats.nonlin_conv_fails);
  ck_assert_double_eq(r.t_last, 10.0);
  ck_assert_double_le(r.err_pos, 1e-6);
  ck_assert_double_le(r.err_vel, 1e-6 * sqrt(p.ga * p.L));
  ck_assert_double_le(r.err_lambda, 1e-6 * p.m * p.ga / p.L);
  /* IDACalcIC: the tension at rest is m ga cos theta0, lambda = tension / L */
  ck_assert_double_le(fabs(r.lambda_first - p.m * p.ga * cos(theta0) / p.L), 1e-12 * p.m * p.ga);
  if (form == IDAREF_GGL) {
    /* h = 0 and hdot = 0 are equations of the GGL form */
    ck_assert_double_le(2.0 * r.max_h, 1e-8);
  } else {
    /* index 1 drifts off h = 0; with position errors e, |X^2 + Y^2 - L^2| <= 2 L e + e^2 */
    ck_assert_double_le(2.0 * r.max_h, 2.0 * p.L * 1e-6 + 1e-12);
  }
}
END_TEST

/* With d = 0 the energy E is conserved; what drifts is IDA's error. Each step commits a local
 * error of at most about rtol |y| (atol is rtol/100), and these add up at most linearly, so with
 * E quartic (|dE|/E <= 4 |dy|/|y|) the relative drift is below 4 rtol per step taken. The
 * drift must also follow the tolerance: at least 10 times smaller when rtol is 100 times. */
START_TEST(oscillator_energy_drift) {
  idaref_form form = _i ? IDAREF_GGL : IDAREF_INDEX1;
  idaref_model p = idaref_model_default(IDAREF_OSCILLATOR);
  const double x0[4] = {1.0, 0.0, 0.0, 0.0};
  double drift[3], rtol = 1e-6;
  p.d = 0.0;
  for (int i = 0; i < 3; i++, rtol *= 1e-2) {
    idaref_options o = options(rtol, 50.0, 0.1);
    recorder r = {.p = &p};
    idaref_result res;
    solve_ok(&p, form, x0, &o, &r, &res);
    drift[i] = r.max_dE / r.E0;
    printf("oscillator %-6s rtol %.0e: relative energy drift %.2e (%ld steps)\n", form_name(form),
           rtol, drift[i], res.stats.steps);
    ck_assert_double_eq_tol(r.E0, p.k / 4.0, 1e-15);
    ck_assert_double_le(drift[i], 4.0 * rtol * (double)res.stats.steps);
    if (i > 0) ck_assert_double_le(drift[i], drift[i - 1] / 10.0);
  }
}
END_TEST

/* With d > 0 the energy only decreases: dE/dt = -d Xdot^2 (up to the tolerance). */
START_TEST(damped_oscillator_dissipates) {
  idaref_form form = _i ? IDAREF_GGL : IDAREF_INDEX1;
  idaref_model p = idaref_model_default(IDAREF_OSCILLATOR);
  const double x0[4] = {1.0, 0.0, 0.0, 0.0};
  idaref_options o = options(1e-10, 20.0, 0.01);
  recorder r = {.p = &p};
  idaref_result res;
  p.d = 0.3;
  solve_ok(&p, form, x0, &o, &r, &res);
  ck_assert_double_le(r.max_rise, 1e-8 * r.E0);
  ck_assert_double_lt(r.E_prev, 0.5 * r.E0);
}
END_TEST

/* ---- consistent initial values --------------------------------------------------------------- */

START_TEST(projection_onto_manifold) {
  idaref_model pend = idaref_model_default(IDAREF_PENDULUM), osc;
  double x[4] = {2.0, 1.0, 0.3, 0.4}, origin[4] = {0.0, 0.0, 1.0, 2.0};
  double t[2] = {-1.0, 2.0}; /* tangent at the direction (2, 1) */
  pend.L = 1.5;
  ck_assert_int_eq(idaref_project(&pend, x), 0);
  ck_assert_double_le(fabs(idaref_h(&pend, x)), 1e-15);
  ck_assert_double_le(fabs(idaref_hdot(&pend, x)), 1e-15);
  /* radial projection of q; v keeps its tangential part (0.3 (-1) + 0.4 (2)) / 5 t */
  ck_assert_double_eq_tol(x[0], 1.5 * 2.0 / sqrt(5.0), 1e-15);
  ck_assert_double_eq_tol(x[1], 1.5 * 1.0 / sqrt(5.0), 1e-15);
  ck_assert_double_eq_tol(x[2], 0.1 * t[0], 1e-15);
  ck_assert_double_eq_tol(x[3], 0.1 * t[1], 1e-15);
  ck_assert_int_eq(idaref_project(&pend, origin), -1); /* G = q vanishes */
  ck_assert_double_eq(origin[2], 1.0);

  osc = idaref_model_default(IDAREF_OSCILLATOR);
  double y[4] = {0.1, 0.6, 0.2, -0.3};
  ck_assert_int_eq(idaref_project(&osc, y), 0);
  ck_assert_double_eq(y[0], 0.1);
  ck_assert_double_eq(y[1], 0.0);
  ck_assert_double_eq(y[2], 0.2);
  ck_assert_double_eq(y[3], 0.0);
}
END_TEST

/* ---- output times and failures ------------------------------------------------------------- */

START_TEST(output_times) {
  double t, k;
  /* tf a multiple of DT up to rounding: 0, 0.1, ..., 10 with the last one exactly tf */
  for (k = 0.0; idaref_output_time(10.0, 0.1, k, &t) == 0; k += 1.0)
    ;
  ck_assert_double_eq(k, 101.0);
  ck_assert_int_eq(idaref_output_time(10.0, 0.1, 100.0, &t), 0);
  ck_assert_double_eq(t, 10.0);
  ck_assert_int_eq(idaref_output_time(10.0, 0.1, 37.0, &t), 0);
  ck_assert_double_eq(t, 37.0 * 0.1);
  /* tf not a multiple: 0, 0.4, 0.8, 1 */
  ck_assert_int_eq(idaref_output_time(1.0, 0.4, 3.0, &t), 0);
  ck_assert_double_eq(t, 1.0);
  ck_assert_int_eq(idaref_output_time(1.0, 0.4, 4.0, &t), -1);
  /* DT beyond tf: 0 and tf; tf = 0: 0 alone */
  ck_assert_int_eq(idaref_output_time(1.0, 5.0, 1.0, &t), 0);
  ck_assert_double_eq(t, 1.0);
  ck_assert_int_eq(idaref_output_time(1.0, 5.0, 2.0, &t), -1);
  ck_assert_int_eq(idaref_output_time(0.0, 0.1, 0.0, &t), 0);
  ck_assert_double_eq(t, 0.0);
  ck_assert_int_eq(idaref_output_time(0.0, 0.1, 1.0, &t), -1);
}
END_TEST

START_TEST(rows_hit_output_times_exactly) {
  idaref_model p = idaref_model_default(IDAREF_PENDULUM);
  const double x0[4] = {sin(0.5), -cos(0.5), 0.0, 0.0};
  idaref_options o = options(1e-8, 1.05, 0.1);
  recorder r = {.p = &p};
  idaref_result res;
  solve_ok(&p, _i ? IDAREF_GGL : IDAREF_INDEX1, x0, &o, &r, &res);
  ck_assert_uint_eq(r.rows, 12);
  ck_assert_double_eq(r.t_first, 0.0);
  ck_assert_double_eq(r.t_last, 1.05);
}
END_TEST

START_TEST(too_much_work_is_reported) {
  idaref_model p = idaref_model_default(IDAREF_PENDULUM);
  const double x0[4] = {sin(0.5), -cos(0.5), 0.0, 0.0};
  idaref_options o = options(1e-10, 10.0, 1.0);
  recorder r = {.p = &p};
  idaref_result res;
  o.max_steps = 5;
  ck_assert_int_eq(idaref_solve(&p, IDAREF_GGL, x0, &o, record, &r, &res), IDAREF_IDA_FAILED);
  ck_assert_int_eq(res.ida_flag, IDA_TOO_MUCH_WORK);
  ck_assert_str_eq(res.flag_name, "IDA_TOO_MUCH_WORK");
  ck_assert_str_eq(res.function, "IDASolve");
  ck_assert_uint_eq(r.rows, 1); /* the t = 0 row only */
  ck_assert_double_gt(res.t_reached, 0.0);
  ck_assert_double_lt(res.t_reached, 1.0);
  ck_assert_int_eq(res.stats.steps, 5);
  ck_assert_int_gt(strlen(res.message), 0);
  ck_assert_ptr_null(strchr(res.message, '\n'));
}
END_TEST

START_TEST(output_failure_stops_the_run) {
  idaref_model p = idaref_model_default(IDAREF_OSCILLATOR);
  const double x0[4] = {0.5, 0.0, 0.0, 0.0};
  idaref_options o = options(1e-8, 5.0, 1.0);
  recorder r = {.p = &p, .fail_at_row = 3};
  idaref_result res;
  ck_assert_int_eq(idaref_solve(&p, IDAREF_INDEX1, x0, &o, record, &r, &res), IDAREF_OUTPUT_FAILED);
  ck_assert_uint_eq(r.rows, 3);
  ck_assert_double_eq(res.t_reached, 2.0);
}
END_TEST

static Suite *ida_suite(void) {
  Suite *s = suite_create("ida");
  TCase *model = tcase_create("model");
  TCase *exact = tcase_create("exact");
  TCase *driver = tcase_create("driver");
  tcase_add_loop_test(model, jacobian_matches_differences, 0, 4);
  tcase_add_test(model, index1_residual_zero_on_exact_motion);
  tcase_add_test(model, projection_onto_manifold);
  tcase_set_timeout(exact, 60);
  tcase_add_loop_test(exact, oscillator_matches_cn, 0, 2);
  tcase_add_loop_test(exact, pendulum_matches_sn, 0, 2);
  tcase_add_loop_test(exact, oscillator_energy_drift, 0, 2);
  tcase_add_loop_test(exact, damped_oscillator_dissipates, 0, 2);
  tcase_add_test(driver, output_times);
  tcase_add_loop_test(driver, rows_hit_output_times_exactly, 0, 2);
  tcase_add_test(driver, too_much_work_is_reported);
  tcase_add_test(driver, output_failure_stops_the_run);
  suite_add_tcase(s, model);
  suite_add_tcase(s, exact);
  suite_add_tcase(s, driver);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(ida_suite());
  int failed;
  gsl_set_error_handler_off(); /* GSL statuses are asserted instead of aborting */
  srunner_run_all(sr, CK_NORMAL);
  failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
