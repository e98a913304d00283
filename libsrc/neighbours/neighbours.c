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
#include <stdio.h>
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

int nbr_unit_setting(void)
{
    const char *e = getenv("SLUICE_GRID_UNIT");
    if (!e || !*e || !strcmp(e, "row")) return 0;
    if (!strcmp(e, "block")) return 4;
    int n = 0;
    char tail = 0;
    if (sscanf(e, "block:%d%c", &n, &tail) == 1 && n >= 2 && n <= 16) return n;
    sl_fatal("SLUICE_GRID_UNIT=%s: row (whole x-rows of cells), block (blocks of 4x4x4 cells) "
             "or block:N (N = 2..16 cells a side)",
             e);
    return 0;
}

const char *nbr_unit_name(const nbr_grid *g, char *buf, size_t len)
{
    if (g->unit[1] == 1 && g->unit[2] == 1 && g->unit[0] == g->nc[0]) snprintf(buf, len, "row");
    else snprintf(buf, len, "block:%d", g->unit[0]);
    return buf;
}

/* The generalised Hilbert curve of a box of any size (Cervený 2018,
 * "gilbert"): a box with a major axis a and two others b, c (vectors from
 * its corner p) is split in halves along the axes long enough to split,
 * and its parts visited in the Hilbert order, each with its axes turned
 * so that the curve enters it where the last one left; a box one cell
 * thick is walked straight.  Each block gets the next number (order[]: the
 * position of the block at linear index bx + mx (by + my bz)); odd sizes
 * may need a diagonal step, never a cell missed or visited twice. */
typedef struct curve {
    int m[3];
    uint32_t *order;
    uint32_t next;
} curve;

static int sgn(int v) { return (v > 0) - (v < 0); }
static int len3(const int v[3]) { return abs(v[0] + v[1] + v[2]); }

static void curve_walk(curve *c, const int p[3], const int a[3])
{
    const int n = len3(a), s[3] = {sgn(a[0]), sgn(a[1]), sgn(a[2])};
    for (int i = 0; i < n; i++) {
        const int x = p[0] + i * s[0], y = p[1] + i * s[1], z = p[2] + i * s[2];
        c->order[(size_t)x + (size_t)c->m[0] * ((size_t)y + (size_t)c->m[1] * (size_t)z)] =
            c->next++;
    }
}

/* q = p + u + v + w (any of them NULL) */
static void add3(int q[3], const int p[3], const int *u, const int *v, const int *w)
{
    for (int k = 0; k < 3; k++) q[k] = p[k] + (u ? u[k] : 0) + (v ? v[k] : 0) + (w ? w[k] : 0);
}

