/* pcs_domain: -parallel's domain mode (see pcs_domain.h). */
#include "solver/pcs_domain.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_reduce.h"
#include "effects/effects.h"
#include "effects/moving_boundary.h"
#include "parallel/par.h"
#include "solver/pcs_sums.h"

/* What travels with a particle that migrates or joins a halo: x, v, rho,
 * p (the state a step carries, particles.h) and the id. */
#define REC 9
/* ... and to rank 0 for output: the same and the cell of the last sort. */
#define REC_OUT 10

struct pcs_domain {
    /* Ownership is by unit of the grid (neighbours.h: whole x-rows of cells,
     * or blocks), the halo by piece: the whole row (a row's cells are
     * within one cell of the same rows), or with blocks the cell.  Units
     * and pieces are runs of the cell numbering, a unit whole pieces. */
    size_t nunits, ucells;           /* units, cells per unit */
    size_t npieces, pcells, upieces; /* pieces, cells per piece, pieces per unit */
    int pn[3], depth;                /* the pieces' grid (rows: 1, ny, nz) */
    uint32_t *plin;                  /* piece k's index in that grid */
    uint32_t *kof;                   /* the piece of an index of that grid */
    size_t *cut;                     /* rank r owns units [cut[r], cut[r+1]) */
    int *owner;                      /* of each piece */
    uint32_t *nstart, *nrank, *mark; /* ranks whose halo holds piece k: nrank[nstart[k]..) */
    size_t nrank_cap;
    /* periodic axes: the pieces where the images of piece k's particles
     * may lie, ipiece[istart[k]..istart[k+1]) (conservative: the cells a
     * shifted band of the piece meets, a cell either way), for the pieces
     * iface[0..nface) that have any; a rank's halo holds a piece when one
     * of its image pieces is an own or halo piece of the rank (iadd:
     * scratch).  NULL: no periodic axis. */
    uint32_t *istart, *ipiece, *iface, *iadd;
    size_t nface;
    size_t nb_real; /* boundary ids below it are real, the others periodic images */
    long *rowcount, *cnt_p, *all_n, *all_s;
    double threshold, imb_after;
    int *dest;
    size_t dest_cap;
    int *scnt, *sdis, *rcnt, *rdis;     /* migration, particles per rank */
    int *hscnt, *hsdis, *hrcnt, *hrdis; /* halo, particles per rank */
    int *ws, *wsd, *wr, *wrd;           /* either, in doubles */
    double *sbuf, *rbuf;
    size_t sbuf_cap, rbuf_cap;
    uint32_t *send_idx, *recv_idx; /* own rows sent (by rank), halo rows received (by owner) */
    size_t send_cap, recv_cap, nsend, nrecv;
    uint32_t *inv;
    size_t inv_cap;
    size_t nown, nsorted, lo, hi;
    size_t *goff; /* rank r's own rows are rows [goff[r], goff[r+1]) of the serial order */
    size_t *boff; /* the blocks whose last row rank r holds: [boff[r], boff[r+1]) */
    /* boundary particles by cell: a rank stores those of its own rows and
     * of its halo rows.  Its own ones (those in the own rows at the last
     * distribution; a partition of all nb_global) by creation index,
     * sorted: walls that move carry them out of the rows, and the next
     * distribution sends them to their new owner with their last density
     * and pressure (their owner computed them: the own cells' lists are
     * complete), so the owner's values are the serial ones. */
    size_t nb_global, nb_own, nb_own_real;
    uint32_t *bown;
    size_t bown_cap;
    int bmoving; /* the walls move (a movingBoundary effect): distributed every step */
    int blists;  /* the boundary -> fluid lists describe the stored set */
    int *brow, *bpos;
    size_t brow_cap;
    uint32_t *bmark, bst; /* marks of the boundary set */
    size_t bmark_cap;
    double bstored_sum, inner_sum;
    long bdistributions, bmigrated;
    /* the iteration's exchanges: buffers, and which one is in flight (0
     * none, 1 x*, 2 p/rho^2 and rho) */
    double *isbuf, *irbuf;
    size_t isbuf_cap, irbuf_cap;
    int inflight, with_b;
    /* one-cell halo: boundary p/rho^2 from the owner of its cell */
    int bsend_own; /* the boundary set is the own cells' active ones */
    int *bscnt, *bsdis, *brcnt, *brdis;
    uint32_t *bsend_idx, *brecv_idx;
    size_t bsend_cap, brecv_cap, nbsend, nbrecv;
    /* rank 0: the gathered state */
    sl_fluid mirror;
    sl_boundary mbound;
    nbr_grid mgrid;
    nbr_list mbf;
    uint32_t *mfstart, *mbstart;
    uint64_t *bkeys;
    size_t bkeys_cap;
    int have_mirror, fresh;
    double *gbuf;
    size_t gbuf_cap;
    uint64_t *tail;
    size_t tail_cap;
    int *pcnt, *pdis;
    pcd_counts c;
    double stored_sum, halo_sum;
    /* the set-up: particles this rank held when the solver was made (the
     * whole case, or built in parts its share), its peak memory then */
    size_t setup_fluid, setup_boundary;
    int parts;
    double peak_setup;
    struct pcd_out *out; /* streamed output (pcd_output_begin .. end) */
    /* the gather near the function objects' points */
    double *nearbox;
    size_t nearbox_cap;
    unsigned char *nearmark; /* by cell rank */
    uint32_t *cell_lin;      /* cell rank -> linear cell */
    double zext[2];
    /* the function objects' sums over every row (pcd_sum_rows): block
     * sums, rank 0's of every block, the rows appended since the sort */
    double *fs_part, *fs_all, *fs_tail, *fs_tall;
    size_t fs_part_cap, fs_all_cap, fs_tail_cap, fs_tall_cap;
    uint64_t *fs_order;
    size_t fs_order_cap;
};

static void out_free(struct pcd_out *o);

/* ---- small helpers ---- */

static void *grow(void *p, size_t *cap, size_t need, size_t elem, const char *what)
{
    if (need <= *cap && p) return p;
    size_t c = *cap ? *cap : 1024;
    while (c < need) c *= 2;
    sl_free_aligned(p);
    *cap = c;
    return sl_alloc_aligned(c * elem, what);
}

static int as_int(size_t v)
{
    if (v > 2147483647u) sl_fatal("-parallel: %zu values exceed MPI's int counts", v);
    return (int)v;
}

/* The piece of a point (the halo's and the owners' unit of account). */
static size_t row_of(const pcs_solver *s, const struct pcs_domain *d, double x, double y, double z)
{
    return nbr_cell_rank(&s->grid, x, y, z) / d->pcells;
}

static void pack(const sl_fluid *f, size_t i, double *o)
{
    o[0] = f->x[i], o[1] = f->y[i], o[2] = f->z[i];
    o[3] = f->vx[i], o[4] = f->vy[i], o[5] = f->vz[i];
    o[6] = f->rho[i], o[7] = f->p[i];
    o[8] = (double)f->id[i];
}

static void unpack(sl_fluid *f, size_t i, const double *o)
{
    f->x[i] = o[0], f->y[i] = o[1], f->z[i] = o[2];
    f->vx[i] = o[3], f->vy[i] = o[4], f->vz[i] = o[5];
    f->rho[i] = o[6], f->p[i] = o[7];
    f->id[i] = (uint32_t)o[8];
}

/* Particle `from` to slot `to` (to <= from), with its cell. */
static void move_to(sl_fluid *f, size_t to, size_t from)
{
    if (to == from) return;
    f->x[to] = f->x[from], f->y[to] = f->y[from], f->z[to] = f->z[from];
    f->vx[to] = f->vx[from], f->vy[to] = f->vy[from], f->vz[to] = f->vz[from];
    f->rho[to] = f->rho[from], f->p[to] = f->p[from];
    f->id[to] = f->id[from];
    f->cell[to] = f->cell[from];
}

/* Room for n particles (the arrays keep their first f->n entries). */
static void reserve(sl_fluid *f, size_t n)
{
    if (n > f->cap) prt_fluid_reserve(f, n + n / 4 + 64);
}

/* Counts in doubles, and displacements, of per-particle counts. */
static size_t scale(const int *cnt, int w, int *wc, int *wd, int p)
{
    size_t tot = 0;
    for (int q = 0; q < p; q++) {
        wc[q] = as_int((size_t)w * (size_t)cnt[q]);
        wd[q] = as_int(tot);
        tot += (size_t)wc[q];
    }
    return tot;
}

static int *ints(int n) { return sl_calloc((size_t)n, sizeof(int), "rank counts"); }

/* ---- boundary particles: fields, packing ---- */

/* A boundary particle's fields (particles.h); what travels with one that
 * migrates or joins a halo: all of them, its body and its creation index. */
#define BFIELDS 20
#define BREC    (BFIELDS + 2)

static void bfields(const sl_boundary *b, double *a[BFIELDS])
{
    double *list[BFIELDS] = {b->x,          b->y,   b->z,  b->nx,  b->ny,  b->nz, b->mass,
                             b->rho_static, b->rho, b->p,  b->pt,  b->vx,  b->vy, b->vz,
                             b->x0,         b->y0,  b->z0, b->nx0, b->ny0, b->nz0};
    memcpy(a, list, sizeof list);
}

static void bpack(const sl_boundary *b, size_t i, double *o)
{
    double *a[BFIELDS];
    bfields(b, a);
    for (int k = 0; k < BFIELDS; k++) o[k] = a[k][i];
    o[BFIELDS] = (double)b->body[i];
    o[BFIELDS + 1] = (double)b->id[i];
}

static void bunpack(sl_boundary *b, size_t i, const double *o)
{
    double *a[BFIELDS];
    bfields(b, a);
    for (int k = 0; k < BFIELDS; k++) a[k][i] = o[k];
    b->body[i] = (uint32_t)o[BFIELDS];
    b->id[i] = (uint32_t)o[BFIELDS + 1];
}

static void bmove_to(sl_boundary *b, size_t to, size_t from)
{
    if (to == from) return;
    double *a[BFIELDS];
    bfields(b, a);
    for (int k = 0; k < BFIELDS; k++) a[k][to] = a[k][from];
    b->body[to] = b->body[from];
    b->id[to] = b->id[from];
}

/* Room for n boundary particles (the arrays keep their first b->n). */
static void breserve(sl_boundary *b, size_t n)
{
    if (n > b->cap) prt_boundary_reserve(b, n + n / 4 + 64);
}

/* The boundary's arrays cut down to room for `want` particles (they were
 * sized for the whole case when it was read). */
static void bshrink(sl_boundary *b, size_t want)
{
    if (want >= b->cap) return;
    sl_boundary g;
    prt_boundary_init(&g);
    prt_boundary_reserve(&g, want);
    double *from[BFIELDS], *to[BFIELDS];
    bfields(b, from);
    bfields(&g, to);
    const size_t n = b->n;
    for (int k = 0; k < BFIELDS; k++) memcpy(to[k], from[k], n * sizeof *to[k]);
    memcpy(g.body, b->body, n * sizeof *g.body);
    memcpy(g.id, b->id, n * sizeof *g.id);
    g.n = n;
    prt_boundary_free(b);
    *b = g;
}

static int cmp_u32(const void *a, const void *b)
{
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* ---- cuts ---- */

/* The pieces within `depth` cells of piece k (in the pieces' grid: rows
 * span x), each given to fn with the context. */
static void near_pieces(struct pcs_domain *d, size_t k, int depth,
                        void (*fn)(struct pcs_domain *, uint32_t, void *), void *ctx)
{
    const size_t l = d->plin[k], n0 = (size_t)d->pn[0], n01 = n0 * (size_t)d->pn[1];
    const int c[3] = {(int)(l % n0), (int)(l % n01 / n0), (int)(l / n01)};
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = c[a] - depth > 0 ? c[a] - depth : 0;
        hi[a] = c[a] + depth < d->pn[a] - 1 ? c[a] + depth : d->pn[a] - 1;
    }
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++)
                fn(d, d->kof[(size_t)x + n0 * (size_t)y + n01 * (size_t)z], ctx);
}

typedef struct need_pass {
    int pass, q;
    uint32_t st;
} need_pass;

static void need_one(struct pcs_domain *d, uint32_t k2, void *ctx)
{
    const need_pass *np = ctx;
    if (d->owner[k2] == np->q || d->mark[k2] == np->st) return;
    d->mark[k2] = np->st;
    if (np->pass == 0) d->nstart[k2 + 1]++;
    else d->nrank[d->nstart[k2]++] = (uint32_t)np->q;
}

/* The ranks whose halo holds each piece: the pieces within `depth` cells
 * of one of their own (not their own). */
static void build_need(struct pcs_domain *d, int p)
{
    memset(d->nstart, 0, (d->npieces + 1) * sizeof *d->nstart);
    memset(d->mark, 0, d->npieces * sizeof *d->mark);
    for (int pass = 0; pass < 2; pass++) {
        for (int q = 0; q < p; q++) {
            need_pass np = {pass, q, (uint32_t)(pass * p + q + 1)};
            for (size_t k = d->cut[q] * d->upieces; k < d->cut[q + 1] * d->upieces; k++)
                near_pieces(d, k, d->depth, need_one, &np);
            /* periodic: the pieces whose images lie in an own or halo piece
             * (decided against the halo above, then added) */
            size_t na = 0;
            for (size_t f = 0; f < d->nface; f++) {
                const uint32_t k = d->iface[f];
                if (d->owner[k] == q || d->mark[k] == np.st) continue;
                for (uint32_t e = d->istart[k]; e < d->istart[k + 1]; e++) {
                    const uint32_t i = d->ipiece[e];
                    if (d->owner[i] == q || d->mark[i] == np.st) {
                        d->iadd[na++] = k;
                        break;
                    }
                }
            }
            for (size_t a = 0; a < na; a++) need_one(d, d->iadd[a], &np);
        }
        if (pass == 0) {
            for (size_t k = 0; k < d->npieces; k++) d->nstart[k + 1] += d->nstart[k];
            d->nrank = grow(d->nrank, &d->nrank_cap, d->nstart[d->npieces] + 1, sizeof *d->nrank,
                            "halo pieces");
        }
    }
    /* the fill advanced each start to the next piece's: shift back */
    for (size_t k = d->npieces; k > 0; k--) d->nstart[k] = d->nstart[k - 1];
    d->nstart[0] = 0;
}

/* The cell of coordinate v along axis a, clamped as the grid clamps. */
static int clamp_coord(const nbr_grid *g, int a, double v)
{
    const double c = floor((v - g->lo[a]) * g->inv_cell);
    return c < 0.0 ? 0 : c > g->nc[a] - 1 ? g->nc[a] - 1 : (int)c;
}

/* The cells [r0, r1] along axis a that the images of the points of [A,
 * B) within h of a periodic face (band -1: the face lo, images at +L; +1:
 * the face hi, images at -L) may lie in, a cell more either way for
 * rounding; 0 when the piece meets no such band. */
static int band_cells(const nbr_grid *g, const dom_periodic *per, double h, int a, int band,
                      double A, double B, int *r0, int *r1)
{
    const double L = per->hi[a] - per->lo[a], e = 1e-9 * L + 1e-12;
    const double b0 = band < 0 ? per->lo[a] - e : per->hi[a] - h - e;
    const double b1 = band < 0 ? per->lo[a] + h + e : per->hi[a] + e;
    const double lo = A > b0 ? A : b0, hi = B < b1 ? B : b1;
    if (!(lo < hi)) return 0;
    const double s = band < 0 ? L : -L;
    *r0 = clamp_coord(g, a, lo + s) - 1;
    *r1 = clamp_coord(g, a, hi + s) + 1;
    *r0 = *r0 < 0 ? 0 : *r0;
    *r1 = *r1 > g->nc[a] - 1 ? g->nc[a] - 1 : *r1;
    return 1;
}

static int cmp_u32(const void *a, const void *b);

/* Piece k's image pieces (sorted, distinct) into out (room for cap);
 * returns how many (possibly more than cap: then call again with room). */
static size_t image_pieces(const struct pcs_domain *d, const nbr_grid *g, const dom_periodic *per,
                           double h, size_t k, uint32_t *out, size_t cap)
{
    const size_t l = d->plin[k], n0 = (size_t)d->pn[0], n01 = n0 * (size_t)d->pn[1];
    const int pc[3] = {(int)(l % n0), (int)(l % n01 / n0), (int)(l / n01)};
    int opt[3][3][2], nopt[3];
    for (int a = 0; a < 3; a++) {
        const int c0 = d->pn[a] == 1 ? 0 : pc[a], c1 = d->pn[a] == 1 ? g->nc[a] - 1 : pc[a];
        opt[a][0][0] = c0, opt[a][0][1] = c1;
        nopt[a] = 1;
        if (!(per->axes & (1u << a))) continue;
        const double A = c0 == 0 ? -HUGE_VAL : g->lo[a] + c0 * g->cell;
        const double B = c1 == g->nc[a] - 1 ? HUGE_VAL : g->lo[a] + (c1 + 1) * g->cell;
        for (int band = -1; band <= 1; band += 2)
            if (band_cells(g, per, h, a, band, A, B, &opt[a][nopt[a]][0], &opt[a][nopt[a]][1]))
                nopt[a]++;
    }
    size_t m = 0;
    for (int i0 = 0; i0 < nopt[0]; i0++)
        for (int i1 = 0; i1 < nopt[1]; i1++)
            for (int i2 = 0; i2 < nopt[2]; i2++) {
                if (!i0 && !i1 && !i2) continue; /* no shift: the piece itself */
                const int *r[3] = {opt[0][i0], opt[1][i1], opt[2][i2]};
                int lo[3], hi[3];
                for (int a = 0; a < 3; a++) {
                    lo[a] = d->pn[a] == 1 ? 0 : r[a][0];
                    hi[a] = d->pn[a] == 1 ? 0 : r[a][1];
                }
                for (int z = lo[2]; z <= hi[2]; z++)
                    for (int y = lo[1]; y <= hi[1]; y++)
                        for (int x = lo[0]; x <= hi[0]; x++) {
                            if (m < cap)
                                out[m] = d->kof[(size_t)x + n0 * (size_t)y + n01 * (size_t)z];
                            m++;
                        }
            }
    if (m > cap) return m;
    qsort(out, m, sizeof *out, cmp_u32);
    size_t u = 0;
    for (size_t q = 0; q < m; q++) /* the piece itself is stored with it anyway */
        if ((!u || out[u - 1] != out[q]) && out[q] != k) out[u++] = out[q];
    return u;
}

