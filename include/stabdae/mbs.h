/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae mechanical front-end (layer: mbs): a mechanism in the multibody convention
 *
 *     q' = v,   M(t, q) v' = F(t, q, v) - G(t, q)^T lambda,   c(t, q) = 0,   G = dc/dq
 *
 * integrated by the paper's stabilized schemes without the user deriving anything. Behind it:
 * xi = per constraint (c_j, G_j v + dc_j/dt); a chart splits q into dependent q_D (n_c) and
 * independent q_I by a pivoted factorization of G, with W = dq/dq_I spanning ker G; the
 * coordinates mu = (q_I, W^T M v); q0 and Q by the rule of <stabdae/dae.h>. The chart switches
 * between steps to the best one when that is better by SDAE_MBS_CHART_FACTOR. The check of the
 * derivatives a mechanism gives, sdae_mbs_check, is with the other checks in <stabdae/check.h>. */
#ifndef STABDAE_MBS_H
#define STABDAE_MBS_H

#include <stddef.h>

#include <stabdae/base.h>
#include <stabdae/pattern.h>
#include <stabdae/stepper.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Every callback returns 0 on success, > 0 for a recoverable failure and < 0 for a fatal one,
 * and receives params. Matrices are row-major, or their nonzeros in pattern order where the
 * mechanism gives a pattern (mass_pattern, jacobian_pattern). */
typedef struct sdae_mbs {
  size_t n_q, n_c; /* coordinates q, constraints c(t, q) = 0; 1 <= n_c < n_q (or see rank) */
  /* n_q x n_q, symmetric; the reduced mass W^T M W (M on the constraints' tangent space, W
   * spanning ker G) positive definite: M itself may be singular (massless points). Checked
   * at every state a step starts from or hands out, and in sdae_mbs_lambda and sdae_mbs_energy
   * (SDAE_ERR_MASS); the reduced mass wherever it is formed. */
  int (*mass)(double t, const double *q, double *M, void *params);
  int (*force)(double t, const double *q, const double *v, double *F, void *params); /* n_q */
  int (*constraint)(double t, const double *q, double *c, void *params);             /* n_c */
  /* optional: dc/dq, n_c x n_q; NULL: fourth-order central differences of c. Without it the
   * mu-dynamics difference those differences again (dG/dt), good to about 1e-10 only: an
   * implicit map's Newton then stops at SDAE_MBS_FD_NEWTON_TOL if newton_tol is smaller */
  int (*jacobian)(double t, const double *q, double *G, void *params);
  /* optional: dc/dt, n_c; NULL: a fourth-order central difference in t (exactly 0 when c does
   * not depend on t, but four evaluations of c at every configuration a step solves for: a
   * mechanism whose c does not depend on t saves them by writing zeros, as the generator does) */
  int (*constraint_t)(double t, const double *q, double *ct, void *params);
  /* optional: F is the force of the Lagrangian v^T M v / 2 - V(q) (minus damping(q) v when
   * given); enables sdae_map_dgrad/dg4/dg6, which then conserve (dissipate) v^T M v / 2 + V.
   * V, D and M must not depend on t, nor c (SDAE_ERR_MAP at a step where dc/dt != 0). */
  int (*potential)(double t, const double *q, double *V, void *params); /* 1 value */
  int (*damping)(double t, const double *q, double *D, void *params);   /* n_q x n_q, PSD */
  void *params;
  /* optional, all three: the derivatives along the motion, at s = 0; each one given replaces a
   * fourth-order difference stencil in every evaluation of the mu-dynamics and of lambda
   * (NULL keeps the stencil): with all of them, jacobian and constraint_t, no difference runs.
   * jacobian_dot without jacobian, or constraint_t_dot without constraint_t, is SDAE_ERR_NULL.
   * sdae_mbs_check compares them with differences. */
  /* n_q values: (d/ds M(t + s, q + s v)) v */
  int (*mass_dot_v)(double t, const double *q, const double *v, double *out, void *params);
  /* n_c x n_q, row-major: d/ds G(t + s, q + s v); with it, jacobian is needed too */
  int (*jacobian_dot)(double t, const double *q, const double *v, double *Gdot, void *params);
  /* n_c values: d/ds (dc/dt)(t + s, q + s v); used with constraint_t */
  int (*constraint_t_dot)(double t, const double *q, const double *v, double *out, void *params);
  /* optional: forces from outside the Lagrangian (actuators, control inputs, contact models),
   * n_q values added to F wherever F is read (the mu-dynamics, lambda). With a potential the
   * discrete gradients treat them as a port and keep, on the manifold, the discrete power
   * balance H(x+) - H(x) = -T gradbar^T R gradbar + T gradbar^T B u_mid (docs/front-ends.md);
   * every other map just sees F plus them. */
  int (*input_force)(double t, const double *q, const double *v, double *F, void *params);
  /* optional sparsity (<stabdae/pattern.h>), copied when the stepper is built and checked there
   * (SDAE_ERR_PATTERN). With both patterns, jacobian_dot and mass_dot_v, every map of the
   * library steps the mechanism at the cost of its nonzeros (the block and a step grow with
   * them, not with n_q^2; the implicit maps' Newton by GMRES on the saddle-point factors, no
   * n_mu x n_mu matrix; a pattern whose factors cannot fit is refused when the stepper is built
   * with SDAE_ERR_PATTERN); a mechanism without them, or without those derivatives, is stepped
   * as a dense one (docs/front-ends.md).
   * NULL: dense. n_q rows, both triangles, symmetric; with it mass() and damping() write nnz
   * values in pattern order */
  const sdae_pattern *mass_pattern;
  /* NULL: dense. n_c rows; with it jacobian() and jacobian_dot() write nnz values in pattern
   * order (jacobian is then needed: SDAE_ERR_NULL without it) */
  const sdae_pattern *jacobian_pattern;
  /* optional: the constraints' rank on the motion where some of them are redundant (dependent
   * on the others, as a planar loop written with spatial joints: sdae_mbs_redundant counts it at
   * a state); 0: n_c, all independent. With 1 <= rank < n_c (and rank < n_q; n_c >= n_q is then
   * allowed) every step's start chooses rank independent constraints, by QR with column
   * pivoting of G^T with its rows scaled, and keeps them while no other choice is more
   * independent by SDAE_MBS_CHART_FACTOR; xi is formed on those (2 rank values), the chart
   * splits q into rank dependent coordinates and n_q - rank, and the other constraints, implied
   * by the chosen ones near the manifold, hold as they do. A step whose chosen constraints are
   * not independent (below SDAE_MBS_CHART_MIN) or whose others are not dependent on them (above
   * it) is SDAE_ERR_RANK: the rank is not the one given there. Stepped on the dense back-end,
   * patterns or not. */
  size_t rank;
} sdae_mbs;

