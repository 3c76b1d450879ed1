/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "fmu_state.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define FMU_STATE_MAGIC 0x73646165666d7531ULL /* "sdaefmu1" */

/* the block: this header, the variables (count doubles), the stepper's bytes (block_len) */
struct fmu_state {
  uint64_t magic;
  uint64_t checksum; /* of the whole block with this field 0: a damaged state is refused */
  size_t bytes;      /* the whole block */
  char token[40];
  fmu_clock clock;
  char map[24]; /* the map by name: the pointer in clock is this process's */
  size_t count;
  /* where the stepper's bytes came from: their place in memory and this binary */
  uintptr_t instance, block, binary;
  size_t block_len, stepper_at; /* stepper_at: the stepper's offset in its block */
  int have_stepper;
};

static size_t header_bytes(void) {
  /* the variables after the header, aligned for doubles */
  return (sizeof(struct fmu_state) + sizeof(double) - 1) / sizeof(double) * sizeof(double);
}

static double *values_of(const fmu_state *s) {
  return (double *)(void *)((unsigned char *)s + header_bytes());
}

static unsigned char *stepper_bytes(const fmu_state *s) {
  return (unsigned char *)values_of(s) + s->count * sizeof(double);
}

/* an address in this binary's data: another load of it (another process) has another one */
static const char here;
static uintptr_t binary_address(void) { return (uintptr_t)(const void *)&here; }

/* FNV-1a over the block, its checksum field taken as 0 */
static uint64_t checksum_of(const fmu_state *s) {
  const unsigned char *p = (const unsigned char *)s;
  size_t skip = offsetof(struct fmu_state, checksum);
  uint64_t h = 0xcbf29ce484222325ULL;
  for (size_t i = 0; i < s->bytes; i++) {
    unsigned char byte = i >= skip && i < skip + sizeof s->checksum ? 0 : p[i];
    h = (h ^ byte) * 0x100000001b3ULL;
  }
  return h;
}

static size_t bytes_for(const fmu_instance *fi) {
  size_t step = fi->stepper ? fi->block_len : 0;
  return header_bytes() + fi->layout.count * sizeof(double) + step;
}

static fmu_state *state_alloc(fmu_instance *fi, size_t bytes, const char *call) {
  fmu_state *s = fmu_mem_get(&fi->alloc, bytes);
  if (!s) fmu_log(fi, FMU_ERROR, "%s: out of memory", call);
  return s;
}

void fmu_state_free(fmu_instance *fi, fmu_state *state) {
  if (state) fmu_mem_put(&fi->alloc, state, state->bytes);
}

fmu_status fmu_state_get(fmu_instance *fi, fmu_state **state) {
  size_t bytes = bytes_for(fi);
  fmu_state *s = *state;
  if (s && s->bytes != bytes) { /* another size: a new block */
    fmu_state_free(fi, s);
    *state = s = NULL;
  }
  if (!s && !(s = state_alloc(fi, bytes, "getFMUState"))) return FMU_ERROR;
  s->magic = FMU_STATE_MAGIC;
  s->bytes = bytes;
  memcpy(s->token, fi->token, sizeof s->token);
  s->clock = fi->clock;
  snprintf(s->map, sizeof s->map, "%s", sdae_map_name(fi->clock.map));
  s->count = fi->layout.count;
  s->instance = (uintptr_t)(void *)fi;
  s->block = (uintptr_t)fi->block;
  s->binary = binary_address();
  s->block_len = fi->block_len;
  s->have_stepper = fi->stepper != NULL;
  s->stepper_at =
      fi->stepper ? (size_t)((unsigned char *)fi->stepper - (unsigned char *)fi->block) : 0;
  memcpy(values_of(s), fi->values, s->count * sizeof(double));
  if (s->have_stepper) memcpy(stepper_bytes(s), fi->block, fi->block_len);
  s->checksum = checksum_of(s);
  *state = s;
  return FMU_OK;
}