/* The image pieces of every piece (periodic axes; nothing otherwise). */
static void periodic_pieces(struct pcs_domain *d, const nbr_grid *g, const dom_periodic *per,
                            double h)
{
    if (!per || !per->axes) return;
    size_t cap = 64, total = 0, tcap = 1024;
    uint32_t *one = sl_malloc(cap * sizeof *one, "periodic pieces");
    d->istart = sl_calloc(d->npieces + 1, sizeof *d->istart, "periodic pieces");
    d->ipiece = sl_malloc(tcap * sizeof *d->ipiece, "periodic pieces");
    d->iface = sl_malloc((d->npieces + 1) * sizeof *d->iface, "periodic pieces");
    d->nface = 0;
    for (size_t k = 0; k < d->npieces; k++) {
        size_t m;
        while ((m = image_pieces(d, g, per, h, k, one, cap)) > cap) {
            cap = 2 * m;
            one = sl_realloc(one, cap * sizeof *one, "periodic pieces");
        }
        if (total + m > tcap) {
            tcap = 2 * (total + m);
            d->ipiece = sl_realloc(d->ipiece, tcap * sizeof *d->ipiece, "periodic pieces");
        }
        memcpy(d->ipiece + total, one, m * sizeof *one);
        total += m;
        d->istart[k + 1] = (uint32_t)total;
        if (m) d->iface[d->nface++] = (uint32_t)k;
    }
    d->iadd = sl_malloc((d->nface + 1) * sizeof *d->iadd, "periodic pieces");
    free(one);
}

/* Cuts from the fluid count of each unit: rank r's first unit is where
 * the running count comes nearest r N / P. */
static double set_cuts(struct pcs_domain *d, const long *cnt, int p)
{
    long total = 0;
    for (size_t k = 0; k < d->nunits; k++) total += cnt[k];
    size_t k = 0;
    long acc = 0;
    d->cut[0] = 0;
    for (int r = 1; r < p; r++) {
        const long target = (long)((long long)total * r / p);
        while (k < d->nunits && acc + cnt[k] <= target) acc += cnt[k++];
        if (k < d->nunits && acc < target && acc + cnt[k] - target < target - acc) acc += cnt[k++];
        d->cut[r] = k;
    }
    d->cut[p] = d->nunits;
    long big = 0;
    for (int r = 0; r < p; r++) {
        long sum = 0;
        for (size_t q = d->cut[r]; q < d->cut[r + 1]; q++) {
            sum += cnt[q];
            for (size_t c = q * d->upieces; c < (q + 1) * d->upieces; c++) d->owner[c] = r;
        }
        big = sum > big ? sum : big;
    }
    build_need(d, p);
    return total > 0 ? (double)big * p / (double)total : 1.0;
}

/* ---- boundary particles by cell ---- */

/* The first cell of rank r's units (a unit is a run of cells). */
static size_t first_cell(const struct pcs_domain *d, int r) { return d->cut[r] * d->ucells; }

/* Whether boundary particle `id` is one of this rank's own. */
static int own_boundary(const struct pcs_domain *d, uint32_t id)
{
    return d->nb_own && bsearch(&id, d->bown, d->nb_own, sizeof *d->bown, cmp_u32) != NULL;
}

/* After a sort of the stored boundary: the own ones (those of the own
 * cells) by creation index. */
static void own_boundary_list(const pcs_solver *s, struct pcs_domain *d)
{
    const int me = s->split.rank;
    const uint32_t *bs = s->grid.bstart;
    const size_t j0 = bs[first_cell(d, me)], j1 = bs[first_cell(d, me + 1)];
    d->nb_own = j1 - j0;
    d->bown = grow(d->bown, &d->bown_cap, d->nb_own + 1, sizeof *d->bown, "own boundary");
    for (size_t j = j0; j < j1; j++) d->bown[j - j0] = s->b->id[j];
    qsort(d->bown, d->nb_own, sizeof *d->bown, cmp_u32);
    size_t real = d->nb_own; /* periodic images (the largest ids) are not written */
    while (real && d->bown[real - 1] >= d->nb_real) real--;
    d->nb_own_real = real;
}

/* Periodic boundary images among the stored boundary particles: each
 * with its original (stored too: its piece is an image piece of the
 * original's, which the rank then stores), as local index pairs for the
 * refresh (dom_refresh_pressure); after every sort of the stored set. */
static void boundary_image_pairs(pcs_solver *s, struct pcs_domain *d)
{
    dom_halo *hl = &s->halo;
    if (!hl->nb_img) return;
    const sl_boundary *b = s->b;
    const size_t nall = hl->nb_real + hl->nb_img;
    for (size_t i = 0; i < nall; i++) hl->bpos[i] = UINT32_MAX;
    size_t m = 0;
    for (size_t j = 0; j < b->n; j++) {
        hl->bpos[b->id[j]] = (uint32_t)j;
        m += b->id[j] >= hl->nb_real;
    }
    hl->bpair = grow(hl->bpair, &hl->bpair_cap, 2 * m + 2, sizeof *hl->bpair, "boundary images");
    size_t q = 0;
    for (size_t j = 0; j < b->n; j++) {
        if (b->id[j] < hl->nb_real) continue;
        const uint32_t o = hl->bpos[hl->bsrc[b->id[j] - hl->nb_real]];
        if (o == UINT32_MAX) { /* in a piece stored for its images only: read by no own row */
            if (d->owner[row_of(s, d, b->x[j], b->y[j], b->z[j])] == s->split.rank)
                sl_fatal("pcs_domain: the original of periodic boundary image %u is not stored "
                         "(internal error)",
                         b->id[j]);
            continue;
        }
        hl->bpair[2 * q] = (uint32_t)j;
        hl->bpair[2 * q + 1] = o;
        q++;
    }
    hl->nbpair = q;
    hl->bpairs = 1;
}

/* Whether rank me stores the boundary particles of row k: its own rows
 * and its halo rows. */
static int stores_row(const struct pcs_domain *d, size_t k, int me)
{
    if (d->owner[k] == me) return 1;
    for (uint32_t q = d->nstart[k]; q < d->nstart[k + 1]; q++)
        if ((int)d->nrank[q] == me) return 1;
    return 0;
}

/* At set-up a rank holds the boundary particles sorted, with their
 * masses (every one of the case, or built in parts those of the rows
 * around its own, pcd_plan): it keeps those of its own and halo rows, in
 * order, and its arrays shrink to them. */
static void keep_boundary_rows(pcs_solver *s, struct pcs_domain *d, size_t nb_global)
{
    sl_boundary *b = s->b;
    nbr_grid *g = &s->grid;
    const int me = s->split.rank;
    d->nb_global = nb_global;
    size_t j = 0;
    for (size_t i = 0; i < b->n; i++)
        if (stores_row(d, row_of(s, d, b->x[i], b->y[i], b->z[i]), me)) bmove_to(b, j++, i);
    b->n = j;
    bshrink(b, j + j / 4 + 256);
    sl_free_aligned(g->bcell), sl_free_aligned(g->bperm); /* sized for them all */
    g->bcell = g->bperm = NULL;
    g->bperm_cap = 0;
    nbr_sort_boundary(g, b); /* the order kept; bstart of the stored ones */
    own_boundary_list(s, d);
    boundary_image_pairs(s, d);
}

/* Counts to and from every rank (an Alltoall), their displacements and
 * totals. */
static void count_exchange(int p, const int *scnt, int *sdis, int *rcnt, int *rdis, size_t *ns,
                           size_t *nr)
{
    par_alltoall_int(scnt, rcnt);
    *ns = *nr = 0;
    for (int q = 0; q < p; q++) {
        sdis[q] = as_int(*ns);
        *ns += (size_t)scnt[q];
        rdis[q] = as_int(*nr);
        *nr += (size_t)rcnt[q];
    }
}

/* The boundary particles to the ranks that store them now (the walls
 * moved, or the cuts did): the own ones whose row another rank owns go
 * there with all their fields, the halo copies are dropped, then every
 * rank sends its own ones in the rows of another rank's halo to it
 * (BREC doubles each); the stored set is sorted again. */
static void distribute_boundary(pcs_solver *s, struct pcs_domain *d)
{
    sl_boundary *b = s->b;
    const int p = s->split.size, me = s->split.rank;
    const size_t n = b->n;
    size_t ns, nr;
    d->brow = grow(d->brow, &d->brow_cap, n + 1, sizeof *d->brow, "boundary rows");
    int *dest = d->brow;
    memset(d->scnt, 0, (size_t)p * sizeof *d->scnt);
    for (size_t i = 0; i < n; i++) {
        if (!own_boundary(d, b->id[i])) { /* a halo copy */
            dest[i] = -1;
            continue;
        }
        dest[i] = d->owner[row_of(s, d, b->x[i], b->y[i], b->z[i])];
        if (dest[i] != me) d->scnt[dest[i]]++;
    }
    count_exchange(p, d->scnt, d->sdis, d->rcnt, d->rdis, &ns, &nr);
    d->bmigrated += (long)ns;
    d->sbuf = grow(d->sbuf, &d->sbuf_cap, BREC * ns + 1, sizeof *d->sbuf, "migration buffer");
    d->rbuf = grow(d->rbuf, &d->rbuf_cap, BREC * nr + 1, sizeof *d->rbuf, "migration buffer");
    int *pos = d->bpos;
    memcpy(pos, d->sdis, (size_t)p * sizeof *pos);
    size_t j = 0;
    for (size_t i = 0; i < n; i++) {
        if (dest[i] == me) bmove_to(b, j++, i);
        else if (dest[i] >= 0) bpack(b, i, d->sbuf + BREC * (size_t)pos[dest[i]]++);
    }
    scale(d->scnt, BREC, d->ws, d->wsd, p);
    scale(d->rcnt, BREC, d->wr, d->wrd, p);
    par_exchange_double(d->sbuf, d->ws, d->wsd, d->rbuf, d->wr, d->wrd);
    b->n = j;
    breserve(b, j + nr);
    for (size_t k = 0; k < nr; k++) bunpack(b, j + k, d->rbuf + BREC * k);
    b->n = j + nr;
    /* the halo: own ones in the rows of another rank's halo */
    const size_t m = b->n;
    d->brow = grow(d->brow, &d->brow_cap, m + 1, sizeof *d->brow, "boundary rows");
    int *row = d->brow;
    memset(d->scnt, 0, (size_t)p * sizeof *d->scnt);
    for (size_t i = 0; i < m; i++) {
        row[i] = (int)row_of(s, d, b->x[i], b->y[i], b->z[i]);
        for (uint32_t q = d->nstart[row[i]]; q < d->nstart[row[i] + 1]; q++) d->scnt[d->nrank[q]]++;
    }
    count_exchange(p, d->scnt, d->sdis, d->rcnt, d->rdis, &ns, &nr);
    d->sbuf = grow(d->sbuf, &d->sbuf_cap, BREC * ns + 1, sizeof *d->sbuf, "halo buffer");
    d->rbuf = grow(d->rbuf, &d->rbuf_cap, BREC * nr + 1, sizeof *d->rbuf, "halo buffer");
    memcpy(pos, d->sdis, (size_t)p * sizeof *pos);
    for (size_t i = 0; i < m; i++)
        for (uint32_t q = d->nstart[row[i]]; q < d->nstart[row[i] + 1]; q++)
            bpack(b, i, d->sbuf + BREC * (size_t)pos[d->nrank[q]]++);
    scale(d->scnt, BREC, d->ws, d->wsd, p);
    scale(d->rcnt, BREC, d->wr, d->wrd, p);
    par_exchange_double(d->sbuf, d->ws, d->wsd, d->rbuf, d->wr, d->wrd);
    breserve(b, m + nr);
    for (size_t k = 0; k < nr; k++) bunpack(b, m + k, d->rbuf + BREC * k);
    b->n = m + nr;
    nbr_sort_boundary(&s->grid, b);
    own_boundary_list(s, d);
    boundary_image_pairs(s, d);
    d->blists = 0;
    d->bdistributions++;
}

static int halo_depth(const pcs_solver *s);

const char *pcd_periodic_refusal(const pcs_solver *s)
{
    if (!s->prm.periodic.axes) return NULL;
    const eff_instance *mb = s->eff ? eff_find(s->eff, "movingBoundary") : NULL;
    if (mb && !eff_moving_boundary_translates_across(mb->state, s->prm.periodic.axes))
        return "a movingBoundary that rotates or moves along a periodic axis (its periodic "
               "images are exact for translations only, and would leave the pieces that hold "
               "their originals' images)";
    if (s->eff && eff_find(s->eff, "emitter")) return "an emitter";
    if (halo_depth(s) > s->grid.reach)
        return "two cells of halo (surfaceTension or SLUICE_PARALLEL_HALO_DEPTH=2: every rank "
               "computes the boundary particles its rows see, and an image's original may lie "
               "on another rank)";
    if (s->prm.point_queries)
        return "a probes or waterGauges function object (rank 0's copy near their points has "
               "no periodic images)";
    return NULL;
}

int pcd_usable(const pcs_solver *s)
{
    const char *e = getenv("SLUICE_PARALLEL_EXCHANGE");
    if (e && (!strcmp(e, "gather") || !strcmp(e, "halo"))) return 0;
    return s->split.size > 1 && !pcd_periodic_refusal(s);
}

/* The fluid's arrays cut down to room for `want` particles (they were
 * sized for the whole case when it was read): the state fields move over,
 * the others are recomputed by every step before they are read. */
static void shrink(sl_fluid *f, size_t want)
{
    if (want >= f->cap) return;
    sl_fluid g;
    prt_fluid_init(&g);
    prt_fluid_reserve(&g, want);
    const size_t n = f->n;
    double *from[8] = {f->x, f->y, f->z, f->vx, f->vy, f->vz, f->rho, f->p};
    double *to[8] = {g.x, g.y, g.z, g.vx, g.vy, g.vz, g.rho, g.p};
    for (int k = 0; k < 8; k++) memcpy(to[k], from[k], n * sizeof *to[k]);
    memcpy(g.id, f->id, n * sizeof *g.id);
    memcpy(g.cell, f->cell, n * sizeof *g.cell);
    g.n = n;
    prt_fluid_free(f);
    *f = g;
}

/* Cells of halo around the own rows.  One makes every own particle's lists
 * complete, and those of the boundary particles in the own cells (their
 * fluid neighbours are within a cell): their owner computes their density
 * and pressure and sends p/rho^2 to the ranks whose rows see them.  Surface
 * tension reads its neighbours' normals, which read their neighbours: two
 * cells, and then every rank computes the boundary particles its rows see
 * (their lists are complete too).  SLUICE_PARALLEL_HALO_DEPTH=1|2 chooses. */
static int halo_depth_of(const eff_set *eff, int reach)
{
    const char *e = getenv("SLUICE_PARALLEL_HALO_DEPTH");
    int cells = eff && eff_find(eff, "surfaceTension") ? 2 : 1;
    if (e && *e) {
        cells = atoi(e);
        if (cells != 1 && cells != 2)
            sl_fatal("SLUICE_PARALLEL_HALO_DEPTH=%s: 1 or 2 (cells of halo)", e);
        if (cells == 1 && eff && eff_find(eff, "surfaceTension"))
            sl_fatal("SLUICE_PARALLEL_HALO_DEPTH=1: surfaceTension needs 2 cells of halo");
    }
    return cells * reach;
}

static int halo_depth(const pcs_solver *s) { return halo_depth_of(s->eff, s->grid.reach); }

