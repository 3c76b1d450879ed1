/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The mechanism's residuals for IDA (ida_mbs.h), the consistent start (index1.h's Cholesky, or KLU
 * on the saddle-point matrix), the KLU path's iteration matrix (its structure, the column groups,
 * the grouped differences), and the run: context, vectors, dense solver with IDA's
 * difference-quotient matrix or KLU with the grouped one, then one IDASolve per output time with
 * tstop set to it. Scratch is allocated once per run (a tool, not the library). */
#include "ida_mbs.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "index1.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the mechanism and its residual ---------------------------------------------------------- */

/* The index-1 form's derivatives and saddle-point solve are tools/index1's (index1.h), shared
 * with the RK4 baseline; the residual and the run are this reference's own. */
typedef struct mech {
  const sdae_mbs *sys;
  idambs_form form;
  size_t n_q, n_c;
  const sdae_pattern *mp, *gp; /* M's and G's patterns (NULL: dense, row-major) */
  size_t m_len, g_len;         /* the values mass() and jacobian() write */
  index1 *w;                   /* the index-1 form (with its dense solve: the dense start) */
  double *block;               /* M, F, G: the residual's evaluations, one allocation */
  double *M, *F, *G;
} mech;

/* The mechanism as this reference reads it: the derivatives along the motion that the library
 * may take from the mechanism (jacobian_dot, constraint_t_dot) differenced instead, so that a
 * wrong one shows as a difference between the two. */
static sdae_mbs reference_view(const sdae_mbs *sys) {
  sdae_mbs own = *sys;
  own.jacobian_dot = NULL, own.constraint_t_dot = NULL;
  return own;
}

/* The arrays of the residual, and with dense_start the index-1 form's dense solve (the KLU
 * path has its own: no array of n_q^2 then). */
static int mech_init(mech *m, const sdae_mbs *sys, idambs_form form, int dense_start) {
  size_t nq = sys->n_q, nc = sys->n_c;
  const sdae_pattern *mp = sys->mass_pattern, *gp = sys->jacobian_pattern;
  size_t m_len = mp ? mp->nnz : nq * nq, g_len = gp ? gp->nnz : nc * nq;
  sdae_mbs own = reference_view(sys);
  *m = (mech){.sys = sys, .form = form, .n_q = nq, .n_c = nc, .mp = mp, .gp = gp};
  m->m_len = m_len, m->g_len = g_len;
  if (!(m->block = calloc(m_len + nq + g_len + 1, sizeof *m->block)) ||
      !(m->w = index1_alloc(&own, dense_start))) {
    free(m->block);
    m->block = NULL; /* the callers free the mech on failure too */
    return -1;
  }
  m->M = m->block, m->F = m->M + m_len, m->G = m->F + nq;
  return 0;
}

static void mech_free(mech *m) {
  index1_free(m->w);
  free(m->block);
}

/* y += A^T x (rows x cols): A row-major (p NULL) or its nonzeros in p's order */
static void mul_t_add(const sdae_pattern *p, const double *a, size_t rows, size_t cols,
                      const double *x, double *y) {
  if (!p) {
    for (size_t i = 0; i < rows; i++)
      for (size_t j = 0; j < cols; j++) y[j] += a[i * cols + j] * x[i];
    return;
  }
  for (size_t i = 0; i < rows; i++)
    for (size_t k = p->row_start[i]; k < p->row_start[i + 1]; k++) y[p->col[k]] += a[k] * x[i];
}

/* M, F and G at (t, q, v) into m->M, m->F, m->G */
static int dynamics(mech *m, double t, const double *q, const double *v) {
  const sdae_mbs *s = m->sys;
  int rc = index1_status(s->mass(t, q, m->M, s->params), m->M, m->m_len);
  if (rc == 0) rc = index1_force(m->w, t, q, v, m->F);
  return rc != 0 ? rc : index1_jacobian(m->w, t, q, m->G);
}

/* r = M v' - F + G^T lambda */
static void momentum_rows(const mech *m, const double *vp, const double *lambda, double *r) {
  size_t nq = m->n_q;
  for (size_t i = 0; i < nq; i++) r[i] = -m->F[i];
  index1_mul_add(m->mp, m->M, nq, nq, vp, r);
  mul_t_add(m->gp, m->G, m->n_c, nq, lambda, r);
}

