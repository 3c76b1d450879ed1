/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "bytes.h"

#include <string.h>

void sdae__bytes(sdae_bytes *b, void *p, size_t n) {
  if (b->out) memcpy(b->out + b->at, p, n);
  if (b->in) memcpy(p, b->in + b->at, n);
  b->at += n;
}

void sdae__bytes_doubles(sdae_bytes *b, double *p, size_t n) { sdae__bytes(b, p, n * sizeof *p); }

void sdae__bytes_sizes(sdae_bytes *b, size_t *p, size_t n) { sdae__bytes(b, p, n * sizeof *p); }

void sdae__bytes_flag(sdae_bytes *b, int *flag) {
  sdae__bytes(b, flag, sizeof *flag);
  if (b->in) *flag = *flag != 0;
}

uint64_t sdae__fnv(uint64_t h, const void *p, size_t n) {
  const unsigned char *c = p;
  for (size_t i = 0; i < n; i++) h = (h ^ c[i]) * 0x100000001b3ULL;
  return h;
}