static void curve_box(curve *c, const int p[3], const int a[3], const int b[3], const int e[3])
{
    const int w = len3(a), h = len3(b), d = len3(e);
    if (h == 1 && d == 1) return curve_walk(c, p, a);
    if (w == 1 && d == 1) return curve_walk(c, p, b);
    if (w == 1 && h == 1) return curve_walk(c, p, e);
    int a2[3], b2[3], e2[3], da[3], db[3], de[3];
    for (int k = 0; k < 3; k++) {
        a2[k] = a[k] / 2, b2[k] = b[k] / 2, e2[k] = e[k] / 2;
        da[k] = sgn(a[k]), db[k] = sgn(b[k]), de[k] = sgn(e[k]);
    }
    /* halves of even length where the side allows */
    if (len3(a2) % 2 && w > 2) add3(a2, a2, da, NULL, NULL);
    if (len3(b2) % 2 && h > 2) add3(b2, b2, db, NULL, NULL);
    if (len3(e2) % 2 && d > 2) add3(e2, e2, de, NULL, NULL);
    int ra[3], rb[3], re[3], nb2[3], q[3], t[3];
    for (int k = 0; k < 3; k++) {
        ra[k] = a[k] - a2[k], rb[k] = b[k] - b2[k], re[k] = e[k] - e2[k]; /* the other halves */
        nb2[k] = -b2[k];
    }
    if (2 * w > 3 * h && 2 * w > 3 * d) { /* long: split a only */
        curve_box(c, p, a2, b, e);
        add3(q, p, a2, NULL, NULL);
        curve_box(c, q, ra, b, e);
    } else if (3 * h > 4 * d) { /* split a and b */
        int nra[3];
        for (int k = 0; k < 3; k++) nra[k] = -ra[k], t[k] = a[k] - da[k] + b2[k] - db[k];
        curve_box(c, p, b2, e, a2);
        add3(q, p, b2, NULL, NULL);
        curve_box(c, q, a, rb, e);
        add3(q, p, t, NULL, NULL);
        curve_box(c, q, nb2, e, nra);
    } else if (3 * d > 4 * h) { /* split a and e */
        int nra[3], ne2[3];
        for (int k = 0; k < 3; k++)
            nra[k] = -ra[k], ne2[k] = -e2[k], t[k] = a[k] - da[k] + e2[k] - de[k];
        curve_box(c, p, e2, a2, b);
        add3(q, p, e2, NULL, NULL);
        curve_box(c, q, a, b, re);
        add3(q, p, t, NULL, NULL);
        curve_box(c, q, ne2, nra, b);
    } else { /* split all three: five parts */
        int nra[3], nre[3], ne[3];
        for (int k = 0; k < 3; k++) nra[k] = -ra[k], nre[k] = -re[k], ne[k] = -e[k];
        curve_box(c, p, b2, e2, a2);
        add3(q, p, b2, NULL, NULL);
        curve_box(c, q, e, a2, rb);
        for (int k = 0; k < 3; k++) t[k] = b2[k] - db[k] + e[k] - de[k];
        add3(q, p, t, NULL, NULL);
        curve_box(c, q, a, nb2, nre);
        for (int k = 0; k < 3; k++) t[k] = a[k] - da[k] + b2[k] + e[k] - de[k];
        add3(q, p, t, NULL, NULL);
        curve_box(c, q, ne, nra, rb);
        for (int k = 0; k < 3; k++) t[k] = a[k] - da[k] + b2[k] - db[k];
        add3(q, p, t, NULL, NULL);
        curve_box(c, q, nb2, e2, nra);
    }
}

/* order[] of the blocks along the curve, starting with the longest axis. */
static void curve_order(const int m[3], uint32_t *order)
{
    curve c = {{m[0], m[1], m[2]}, order, 0};
    const size_t n = (size_t)m[0] * (size_t)m[1] * (size_t)m[2];
    for (size_t u = 0; u < n; u++) order[u] = UINT32_MAX;
    const int o[3] = {0, 0, 0}, X[3] = {m[0], 0, 0}, Y[3] = {0, m[1], 0}, Z[3] = {0, 0, m[2]};
    if (m[0] >= m[1] && m[0] >= m[2]) curve_box(&c, o, X, Y, Z);
    else if (m[1] >= m[0] && m[1] >= m[2]) curve_box(&c, o, Y, X, Z);
    else curve_box(&c, o, Z, X, Y);
    int ok = c.next == n;
    for (size_t u = 0; u < n && ok; u++) ok = order[u] < n;
    if (!ok) sl_fatal("neighbour grid: the block order is not a permutation (internal error)");
}

/* Rows of cells along x stay contiguous (so that the three cells of a
 * neighbourhood row form one particle range); the rows are ordered by the
 * Morton code of (cy, cz). */
static void order_rows(nbr_grid *g)
{
    size_t nrows = (size_t)g->nc[1] * (size_t)g->nc[2];
    cell_key *keys = sl_malloc(nrows * sizeof *keys, "grid row order");
    for (int cz = 0; cz < g->nc[2]; cz++)
        for (int cy = 0; cy < g->nc[1]; cy++) {
            size_t row = (size_t)cy + (size_t)g->nc[1] * (size_t)cz;
            keys[row].linear = (uint32_t)row;
            keys[row].morton =
                sl_morton_spread3((uint64_t)cy) | sl_morton_spread3((uint64_t)cz) << 1;
        }
    qsort(keys, nrows, sizeof *keys, cmp_cell_key);
    for (size_t k = 0; k < nrows; k++)
        for (int cx = 0; cx < g->nc[0]; cx++)
            g->rank[(size_t)cx + (size_t)g->nc[0] * keys[k].linear] =
                (uint32_t)(k * (size_t)g->nc[0] + (size_t)cx);
    free(keys);
}

/* Blocks of B^3 cells along the curve (a run of blocks is a compact
 * region, so a rank's own cells have a small surface), the cells inside a
 * block x fastest (an x-row of cells inside a block is one range). */
