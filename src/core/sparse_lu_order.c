/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The rows' orders the wide sparse LU tries (core/sparse_lu.h), each from A's pattern alone.
 * Row r's elimination takes out the earlier rows whose pivot columns it holds, so the fill is
 * that of the row-merge tree; which order keeps it least depends on the topology, measured
 * (docs/performance.md): the leaves first is fill-free on chains and trees; on a mesh, AMD's
 * minimum degree on the graph of A A^T (COLAMD's idea, an order of A^T A's columns from A
 * alone, on A^T) keeps L and U near A's nonzeros; on long loops (a ladder, a closed rope) only a
 * shallow tree does, nested dissection's, for a column no row pivots on is carried through every
 * row above it in the tree. AMD by amd_l2, which takes every array from the caller and is linked
 * already (core/sparse_ldl.c); the dissection George's automatic one (SPARSPAK's GENND), as
 * nothing linked orders by dissection (METIS, which CHOLMOD calls, allocates). A column held by
 * many rows (a hub: a cart under k pendulums) would join them all; it is left out of the graph,
 * as COLAMD leaves out dense rows. */
#include <stdint.h>
#include <string.h>

#include <amd.h>
#include <stabdae/stabdae.h>

#include "sparse_lu.h"

typedef SuiteSparse_long sslong;

/* A's pattern, its transpose (the rows holding each column: at[n + 1], rows[nnz]) and the room
 * after them, which each order takes as its own workspace */
typedef struct orders_work {
  const sdae_pattern *A;
  size_t m, n, room;
  sslong *at, *rows, *rest;
} orders_work;

static void transpose(orders_work *w) {
  const sdae_pattern *A = w->A;
  sslong *at = w->at;
  memset(at, 0, (w->n + 1) * sizeof *at);
  for (size_t e = 0; e < A->nnz; e++) at[A->col[e] + 1]++;
  for (size_t c = 0; c < w->n; c++) at[c + 1] += at[c];
  for (size_t r = 0; r < w->m; r++) /* at[c] moves on as column c's rows are written */
    for (size_t e = A->row_start[r]; e < A->row_start[r + 1]; e++)
      w->rows[at[A->col[e]]++] = (sslong)r;
  for (size_t c = w->n; c > 0; c--) at[c] = at[c - 1]; /* each back at its column's start */
  at[0] = 0;
}

/* rows holding column c */
static size_t held(const orders_work *w, size_t c) { return (size_t)(w->at[c + 1] - w->at[c]); }

/* ---- the leaves first ---- */

typedef struct leaves_work {
  const orders_work *w;
  sslong *count, *queue, *done; /* n, 2 n (a column leaves one row at most twice), m */
  size_t n_queue;
} leaves_work;

/* row r placed: its columns' counts of the rows left, and a column it leaves to one row
 * queues that row */
static void taken(leaves_work *l, size_t r) {
  const sdae_pattern *A = l->w->A;
  l->done[r] = 1;
  for (size_t e = A->row_start[r]; e < A->row_start[r + 1]; e++) l->count[A->col[e]]--;
  for (size_t e = A->row_start[r]; e < A->row_start[r + 1]; e++) {
    size_t c = A->col[e];
    if (l->count[c] != 1) continue;
    for (sslong k = l->w->at[c]; k < l->w->at[c + 1]; k++)
      if (!l->done[l->w->rows[k]]) l->queue[l->n_queue++] = l->w->rows[k];
  }
}

/* a queued leaf not placed yet into *r: 1, or 0 when none is queued */
static int next_leaf(leaves_work *l, size_t *r) {
  while (l->n_queue > 0) {
    *r = (size_t)l->queue[--l->n_queue];
    if (!l->done[*r]) return 1;
  }
  return 0;
}

/* A row holding a column no other row left holds (a leaf) whenever there is one: it pivots
 * there, and no row after it takes it out. When none is (every column left is held by two
 * rows or more: a closed loop), the first row not yet placed is set aside for the end, counted
 * out as if placed, which opens the loop into a chain with leaves; the rows set aside come
 * last (the first of them last), each eliminating through its loop. */
static void leaves(const orders_work *w, size_t *order) {
  leaves_work l = {w, w->rest, w->rest + w->n, w->rest + 3 * w->n, 0};
  size_t first = 0, placed = 0, aside = w->m;
  for (size_t c = 0; c < w->n; c++) {
    l.count[c] = (sslong)held(w, c);
    if (l.count[c] == 1) l.queue[l.n_queue++] = w->rows[w->at[c]];
  }
  for (size_t r = 0; r < w->m; r++) l.done[r] = 0;
  while (placed < aside) {
    size_t r;
    if (next_leaf(&l, &r)) {
      order[placed++] = r;
    } else {
      while (l.done[first]) first++;
      r = first, order[--aside] = r;
    }
    taken(&l, r);
  }
}

/* ---- the graph of A A^T ---- */

/* The graph over the columns held by at most hub rows: row r's neighbours written from
 * adj[pe[r]] (len[r] of them; adj NULL: only counted), mark's stamps keeping each once.
 * Returns the entries, all rows'. */
