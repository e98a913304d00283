/* neighbours: grid, Z-order sorting and neighbour lists (see neighbours.h). */
#include "core/sl_morton.h"
#include "neighbours/neighbours.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <math.h>
#include <omp.h>
#if defined(__AVX512F__)
#include <immintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

/* ---- grid set-up ---- */

typedef struct cell_key {
    uint64_t morton;
    uint32_t linear;
} cell_key;

static int cmp_cell_key(const void *a, const void *b)
{
    const cell_key *x = a, *y = b;
    return (x->morton > y->morton) - (x->morton < y->morton);
}

void nbr_grid_init(nbr_grid *g, const double lo[3], const double hi[3], double h,
                   size_t max_cells)
{
    memset(g, 0, sizeof *g);
    double cell = h / NBR_CELLS_PER_H;
    for (;;) {
        size_t total = 1;
        for (int d = 0; d < 3; d++) {
            double len = hi[d] - lo[d];
            g->nc[d] = (int)ceil(len / cell) + 1;
            if (g->nc[d] < 1) g->nc[d] = 1;
            total *= (size_t)g->nc[d];
        }
        if (total <= max_cells || total < 64) { g->ncells = total; break; }
        cell *= 1.25;
    }
    if (cell > h / NBR_CELLS_PER_H * 1.0000001)
        sl_warning("neighbour grid: scene too large for %zu cells of size h; "
                   "using cells of %g (h = %g): search is slower", max_cells, cell, h);
    for (int d = 0; d < 3; d++) g->lo[d] = lo[d];
    g->cell = cell;
    g->inv_cell = 1.0 / cell;
    g->reach = (int)ceil(h / cell - 1e-9);
    g->h2 = h * h;
    /* Rows of cells along x stay contiguous (so that the three cells of a
     * neighbourhood row form one particle range); the rows are ordered by
     * the Morton code of (cy, cz). */
    size_t nrows = (size_t)g->nc[1] * (size_t)g->nc[2];
    cell_key *keys = sl_malloc(nrows * sizeof *keys, "grid row order");
    for (int cz = 0; cz < g->nc[2]; cz++)
        for (int cy = 0; cy < g->nc[1]; cy++) {
            size_t row = (size_t)cy + (size_t)g->nc[1] * (size_t)cz;
            keys[row].linear = (uint32_t)row;
            keys[row].morton = sl_morton_spread3((uint64_t)cy) | sl_morton_spread3((uint64_t)cz) << 1;
        }
    qsort(keys, nrows, sizeof *keys, cmp_cell_key);
    g->rank = sl_alloc_aligned(g->ncells * sizeof *g->rank, "grid ranks");
    for (size_t k = 0; k < nrows; k++)
        for (int cx = 0; cx < g->nc[0]; cx++)
            g->rank[(size_t)cx + (size_t)g->nc[0] * keys[k].linear] =
                (uint32_t)(k * (size_t)g->nc[0] + (size_t)cx);
    free(keys);
    g->fstart = sl_alloc_aligned((g->ncells + 1) * sizeof *g->fstart, "grid cells");
    g->bstart = sl_alloc_aligned((g->ncells + 1) * sizeof *g->bstart, "grid cells");
    g->count = sl_alloc_aligned((g->ncells + 1) * sizeof *g->count, "grid cells");
}

void nbr_grid_free(nbr_grid *g)
{
    sl_free_aligned(g->rank);
    sl_free_aligned(g->fstart);
    sl_free_aligned(g->bstart);
    sl_free_aligned(g->count);
    sl_free_aligned(g->perm);
    sl_free_aligned(g->bcell);
    sl_free_aligned(g->bperm);
    memset(g, 0, sizeof *g);
}

static inline int clamp_cell(double v, double lo, double inv, int n)
{
    double c = floor((v - lo) * inv);
    if (!(c >= 0.0)) c = 0.0; /* also catches NaN */
    if (c > (double)(n - 1)) c = (double)(n - 1);
    return (int)c;
}

static inline void cell_of(const nbr_grid *g, double x, double y, double z, int c[3])
{
    c[0] = clamp_cell(x, g->lo[0], g->inv_cell, g->nc[0]);
    c[1] = clamp_cell(y, g->lo[1], g->inv_cell, g->nc[1]);
    c[2] = clamp_cell(z, g->lo[2], g->inv_cell, g->nc[2]);
}