static void order_blocks(nbr_grid *g)
{
    const int B = g->unit[0];
    const int m[3] = {g->nc[0] / B, g->nc[1] / B, g->nc[2] / B};
    uint32_t *order = sl_malloc(g->nunits * sizeof *order, "grid block order");
    curve_order(m, order);
    for (int cz = 0; cz < g->nc[2]; cz++)
        for (int cy = 0; cy < g->nc[1]; cy++)
            for (int cx = 0; cx < g->nc[0]; cx++) {
                const size_t u = (size_t)(cx / B) +
                    (size_t)m[0] * ((size_t)(cy / B) + (size_t)m[1] * (size_t)(cz / B));
                const int in = cx % B + B * (cy % B + B * (cz % B));
                g->rank[(size_t)cx + (size_t)g->nc[0] * ((size_t)cy + (size_t)g->nc[1] * cz)] =
                    (uint32_t)((size_t)order[u] * g->ucells + (size_t)in);
            }
    free(order);
}

void nbr_grid_init(nbr_grid *g, const double lo[3], const double hi[3], double h, size_t max_cells)
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
        if (total <= max_cells || total < 64) {
            g->ncells = total;
            break;
        }
        cell *= 1.25;
    }
    if (cell > h / NBR_CELLS_PER_H * 1.0000001)
        sl_warning("neighbour grid: scene too large for %zu cells of size h; "
                   "using cells of %g (h = %g): search is slower",
                   max_cells, cell, h);
    for (int d = 0; d < 3; d++) g->lo[d] = lo[d];
    g->cell = cell;
    g->inv_cell = 1.0 / cell;
    g->reach = (int)ceil(h / cell - 1e-9);
    g->h2 = h * h;
    const int B = nbr_unit_setting();
    if (B) { /* whole blocks: the cells past hi are empty (clamping stays 1-Lipschitz) */
        g->ncells = 1;
        for (int d = 0; d < 3; d++) {
            g->nc[d] = (g->nc[d] + B - 1) / B * B;
            g->unit[d] = B;
            g->ncells *= (size_t)g->nc[d];
        }
        if (g->ncells > UINT32_MAX - 1) sl_fatal("neighbour grid: %zu cells", g->ncells);
    } else {
        g->unit[0] = g->nc[0];
        g->unit[1] = g->unit[2] = 1;
    }
    g->ucells = (size_t)g->unit[0] * (size_t)g->unit[1] * (size_t)g->unit[2];
    g->nunits = g->ncells / g->ucells;
    g->rank = sl_alloc_aligned(g->ncells * sizeof *g->rank, "grid ranks");
    if (B) order_blocks(g);
    else order_rows(g);
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

/* The counting sort of sort_by_cell after the cells are known: start
 * (ncells + 1) and perm (new index -> old index).  Stable. */
static void count_by_cell(nbr_grid *g, size_t n, const uint32_t *cellv, uint32_t *start,
                          uint32_t *perm)
{
    memset(g->count, 0, (g->ncells + 1) * sizeof *g->count);
    for (size_t i = 0; i < n; i++) g->count[cellv[i] + 1]++;
    start[0] = 0;
    for (size_t k = 0; k < g->ncells; k++) start[k + 1] = start[k] + g->count[k + 1];
    memcpy(g->count, start, g->ncells * sizeof *g->count);
    for (size_t i = 0; i < n; i++) perm[g->count[cellv[i]]++] = (uint32_t)i;
}

/* Counting sort of n particles by cell rank: fills start (ncells + 1) and
 * perm (new index -> old index).  Stable, hence deterministic. */
static void sort_by_cell(nbr_grid *g, size_t n, const double *x, const double *y, const double *z,
                         uint32_t *cellv, uint32_t *start, uint32_t *perm)
{
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        int c[3];
        cell_of(g, x[i], y[i], z[i], c);
        cellv[i] = rank_of(g, c);
    }
    count_by_cell(g, n, cellv, start, perm);
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
            while (c > 0 && id[seg[c - 1]] > id[v]) {
                seg[c] = seg[c - 1];
                c--;
            }
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


/* One parallel region (each costs a barrier, and a busy machine makes
 * barriers dear): cells, counting sort, order within the cells by id,
 * then the state fields gathered into their spares (particles.h) and the
 * pointers swapped; f->cell ends in the new order. */