/* The residual of the form (ida_mbs.h). */
static int residual(mech *m, double t, const double *y, const double *yp, double *r) {
  size_t nq = m->n_q, nc = m->n_c;
  const double *q = y, *v = y + nq, *lambda = y + 2 * nq, *vp = yp + nq;
  double *rl = r + 2 * nq;
  int rc = dynamics(m, t, q, v);
  if (rc != 0) return rc;
  for (size_t i = 0; i < nq; i++) r[i] = yp[i] - v[i]; /* q' = v */
  momentum_rows(m, vp, lambda, r + nq);
  if (m->form == IDAMBS_INDEX1) {
    if ((rc = index1_gamma(m->w, t, q, v, rl)) != 0) return rc;
    index1_mul_add(m->gp, m->G, nc, nq, vp, rl); /* G v' + gamma = 0 */
    return 0;
  }
  mul_t_add(m->gp, m->G, nc, nq, y + 2 * nq + nc, r); /* q' = v - G^T nu */
  if ((rc = index1_constraint(m->w, t, q, rl)) != 0) return rc;
  return index1_velocity(m->w, t, q, v, rl + nc);
}

size_t idambs_dim(const sdae_mbs *sys, idambs_form form) {
  return 2 * sys->n_q + (form == IDAMBS_GGL ? 2 : 1) * sys->n_c;
}

int idambs_lambda(const sdae_mbs *sys, double t, const double *q, const double *v, double *lambda,
                  double *vdot) {
  mech m;
  double *a = vdot ? vdot : malloc((sys->n_q ? sys->n_q : 1) * sizeof *a);
  int rc = -1;
  if (a && !index1_refused(sys) && mech_init(&m, sys, IDAMBS_INDEX1, 1) == 0) {
    rc = index1_accel(m.w, t, q, v, a, lambda) == 0 ? 0 : -1;
    mech_free(&m);
  }
  if (a != vdot) free(a);
  return rc;
}

/* ---- the KLU path: the iteration matrix's structure, groups and values ---------------------- */

/* A matrix's structure in compressed columns: column j's rows are rowind[colptr[j] ..
 * colptr[j + 1]), ascending. */
typedef struct csc {
  size_t rows, cols, nnz;
  sunindextype *colptr, *rowind;
} csc;

static void csc_free(csc *a) {
  free(a->colptr);
  free(a->rowind);
  a->colptr = a->rowind = NULL;
}

/* The structure of the entries (ti[k], tj[k]), k < count, duplicates merged, by two stable
 * counting sorts (by row, then by column); slot[k] (when slot) the place of entry k. 0, or -1
 * without memory. */
static int csc_build(size_t rows, size_t cols, size_t count, const size_t *ti, const size_t *tj,
                     csc *a, size_t *slot) {
  size_t big = rows > cols ? rows : cols, room = count > 0 ? count : 1;
  size_t *cnt = calloc(big + 1, sizeof *cnt), *by_row = malloc(room * sizeof *by_row);
  size_t *ord = malloc(room * sizeof *ord);
  int rc = -1;
  *a = (csc){.rows = rows, .cols = cols};
  a->colptr = calloc(cols + 1, sizeof *a->colptr);
  a->rowind = malloc(room * sizeof *a->rowind);
  if (cnt && by_row && ord && a->colptr && a->rowind) {
    for (size_t k = 0; k < count; k++) cnt[ti[k] + 1]++;
    for (size_t i = 0; i < rows; i++) cnt[i + 1] += cnt[i];
    for (size_t k = 0; k < count; k++) by_row[cnt[ti[k]]++] = k;
    memset(cnt, 0, (big + 1) * sizeof *cnt);
    for (size_t k = 0; k < count; k++) cnt[tj[k] + 1]++;
    for (size_t j = 0; j < cols; j++) cnt[j + 1] += cnt[j];
    for (size_t x = 0; x < count; x++) ord[cnt[tj[by_row[x]]]++] = by_row[x];
    for (size_t x = 0; x < count; x++) {
      size_t k = ord[x], prev = x > 0 ? ord[x - 1] : 0;
      if (x == 0 || ti[k] != ti[prev] || tj[k] != tj[prev]) {
        a->rowind[a->nnz++] = (sunindextype)ti[k];
        a->colptr[tj[k] + 1]++;
      }
      if (slot) slot[k] = a->nnz - 1;
    }
    for (size_t j = 0; j < cols; j++) a->colptr[j + 1] += a->colptr[j];
    rc = 0;
  }
  free(cnt), free(by_row), free(ord);
  if (rc != 0) csc_free(a);
  return rc;
}

/* a list of entries, its room counted beforehand */
typedef struct entries {
  size_t n, *i, *j;
} entries;

static void put(entries *e, size_t i, size_t j) { e->i[e->n] = i, e->j[e->n++] = j; }

/* The index1 iteration matrix's structure (ida_mbs.h), of order 2 n_q + n_c: the residual's rows
 * q' - v (q), M v' - F + G^T lambda (v), G v' + gamma (lambda) against the columns of y. */