/* the header's sizes and clock, before anything else is read */
static int header_whole(const fmu_instance *fi, const fmu_state *s, size_t len) {
  const fmu_clock *c = &s->clock;
  return s->magic == FMU_STATE_MAGIC && s->bytes == len && s->count == fi->layout.count &&
         strncmp(s->token, fi->token, sizeof s->token) == 0 &&
         (s->have_stepper == 0 || s->have_stepper == 1) &&
         (!s->have_stepper || (s->block_len == fi->block_len && s->stepper_at < s->block_len)) &&
         len == header_bytes() + s->count * sizeof(double) + (s->have_stepper ? s->block_len : 0) &&
         memchr(s->map, '\0', sizeof s->map) && sdae_map_by_name(s->map) &&
         c->phase >= FMU_INSTANTIATED && c->phase <= FMU_FAILED && isfinite(c->t) &&
         isfinite(c->t_grid) && (c->start_set == 0 || c->start_set == 1);
}

/* a state of this model, whole and undamaged (its checksum); FMU_ERROR with a message
 * otherwise */
static fmu_status check(fmu_instance *fi, const fmu_state *s, size_t len, const char *call) {
  if (!s || len < sizeof *s || !header_whole(fi, s, len) || s->checksum != checksum_of(s)) {
    fmu_log(fi, FMU_ERROR, "%s: not a state of this model, or a damaged one", call);
    return FMU_ERROR;
  }
  return FMU_OK;
}

/* the stepper's bytes belong here: this instance, its block, this binary at this address */
static int same_place(const fmu_instance *fi, const fmu_state *s) {
  return s->instance == (uintptr_t)(const void *)fi && s->block == (uintptr_t)fi->block &&
         s->block_len == fi->block_len && s->binary == binary_address();
}

fmu_status fmu_state_set(fmu_instance *fi, const fmu_state *s) {
  if (check(fi, s, s ? s->bytes : 0, "setFMUState") != FMU_OK) return FMU_ERROR;
  memcpy(fi->values, values_of(s), s->count * sizeof(double));
  fi->clock = s->clock;
  fi->clock.map = sdae_map_by_name(s->map);
  fi->stepper = NULL;
  if (!s->have_stepper) return FMU_OK;
  if (same_place(fi, s)) {
    fmu_mechanism(fi); /* the params struct the stepper's mechanism reads */
    memcpy(fi->block, stepper_bytes(s), s->block_len);
    fi->stepper = (sdae_mbs_stepper *)(void *)((unsigned char *)fi->block + s->stepper_at);
    return FMU_OK;
  }
  fmu_log(fi, FMU_OK, "setFMUState: a state of another instance: a new stepper at its state");
  if (fmu_build(fi, "setFMUState") != FMU_OK) {
    fi->clock.phase = FMU_FAILED;
    return FMU_ERROR;
  }
  return FMU_OK;
}

size_t fmu_state_size(const fmu_state *state) { return state ? state->bytes : 0; }

fmu_status fmu_state_serialize(fmu_instance *fi, const fmu_state *state, unsigned char *bytes,
                               size_t len) {
  if (!state || !bytes || len < state->bytes) {
    fmu_log(fi, FMU_ERROR, "serializeFMUState: no state, or %zu bytes are too few", len);
    return FMU_ERROR;
  }
  memcpy(bytes, state, state->bytes);
  return FMU_OK;
}

fmu_status fmu_state_deserialize(fmu_instance *fi, const unsigned char *bytes, size_t len,
                                 fmu_state **state) {
  fmu_state head, *s;
  if (!bytes || len < sizeof head) {
    fmu_log(fi, FMU_ERROR, "deserializeFMUState: not a state of this model");
    return FMU_ERROR;
  }
  memcpy(&head, bytes, sizeof head);
  if (!header_whole(fi, &head, len)) {
    fmu_log(fi, FMU_ERROR, "deserializeFMUState: not a state of this model");
    return FMU_ERROR;
  }
  /* checked in a block of its own: the importer's state, if it passed one, is replaced only
   * by a good one */
  if (!(s = state_alloc(fi, len, "deserializeFMUState"))) return FMU_ERROR;
  memcpy(s, bytes, len);
  if (check(fi, s, len, "deserializeFMUState") != FMU_OK) {
    fmu_state_free(fi, s);
    return FMU_ERROR;
  }
  fmu_state_free(fi, *state);
  *state = s;
  return FMU_OK;
}