static inline uint32_t rank_of(const nbr_grid *g, const int c[3])
{
    size_t lin = (size_t)c[0] + (size_t)g->nc[0] * ((size_t)c[1] + (size_t)g->nc[1] * (size_t)c[2]);
    return g->rank[lin];
}

uint32_t nbr_cell_rank(const nbr_grid *g, double x, double y, double z)
{
    int c[3];
    cell_of(g, x, y, z, c);
    return rank_of(g, c);
}

/* Counting sort of n particles by cell rank: fills start (ncells + 1) and
 * perm (new index -> old index).  Stable, hence deterministic. */
static void sort_by_cell(nbr_grid *g, size_t n, const double *x, const double *y,
                         const double *z, uint32_t *cellv, uint32_t *start, uint32_t *perm)
{
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        int c[3];
        cell_of(g, x[i], y[i], z[i], c);
        cellv[i] = rank_of(g, c);
    }
    memset(g->count, 0, (g->ncells + 1) * sizeof *g->count);
    for (size_t i = 0; i < n; i++) g->count[cellv[i] + 1]++;
    start[0] = 0;
    for (size_t k = 0; k < g->ncells; k++) start[k + 1] = start[k] + g->count[k + 1];
    memcpy(g->count, start, g->ncells * sizeof *g->count);
    for (size_t i = 0; i < n; i++) perm[g->count[cellv[i]]++] = (uint32_t)i;
}

/* Within each cell, order the particles (perm: new -> old index) by id
 * (insertion sort: the previous step's order is nearly sorted already).
 * The key (cell, id) fixes the order, and so every neighbour order and
 * every sum, whatever the order the particles came in: the history of
 * moves, a restart, or another rank's numbering. */
static void order_cells_by_id(const nbr_grid *g, const uint32_t *start, uint32_t *perm,
                              const uint32_t *id)
{
#pragma omp parallel for schedule(dynamic, 256)
    for (size_t k = 0; k < g->ncells; k++) {
        uint32_t *seg = perm + start[k];
        uint32_t len = start[k + 1] - start[k];
        for (uint32_t a = 1; a < len; a++) {
            uint32_t v = seg[a], c = a;
            while (c > 0 && id[seg[c - 1]] > id[v]) { seg[c] = seg[c - 1]; c--; }
            seg[c] = v;
        }
    }
}

void nbr_sort_boundary(nbr_grid *g, sl_boundary *b)
{
    if (g->bperm_cap < b->n) { /* once: moving bodies re-sort every step */
        sl_free_aligned(g->bcell);
        sl_free_aligned(g->bperm);
        g->bcell = sl_alloc_aligned(b->n * sizeof *g->bcell, "boundary cells");
        g->bperm = sl_alloc_aligned(b->n * sizeof *g->bperm, "boundary permutation");
        g->bperm_cap = b->n;
    }
    sort_by_cell(g, b->n, b->x, b->y, b->z, g->bcell, g->bstart, g->bperm);
    /* within a cell, by creation index: restarts of moving scenes stay
     * bit-identical */
    order_cells_by_id(g, g->bstart, g->bperm, b->id);
    prt_boundary_permute(b, g->bperm);
}

void nbr_sort_fluid(nbr_grid *g, sl_fluid *f)
{
    if (g->perm_cap < f->cap) {
        sl_free_aligned(g->perm);
        g->perm = sl_alloc_aligned(f->cap * sizeof *g->perm, "fluid permutation");
        g->perm_cap = f->cap;
    }
    sort_by_cell(g, f->n, f->x, f->y, f->z, f->cell, g->fstart, g->perm);
    /* key (cell, global id): the order does not depend on the previous one */
    order_cells_by_id(g, g->fstart, g->perm, f->id);
    prt_fluid_permute(f, g->perm);
}

/* ---- neighbour lists ---- */

void nbr_list_init(nbr_list *l) { memset(l, 0, sizeof *l); }

void nbr_list_free(nbr_list *l)
{
    sl_free_aligned(l->start);
    sl_free_aligned(l->idx);
    for (int t = 0; t < l->nthreads; t++) free(l->tbuf[t]);
    free(l->tbuf);
    free(l->tcap);
    free(l->tlen);
    memset(l, 0, sizeof *l);
}