/* The row tables of grid g and room for p ranks' cuts. */
static struct pcs_domain *domain_new(const nbr_grid *g, int p, int depth, const dom_periodic *per,
                                     double h)
{
    struct pcs_domain *d = sl_calloc(1, sizeof *d, "domain decomposition");
    const int rows = g->unit[0] == g->nc[0] && g->unit[1] == 1 && g->unit[2] == 1;
    d->nunits = g->nunits;
    d->ucells = g->ucells;
    d->pcells = rows ? (size_t)g->nc[0] : 1;
    d->npieces = g->ncells / d->pcells;
    d->upieces = d->ucells / d->pcells;
    d->pn[0] = rows ? 1 : g->nc[0];
    d->pn[1] = g->nc[1];
    d->pn[2] = g->nc[2];
    d->depth = depth;
    d->plin = sl_malloc(d->npieces * sizeof *d->plin, "grid pieces");
    d->kof = sl_malloc(d->npieces * sizeof *d->kof, "grid pieces");
    for (size_t lin = 0; lin < d->npieces; lin++) {
        const uint32_t k = (uint32_t)(g->rank[d->pcells * lin] / d->pcells);
        d->kof[lin] = k;
        d->plin[k] = (uint32_t)lin;
    }
    d->cut = sl_malloc(((size_t)p + 1) * sizeof *d->cut, "rank cuts");
    d->goff = sl_calloc((size_t)p + 1, sizeof *d->goff, "rank rows");
    d->boff = sl_calloc((size_t)p + 1, sizeof *d->boff, "rank rows");
    d->owner = sl_malloc(d->npieces * sizeof *d->owner, "piece owners");
    d->nstart = sl_malloc((d->npieces + 1) * sizeof *d->nstart, "halo pieces");
    d->mark = sl_malloc(d->npieces * sizeof *d->mark, "halo pieces");
    d->rowcount = sl_calloc(d->nunits, sizeof *d->rowcount, "unit counts");
    d->cnt_p = sl_calloc((size_t)p, sizeof *d->cnt_p, "rank counts");
    d->all_n = sl_calloc((size_t)p, sizeof *d->all_n, "rank counts");
    d->all_s = sl_calloc((size_t)p, sizeof *d->all_s, "rank counts");
    d->scnt = ints(p), d->sdis = ints(p), d->rcnt = ints(p), d->rdis = ints(p);
    d->hscnt = ints(p), d->hsdis = ints(p), d->hrcnt = ints(p), d->hrdis = ints(p);
    d->ws = ints(p), d->wsd = ints(p), d->wr = ints(p), d->wrd = ints(p);
    d->pcnt = ints(p), d->pdis = ints(p);
    d->bscnt = ints(p), d->bsdis = ints(p), d->brcnt = ints(p), d->brdis = ints(p);
    d->bpos = ints(p);
    d->bsend_own = depth < 2 * g->reach;
    prt_fluid_init(&d->mirror);
    prt_boundary_init(&d->mbound);
    nbr_list_init(&d->mbf);
    d->nb_real = SIZE_MAX;
    periodic_pieces(d, g, per, h);
    return d;
}

static void domain_free(struct pcs_domain *d);

void pcd_partition(const pcs_solver *s, int p, int *rank, size_t *stored, size_t *halo,
                   size_t *bstored, int *brank)
{
    struct pcs_domain *d = domain_new(&s->grid, p, halo_depth(s), &s->prm.periodic, s->h);
    const sl_fluid *f = s->f;
    const sl_boundary *b = s->b;
    for (size_t i = 0; i < f->n; i++)
        d->rowcount[row_of(s, d, f->x[i], f->y[i], f->z[i]) / d->upieces]++;
    set_cuts(d, d->rowcount, p);
    for (int r = 0; r < p; r++) stored[r] = halo[r] = bstored[r] = 0;
    for (size_t i = 0; i < f->n; i++) {
        const size_t k = row_of(s, d, f->x[i], f->y[i], f->z[i]);
        rank[i] = d->owner[k];
        stored[rank[i]]++;
        for (uint32_t q = d->nstart[k]; q < d->nstart[k + 1]; q++) halo[d->nrank[q]]++;
    }
    for (int r = 0; r < p; r++) stored[r] += halo[r];
    for (size_t j = 0; j < b->n - b->nimages; j++) { /* own rows and halo rows */
        const size_t k = row_of(s, d, b->x[j], b->y[j], b->z[j]);
        bstored[d->owner[k]]++;
        brank[j] = d->owner[k];
        for (uint32_t q = d->nstart[k]; q < d->nstart[k + 1]; q++) bstored[d->nrank[q]]++;
    }
    domain_free(d);
}

/* ---- set-up in parts (pcd_plan, case/case_part.h) ---- */

struct pcd_plan {
    nbr_grid grid;        /* the solver's grid (pcs_init_part makes the same again) */
    struct pcs_domain *d; /* rows, counts, cuts: handed to the solver (pcd_init) */
    int me, p, reach;
    size_t nfluid, nboundary;
    unsigned char *need; /* rows whose boundary particles the set-up needs */
};

int pcd_plan_usable(const pcs_params *p)
{
    const char *e = getenv("SLUICE_PARALLEL_EXCHANGE");
    if (e && (!strcmp(e, "gather") || !strcmp(e, "halo"))) return 0;
    return par_size() > 1 && !p->periodic.axes && !p->one_rank;
}

pcd_plan *pcd_plan_new(const pcs_params *prm, const eff_set *eff, const double lo[3],
                       const double hi[3], size_t nfluid, size_t nboundary)
{
    pcd_plan *pl = sl_calloc(1, sizeof *pl, "set-up plan");
    pl->me = par_rank();
    pl->p = par_size();
    pl->nfluid = nfluid;
    pl->nboundary = nboundary;
    nbr_grid_init(&pl->grid, lo, hi, pcs_support(prm), pcs_grid_cells(nfluid, nboundary));
    pl->reach = pl->grid.reach;
    pl->d = domain_new(&pl->grid, pl->p, halo_depth_of(eff, pl->reach), NULL, 0.0);
    return pl;
}

static size_t plan_row(const pcd_plan *pl, double x, double y, double z)
{
    return nbr_cell_rank(&pl->grid, x, y, z) / pl->d->pcells;
}

void pcd_plan_count(pcd_plan *pl, double x, double y, double z)
{
    pl->d->rowcount[plan_row(pl, x, y, z) / pl->d->upieces]++;
}

static void need_mark(struct pcs_domain *d, uint32_t k, void *ctx)
{
    (void)d;
    ((unsigned char *)ctx)[k] = 1;
}

/* The cuts from the counts (every rank counted the whole case alike), and
 * the rows whose boundary particles this rank makes: those within the
 * halo depth of an own row (it stores them) and two supports more (their
 * rest density reads their neighbours' masses, which read theirs). */
void pcd_plan_cut(pcd_plan *pl)
{
    struct pcs_domain *d = pl->d;
    d->imb_after = set_cuts(d, d->rowcount, pl->p);
    const int R = d->depth + 2 * pl->reach;
    pl->need = sl_calloc(d->npieces + 1, 1, "set-up pieces");
    for (size_t k = d->cut[pl->me] * d->upieces; k < d->cut[pl->me + 1] * d->upieces; k++)
        near_pieces(d, k, R, need_mark, pl->need);
}

int pcd_plan_fluid(const pcd_plan *pl, double x, double y, double z)
{
    return pl->d->owner[plan_row(pl, x, y, z)] == pl->me;
}

/* Whether a point of the box [lo, hi] may be in an own row: an own cell
 * among the cells the box meets (tested by their centres, so whatever
 * decides pcd_plan_fluid decides this). */
int pcd_plan_fluid_box(const pcd_plan *pl, const double lo[3], const double hi[3])
{
    const nbr_grid *g = &pl->grid;
    int c0[3], c1[3];
    for (int a = 0; a < 3; a++) {
        const double f0 = floor((lo[a] - g->lo[a]) * g->inv_cell);
        const double f1 = floor((hi[a] - g->lo[a]) * g->inv_cell), top = g->nc[a] - 1;
        c0[a] = (int)(f0 >= 0.0 ? (f0 < top ? f0 : top) : 0.0); /* NaN: 0 */
        c1[a] = (int)(f1 < top ? (f1 >= 0.0 ? f1 : 0.0) : top); /* NaN: the last */
    }
    for (int cz = c0[2]; cz <= c1[2]; cz++)
        for (int cy = c0[1]; cy <= c1[1]; cy++)
            for (int cx = c0[0]; cx <= c1[0]; cx++)
                if (pcd_plan_fluid(pl, g->lo[0] + (cx + 0.5) * g->cell,
                                   g->lo[1] + (cy + 0.5) * g->cell,
                                   g->lo[2] + (cz + 0.5) * g->cell))
                    return 1;
    return 0;
}

void pcd_plan_count_sum(pcd_plan *pl) { par_sum_longs(pl->d->rowcount, pl->d->nunits); }

int pcd_plan_boundary(const pcd_plan *pl, double x, double y, double z)
{
    return pl->need[plan_row(pl, x, y, z)];
}

void pcd_plan_built(pcd_plan *pl)
{
    nbr_grid_free(&pl->grid);
    free(pl->need);
    pl->need = NULL;
}

void pcd_plan_free(pcd_plan *pl)
{
    if (!pl) return;
    pcd_plan_built(pl);
    if (pl->d) domain_free(pl->d);
    free(pl);
}

size_t pcd_plan_fluid_total(const pcd_plan *pl) { return pl->nfluid; }
size_t pcd_plan_boundary_total(const pcd_plan *pl) { return pl->nboundary; }

static double rss_peak(void); /* peak resident bytes so far (VmHWM) */

void pcd_init(pcs_solver *s, pcd_plan *plan)
{
    const int p = s->split.size, me = s->split.rank;
    struct pcs_domain *d =
        plan ? plan->d : domain_new(&s->grid, p, halo_depth(s), &s->prm.periodic, s->h);
    if (plan) plan->d = NULL;
    s->split.dd = d;
    const char *th = getenv("SLUICE_PARALLEL_REBALANCE");
    d->threshold = th && *th ? atof(th) : 0.05;
    if (!(d->threshold >= 0.0))
        sl_fatal("SLUICE_PARALLEL_REBALANCE=%s: a fraction >= 0 is needed (0.05: rebalance when "
                 "the largest rank holds 5 %% more fluid than the mean)",
                 th);
    sl_fluid *f = s->f;
    d->setup_fluid = f->n;
    d->setup_boundary = s->b->n;
    d->parts = plan != NULL;
    if (!plan) { /* every rank holds every particle: the same cuts everywhere */
        for (size_t i = 0; i < f->n; i++)
            d->rowcount[row_of(s, d, f->x[i], f->y[i], f->z[i]) / d->upieces]++;
        d->imb_after = set_cuts(d, d->rowcount, p);
    } /* else the plan's cuts, from the counts of the whole case */
    size_t j = 0;
    for (size_t i = 0; i < f->n; i++)
        if (d->owner[row_of(s, d, f->x[i], f->y[i], f->z[i])] == me) move_to(f, j++, i);
    if (plan && j != f->n)
        sl_fatal("pcs_domain: %zu of this rank's %zu fluid particles lie outside its rows "
                 "(internal error)",
                 f->n - j, f->n);
    s->split.nglobal = plan ? plan->nfluid : f->n;
    f->n = j;
    d->nown = j;
    shrink(f, j + j / 4 + 1024); /* own and some halo; grows when it must */
    d->nsorted = 0;
    /* the boundary: own and halo rows; moving walls carry it across them */
    d->bmoving = s->eff && eff_find(s->eff, "movingBoundary");
    s->split.nbglobal = plan ? plan->nboundary : s->b->n;
    d->nb_real = s->halo.nb_img ? s->halo.nb_real : SIZE_MAX; /* periodic boundary images */
    keep_boundary_rows(s, d, s->split.nbglobal);
    sl_free_aligned(s->split.bbuf); /* the gather mode's, sized for every boundary particle */
    s->split.bbuf = NULL;
    /* overlap: the rows that read no halo value computed while it travels
     * (not with EFF_DENSITY effects, whose set-up reads the halo's x*) */
    const char *ov = getenv("SLUICE_PARALLEL_OVERLAP");
    if (ov && *ov && strcmp(ov, "0") && strcmp(ov, "1"))
        sl_fatal("SLUICE_PARALLEL_OVERLAP=%s: 0 (blocking exchanges) or 1 (overlap)", ov);
    s->split.overlap = !(ov && !strcmp(ov, "0")) && s->ndens == 0;
    d->with_b = d->bsend_own && s->prm.method->wall_density;
    d->peak_setup = rss_peak();
}

void pcd_free(pcs_solver *s)
{
    if (s->split.dd) domain_free(s->split.dd);
    s->split.dd = NULL;
}

static void domain_free(struct pcs_domain *d)
{
    free(d->plin), free(d->kof), free(d->cut), free(d->goff), free(d->boff), free(d->owner);
    free(d->istart), free(d->ipiece), free(d->iface), free(d->iadd);
    free(d->nstart), free(d->mark), free(d->rowcount), free(d->cnt_p), free(d->all_n);
    free(d->all_s);
    sl_free_aligned(d->nrank);
    free(d->scnt), free(d->sdis), free(d->rcnt), free(d->rdis);
    free(d->hscnt), free(d->hsdis), free(d->hrcnt), free(d->hrdis);
    free(d->ws), free(d->wsd), free(d->wr), free(d->wrd), free(d->pcnt), free(d->pdis);
    free(d->bscnt), free(d->bsdis), free(d->brcnt), free(d->brdis), free(d->bpos);
    sl_free_aligned(d->bown), sl_free_aligned(d->brow), sl_free_aligned(d->bmark);
    sl_free_aligned(d->isbuf), sl_free_aligned(d->irbuf);
    sl_free_aligned(d->mbstart), sl_free_aligned(d->bkeys);
    prt_boundary_free(&d->mbound);
    sl_free_aligned(d->bsend_idx), sl_free_aligned(d->brecv_idx);
    sl_free_aligned(d->dest);
    sl_free_aligned(d->sbuf), sl_free_aligned(d->rbuf);
    sl_free_aligned(d->send_idx), sl_free_aligned(d->recv_idx), sl_free_aligned(d->inv);
    prt_fluid_free(&d->mirror);
    sl_free_aligned(d->mfstart);
    nbr_list_free(&d->mbf);
    sl_free_aligned(d->gbuf);
    free(d->tail);
    out_free(d->out);
    sl_free_aligned(d->nearbox);
    free(d->nearmark), free(d->cell_lin);
    sl_free_aligned(d->fs_part), sl_free_aligned(d->fs_all), sl_free_aligned(d->fs_tail);
    sl_free_aligned(d->fs_tall), sl_free_aligned(d->fs_order);
    free(d);
}

/* ---- the start of a step: migration, rebalancing, halo ---- */

/* Destinations of the n particles (rows in f->cell); per-rank counts. */
static void destinations(const struct pcs_domain *d, const sl_fluid *f, int *dest, long *cnt, int p)
{
    memset(cnt, 0, (size_t)p * sizeof *cnt);
    for (size_t i = 0; i < f->n; i++) {
        dest[i] = d->owner[f->cell[i]];
        cnt[dest[i]]++;
    }
}

/* The particles whose row another rank owns go there; the kept ones stay
 * in order, the arrivals after them. */
static void migrate(pcs_solver *s, struct pcs_domain *d)
{
    sl_fluid *f = s->f;
    const int p = s->split.size, me = s->split.rank;
    const size_t n = f->n;
    memset(d->scnt, 0, (size_t)p * sizeof *d->scnt);
    for (size_t i = 0; i < n; i++)
        if (d->dest[i] != me) d->scnt[d->dest[i]]++;
    par_alltoall_int(d->scnt, d->rcnt);
    size_t ns = 0, nr = 0;
    for (int q = 0; q < p; q++) {
        d->sdis[q] = as_int(ns);
        ns += (size_t)d->scnt[q];
        d->rdis[q] = as_int(nr);
        nr += (size_t)d->rcnt[q];
        if (q > me) d->c.migrated_up += d->scnt[q];
        if (q < me) d->c.migrated_down += d->scnt[q];
    }
    d->sbuf = grow(d->sbuf, &d->sbuf_cap, REC * ns + 1, sizeof *d->sbuf, "migration buffer");
    d->rbuf = grow(d->rbuf, &d->rbuf_cap, REC * nr + 1, sizeof *d->rbuf, "migration buffer");
    int *pos = d->hscnt; /* scratch */
    memcpy(pos, d->sdis, (size_t)p * sizeof *pos);
    size_t j = 0;
    for (size_t i = 0; i < n; i++) {
        if (d->dest[i] == me) move_to(f, j++, i);
        else pack(f, i, d->sbuf + REC * (size_t)pos[d->dest[i]]++);
    }
    scale(d->scnt, REC, d->ws, d->wsd, p);
    scale(d->rcnt, REC, d->wr, d->wrd, p);
    par_exchange_double(d->sbuf, d->ws, d->wsd, d->rbuf, d->wr, d->wrd);
    f->n = j;
    reserve(f, j + nr);
    for (size_t k = 0; k < nr; k++) {
        unpack(f, j + k, d->rbuf + REC * k);
        f->cell[j + k] = (uint32_t)row_of(s, d, f->x[j + k], f->y[j + k], f->z[j + k]);
    }
    f->n = j + nr;
}

/* Every rank's own particles in the rows of the other ranks' halo go
 * there; they arrive after the own ones (recv_idx: where, before the
 * sort), send_idx the own rows sent, by rank. */
