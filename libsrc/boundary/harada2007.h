/*
 * harada2007: the wall weight of Harada, Koshizuka & Kawaguchi 2007
 * [HKK07]: a wall adds the density Z(d) of a solid half-space lattice at
 * the distance d of the fluid particle from the plane of its nearest
 * boundary particle (a table on [0, h]); its wall particles carry the
 * fluid particle's own pressure, so the pressure force of the wall is
 * -2 p_i / rho_i^2 dZ/dd n.  The collision is a distance constraint: a
 * particle closer than r0 to that plane is put back to r0 along the normal;
 * with velocities, the approaching normal component is removed and epsilon
 * times the tangential kept.
 *
 * State: the table and, per fluid particle, the nearest boundary particle
 * and dZ/dd found by the density pass and read by the pressure pass.
 */
#ifndef SL_HARADA2007_H
#define SL_HARADA2007_H

#include <math.h>

#include "boundary/bnd_method.h"

extern const bnd_method_type harada2007_method;
enum { harada2007_wall_density = 0 };

/* Wall-weight table: Z(d) and dZ/dd on [0, h]. */
typedef struct bnd_wall_table {
    size_t n;
    double dmax, inv_step;
    double *z, *dz;
} bnd_wall_table;

typedef struct harada2007_state {
    bnd_wall_table wall;
    double *wall_d;   /* per fluid particle: dZ/dd at its wall distance */
    uint32_t *wall_b; /* per fluid particle: nearest boundary particle (UINT32_MAX: none) */
    size_t cap;
} harada2007_state;

/* Z(d) = m sum over a solid half-space lattice (spacing r0, layers at plane
 * distance 0, -r0, -2 r0, ...; averaged over in-plane offsets) of W. */
void bnd_wall_table_build(bnd_wall_table *t, const krn_kernel *k, double r0, double mass, size_t n);
void bnd_wall_table_free(bnd_wall_table *t);
static inline void bnd_wall_lookup(const bnd_wall_table *t, double d, double *z, double *dz)
{
    double u = d * t->inv_step;
    if (!(u > 0.0)) u = 0.0;
    if (u >= (double)(t->n - 1)) {
        *z = 0.0;
        *dz = 0.0;
        return;
    }
    size_t i = (size_t)u;
    double w = u - (double)i;
    *z = (1.0 - w) * t->z[i] + w * t->z[i + 1];
    *dz = (1.0 - w) * t->dz[i] + w * t->dz[i + 1];
}

/* Nearest boundary particle of fluid row i (UINT32_MAX if none) and the
 * distance to its plane, (x - x_b) . n_b. */
static inline uint32_t bnd_nearest(const uint32_t *fbs, const uint32_t *fbi, const sl_boundary *b,
                                   size_t i, double x, double y, double z, double *plane_d)
{
    uint32_t best = UINT32_MAX;
    double d2 = INFINITY;
    for (uint32_t q = fbs[i]; q < fbs[i + 1]; q++) {
        uint32_t j = fbi[q];
        double dx = x - b->x[j], dy = y - b->y[j], dz = z - b->z[j];
        double r2 = dx * dx + dy * dy + dz * dz;
        if (r2 < d2) {
            d2 = r2;
            best = j;
        }
    }
    if (best != UINT32_MAX)
        *plane_d = (x - b->x[best]) * b->nx[best] + (y - b->y[best]) * b->ny[best] +
            (z - b->z[best]) * b->nz[best];
    return best;
}

/* The wall weight Z(d) of the nearest wall; remembers it for the pressure. */
static inline __attribute__((always_inline)) double
harada2007_density(const bnd_pass *c, size_t i, double x, double y, double z, double rb)
{
    harada2007_state *st = c->state;
    double d = 0.0, zw = 0.0, dz = 0.0;
    (void)rb;
    uint32_t j = bnd_nearest(c->fbs, c->fbi, c->b, i, x, y, z, &d);
    if (j != UINT32_MAX) bnd_wall_lookup(&st->wall, d, &zw, &dz);
    st->wall_b[i] = j;
    st->wall_d[i] = dz;
    return zw;
}

/* -sum_w m_w 2 p_i / rho_i^2 grad W = -2 p_i / rho_i^2 dZ/dd n [HKK07] */
static inline __attribute__((always_inline)) void harada2007_pressure(const bnd_pass *c, size_t i,
                                                                      double x, double y, double z,
                                                                      double pti, double a[3])
{
    const harada2007_state *st = c->state;
    const uint32_t j = st->wall_b[i];
    (void)x;
    (void)y;
    (void)z;
    if (j == UINT32_MAX) return;
    const double s = -2.0 * pti * st->wall_d[i];
    a[0] += s * c->b->nx[j];
    a[1] += s * c->b->ny[j];
    a[2] += s * c->b->nz[j];
}

size_t bnd_collide_harada(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          size_t n, double *x, double *y, double *z, double *vx, double *vy,
                          double *vz);

#endif