/* A chart is replaced by the best one at a step boundary only when that one's measure
 * max |dq_D/dq_I| = max |G_D^-1 G_I| is smaller by this factor (hysteresis). The best one's
 * measure is at most about 1 (some n_c columns of G have the largest |det|). */
#define SDAE_MBS_CHART_FACTOR 1.5
/* No usable chart (SDAE_ERR_CHART): the constraints' gradients are nearly dependent, the sine
 * of the smallest angle between one of them and the span of the others below this. */
#define SDAE_MBS_CHART_MIN 1e-8
/* Singular configurations (where rank G drops for an instant along the motion, as a
 * parallelogram's flat position): a step whose start finds the constraints' independence (their
 * least sine: the dense chart's pivoted QR, the sparse back-end's least singular value of its
 * velocity system's constraint block) below this fraction of the largest found at any step's
 * start, or falling toward that within the step as it fell over the last step, is a projection
 * step (docs/front-ends.md): rk8 in (q, v) with the acceleration from the saddle-point system,
 * its nearly dependent rows set aside, then q and v projected M-orthogonally onto the
 * constraints. Not the first step (there, as before, dependent constraints are SDAE_ERR_RANK
 * and nearly dependent ones stepped in their chart or SDAE_ERR_CHART), not with redundant rows
 * declared (rank); a mechanism whose constraints are nearly dependent all along (a long chain,
 * two nearly tangent surfaces) stays in its chart. A projection step that moves q off the
 * constraints by more than SDAE_MBS_PROJECT_DRIFT of the step's own motion cannot be taken
 * accurately: SDAE_ERR_CHART. */