static void list_prepare(nbr_list *l, size_t rows)
{
    int nt = omp_get_max_threads();
    if (rows + 1 > l->rows_cap) {
        sl_free_aligned(l->start);
        l->rows_cap = rows + 1 + rows / 4;
        l->start = sl_alloc_aligned(l->rows_cap * sizeof *l->start, "neighbour list rows");
    }
    if (nt > l->nthreads) {
        l->tbuf = sl_realloc(l->tbuf, (size_t)nt * sizeof *l->tbuf, "neighbour buffers");
        l->tcap = sl_realloc(l->tcap, (size_t)nt * sizeof *l->tcap, "neighbour buffers");
        l->tlen = sl_realloc(l->tlen, (size_t)nt * sizeof *l->tlen, "neighbour buffers");
        for (int t = l->nthreads; t < nt; t++) {
            l->tbuf[t] = NULL;
            l->tcap[t] = 0;
        }
        l->nthreads = nt;
    }
    for (int t = 0; t < l->nthreads; t++) l->tlen[t] = 0;
    l->n = rows;
}

/* Make room for `extra` more entries in thread t's buffer. */
static inline void buf_reserve(nbr_list *l, int t, size_t extra)
{
    if (l->tlen[t] + extra > l->tcap[t]) {
        size_t cap = 2 * (l->tlen[t] + extra) + 4096;
        l->tbuf[t] = sl_realloc(l->tbuf[t], cap * sizeof *l->tbuf[t], "neighbour buffer");
        l->tcap[t] = cap;
    }
}

/* Append to buf (at len) the indices j in [j0, j1) with |p - x_j|^2 < h2,
 * j != self; returns the new length.  The candidates are contiguous in
 * memory, so the distance test runs on vectors of them (AVX-512: with a
 * compress-store of the accepted indices). */
static inline size_t filter_range(uint32_t *restrict buf, size_t len, uint32_t j0, uint32_t j1,
                                  uint32_t self, double px, double py, double pz,
                                  const double *restrict tx, const double *restrict ty,
                                  const double *restrict tz, double h2)
{
    uint32_t j = j0;
#if defined(__AVX512F__) && defined(__AVX512VL__)
    const __m512d vpx = _mm512_set1_pd(px), vpy = _mm512_set1_pd(py), vpz = _mm512_set1_pd(pz);
    const __m512d vh2 = _mm512_set1_pd(h2);
    const __m256i step = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i vself = _mm256_set1_epi32((int)self);
    for (; j + 8 <= j1; j += 8) {
        __m512d dx = _mm512_sub_pd(vpx, _mm512_loadu_pd(tx + j));
        __m512d dy = _mm512_sub_pd(vpy, _mm512_loadu_pd(ty + j));
        __m512d dz = _mm512_sub_pd(vpz, _mm512_loadu_pd(tz + j));
        __m512d d2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
        __m256i idx = _mm256_add_epi32(_mm256_set1_epi32((int)j), step);
        __mmask8 keep = _mm512_cmp_pd_mask(d2, vh2, _CMP_LT_OQ) &
                        (__mmask8)~_mm256_cmpeq_epi32_mask(idx, vself);
        _mm256_mask_compressstoreu_epi32(buf + len, keep, idx);
        len += (size_t)__builtin_popcount(keep);
    }
#endif
    for (; j < j1; j++) {
        const double dx = px - tx[j], dy = py - ty[j], dz = pz - tz[j];
        buf[len] = j;
        len += (dx * dx + dy * dy + dz * dz < h2) & (j != self);
    }
    return len;
}

/* Appends to thread t's buffer the particles of the target set within h of
 * (px, py, pz), skipping index `self`; returns how many were appended.
 * The three cells of each neighbourhood row along x are one contiguous
 * range; candidates are written unconditionally and kept by advancing the
 * length (branch-free compaction). */
static uint32_t gather(const nbr_grid *g, nbr_list *l, int t, const uint32_t *start,
                       const double *tx, const double *ty, const double *tz,
                       double px, double py, double pz, uint32_t self)
{
    int c[3];
    const size_t len0 = l->tlen[t];
    cell_of(g, px, py, pz, c);
    const int R = g->reach;
    const int x0 = c[0] > R ? c[0] - R : 0, x1 = c[0] + R < g->nc[0] ? c[0] + R : g->nc[0] - 1;
    const int y0 = c[1] > R ? c[1] - R : 0, y1 = c[1] + R < g->nc[1] ? c[1] + R : g->nc[1] - 1;
    const int z0 = c[2] > R ? c[2] - R : 0, z1 = c[2] + R < g->nc[2] ? c[2] + R : g->nc[2] - 1;
    for (int cz = z0; cz <= z1; cz++) {
        for (int cy = y0; cy <= y1; cy++) {
            int a[3] = {x0, cy, cz}, b[3] = {x1, cy, cz};
            const uint32_t j0 = start[rank_of(g, a)], j1 = start[rank_of(g, b) + 1];
            buf_reserve(l, t, j1 - j0);
            l->tlen[t] = filter_range(l->tbuf[t], l->tlen[t], j0, j1, self, px, py, pz, tx, ty,
                                      tz, g->h2);
        }
    }
    return (uint32_t)(l->tlen[t] - len0);
}

