/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Nelder-Mead (Nelder and Mead 1965) with the moves of GSL's nmsimplex2: reflect the worst
 * vertex through the centroid of the others, expand when that beats the best (keeping the
 * expansion only when it beats the reflection, as Lagarias et al.), contract when it is worse
 * than the second worst, and shrink towards the best when the contraction fails too.
 * GSL's own minimizer is not used: it allocates with malloc and reports failure through GSL's
 * error handler, which aborts by default. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "simplex.h"

typedef struct nm {
  sdae__simplex_fn f;
  void *data;
  size_t n;
  double *x;     /* n + 1 vertices of n values */
  double *fx;    /* n + 1 objective values */
  double *c;     /* centroid of the vertices but the worst */
  double *r, *e; /* trial points */
} nm;

size_t sdae__simplex_work(size_t n) {
  if (n == 0) return 0;
  if (n > SIZE_MAX / 4 - 1 || n + 1 > (SIZE_MAX - 3 * n) / (n + 1)) return SIZE_MAX;
  return (n + 1) * (n + 1) + 3 * n;
}

static double *vertex(const nm *s, size_t i) { return s->x + i * s->n; }

static int eval(const nm *s, const double *p, double *fp) { return s->f(p, fp, s->data); }

/* the worst (hi), second worst (second) and best (lo) vertices */
static void rank(const nm *s, size_t *lo, size_t *hi, size_t *second) {
  *lo = *hi = 0;
  for (size_t i = 1; i <= s->n; i++) {
    if (s->fx[i] < s->fx[*lo]) *lo = i;
    if (s->fx[i] > s->fx[*hi]) *hi = i;
  }
  *second = *hi == 0 ? 1 : 0;
  for (size_t i = 0; i <= s->n; i++)
    if (i != *hi && s->fx[i] > s->fx[*second]) *second = i;
}

static void centroid(const nm *s, size_t hi) {
  memset(s->c, 0, s->n * sizeof *s->c);
  for (size_t i = 0; i <= s->n; i++)
    if (i != hi)
      for (size_t j = 0; j < s->n; j++) s->c[j] += vertex(s, i)[j];
  for (size_t j = 0; j < s->n; j++) s->c[j] /= (double)s->n;
}

/* p = c + coeff (x_hi - c): coeff -1 reflects, -2 expands, 1/2 contracts */
static int move(const nm *s, size_t hi, double coeff, double *p, double *fp) {
  const double *xh = vertex(s, hi);
  for (size_t j = 0; j < s->n; j++) p[j] = s->c[j] + coeff * (xh[j] - s->c[j]);
  return eval(s, p, fp);
}

static void replace(const nm *s, size_t i, const double *p, double fp) {
  memcpy(vertex(s, i), p, s->n * sizeof *p);
  s->fx[i] = fp;
}

/* every vertex but the best halfway towards it */
static int shrink(const nm *s, size_t lo) {
  for (size_t i = 0; i <= s->n; i++) {
    if (i == lo) continue;
    for (size_t j = 0; j < s->n; j++) vertex(s, i)[j] = 0.5 * (vertex(s, i)[j] + vertex(s, lo)[j]);
    int rc = eval(s, vertex(s, i), &s->fx[i]);
    if (rc) return rc;
  }
  return 0;
}

static int iterate(const nm *s) {
  size_t lo, hi, second;
  double fr, fe;
  int rc;
  rank(s, &lo, &hi, &second);
  centroid(s, hi);
  if ((rc = move(s, hi, -1.0, s->r, &fr))) return rc;
  if (fr < s->fx[lo]) {
    if ((rc = move(s, hi, -2.0, s->e, &fe))) return rc;
    if (fe < fr)
      replace(s, hi, s->e, fe);
    else
      replace(s, hi, s->r, fr);
  } else if (fr > s->fx[second]) {
    /* the reflection replaces the worst when no worse; the contraction must then be no worse
     * than that new worst vertex, as in GSL, not than the old one */
    if (fr <= s->fx[hi]) replace(s, hi, s->r, fr);
    if ((rc = move(s, hi, 0.5, s->e, &fe))) return rc;
    if (fe <= s->fx[hi])
      replace(s, hi, s->e, fe);
    else
      return shrink(s, lo);
  } else {
    replace(s, hi, s->r, fr);
  }
  return 0;
}

/* RMS distance of the vertices from their center (the center goes to r) */
static double size(const nm *s) {
  double ss = 0.0;
  memset(s->r, 0, s->n * sizeof *s->r);
  for (size_t i = 0; i <= s->n; i++)
    for (size_t j = 0; j < s->n; j++) s->r[j] += vertex(s, i)[j] / (double)(s->n + 1);
  for (size_t i = 0; i <= s->n; i++)
    for (size_t j = 0; j < s->n; j++) {
      double d = vertex(s, i)[j] - s->r[j];
      ss += d * d;
    }
  return sqrt(ss / (double)(s->n + 1));
}

int sdae__simplex_minimize(sdae__simplex_fn f, void *data, size_t n, double *u, double step,
                           double size_tol, int max_iter, double *work) {
  nm s = {f, data, n, work, work + (n + 1) * n, NULL, NULL, NULL};
  size_t lo, hi, second;
  int rc = 0;
  s.c = s.fx + n + 1, s.r = s.c + n, s.e = s.r + n;
  for (size_t i = 0; i <= n && rc == 0; i++) {
    memcpy(vertex(&s, i), u, n * sizeof *u);
    if (i > 0) vertex(&s, i)[i - 1] += step;
    rc = eval(&s, vertex(&s, i), &s.fx[i]);
  }
  for (int it = 0; it < max_iter && rc == 0; it++) {
    rc = iterate(&s);
    if (rc == 0 && size(&s) < size_tol) break;
  }
  if (rc == 0) {
    rank(&s, &lo, &hi, &second);
    memcpy(u, vertex(&s, lo), n * sizeof *u);
  }
  return rc;
}