#define SDAE_MBS_SINGULAR_NEAR 5e-2
#define SDAE_MBS_PROJECT_DRIFT 1e-3

/* Newton's least tolerance in the front-end: its mu-dynamics come from fourth-order
 * differences, good to about 1e-13 (1e-10 without jacobian, see there), and an implicit map's
 * Newton cannot settle below that noise. A smaller newton_tol is raised to these. With
 * jacobian_dot and mass_dot_v given the mu-dynamics are exact to rounding, yet the floor stays:
 * at 1e-14 the discrete gradient's Newton failed to converge (the four-bar at T = 1e-3,
 * Andrews' mechanism), its difference quotient dividing the rounding of H by the step's
 * increment, and 1e-13 only added iterations, the energy kept as well at 1e-12. */
#define SDAE_MBS_NEWTON_TOL 1e-12
#define SDAE_MBS_FD_NEWTON_TOL 1e-9

typedef struct sdae_mbs_stepper sdae_mbs_stepper;

/* The work of the steps taken (a step retried in the best chart counts its retry alone; a
 * failed step counts nothing). sdae_mbs_stepper_reset_stats zeroes the counters, not the
 * current chart's measure. */
typedef struct sdae_mbs_stats {
  sdae_stats step;               /* the normal form's stepper: steps, Newton, phi evaluations */
  unsigned long chart_switches;  /* charts replaced at step boundaries (the first one is not) */
  unsigned long phi_inv_iters;   /* Newton iterations of Phi^-1 (q_D from c(t, q) = xi) */
  double chart_measure;          /* max |G_D^-1 G_I| of the current chart where it was chosen */
  unsigned long row_switches;    /* with redundant constraints (rank < n_c): the rows chosen
                                  * replaced at step boundaries (the first choice is not) */
  unsigned long projected_steps; /* steps taken by projection near a singular configuration
                                  * (SDAE_MBS_SINGULAR_NEAR), not by the normal form's stepper */
} sdae_mbs_stats;

/* Bytes sdae_mbs_stepper_init needs; 0 when the mechanism or the options are invalid, or when
 * there is no memory for the analysis below. A mechanism stepped on the sparse back-end (both
 * patterns, jacobian_dot and mass_dot_v, and an explicit map or one whose slope is known:
 * docs/front-ends.md) has its saddle-point system analysed to size its factors, in memory of
 * its own given back before the call returns: from malloc here, from the allocator a in
 * _size_with (NULL: malloc), from it too in _alloc_with, in the caller's block in _init. */
SDAE_API size_t sdae_mbs_stepper_size(const sdae_mbs *sys, const sdae_options *o);
SDAE_API size_t sdae_mbs_stepper_size_with(const sdae_mbs *sys, const sdae_options *o,
                                           const sdae_allocator *a);
/* Builds the stepper in the caller's block (no malloc); sys and o are copied. On failure *s is
 * left as it was, but the block's bytes may not be (the analysis runs there, and the build).
 * SDAE_ERR_MAP for a discrete-gradient map without potential. */
SDAE_API int sdae_mbs_stepper_init(sdae_mbs_stepper **s, void *mem, size_t len, const sdae_mbs *sys,
                                   const sdae_options *o);
SDAE_API int sdae_mbs_stepper_alloc(sdae_mbs_stepper **s, const sdae_mbs *sys,
                                    const sdae_options *o);
/* As sdae_mbs_stepper_alloc, the block from the allocator a (NULL: malloc). */
SDAE_API int sdae_mbs_stepper_alloc_with(sdae_mbs_stepper **s, const sdae_mbs *sys,
                                         const sdae_options *o, const sdae_allocator *a);
/* as sdae_stepper_free: NULL and init'ed ones are fine */
SDAE_API void sdae_mbs_stepper_free(sdae_mbs_stepper *s);

/* One step from (t, q, v) in the current chart (chosen anew at the boundary); q, v updated in
 * place, untouched on error (and the chart as it was). A start off c = 0 needs no assembly:
 * the scheme brings it onto the constraints, as long as Phi^-1 exists there; each coordinate
 * of xi decays at least as 1 / (1 + T epsilon) per step (scheme 15), so the velocity level
 * G v + dc/dt, whose gain is often near -epsilon, may take a while: a larger epsilon assembles
 * faster. SDAE_ERR_PHI_INV when the step leaves the chart's domain (q_I past a fold of the
 * chart) even after one retry in the best chart: a smaller T helps, the state being kept. */