static int iteration_structure(const sdae_mbs *sys, csc *a) {
  const sdae_pattern *mp = sys->mass_pattern, *gp = sys->jacobian_pattern;
  size_t nq = sys->n_q, nc = sys->n_c, n = 2 * nq + nc, count = 4 * nq + 2 * mp->nnz + 3 * gp->nnz;
  entries e = {0};
  int rc = -1;
  for (size_t c = 0; c < nc; c++) {
    size_t len = gp->row_start[c + 1] - gp->row_start[c];
    count += 2 * len * len;
  }
  e.i = malloc(count * sizeof *e.i), e.j = malloc(count * sizeof *e.j);
  if (e.i && e.j) {
    for (size_t k = 0; k < nq; k++) {
      put(&e, k, k), put(&e, k, nq + k);           /* q' - v */
      put(&e, nq + k, k), put(&e, nq + k, nq + k); /* S's diagonal */
    }
    for (size_t i = 0; i < nq; i++) /* M v' and, by assumption, F: S's pattern(M) */
      for (size_t k = mp->row_start[i]; k < mp->row_start[i + 1]; k++)
        put(&e, nq + i, mp->col[k]), put(&e, nq + i, nq + mp->col[k]);
    for (size_t c = 0; c < nc; c++)
      for (size_t k = gp->row_start[c]; k < gp->row_start[c + 1]; k++) {
        size_t at = gp->col[k];
        put(&e, nq + at, 2 * nq + c);                          /* G^T lambda: lambda's columns */
        put(&e, 2 * nq + c, at), put(&e, 2 * nq + c, nq + at); /* G v' + gamma */
        for (size_t l = gp->row_start[c]; l < gp->row_start[c + 1]; l++) /* G^T lambda in q */
          put(&e, nq + at, gp->col[l]), put(&e, nq + at, nq + gp->col[l]);
      }
    rc = csc_build(n, n, e.n, e.i, e.j, a, NULL);
  }
  free(e.i), free(e.j);
  return rc;
}

/* The column groups of a: a greedy coloring in column order (a column joins the first group
 * with no column sharing a row with it), group g's columns group_col[group_start[g] ..
 * group_start[g + 1]). 0, or -1 without memory. */
static int color_columns(const csc *a, size_t *groups, size_t **group_start, size_t **group_col) {
  size_t n = a->cols, m = a->rows, ng = 0;
  size_t *row_start = calloc(m + 1, sizeof *row_start), *next = malloc((m + 1) * sizeof *next);
  size_t *cols = malloc((a->nnz > 0 ? a->nnz : 1) * sizeof *cols);
  size_t *color = malloc(n * sizeof *color), *mark = malloc((n + 1) * sizeof *mark);
  int rc = -1;
  *group_start = *group_col = NULL;
  if (row_start && next && cols && color && mark) {
    for (size_t p = 0; p < a->nnz; p++) row_start[a->rowind[p] + 1]++;
    for (size_t i = 0; i < m; i++) row_start[i + 1] += row_start[i];
    memcpy(next, row_start, (m + 1) * sizeof *next);
    for (size_t j = 0; j < n; j++) /* the rows' columns, ascending */
      for (sunindextype p = a->colptr[j]; p < a->colptr[j + 1]; p++) cols[next[a->rowind[p]]++] = j;
    for (size_t j = 0; j <= n; j++) mark[j] = SIZE_MAX;
    for (size_t j = 0; j < n; j++) {
      size_t c = 0;
      for (sunindextype p = a->colptr[j]; p < a->colptr[j + 1]; p++) {
        size_t i = (size_t)a->rowind[p];
        for (size_t x = row_start[i]; x < row_start[i + 1] && cols[x] < j; x++)
          mark[color[cols[x]]] = j;
      }
      while (mark[c] == j) c++;
      color[j] = c;
      if (c + 1 > ng) ng = c + 1;
    }
    *group_start = calloc(ng + 1, sizeof **group_start);
    *group_col = malloc((n > 0 ? n : 1) * sizeof **group_col);
  }
  if (*group_start && *group_col) {
    for (size_t j = 0; j < n; j++) (*group_start)[color[j] + 1]++;
    for (size_t g = 0; g < ng; g++) (*group_start)[g + 1] += (*group_start)[g];
    memcpy(next, *group_start, (ng + 1) * sizeof *next);
    for (size_t j = 0; j < n; j++) (*group_col)[next[color[j]]++] = j;
    *groups = ng;
    rc = 0;
  }
  free(row_start), free(next), free(cols), free(color), free(mark);
  return rc;
}