/* Both rows of fluid particle i in one sweep over its cells: fluid
 * neighbours into l (thread t) and boundary neighbours into lb. */
static void gather_both(const nbr_grid *g, nbr_list *l, nbr_list *lb, int t, const sl_fluid *f,
                        const sl_boundary *b, uint32_t i)
{
    int c[3];
    const double px = f->x[i], py = f->y[i], pz = f->z[i];
    const size_t len0 = l->tlen[t], blen0 = lb->tlen[t];
    cell_of(g, px, py, pz, c);
    const int R = g->reach;
    const int x0 = c[0] > R ? c[0] - R : 0, x1 = c[0] + R < g->nc[0] ? c[0] + R : g->nc[0] - 1;
    const int y0 = c[1] > R ? c[1] - R : 0, y1 = c[1] + R < g->nc[1] ? c[1] + R : g->nc[1] - 1;
    const int z0 = c[2] > R ? c[2] - R : 0, z1 = c[2] + R < g->nc[2] ? c[2] + R : g->nc[2] - 1;
    for (int cz = z0; cz <= z1; cz++)
        for (int cy = y0; cy <= y1; cy++) {
            int a[3] = {x0, cy, cz}, e[3] = {x1, cy, cz};
            const uint32_t ka = rank_of(g, a), ke = rank_of(g, e) + 1;
            uint32_t j0 = g->fstart[ka], j1 = g->fstart[ke];
            buf_reserve(l, t, j1 - j0);
            l->tlen[t] = filter_range(l->tbuf[t], l->tlen[t], j0, j1, i, px, py, pz, f->x, f->y,
                                      f->z, g->h2);
            if (g->hstart && f->nhalo) { /* halo copies of the row's cells */
                j0 = g->hstart[ka];
                j1 = g->hstart[ke];
                buf_reserve(l, t, j1 - j0);
                l->tlen[t] = filter_range(l->tbuf[t], l->tlen[t], j0, j1, i, px, py, pz, f->x,
                                          f->y, f->z, g->h2);
            }
            j0 = g->bstart[ka];
            j1 = g->bstart[ke];
            if (j1 > j0) {
                buf_reserve(lb, t, j1 - j0);
                lb->tlen[t] = filter_range(lb->tbuf[t], lb->tlen[t], j0, j1, UINT32_MAX, px, py,
                                           pz, b->x, b->y, b->z, g->h2);
            }
        }
    l->start[i + 1] = (uint32_t)(l->tlen[t] - len0);
    lb->start[i + 1] = (uint32_t)(lb->tlen[t] - blen0);
}

/* Concatenate the thread buffers (thread order = particle order). */
static void list_finish(nbr_list *l)
{
    size_t total = 0;
    for (int t = 0; t < l->nthreads; t++) total += l->tlen[t];
    if (total > UINT32_MAX) sl_fatal("neighbour list exceeds 2^32 entries");
    if (total > l->idx_cap) {
        sl_free_aligned(l->idx);
        l->idx_cap = total + total / 4;
        l->idx = sl_alloc_aligned(l->idx_cap * sizeof *l->idx, "neighbour list");
    }
    size_t off = 0;
    for (int t = 0; t < l->nthreads; t++) {
        if (l->tlen[t]) memcpy(l->idx + off, l->tbuf[t], l->tlen[t] * sizeof *l->idx);
        off += l->tlen[t];
    }
    /* start[] holds counts in rows 1..n; turn them into offsets. */
    l->start[0] = 0;
    for (size_t i = 0; i < l->n; i++) l->start[i + 1] += l->start[i];
}

/* Rows are split into one contiguous block per thread. */
#define FOR_ROWS_BY_THREAD(l, rows, body)                                     \
    _Pragma("omp parallel") {                                                 \
        int t_ = omp_get_thread_num(), nt_ = omp_get_num_threads();           \
        size_t lo_ = (rows) * (size_t)t_ / (size_t)nt_;                       \
        size_t hi_ = (rows) * (size_t)(t_ + 1) / (size_t)nt_;                 \
        for (size_t i = lo_; i < hi_; i++) { body }                           \
    }

