/* becker2009: direct forcing [BTT09] (see becker2009.h). */
#include "boundary/becker2009.h"

size_t bnd_collide_becker(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          double restitution, size_t n, double *x, double *y, double *z, double *vx,
                          double *vy, double *vz)
{
    size_t hits = 0;
#pragma omp parallel for schedule(static) reduction(+ : hits)
    for (size_t i = 0; i < n; i++) {
        int hit = 0;
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
            uint32_t j = fb->idx[q];
            double dx = x[i] - b->x[j], dy = y[i] - b->y[j], dz = z[i] - b->z[j];
            if (dx * dx + dy * dy + dz * dz >= r0 * r0) continue;
            double dn = dx * b->nx[j] + dy * b->ny[j] + dz * b->nz[j];
            if (dn >= r0) continue;
            double push = r0 - dn; /* eq. (8): back to the contact distance */
            x[i] += push * b->nx[j];
            y[i] += push * b->ny[j];
            z[i] += push * b->nz[j];
            hit = 1;
            if (vx) { /* eq. (7), relative to the wall */
                double rx = vx[i] - b->vx[j], ry = vy[i] - b->vy[j], rz = vz[i] - b->vz[j];
                double vn = rx * b->nx[j] + ry * b->ny[j] + rz * b->nz[j];
                double tx = rx - vn * b->nx[j], ty = ry - vn * b->ny[j], tz = rz - vn * b->nz[j];
                double nn = vn < 0.0 ? -restitution * vn : vn;
                vx[i] = b->vx[j] + epsilon * tx + nn * b->nx[j];
                vy[i] = b->vy[j] + epsilon * ty + nn * b->ny[j];
                vz[i] = b->vz[j] + epsilon * tz + nn * b->nz[j];
            }
        }
        hits += (size_t)hit;
    }
    return hits;
}

static size_t collide(void *state, const bnd_setup *su, const nbr_list *fb, const sl_boundary *b,
                      size_t n, double *x, double *y, double *z, double *vx, double *vy, double *vz)
{
    (void)state;
    return bnd_collide_becker(fb, b, su->r0, su->epsilon, su->restitution, n, x, y, z, vx, vy, vz);
}

const bnd_method_type becker2009_method = {
    .name = "becker2009",
    .what = "direct forcing, no wall density (Becker et al. 2009)",
    .wall_density = becker2009_wall_density,
    .collide = collide,
};