/* The iteration matrix of the KLU path: its structure and groups, and the differences' scratch. */
typedef struct klu_jac {
  csc a;
  size_t groups, *group_start, *group_col;
  double *inc;      /* per column: its increment */
  double *dir;      /* per column: the check's direction */
  double *jd, *mag; /* per row: (J d)_i and sum_j |J_ij d_j| */
  double worst;     /* the check's largest ratio over the v rows, */
  size_t worst_row; /* its row among them */
  int refused;      /* the run failed on it */
  long res_evals;   /* residuals spent on the differences and the check */
  uint64_t calls;   /* matrices computed: each check's direction its own */
  N_Vector ewt;     /* IDA's error weights */
} klu_jac;

static void klu_jac_free(klu_jac *k) {
  csc_free(&k->a);
  free(k->group_start), free(k->group_col), free(k->inc);
  if (k->ewt) N_VDestroy(k->ewt);
  *k = (klu_jac){0};
}

static int klu_jac_init(klu_jac *k, const sdae_mbs *sys) {
  size_t n;
  *k = (klu_jac){0};
  if (iteration_structure(sys, &k->a) != 0 ||
      color_columns(&k->a, &k->groups, &k->group_start, &k->group_col) != 0)
    return -1;
  n = k->a.cols;
  if (!(k->inc = malloc(4 * n * sizeof *k->inc))) return -1;
  k->dir = k->inc + n, k->jd = k->inc + 2 * n, k->mag = k->inc + 3 * n;
  return 0;
}

/* A factor in [0.5, 1) with a random sign, the next of a fixed sequence (64-bit LCG, Knuth's
 * MMIX constants): the check's direction, the same in every run. */
static double check_factor(uint64_t *state) {
  double u;
  *state = *state * 6364136223846793005u + 1442695040888963407u;
  u = (double)(*state >> 11) * 0x1p-53;
  return u < 0.5 ? -(0.5 + u) : u;
}

/* The iteration matrix dF/dy + cj dF/dy' at (t, y, yp), r0 its residual there, into val (the
 * structure's order): per group, y_j += inc_j and y'_j += cj inc_j for its columns, one residual,
 * each changed row's value to the one column of the group it holds. Then the check of the
 * structure (ida_mbs.h), one residual more: in the direction d_j = s_j inc_j (s_j from
 * check_factor), a v row whose difference r(y + d, y' + cj d) - r0 departs from (J d)_i by more
 * than IDAMBS_KLU_OUTSIDE of sum_j |J_ij d_j| has an entry outside the structure (or one that a
 * column of its group took for its own); the largest such ratio into k->worst. Differences that
 * the structure holds agree to rounding and to second order, about 1e-8 of the row. yk, ypk, rk:
 * scratch of n values. 0, or the residual's status. */
static int grouped_differences(mech *m, klu_jac *k, double t, double cj, const double *y,
                               const double *yp, const double *r0, double *yk, double *ypk,
                               double *rk, double *val) {
  size_t n = k->a.cols, nq = m->n_q;
  const sunindextype *cp = k->a.colptr, *ri = k->a.rowind;
  uint64_t state = 0x9E3779B97F4A7C15u ^ ++k->calls;
  int rc;
  memcpy(yk, y, n * sizeof *y);
  memcpy(ypk, yp, n * sizeof *yp);
  for (size_t g = 0; g < k->groups; g++) {
    size_t first = k->group_start[g], last = k->group_start[g + 1];
    for (size_t x = first; x < last; x++) {
      size_t j = k->group_col[x];
      yk[j] += k->inc[j], ypk[j] += cj * k->inc[j];
    }
    rc = residual(m, t, yk, ypk, rk);
    k->res_evals++;
    for (size_t x = first; x < last; x++) {
      size_t j = k->group_col[x];
      yk[j] = y[j], ypk[j] = yp[j];
    }
    if (rc != 0) return rc;
    for (size_t x = first; x < last; x++) {
      size_t j = k->group_col[x];
      for (sunindextype p = cp[j]; p < cp[j + 1]; p++) val[p] = (rk[ri[p]] - r0[ri[p]]) / k->inc[j];
    }
  }
  for (size_t j = 0; j < n; j++) {
    yk[j] = y[j] + check_factor(&state) * k->inc[j];
    k->dir[j] = yk[j] - y[j];
    ypk[j] = yp[j] + cj * k->dir[j];
    k->jd[j] = k->mag[j] = 0.0;
  }
  rc = residual(m, t, yk, ypk, rk);
  k->res_evals++;
  if (rc != 0) return rc;
  for (size_t j = 0; j < n; j++)
    for (sunindextype p = cp[j]; p < cp[j + 1]; p++) {
      k->jd[ri[p]] += val[p] * k->dir[j];
      k->mag[ri[p]] += fabs(val[p] * k->dir[j]);
    }
  k->worst = 0.0;
  for (size_t i = nq; i < 2 * nq; i++) {
    double miss = fabs(rk[i] - r0[i] - k->jd[i]);
    if (miss > 0.0 && !(miss / k->mag[i] <= k->worst))
      k->worst = miss / k->mag[i], k->worst_row = i - nq;
  }
  return 0;
}

