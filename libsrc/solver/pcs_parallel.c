/* pcs_parallel: -parallel's halo mode (see pcs_parallel.h). */
#include "solver/pcs_parallel.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"
#include "core/sl_reduce.h"
#include "parallel/par.h"
#include "solver/pcs_domain.h"

/* The halo lists of one search and the buffers of the exchanges. */
struct pcs_halo_x {
    uint32_t stamp;
    uint32_t *fmark, *bmark; /* stamp: row / boundary particle is in this search's sets */
    size_t fmark_cap, bmark_cap;
    uint32_t *recv_idx, *send_idx; /* halo rows received (by owner), own rows sent (by rank) */
    size_t nrecv, nsend, recv_cap, send_cap;
    int *rcnt, *rdis, *scnt, *sdis;                                     /* per rank: rows */
    int *rcnt2, *rdis2, *scnt2, *sdis2, *rcnt3, *rdis3, *scnt3, *sdis3; /* 2 and 3 per row */
    double *sbuf, *rbuf;
    size_t sbuf_cap, rbuf_cap;
    double *pbuf, *pall; /* block sums: this rank's pieces, everyone's */
    size_t pbuf_cap, pall_cap;
    int *pcnt, *pdis;
};

int pcx_usable(const pcs_solver *s)
{
    const char *e = getenv("SLUICE_PARALLEL_EXCHANGE");
    if (e && !strcmp(e, "gather")) return 0;
    return s->split.size > 1;
}

static void *grow(void *p, size_t *cap, size_t need, size_t elem, const char *what)
{
    if (need <= *cap && p) return p;
    size_t c = *cap ? *cap : 1024;
    while (c < need) c *= 2;
    sl_free_aligned(p);
    *cap = c;
    return sl_alloc_aligned(c * elem, what);
}

static int *ints(int n) { return sl_malloc((size_t)n * sizeof(int), "rank counts"); }

static struct pcs_halo_x *state(pcs_solver *s)
{
    if (!s->split.hx) {
        const int p = s->split.size;
        struct pcs_halo_x *h = sl_malloc(sizeof *h, "halo lists");
        memset(h, 0, sizeof *h);
        h->rcnt = ints(p), h->rdis = ints(p), h->scnt = ints(p), h->sdis = ints(p);
        h->rcnt2 = ints(p), h->rdis2 = ints(p), h->scnt2 = ints(p), h->sdis2 = ints(p);
        h->rcnt3 = ints(p), h->rdis3 = ints(p), h->scnt3 = ints(p), h->sdis3 = ints(p);
        h->pcnt = ints(p), h->pdis = ints(p);
        s->split.hx = h;
    }
    return s->split.hx;
}

static void mark_grow(uint32_t **m, size_t *cap, size_t need, uint32_t *stamp)
{
    if (need <= *cap && *m) return;
    size_t c = *cap ? *cap : 1024;
    while (c < need) c *= 2;
    sl_free_aligned(*m);
    *m = sl_alloc_aligned(c * sizeof **m, "halo marks");
    memset(*m, 0, c * sizeof **m);
    *cap = c;
    (void)stamp;
}

static int as_int(size_t v)
{
    if (v > 2147483647u) sl_fatal("-parallel: %zu values exceed MPI's int counts", v);
    return (int)v;
}

/* Boundary particle j into this rank's set; a periodic image brings its
 * original (the image's values are refreshed from it, dom_periodic.h). */
static void add_boundary(pcs_solver *s, struct pcs_halo_x *h, uint32_t st, uint32_t j, size_t *nbs)
{
    const dom_halo *hl = &s->halo;
    for (int k = 0; k < 2; k++) {
        if (h->bmark[j] == st) return;
        h->bmark[j] = st;
        s->split.bset[(*nbs)++] = j;
        const uint32_t id = s->b->id[j];
        if (!hl->nb_img || id < hl->nb_real) return;
        j = hl->bpos[hl->bsrc[id - hl->nb_real]];
    }
}

