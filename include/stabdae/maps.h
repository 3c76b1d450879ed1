/* SPDX-License-Identifier: GPL-3.0-or-later */
/* stabdae's maps (layer: maps): the maps phi_T(mu, mu+) for the constrained motion, by value
 * and by name, and the order each declares. */
#ifndef STABDAE_MAPS_H
#define STABDAE_MAPS_H

#include <stabdae/base.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A map phi_T(mu, mu+) for the constrained motion: a static table of functions (src/maps/map.h),
 * one file per map. Each needs of the model what its comment says. */
typedef struct sdae_map_type sdae_map_type;

SDAE_API extern const sdae_map_type *const sdae_map_euler;    /* "euler": q0(mu), explicit */
SDAE_API extern const sdae_map_type *const sdae_map_midpoint; /* "midpoint": q0((mu + mu+)/2) */
/* "dgrad": S(mid) gradbar H, Gonzalez's discrete gradient (H, grad_H, S or S_apply) */
SDAE_API extern const sdae_map_type *const sdae_map_dgrad;
SDAE_API extern const sdae_map_type *const sdae_map_user; /* "user": the model's user_phi */
/* dgrad composed symmetrically, H conserved for skew S (dgrad's callbacks): "dg4" by Yoshida's
 * triple jump (order 4, 3 stages), "dg6" by Kahan and Li's s9odr6a (order 6, 9 stages) */
SDAE_API extern const sdae_map_type *const sdae_map_dg4;
SDAE_API extern const sdae_map_type *const sdae_map_dg6;
/* midpoint composed the same ways, for any forces and time-dependent models (q0 only):
 * "midpoint4" (order 4, 3 stages) and "midpoint6" (order 6, 9 stages) */
SDAE_API extern const sdae_map_type *const sdae_map_midpoint4;
SDAE_API extern const sdae_map_type *const sdae_map_midpoint6;
/* "rk4": the classical Runge-Kutta method on mu' = q0(t, mu), explicit, order 4 (q0 only) */
SDAE_API extern const sdae_map_type *const sdae_map_rk4;
/* "rk8": DOP853's eighth-order Runge-Kutta solution, explicit, order 8, 12 stages (q0 only) */
SDAE_API extern const sdae_map_type *const sdae_map_rk8;

/* The map's name ("(none)" for NULL), and the map of a name (NULL when there is none). */
SDAE_API const char *sdae_map_name(const sdae_map_type *map);
SDAE_API const sdae_map_type *sdae_map_by_name(const char *name);
/* The map's order of accuracy as T -> 0 (0 for sdae_map_user: the user's map decides). */
SDAE_API unsigned sdae_map_order(const sdae_map_type *map);

#ifdef __cplusplus
}
#endif

#endif /* STABDAE_MAPS_H */
