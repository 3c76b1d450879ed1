/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "fmu_state.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define FMU_STATE_MAGIC 0x73646165666d7532ULL /* "sdaefmu2" */

/* the block: this header, the variables (count doubles), the stepper's state (stepper_len) */
struct fmu_state {
  uint64_t magic;
  uint64_t checksum; /* of the whole block with this field 0: a damaged state is refused */
  size_t bytes;      /* the whole block */
  char token[40];
  fmu_clock clock;
  char map[24]; /* the map by name: the pointer in clock is this process's */
  size_t count;
  size_t stepper_len; /* 0: no stepper (before exitInitializationMode) */
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
  return header_bytes() + fi->layout.count * sizeof(double) + sdae_mbs_state_size(fi->stepper);
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
  memset(s, 0, header_bytes()); /* the header's padding too: the checksum reads it */
  s->magic = FMU_STATE_MAGIC;
  s->bytes = bytes;
  memcpy(s->token, fi->token, sizeof s->token);
  s->clock = fi->clock;
  s->clock.map = NULL; /* by name below */
  snprintf(s->map, sizeof s->map, "%s", sdae_map_name(fi->clock.map));
  s->count = fi->layout.count;
  s->stepper_len = sdae_mbs_state_size(fi->stepper);
  memcpy(values_of(s), fi->values, s->count * sizeof(double));
  if (fi->stepper) sdae_mbs_get_state(fi->stepper, stepper_bytes(s), s->stepper_len);
  s->checksum = checksum_of(s);
  *state = s;
  return FMU_OK;
}

/* the header's sizes and clock, before anything else is read; the sizes compared by
 * subtraction only, in an order where none wraps (a crafted count or stepper_len with a
 * matching checksum must not lead a read past the block) */
static int header_whole(const fmu_instance *fi, const fmu_state *s, size_t len) {
  const fmu_clock *c = &s->clock;
  return s->magic == FMU_STATE_MAGIC && s->bytes == len && s->count == fi->layout.count &&
         strncmp(s->token, fi->token, sizeof s->token) == 0 && len >= header_bytes() &&
         s->count <= (len - header_bytes()) / sizeof(double) &&
         s->stepper_len == len - header_bytes() - s->count * sizeof(double) &&
         memchr(s->map, '\0', sizeof s->map) && sdae_map_by_name(s->map) &&
         c->phase >= FMU_INSTANTIATED && c->phase <= FMU_FAILED && isfinite(c->t) &&
         isfinite(c->t_grid) && (c->start_set == 0 || c->start_set == 1);
}

/* a state of this model, whole and undamaged (its checksum); FMU_ERROR with a message
 * otherwise */
static fmu_status check(fmu_instance *fi, const fmu_state *s, size_t len, const char *call) {
  if (!s || len < header_bytes() || !header_whole(fi, s, len) || s->checksum != checksum_of(s)) {
    fmu_log(fi, FMU_ERROR, "%s: not a state of this model, or a damaged one", call);
    return FMU_ERROR;
  }
  return FMU_OK;
}

fmu_status fmu_state_set(fmu_instance *fi, const fmu_state *s) {
  int rc;
  if (check(fi, s, s ? s->bytes : 0, "setFMUState") != FMU_OK) return FMU_ERROR;
  memcpy(fi->values, values_of(s), s->count * sizeof(double));
  fi->clock = s->clock;
  fi->clock.map = sdae_map_by_name(s->map);
  fmu_drop_stepper(fi);
  /* a state got after a set of u holds outputs of the u before: computed on the next get */
  fi->outputs_stale = 1;
  if (s->stepper_len == 0) return FMU_OK;
  /* the stepper at the state's parameters and map, then its own state: the chart and what it
   * keeps, so that the next step is the one the state's instance would have taken */
  if (fmu_build(fi, "setFMUState") != FMU_OK) {
    fi->clock.phase = FMU_FAILED;
    return FMU_ERROR;
  }
  if ((rc = sdae_mbs_set_state(fi->stepper, stepper_bytes(s), s->stepper_len)) != SDAE_OK) {
    fmu_log(fi, FMU_ERROR, "setFMUState: the stepper's state: %s", sdae_strerror(rc));
    fmu_drop_stepper(fi);
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
  if (!bytes || len < header_bytes()) {
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