void nbr_sort_fluid(nbr_grid *g, sl_fluid *f)
{
    if (g->perm_cap < f->cap) {
        sl_free_aligned(g->perm);
        g->perm = sl_alloc_aligned(f->cap * sizeof *g->perm, "fluid permutation");
        g->perm_cap = f->cap;
    }
    double **state[PRT_STATE_PAIRS], **spare[PRT_STATE_PAIRS];
    const int npairs = prt_fluid_state_pairs(f, state, spare);
    const size_t n = f->n;
    uint32_t *restrict perm = g->perm, *restrict cellv = f->cell, *restrict start = g->fstart;
    const double *restrict x = f->x, *restrict y = f->y, *restrict z = f->z;
#pragma omp parallel
    {
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; i++) {
            int c[3];
            cell_of(g, x[i], y[i], z[i], c);
            cellv[i] = rank_of(g, c);
        }
#pragma omp single
        count_by_cell(g, n, cellv, start, perm);
        /* key (cell, global id): the order does not depend on the previous one */
#pragma omp for schedule(dynamic, 256)
        for (size_t k = 0; k < g->ncells; k++) {
            uint32_t *seg = perm + start[k];
            const uint32_t len = start[k + 1] - start[k];
            for (uint32_t a = 1; a < len; a++) {
                uint32_t v = seg[a], q = a;
                while (q > 0 && f->id[seg[q - 1]] > f->id[v]) {
                    seg[q] = seg[q - 1];
                    q--;
                }
                seg[q] = v;
            }
            for (uint32_t a = 0; a < len; a++) cellv[start[k] + a] = (uint32_t)k;
        }
        for (int p = 0; p < npairs; p++) {
            const double *restrict from = *state[p];
            double *restrict to = *spare[p];
#pragma omp for schedule(static) nowait
            for (size_t i = 0; i < n; i++) to[i] = from[perm[i]];
        }
        {
            const uint32_t *restrict from = f->id;
            uint32_t *restrict to = f->scratch_u;
#pragma omp for schedule(static)
            for (size_t i = 0; i < n; i++) to[i] = from[perm[i]];
        }
    }
    for (int p = 0; p < npairs; p++) {
        double *t = *state[p];
        *state[p] = *spare[p];
        *spare[p] = t;
    }
    uint32_t *t = f->id;
    f->id = f->scratch_u;
    f->scratch_u = t;
}

/* ---- neighbour lists ---- */

void nbr_list_init(nbr_list *l) { memset(l, 0, sizeof *l); }

void nbr_list_free(nbr_list *l)
{
    sl_free_aligned(l->start);
    sl_free_aligned(l->idx);
    for (size_t c = 0; c < l->nbuf; c++) free(l->buf[c]);
    free(l->buf);
    free(l->bcap);
    free(l->blen);
    memset(l, 0, sizeof *l);
}

static size_t chunks_of(size_t rows) { return (rows + NBR_CHUNK - 1) / NBR_CHUNK; }

/* Rows and chunk buffers for `rows` rows.  Buffers are kept from build to
 * build: they grow only when a chunk finds more neighbours than ever before. */
static void list_prepare(nbr_list *l, size_t rows)
{
    const size_t nch = chunks_of(rows);
    if (rows + 1 > l->rows_cap) {
        sl_free_aligned(l->start);
        l->rows_cap = rows + 1 + rows / 4;
        l->start = sl_alloc_aligned(l->rows_cap * sizeof *l->start, "neighbour list rows");
    }
    if (nch > l->nbuf) {
        l->buf = sl_realloc(l->buf, nch * sizeof *l->buf, "neighbour buffers");
        l->bcap = sl_realloc(l->bcap, nch * sizeof *l->bcap, "neighbour buffers");
        l->blen = sl_realloc(l->blen, nch * sizeof *l->blen, "neighbour buffers");
        for (size_t c = l->nbuf; c < nch; c++) {
            l->buf[c] = NULL;
            l->bcap[c] = 0;
        }
        l->nbuf = nch;
    }
    for (size_t c = 0; c < l->nbuf; c++) l->blen[c] = 0;
    l->n = rows;
    l->start[0] = 0;
}

/* Room for `extra` more entries in chunk c's buffer, plus the slack of
 * one vector that filter_range stores past the end. */