/* ---- the run -------------------------------------------------------------------------------- */

typedef struct run {
  mech m;
  idaref_ida ida;
  klu_jac *jac;   /* the KLU path's matrix; NULL: dense */
  int configured; /* the linear solver attached: the counters can be read */
} run;

static int residual_cb(realtype t, N_Vector yy, N_Vector yp, N_Vector rr, void *user_data) {
  run *r = user_data;
  return residual(&r->m, t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), N_VGetArrayPointer(rr));
}

/* IDA's Jacobian function of the KLU path: increments as IDA's own dense difference quotient
 * takes them, sqrt(eps) max(|y_j|, |h y'_j|) but at least the tolerance 1 / ewt_j, signed as
 * h y'_j; then the grouped differences, and the structure's check (ida_mbs.h). */
static int klu_jacobian_cb(realtype t, realtype cj, N_Vector yy, N_Vector yp, N_Vector rr,
                           SUNMatrix J, void *user_data, N_Vector t1, N_Vector t2, N_Vector t3) {
  run *r = user_data;
  klu_jac *k = r->jac;
  const double *y = N_VGetArrayPointer(yy), *ypd = N_VGetArrayPointer(yp), *ewt;
  double h = 0.0;
  int rc;
  if (IDAGetCurrentStep(r->ida.mem, &h) != IDA_SUCCESS ||
      IDAGetErrWeights(r->ida.mem, k->ewt) != IDA_SUCCESS)
    return -1;
  ewt = N_VGetArrayPointer(k->ewt);
  for (size_t j = 0; j < k->a.cols; j++) {
    double inc = fmax(sqrt(DBL_EPSILON) * fmax(fabs(y[j]), fabs(h * ypd[j])), 1.0 / ewt[j]);
    if (h * ypd[j] < 0.0) inc = -inc;
    k->inc[j] = (y[j] + inc) - y[j];
  }
  memcpy(SM_INDEXPTRS_S(J), k->a.colptr, (k->a.cols + 1) * sizeof *k->a.colptr);
  memcpy(SM_INDEXVALS_S(J), k->a.rowind, k->a.nnz * sizeof *k->a.rowind);
  rc = grouped_differences(&r->m, k, t, cj, y, ypd, N_VGetArrayPointer(rr), N_VGetArrayPointer(t1),
                           N_VGetArrayPointer(t2), N_VGetArrayPointer(t3), SM_DATA_S(J));
  if (rc != 0) return rc;
  if (k->worst > IDAMBS_KLU_OUTSIDE) {
    k->refused = 1;
    return -1;
  }
  return 0;
}

/* v' and lambda at the start from [M G^T; G 0] [v'; lambda] = [F; -gamma] by KLU (lambda first
 * holds gamma). 0, or -1: a callback failed, the matrix is singular, no memory. */