void nbr_build_ff(const nbr_grid *g, const sl_fluid *f, nbr_list *l)
{
    list_prepare(l, f->n);
    FOR_ROWS_BY_THREAD(l, f->n, {
        l->start[i + 1] = gather(g, l, t_, g->fstart, f->x, f->y, f->z,
                                 f->x[i], f->y[i], f->z[i], (uint32_t)i);
    })
    list_finish(l);
}

void nbr_build_fluid(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *ff,
                     nbr_list *fb)
{
    const size_t rows = f->n + f->nhalo;
    list_prepare(ff, rows);
    list_prepare(fb, rows);
    FOR_ROWS_BY_THREAD(ff, rows, { gather_both(g, ff, fb, t_, f, b, (uint32_t)i); })
    list_finish(ff);
    list_finish(fb);
}

void nbr_build_fb(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *l)
{
    list_prepare(l, f->n);
    FOR_ROWS_BY_THREAD(l, f->n, {
        l->start[i + 1] = gather(g, l, t_, g->bstart, b->x, b->y, b->z,
                                 f->x[i], f->y[i], f->z[i], UINT32_MAX);
    })
    list_finish(l);
}

/* True when some fluid particle sits in the cells within reach of (x, y, z). */
static int fluid_nearby(const nbr_grid *g, double x, double y, double z)
{
    int c[3];
    cell_of(g, x, y, z, c);
    const int R = g->reach;
    const int x0 = c[0] > R ? c[0] - R : 0, x1 = c[0] + R < g->nc[0] ? c[0] + R : g->nc[0] - 1;
    for (int cz = c[2] - R; cz <= c[2] + R; cz++) {
        if (cz < 0 || cz >= g->nc[2]) continue;
        for (int cy = c[1] - R; cy <= c[1] + R; cy++) {
            if (cy < 0 || cy >= g->nc[1]) continue;
            int a[3] = {x0, cy, cz}, b[3] = {x1, cy, cz};
            if (g->fstart[rank_of(g, b) + 1] > g->fstart[rank_of(g, a)]) return 1;
        }
    }
    return 0;
}

void nbr_build_bf(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *l,
                  uint32_t *active, size_t *nactive)
{
    list_prepare(l, b->n);
    FOR_ROWS_BY_THREAD(l, b->n, {
        l->start[i + 1] = fluid_nearby(g, b->x[i], b->y[i], b->z[i])
                              ? gather(g, l, t_, g->fstart, f->x, f->y, f->z,
                                       b->x[i], b->y[i], b->z[i], UINT32_MAX)
                              : 0;
    })
    size_t na = 0;
    for (size_t i = 0; i < b->n; i++)
        if (l->start[i + 1] > 0) active[na++] = (uint32_t)i;
    *nactive = na;
    list_finish(l);
}

void nbr_transpose(const nbr_list *fb, size_t nb, nbr_list *bf, uint32_t *active, size_t *nactive)
{
    list_prepare(bf, nb);
    size_t total = nbr_list_size(fb);
    if (total > bf->idx_cap) {
        sl_free_aligned(bf->idx);
        bf->idx_cap = total + total / 4;
        bf->idx = sl_alloc_aligned(bf->idx_cap * sizeof *bf->idx, "neighbour list");
    }
    uint32_t *restrict st = bf->start;
    memset(st, 0, (nb + 1) * sizeof *st);
    for (size_t q = 0; q < total; q++) st[fb->idx[q] + 1]++;
    size_t na = 0;
    for (size_t b = 0; b < nb; b++) {
        if (st[b + 1]) active[na++] = (uint32_t)b;
        st[b + 1] += st[b];
    }
    *nactive = na;
    /* fill: rows in ascending fluid index; st[b] walks to the row's end */
    for (size_t i = 0; i < fb->n; i++)
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) bf->idx[st[fb->idx[q]]++] = (uint32_t)i;
    for (size_t b = nb; b > 0; b--) st[b] = st[b - 1];
    st[0] = 0;
}

void nbr_build_bb(const nbr_grid *g, const sl_boundary *b, nbr_list *l)
{
    list_prepare(l, b->n);
    FOR_ROWS_BY_THREAD(l, b->n, {
        l->start[i + 1] = gather(g, l, t_, g->bstart, b->x, b->y, b->z,
                                 b->x[i], b->y[i], b->z[i], UINT32_MAX);
    })
    list_finish(l);
}