static inline uint32_t *buf_reserve(nbr_list *l, size_t c, size_t extra)
{
    const size_t need = l->blen[c] + extra + 16;
    if (need > l->bcap[c]) {
        size_t cap = 2 * need + 4096;
        l->buf[c] = sl_realloc(l->buf[c], cap * sizeof *l->buf[c], "neighbour buffer");
        l->bcap[c] = cap;
    }
    return l->buf[c];
}

/* Append to buf (at len) the indices j in [j0, j1) with |p - x_j|^2 < h2,
 * j != self; returns the new length.  The candidates are contiguous in
 * memory, so the distance test runs on vectors of them (AVX-512: the
 * row's tail under a mask, the accepted indices compressed in a register
 * and stored whole: buf needs 8 entries of slack). */
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
    for (; j < j1; j += 8) {
        const uint32_t left = j1 - j;
        const __mmask8 m = left >= 8 ? (__mmask8)0xff : (__mmask8)((1u << left) - 1u);
        __m512d dx = _mm512_sub_pd(vpx, _mm512_maskz_loadu_pd(m, tx + j));
        __m512d dy = _mm512_sub_pd(vpy, _mm512_maskz_loadu_pd(m, ty + j));
        __m512d dz = _mm512_sub_pd(vpz, _mm512_maskz_loadu_pd(m, tz + j));
        __m512d d2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
        __m256i idx = _mm256_add_epi32(_mm256_set1_epi32((int)j), step);
        __mmask8 keep = _mm512_mask_cmp_pd_mask(m, d2, vh2, _CMP_LT_OQ) &
            (__mmask8)~_mm256_cmpeq_epi32_mask(idx, vself);
        __m256i kept = _mm256_maskz_compress_epi32(keep, idx);
        __asm__("" : "+v"(kept)); /* keeps gcc from fusing a (slow) compress to memory */
        _mm256_storeu_si256((__m256i *)(buf + len), kept);
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

/* The candidate ranges around one cell: the cells of each neighbourhood
 * row along x are one contiguous range of a sorted set. */
/* (2 reach + 1)^2 rows for reach <= 2, each cut into at most 3 ranges by
 * the units along x (blocks of 2 or more cells) */
#define NBR_MAX_ROWS 75
_Static_assert(NBR_CELLS_PER_H <= 2, "NBR_MAX_ROWS assumes reach <= 2");

typedef struct cell_rows {
    uint32_t rank; /* the cell (UINT32_MAX: none yet) */
    int n;
    uint32_t ka[NBR_MAX_ROWS], ke[NBR_MAX_ROWS]; /* rank ranges [ka, ke) */
} cell_rows;

/* The rows of the cell of (px, py, pz), recomputed only when the cell
 * differs from the one r holds (sorted particles share it). */
static inline void rows_of(const nbr_grid *g, double px, double py, double pz, cell_rows *r)
{
    int c[3];
    cell_of(g, px, py, pz, c);
    const uint32_t rank = rank_of(g, c);
    if (rank == r->rank) return;
    r->rank = rank;
    r->n = 0;
    const int R = g->reach;
    const int x0 = c[0] > R ? c[0] - R : 0, x1 = c[0] + R < g->nc[0] ? c[0] + R : g->nc[0] - 1;
    const int y0 = c[1] > R ? c[1] - R : 0, y1 = c[1] + R < g->nc[1] ? c[1] + R : g->nc[1] - 1;
    const int z0 = c[2] > R ? c[2] - R : 0, z1 = c[2] + R < g->nc[2] ? c[2] + R : g->nc[2] - 1;
    const int ux = g->unit[0];
    for (int cz = z0; cz <= z1; cz++)
        for (int cy = y0; cy <= y1; cy++)
            for (int xa = x0; xa <= x1;) { /* one range per unit the row crosses */
                const int xe = (xa / ux + 1) * ux - 1 < x1 ? (xa / ux + 1) * ux - 1 : x1;
                int a[3] = {xa, cy, cz}, e[3] = {xe, cy, cz};
                const uint32_t ka = rank_of(g, a), ke = rank_of(g, e) + 1;
                if (r->n && r->ke[r->n - 1] == ka) r->ke[r->n - 1] = ke; /* adjacent: one */
                else {
                    r->ka[r->n] = ka;
                    r->ke[r->n] = ke;
                    r->n++;
                }
                xa = xe + 1;
            }
}

/* A target set of a list: its cell starts and positions; `same` when it
 * is the set the rows belong to (row i then skips j = i). */
typedef struct nbr_targets {
    const uint32_t *start;
    const uint32_t *start2; /* a second set over the same positions (periodic images), or NULL */
    const double *x, *y, *z;
    int same;
} nbr_targets;

/* Rows handled together: particles of one cell share its candidate rows,
 * so each row's trip counts repeat from particle to particle (the
 * branches predict) and its candidates stay in L1. */
#define NBR_BATCH 16

/* Rows [i0, i1) (one cell, at most NBR_BATCH) of list l against target
 * set t, into chunk c's buffer: each row first in a slot of its own (the
 * cell's candidate count plus slack), then moved down to be contiguous;
 * l->start[i] gets row i's count. */
static void gather_batch(const nbr_grid *g, const cell_rows *r, nbr_list *l, size_t c,
                         const nbr_targets *t, const double *px, const double *py, const double *pz,
                         size_t i0, size_t i1)
{
    size_t cand = 0;
    for (int k = 0; k < r->n; k++) {
        cand += t->start[r->ke[k]] - t->start[r->ka[k]];
        if (t->start2) cand += t->start2[r->ke[k]] - t->start2[r->ka[k]];
    }
    const size_t m = i1 - i0, stride = cand + 16, base = l->blen[c];
    uint32_t *buf = buf_reserve(l, c, m * stride);
    size_t len[NBR_BATCH];
    for (size_t q = 0; q < m; q++) len[q] = base + q * stride;
    for (int k = 0; k < r->n; k++) {
        for (int set = 0; set < (t->start2 ? 2 : 1); set++) { /* a row's own, then its images */
            const uint32_t *st = set ? t->start2 : t->start;
            const uint32_t j0 = st[r->ka[k]], j1 = st[r->ke[k]];
            if (j1 == j0) continue;
            for (size_t q = 0; q < m; q++) {
                const size_t i = i0 + q;
                len[q] = filter_range(buf, len[q], j0, j1, t->same ? (uint32_t)i : UINT32_MAX,
                                      px[i], py[i], pz[i], t->x, t->y, t->z, g->h2);
            }
        }
    }
    size_t out = base;
    for (size_t q = 0; q < m; q++) {
        const size_t from = base + q * stride, cnt = len[q] - from;
        if (cnt && out != from) memmove(buf + out, buf + from, cnt * sizeof *buf);
        l->start[i0 + q] = (uint32_t)cnt;
        out += cnt;
    }
    l->blen[c] = out;
}

/* Chunk c's rows [lo, hi). */
static inline size_t chunk_lo(size_t c) { return c * NBR_CHUNK; }
static inline size_t chunk_hi(size_t c, size_t rows)
{
    return (c + 1) * NBR_CHUNK < rows ? (c + 1) * NBR_CHUNK : rows;
}

/* After the rows: where each chunk's entries go (one thread); the index
 * array grows when needed. */
static void list_offsets(nbr_list *l)
{
    size_t total = 0;
    const size_t nch = chunks_of(l->n);
    for (size_t c = 0; c < nch; c++) {
        const size_t len = l->blen[c];
        l->blen[c] = total; /* from here on: the chunk's offset */
        total += len;
    }
    if (total > UINT32_MAX) sl_fatal("neighbour list exceeds 2^32 entries");
    if (total > l->idx_cap) {
        sl_free_aligned(l->idx);
        l->idx_cap = total + total / 4;
        l->idx = sl_alloc_aligned(l->idx_cap * sizeof *l->idx, "neighbour list");
    }
    l->start[l->n] = (uint32_t)total;
}

/* Chunk c into place: its entries copied, its row counts (start[i] for
 * row i while building) made offsets. */
static void list_place(nbr_list *l, size_t c)
{
    const size_t lo = chunk_lo(c), hi = chunk_hi(c, l->n);
    const size_t off = l->blen[c];
    uint32_t acc = (uint32_t)off;
    for (size_t i = lo; i < hi; i++) {
        const uint32_t cnt = l->start[i];
        l->start[i] = acc;
        acc += cnt;
    }
    if (acc > off) memcpy(l->idx + off, l->buf[c], (acc - off) * sizeof *l->idx);
}

/* The rows of chunk c: runs of particles in one cell, in batches. */
static void build_chunk(const nbr_grid *g, size_t n, const double *px, const double *py,
                        const double *pz, nbr_list *l, const nbr_targets *tl, nbr_list *lb,
                        const nbr_targets *tb, size_t c)
{
    cell_rows cr = {.rank = UINT32_MAX};
    const size_t hi = chunk_hi(c, n);
    for (size_t i = chunk_lo(c); i < hi;) {
        rows_of(g, px[i], py[i], pz[i], &cr);
        const uint32_t rank = cr.rank;
        size_t e = i + 1;
        while (e < hi && e - i < NBR_BATCH) {
            int cc[3];
            cell_of(g, px[e], py[e], pz[e], cc);
            if (rank_of(g, cc) != rank) break;
            e++;
        }
        gather_batch(g, &cr, l, c, tl, px, py, pz, i, e);
        if (lb) gather_batch(g, &cr, lb, c, tb, px, py, pz, i, e);
        i = e;
    }
}

/* Lists l (targets tl) and lb (targets tb, when lb is not NULL) of the n
 * rows at (px, py, pz), chunk by chunk.  Chunks are taken by whichever
 * thread is free (a delayed thread's work moves), yet each chunk's rows
 * are the same whoever builds them, so the lists are identical for any
 * thread count.  One parallel region for the rows, the offsets and the
 * copies. */
static void build_lists(const nbr_grid *g, size_t n, const double *px, const double *py,
                        const double *pz, nbr_list *l, nbr_targets tl, nbr_list *lb, nbr_targets tb)
{
    const size_t nch = chunks_of(n);
    list_prepare(l, n);
    if (lb) list_prepare(lb, n);
#pragma omp parallel
    {
#pragma omp for schedule(dynamic, 1)
        for (size_t c = 0; c < nch; c++) build_chunk(g, n, px, py, pz, l, &tl, lb, &tb, c);
#pragma omp single
        {
            list_offsets(l);
            if (lb) list_offsets(lb);
        }
#pragma omp for schedule(dynamic, 1)
        for (size_t c = 0; c < nch; c++) {
            list_place(l, c);
            if (lb) list_place(lb, c);
        }
    }
}

static nbr_targets fluid_targets(const nbr_grid *g, const sl_fluid *f, int same)
{
    return (nbr_targets){.start = g->fstart, .x = f->x, .y = f->y, .z = f->z, .same = same};
}

static nbr_targets boundary_targets(const nbr_grid *g, const sl_boundary *b, int same)
{
    return (nbr_targets){.start = g->bstart, .x = b->x, .y = b->y, .z = b->z, .same = same};
}

void nbr_build_ff(const nbr_grid *g, const sl_fluid *f, nbr_list *l)
{
    build_lists(g, f->n, f->x, f->y, f->z, l, fluid_targets(g, f, 1), NULL, (nbr_targets){0});
}

void nbr_build_fluid(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *ff,
                     nbr_list *fb)
{
    /* the rows of the periodic images too (they feed the boundary rows), and
     * each row's candidates among the images after its own */
    nbr_targets tf = fluid_targets(g, f, 1);
    if (f->nhalo && g->hstart) tf.start2 = g->hstart;
    build_lists(g, f->n + f->nhalo, f->x, f->y, f->z, ff, tf, fb, boundary_targets(g, b, 0));
}

void nbr_build_fb(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *l)
{
    build_lists(g, f->n, f->x, f->y, f->z, l, boundary_targets(g, b, 0), NULL, (nbr_targets){0});
}

void nbr_build_bf(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *l,
                  uint32_t *active, size_t *nactive)
{
    build_lists(g, b->n, b->x, b->y, b->z, l, fluid_targets(g, f, 0), NULL, (nbr_targets){0});
    size_t na = 0;
    for (size_t i = 0; i < b->n; i++)
        if (l->start[i + 1] > l->start[i]) active[na++] = (uint32_t)i;
    *nactive = na;
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
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++)
            bf->idx[st[fb->idx[q]]++] = (uint32_t)i;
    for (size_t b = nb; b > 0; b--) st[b] = st[b - 1];
    st[0] = 0;
}

void nbr_build_bb(const nbr_grid *g, const sl_boundary *b, nbr_list *l)
{
    build_lists(g, b->n, b->x, b->y, b->z, l, boundary_targets(g, b, 0), NULL, (nbr_targets){0});
}