static void fill_halo(pcs_solver *s, struct pcs_domain *d)
{
    sl_fluid *f = s->f;
    const int p = s->split.size;
    const size_t n = f->n;
    memset(d->hscnt, 0, (size_t)p * sizeof *d->hscnt);
    for (size_t i = 0; i < n; i++) {
        const uint32_t k = f->cell[i];
        for (uint32_t q = d->nstart[k]; q < d->nstart[k + 1]; q++) d->hscnt[d->nrank[q]]++;
    }
    par_alltoall_int(d->hscnt, d->hrcnt);
    size_t ns = 0, nr = 0;
    for (int q = 0; q < p; q++) {
        d->hsdis[q] = as_int(ns);
        ns += (size_t)d->hscnt[q];
        d->hrdis[q] = as_int(nr);
        nr += (size_t)d->hrcnt[q];
    }
    d->nsend = ns;
    d->nrecv = nr;
    d->send_idx = grow(d->send_idx, &d->send_cap, ns + 1, sizeof *d->send_idx, "halo rows");
    d->recv_idx = grow(d->recv_idx, &d->recv_cap, nr + 1, sizeof *d->recv_idx, "halo rows");
    d->sbuf = grow(d->sbuf, &d->sbuf_cap, REC * ns + 1, sizeof *d->sbuf, "halo buffer");
    d->rbuf = grow(d->rbuf, &d->rbuf_cap, REC * nr + 1, sizeof *d->rbuf, "halo buffer");
    int *pos = d->scnt; /* scratch */
    memcpy(pos, d->hsdis, (size_t)p * sizeof *pos);
    for (size_t i = 0; i < n; i++) {
        const uint32_t k = f->cell[i];
        for (uint32_t q = d->nstart[k]; q < d->nstart[k + 1]; q++) {
            const size_t at = (size_t)pos[d->nrank[q]]++;
            d->send_idx[at] = (uint32_t)i;
            pack(f, i, d->sbuf + REC * at);
        }
    }
    scale(d->hscnt, REC, d->ws, d->wsd, p);
    scale(d->hrcnt, REC, d->wr, d->wrd, p);
    par_exchange_double(d->sbuf, d->ws, d->wsd, d->rbuf, d->wr, d->wrd);
    reserve(f, n + nr);
    for (size_t k = 0; k < nr; k++) {
        unpack(f, n + k, d->rbuf + REC * k);
        d->recv_idx[k] = (uint32_t)(n + k);
    }
    f->n = n + nr;
}

void pcd_distribute(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    sl_fluid *f = s->f;
    const int p = s->split.size;
    const double t0 = omp_get_wtime();
    const double c0 = par_counters().seconds;
    d->dest = grow(d->dest, &d->dest_cap, f->n + 1, sizeof *d->dest, "particle ranks");
    for (size_t i = 0; i < f->n; i++)
        f->cell[i] = (uint32_t)row_of(s, d, f->x[i], f->y[i], f->z[i]);
    destinations(d, f, d->dest, d->cnt_p, p);
    par_sum_longs(d->cnt_p, (size_t)p); /* what each rank would own */
    long total = 0, big = 0;
    for (int q = 0; q < p; q++) {
        total += d->cnt_p[q];
        big = d->cnt_p[q] > big ? d->cnt_p[q] : big;
    }
    const double imb = total > 0 ? (double)big * p / (double)total : 1.0;
    int recut = 0;
    if (imb > 1.0 + d->threshold && imb > d->imb_after + 0.5 * d->threshold) {
        /* rebalance: the cuts again from the global counts per row */
        memset(d->rowcount, 0, d->nunits * sizeof *d->rowcount);
        for (size_t i = 0; i < f->n; i++) d->rowcount[f->cell[i] / d->upieces]++;
        par_sum_longs(d->rowcount, d->nunits);
        d->imb_after = set_cuts(d, d->rowcount, p);
        destinations(d, f, d->dest, d->cnt_p, p);
        d->c.rebalances++;
        recut = 1;
    }
    if (d->bmoving || recut) distribute_boundary(s, d); /* to the rows that store them now */
    if (imb > d->c.imbalance_max) d->c.imbalance_max = imb;
    s->split.nglobal = (size_t)total;
    migrate(s, d);
    d->nown = f->n;
    fill_halo(s, d);
    s->time.comm += par_counters().seconds - c0;
    s->time.halo += omp_get_wtime() - t0;
}

/* ---- after the search ---- */

/* One-cell halo: the boundary particles whose p/rho^2 this rank sends
 * (those of its own rows in another rank's halo rows) and receives (those
 * of its halo rows, from their owners), in row order on both sides: the
 * boundary is the same on every rank, sorted by cell, so no list travels. */
static void boundary_lists(const pcs_solver *s, struct pcs_domain *d)
{
    const nbr_grid *g = &s->grid;
    const int p = s->split.size, me = s->split.rank;
    const size_t pc = d->pcells;
    for (int pass = 0; pass < 2; pass++) {
        memset(d->bscnt, 0, (size_t)p * sizeof *d->bscnt);
        memset(d->brcnt, 0, (size_t)p * sizeof *d->brcnt);
        for (size_t k = 0; k < d->npieces; k++) {
            const uint32_t b0 = g->bstart[k * pc], b1 = g->bstart[(k + 1) * pc];
            if (b1 == b0) continue;
            const int own = d->owner[k];
            for (uint32_t q = d->nstart[k]; q < d->nstart[k + 1]; q++) {
                const int to = (int)d->nrank[q];
                if (own == me) { /* to rank `to` */
                    if (pass)
                        for (uint32_t j = b0; j < b1; j++)
                            d->bsend_idx[d->bsdis[to] + d->bscnt[to]++] = j;
                    else d->bscnt[to] += (int)(b1 - b0);
                } else if (to == me) { /* from the owner */
                    if (pass)
                        for (uint32_t j = b0; j < b1; j++)
                            d->brecv_idx[d->brdis[own] + d->brcnt[own]++] = j;
                    else d->brcnt[own] += (int)(b1 - b0);
                }
            }
        }
        if (pass) break;
        size_t ns = 0, nr = 0;
        for (int q = 0; q < p; q++) {
            d->bsdis[q] = as_int(ns);
            ns += (size_t)d->bscnt[q];
            d->brdis[q] = as_int(nr);
            nr += (size_t)d->brcnt[q];
        }
        d->nbsend = ns;
        d->nbrecv = nr;
        d->bsend_idx = grow(d->bsend_idx, &d->bsend_cap, ns + 1, sizeof *d->bsend_idx, "halo rows");
        d->brecv_idx = grow(d->brecv_idx, &d->brecv_cap, nr + 1, sizeof *d->brecv_idx, "halo rows");
    }
}

/* The overlap's order: the own rows whose lists hold no halo particle
 * (no fluid neighbour outside the own rows, no boundary neighbour outside
 * the own cells [j0, j1): its p/rho^2 would travel) first, in order, then
 * the others; the boundary set's particles whose fluid neighbours are all
 * own first (their density reads no halo x*). */
static void split_inner(pcs_solver *s, struct pcs_domain *d, size_t j0, size_t j1)
{
    pcs_split *sp = &s->split;
    const uint32_t *ffs = s->ff.start, *ffi = s->ff.idx, *fbs = s->fb.start, *fbi = s->fb.idx;
    const uint32_t *bid = s->b->id;
    const size_t lo = d->lo, hi = d->hi, m = hi - lo;
    sp->order = grow(sp->order, &sp->order_cap, m + 1, sizeof *sp->order, "own rows");
    size_t a = 0, z = m;
    for (size_t i = lo; i < hi; i++) { /* inner from the front, border from the back */
        int in = 1;
        for (uint32_t q = ffs[i]; in && q < ffs[i + 1]; q++) in = ffi[q] >= lo && ffi[q] < hi;
        for (uint32_t q = fbs[i]; in && q < fbs[i + 1]; q++) /* images: refreshed after the wait */
            in = fbi[q] >= j0 && fbi[q] < j1 && bid[fbi[q]] < d->nb_real;
        if (in) sp->order[a++] = (uint32_t)i;
        else sp->order[--z] = (uint32_t)i;
    }
    for (size_t u = a, v = m; u + 1 < v; u++, v--) { /* the border rows in order */
        const uint32_t t = sp->order[u];
        sp->order[u] = sp->order[v - 1];
        sp->order[v - 1] = t;
    }
    sp->ninner = a;
    sp->norder = m;
    d->inner_sum += m ? (double)a / (double)m : 1.0;
    const uint32_t *bfs = s->bf.start, *bfi = s->bf.idx;
    size_t nin = 0;
    for (size_t q = 0; q < sp->nbset; q++) {
        const uint32_t j = sp->bset[q];
        int in = 1;
        for (uint32_t k = bfs[j]; in && k < bfs[j + 1]; k++) in = bfi[k] >= lo && bfi[k] < hi;
        if (in) { /* to the front (the set's order does not matter) */
            sp->bset[q] = sp->bset[nin];
            sp->bset[nin++] = j;
        }
    }
    sp->nbset_inner = nin;
}

void pcd_after_search(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    pcs_split *sp = &s->split;
    const nbr_grid *g = &s->grid;
    const sl_fluid *f = s->f;
    const int p = sp->size, me = sp->rank;
    const double c0 = par_counters().seconds;
    const size_t n = f->n, nb = s->b->n;
    /* the exchange lists in the sorted order (perm: new -> old) */
    d->inv = grow(d->inv, &d->inv_cap, n + 1, sizeof *d->inv, "halo rows");
    for (size_t i = 0; i < n; i++) d->inv[g->perm[i]] = (uint32_t)i;
    for (size_t k = 0; k < d->nsend; k++) d->send_idx[k] = d->inv[d->send_idx[k]];
    for (size_t k = 0; k < d->nrecv; k++) d->recv_idx[k] = d->inv[d->recv_idx[k]];
    const size_t c0cell = first_cell(d, me), c1cell = first_cell(d, me + 1);
    d->lo = g->fstart[c0cell];
    d->hi = g->fstart[c1cell];
    if (d->hi - d->lo != d->nown)
        sl_fatal("pcs_domain: %zu own rows after the sort, %zu before (internal error)",
                 d->hi - d->lo, d->nown);
    for (int r = 0; r <= p; r++) sp->row[r] = r <= me ? d->lo : d->hi;
    par_allgather_long((long)d->nown, d->all_n);
    d->goff[0] = 0;
    size_t mn = (size_t)-1, mx = 0;
    for (int r = 0; r < p; r++) {
        const size_t k = (size_t)d->all_n[r];
        d->goff[r + 1] = d->goff[r] + k;
        mn = k < mn ? k : mn;
        mx = k > mx ? k : mx;
    }
    sp->nglobal = d->goff[p];
    sp->gshift = (ptrdiff_t)d->goff[me] - (ptrdiff_t)d->lo;
    sp->rows_min = mn;
    sp->rows_max = mx;
    sp->steps++;
    sp->empty += mn == 0;
    sp->rows_min_sum += (double)mn;
    sp->rows_max_sum += (double)mx;
    /* the boundary particles this rank computes: the active ones in the
     * own cells (their lists are complete; so their owner holds their
     * serial density and pressure) and, with two cells of halo, those the
     * own rows see (their lists are complete too) */
    sp->bset = grow(sp->bset, &sp->bset_cap, nb + 1, sizeof *sp->bset, "boundary set");
    if (d->bmark_cap < nb + 1) {
        d->bmark = grow(d->bmark, &d->bmark_cap, nb + 1, sizeof *d->bmark, "boundary marks");
        memset(d->bmark, 0, d->bmark_cap * sizeof *d->bmark);
        d->bst = 0;
    }
    if (++d->bst == 0) {
        memset(d->bmark, 0, d->bmark_cap * sizeof *d->bmark);
        d->bst = 1;
    }
    size_t nbs = 0;
    const size_t j0 = g->bstart[c0cell], j1 = g->bstart[c1cell];
    for (size_t q = 0; q < s->nactive; q++)
        if (s->active[q] >= j0 && s->active[q] < j1) {
            sp->bset[nbs++] = s->active[q];
            d->bmark[s->active[q]] = d->bst;
        }
    if (d->bsend_own) boundary_lists(s, d); /* one cell: the others' p/rho^2 from their owners */
    else {                                  /* two cells: those the own rows see */
        const uint32_t *fbs = s->fb.start, *fbi = s->fb.idx;
        for (size_t i = d->lo; i < d->hi; i++)
            for (uint32_t q = fbs[i]; q < fbs[i + 1]; q++) {
                const uint32_t j = fbi[q];
                if (d->bmark[j] == d->bst) continue;
                d->bmark[j] = d->bst;
                sp->bset[nbs++] = j;
            }
    }
    sp->nbset = nbs;
    if (sp->overlap) split_inner(s, d, j0, j1);
    /* the active boundary particles in the own cells: counted once */
    long act = 0;
    for (size_t q = 0; q < s->nactive; q++) act += s->active[q] >= j0 && s->active[q] < j1;
    sp->nactive_all = (size_t)par_sum_long(act);
    d->c.searches++;
    d->stored_sum += (double)n;
    d->halo_sum += (double)d->nrecv;
    d->bstored_sum += (double)nb;
    d->blists = 1;
    sp->halo_rows = d->nrecv;
    sp->halo_sum += (double)d->nrecv;
    sp->halo_max = d->nrecv > sp->halo_max ? d->nrecv : sp->halo_max;
    s->time.comm += par_counters().seconds - c0;
}

/* ---- per PCISPH iteration ---- */

/* The halo's x* (3 doubles per particle) started, from send_idx. */
void pcd_exchange_predicted(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    const int p = s->split.size;
    const double t0 = omp_get_wtime();
    const double *x = s->f->xs, *y = s->f->ys, *z = s->f->zs;
    d->isbuf = grow(d->isbuf, &d->isbuf_cap, 3 * d->nsend + 1, sizeof *d->isbuf, "halo buffer");
    d->irbuf = grow(d->irbuf, &d->irbuf_cap, 3 * d->nrecv + 1, sizeof *d->irbuf, "halo buffer");
    double *o = d->isbuf;
    for (size_t k = 0; k < d->nsend; k++) {
        const uint32_t i = d->send_idx[k];
        o[3 * k] = x[i], o[3 * k + 1] = y[i], o[3 * k + 2] = z[i];
    }
    scale(d->hscnt, 3, d->ws, d->wsd, p);
    scale(d->hrcnt, 3, d->wr, d->wrd, p);
    par_exchange_start(d->isbuf, d->ws, d->wsd, d->irbuf, d->wr, d->wrd);
    d->inflight = 1;
    s->time.comm += omp_get_wtime() - t0;
    if (!s->split.overlap) pcd_wait(s);
}

void pcd_exchange_rows(pcs_solver *s, double *a, int width)
{
    struct pcs_domain *d = s->split.dd;
    const int p = s->split.size;
    const size_t w = (size_t)width;
    const double t0 = omp_get_wtime();
    pcd_wait(s); /* one exchange in flight at a time */
    d->isbuf = grow(d->isbuf, &d->isbuf_cap, w * d->nsend + 1, sizeof *d->isbuf, "halo buffer");
    d->irbuf = grow(d->irbuf, &d->irbuf_cap, w * d->nrecv + 1, sizeof *d->irbuf, "halo buffer");
    for (size_t k = 0; k < d->nsend; k++)
        memcpy(d->isbuf + w * k, a + w * d->send_idx[k], w * sizeof *a);
    scale(d->hscnt, width, d->ws, d->wsd, p);
    scale(d->hrcnt, width, d->wr, d->wrd, p);
    par_exchange_double(d->isbuf, d->ws, d->wsd, d->irbuf, d->wr, d->wrd);
    for (size_t k = 0; k < d->nrecv; k++)
        memcpy(a + w * d->recv_idx[k], d->irbuf + w * k, w * sizeof *a);
    s->time.comm += omp_get_wtime() - t0;
}

/* The halo's p/rho^2 and rho (2 doubles per particle), and with the
 * one-cell halo the boundary's p/rho^2 from the owners of their cells (1
 * each), in one message per neighbour rank, started. */
static void start_pressure(pcs_solver *s, struct pcs_domain *d)
{
    const int p = s->split.size;
    const double t0 = omp_get_wtime();
    const double *pt = s->f->pt, *rho = s->f->rho, *bpt = s->b->pt;
    const int wb = d->with_b;
    d->isbuf = grow(d->isbuf, &d->isbuf_cap, 2 * d->nsend + d->nbsend + 1, sizeof *d->isbuf,
                    "halo buffer");
    d->irbuf = grow(d->irbuf, &d->irbuf_cap, 2 * d->nrecv + d->nbrecv + 1, sizeof *d->irbuf,
                    "halo buffer");
    size_t at = 0, rat = 0;
    for (int q = 0; q < p; q++) {
        d->wsd[q] = as_int(at);
        for (int k = d->hsdis[q]; k < d->hsdis[q] + d->hscnt[q]; k++) {
            const uint32_t i = d->send_idx[k];
            d->isbuf[at++] = pt[i];
            d->isbuf[at++] = rho[i];
        }
        if (wb)
            for (int k = d->bsdis[q]; k < d->bsdis[q] + d->bscnt[q]; k++)
                d->isbuf[at++] = bpt[d->bsend_idx[k]];
        d->ws[q] = as_int(at) - d->wsd[q];
        d->wrd[q] = as_int(rat);
        rat += 2 * (size_t)d->hrcnt[q] + (wb ? (size_t)d->brcnt[q] : 0);
        d->wr[q] = as_int(rat) - d->wrd[q];
    }
    par_exchange_start(d->isbuf, d->ws, d->wsd, d->irbuf, d->wr, d->wrd);
    d->inflight = 2;
    s->time.comm += omp_get_wtime() - t0;
}