void pcx_build(pcs_solver *s)
{
    pcs_split *sp = &s->split;
    struct pcs_halo_x *h = state(s);
    const int p = sp->size, me = sp->rank;
    const size_t n = s->f->n, nb = s->b->n;
    const size_t lo = sp->row[me], hi = sp->row[me + 1];
    mark_grow(&h->fmark, &h->fmark_cap, n + 1, &h->stamp);
    mark_grow(&h->bmark, &h->bmark_cap, nb + 1, &h->stamp);
    if (++h->stamp == 0) { /* wrapped: clear the marks */
        memset(h->fmark, 0, h->fmark_cap * sizeof *h->fmark);
        memset(h->bmark, 0, h->bmark_cap * sizeof *h->bmark);
        h->stamp = 1;
    }
    const uint32_t st = h->stamp;
    /* the boundary particles this rank computes: those its rows see, and
     * its share of the active ones (gathered at the end of the step) */
    sp->bset = grow(sp->bset, &sp->bset_cap, nb + 1, sizeof *sp->bset, "boundary set");
    size_t nbs = 0;
    const uint32_t *fbs = s->fb.start, *fbi = s->fb.idx;
    for (size_t i = lo; i < hi; i++)
        for (uint32_t q = fbs[i]; q < fbs[i + 1]; q++) add_boundary(s, h, st, fbi[q], &nbs);
    for (size_t q = sp->act[me]; q < sp->act[me + 1]; q++)
        add_boundary(s, h, st, s->active[q], &nbs);
    sp->nbset = nbs;
    /* the fluid rows of other ranks read: by the own rows, and by those
     * boundary particles */
    const uint32_t *ffs = s->ff.start, *ffi = s->ff.idx, *bfs = s->bf.start, *bfi = s->bf.idx;
    const uint32_t *src = s->halo.src; /* periodic: the original of fluid image j - n */
    for (size_t i = lo; i < hi; i++)
        for (uint32_t q = ffs[i]; q < ffs[i + 1]; q++) {
            const uint32_t j = ffi[q];
            h->fmark[j < n ? j : src[j - n]] = st;
        }
    for (size_t k = 0; k < nbs; k++) {
        const uint32_t j = sp->bset[k];
        for (uint32_t q = bfs[j]; q < bfs[j + 1]; q++) {
            const uint32_t i = bfi[q];
            h->fmark[i < n ? i : src[i - n]] = st;
        }
    }
    h->recv_idx = grow(h->recv_idx, &h->recv_cap, n + 1, sizeof *h->recv_idx, "halo rows");
    size_t nr = 0;
    for (int r = 0; r < p; r++) {
        h->rdis[r] = as_int(nr);
        if (r != me)
            for (size_t j = sp->row[r]; j < sp->row[r + 1]; j++)
                if (h->fmark[j] == st) h->recv_idx[nr++] = (uint32_t)j;
        h->rcnt[r] = as_int(nr) - h->rdis[r];
    }
    h->nrecv = nr;
    par_alltoall_int(h->rcnt, h->scnt);
    size_t ns = 0;
    for (int r = 0; r < p; r++) {
        h->sdis[r] = as_int(ns);
        ns += (size_t)h->scnt[r];
    }
    h->nsend = ns;
    h->send_idx = grow(h->send_idx, &h->send_cap, ns + 1, sizeof *h->send_idx, "halo rows");
    par_alltoallv_u32(h->recv_idx, h->rcnt, h->rdis, h->send_idx, h->scnt, h->sdis);
    for (int r = 0; r < p; r++) {
        h->rcnt2[r] = 2 * h->rcnt[r], h->rdis2[r] = 2 * h->rdis[r];
        h->scnt2[r] = 2 * h->scnt[r], h->sdis2[r] = 2 * h->sdis[r];
        h->rcnt3[r] = 3 * h->rcnt[r], h->rdis3[r] = 3 * h->rdis[r];
        h->scnt3[r] = 3 * h->scnt[r], h->sdis3[r] = 3 * h->sdis[r];
    }
    h->sbuf = grow(h->sbuf, &h->sbuf_cap, 3 * ns + 1, sizeof *h->sbuf, "halo buffer");
    h->rbuf = grow(h->rbuf, &h->rbuf_cap, 3 * nr + 1, sizeof *h->rbuf, "halo buffer");
    sp->halo_rows = nr;
    sp->halo_sum += (double)nr;
    sp->halo_max = nr > sp->halo_max ? nr : sp->halo_max;
}

