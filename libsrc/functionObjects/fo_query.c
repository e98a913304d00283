/* fo_query: SPH interpolation and colour at points (see fo_query.h). */
#include "functionObjects/fo_query.h"

#include "core/sl_mem.h"

#include <math.h>
#include <stdlib.h>

/* Running sums of V_j W and V_j A_j W. */
typedef struct acc {
    int n;
    double vw, p, rho, vx, vy, vz;
} acc;

static inline void add_fluid(acc *a, const pcs_view *s, size_t j, double x, double y, double z)
{
    const sl_fluid *f = s->f;
    double dx = x - f->x[j], dy = y - f->y[j], dz = z - f->z[j];
    double r2 = dx * dx + dy * dy + dz * dz;
    if (!(r2 < s->h * s->h)) return;
    double rho = f->rho[j] > 0.0 ? f->rho[j] : s->rho0;
    double vw = s->mass / rho * krn_w(&s->k, sqrt(r2));
    a->n++;
    a->vw += vw;
    a->p += vw * f->p[j];
    a->rho += vw * rho;
    a->vx += vw * f->vx[j];
    a->vy += vw * f->vy[j];
    a->vz += vw * f->vz[j];
}

/* Boundary particles without a fluid neighbour at the last search keep
 * stale pressures; they are left out. */
static inline int boundary_active(const pcs_view *s, size_t j)
{
    const nbr_list *l = s->bf;
    return l->n != s->b->n || l->start[j + 1] > l->start[j];
}

static inline void add_boundary(acc *a, const pcs_view *s, size_t j, double x, double y, double z)
{
    const sl_boundary *b = s->b;
    double dx = x - b->x[j], dy = y - b->y[j], dz = z - b->z[j];
    double r2 = dx * dx + dy * dy + dz * dz;
    if (!(r2 < s->h * s->h) || !boundary_active(s, j)) return;
    double rho = b->rho[j] > 0.0 ? b->rho[j] : s->rho0;
    double vw = b->mass[j] / rho * krn_w(&s->k, sqrt(r2));
    a->n++;
    a->vw += vw;
    a->p += vw * b->p[j];
    a->rho += vw * rho;
    a->vx += vw * b->vx[j]; /* the wall's own velocity (zero unless it moves) */
    a->vy += vw * b->vy[j];
    a->vz += vw * b->vz[j];
}

/* The cell of a point, clamped into the grid as the neighbour search does. */
static inline int clamp_cell(double v, double lo, double inv, int n)
{
    double c = floor((v - lo) * inv);
    if (!(c >= 0.0)) c = 0.0; /* also NaN */
    if (c > (double)(n - 1)) c = (double)(n - 1);
    return (int)c;
}

/* Are the n particles of start[] (by rank) each within one cell of the
 * cell they are sorted in? */
static int sorted_ok(const nbr_grid *g, const uint32_t *inv, const uint32_t *start, size_t n,
                     const double *x, const double *y, const double *z)
{
    const size_t nx = (size_t)g->nc[0], nxy = nx * (size_t)g->nc[1];
    size_t i = 0;
    if (start[0] != 0) return 0;
    for (size_t r = 0; r < g->ncells; r++) {
        if (start[r + 1] < start[r] || start[r + 1] > n) return 0;
        const size_t lin = inv[r];
        const int cx = (int)(lin % nx), cy = (int)(lin % nxy / nx), cz = (int)(lin / nxy);
        for (; i < start[r + 1]; i++) {
            int dx = clamp_cell(x[i], g->lo[0], g->inv_cell, g->nc[0]) - cx;
            int dy = clamp_cell(y[i], g->lo[1], g->inv_cell, g->nc[1]) - cy;
            int dz = clamp_cell(z[i], g->lo[2], g->inv_cell, g->nc[2]) - cz;
            if (dx < -1 || dx > 1 || dy < -1 || dy > 1 || dz < -1 || dz > 1) return 0;
        }
    }
    return i == n;
}

void fo_index_update(fo_index *ix, const pcs_view *s)
{
    const nbr_grid *g = s->grid;
    ix->s = s;
    ix->use_grid = 0;
    if (g->ncells == 0 || !g->rank || !g->fstart || !g->bstart || !s->b) return;
    if (ix->ncells < g->ncells) {
        free(ix->cell_of_rank);
        ix->cell_of_rank = sl_malloc(g->ncells * sizeof *ix->cell_of_rank, "grid cell index");
        ix->ncells = g->ncells;
    }
    for (size_t r = 0; r < g->ncells; r++) ix->cell_of_rank[r] = UINT32_MAX;
    for (size_t lin = 0; lin < g->ncells; lin++) {
        uint32_t r = g->rank[lin];
        if (r >= g->ncells || ix->cell_of_rank[r] != UINT32_MAX) return; /* not a permutation */
        ix->cell_of_rank[r] = (uint32_t)lin;
    }
    const sl_fluid *f = s->f;
    const sl_boundary *b = s->b;
    ix->use_grid = sorted_ok(g, ix->cell_of_rank, g->fstart, f->n, f->x, f->y, f->z) &&
        sorted_ok(g, ix->cell_of_rank, g->bstart, b->n, b->x, b->y, b->z);
}