void pcd_wait(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    if (!d || !d->inflight) return;
    const int p = s->split.size;
    const double t0 = omp_get_wtime();
    par_exchange_wait();
    const double *o = d->irbuf;
    if (d->inflight == 1) {
        double *x = s->f->xs, *y = s->f->ys, *z = s->f->zs;
        for (size_t k = 0; k < d->nrecv; k++) {
            const uint32_t i = d->recv_idx[k];
            x[i] = o[3 * k], y[i] = o[3 * k + 1], z[i] = o[3 * k + 2];
        }
    } else {
        double *pt = s->f->pt, *rho = s->f->rho, *bpt = s->b->pt;
        size_t at = 0;
        for (int q = 0; q < p; q++) {
            for (int k = d->hrdis[q]; k < d->hrdis[q] + d->hrcnt[q]; k++) {
                const uint32_t i = d->recv_idx[k];
                pt[i] = o[at++];
                rho[i] = o[at++];
            }
            if (d->with_b)
                for (int k = d->brdis[q]; k < d->brdis[q] + d->brcnt[q]; k++)
                    bpt[d->brecv_idx[k]] = o[at++];
        }
    }
    /* periodic images from their originals, the halo's among them here now */
    if (dom_halo_on(&s->halo)) {
        if (d->inflight == 1) dom_refresh_predicted(&s->halo, s->f);
        else dom_refresh_pressure(&s->halo, s->f, s->b);
    }
    d->inflight = 0;
    s->time.comm += omp_get_wtime() - t0;
}

/* The rank whose own rows hold row g of the serial order. */
static int owner_of_row(const struct pcs_domain *d, int p, size_t g)
{
    int lo = 0, hi = p - 1;
    while (lo < hi) { /* the last rank with goff[r] <= g */
        const int mid = (lo + hi + 1) / 2;
        if (d->goff[mid] <= g) lo = mid;
        else hi = mid - 1;
    }
    while (d->goff[lo + 1] <= g) lo++; /* past empty ranks */
    return lo;
}

/* The density error's block sums in the serial order (SL_REDUCE_BLOCK
 * rows of the serial array each, summed one row at a time), on every
 * rank.  The density pass summed this rank's whole blocks and the start
 * of the block its rows end in; a block shared with lower ranks goes on
 * from the running sum they pass up (one double, point-to-point), so it
 * is summed in the serial order; then each block's sum is sent by the
 * rank holding its last row to every rank (N / 4096 doubles). */
static void chain_block_sums(pcs_solver *s, struct pcs_domain *d, const double *rows, double *part)
{
    const int p = s->split.size, me = s->split.rank;
    const size_t n = s->split.nglobal, B = SL_REDUCE_BLOCK;
    const size_t nb = (n + B - 1) / B;
    const size_t G0 = d->goff[me], G1 = d->goff[me + 1];
    const double *err = rows + d->lo; /* row G0 */
    if (G1 > G0) {
        const size_t bfirst = G0 / B, blast = (G1 - 1) / B;
        int sent = 0;
        if (G0 % B) { /* the block began on lower ranks */
            double run = par_recv_double(owner_of_row(d, p, G0 - 1));
            const size_t be = (bfirst + 1) * B < n ? (bfirst + 1) * B : n;
            const size_t e = be < G1 ? be : G1;
            for (size_t i = G0; i < e; i++) {
                run += err[i - G0];
                __asm__("" : "+m"(run)); /* one at a time, as the pass sums */
            }
            part[bfirst] = run;
            if (e < be) { /* and goes on past this rank's rows */
                par_send_double(run, owner_of_row(d, p, G1));
                sent = 1;
            }
        }
        if (!sent && G1 < n && G1 % B && !(G0 % B && blast == bfirst))
            par_send_double(part[blast], owner_of_row(d, p, G1));
    }
    size_t *off = d->boff;
    for (int r = 0; r <= p; r++) off[r] = d->goff[r] >= n ? nb : d->goff[r] / B;
    par_gather_rows(part, off); /* each block from the rank holding its last row */
}

void pcd_block_sums(pcs_solver *s, const double *rows, double *part)
{
    const double t0 = omp_get_wtime();
    chain_block_sums(s, s->split.dd, rows, part);
    s->time.comm += omp_get_wtime() - t0;
}

double pcd_after_density(pcs_solver *s, double emax)
{
    struct pcs_domain *d = s->split.dd;
    const double t0 = omp_get_wtime();
    chain_block_sums(s, d, s->err, s->err_block);
    s->time.comm += omp_get_wtime() - t0;
    /* the halo's p/rho^2 (the pressure force) and density (the next
     * density pass's EFF_DENSITY effects), and the boundary's p/rho^2:
     * started, completed before the pressure force reads them */
    start_pressure(s, d);
    const double t1 = omp_get_wtime();
    emax = par_max_double(emax); /* a maximum: exact in any order */
    s->time.comm += omp_get_wtime() - t1;
    if (!s->split.overlap) pcd_wait(s);
    return emax;
}

double pcd_vol_blocks(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    const int me = s->split.rank;
    const size_t B = SL_REDUCE_BLOCK;
    const size_t G0 = d->goff[me], G1 = d->goff[me + 1];
    const double *ev = s->err_vol + d->lo; /* row G0 */
    double *part = s->vol_block, vmax = -HUGE_VAL;
    const double t0 = omp_get_wtime();
    if (G1 > G0) /* this rank's whole blocks and the start of its last (as the pass sums err) */
        for (size_t blk = G0 / B; blk <= (G1 - 1) / B; blk++) {
            const size_t lo = blk * B > G0 ? blk * B : G0;
            const size_t hi = (blk + 1) * B < G1 ? (blk + 1) * B : G1;
            double sum = 0.0;
            for (size_t g = lo; g < hi; g++) {
                sum += ev[g - G0];
                __asm__("" : "+m"(sum)); /* one at a time: the serial order */
                vmax = ev[g - G0] > vmax ? ev[g - G0] : vmax;
            }
            part[blk] = sum;
        }
    chain_block_sums(s, d, s->err_vol, part);
    vmax = par_max_double(vmax); /* a maximum: exact in any order */
    s->time.comm += omp_get_wtime() - t0;
    return vmax;
}

/* ---- the end of a step ---- */

void pcd_keep_own(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    sl_fluid *f = s->f;
    const size_t lo = d->lo, m = d->nown;
    if (lo) {
        double *a[8] = {f->x, f->y, f->z, f->vx, f->vy, f->vz, f->rho, f->p};
        for (int k = 0; k < 8; k++) memmove(a[k], a[k] + lo, m * sizeof *a[k]);
        memmove(f->id, f->id + lo, m * sizeof *f->id);
        memmove(f->cell, f->cell + lo, m * sizeof *f->cell);
    }
    f->n = m;
    f->nhalo = 0; /* periodic images: made again after the next sort */
    d->nsorted = m;
    d->lo = 0;
    d->hi = m;
    d->fresh = 0;
}

void pcd_keep_emitted(pcs_solver *s, size_t n0)
{
    struct pcs_domain *d = s->split.dd;
    sl_fluid *f = s->f;
    const size_t n = f->n;
    if (n == n0) return;
    size_t j = n0;
    for (size_t i = n0; i < n; i++)
        if (d->owner[row_of(s, d, f->x[i], f->y[i], f->z[i])] == s->split.rank) move_to(f, j++, i);
    f->n = j;
    s->split.nglobal += n - n0; /* every rank emitted the same */
    d->fresh = 0;
}

/* ---- rank 0's whole state, for output and function objects ---- */

static int cmp_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* What rank 0 receives of a boundary particle for output and function
 * objects: x, n, m_b, rho, p, p/rho^2, the wall velocity, body, creation
 * index, and whether it was active at the last search. */
#define BOUT 16

/* Rank 0's copy of the boundary in the serial order ((cell, creation
 * index) at the current positions, as nbr_sort_boundary orders it): every
 * rank sends its own boundary particles with their last density and
 * pressure (their owner computed those), and whether their rows of the
 * last search were non-empty (the own cells' lists are complete).  With
 * sel (marks by cell rank), only those in the marked cells. */
static void gather_boundary(pcs_solver *s, struct pcs_domain *d, const unsigned char *sel)
{
    const sl_boundary *b = s->b;
    const int p = s->split.size, me = s->split.rank;
    const size_t n = b->n;
    const int lists = d->blists && s->bf.n == n;
    const uint32_t *st = s->bf.start;
    const nbr_grid *g = &s->grid;
    d->sbuf = grow(d->sbuf, &d->sbuf_cap, BOUT * d->nb_own + 1, sizeof *d->sbuf, "output buffer");
    size_t m = 0, mine = 0;
    for (size_t j = 0; j < n; j++) {
        if (!own_boundary(d, b->id[j])) continue;
        mine++;
        if (sel && !sel[nbr_cell_rank(g, b->x[j], b->y[j], b->z[j])]) continue;
        double *o = d->sbuf + BOUT * m++;
        o[0] = b->x[j], o[1] = b->y[j], o[2] = b->z[j];
        o[3] = b->nx[j], o[4] = b->ny[j], o[5] = b->nz[j];
        o[6] = b->mass[j], o[7] = b->rho[j], o[8] = b->p[j], o[9] = b->pt[j];
        o[10] = b->vx[j], o[11] = b->vy[j], o[12] = b->vz[j];
        o[13] = (double)b->body[j], o[14] = (double)b->id[j];
        o[15] = lists && st[j + 1] > st[j];
    }
    if (mine != d->nb_own)
        sl_fatal("pcs_domain: %zu own boundary particles stored of %zu (internal error)", mine,
                 d->nb_own);
    par_allgather_long((long)m, d->all_n);
    size_t total = 0;
    for (int r = 0; r < p; r++) {
        d->pcnt[r] = as_int(BOUT * (size_t)d->all_n[r]);
        d->pdis[r] = as_int(total);
        total += (size_t)d->pcnt[r];
    }
    if (!sel && total != BOUT * d->nb_global)
        sl_fatal("pcs_domain: %zu boundary particles owned by the ranks, %zu in the case "
                 "(internal error)",
                 total / BOUT, d->nb_global);
    if (!me) d->gbuf = grow(d->gbuf, &d->gbuf_cap, total + 1, sizeof *d->gbuf, "output buffer");
    par_gatherv_root(d->sbuf, d->pcnt[me], d->gbuf, d->pcnt, d->pdis);
    if (me) return;
    const size_t N = total / BOUT;
    d->bkeys = grow(d->bkeys, &d->bkeys_cap, 2 * N + 2, sizeof *d->bkeys, "output order");
    if (!d->mbstart)
        d->mbstart = sl_alloc_aligned((g->ncells + 1) * sizeof *d->mbstart, "grid cells");
    /* (key, where) pairs sorted by key: the serial order of those gathered */
    for (size_t q = 0; q < N; q++) {
        const double *o = d->gbuf + BOUT * q;
        const uint32_t id = (uint32_t)o[14];
        if (id >= d->nb_global)
            sl_fatal("pcs_domain: boundary index %u of %zu (internal error)", id, d->nb_global);
        d->bkeys[2 * q] = (uint64_t)nbr_cell_rank(g, o[0], o[1], o[2]) << 32 | id;
        d->bkeys[2 * q + 1] = q;
    }
    qsort(d->bkeys, N, 2 * sizeof *d->bkeys, cmp_u64);
    sl_boundary *mb = &d->mbound;
    prt_boundary_reserve(mb, N);
    memset(d->mbstart, 0, (g->ncells + 1) * sizeof *d->mbstart);
    nbr_list *l = &d->mbf;
    if (l->rows_cap < N + 1) {
        sl_free_aligned(l->start);
        l->start = sl_alloc_aligned((N + 1) * sizeof *l->start, "boundary rows");
        l->rows_cap = N + 1;
    }
    l->start[0] = 0;
    for (size_t q = 0; q < N; q++) {
        const uint32_t id = (uint32_t)(d->bkeys[2 * q] & 0xffffffffu);
        const double *o = d->gbuf + BOUT * d->bkeys[2 * q + 1];
        mb->x[q] = o[0], mb->y[q] = o[1], mb->z[q] = o[2];
        mb->nx[q] = o[3], mb->ny[q] = o[4], mb->nz[q] = o[5];
        mb->mass[q] = o[6], mb->rho[q] = o[7], mb->p[q] = o[8], mb->pt[q] = o[9];
        mb->vx[q] = o[10], mb->vy[q] = o[11], mb->vz[q] = o[12];
        mb->body[q] = (uint32_t)o[13];
        mb->id[q] = id;
        d->mbstart[(d->bkeys[2 * q] >> 32) + 1]++;
        l->start[q + 1] = l->start[q] + (o[15] != 0.0 ? 1u : 0u);
    }
    mb->n = N;
    for (size_t c = 0; c < g->ncells; c++) d->mbstart[c + 1] += d->mbstart[c];
    /* no lists yet (before the first search): the serial run's are empty,
     * and every particle counts as active (fo_query: the counts differ) */
    l->n = lists ? N : N + 1;
}

/* The whole fluid's z extent (exact: a min and a max), for the gauges. */
static void fluid_z_extent(const pcs_solver *s, struct pcs_domain *d)
{
    const sl_fluid *f = s->f;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < f->n; i++) {
        if (f->z[i] < lo) lo = f->z[i];
        if (f->z[i] > hi) hi = f->z[i];
    }
    d->zext[0] = -par_max_double(-lo);
    d->zext[1] = par_max_double(hi);
}

/* Rank 0's copy of the fluid (sel NULL: all of it; else the particles
 * whose sorted cell or current cell is marked) and of the boundary, in
 * the serial order.  grid_ok: the serial copy's grid would describe it
 * (fo_query's test: no particle appended since the sort, every one within
 * a cell of its sorted cell); when not, rank 0's copy gets no fluid cell
 * starts, so that queries test every particle of it, as the serial run's. */
static void gather_sel(pcs_solver *s, struct pcs_domain *d, const unsigned char *sel, int grid_ok)
{
    const double t0 = omp_get_wtime(), c0 = par_counters().seconds, b0 = par_counters().bytes;
    const int p = s->split.size, me = s->split.rank;
    const sl_fluid *f = s->f;
    const nbr_grid *g = &s->grid;
    const size_t n = f->n, ns = d->nsorted < n ? d->nsorted : n;
    d->sbuf = grow(d->sbuf, &d->sbuf_cap, REC_OUT * n + 1, sizeof *d->sbuf, "output buffer");
    size_t m = 0, ms = 0;
    for (size_t i = 0; i < n; i++) {
        if (sel && !sel[nbr_cell_rank(g, f->x[i], f->y[i], f->z[i])] &&
            !(i < ns && sel[f->cell[i]]))
            continue;
        pack(f, i, d->sbuf + REC_OUT * m);
        d->sbuf[REC_OUT * m + REC] = (double)f->cell[i];
        m++;
        if (i < ns) ms = m;
    }
    par_allgather_long((long)m, d->all_n);
    par_allgather_long((long)ms, d->all_s);
    size_t total = 0;
    for (int r = 0; r < p; r++) {
        d->pcnt[r] = as_int(REC_OUT * (size_t)d->all_n[r]);
        d->pdis[r] = as_int(total);
        total += (size_t)d->pcnt[r];
    }
    if (!me) d->gbuf = grow(d->gbuf, &d->gbuf_cap, total + 1, sizeof *d->gbuf, "output buffer");
    par_gatherv_root(d->sbuf, d->pcnt[me], d->gbuf, d->pcnt, d->pdis);
    if (!me) {
        /* the rows sorted at the last search in rank order (the serial
         * order), then the particles appended since (emitted), by id */
        const size_t N = total / REC_OUT;
        sl_fluid *mf = &d->mirror;
        if (mf->cap < N) prt_fluid_reserve(mf, N + N / 4 + 64);
        d->tail = d->tail_cap >= N + 1
            ? d->tail
            : sl_realloc(d->tail, (N + 1) * sizeof *d->tail, "output order");
        d->tail_cap = d->tail_cap > N + 1 ? d->tail_cap : N + 1;
        size_t j = 0, nt = 0;
        for (int r = 0; r < p; r++) {
            const double *src = d->gbuf + d->pdis[r];
            for (size_t i = 0; i < (size_t)d->all_n[r]; i++) {
                const double *o = src + REC_OUT * i;
                if (i < (size_t)d->all_s[r]) {
                    unpack(mf, j, o);
                    mf->cell[j++] = (uint32_t)o[REC];
                } else {
                    const size_t at = (size_t)(o - d->gbuf) / REC_OUT;
                    d->tail[nt++] = (uint64_t)(uint32_t)o[8] << 32 | (uint64_t)at;
                }
            }
        }
        const size_t nsort = j;
        qsort(d->tail, nt, sizeof *d->tail, cmp_u64);
        for (size_t q = 0; q < nt; q++) {
            const double *o = d->gbuf + REC_OUT * (d->tail[q] & 0xffffffffu);
            unpack(mf, j, o);
            mf->cell[j++] = (uint32_t)o[REC];
        }
        mf->n = N;
        /* the grid of the last search over the sorted rows */
        if (!d->mfstart)
            d->mfstart = sl_alloc_aligned((g->ncells + 1) * sizeof *d->mfstart, "grid cells");
        memset(d->mfstart, 0, (g->ncells + 1) * sizeof *d->mfstart);
        for (size_t i = 0; i < nsort; i++) d->mfstart[mf->cell[i] + 1]++;
        for (size_t c = 0; c < g->ncells; c++) d->mfstart[c + 1] += d->mfstart[c];
        d->mgrid = *g;
        d->mgrid.fstart = grid_ok ? d->mfstart : NULL;
        d->mgrid.hstart = NULL;
        d->mgrid.bcell = d->mgrid.bperm = NULL; /* not for sorting */
        d->mgrid.bperm_cap = 0;
        d->have_mirror = 1;
    }
    gather_boundary(s, d, sel); /* after the fluid's: it reuses the buffers */
    if (!me) d->mgrid.bstart = d->mbstart;
    fluid_z_extent(s, d);
    d->c.gather_seconds += omp_get_wtime() - t0;
    d->c.gather_bytes += par_counters().bytes - b0;
    s->time.comm += par_counters().seconds - c0;
}