static int klu_start(run *r, double t, const double *q, const double *v, double *lambda,
                     double *vdot) {
  mech *m = &r->m;
  size_t nq = m->n_q, nc = m->n_c, nm = m->m_len, ng = m->g_len, count = nm + 2 * ng, k = 0;
  size_t *ti = malloc(count * sizeof *ti), *tj = malloc(count * sizeof *tj);
  size_t *slot = malloc(count * sizeof *slot);
  sunindextype n = (sunindextype)(nq + nc);
  SUNMatrix A = NULL;
  SUNLinearSolver ls = NULL;
  N_Vector x = NULL, b = NULL;
  csc a = {0};
  int rc = -1;
  if (!ti || !tj || !slot || dynamics(m, t, q, v) != 0 || index1_gamma(m->w, t, q, v, lambda) != 0)
    goto done;
  for (size_t i = 0; i < nq; i++)
    for (size_t p = m->mp->row_start[i]; p < m->mp->row_start[i + 1]; p++)
      ti[k] = i, tj[k++] = m->mp->col[p];
  for (size_t c = 0; c < nc; c++)
    for (size_t p = m->gp->row_start[c]; p < m->gp->row_start[c + 1]; p++) {
      ti[k] = nq + c, tj[k++] = m->gp->col[p]; /* G */
      ti[k] = m->gp->col[p], tj[k++] = nq + c; /* G^T */
    }
  if (csc_build(nq + nc, nq + nc, count, ti, tj, &a, slot) != 0) goto done;
  A = SUNSparseMatrix(n, n, (sunindextype)a.nnz, CSC_MAT, r->ida.ctx);
  x = N_VNew_Serial(n, r->ida.ctx), b = N_VNew_Serial(n, r->ida.ctx);
  if (!A || !x || !b || !(ls = SUNLinSol_KLU(x, A, r->ida.ctx))) goto done;
  memcpy(SM_INDEXPTRS_S(A), a.colptr, (nq + nc + 1) * sizeof *a.colptr);
  memcpy(SM_INDEXVALS_S(A), a.rowind, a.nnz * sizeof *a.rowind);
  memset(SM_DATA_S(A), 0, a.nnz * sizeof(double));
  for (k = 0; k < count; k++) SM_DATA_S(A)[slot[k]] += k < nm ? m->M[k] : m->G[(k - nm) / 2];
  for (size_t i = 0; i < nq; i++) N_VGetArrayPointer(b)[i] = m->F[i];
  for (size_t c = 0; c < nc; c++) N_VGetArrayPointer(b)[nq + c] = -lambda[c];
  if (SUNLinSolInitialize(ls) == SUNLS_SUCCESS && SUNLinSolSetup(ls, A) == SUNLS_SUCCESS &&
      SUNLinSolSolve(ls, A, x, b, 0.0) == SUNLS_SUCCESS &&
      index1_status(0, N_VGetArrayPointer(x), nq + nc) == 0) {
    memcpy(vdot, N_VGetArrayPointer(x), nq * sizeof *vdot);
    memcpy(lambda, N_VGetArrayPointer(x) + nq, nc * sizeof *lambda);
    rc = 0;
  }
done:
  SUNLinSolFree(ls);
  SUNMatDestroy(A);
  if (x) N_VDestroy(x);
  if (b) N_VDestroy(b);
  csc_free(&a);
  free(ti), free(tj), free(slot);
  return rc;
}

/* IDA's objects of the KLU path: as idaref_ida_create's, with the sparse matrix and KLU. */
static int klu_ida_create(run *r, size_t n, idaref_result *res) {
  idaref_ida *d = &r->ida;
  sunindextype len = (sunindextype)n;
  if (idaref_failed(res, SUNContext_Create(NULL, &d->ctx), "SUNContext_Create")) return -1;
  d->mem = IDACreate(d->ctx);
  d->yy = N_VNew_Serial(len, d->ctx);
  d->yp = N_VNew_Serial(len, d->ctx);
  d->id = N_VNew_Serial(len, d->ctx);
  d->A = SUNSparseMatrix(len, len, (sunindextype)r->jac->a.nnz, CSC_MAT, d->ctx);
  r->jac->ewt = N_VNew_Serial(len, d->ctx);
  if (!d->mem || !d->yy || !d->yp || !d->id || !d->A || !r->jac->ewt)
    return idaref_failed(res, IDA_MEM_FAIL, "IDACreate");
  d->ls = SUNLinSol_KLU(d->yy, d->A, d->ctx);
  return d->ls ? 0 : idaref_failed(res, IDA_MEM_FAIL, "SUNLinSol_KLU");
}

/* y = (q0, v0, lambda[, nu = 0]), y' = (v0, v'[, 0, 0]) and the id vector (1 for q and v). */
static int consistent_start(run *r, double t0, const double *q0, const double *v0,
                            idaref_result *res) {
  size_t nq = r->m.n_q, n = idambs_dim(r->m.sys, r->m.form);
  double *y = N_VGetArrayPointer(r->ida.yy), *yp = N_VGetArrayPointer(r->ida.yp);
  double *id = N_VGetArrayPointer(r->ida.id);
  for (size_t i = 0; i < n; i++) {
    y[i] = yp[i] = 0.0;
    id[i] = i < 2 * nq ? 1.0 : 0.0;
  }
  memcpy(y, q0, nq * sizeof *q0);
  memcpy(y + nq, v0, nq * sizeof *v0);
  memcpy(yp, v0, nq * sizeof *v0);
  if (r->jac ? klu_start(r, t0, q0, v0, y + 2 * nq, yp + nq) == 0
             : index1_accel(r->m.w, t0, q0, v0, yp + nq, y + 2 * nq) == 0)
    return 0;
  res->function = r->jac ? "klu_start" : "idambs_lambda";
  snprintf(res->flag_name, sizeof res->flag_name, "no consistent start");
  snprintf(res->message, sizeof res->message, "%s at t = %.17g",
           r->jac ? "a callback failed or [M G^T; G 0] is singular"
                  : "a callback failed or M or G M^-1 G^T is not positive definite",
           t0);
  return -1;
}
/* Absolute tolerances: atol for q, v and lambda; 1 for GGL's nu, which vanishes on every
 * solution and which IDA computes as rounding noise of size eps |q| cj (as ida_solve.c says). */
