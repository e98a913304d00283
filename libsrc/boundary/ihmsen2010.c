/* ihmsen2010: this paper's boundary method (see ihmsen2010.h). */
#include "boundary/ihmsen2010.h"

#include <math.h>

size_t bnd_collide(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon, size_t n,
                   double *x, double *y, double *z, double *vx, double *vy, double *vz)
{
    size_t hits = 0;
#pragma omp parallel for schedule(static) reduction(+ : hits)
    for (size_t i = 0; i < n; i++) {
        double ncx = 0, ncy = 0, ncz = 0, sw = 0, swd = 0, wvx = 0, wvy = 0, wvz = 0;
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
            uint32_t j = fb->idx[q];
            double dx = x[i] - b->x[j], dy = y[i] - b->y[j], dz = z[i] - b->z[j];
            double d = sqrt(dx * dx + dy * dy + dz * dz);
            double w = d < r0 ? (r0 - d) / r0 : 0.0; /* eq. (10) */
            ncx += w * b->nx[j];                     /* eq. (9) */
            ncy += w * b->ny[j];
            ncz += w * b->nz[j];
            sw += w;
            swd += w * (r0 - d);
            wvx += w * b->vx[j]; /* the wall's velocity, same weights */
            wvy += w * b->vy[j];
            wvz += w * b->vz[j];
        }
        double len = sqrt(ncx * ncx + ncy * ncy + ncz * ncz);
        if (sw <= 0.0 || len <= 1e-12) continue;
        double s = swd / (sw * len); /* eq. (11) */
        x[i] += s * ncx;
        y[i] += s * ncy;
        z[i] += s * ncz;
        hits++;
        if (vx) { /* eq. (12) relative to the wall: keep epsilon times the tangential velocity */
            double ux = ncx / len, uy = ncy / len, uz = ncz / len;
            wvx /= sw;
            wvy /= sw;
            wvz /= sw;
            double rx = vx[i] - wvx, ry = vy[i] - wvy, rz = vz[i] - wvz;
            double vn = rx * ux + ry * uy + rz * uz;
            vx[i] = wvx + epsilon * (rx - vn * ux);
            vy[i] = wvy + epsilon * (ry - vn * uy);
            vz[i] = wvz + epsilon * (rz - vn * uz);
        }
    }
    return hits;
}

static size_t collide(void *state, const bnd_setup *su, const nbr_list *fb, const sl_boundary *b,
                      size_t n, double *x, double *y, double *z, double *vx, double *vy, double *vz)
{
    (void)state;
    return bnd_collide(fb, b, su->r0, su->epsilon, n, x, y, z, vx, vy, vz);
}

const bnd_method_type ihmsen2010_method = {
    .name = "ihmsen2010",
    .what = "boundary particles with density and pressure in the solve (Ihmsen et al. 2010)",
    .wall_density = ihmsen2010_wall_density,
    .collide = collide,
};