void pcd_gather(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    if (d->fresh) return;
    gather_sel(s, d, NULL, 1);
    d->fresh = 1;
    d->c.gathers++;
}

/* The cell of v along axis a, as fo_query's cell_range takes it, moved by
 * `by` cells and clamped into the grid. */
static int near_cell(const nbr_grid *g, double v, int a, int by)
{
    double c = floor((v - g->lo[a]) * g->inv_cell) + by;
    const double top = (double)(g->nc[a] - 1);
    if (!(c >= 0.0)) c = 0.0; /* also NaN, and -inf */
    if (c > top) c = top;
    return (int)c;
}

void pcd_gather_near(pcs_solver *s, const double *boxes, size_t nboxes)
{
    struct pcs_domain *d = s->split.dd;
    const nbr_grid *g = &s->grid;
    long nb = (long)nboxes;
    par_bcast(&nb, sizeof nb);
    d->nearbox =
        grow(d->nearbox, &d->nearbox_cap, 6 * (size_t)nb + 1, sizeof *d->nearbox, "query boxes");
    if (!s->split.rank && nb) memcpy(d->nearbox, boxes, 6 * (size_t)nb * sizeof *boxes);
    if (nb) par_bcast(d->nearbox, 6 * (size_t)nb * sizeof *d->nearbox);
    /* the cells a query in a box reads: fo_query's reach around its cell */
    if (!d->nearmark) {
        d->nearmark = sl_malloc(g->ncells + 1, "query cells");
        d->cell_lin = sl_malloc((g->ncells + 1) * sizeof *d->cell_lin, "query cells");
        for (size_t lin = 0; lin < g->ncells; lin++) d->cell_lin[g->rank[lin]] = (uint32_t)lin;
    }
    memset(d->nearmark, 0, g->ncells);
    const int reach = (int)ceil(s->h * g->inv_cell - 1e-9) + 1;
    size_t marked = 0;
    for (long q = 0; q < nb; q++) {
        const double *bx = d->nearbox + 6 * q;
        int lo[3], hi[3];
        for (int a = 0; a < 3; a++) {
            lo[a] = near_cell(g, bx[a], a, -reach);
            hi[a] = near_cell(g, bx[3 + a], a, reach);
        }
        for (int cz = lo[2]; cz <= hi[2]; cz++)
            for (int cy = lo[1]; cy <= hi[1]; cy++)
                for (int cx = lo[0]; cx <= hi[0]; cx++) {
                    const size_t lin = (size_t)cx +
                        (size_t)g->nc[0] * ((size_t)cy + (size_t)g->nc[1] * (size_t)cz);
                    marked += !d->nearmark[g->rank[lin]];
                    d->nearmark[g->rank[lin]] = 1;
                }
    }
    /* would the serial copy's grid describe it (fo_index_update)? */
    const sl_fluid *f = s->f;
    const size_t n = f->n, ns = d->nsorted < n ? d->nsorted : n;
    const size_t nx = (size_t)g->nc[0], nxy = nx * (size_t)g->nc[1];
    int bad = ns != n;
    for (size_t i = 0; i < ns && !bad; i++) {
        const size_t lin = d->cell_lin[f->cell[i]];
        const int c[3] = {(int)(lin % nx), (int)(lin % nxy / nx), (int)(lin / nxy)};
        const double x[3] = {f->x[i], f->y[i], f->z[i]};
        for (int a = 0; a < 3; a++) {
            const int k = near_cell(g, x[a], a, 0) - c[a];
            if (k < -1 || k > 1) bad = 1;
        }
    }
    const int grid_ok = !par_max_int(bad);
    gather_sel(s, d, d->nearmark, grid_ok);
    d->fresh = 0; /* not the whole state */
    d->c.near_gathers++;
    d->c.near_cells = marked;
}

/* ---- the function objects' sums over every row, without the rows ---- */

#define TAG_SUM 23

/* The running sums of a block continued across a rank boundary (k doubles). */
static void sum_send(const double *run, size_t k, const struct pcs_domain *d, int p, size_t g)
{
    par_send_bytes(run, k * sizeof *run, owner_of_row(d, p, g), TAG_SUM);
}

/* The bytes received and seconds spent, counted for the End summary. */
static void fo_counted(const pcs_solver *s, double t0, double b0)
{
    struct pcs_domain *d = s->split.dd;
    d->c.fo_reductions++;
    d->c.fo_bytes += par_counters().bytes - b0;
    d->c.fo_seconds += omp_get_wtime() - t0;
}

void pcd_sum_rows(const pcs_solver *s, size_t k, pcs_row_terms terms, const void *ctx, double *sum)
{
    struct pcs_domain *d = s->split.dd;
    const double t0 = omp_get_wtime(), b0 = par_counters().bytes;
    const int p = s->split.size, me = s->split.rank;
    const sl_fluid *f = s->f;
    const size_t B = SL_REDUCE_BLOCK, ns = d->goff[p], N = s->split.nglobal;
    const size_t G0 = d->goff[me], G1 = d->goff[me + 1];
    const size_t nbs = (ns + B - 1) / B, nball = (N + B - 1) / B;
    const size_t mine = d->nsorted < f->n ? d->nsorted : f->n;
    if (d->lo != 0 || mine != G1 - G0 || N < ns)
        sl_fatal("pcs_domain: sums over %zu own rows of [%zu, %zu) (internal error)", mine, G0, G1);
    double *part = d->fs_part =
        grow(d->fs_part, &d->fs_part_cap, k * nbs + 1, sizeof *d->fs_part, "block sums");
    if (G1 > G0) {
        const size_t bfirst = G0 / B, blast = (G1 - 1) / B;
        const int cont = G0 % B != 0;            /* the first block began on lower ranks */
        const int hand = G1 < ns && G1 % B != 0; /* the last goes on past this rank's rows */
#pragma omp parallel for schedule(dynamic, 1)
        for (size_t blk = bfirst + (size_t)cont; blk <= blast; blk++) {
            double run[PCS_SUM_TERMS] = {0.0, 0.0, 0.0, 0.0};
            const size_t lo = blk * B > G0 ? blk * B : G0;
            const size_t hi = (blk + 1) * B < G1 ? (blk + 1) * B : G1;
            pcs_sums_rows(f, lo - G0, hi - G0, k, terms, ctx, run);
            for (size_t q = 0; q < k; q++) part[blk * k + q] = run[q];
        }
        if (hand && !(cont && blast == bfirst)) sum_send(part + blast * k, k, d, p, G1);
        if (cont) {
            double run[PCS_SUM_TERMS];
            par_recv_bytes(run, k * sizeof *run, owner_of_row(d, p, G0 - 1), TAG_SUM);
            const size_t e = (bfirst + 1) * B < G1 ? (bfirst + 1) * B : G1;
            pcs_sums_rows(f, 0, e - G0, k, terms, ctx, run);
            for (size_t q = 0; q < k; q++) part[bfirst * k + q] = run[q];
            if (hand && blast == bfirst) sum_send(run, k, d, p, G1);
        }
    }
    /* each block's sum on rank 0, from the rank holding its last row */
    size_t *off = d->boff;
    for (int r = 0; r <= p; r++) off[r] = d->goff[r] >= ns ? nbs : d->goff[r] / B;
    for (int r = 0; r < p; r++) {
        d->pcnt[r] = as_int(k * (off[r + 1] - off[r]));
        d->pdis[r] = as_int(k * off[r]);
    }
    double *all = NULL;
    if (!me)
        all = d->fs_all =
            grow(d->fs_all, &d->fs_all_cap, k * nball + 1, sizeof *d->fs_all, "block sums");
    par_gatherv_root(part + k * off[me], d->pcnt[me], all, d->pcnt, d->pdis);
    /* the rows appended since the sort (emitted), with their terms, to rank
     * 0: the serial array's rows [ns, N), by id */
    const size_t nt_mine = f->n - mine, rec = k + 1;
    par_allgather_long((long)nt_mine, d->all_n);
    size_t nt = 0;
    for (int r = 0; r < p; r++) {
        d->pcnt[r] = as_int(rec * (size_t)d->all_n[r]);
        d->pdis[r] = as_int(rec * nt);
        nt += (size_t)d->all_n[r];
    }
    if (nt != N - ns)
        sl_fatal("pcs_domain: %zu rows appended since the sort, %zu expected (internal error)", nt,
                 N - ns);
    if (nt) {
        double *t = d->fs_tail = grow(d->fs_tail, &d->fs_tail_cap, rec * nt_mine + 1,
                                      sizeof *d->fs_tail, "appended rows");
        for (size_t i = mine; i < f->n; i++) {
            terms(ctx, f, i, t + rec * (i - mine));
            t[rec * (i - mine) + k] = (double)f->id[i];
        }
        double *ta = NULL;
        if (!me)
            ta = d->fs_tall = grow(d->fs_tall, &d->fs_tall_cap, rec * nt + 1, sizeof *d->fs_tall,
                                   "appended rows");
        par_gatherv_root(t, d->pcnt[me], ta, d->pcnt, d->pdis);
        if (!me) {
            uint64_t *ord = d->fs_order =
                grow(d->fs_order, &d->fs_order_cap, nt + 1, sizeof *d->fs_order, "appended rows");
            for (size_t q = 0; q < nt; q++)
                ord[q] = (uint64_t)(uint32_t)ta[rec * q + k] << 32 | (uint64_t)q;
            qsort(ord, nt, sizeof *ord, cmp_u64);
            double run[PCS_SUM_TERMS] = {0.0, 0.0, 0.0, 0.0};
            for (size_t q = 0; q < nt; q++) {
                const size_t g = ns + q, blk = g / B;
                const double *tv = ta + rec * (ord[q] & 0xffffffffu);
                if (g % B == 0)
                    for (size_t c = 0; c < k; c++) run[c] = 0.0;
                else if (q == 0) /* the last sorted block goes on */
                    for (size_t c = 0; c < k; c++) run[c] = all[blk * k + c];
                for (size_t c = 0; c < k; c++) {
                    run[c] += tv[c];
                    __asm__("" : "+m"(run[c])); /* one row at a time, as pcs_sums_rows */
                }
                if (g % B == B - 1 || g == N - 1)
                    for (size_t c = 0; c < k; c++) all[blk * k + c] = run[c];
            }
        }
    }
    if (!me) pcs_sums_blocks(all, nball, k, sum);
    fo_counted(s, t0, b0);
}

void pcd_sum_longs(const pcs_solver *s, long *c, size_t n)
{
    const double t0 = omp_get_wtime(), b0 = par_counters().bytes;
    par_sum_longs(c, n);
    fo_counted(s, t0, b0);
}

void pcd_max_doubles(const pcs_solver *s, double *m, size_t n)
{
    const double t0 = omp_get_wtime(), b0 = par_counters().bytes;
    for (size_t i = 0; i < n; i++) m[i] = par_max_double(m[i]);
    fo_counted(s, t0, b0);
}

const double *pcd_mirror_zext(const pcs_solver *s)
{
    const struct pcs_domain *d = s->split.dd;
    return d ? d->zext : NULL;
}

const sl_fluid *pcd_mirror(const pcs_solver *s)
{
    const struct pcs_domain *d = s->split.dd;
    return d && d->have_mirror ? &d->mirror : NULL;
}

const nbr_grid *pcd_mirror_grid(const pcs_solver *s)
{
    const struct pcs_domain *d = s->split.dd;
    return d && d->have_mirror ? &d->mgrid : NULL;
}

const sl_boundary *pcd_mirror_boundary(const pcs_solver *s)
{
    const struct pcs_domain *d = s->split.dd;
    return d && d->have_mirror ? &d->mbound : NULL;
}

const nbr_list *pcd_mirror_bf(const pcs_solver *s)
{
    const struct pcs_domain *d = s->split.dd;
    return d && d->have_mirror && d->mbf.start ? &d->mbf : NULL;
}

void pcd_localize_snapshot(const pcs_solver *s, pcs_snapshot *snap)
{
    const struct pcs_domain *d = s->split.dd;
    if (!d) return;
    size_t j = 0;
    for (size_t i = 0; i < snap->n; i++) {
        if (d->owner[row_of(s, d, snap->x[i], snap->y[i], snap->z[i])] != s->split.rank) continue;
        snap->x[j] = snap->x[i], snap->y[j] = snap->y[i], snap->z[j] = snap->z[i];
        snap->vx[j] = snap->vx[i], snap->vy[j] = snap->vy[i], snap->vz[j] = snap->vz[i];
        snap->p[j] = snap->p[i], snap->rho[j] = snap->rho[i];
        snap->id[j] = snap->id[i];
        j++;
    }
    snap->n = j;
}

/* The peak resident memory of this process (VmHWM, bytes; 0 where /proc
 * is not). */
static double rss_peak(void)
{
    FILE *fp = fopen("/proc/self/status", "r");
    char line[256];
    double kb = 0.0;
    if (!fp) return 0.0;
    while (fgets(line, sizeof line, fp))
        if (!strncmp(line, "VmHWM:", 6)) kb = atof(line + 6);
    fclose(fp);
    return 1024.0 * kb;
}

/* The resident memory of this process now (bytes; 0 where /proc is not). */
static double rss_now(void)
{
    FILE *fp = fopen("/proc/self/statm", "r");
    unsigned long size = 0, res = 0;
    if (!fp) return 0.0;
    const int ok = fscanf(fp, "%lu %lu", &size, &res) == 2;
    fclose(fp);
    return ok ? (double)res * (double)sysconf(_SC_PAGESIZE) : 0.0;
}

pcd_counts pcd_counters(const pcs_solver *s)
{
    const struct pcs_domain *d = s->split.dd;
    pcd_counts c = d->c;
    const double searches = c.searches > 0 ? (double)c.searches : 1.0;
    const double stored = (double)(s->f->n > d->nown ? s->f->n : d->nown);
    c.stored_max = (size_t)par_max_double((double)(d->nown + d->nrecv));
    c.stored_min = (size_t)-par_max_double(-(double)(d->nown + d->nrecv));
    c.halo_max = (size_t)par_max_double((double)d->nrecv);
    c.halo_min = (size_t)-par_max_double(-(double)d->nrecv);
    c.stored_mean = d->stored_sum / searches;
    c.halo_mean = d->halo_sum / searches;
    c.cap = s->f->cap;
    const double mem = rss_now();
    c.mem_max = par_max_double(mem);
    c.mem_min = -par_max_double(-mem);
    const double hwm = rss_peak();
    c.peak_root = hwm;
    par_bcast(&c.peak_root, sizeof c.peak_root);
    c.peak_others_max = par_max_double(s->split.rank ? hwm : 0.0);
    c.peak_others_min = -par_max_double(s->split.rank ? -hwm : -1e300);
    const nbr_list *ls[3] = {&s->ff, &s->fb, &s->bf};
    double arrays = (double)s->f->cap * PRT_FLUID_BYTES + (double)s->b->cap * PRT_BOUNDARY_BYTES;
    for (int k = 0; k < 3; k++) arrays += 4.0 * (double)(ls[k]->rows_cap + ls[k]->idx_cap);
    c.arrays_max = par_max_double(arrays);
    c.arrays_min = -par_max_double(-arrays);
    c.migrated_up = par_sum_long(c.migrated_up);
    c.migrated_down = par_sum_long(c.migrated_down);
    c.bstored_max = (size_t)par_max_double((double)s->b->n);
    c.bstored_min = (size_t)-par_max_double(-(double)s->b->n);
    c.bstored_mean = d->bstored_sum / searches;
    c.nb_global = d->nb_global;
    c.bdistributions = d->bdistributions;
    c.bmigrated = par_sum_long(d->bmigrated);
    c.overlap = s->split.overlap;
    c.inner_share = -par_max_double(-d->inner_sum / searches);
    c.parts = d->parts;
    c.setup_fluid_max = (size_t)par_max_double((double)d->setup_fluid);
    c.setup_fluid_min = (size_t)-par_max_double(-(double)d->setup_fluid);
    c.setup_boundary_max = (size_t)par_max_double((double)d->setup_boundary);
    c.setup_boundary_min = (size_t)-par_max_double(-(double)d->setup_boundary);
    c.setup_fluid = d->setup_fluid;
    c.setup_boundary = d->setup_boundary;
    c.peak_setup_max = par_max_double(d->peak_setup);
    c.peak_setup_min = -par_max_double(-d->peak_setup);
    if ((size_t)par_sum_long((long)d->nb_own) != d->nb_global)
        sl_fatal("pcs_domain: the ranks own %ld boundary particles of %zu (internal error)",
                 par_sum_long((long)d->nb_own), d->nb_global);
    (void)stored;
    return c;
}

/* ---- streamed output: rank 0 writes, the others serve their parts ---- */

