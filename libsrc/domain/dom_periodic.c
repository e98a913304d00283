/* dom_periodic: periodic images as halo copies (see dom_periodic.h). */
#include "domain/dom_periodic.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_log.h"
#include "core/sl_mem.h"

void dom_periodic_axes_text(unsigned axes, char *buf, size_t len)
{
    size_t off = 0;
    if (len) buf[0] = '\0';
    for (int d = 0; d < 3; d++)
        if (axes & (1u << d) && off + 2 < len) {
            buf[off++] = "xyz"[d];
            buf[off] = '\0';
        }
}

void dom_periodic_wrap(const dom_periodic *p, size_t n, double *x, double *y, double *z)
{
    double *c[3] = {x, y, z};
    for (int d = 0; d < 3; d++) {
        if (!(p->axes & (1u << d))) continue;
        const double lo = p->lo[d], hi = p->hi[d], len = hi - lo;
        double *v = c[d];
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; i++) {
            if (v[i] < lo) v[i] += len * ceil((lo - v[i]) / len);
            if (v[i] >= hi) v[i] -= len * floor((v[i] - lo) / len);
            if (v[i] >= hi || v[i] < lo) v[i] = lo; /* rounding at the face */
        }
    }
}

void dom_halo_init(dom_halo *hl, const dom_periodic *p, double h)
{
    memset(hl, 0, sizeof *hl);
    hl->per = *p;
    hl->h = h;
    for (int code = 0; code < 27; code++) {
        const int k[3] = {code % 3 - 1, code / 3 % 3 - 1, code / 9 - 1};
        for (int d = 0; d < 3; d++) hl->shift[code][d] = -(double)k[d] * (p->hi[d] - p->lo[d]);
    }
}

void dom_halo_free(dom_halo *hl)
{
    sl_free_aligned(hl->src);
    sl_free_aligned(hl->code);
    sl_free_aligned(hl->cand_src);
    sl_free_aligned(hl->cand_cell);
    sl_free_aligned(hl->cand_code);
    sl_free_aligned(hl->count);
    sl_free_aligned(hl->hstart);
    free(hl->bsrc);
    free(hl->bcode);
    free(hl->bpos);
    sl_free_aligned(hl->bpair); /* pcs_domain.c grows it aligned */
    memset(hl, 0, sizeof *hl);
}

/* The side of the period a coordinate is within h of: +1 near hi (its
 * image is at v - L, code digit 2), -1 near lo (image at v + L, digit 0),
 * 0 otherwise. */
static int near_face(const dom_halo *hl, int d, double v)
{
    if (!(hl->per.axes & (1u << d))) return 0;
    if (v < hl->per.lo[d] + hl->h) return -1;
    if (v >= hl->per.hi[d] - hl->h) return 1;
    return 0;
}

/* The image codes of a point: every non-zero combination of its faces.
 * Returns how many (at most 7), in a fixed order. */
static int image_codes(const dom_halo *hl, double x, double y, double z, uint8_t out[7])
{
    const int s[3] = {near_face(hl, 0, x), near_face(hl, 1, y), near_face(hl, 2, z)};
    if (!s[0] && !s[1] && !s[2]) return 0;
    int m = 0;
    for (int mask = 1; mask < 8; mask++) {
        int code = 0, ok = 1;
        for (int d = 0; d < 3; d++) {
            const int k = mask & (1 << d) ? s[d] : 0; /* shift -k L */
            if (mask & (1 << d) && !s[d]) ok = 0;
            code += (k + 1) * (d == 0 ? 1 : d == 1 ? 3 : 9);
        }
        if (ok) out[m++] = (uint8_t)code;
    }
    return m;
}

/* ---- boundary images (set-up) ---- */

/* Inside [lo, hi) to rounding (a sample on the face hi is the image of
 * the one on lo). */
static int inside_period(const dom_periodic *p, double x, double y, double z)
{
    const double c[3] = {x, y, z};
    for (int d = 0; d < 3; d++) {
        const double eps = 1e-9 * (p->hi[d] - p->lo[d]);
        if (p->axes & (1u << d) && (c[d] < p->lo[d] - eps || c[d] >= p->hi[d] - eps)) return 0;
    }
    return 1;
}

/* Keep the boundary particles inside the period, in order, ids renumbered. */
static void drop_outside(const dom_periodic *p, sl_boundary *b)
{
    uint32_t *perm = sl_malloc((b->n + 1) * sizeof *perm, "boundary images");
    size_t keep = 0;
    for (size_t i = 0; i < b->n; i++)
        if (inside_period(p, b->x[i], b->y[i], b->z[i])) perm[keep++] = (uint32_t)i;
    b->n = keep;
    prt_boundary_permute(b, perm);
    for (size_t i = 0; i < keep; i++) b->id[i] = (uint32_t)i;
    free(perm);
}

