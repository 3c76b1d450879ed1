/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A mechanical stepper's state as bytes (<stabdae/mbs.h>, after MuJoCo's mj_getState and
 * mj_setState): what the next step depends on besides the caller's (t, q, v), each part's
 * fields listed once by the part itself (core/bytes.h), in this order: the statistics' counters,
 * the chart, the point Phi^-1 left, the normal form's stepper (its counters and the Newton
 * matrix it keeps). Around
 * them a header (a magic, the format, the build's identity, the stepper's identity: the
 * mechanism's sizes and callbacks, the options and the map by name, the length) and a
 * checksum of everything before it. Nothing is a pointer, so the bytes serve another stepper
 * of the same mechanism and options, in this process or another of the same build. */
#include <string.h>

#include <stabdae/version.h>

#include "core/bytes.h"
#include "maps/map.h"
#include "mbs_impl.h"
#include "stepper/stepper.h"

static const char magic[8] = {'s', 'd', 'a', 'e', 'm', 'b', 's', '\0'};
/* the layout of the bytes; a change of any part's fields is a new format */
#define STATE_FORMAT                                                                               \
  7u /* 7: the largest independence seen (6: the independence last seen, the projected steps       \
      * counted; 5: the rows chosen, the row switches counted; 4: the back-end's chart and         \
      * matrices, then the point; 3: the counters first) */

typedef struct header {
  char magic[8];
  uint32_t format;
  uint64_t build, identity, length;
} header;

/* the header's fields one by one (no padding in the bytes) */
static void header_fields(header *h, sdae_bytes *b) {
  sdae__bytes(b, h->magic, sizeof h->magic);
  sdae__bytes(b, &h->format, sizeof h->format);
  sdae__bytes(b, &h->build, sizeof h->build);
  sdae__bytes(b, &h->identity, sizeof h->identity);
  sdae__bytes(b, &h->length, sizeof h->length);
}

static size_t header_size(void) {
  header h;
  sdae_bytes b = {NULL, NULL, 0};
  header_fields(&h, &b);
  return b.at;
}

/* the build: the library's version, the sizes and byte order its fields are written in */
static uint64_t build_identity(void) {
  const uint32_t one = 1;
  const size_t sizes[5] = {sizeof(size_t), sizeof(double), sizeof(unsigned long), sizeof(unsigned),
                           sizeof(int)};
  uint64_t h = sdae__fnv(SDAE_FNV_START, SDAE_VERSION_STRING, sizeof SDAE_VERSION_STRING);
  h = sdae__fnv(h, sizes, sizeof sizes);
  return sdae__fnv(h, &one, sizeof one);
}

#define HASH(h, x) ((h) = sdae__fnv((h), &(x), sizeof(x)))

/* the stepper: the mechanism's sizes, which optional callbacks it gives and its patterns, the
 * options (the map by its name, the same in every process) */
static uint64_t stepper_identity(const sdae_mbs_stepper *s) {
  const sdae_mbs *m = &s->eval.sys;
  const sdae_options *o = &s->opt;
  const char *map = sdae_map_name(o->map);
  unsigned given = (m->jacobian != NULL) | (m->constraint_t != NULL) << 1 |
                   (m->potential != NULL) << 2 | (m->damping != NULL) << 3 |
                   (m->mass_dot_v != NULL) << 4 | (m->jacobian_dot != NULL) << 5 |
                   (m->constraint_t_dot != NULL) << 6 | (m->input_force != NULL) << 7 |
                   (m->mass_pattern != NULL) << 8 | (m->jacobian_pattern != NULL) << 9;
  int scheme = (int)o->scheme, stabilizer = (int)o->stabilizer;
  uint64_t h = SDAE_FNV_START;
  HASH(h, s->n_q), HASH(h, s->n_c), HASH(h, given);
  if (s->n_c < m->n_c) HASH(h, m->n_c); /* redundant: rank n_c of these rows */
  HASH(h, scheme), HASH(h, o->delta), HASH(h, o->epsilon), HASH(h, o->newton_tol);
  HASH(h, o->newton_max_iter), HASH(h, o->bandwidth), HASH(h, stabilizer);
  HASH(h, o->baumgarte_alpha);
  if (m->mass_pattern) h = sdae__pattern_hash(h, m->mass_pattern, s->n_q);
  if (m->jacobian_pattern) h = sdae__pattern_hash(h, m->jacobian_pattern, m->n_c);
  return sdae__fnv(h, map, strlen(map));
}

/* every part's fields, in the one order: the coordinates' (the chart and the point), the normal
 * form's stepper's; the counters the steps committed are the stepper's own, in the bytes but
 * not in a rollback (a failed step commits none) */
static void parts(sdae_mbs_stepper *s, sdae_bytes *b) {
  sdae__mbs_coords_state(&s->coords, b);
  sdae__mbs_project_state(&s->project, b);
  sdae__stepper_state(s->inner, b);
}

static void counters(sdae_mbs_stats *stats, sdae_bytes *b) {
  sdae__bytes(b, &stats->chart_switches, sizeof stats->chart_switches);
  sdae__bytes(b, &stats->phi_inv_iters, sizeof stats->phi_inv_iters);
  sdae__bytes(b, &stats->row_switches, sizeof stats->row_switches);
  sdae__bytes(b, &stats->projected_steps, sizeof stats->projected_steps);
}

size_t sdae__mbs_parts_bytes(const sdae_mbs_stepper *s) {
  sdae_bytes b = {NULL, NULL, 0}; /* counted: the sizes read, nothing else */
  sdae__mbs_coords_state((sdae_mbs_coords *)&s->coords, &b);
  sdae__mbs_project_state((sdae_mbs_project *)&s->project, &b);
  return b.at + sdae__stepper_state_bytes(&s->nf.model, &s->opt);
}

void sdae__mbs_rollback_save(sdae_mbs_stepper *s) {
  sdae_bytes b = {s->rollback, NULL, 0};
  parts(s, &b);
}

void sdae__mbs_rollback(sdae_mbs_stepper *s) {
  sdae_bytes b = {NULL, s->rollback, 0};
  parts(s, &b);
}

/* counted on a stats struct of its own: a whole stepper here was a 1.8 KB stack frame on a
 * Cortex-M7 (docs/embedded.md) */
static size_t counters_size(void) {
  sdae_mbs_stats probe;
  sdae_bytes b = {NULL, NULL, 0};
  counters(&probe, &b);
  return b.at;
}

size_t sdae__mbs_state_size(const sdae_mbs_stepper *s) {
  return header_size() + counters_size() + sdae__mbs_parts_bytes(s) + sizeof(uint64_t);
}

int sdae__mbs_state_get(const sdae_mbs_stepper *s, void *buf, size_t len) {
  size_t size = sdae__mbs_state_size(s);
  header h;
  sdae_bytes b = {buf, NULL, 0};
  uint64_t sum;
  if (len < size) return SDAE_ERR_BUFFER;
  memcpy(h.magic, magic, sizeof magic);
  h.format = STATE_FORMAT;
  h.build = build_identity();
  h.identity = stepper_identity(s);
  h.length = size;
  header_fields(&h, &b);
  counters((sdae_mbs_stats *)&s->stats, &b); /* written: s is only read */
  parts((sdae_mbs_stepper *)s, &b);
  sum = sdae__fnv(SDAE_FNV_START, buf, b.at);
  sdae__bytes(&b, &sum, sizeof sum);
  return SDAE_OK;
}

/* the bytes whole (their length and checksum), then of this build and stepper */
static int verify(const sdae_mbs_stepper *s, const unsigned char *in, size_t len) {
  header h;
  sdae_bytes b = {NULL, in, 0};
  uint64_t sum;
  if (len < header_size() + sizeof sum) return SDAE_ERR_STATE_DAMAGED;
  header_fields(&h, &b);
  if (h.length != len) return SDAE_ERR_STATE_DAMAGED;
  memcpy(&sum, in + len - sizeof sum, sizeof sum);
  if (sdae__fnv(SDAE_FNV_START, in, len - sizeof sum) != sum) return SDAE_ERR_STATE_DAMAGED;
  if (memcmp(h.magic, magic, sizeof magic) != 0 || h.format != STATE_FORMAT ||
      h.build != build_identity() || h.identity != stepper_identity(s) ||
      len != sdae__mbs_state_size(s))
    return SDAE_ERR_STATE_FOREIGN;
  return SDAE_OK;
}

int sdae__mbs_state_set(sdae_mbs_stepper *s, const void *buf, size_t len) {
  const unsigned char *in = buf;
  sdae_bytes b = {NULL, in, header_size() + counters_size()};
  int rc;
  if ((rc = verify(s, in, len)) != SDAE_OK) return rc;
  /* whole and ours, yet what indexes memory (the chart, Newton's pivots) may have been made by
   * hand: read, checked, and the stepper put back as it was when it is not whole */
  sdae__mbs_rollback_save(s);
  parts(s, &b);
  if (!sdae__stepper_state_valid(s->inner) || !sdae__mbs_coords_state_read(&s->coords)) {
    sdae__mbs_rollback(s);
    return SDAE_ERR_STATE_DAMAGED;
  }
  b.at = header_size(); /* whole: the counters too */
  counters(&s->stats, &b);
  return SDAE_OK;
}
