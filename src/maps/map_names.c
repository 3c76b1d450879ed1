/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The maps the library provides, by name. */
#include <string.h>

#include "map.h"

const char *sdae_map_name(const sdae_map_type *map) { return map ? map->name : "(none)"; }

unsigned sdae_map_order(const sdae_map_type *map) { return map ? map->order : 0; }

const sdae_map_type *sdae_map_by_name(const char *name) {
  const sdae_map_type *const *maps[] = {
      &sdae_map_euler, &sdae_map_midpoint,  &sdae_map_dgrad,     &sdae_map_user, &sdae_map_dg4,
      &sdae_map_dg6,   &sdae_map_midpoint4, &sdae_map_midpoint6, &sdae_map_rk4,  &sdae_map_rk8};
  if (!name) return NULL;
  for (size_t i = 0; i < sizeof maps / sizeof *maps; i++)
    if (strcmp((*maps[i])->name, name) == 0) return *maps[i];
  return NULL;
}
