/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae: fixed-step integration of constrained mechanical systems without constraint drift.
 * The umbrella (layer: umbrella): includes every public header, each the face of one layer of
 * the library, bottom first; it declares nothing of its own.
 *
 * Implements Di Franco, Scarciotti, Astolfi, "Discretization schemes for constraint
 * stabilization in nonlinear differential-algebraic systems". A DAE xdot = f + g lambda,
 * 0 = h (eq. 1) written in coordinates (xi, mu) (eq. 2-3) is replaced by the stabilized
 * system (eq. 5)
 *
 *     xi_i' = k_i xi_i,   k_i = -(delta^2/2) ||q_i(xi, mu)||^2 - epsilon        (eq. 6)
 *     mu'   = q0(mu) + Q(xi, mu) xi,  Q = [q_1 ... q_p]
 *
 * and discretized with a fixed step T by scheme 11 (explicit) or scheme 15 (semi-implicit),
 * with a map phi_T(mu, mu+) -> q0 (eq. 13) for the constrained motion.
 *
 * Conventions: every call returns an sdae_status (0 success, negative error, positive
 * information); matrices are row-major flat arrays; callbacks return 0 on success, > 0 for a
 * recoverable failure and < 0 for a fatal one. The library keeps no global state, never
 * prints, never aborts, and sdae_step never allocates.
 */
#ifndef STABDAE_STABDAE_H
#define STABDAE_STABDAE_H

#include <stabdae/base.h>    /* core: statuses, version, allocator */
#include <stabdae/certify.h> /* analysis: step-size certificates, condition (18) */
#include <stabdae/check.h>   /* analysis: the model and mechanism checks */
#include <stabdae/dae.h>     /* dae: the generic front-end */
#include <stabdae/maps.h>    /* maps: phi_T */
#include <stabdae/mbs.h>     /* mbs: the mechanical front-end */
#include <stabdae/model.h>   /* model: the normal form as callbacks */
#include <stabdae/pattern.h> /* core: sparsity patterns */
#include <stabdae/stepper.h> /* stepper: options, a step, a run */

#endif /* STABDAE_STABDAE_H */