void fo_index_free(fo_index *ix)
{
    free(ix->cell_of_rank);
    ix->cell_of_rank = NULL;
    ix->ncells = 0;
}

static void cell_range(const nbr_grid *g, double v, int d, int reach, int *c0, int *c1)
{
    double c = floor((v - g->lo[d]) * g->inv_cell), top = (double)(g->nc[d] - 1);
    double a = c - reach, b = c + reach;
    if (!(a >= 0.0)) a = 0.0; /* also NaN */
    if (!(b >= 0.0)) b = 0.0;
    if (a > top) a = top;
    if (b > top) b = top;
    *c0 = (int)a;
    *c1 = (int)b;
}

/* The one particle loop: fluid (and boundary) particles within h of x,
 * added to a. */
static void gather_at(const fo_index *ix, double x, double y, double z, int boundary, acc *a)
{
    const pcs_view *s = ix->s;
    const nbr_grid *g = s->grid;
    const size_t nb = boundary && s->b ? s->b->n : 0;
    if (!ix->use_grid) {
        for (size_t j = 0; j < s->f->n; j++) add_fluid(a, s, j, x, y, z);
        for (size_t j = 0; j < nb; j++) add_boundary(a, s, j, x, y, z);
        return;
    }
    const int reach = (int)ceil(s->h * g->inv_cell - 1e-9) + 1;
    int lo[3], hi[3];
    cell_range(g, x, 0, reach, &lo[0], &hi[0]);
    cell_range(g, y, 1, reach, &lo[1], &hi[1]);
    cell_range(g, z, 2, reach, &lo[2], &hi[2]);
    for (int cz = lo[2]; cz <= hi[2]; cz++)
        for (int cy = lo[1]; cy <= hi[1]; cy++)
            for (int cx = lo[0]; cx <= hi[0]; cx++) {
                size_t lin =
                    (size_t)cx + (size_t)g->nc[0] * ((size_t)cy + (size_t)g->nc[1] * (size_t)cz);
                uint32_t r = g->rank[lin];
                for (uint32_t j = g->fstart[r]; j < g->fstart[r + 1]; j++)
                    add_fluid(a, s, j, x, y, z);
                for (uint32_t j = nb ? g->bstart[r] : 0; j < (nb ? g->bstart[r + 1] : 0); j++)
                    add_boundary(a, s, j, x, y, z);
            }
}

/* Periodic axes: the particles within h of x across a periodic face are
 * those within h of x shifted by the period, so the point is queried
 * again at each shift that brings it within h of the period's other side
 * (for two or three axes, each combination).  A running solver's boundary
 * already holds the boundary images: the shifted queries then add fluid
 * only; a snapshot's boundary is the real particles, shifted alike. */
static void gather(const fo_index *ix, double x, double y, double z, int boundary, acc *a)
{
    const pcs_view *s = ix->s;
    const dom_periodic *per = s->periodic;
    *a = (acc){0};
    gather_at(ix, x, y, z, boundary, a);
    if (!per || !per->axes) return;
    const double p[3] = {x, y, z};
    double shift[3][2];
    int ns[3];
    for (int d = 0; d < 3; d++) {
        ns[d] = 1;
        shift[d][0] = 0.0;
        if (!(per->axes & (1u << d))) continue;
        const double len = per->hi[d] - per->lo[d];
        if (p[d] - per->lo[d] < s->h) shift[d][ns[d]++] = len;
        else if (per->hi[d] - p[d] < s->h) shift[d][ns[d]++] = -len;
    }
    const int shifted_boundary = boundary && !s->boundary_images;
    for (int i = 0; i < ns[0]; i++)
        for (int j = 0; j < ns[1]; j++)
            for (int k = 0; k < ns[2]; k++)
                if (i || j || k)
                    gather_at(ix, x + shift[0][i], y + shift[1][j], z + shift[2][k],
                              shifted_boundary, a);
}

void fo_query_sample(const fo_index *ix, double x, double y, double z, fo_sample *out)
{
    acc a;
    gather(ix, x, y, z, 1, &a);
    out->n = a.n;
    if (a.n == 0 || !(a.vw > 0.0)) {
        out->pressure = out->density = NAN;
        out->velocity[0] = out->velocity[1] = out->velocity[2] = NAN;
        return;
    }
    double inv = 1.0 / a.vw;
    out->pressure = a.p * inv;
    out->density = a.rho * inv;
    out->velocity[0] = a.vx * inv;
    out->velocity[1] = a.vy * inv;
    out->velocity[2] = a.vz * inv;
}

double fo_query_colour(const fo_index *ix, double x, double y, double z)
{
    acc a;
    gather(ix, x, y, z, 0, &a);
    return a.vw;
}
