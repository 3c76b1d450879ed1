/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae model check: is a normal form typed by hand (q0, Q) consistent with the original DAE
 * xdot = f(x) + g(x) lambda, 0 = h(x) and its coordinates z = Phi(x) = (xi, mu)? */
#ifndef STABDAE_CHECK_H
#define STABDAE_CHECK_H

#include <stddef.h>

#include <stabdae/alloc.h>
#include <stabdae/dae.h>
#include <stabdae/export.h>
#include <stabdae/model.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sdae_check_kind {
  SDAE_CHECK_INVERSE = 0, /* Phi(Phi^-1(z)) = z */
  SDAE_CHECK_LG = 1,      /* L_g phi_j = 0 for mu and all but the last of each xi chain */
  SDAE_CHECK_CHAIN = 2,   /* L_f xi_j = xi_{j+1} along each chain */
  SDAE_CHECK_DYNAMICS = 3 /* q0(mu) + Q(xi, mu) xi = L_f mu(Phi^-1(xi, mu)) */
} sdae_check_kind;

typedef struct sdae_check_report {
  size_t points;      /* points checked */
  double residual[4]; /* the worst residual of each check, relative to its terms' size */
  int worst_check;    /* the check with the largest residual */
  size_t worst_index; /* the component of z where it was found */
  int consistent;     /* every residual <= tol */
} sdae_check_report;

/* At npoints random points of the box lo <= z <= hi (seeded, reproducible) checks the model
 * against the DAE. Jacobians of Phi by central differences unless Phi_jac is given; Phi^-1 by
 * Newton from x = z unless Phi_inv is given. The relative degrees come from the model's
 * rel_degree (one chain of n_xi when it has none; SDAE_ERR_REL_DEGREE when they are not
 * n_constraints values >= 1 summing to n_xi). worst_z (n values, or NULL) receives the
 * point where the largest residual was found; *r is written whole. */
SDAE_API int sdae_check_model(const sdae_model *model, const sdae_dae *dae, double t,
                              const double *lo, const double *hi, size_t npoints,
                              unsigned long seed, double tol, double *worst_z,
                              sdae_check_report *r);

/* sdae_check_model with its workspace (one block, given back before the call returns) from the
 * allocator a; NULL means malloc and free. SDAE_ERR_NOMEM when there is no room, and then *r is
 * untouched. */
SDAE_API int sdae_check_model_with(const sdae_model *model, const sdae_dae *dae, double t,
                                   const double *lo, const double *hi, size_t npoints,
                                   unsigned long seed, double tol, double *worst_z,
                                   const sdae_allocator *a, sdae_check_report *r);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_CHECK_H */
