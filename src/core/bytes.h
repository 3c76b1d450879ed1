/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A part's state as bytes (the front-ends' get/set state): each part lists the fields the next
 * step depends on once, in one function that counts, writes or reads them through sdae_bytes,
 * so that the three can never disagree. Fields are written as the build lays them out (the
 * state names its build), never pointers: offsets and values only. */
#ifndef STABDAE_SRC_CORE_BYTES_H
#define STABDAE_SRC_CORE_BYTES_H

#include <stddef.h>
#include <stdint.h>

/* counts (out and in NULL), writes to out or reads from in, at `at` */
typedef struct sdae_bytes {
  unsigned char *out;
  const unsigned char *in;
  size_t at;
} sdae_bytes;

/* one field of n bytes at p: counted, written from p, or read into p */
void sdae__bytes(sdae_bytes *b, void *p, size_t n);
/* n doubles (n size_t) at p, as sdae__bytes */
void sdae__bytes_doubles(sdae_bytes *b, double *p, size_t n);
void sdae__bytes_sizes(sdae_bytes *b, size_t *p, size_t n);
/* an int flag read back as 0 or 1 (the bytes may say anything) */
void sdae__bytes_flag(sdae_bytes *b, int *flag);

/* FNV-1a, 64 bits, of n bytes continuing from h (start: SDAE_FNV_START): every change of a
 * single byte changes it (each step is a bijection of h for a given byte) */
#define SDAE_FNV_START 0xcbf29ce484222325ULL
uint64_t sdae__fnv(uint64_t h, const void *p, size_t n);

#endif /* STABDAE_SRC_CORE_BYTES_H */