void dom_boundary_images(dom_halo *hl, sl_boundary *b)
{
    if (!dom_halo_on(hl)) return;
    drop_outside(&hl->per, b);
    const size_t nreal = b->n;
    size_t cap = 0;
    for (size_t i = 0; i < nreal; i++) {
        uint8_t codes[7];
        const int m = image_codes(hl, b->x[i], b->y[i], b->z[i], codes);
        for (int q = 0; q < m; q++) {
            if (hl->nb_img == cap) {
                cap = cap ? 2 * cap : 1024;
                hl->bsrc = sl_realloc(hl->bsrc, cap * sizeof *hl->bsrc, "boundary images");
                hl->bcode = sl_realloc(hl->bcode, cap * sizeof *hl->bcode, "boundary images");
            }
            const double *s = hl->shift[codes[q]];
            prt_boundary_push(b, b->x[i] + s[0], b->y[i] + s[1], b->z[i] + s[2], b->nx[i], b->ny[i],
                              b->nz[i], b->body[i]);
            const size_t j = b->n - 1;
            b->x0[j] = b->x0[i] + s[0];
            b->y0[j] = b->y0[i] + s[1];
            b->z0[j] = b->z0[i] + s[2];
            hl->bsrc[hl->nb_img] = (uint32_t)i;
            hl->bcode[hl->nb_img] = codes[q];
            hl->nb_img++;
        }
    }
    hl->nb_real = nreal;
    b->nimages = hl->nb_img;
    hl->bpos = sl_malloc((b->n + 1) * sizeof *hl->bpos, "boundary images");
}

/* Where each boundary id sits now (the boundary is sorted by cell). */
static void boundary_positions(dom_halo *hl, const sl_boundary *b)
{
    for (size_t i = 0; i < b->n; i++) hl->bpos[b->id[i]] = (uint32_t)i;
}

void dom_boundary_images_mass(dom_halo *hl, const nbr_grid *g, const krn_kernel *k, double c_static,
                              sl_boundary *b)
{
    if (!hl->nb_img) return;
    boundary_positions(hl, b);
    for (size_t q = 0; q < hl->nb_img; q++)
        b->mass[hl->bpos[hl->nb_real + q]] = b->mass[hl->bpos[hl->bsrc[q]]];
    nbr_list bb;
    nbr_list_init(&bb);
    nbr_build_bb(g, b, &bb);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        double s = 0.0;
        for (uint32_t q = bb.start[i]; q < bb.start[i + 1]; q++) {
            const uint32_t j = bb.idx[q];
            const double dx = b->x[i] - b->x[j], dy = b->y[i] - b->y[j], dz = b->z[i] - b->z[j];
            s += b->mass[j] * krn_w(k, sqrt(dx * dx + dy * dy + dz * dz));
        }
        b->rho_static[i] = c_static * s;
    }
    nbr_list_free(&bb);
    for (size_t q = 0; q < hl->nb_img; q++)
        b->rho_static[hl->bpos[hl->nb_real + q]] = b->rho_static[hl->bpos[hl->bsrc[q]]];
}

/* ---- fluid images (every search) ---- */

static void grow_u32(uint32_t **p, size_t cap, const char *what)
{
    sl_free_aligned(*p);
    *p = sl_alloc_aligned(cap * sizeof **p, what);
}

static void grow_u8(uint8_t **p, size_t cap, const char *what)
{
    sl_free_aligned(*p);
    *p = sl_alloc_aligned(cap * sizeof **p, what);
}

/* Room for m images (scratch kept: no allocation once the count settles). */
static void reserve_images(dom_halo *hl, size_t m)
{
    if (m <= hl->cap) return;
    const size_t cap = m + m / 4 + 64;
    grow_u32(&hl->src, cap, "fluid images");
    grow_u32(&hl->cand_src, cap, "fluid images");
    grow_u32(&hl->cand_cell, cap, "fluid images");
    grow_u8(&hl->code, cap, "fluid images");
    grow_u8(&hl->cand_code, cap, "fluid images");
    hl->cap = cap;
}

/* The candidates (original, code) in owned order, with their cells. */
static size_t list_candidates(dom_halo *hl, const nbr_grid *g, const sl_fluid *f)
{
    size_t m = 0;
    uint8_t codes[7];
    for (size_t i = 0; i < f->n; i++)
        m += (size_t)image_codes(hl, f->x[i], f->y[i], f->z[i], codes);
    reserve_images(hl, m);
    m = 0;
    for (size_t i = 0; i < f->n; i++) {
        const int c = image_codes(hl, f->x[i], f->y[i], f->z[i], codes);
        for (int q = 0; q < c; q++) {
            const double *s = hl->shift[codes[q]];
            hl->cand_src[m] = (uint32_t)i;
            hl->cand_code[m] = codes[q];
            hl->cand_cell[m] = nbr_cell_rank(g, f->x[i] + s[0], f->y[i] + s[1], f->z[i] + s[2]);
            m++;
        }
    }
    return m;
}