static int set_tolerances(run *r, const idaref_options *o) {
  N_Vector atol = N_VClone(r->ida.yy);
  size_t nq = r->m.n_q, nc = r->m.n_c;
  int flag;
  if (!atol) return IDA_MEM_FAIL;
  for (size_t i = 0; i < idambs_dim(r->m.sys, r->m.form); i++)
    N_VGetArrayPointer(atol)[i] = i >= 2 * nq + nc ? 1.0 : o->atol;
  flag = IDASVtolerances(r->ida.mem, o->rtol, atol);
  N_VDestroy(atol);
  return flag;
}

/* The first step: the one whose backward-Euler local error in q, h^2 |q''| / 2, is the
 * tolerance, in IDA's weighted max norm (0: IDA's own choice, when q'' = 0). IDA's own choice,
 * h |y'| within the tolerance, is far smaller at tight tolerances, and there GGL's Newton
 * fails: its index-2 iteration matrix has a condition growing as 1/h^2 (the four-bar at rtol
 * 1e-10: IDA_CONV_FAIL at t = 0 with h = 3e-19). */
static double first_step(const run *r, const idaref_options *o) {
  const double *q = N_VGetArrayPointer(r->ida.yy);
  const double *qdd = N_VGetArrayPointer(r->ida.yp) + r->m.n_q;
  double worst = 0.0;
  for (size_t j = 0; j < r->m.n_q; j++)
    worst = fmax(worst, fabs(qdd[j]) / (o->rtol * fabs(q[j]) + o->atol));
  return worst > 0.0 ? sqrt(2.0 / worst) : 0.0;
}

static int configure(run *r, double t0, const idaref_options *o, idaref_result *res) {
  void *mem = r->ida.mem;
  if (idaref_failed(res, IDASetErrHandlerFn(mem, idaref_error_handler, res),
                    "IDASetErrHandlerFn") ||
      idaref_failed(res, IDAInit(mem, residual_cb, t0, r->ida.yy, r->ida.yp), "IDAInit") ||
      idaref_failed(res, IDASetUserData(mem, r), "IDASetUserData") ||
      idaref_failed(res, set_tolerances(r, o), "IDASVtolerances") ||
      idaref_failed(res, IDASetLinearSolver(mem, r->ida.ls, r->ida.A), "IDASetLinearSolver") ||
      (r->jac && idaref_failed(res, IDASetJacFn(mem, klu_jacobian_cb), "IDASetJacFn")) ||
      idaref_failed(res, IDASetId(mem, r->ida.id), "IDASetId") ||
      idaref_failed(res, IDASetMaxNumSteps(mem, o->max_steps), "IDASetMaxNumSteps"))
    return -1;
  /* lambda (and nu) out of the error test: they are functions of (q, v), as accurate as those
   * to the Newton tolerance; their own BDF error estimate, lambda changing much faster than q
   * on a mechanism, only costs steps (index 1: the four-bar's steps fall from 20000 to 2400) */
  if (idaref_failed(res, IDASetSuppressAlg(mem, SUNTRUE), "IDASetSuppressAlg") ||
      idaref_failed(res, IDASetInitStep(mem, first_step(r, o)), "IDASetInitStep"))
    return -1;
  r->configured = 1;
  return 0;
}

/* the rows as the caller wants them: (t, q, v, lambda) */
typedef struct emit_ctx {
  const run *r;
  idambs_row_fn row;
  void *ctx;
} emit_ctx;

static int emit(double t, const double *y, void *data) {
  const emit_ctx *e = data;
  size_t nq = e->r->m.n_q;
  return e->row(t, y, y + nq, y + 2 * nq, e->ctx);
}

/* Why the request is not served, or NULL. */
static const char *refusal(const sdae_mbs *sys, idambs_form form, idambs_solver solver) {
  const char *why = index1_refused(sys);
  if (why || solver == IDAMBS_DENSE) return why;
  if (solver != IDAMBS_KLU) return "unknown linear solver";
  if (form != IDAMBS_INDEX1) return "KLU serves the index1 form only (no GGL iteration matrix)";
  if (!sys->mass_pattern || !sys->jacobian_pattern)
    return "KLU needs mass_pattern and jacobian_pattern (the dense solver takes the rest)";
  return NULL;
}