void pcx_exchange_predicted(pcs_solver *s)
{
    if (s->split.domain) {
        pcd_exchange_predicted(s);
        return;
    }
    struct pcs_halo_x *h = s->split.hx;
    const double t0 = omp_get_wtime();
    sl_fluid *f = s->f;
    for (size_t k = 0; k < h->nsend; k++) {
        const uint32_t j = h->send_idx[k];
        h->sbuf[3 * k] = f->xs[j];
        h->sbuf[3 * k + 1] = f->ys[j];
        h->sbuf[3 * k + 2] = f->zs[j];
    }
    par_alltoallv_double(h->sbuf, h->scnt3, h->sdis3, h->rbuf, h->rcnt3, h->rdis3);
    for (size_t k = 0; k < h->nrecv; k++) {
        const uint32_t j = h->recv_idx[k];
        f->xs[j] = h->rbuf[3 * k];
        f->ys[j] = h->rbuf[3 * k + 1];
        f->zs[j] = h->rbuf[3 * k + 2];
    }
    s->time.comm += omp_get_wtime() - t0;
}

/* What rank r contributes to the block sums: the sum of each block it
 * holds whole, the rows of each block it shares (in row order). */
static size_t pieces(size_t lo, size_t hi, size_t n, double *out, const double *err,
                     const double *part)
{
    const size_t B = SL_REDUCE_BLOCK;
    size_t k = 0;
    if (lo >= hi) return 0;
    for (size_t blk = lo / B; blk <= (hi - 1) / B; blk++) {
        const size_t bl = blk * B, be = bl + B < n ? bl + B : n;
        if (lo <= bl && hi >= be) {
            if (out) out[k] = part[blk];
            k++;
        } else {
            const size_t a = lo > bl ? lo : bl, e = hi < be ? hi : be;
            if (out) memcpy(out + k, err + a, (e - a) * sizeof *out);
            k += e - a;
        }
    }
    return k;
}

void pcx_block_sums(pcs_solver *s, const double *rows, double *part)
{
    if (s->split.domain) {
        pcd_block_sums(s, rows, part);
        return;
    }
    pcs_split *sp = &s->split;
    struct pcs_halo_x *h = sp->hx;
    const int p = sp->size, me = sp->rank;
    const size_t n = s->f->n, B = SL_REDUCE_BLOCK;
    size_t total = 0;
    for (int r = 0; r < p; r++) {
        h->pdis[r] = as_int(total);
        h->pcnt[r] = as_int(pieces(sp->row[r], sp->row[r + 1], n, NULL, NULL, NULL));
        total += (size_t)h->pcnt[r];
    }
    h->pbuf = grow(h->pbuf, &h->pbuf_cap, (size_t)h->pcnt[me] + 1, sizeof *h->pbuf, "block sums");
    h->pall = grow(h->pall, &h->pall_cap, total + 1, sizeof *h->pall, "block sums");
    pieces(sp->row[me], sp->row[me + 1], n, h->pbuf, rows, part);
    par_allgatherv(h->pbuf, h->pcnt[me], h->pall, h->pcnt, h->pdis);
    /* every block's sum: whole ones as sent, shared ones summed from 0 in
     * row order across the ranks that share them (the serial order) */
    size_t k = 0, run_blk = (size_t)-1;
    double run = 0.0;
    for (int r = 0; r < p; r++) {
        const size_t lo = sp->row[r], hi = sp->row[r + 1];
        if (lo >= hi) continue;
        for (size_t blk = lo / B; blk <= (hi - 1) / B; blk++) {
            const size_t bl = blk * B, be = bl + B < n ? bl + B : n;
            if (lo <= bl && hi >= be) {
                part[blk] = h->pall[k++];
                continue;
            }
            const size_t a = lo > bl ? lo : bl, e = hi < be ? hi : be;
            if (run_blk != blk) {
                run_blk = blk;
                run = 0.0;
            }
            for (size_t i = a; i < e; i++) {
                run += h->pall[k++];
                __asm__("" : "+m"(run)); /* one at a time, as the pass sums */
            }
            part[blk] = run;
        }
    }
}