/* Tuples of the window rank 0 holds of the array it is writing: every
 * array of a file passes through it (x, y, z of 16384 particles: 384 KiB);
 * SLUICE_PARALLEL_OUTPUT_WINDOW sets another (the tests' small windows
 * cross every rank's part). */
#define OUT_WINDOW      16384
#define OUT_MAX_STREAMS 40
#define TAG_ASK         21
#define TAG_PART        22

typedef struct pcd_stream {
    pcs_solver *s;
    int set, ncomp, col[3];
    size_t tsz; /* bytes per tuple */
    sl_source src;
    int read;   /* its first window was filled in this write */
    int dup;    /* streams of the same set and columns made before it in this write */
    size_t zbs; /* compressed reads: the block size (0: none yet) */
    int zlevel;
} pcd_stream;

/* What a stream is (set, columns and which of those alike: the restart
 * file's ids and fluid.vtu's are both the fluid's id column), to recognise
 * it in the next write. */
typedef struct out_key {
    int set, ncomp, col[3], dup;
    int z; /* read compressed (not compared) */
} out_key;

/* A particle emitted since the last sort: serial appends them by id. */
typedef struct out_tail {
    uint32_t id, rank;
    uint64_t local;
} out_tail;

/* The boundary's own particles in the serial order: key (cell, id). */
typedef struct out_bkey {
    uint64_t key;
    uint32_t j;
} out_bkey;

struct pcd_out {
    int active;
    size_t *off[3]; /* per set: rank r's tuples are [off[r], off[r+1]) (sorted fluid only) */
    size_t total[3];
    out_tail *tail;
    size_t ntail, tail_cap;
    double *tbuf;
    size_t tbuf_cap;
    uint32_t *bperm; /* this rank's own boundary particles in the serial order */
    out_bkey *bkey;
    size_t bperm_cap;
    const pcs_snapshot *prev;
    double pmax;
    pcd_stream st[OUT_MAX_STREAMS];
    int nst;
    unsigned char *win;
    const pcd_stream *wcur;
    size_t w0, wn, window;
    /* the next window, asked for while the writer compresses this one:
     * its tuples [p0, p0 + pn) of stream pcur arrive in win2 */
    int prefetch, pending, npost;
    unsigned char *win2;
    const pcd_stream *pcur;
    size_t p0, pn;
    long prefetched, discarded;
    int seq_off, cross_off; /* this write's reads: not sequential; not in the last order */
    /* the order the writer read the streams in: this write's (seq), the
     * last write's (order: after its stream k it read stream k + 1) */
    out_key seq[OUT_MAX_STREAMS], order[OUT_MAX_STREAMS];
    int nseq, norder;
    /* compressed blocks (zlib appended VTK data): compress_ranks: every
     * rank compresses the blocks inside its part of an array when rank 0
     * starts it (the others' all at once, while rank 0 does its own), and
     * rank 0 receives them in order, OUT_ZBATCH blocks a message.
     * Rank 0: the batch received (blocks [zb0, zb1) of stream zst, rank
     * zrank: zlen, then the bytes at zbuf); raw, a block's bytes.  The
     * others: their blocks of the array asked for (zown: the bytes, zoff:
     * each block's start, blocks [zown0, zown1)). */
    int compress_ranks, in_zread;
    size_t zlimit; /* in_zread: a raw window ends at this tuple (the block's end) */
    const pcd_stream *zst;
    int zrank;
    size_t zb0, zb1;
    unsigned char *zbuf, *raw;
    size_t zbuf_cap, raw_cap;
    unsigned char *zown;
    size_t zown_cap, *zoff, zoff_cap, zown0, zown1;
    long zblocks_ranks, zblocks_root;
    double bytes0, t0;
};

static void out_free(struct pcd_out *o)
{
    if (!o) return;
    for (int k = 0; k < 3; k++) free(o->off[k]);
    free(o->tail), sl_free_aligned(o->tbuf), free(o->bperm), free(o->bkey), free(o->win);
    free(o->win2), free(o->zbuf), free(o->raw), free(o->zown), free(o->zoff);
    free(o);
}

static size_t col_size(int c) { return c == PCD_ID || c == PCD_BODY ? 4 : 8; }

static int cmp_bkey(const void *a, const void *b)
{
    const uint64_t x = ((const out_bkey *)a)->key, y = ((const out_bkey *)b)->key;
    return (x > y) - (x < y);
}

static int cmp_tail(const void *a, const void *b)
{
    const out_tail *x = a, *y = b;
    return (x->id > y->id) - (x->id < y->id);
}

/* Tuples [first, first + count) of set `set`, this rank's part, packed as
 * VTK lays them out (components interleaved). */
static void out_pack(const pcs_solver *s, const struct pcd_out *o, int set, int ncomp,
                     const int *col, size_t first, size_t count, unsigned char *out)
{
    const sl_fluid *f = s->f;
    const sl_boundary *b = s->b;
    const pcs_snapshot *q = o->prev;
    const double rho0 = s->prm.rho0;
    for (size_t i = first; i < first + count; i++)
        for (int k = 0; k < ncomp; k++) {
            const int c = col[k];
            double v = 0.0;
            uint32_t u = 0;
            if (set == PCD_SET_FLUID) {
                switch (c) {
                case PCD_X:
                    v = f->x[i];
                    break;
                case PCD_Y:
                    v = f->y[i];
                    break;
                case PCD_Z:
                    v = f->z[i];
                    break;
                case PCD_VX:
                    v = f->vx[i];
                    break;
                case PCD_VY:
                    v = f->vy[i];
                    break;
                case PCD_VZ:
                    v = f->vz[i];
                    break;
                case PCD_P:
                    v = f->p[i];
                    break;
                case PCD_RHO:
                    v = f->rho[i];
                    break;
                case PCD_DERR:
                    v = pcs_density_error_percent(f->rho[i], rho0);
                    break;
                case PCD_PR:
                    v = pcs_pressure_ratio(f->p[i], o->pmax);
                    break;
                case PCD_ID:
                    u = f->id[i];
                    break;
                default:
                    sl_fatal("pcs_domain: fluid output column %d (internal error)", c);
                }
            } else if (set == PCD_SET_BOUNDARY) {
                const size_t j = o->bperm[i];
                switch (c) {
                case PCD_X:
                    v = b->x[j];
                    break;
                case PCD_Y:
                    v = b->y[j];
                    break;
                case PCD_Z:
                    v = b->z[j];
                    break;
                case PCD_NX:
                    v = b->nx[j];
                    break;
                case PCD_NY:
                    v = b->ny[j];
                    break;
                case PCD_NZ:
                    v = b->nz[j];
                    break;
                case PCD_P:
                    v = b->p[j];
                    break;
                case PCD_RHO:
                    v = b->rho[j];
                    break;
                case PCD_MASS:
                    v = b->mass[j];
                    break;
                case PCD_PT:
                    v = b->pt[j];
                    break;
                case PCD_ID:
                    u = b->id[j];
                    break;
                case PCD_BODY:
                    u = b->body[j];
                    break;
                default:
                    sl_fatal("pcs_domain: boundary output column %d (internal error)", c);
                }
            } else {
                switch (c) {
                case PCD_X:
                    v = q->x[i];
                    break;
                case PCD_Y:
                    v = q->y[i];
                    break;
                case PCD_Z:
                    v = q->z[i];
                    break;
                case PCD_VX:
                    v = q->vx[i];
                    break;
                case PCD_VY:
                    v = q->vy[i];
                    break;
                case PCD_VZ:
                    v = q->vz[i];
                    break;
                case PCD_P:
                    v = q->p[i];
                    break;
                case PCD_RHO:
                    v = q->rho[i];
                    break;
                case PCD_ID:
                    u = q->id[i];
                    break;
                default:
                    sl_fatal("pcs_domain: snapshot output column %d (internal error)", c);
                }
            }
            if (col_size(c) == 4) memcpy(out, &u, 4), out += 4;
            else memcpy(out, &v, 8), out += 8;
        }
}

/* Tuples [first, first + count) of rank r's part, into out: packed here,
 * or asked of rank r (one request, one reply; the reply received now, or,
 * `later`, posted and completed by par_irecv_wait). */
static void out_get(pcs_solver *s, struct pcd_out *o, const pcd_stream *st, int r, size_t first,
                    size_t count, unsigned char *out, int later)
{
    if (!count) return;
    if (r == s->split.rank) {
        out_pack(s, o, st->set, st->ncomp, st->col, first, count, out);
        return;
    }
    const int64_t ask[8] = {1,          st->set,    st->ncomp,      st->col[0],
                            st->col[1], st->col[2], (int64_t)first, (int64_t)count};
    par_send_bytes(ask, sizeof ask, r, TAG_ASK);
    if (!later) {
        par_recv_bytes(out, count * st->tsz, r, TAG_PART);
        return;
    }
    if (o->npost == PAR_MAX_IRECV) par_irecv_wait(), o->npost = 0;
    par_irecv_bytes(out, count * st->tsz, r, TAG_PART);
    o->npost++;
}

/* A window: the stream's tuples [t, t + window) in the serial order (rank
 * by rank; then the particles emitted since the last sort, by id), into
 * buf; `later`: the replies posted, not waited for.  Returns the count. */
static size_t out_fill_into(pcs_solver *s, struct pcd_out *o, const pcd_stream *st, size_t t,
                            unsigned char *buf, int later)
{
    const int p = s->split.size;
    const size_t *off = o->off[st->set], nsorted = off[p];
    size_t end = t + o->window < o->total[st->set] ? t + o->window : o->total[st->set];
    if (o->in_zread && o->zlimit < end) end = o->zlimit > t ? o->zlimit : t + 1;
    size_t g = t;
    int r = 0;
    while (g < end && g < nsorted) {
        while (off[r + 1] <= g) r++;
        const size_t c = (off[r + 1] < end ? off[r + 1] : end) - g;
        out_get(s, o, st, r, g - off[r], c, buf + (g - t) * st->tsz, later);
        g += c;
    }
    while (g < end) { /* the tail: runs of one rank's consecutive particles */
        const out_tail *e = &o->tail[g - nsorted];
        size_t c = 1;
        while (g + c < end && e[c].rank == e->rank && e[c].local == e->local + c) c++;
        out_get(s, o, st, (int)e->rank, (size_t)e->local, c, buf + (g - t) * st->tsz, later);
        g += c;
    }
    return end - t;
}

static out_key key_of(const pcd_stream *st)
{
    return (out_key){st->set, st->ncomp, {st->col[0], st->col[1], st->col[2]}, st->dup, 0};
}

static int same_key(out_key a, out_key b)
{
    return a.set == b.set && a.ncomp == b.ncomp && a.col[0] == b.col[0] && a.col[1] == b.col[1] &&
        a.col[2] == b.col[2] && a.dup == b.dup;
}

/* The stream the writer will read after st, judged by the last write's
 * order (the writers read their arrays in a fixed order): one of this
 * write's streams not read yet, or NULL. */
static const pcd_stream *out_next_stream(const struct pcd_out *o, const pcd_stream *st)
{
    const out_key k = key_of(st);
    for (int i = 0; i + 1 < o->norder; i++)
        if (same_key(o->order[i], k)) {
            if (o->order[i + 1].z) return NULL; /* compressed by its ranks: nothing to fetch */
            for (int j = 0; j < o->nst; j++)
                if (!o->st[j].read && same_key(key_of(&o->st[j]), o->order[i + 1]))
                    return &o->st[j];
            return NULL;
        }
    return NULL;
}

/* The window holding tuple t of stream st: the prefetched one when it is
 * (then the next is asked for at once, so that the ranks pack and send it
 * while the writer compresses this one: the stream's next window, or
 * after its last the first of the stream the last write read next), else
 * filled now.  A prefetched window the writer does not read next is
 * completed and dropped, and the write prefetches no more. */
static void out_fill(pcs_solver *s, struct pcd_out *o, pcd_stream *st, size_t t)
{
    if (!st->read) {
        st->read = 1;
        if (o->nseq < OUT_MAX_STREAMS) o->seq[o->nseq++] = key_of(st);
    }
    if (o->pending && o->pcur == st && t >= o->p0 && t < o->p0 + o->pn) {
        par_irecv_wait();
        o->npost = o->pending = 0;
        unsigned char *w = o->win;
        o->win = o->win2, o->win2 = w;
        o->wcur = st, o->w0 = o->p0, o->wn = o->pn;
    } else {
        if (o->pending) {
            par_irecv_wait();
            /* the writer read another stream than the last write did next, or
             * not the next window of the stream it was reading */
            if (o->pcur != st && !o->p0) o->cross_off = 1;
            else o->seq_off = 1;
            o->npost = o->pending = 0;
            o->discarded++;
        }
        o->wn = out_fill_into(s, o, st, t, o->win, 0);
        o->wcur = st, o->w0 = t;
    }
    if (!o->prefetch || !o->wn || o->in_zread) return;
    const pcd_stream *nst = st;
    size_t next = o->w0 + o->wn;
    if (next < o->total[st->set] && o->seq_off) return;
    if (next >= o->total[st->set]) {
        if (o->cross_off) return;
        nst = out_next_stream(o, st);
        next = 0;
        if (!nst || !o->total[nst->set]) return;
    }
    o->pn = out_fill_into(s, o, nst, next, o->win2, 1);
    o->pcur = nst, o->p0 = next, o->pending = 1;
    o->prefetched++;
}

static void out_read(void *ctx, size_t off, size_t len, void *dst)
{
    pcd_stream *st = ctx;
    pcs_solver *s = st->s;
    struct pcd_out *o = s->split.dd->out;
    unsigned char *out = dst;
    while (len > 0) {
        const size_t t = off / st->tsz;
        if (o->wcur != st || t < o->w0 || t >= o->w0 + o->wn) out_fill(s, o, st, t);
        else if (o->pending) par_irecv_test(); /* let the next window move */
        if (!o->wn) sl_fatal("pcs_domain: output read past the end (internal error)");
        const size_t wend = (o->w0 + o->wn) * st->tsz;
        const size_t take = len < wend - off ? len : wend - off;
        memcpy(out, o->win + (off - o->w0 * st->tsz), take);
        out += take;
        off += take;
        len -= take;
    }
}

#define OUT_ZBATCH 16 /* compressed blocks per message */

/* The blocks of a stream (nbytes in all, blocks of bs) wholly inside rank
 * r's sorted part: [*b0, *b1). */
static void out_zblocks(const struct pcd_out *o, int set, size_t tsz, size_t bs, int r, size_t *b0,
                        size_t *b1)
{
    const size_t lo = o->off[set][r] * tsz, hi = o->off[set][r + 1] * tsz;
    const size_t nbytes = o->total[set] * tsz, nblocks = (nbytes + bs - 1) / bs;
    *b0 = (lo + bs - 1) / bs;
    *b1 = hi == nbytes ? nblocks : hi / bs;
    if (*b1 < *b0) *b1 = *b0;
}

/* A rank's blocks of one stream, compressed at once (the threads share
 * the blocks; each block's bytes are compress2's whatever the thread). */
static void out_zcompress(pcs_solver *s, struct pcd_out *o, int set, int ncomp, const int *col,
                          size_t bs, int level)
{
    size_t tsz = 0;
    for (int k = 0; k < ncomp; k++) tsz += col_size(col[k]);
    const int me = s->split.rank;
    size_t b0, b1;
    out_zblocks(o, set, tsz, bs, me, &b0, &b1);
    const size_t nb = b1 - b0, cap = compressBound((uLong)bs), lo = o->off[set][me] * tsz;
    const size_t nbytes = o->total[set] * tsz;
    o->zoff = grow(o->zoff, &o->zoff_cap, nb + 1, sizeof *o->zoff, "output blocks");
    o->zown = grow(o->zown, &o->zown_cap, nb * cap + 1, 1, "output blocks");
    const int nt = omp_get_max_threads();
    o->raw = grow(o->raw, &o->raw_cap, (size_t)nt * (bs + 2 * tsz), 1, "output blocks");
    size_t *zl = o->zoff + 1; /* each block's length first, then the starts */
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t q = 0; q < nb; q++) {
        unsigned char *raw = o->raw + (size_t)omp_get_thread_num() * (bs + 2 * tsz);
        const size_t g0 = (b0 + q) * bs, len = nbytes - g0 < bs ? nbytes - g0 : bs;
        const size_t l0 = g0 - lo, first = l0 / tsz, last = (l0 + len + tsz - 1) / tsz;
        out_pack(s, o, set, ncomp, col, first, last - first, raw);
        uLongf zlen = (uLongf)cap;
        if (compress2(o->zown + q * cap, &zlen, raw + (l0 - first * tsz), (uLong)len, level) !=
            Z_OK)
            sl_fatal("pcs_domain: zlib failed on an output block (internal error)");
        zl[q] = zlen;
    }
    /* packed: the blocks one after another, zoff[q] the start of block q */
    size_t at = 0;
    for (size_t q = 0; q < nb; q++) {
        const size_t len = zl[q];
        memmove(o->zown + at, o->zown + q * cap, len);
        o->zoff[q] = at;
        at += len;
    }
    o->zoff[nb] = at;
    o->zown0 = b0, o->zown1 = b1;
}

/* The reply to a batch request: the lengths of blocks [b0, b1) (8 B each),
 * then their bytes, one message. */