SDAE_API int sdae_mbs_step(sdae_mbs_stepper *s, double t, double T, double *q, double *v);

/* A stepper's state as bytes (after MuJoCo's mj_getState/mj_setState): everything the next step
 * depends on besides the caller's (t, q, v), that is the chart, what is kept of the last step
 * (factors, the point Phi^-1 left) and the counters, without pointers, with a version, the
 * build's identity and a checksum. A state set into a stepper of the same mechanism and options
 * (in this process or another) continues bit for bit. sdae_mbs_state_size: its bytes (0 for a
 * NULL stepper). sdae_mbs_get_state: SDAE_ERR_BUFFER when len is smaller. sdae_mbs_set_state:
 * SDAE_ERR_STATE_DAMAGED (wrong length, checksum), SDAE_ERR_STATE_FOREIGN (another mechanism's
 * sizes, map, options or build), the stepper untouched on refusal. What the bytes cannot tell:
 * the stepper set must integrate the same mechanism, its params included (only the sizes, the
 * optional callbacks given and the options are checked); the caller keeps (t, q, v) and steps on
 * from exactly the q, v the last step returned, at its t; len is sdae_mbs_state_size(s), fixed
 * for a stepper; get and set are calls between steps, never from inside a callback. */
SDAE_API size_t sdae_mbs_state_size(const sdae_mbs_stepper *s);
SDAE_API int sdae_mbs_get_state(const sdae_mbs_stepper *s, void *buf, size_t len);
SDAE_API int sdae_mbs_set_state(sdae_mbs_stepper *s, const void *buf, size_t len);

/* Between steps: the constraint forces lambda (n_c) at a state, from M v' = F - G^T lambda and G v'
 * + gamma = 0, gamma the derivative of G v + dc/dt along (1, v) with v fixed: solved on the null
 * space of G (G^T = Q R), so it needs of M what a step needs (a singular M with a positive definite
 * reduced mass too). F includes input_force. With redundant constraints (rank < n_c) the
 * multipliers are not unique, the constraint force G^T lambda is: the rows chosen at the state
 * give theirs, and every row's are the least-norm ones with that force (the pseudo-inverse's,
 * lambda = C (C^T C)^-1 lambda_chosen, C each row's coefficients on the chosen ones). */
SDAE_API int sdae_mbs_lambda(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                             double *lambda);
/* The constraint coordinates xi (2 n_c: c_j and G_j v + dc_j/dt, constraint by constraint,
 * redundant ones included), the same in every chart. */
SDAE_API int sdae_mbs_xi(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                         double *xi);
/* The energy v^T M v / 2 + V(q) (V = 0 without potential). */
SDAE_API int sdae_mbs_energy(sdae_mbs_stepper *s, double t, const double *q, const double *v,
                             double *E);
/* The dependent coordinates of the current chart: n_c indices into q (rank with redundant
 * constraints), ascending (none before the first step: SDAE_ERR_CHART). */
SDAE_API int sdae_mbs_chart(const sdae_mbs_stepper *s, size_t *dependent);

SDAE_API const sdae_mbs_stats *sdae_mbs_stepper_stats(const sdae_mbs_stepper *s);
SDAE_API void sdae_mbs_stepper_reset_stats(sdae_mbs_stepper *s);

/* Called with the state after step `step` (0: the initial one); non-zero stops the run. */
typedef int (*sdae_mbs_observer)(size_t step, double t, const double *q, const double *v,
                                 void *data);
/* nsteps fixed steps of size T from t0, as sdae_integrate: the observer (may be NULL) sees step
 * 0, every `every`-th step and the last; on failure q, v hold the state after the last good
 * step and *steps_done (may be NULL) says how many were taken; SDAE_STOPPED when the observer
 * stopped the run. */
SDAE_API int sdae_mbs_integrate(sdae_mbs_stepper *s, double t0, double T, size_t nsteps,
                                size_t every, double *q, double *v, sdae_mbs_observer obs,
                                void *data, size_t *steps_done);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_MBS_H */