double pcx_after_density(pcs_solver *s, double emax)
{
    if (s->split.domain) return pcd_after_density(s, emax);
    pcs_split *sp = &s->split;
    struct pcs_halo_x *h = sp->hx;
    const double t0 = omp_get_wtime();
    pcx_block_sums(s, s->err, s->err_block);
    /* the halo's p/rho^2, which the pressure force reads, and its density,
     * which the next density pass's EFF_DENSITY effects read */
    sl_fluid *f = s->f;
    for (size_t q = 0; q < h->nsend; q++) {
        h->sbuf[2 * q] = f->pt[h->send_idx[q]];
        h->sbuf[2 * q + 1] = f->rho[h->send_idx[q]];
    }
    par_alltoallv_double(h->sbuf, h->scnt2, h->sdis2, h->rbuf, h->rcnt2, h->rdis2);
    for (size_t q = 0; q < h->nrecv; q++) {
        f->pt[h->recv_idx[q]] = h->rbuf[2 * q];
        f->rho[h->recv_idx[q]] = h->rbuf[2 * q + 1];
    }
    /* the methods without wall density measure the compression with the
     * wall's share over every row (sl_sum's blocks): their rows, whole */
    if (!s->prm.method->wall_density) par_gather_rows(s->err_vol, sp->row);
    emax = par_max_double(emax);
    s->time.comm += omp_get_wtime() - t0;
    return emax;
}

void pcx_after_integrate(pcs_solver *s)
{
    if (s->split.domain) { /* nothing gathered: the own rows kept */
        pcd_keep_own(s);
        return;
    }
    pcs_split *sp = &s->split;
    const double t0 = omp_get_wtime();
    sl_fluid *f = s->f;
    sl_boundary *b = s->b;
    double *a[8] = {f->x, f->y, f->z, f->vx, f->vy, f->vz, f->p, f->rho};
    for (int k = 0; k < 8; k++) par_gather_rows(a[k], sp->row);
    if (s->nactive) {
        const uint32_t *act = s->active;
        double *buf = sp->bbuf;
        const size_t q0 = sp->act[sp->rank], q1 = sp->act[sp->rank + 1];
        for (size_t q = q0; q < q1; q++) {
            buf[3 * q] = b->rho[act[q]];
            buf[3 * q + 1] = b->p[act[q]];
            buf[3 * q + 2] = b->pt[act[q]];
        }
        size_t off[sp->size + 1];
        for (int r = 0; r <= sp->size; r++) off[r] = 3 * sp->act[r];
        par_gather_rows(buf, off);
        for (size_t q = 0; q < s->nactive; q++) {
            b->rho[act[q]] = buf[3 * q];
            b->p[act[q]] = buf[3 * q + 1];
            b->pt[act[q]] = buf[3 * q + 2];
        }
    }
    s->time.comm += omp_get_wtime() - t0;
}

void pcx_free(pcs_solver *s)
{
    struct pcs_halo_x *h = s->split.hx;
    sl_free_aligned(s->split.bset);
    if (!h) return;
    sl_free_aligned(h->fmark);
    sl_free_aligned(h->bmark);
    sl_free_aligned(h->recv_idx);
    sl_free_aligned(h->send_idx);
    sl_free_aligned(h->sbuf);
    sl_free_aligned(h->rbuf);
    sl_free_aligned(h->pbuf);
    sl_free_aligned(h->pall);
    free(h->rcnt), free(h->rdis), free(h->scnt), free(h->sdis);
    free(h->rcnt2), free(h->rdis2), free(h->scnt2), free(h->sdis2);
    free(h->rcnt3), free(h->rdis3), free(h->scnt3), free(h->sdis3);
    free(h->pcnt), free(h->pdis);
    free(h);
}