/* Copy original src into slot j with shift s (every field). */
static void copy_image(sl_fluid *f, size_t j, size_t src, const double s[3])
{
    f->x[j] = f->x[src] + s[0];
    f->y[j] = f->y[src] + s[1];
    f->z[j] = f->z[src] + s[2];
    f->xs[j] = f->xs[src] + s[0];
    f->ys[j] = f->ys[src] + s[1];
    f->zs[j] = f->zs[src] + s[2];
    f->vx[j] = f->vx[src];
    f->vy[j] = f->vy[src];
    f->vz[j] = f->vz[src];
    f->ax[j] = f->ax[src];
    f->ay[j] = f->ay[src];
    f->az[j] = f->az[src];
    f->apx[j] = f->apx[src];
    f->apy[j] = f->apy[src];
    f->apz[j] = f->apz[src];
    f->rho[j] = f->rho[src];
    f->p[j] = f->p[src];
    f->pt[j] = f->pt[src];
    f->id[j] = f->id[src];
}

void dom_fluid_images(dom_halo *hl, nbr_grid *g, sl_fluid *f, const sl_boundary *b)
{
    f->nhalo = 0;
    if (!dom_halo_on(hl)) return;
    if (hl->ncells != g->ncells) {
        grow_u32(&hl->hstart, g->ncells + 1, "image cells");
        grow_u32(&hl->count, g->ncells + 1, "image cells");
        hl->ncells = g->ncells;
    }
    if (hl->nb_img) boundary_positions(hl, b); /* moving bodies re-sort the boundary */
    const size_t m = list_candidates(hl, g, f);
    if (f->n + m > f->cap) prt_fluid_reserve(f, f->n + m + (f->n + m) / 8);
    /* counting sort by cell, stable: within a cell in the originals' order */
    uint32_t *cnt = hl->count;
    memset(cnt, 0, (g->ncells + 1) * sizeof *cnt);
    for (size_t q = 0; q < m; q++) cnt[hl->cand_cell[q] + 1]++;
    hl->hstart[0] = (uint32_t)f->n;
    for (size_t c = 0; c < g->ncells; c++) hl->hstart[c + 1] = hl->hstart[c] + cnt[c + 1];
    for (size_t c = 0; c < g->ncells; c++) cnt[c] = hl->hstart[c] - (uint32_t)f->n;
    for (size_t q = 0; q < m; q++) {
        const uint32_t k = cnt[hl->cand_cell[q]]++;
        hl->src[k] = hl->cand_src[q];
        hl->code[k] = hl->cand_code[q];
    }
#pragma omp parallel for schedule(static)
    for (size_t k = 0; k < m; k++) {
        copy_image(f, f->n + k, hl->src[k], hl->shift[hl->code[k]]);
        f->cell[f->n + k] = 0;
    }
    hl->n = m;
    f->nhalo = m;
    g->hstart = hl->hstart;
    hl->steps++;
    hl->images_sum += (double)m;
}

void dom_refresh_predicted(const dom_halo *hl, sl_fluid *f)
{
    const size_t n = f->n;
#pragma omp parallel for schedule(static)
    for (size_t k = 0; k < hl->n; k++) {
        const uint32_t s = hl->src[k];
        const double *sh = hl->shift[hl->code[k]];
        f->xs[n + k] = f->xs[s] + sh[0];
        f->ys[n + k] = f->ys[s] + sh[1];
        f->zs[n + k] = f->zs[s] + sh[2];
    }
}

void dom_refresh_rows(const dom_halo *hl, size_t n, double *a, int width)
{
    const size_t w = (size_t)width;
#pragma omp parallel for schedule(static)
    for (size_t k = 0; k < hl->n; k++) memcpy(a + w * (n + k), a + w * hl->src[k], w * sizeof *a);
}

void dom_refresh_pressure(const dom_halo *hl, sl_fluid *f, sl_boundary *b)
{
    const size_t n = f->n;
#pragma omp parallel for schedule(static)
    for (size_t k = 0; k < hl->n; k++) {
        const uint32_t s = hl->src[k];
        f->rho[n + k] = f->rho[s];
        f->p[n + k] = f->p[s];
        f->pt[n + k] = f->pt[s];
    }
    if (hl->bpairs)
        for (size_t q = 0; q < hl->nbpair; q++) {
            const uint32_t j = hl->bpair[2 * q], s = hl->bpair[2 * q + 1];
            b->rho[j] = b->rho[s];
            b->p[j] = b->p[s];
            b->pt[j] = b->pt[s];
        }
    else
        for (size_t q = 0; q < hl->nb_img; q++) {
            const uint32_t j = hl->bpos[hl->nb_real + q], s = hl->bpos[hl->bsrc[q]];
            b->rho[j] = b->rho[s];
            b->p[j] = b->p[s];
            b->pt[j] = b->pt[s];
        }
}

void dom_after_integrate(const dom_halo *hl, sl_fluid *f)
{
    if (!dom_halo_on(hl)) return;
    dom_periodic_wrap(&hl->per, f->n, f->x, f->y, f->z);
    f->nhalo = 0;
}