static size_t graph(const orders_work *w, size_t hub, sslong *mark, sslong *pe, sslong *len,
                    sslong *adj) {
  const sdae_pattern *A = w->A;
  size_t nz = 0;
  for (size_t r = 0; r < w->m; r++) mark[r] = -1;
  for (size_t r = 0; r < w->m; r++) {
    if (adj) pe[r] = (sslong)nz;
    mark[r] = (sslong)r;
    for (size_t e = A->row_start[r]; e < A->row_start[r + 1]; e++) {
      size_t c = A->col[e];
      if (held(w, c) > hub) continue;
      for (sslong k = w->at[c]; k < w->at[c + 1]; k++)
        if (mark[w->rows[k]] != (sslong)r) {
          mark[w->rows[k]] = (sslong)r;
          if (adj) adj[nz] = w->rows[k];
          nz++;
        }
    }
    if (adj) len[r] = (sslong)nz - pe[r];
  }
  return nz;
}

/* the graph in room entries (with extra of them to spare per row and a fifth of its own):
 * the hubs' bound halved until it fits, at 1 no entry; returns its entries */
static size_t fitted_graph(const orders_work *w, size_t room, size_t extra, sslong *mark,
                           sslong *pe, sslong *len, sslong *adj) {
  size_t hub = SDAE_SPARSE_LU_HUB;
  for (; hub > 1; hub /= 2) {
    size_t nz = graph(w, hub, mark, pe, len, NULL);
    if (nz + nz / 5 + extra * w->m <= room) break;
  }
  return graph(w, hub, mark, pe, len, adj);
}

/* ---- minimum degree ---- */

/* AMD's order of the graph: its arrays (mark, Pe, Len, Nv, Next, Last, Head, Elen, Degree, W:
 * m each), then Iw, the graph with a fifth more and m to work in, as amd_order gives it */
static void minimum_degree(const orders_work *w, size_t *order) {
  size_t m = w->m, nz;
  sslong *mark = w->rest, *Pe = mark + m, *Len = Pe + m, *Nv = Len + m, *Next = Nv + m;
  sslong *Last = Next + m, *Head = Last + m, *Elen = Head + m, *Degree = Elen + m, *W = Degree + m;
  sslong *Iw = W + m;
  double control[AMD_CONTROL], info[AMD_INFO];
  nz = fitted_graph(w, w->room - 10 * m, 1, mark, Pe, Len, Iw);
  amd_l_defaults(control);
  amd_l2((sslong)m, Pe, Iw, Len, (sslong)(w->room - 10 * m), (sslong)nz, Nv, Next, Last, Head, Elen,
         Degree, W, control, info);
  for (size_t k = 0; k < m; k++) order[k] = (size_t)Last[k];
}

/* ---- nested dissection (George's automatic one, SPARSPAK's GENND) ---- */

typedef struct nd_graph {
  const sslong *pe, *len, *adj;
  sslong *live, *xls, *ls, *next_level; /* m each (xls m + 1) */
} nd_graph;

/* the rooted level structure of root's component among the live nodes: ls by level, level l
 * from xls[l]; returns the levels */
static size_t rooted_levels(nd_graph *g, sslong root) {
  size_t nl = 0, end = 1, beg = 0;
  g->ls[0] = root, g->live[root] = 0;
  while (beg < end) {
    size_t lend = end;
    g->xls[nl++] = (sslong)beg;
    for (size_t k = beg; k < lend; k++) {
      sslong u = g->ls[k];
      for (sslong e = g->pe[u]; e < g->pe[u] + g->len[u]; e++)
        if (g->live[g->adj[e]]) g->live[g->adj[e]] = 0, g->ls[end++] = g->adj[e];
    }
    beg = lend;
  }
  g->xls[nl] = (sslong)end;
  for (size_t k = 0; k < end; k++) g->live[g->ls[k]] = 1;
  return nl;
}

/* the live neighbours of u */
static size_t live_degree(const nd_graph *g, sslong u) {
  size_t d = 0;
  for (sslong e = g->pe[u]; e < g->pe[u] + g->len[u]; e++) d += g->live[g->adj[e]] != 0;
  return d;
}

/* a pseudo-peripheral node of root's component (SPARSPAK's FNROOT): the level structure from
 * the last level's node of least degree, while it grows deeper; returns its levels */
static size_t peripheral(nd_graph *g, sslong root) {
  size_t nl = rooted_levels(g, root);
  for (;;) {
    size_t size = (size_t)g->xls[nl], best = size, next;
    if (nl == 1 || nl == size) return nl;
    for (sslong k = g->xls[nl - 1]; k < g->xls[nl]; k++) {
      size_t d = live_degree(g, g->ls[k]);
      if (d < best) best = d, root = g->ls[k];
    }
    next = rooted_levels(g, root);
    if (next <= nl) return next; /* as deep: its eccentricity is at least nl - 1 */
    nl = next;
  }
}

