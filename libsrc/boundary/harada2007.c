/* harada2007: wall weight [HKK07] (see harada2007.h). */
#include "boundary/harada2007.h"

#include <stdlib.h>

#include "core/sl_mem.h"

void bnd_wall_table_build(bnd_wall_table *t, const krn_kernel *k, double r0, double mass, size_t n)
{
    const int reach = (int)ceil(k->h / r0) + 1, noff = 4;
    t->n = n;
    t->dmax = k->h;
    t->inv_step = (double)(n - 1) / t->dmax;
    t->z = sl_malloc(n * sizeof *t->z, "wall weight table");
    t->dz = sl_malloc(n * sizeof *t->dz, "wall weight table");
    for (size_t q = 0; q < n; q++) {
        double d = (double)q / t->inv_step, s = 0.0;
        for (int a = 0; a < noff; a++) /* average over in-plane lattice offsets */
            for (int c = 0; c < noff; c++)
                for (int i = -reach; i <= reach; i++)
                    for (int j = -reach; j <= reach; j++)
                        for (int l = 0; l <= reach; l++) {
                            double x = (i + (double)a / noff) * r0, y = (j + (double)c / noff) * r0;
                            double zz = d + l * r0;
                            s += krn_w(k, sqrt(x * x + y * y + zz * zz));
                        }
        t->z[q] = mass * s / (noff * noff);
    }
    for (size_t q = 0; q < n; q++) { /* central differences, one-sided at the ends */
        size_t a = q ? q - 1 : q, c = q + 1 < n ? q + 1 : q;
        t->dz[q] = (t->z[c] - t->z[a]) * t->inv_step / (double)(c - a);
    }
}

void bnd_wall_table_free(bnd_wall_table *t)
{
    free(t->z);
    free(t->dz);
    t->z = t->dz = NULL;
}

size_t bnd_collide_harada(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          size_t n, double *x, double *y, double *z, double *vx, double *vy,
                          double *vz)
{
    size_t hits = 0;
#pragma omp parallel for schedule(static) reduction(+ : hits)
    for (size_t i = 0; i < n; i++) {
        double d;
        uint32_t j = bnd_nearest(fb->start, fb->idx, b, i, x[i], y[i], z[i], &d);
        if (j == UINT32_MAX || d >= r0) continue;
        double push = r0 - d;
        x[i] += push * b->nx[j];
        y[i] += push * b->ny[j];
        z[i] += push * b->nz[j];
        hits++;
        if (vx) { /* relative to the wall */
            double rx = vx[i] - b->vx[j], ry = vy[i] - b->vy[j], rz = vz[i] - b->vz[j];
            double vn = rx * b->nx[j] + ry * b->ny[j] + rz * b->nz[j];
            double keep = vn < 0.0 ? 0.0 : vn;
            double tx = rx - vn * b->nx[j], ty = ry - vn * b->ny[j], tz = rz - vn * b->nz[j];
            vx[i] = b->vx[j] + epsilon * tx + keep * b->nx[j];
            vy[i] = b->vy[j] + epsilon * ty + keep * b->ny[j];
            vz[i] = b->vz[j] + epsilon * tz + keep * b->nz[j];
        }
    }
    return hits;
}

static void *init(const bnd_setup *su)
{
    harada2007_state *st = sl_malloc(sizeof *st, "harada2007 state");
    st->wall_d = NULL;
    st->wall_b = NULL;
    st->cap = 0;
    bnd_wall_table_build(&st->wall, &su->k, su->r0, su->mass, 256);
    return st;
}

static void reserve(void *state, size_t cap)
{
    harada2007_state *st = state;
    if (st->cap >= cap) return;
    sl_free_aligned(st->wall_d);
    sl_free_aligned(st->wall_b);
    st->wall_d = sl_alloc_aligned(cap * sizeof *st->wall_d, "wall distances");
    st->wall_b = sl_alloc_aligned(cap * sizeof *st->wall_b, "wall neighbours");
    st->cap = cap;
}

static void release(void *state)
{
    harada2007_state *st = state;
    if (!st) return;
    bnd_wall_table_free(&st->wall);
    sl_free_aligned(st->wall_d);
    sl_free_aligned(st->wall_b);
    free(st);
}

static size_t collide(void *state, const bnd_setup *su, const nbr_list *fb, const sl_boundary *b,
                      size_t n, double *x, double *y, double *z, double *vx, double *vy, double *vz)
{
    (void)state;
    return bnd_collide_harada(fb, b, su->r0, su->epsilon, n, x, y, z, vx, vy, vz);
}

const bnd_method_type harada2007_method = {
    .name = "harada2007",
    .what =
        "wall weight from the wall distance, no wall particles in the solve (Harada et al. 2007)",
    .wall_density = harada2007_wall_density,
    .init = init,
    .reserve = reserve,
    .free = release,
    .collide = collide,
};
