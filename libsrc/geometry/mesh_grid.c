/* mesh_grid: hashed uniform grid of points (see mesh_grid.h). */
#include "geometry/mesh_grid.h"

#include "core/sl_mem.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* Cell coordinate, clamped so that the conversion is always defined. */
static int64_t cell_of(double x, double inv_h)
{
    double c = floor(x * inv_h);
    const double lim = 4.0e18;
    if (!(c > -lim)) c = -lim;
    if (c > lim) c = lim;
    return (int64_t)c;
}

static size_t bucket_of(const mgrid *g, int64_t i, int64_t j, int64_t k)
{
    /* combine, then the murmur3 finaliser: every input bit reaches the
     * low bits that pick the bucket */
    uint64_t h = (uint64_t)i * 0x9E3779B97F4A7C15ull + (uint64_t)j * 0xC2B2AE3D27D4EB4Full +
        (uint64_t)k * 0x165667B19E3779F9ull;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return (size_t)h & (g->nb - 1);
}

static size_t bucket_of_point(const mgrid *g, const double x[3])
{
    return bucket_of(g, cell_of(x[0], g->inv_h), cell_of(x[1], g->inv_h), cell_of(x[2], g->inv_h));
}

static void rehash(mgrid *g, size_t nb)
{
    free(g->head);
    g->nb = nb;
    g->head = sl_malloc(nb * sizeof *g->head, "a point grid");
    for (size_t b = 0; b < nb; b++) g->head[b] = MGRID_NONE;
    for (size_t p = 0; p < g->n; p++) {
        size_t b = bucket_of_point(g, g->x + 3 * p);
        g->next[p] = g->head[b];
        g->head[b] = p;
    }
}

void mgrid_init(mgrid *g, double h, size_t expected)
{
    size_t nb = 64;
    while (nb < expected && nb < ((size_t)1 << 40)) nb *= 2;
    g->h = h;
    g->inv_h = 1.0 / h;
    g->n = 0;
    g->cap = expected > 16 ? expected : 16;
    g->x = sl_malloc(3 * g->cap * sizeof *g->x, "a point grid");
    g->next = sl_malloc(g->cap * sizeof *g->next, "a point grid");
    g->head = NULL;
    rehash(g, nb);
}

void mgrid_free(mgrid *g)
{
    free(g->x);
    free(g->next);
    free(g->head);
    g->x = NULL;
    g->next = g->head = NULL;
    g->n = g->cap = g->nb = 0;
}

size_t mgrid_insert(mgrid *g, const double x[3])
{
    size_t p = g->n, b;
    if (p == g->cap) {
        g->cap *= 2;
        g->x = sl_realloc(g->x, 3 * g->cap * sizeof *g->x, "a point grid");
        g->next = sl_realloc(g->next, g->cap * sizeof *g->next, "a point grid");
    }
    g->x[3 * p] = x[0];
    g->x[3 * p + 1] = x[1];
    g->x[3 * p + 2] = x[2];
    g->n++;
    if (g->n > g->nb) {
        rehash(g, 2 * g->nb);
        return p;
    }
    b = bucket_of_point(g, x);
    g->next[p] = g->head[b];
    g->head[b] = p;
    return p;
}

static double dist2(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* Nearest over every point: used when the cell range would cost more. */
static size_t brute_nearest(const mgrid *g, const double x[3], double r2, size_t skip,
                            double *best2)
{
    size_t best = MGRID_NONE;
    *best2 = r2;
    for (size_t p = 0; p < g->n; p++) {
        double d2 = dist2(g->x + 3 * p, x);
        if (p != skip && d2 <= *best2) {
            if (best == MGRID_NONE || d2 < *best2 || p < best) best = p;
            *best2 = d2;
        }
    }
    return best;
}

size_t mgrid_nearest_within(const mgrid *g, const double x[3], double r, size_t skip, double *dist)
{
    size_t best = MGRID_NONE;
    double best2 = r * r;
    double span = ceil(r * g->inv_h);
    if (g->n == 0 || !(r >= 0.0)) return MGRID_NONE;
    if (span > 1000.0 || (2 * span + 1) * (2 * span + 1) * (2 * span + 1) > (double)g->n) {
        best = brute_nearest(g, x, best2, skip, &best2);
    } else {
        int64_t k = (int64_t)span;
        int64_t c[3] = {cell_of(x[0], g->inv_h), cell_of(x[1], g->inv_h), cell_of(x[2], g->inv_h)};
        for (int64_t i = c[0] - k; i <= c[0] + k; i++)
            for (int64_t j = c[1] - k; j <= c[1] + k; j++)
                for (int64_t l = c[2] - k; l <= c[2] + k; l++)
                    for (size_t p = g->head[bucket_of(g, i, j, l)]; p != MGRID_NONE;
                         p = g->next[p]) {
                        double d2 = dist2(g->x + 3 * p, x);
                        if (p == skip || d2 > best2) continue;
                        /* ties go to the lowest number: results do not
                         * depend on the bucket layout */
                        if (best == MGRID_NONE || d2 < best2 || p < best) best = p;
                        best2 = d2;
                    }
    }
    if (dist && best != MGRID_NONE) *dist = sqrt(best2);
    return best;
}

void mgrid_visit(const mgrid *g, const double x[3], double r,
                 void (*visit)(void *ctx, size_t id, double dist), void *ctx)
{
    double span = ceil(r * g->inv_h), r2 = r * r;
    if (g->n == 0 || !(r >= 0.0)) return;
    if (span > 1.0 || 27.0 > (double)g->n) {
        /* rare (radius above the cell size, or tiny grids): every point */
        for (size_t p = 0; p < g->n; p++) {
            double d2 = dist2(g->x + 3 * p, x);
            if (d2 <= r2) visit(ctx, p, sqrt(d2));
        }
        return;
    }
    /* the 27 cells' buckets, each walked once (two cells may share one) */
    size_t seen[27];
    int ns = 0;
    int64_t c[3] = {cell_of(x[0], g->inv_h), cell_of(x[1], g->inv_h), cell_of(x[2], g->inv_h)};
    for (int64_t i = c[0] - 1; i <= c[0] + 1; i++)
        for (int64_t j = c[1] - 1; j <= c[1] + 1; j++)
            for (int64_t l = c[2] - 1; l <= c[2] + 1; l++) {
                size_t b = bucket_of(g, i, j, l);
                int dup = 0;
                for (int q = 0; q < ns && !dup; q++) dup = seen[q] == b;
                if (dup) continue;
                seen[ns++] = b;
                for (size_t p = g->head[b]; p != MGRID_NONE; p = g->next[p]) {
                    double d2 = dist2(g->x + 3 * p, x);
                    if (d2 <= r2) visit(ctx, p, sqrt(d2));
                }
            }
}

size_t mgrid_nearest(const mgrid *g, const double x[3], size_t skip, double *dist)
{
    double r = g->h;
    if (g->n == 0 || (g->n == 1 && skip == 0)) return MGRID_NONE;
    for (;;) {
        size_t p = mgrid_nearest_within(g, x, r, skip, dist);
        if (p != MGRID_NONE) return p;
        if (r > 1e300) return MGRID_NONE;
        r *= 2.0;
    }
}