/* The separator of root's component (SPARSPAK's FNDSEP) into sep: the nodes of the middle level
 * of a level structure from a pseudo-peripheral node that have a neighbour in the level after;
 * under three levels, the whole component. Its nodes are no longer live; returns their count. */
static size_t separator(nd_graph *g, sslong root, sslong *sep) {
  size_t nl = peripheral(g, root), ns = 0;
  sslong mid, nb, ne;
  if (nl < 3) {
    for (sslong k = 0; k < g->xls[nl]; k++) sep[ns++] = g->ls[k], g->live[g->ls[k]] = 0;
    return ns;
  }
  mid = (sslong)nl / 2, nb = g->xls[mid + 1], ne = g->xls[mid + 2]; /* mid + 2 <= nl */
  for (sslong k = nb; k < ne; k++) g->next_level[g->ls[k]] = 1;
  for (sslong k = g->xls[mid]; k < nb; k++) {
    sslong u = g->ls[k];
    for (sslong e = g->pe[u]; e < g->pe[u] + g->len[u]; e++)
      if (g->next_level[g->adj[e]]) {
        sep[ns++] = u;
        break;
      }
  }
  for (sslong k = nb; k < ne; k++) g->next_level[g->ls[k]] = 0;
  for (size_t k = 0; k < ns; k++) g->live[sep[k]] = 0;
  return ns;
}

/* Each component's separator numbered from the end, the first found last, until every row
 * is: its arrays (mark, pe, len, live, ls, next_level, sep: m each; xls: m + 1), then the graph */
static void dissection(const orders_work *w, size_t *order) {
  size_t m = w->m, left = m;
  sslong *mark = w->rest, *pe = mark + m, *len = pe + m, *live = len + m, *ls = live + m;
  sslong *nxt = ls + m, *sep = nxt + m, *xls = sep + m, *adj = xls + m + 1;
  nd_graph g = {pe, len, adj, live, xls, ls, nxt};
  fitted_graph(w, w->room - 8 * m - 1, 0, mark, pe, len, adj);
  for (size_t r = 0; r < m; r++) live[r] = 1, nxt[r] = 0;
  for (size_t r = 0; r < m; r++)
    while (live[r]) {
      size_t ns = separator(&g, (sslong)r, sep);
      for (size_t k = 0; k < ns; k++) order[--left] = (size_t)sep[k];
    }
}

/* ---- the bound on L ---- */

/* Row k of L holds the earlier steps whose pivot row k takes out: with the rows in order, the
 * chart's LU is Gaussian elimination on A^T with row interchanges (the pivot columns), whose
 * U lies within the Cholesky factor of A A^T in that order whatever the interchanges (George
 * and Ng). Its strictly lower entries counted by LDL's row subtrees (ldl_symbolic's walk), A
 * A^T's row k being the rows that share a column with A's row order[k]: never formed. */
static size_t cholesky_entries(const orders_work *w, const size_t *order, size_t most, sslong *pos,
                               sslong *parent, sslong *flag) {
  const sdae_pattern *A = w->A;
  size_t entries = 0;
  for (size_t k = 0; k < w->m; k++) pos[order[k]] = (sslong)k;
  for (sslong k = 0; k < (sslong)w->m && entries <= most; k++) {
    size_t r = order[k];
    parent[k] = -1, flag[k] = k;
    for (size_t e = A->row_start[r]; e < A->row_start[r + 1]; e++)
      for (sslong h = w->at[A->col[e]]; h < w->at[A->col[e] + 1]; h++)
        for (sslong i = pos[w->rows[h]]; i < k && flag[i] != k; i = parent[i]) {
          if (parent[i] == -1) parent[i] = k;
          flag[i] = k;
          entries++;
        }
  }
  return entries;
}

size_t sdae__sparse_lu_l_bound(const sdae_pattern *A, size_t m, size_t n, const size_t *order,
                               size_t most, SuiteSparse_long *work) {
  orders_work w = {A, m, n, 0, work, work + n + 1, work + n + 1 + A->nnz};
  transpose(&w);
  return cholesky_entries(&w, order, most, w.rest, w.rest + m, w.rest + 2 * m);
}

/* ---- the orders ---- */

size_t sdae__sparse_lu_orders_min(size_t m, size_t n, size_t nnz) {
  return n + 1 + nnz + 3 * n + 11 * m; /* the leaves' 3 n + m, AMD's 10 m + m */
}

int sdae__sparse_lu_orders(const sdae_pattern *A, size_t m, size_t n, SuiteSparse_long *work,
                           size_t len, size_t *orders) {
  orders_work w = {A, m, n, 0, work, work + n + 1, work + n + 1 + A->nnz};
  if (len < sdae__sparse_lu_orders_min(m, n, A->nnz)) return SDAE_ERR_BUFFER;
  w.room = len - (n + 1 + A->nnz);
  transpose(&w);
  leaves(&w, orders + SDAE_SPARSE_LU_LEAVES * m);
  minimum_degree(&w, orders + SDAE_SPARSE_LU_AMD * m);
  dissection(&w, orders + SDAE_SPARSE_LU_DISSECTION * m);
  return SDAE_OK;
}
