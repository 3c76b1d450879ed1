/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Index-reduced forms of the oscillator and the planar pendulum (notes: models.md) written as
 * residuals F(y, y') = 0 for SUNDIALS IDA.
 *
 * Both models are one point mass with position q = (X, Y), velocity v = (Xdot, Ydot), an applied
 * force f(q, v), one constraint h(q) = 0 and the multiplier lambda acting through G = dh/dq:
 *     q' = v,   m v' = f(q, v) - G(q)^T lambda,   0 = h(q).
 * Oscillator: f = (-k X^3 - d Xdot, -m ga), h = Y.
 * Pendulum:   f = (0, -m ga),               h = (X^2 + Y^2 - L^2) / 2.
 * (This gives Ydd = -ga - lambda/m and Xdd = -lambda X/m, Ydd = -ga - lambda Y/m as in the
 * shared model definitions.) Both constraints are at most quadratic, so the Hessian of h is a
 * constant matrix; the Jacobians below rely on that.
 *
 * Forms (y is what IDA integrates):
 *   index1: y = (X, Y, Xdot, Ydot, lambda); the constraint replaced by its second derivative
 *           hdd = G q'' + v^T Hess(h) v = 0, with q'' taken from the dynamics (lambda algebraic).
 *   ggl:    y = (X, Y, Xdot, Ydot, lambda, nu); Gear-Gupta-Leimkuhler: q' = v - G^T nu, with both
 *           h = 0 and hdot = G v = 0 imposed (index 2; lambda and nu algebraic, nu = 0 exactly).
 */
#ifndef STABDAE_TOOLS_IDA_MODELS_H
#define STABDAE_TOOLS_IDA_MODELS_H

#include <stddef.h>

typedef enum idaref_kind { IDAREF_OSCILLATOR, IDAREF_PENDULUM } idaref_kind;
typedef enum idaref_form { IDAREF_INDEX1, IDAREF_GGL } idaref_form;

/* Largest size of y over both forms. */
enum { IDAREF_MAX_DIM = 6 };

/* Positions of the components of y. */
enum { IDAREF_X, IDAREF_Y, IDAREF_XDOT, IDAREF_YDOT, IDAREF_LAMBDA, IDAREF_NU };

typedef struct idaref_model {
  idaref_kind kind;
  double k, d;  /* oscillator: cubic spring and damping */
  double L;     /* pendulum: length */
  double m, ga; /* both: mass and gravity */
} idaref_model;

/* The models' defaults of models.md. */
idaref_model idaref_model_default(idaref_kind kind);

/* Number of components of y in the given form (5 or 6). */
size_t idaref_dim(idaref_form form);

/* IDA's id vector: 1 for a differential component, 0 for an algebraic one. */
void idaref_id(idaref_form form, double *id);

/* Residual F(y, y') of the form. */
void idaref_residual(const idaref_model *p, idaref_form form, const double *y, const double *yp,
                     double *r);

/* Iteration matrix dF/dy + cj dF/dy' (n x n, row-major). F is linear in y' with constant
 * coefficients, so y' is not needed. */
void idaref_jacobian(const idaref_model *p, idaref_form form, double cj, const double *y,
                     double *J);

/* Constraint h and its time derivative hdot = G v at the state x = (X, Y, Xdot, Ydot). */
double idaref_h(const idaref_model *p, const double *x);
double idaref_hdot(const idaref_model *p, const double *x);

/* Total energy E = m |v|^2 / 2 + (k X^4 / 4 for the oscillator) + m ga Y. */
double idaref_energy(const idaref_model *p, const double *x);

/* Orthogonal projection of x onto the manifold h = 0, hdot = 0: q by Gauss-Newton steps
 * q <- q - G^T h / |G|^2, then v <- v - G^T (G v) / |G|^2. Returns 0, or -1 (x untouched) when
 * G vanishes (the pendulum's origin) or the iteration does not converge. */
int idaref_project(const idaref_model *p, double *x);

/* Starting values for IDACalcIC: y = (x, lambda = 0[, nu = 0]) and y' = (v, f/m[, 0]), i.e. the
 * differential components of y' computed without the constraint force. */
void idaref_initial_guess(const idaref_model *p, idaref_form form, const double *x, double *y,
                          double *yp);

#endif