int idambs_solve(const sdae_mbs *sys, idambs_form form, double t0, const double *q0,
                 const double *v0, const idaref_options *o, idambs_row_fn row, void *ctx,
                 idaref_result *res) {
  return idambs_solve_with(sys, form, IDAMBS_DENSE, t0, q0, v0, o, row, ctx, res);
}

int idambs_solve_with(const sdae_mbs *sys, idambs_form form, idambs_solver solver, double t0,
                      const double *q0, const double *v0, const idaref_options *o,
                      idambs_row_fn row, void *ctx, idaref_result *res) {
  run r = {0};
  klu_jac jac = {0};
  int status = IDAREF_IDA_FAILED, created;
  const char *why = refusal(sys, form, solver);
  memset(res, 0, sizeof *res);
  res->t_reached = t0;
  emit_ctx e = {&r, row, ctx};
  if (why) {
    res->function = "idambs_solve_with";
    snprintf(res->flag_name, sizeof res->flag_name, "unsupported");
    snprintf(res->message, sizeof res->message, "%s", why);
    return IDAMBS_UNSUPPORTED;
  }
  if (mech_init(&r.m, sys, form, solver == IDAMBS_DENSE) != 0 ||
      (solver == IDAMBS_KLU && klu_jac_init(r.jac = &jac, sys) != 0)) {
    idaref_failed(res, IDA_MEM_FAIL, "calloc");
    klu_jac_free(&jac);
    mech_free(&r.m);
    return status;
  }
  created = r.jac ? klu_ida_create(&r, idambs_dim(sys, form), res)
                  : idaref_ida_create(&r.ida, idambs_dim(sys, form), res);
  if (created == 0) {
    if (consistent_start(&r, t0, q0, v0, res) != 0)
      status = IDAMBS_START_FAILED;
    else if (configure(&r, t0, o, res) == 0)
      status = idaref_march(&r.ida, t0, o, emit, &e, res);
  }
  if (status == IDAREF_IDA_FAILED && jac.refused)
    snprintf(res->message, sizeof res->message,
             "KLU matrix: M or F of coordinate %zu depends on a coordinate outside its structure "
             "(the check's row off by %.2g; ida_mbs.h): use the dense solver",
             jac.worst_row, jac.worst);
  if (r.configured) {
    idaref_collect_stats(r.ida.mem, &res->stats);
    res->stats.lin_res_evals += jac.res_evals;
  }
  klu_jac_free(&jac); /* its vector before the context */
  idaref_ida_destroy(&r.ida);
  mech_free(&r.m);
  return status;
}

static const char *klu_refused(const sdae_mbs *sys) {
  return refusal(sys, IDAMBS_INDEX1, IDAMBS_KLU);
}

int idambs_klu_structure(const sdae_mbs *sys, size_t *n, size_t *nnz, size_t *groups) {
  klu_jac k = {0};
  int rc = klu_refused(sys) || klu_jac_init(&k, sys) != 0 ? -1 : 0;
  if (rc == 0) *n = k.a.cols, *nnz = k.a.nnz, *groups = k.groups;
  klu_jac_free(&k);
  return rc;
}

int idambs_klu_matrix(const sdae_mbs *sys, double t, const double *y, const double *yp, double cj,
                      double *J, double *outside) {
  size_t n = idambs_dim(sys, IDAMBS_INDEX1);
  klu_jac k = {0};
  double *work = NULL;
  mech m;
  int rc = -1;
  if (klu_refused(sys) || mech_init(&m, sys, IDAMBS_INDEX1, 0) != 0) return -1;
  if (klu_jac_init(&k, sys) == 0 && (work = malloc((4 * n + k.a.nnz) * sizeof *work))) {
    double *r0 = work, *yk = r0 + n, *ypk = yk + n, *rk = ypk + n, *val = rk + n;
    for (size_t j = 0; j < n; j++)
      k.inc[j] = (y[j] + sqrt(DBL_EPSILON) * fmax(fabs(y[j]), 1.0)) - y[j];
    if (residual(&m, t, y, yp, r0) == 0 &&
        grouped_differences(&m, &k, t, cj, y, yp, r0, yk, ypk, rk, val) == 0) {
      memset(J, 0, n * n * sizeof *J);
      for (size_t j = 0; j < n; j++)
        for (sunindextype p = k.a.colptr[j]; p < k.a.colptr[j + 1]; p++)
          J[(size_t)k.a.rowind[p] * n + j] = val[p];
      *outside = k.worst;
      rc = 0;
    }
  }
  free(work);
  klu_jac_free(&k);
  mech_free(&m);
  return rc;
}