static void out_zsend(struct pcd_out *o, size_t b0, size_t b1)
{
    if (b0 < o->zown0 || b1 > o->zown1 || b1 <= b0 || b1 - b0 > OUT_ZBATCH)
        sl_fatal("pcs_domain: compressed output blocks %zu-%zu asked for, %zu-%zu held (internal "
                 "error)",
                 b0, b1, o->zown0, o->zown1);
    const size_t q0 = b0 - o->zown0, q1 = b1 - o->zown0;
    const size_t data = o->zoff[q1] - o->zoff[q0], head = (b1 - b0) * sizeof(uint64_t);
    o->raw = grow(o->raw, &o->raw_cap, head + data, 1, "output blocks");
    for (size_t q = q0; q < q1; q++) {
        const uint64_t len = o->zoff[q + 1] - o->zoff[q];
        memcpy(o->raw + (q - q0) * sizeof len, &len, sizeof len);
    }
    memcpy(o->raw + head, o->zown + o->zoff[q0], data);
    par_send_bytes(o->raw, head + data, 0, TAG_PART);
}

static void out_read(void *ctx, size_t off, size_t len, void *dst);

/* zread of a stream (rank 0): a block wholly inside another rank's part
 * from that rank (compressed there), any other compressed here. */
static size_t out_zread(void *ctx, size_t off, size_t len, int level, void *dst, size_t cap)
{
    pcd_stream *st = ctx;
    pcs_solver *s = st->s;
    struct pcd_out *o = s->split.dd->out;
    const int p = s->split.size;
    if (!st->zbs) { /* the array's first block: every rank compresses its blocks now */
        if (off) sl_fatal("pcs_domain: compressed output not read from its start (internal error)");
        st->zbs = len, st->zlevel = level;
        if (!st->read) {
            st->read = 1;
            out_key k = key_of(st);
            k.z = 1;
            if (o->nseq < OUT_MAX_STREAMS) o->seq[o->nseq++] = k;
        }
        const int64_t ask[8] = {2,          st->set,    st->ncomp,        st->col[0],
                                st->col[1], st->col[2], (int64_t)st->zbs, level};
        for (int r = 1; r < p; r++) par_send_bytes(ask, sizeof ask, r, TAG_ASK);
    }
    const size_t bs = st->zbs, nbytes = o->total[st->set] * st->tsz;
    if (off % bs || level != st->zlevel || len != (nbytes - off < bs ? nbytes - off : bs))
        sl_fatal("pcs_domain: compressed output read out of its blocks (internal error)");
    const size_t b = off / bs;
    /* the rank whose sorted part holds the block's first byte */
    const size_t *ro = o->off[st->set];
    int r = 0;
    while (r + 1 < p && ro[r + 1] * st->tsz <= off) r++;
    size_t b0, b1;
    out_zblocks(o, st->set, st->tsz, bs, r, &b0, &b1);
    if (r == 0 || b < b0 || b >= b1) { /* here: rank 0's, across ranks, or the tail */
        o->raw = grow(o->raw, &o->raw_cap, len, 1, "output blocks");
        o->in_zread = 1;
        o->zlimit = (off + len + st->tsz - 1) / st->tsz;
        out_read(st, off, len, o->raw);
        o->in_zread = 0;
        uLongf zlen = (uLongf)cap;
        if (compress2(dst, &zlen, o->raw, (uLong)len, level) != Z_OK)
            sl_fatal("pcs_domain: zlib failed on an output block (internal error)");
        o->zblocks_root++;
        return zlen;
    }
    if (o->zst != st || o->zrank != r || b < o->zb0 || b >= o->zb1) {
        const size_t e = b + OUT_ZBATCH < b1 ? b + OUT_ZBATCH : b1;
        const int64_t ask[8] = {3, (int64_t)b, (int64_t)e, 0, 0, 0, 0, 0};
        par_send_bytes(ask, sizeof ask, r, TAG_ASK);
        const size_t most = (e - b) * (sizeof(uint64_t) + compressBound((uLong)bs));
        o->zbuf = grow(o->zbuf, &o->zbuf_cap, most, 1, "output blocks");
        par_recv_bytes_upto(o->zbuf, most, r, TAG_PART);
        o->zst = st, o->zrank = r, o->zb0 = b, o->zb1 = e;
    }
    size_t at = (o->zb1 - o->zb0) * sizeof(uint64_t);
    uint64_t zl = 0;
    for (size_t q = o->zb0; q <= b; q++) {
        memcpy(&zl, o->zbuf + (q - o->zb0) * sizeof zl, sizeof zl);
        if (q < b) at += (size_t)zl;
    }
    if (zl > cap)
        sl_fatal("pcs_domain: a compressed output block larger than its bound (internal error)");
    memcpy(dst, o->zbuf + at, (size_t)zl);
    o->zblocks_ranks++;
    return (size_t)zl;
}

/* The prefix offsets of one count per rank. */
static void out_offsets(struct pcd_out *o, int set, const long *all, int p)
{
    if (!o->off[set]) o->off[set] = sl_malloc(((size_t)p + 1) * sizeof *o->off[set], "output");
    o->off[set][0] = 0;
    for (int r = 0; r < p; r++) o->off[set][r + 1] = o->off[set][r] + (size_t)all[r];
}

int pcd_output_begin(pcs_solver *s, const pcs_snapshot *prev)
{
    struct pcs_domain *d = s->split.dd;
    const double t0 = omp_get_wtime(), c0 = par_counters().seconds;
    const int p = s->split.size, me = s->split.rank;
    if (!d->out) {
        d->out = sl_calloc(1, sizeof *d->out, "output");
        const char *w = getenv("SLUICE_PARALLEL_OUTPUT_WINDOW");
        d->out->window = w && *w ? (size_t)atol(w) : OUT_WINDOW;
        if (!(w && *w ? atol(w) >= 1 && atol(w) <= 1L << 26 : 1))
            sl_fatal("SLUICE_PARALLEL_OUTPUT_WINDOW=%s: the particles rank 0 holds of an "
                     "array it writes, 1 to 67108864 (default %d)",
                     w, OUT_WINDOW);
        d->out->win = sl_malloc(d->out->window * 3 * sizeof(double), "output window");
        const char *pf = getenv("SLUICE_PARALLEL_OUTPUT_PREFETCH");
        d->out->prefetch = !(pf && *pf) || !strcmp(pf, "1");
        if (pf && *pf && strcmp(pf, "0") && strcmp(pf, "1"))
            sl_fatal("SLUICE_PARALLEL_OUTPUT_PREFETCH=%s: 1 (rank 0 asks for the next window "
                     "of an array while it writes this one; the default) or 0",
                     pf);
        const char *zc = getenv("SLUICE_PARALLEL_OUTPUT_COMPRESS");
        d->out->compress_ranks = !(zc && *zc) || !strcmp(zc, "ranks");
        if (zc && *zc && strcmp(zc, "ranks") && strcmp(zc, "root"))
            sl_fatal("SLUICE_PARALLEL_OUTPUT_COMPRESS=%s: ranks (every rank compresses the "
                     "blocks of its part of fluid.vtu and boundary.vtu; the default) or root "
                     "(rank 0 compresses them all)",
                     zc);
        if (d->out->prefetch && !s->split.rank)
            d->out->win2 = sl_malloc(d->out->window * 3 * sizeof(double), "output window");
    }
    struct pcd_out *o = d->out;
    o->bytes0 = par_counters().bytes;
    o->t0 = t0;
    const sl_fluid *f = s->f;
    const size_t n = f->n, ns = d->nsorted < n ? d->nsorted : n;
    /* the counts: sorted fluid, all fluid, own boundary, the snapshot */
    par_allgather_long((long)ns, d->all_s);
    out_offsets(o, PCD_SET_FLUID, d->all_s, p);
    par_allgather_long((long)n, d->all_n);
    size_t nt = 0, nall = 0;
    for (int r = 0; r < p; r++) nall += (size_t)d->all_n[r];
    o->total[PCD_SET_FLUID] = nall;
    nt = nall - o->off[PCD_SET_FLUID][p];
    /* the tail's ids on rank 0, ordered as the serial code appends them */
    for (int r = 0; r < p; r++) {
        d->pcnt[r] = as_int((size_t)(d->all_n[r] - d->all_s[r]));
        d->pdis[r] = r ? d->pdis[r - 1] + d->pcnt[r - 1] : 0;
    }
    o->tbuf = grow(o->tbuf, &o->tbuf_cap, (n - ns) + nt + 1, sizeof *o->tbuf, "output order");
    double *mine = o->tbuf, *all = o->tbuf + (n - ns);
    for (size_t i = ns; i < n; i++) mine[i - ns] = (double)f->id[i];
    if (nt) par_gatherv_root(mine, d->pcnt[me], all, d->pcnt, d->pdis);
    o->ntail = 0;
    if (!me && nt) {
        if (o->tail_cap < nt) {
            free(o->tail);
            o->tail_cap = nt + nt / 4;
            o->tail = sl_malloc(o->tail_cap * sizeof *o->tail, "output order");
        }
        for (int r = 0; r < p; r++)
            for (int k = 0; k < d->pcnt[r]; k++)
                o->tail[o->ntail++] = (out_tail){(uint32_t)all[d->pdis[r] + k], (uint32_t)r,
                                                 (uint64_t)d->all_s[r] + (uint64_t)k};
        qsort(o->tail, o->ntail, sizeof *o->tail, cmp_tail);
    }
    /* the largest pressure (the pressure ratio's scale): a max, exact */
    double pmax = 0.0;
    for (size_t i = 0; i < n; i++)
        if (f->p[i] > pmax) pmax = f->p[i];
    o->pmax = par_max_double(pmax);
    /* the own boundary particles by (cell, creation index) */
    const sl_boundary *b = s->b;
    const size_t nb = d->nb_own_real; /* periodic images left out, as the serial write does */
    if (o->bperm_cap < nb + 1) {
        free(o->bperm), free(o->bkey);
        o->bperm_cap = nb + nb / 4 + 1;
        o->bperm = sl_malloc(o->bperm_cap * sizeof *o->bperm, "output order");
        o->bkey = sl_malloc(o->bperm_cap * sizeof *o->bkey, "output order");
    }
    size_t m = 0;
    for (size_t j = 0; j < b->n; j++) {
        if (b->id[j] >= d->nb_real || !own_boundary(d, b->id[j])) continue;
        /* count every own one, store at most nb: more than nb is caught below */
        if (m < nb)
            o->bkey[m] = (out_bkey){
                (uint64_t)nbr_cell_rank(&s->grid, b->x[j], b->y[j], b->z[j]) << 32 | b->id[j],
                (uint32_t)j};
        m++;
    }
    if (m != nb)
        sl_fatal("pcs_domain: %zu own boundary particles stored of %zu (internal error)", m, nb);
    qsort(o->bkey, nb, sizeof *o->bkey, cmp_bkey);
    for (size_t q = 0; q < nb; q++) o->bperm[q] = o->bkey[q].j;
    par_allgather_long((long)nb, d->all_n);
    out_offsets(o, PCD_SET_BOUNDARY, d->all_n, p);
    o->total[PCD_SET_BOUNDARY] = o->off[PCD_SET_BOUNDARY][p];
    /* rank order is the serial order when each rank's keys follow the
     * lower ranks' (own rows are a run of cells): checked */
    double ends[2] = {nb ? (double)(o->bkey[0].key >> 32) : -1.0,
                      nb ? (double)(o->bkey[nb - 1].key >> 32) : -1.0};
    o->tbuf = grow(o->tbuf, &o->tbuf_cap, 2 * (size_t)p + 1, sizeof *o->tbuf, "output order");
    for (int r = 0; r < p; r++) d->pcnt[r] = 2, d->pdis[r] = 2 * r;
    par_gatherv_root(ends, 2, o->tbuf, d->pcnt, d->pdis);
    if (!me) {
        double last = -1.0;
        for (int r = 0; r < p; r++) {
            if (o->tbuf[2 * r] < 0.0) continue;
            if (o->tbuf[2 * r] < last)
                sl_fatal("pcs_domain: rank %d's boundary particles are not after rank %d's in the "
                         "grid's order (internal error)",
                         r, r - 1);
            last = o->tbuf[2 * r + 1];
        }
    }
    /* the snapshot of the start of the step before (restart files) */
    o->prev = prev;
    par_allgather_long(prev ? (long)prev->n : 0L, d->all_n);
    out_offsets(o, PCD_SET_PREV, d->all_n, p);
    o->total[PCD_SET_PREV] = o->off[PCD_SET_PREV][p];
    o->nst = 0;
    o->wcur = NULL;
    o->wn = 0;
    o->pending = o->npost = 0;
    o->discarded = 0;
    o->nseq = 0;
    o->seq_off = o->cross_off = 0;
    o->zst = NULL;
    o->zblocks_ranks = o->zblocks_root = 0;
    o->active = 1;
    d->c.out_window = o->window;
    if (!me) return 1;
    /* the others serve their parts until rank 0 is done */
    unsigned char *buf = o->win;
    for (;;) {
        int64_t ask[8];
        par_recv_bytes(ask, sizeof ask, 0, TAG_ASK);
        if (!ask[0]) break;
        const int col[3] = {(int)ask[3], (int)ask[4], (int)ask[5]};
        if (ask[0] == 2) { /* compress this rank's blocks of an array */
            if (ask[1] != PCD_SET_FLUID && ask[1] != PCD_SET_BOUNDARY && ask[1] != PCD_SET_PREV)
                sl_fatal("pcs_domain: an output request for set %ld (internal error)",
                         (long)ask[1]);
            if (ask[2] < 1 || ask[2] > 3 || ask[6] < 1 || ask[7] < 0 || ask[7] > 9)
                sl_fatal("pcs_domain: an output request for blocks of %ld bytes (internal error)",
                         (long)ask[6]);
            out_zcompress(s, o, (int)ask[1], (int)ask[2], col, (size_t)ask[6], (int)ask[7]);
            continue;
        }
        if (ask[0] == 3) {
            out_zsend(o, (size_t)ask[1], (size_t)ask[2]);
            continue;
        }
        size_t tsz = 0;
        for (int k = 0; k < (int)ask[2]; k++) tsz += col_size(col[k]);
        const size_t first = (size_t)ask[6], count = (size_t)ask[7];
        const size_t have = ask[1] == PCD_SET_FLUID ? n
            : ask[1] == PCD_SET_BOUNDARY            ? nb
                                                    : (prev ? prev->n : 0);
        if (ask[2] < 1 || ask[2] > 3 || count > o->window || first + count > have)
            sl_fatal("pcs_domain: an output request for tuples %zu-%zu of %zu (internal error)",
                     first, first + count, have);
        out_pack(s, o, (int)ask[1], (int)ask[2], col, first, count, buf);
        par_send_bytes(buf, count * tsz, 0, TAG_PART);
    }
    o->active = 0;
    d->c.out_seconds += omp_get_wtime() - t0;
    s->time.comm += par_counters().seconds - c0;
    return 0;
}

const sl_source *pcd_output_source(pcs_solver *s, int set, int ncomp, int c0, int c1, int c2)
{
    struct pcs_domain *d = s->split.dd;
    struct pcd_out *o = d->out;
    if (!o || !o->active || o->nst == OUT_MAX_STREAMS || ncomp < 1 || ncomp > 3)
        sl_fatal("pcs_domain: output source outside pcd_output_begin .. end (internal error)");
    pcd_stream *st = &o->st[o->nst++];
    *st = (pcd_stream){.s = s, .set = set, .ncomp = ncomp, .col = {c0, c1, c2}};
    for (int k = 0; k < ncomp; k++) st->tsz += col_size(st->col[k]);
    for (int j = 0; j + 1 < o->nst; j++)
        if (same_key(key_of(&o->st[j]), key_of(st))) st->dup++;
    st->src = (sl_source){out_read, st, o->compress_ranks ? out_zread : NULL};
    return &st->src;
}

size_t pcd_output_count(const pcs_solver *s, int set)
{
    const struct pcd_out *o = s->split.dd->out;
    return o && o->active ? o->total[set] : 0;
}

void pcd_output_end(pcs_solver *s)
{
    struct pcs_domain *d = s->split.dd;
    struct pcd_out *o = d->out;
    const double c0 = par_counters().seconds;
    const int64_t done[8] = {0};
    if (o->pending) { /* a window asked for and not read: its replies are due */
        par_irecv_wait();
        o->npost = o->pending = 0;
    }
    for (int r = 1; r < s->split.size; r++) par_send_bytes(done, sizeof done, r, TAG_ASK);
    o->active = 0;
    d->c.out_writes++;
    memcpy(o->order, o->seq, (size_t)o->nseq * sizeof *o->seq);
    o->norder = o->nseq;
    d->c.out_zblocks_ranks += o->zblocks_ranks;
    d->c.out_zblocks_root += o->zblocks_root;
    d->c.out_prefetched += o->prefetched;
    d->c.out_discarded += o->discarded;
    o->prefetched = 0;
    d->c.out_bytes += par_counters().bytes - o->bytes0;
    const double held = (double)(o->window * 3 * sizeof(double)) * (o->win2 ? 2.0 : 1.0) +
        (double)o->tail_cap * sizeof *o->tail + (double)o->tbuf_cap * sizeof *o->tbuf;
    if (held > d->c.out_held) d->c.out_held = held;
    d->c.out_seconds += omp_get_wtime() - o->t0;
    s->time.comm += par_counters().seconds - c0;
}
