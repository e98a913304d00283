/* boundary: calibration, masses and world collision (see boundary.h). */
#include "boundary/boundary.h"

#include <math.h>

/* Sum of W over a square lattice (spacing r0, |i|,|j| <= 4) in the plane
 * z = 0, seen from (0, 0, zq). */
static double wall_sum(const krn_kernel *k, double r0, double zq)
{
    double s = 0.0;
    for (int i = -4; i <= 4; i++)
        for (int j = -4; j <= 4; j++)
            s += krn_w(k, sqrt((i * i + j * j) * r0 * r0 + zq * zq));
    return s;
}

/* Sum of W over a cubic fluid lattice filling z >= r0, seen from (0,0,zq). */
static double fluid_sum(const krn_kernel *k, double r0, double zq)
{
    double s = 0.0;
    for (int i = -4; i <= 4; i++)
        for (int j = -4; j <= 4; j++)
            for (int l = 1; l <= 6; l++) {
                double dz = l * r0 - zq;
                s += krn_w(k, sqrt((i * i + j * j) * r0 * r0 + dz * dz));
            }
    return s;
}

bnd_calibration bnd_calibrate(const krn_kernel *k, double r0, double mfluid, double rho0)
{
    bnd_calibration c;
    double v_proto = 1.0 / wall_sum(k, r0, 0.0);
    double fluid_first = mfluid * fluid_sum(k, r0, r0);
    double wall_seen = wall_sum(k, r0, r0);
    c.gamma = (rho0 - fluid_first) / (rho0 * v_proto * wall_seen);
    c.fluid_sum = mfluid * fluid_sum(k, r0, 0.0);
    /* prototype wall particle: sum_k m_k W_0k = gamma rho0 */
    c.c_static = (rho0 - c.fluid_sum) / (c.gamma * rho0);
    return c;
}

void bnd_set_mass(const nbr_grid *g, const krn_kernel *k, const bnd_calibration *c,
                  double rho0, sl_boundary *b)
{
    nbr_list bb;
    nbr_list_init(&bb);
    nbr_build_bb(g, b, &bb);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        double s = 0.0;
        for (uint32_t q = bb.start[i]; q < bb.start[i + 1]; q++) {
            uint32_t j = bb.idx[q];
            double dx = b->x[i] - b->x[j], dy = b->y[i] - b->y[j], dz = b->z[i] - b->z[j];
            s += krn_w(k, sqrt(dx * dx + dy * dy + dz * dz));
        }
        b->mass[i] = c->gamma * rho0 / s; /* s > 0: the list holds the particle itself */
    }
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        double s = 0.0;
        for (uint32_t q = bb.start[i]; q < bb.start[i + 1]; q++) {
            uint32_t j = bb.idx[q];
            double dx = b->x[i] - b->x[j], dy = b->y[i] - b->y[j], dz = b->z[i] - b->z[j];
            s += b->mass[j] * krn_w(k, sqrt(dx * dx + dy * dy + dz * dz));
        }
        b->rho_static[i] = c->c_static * s;
    }
    nbr_list_free(&bb);
}

size_t bnd_collide(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                   size_t n, double *x, double *y, double *z,
                   double *vx, double *vy, double *vz)
{
    size_t hits = 0;
#pragma omp parallel for schedule(static) reduction(+ : hits)
    for (size_t i = 0; i < n; i++) {
        double ncx = 0, ncy = 0, ncz = 0, sw = 0, swd = 0;
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
            uint32_t j = fb->idx[q];
            double dx = x[i] - b->x[j], dy = y[i] - b->y[j], dz = z[i] - b->z[j];
            double d = sqrt(dx * dx + dy * dy + dz * dz);
            double w = d < r0 ? (r0 - d) / r0 : 0.0; /* eq. (10) */
            ncx += w * b->nx[j];                      /* eq. (9) */
            ncy += w * b->ny[j];
            ncz += w * b->nz[j];
            sw += w;
            swd += w * (r0 - d);
        }
        double len = sqrt(ncx * ncx + ncy * ncy + ncz * ncz);
        if (sw <= 0.0 || len <= 1e-12) continue;
        double s = swd / (sw * len); /* eq. (11) */
        x[i] += s * ncx;
        y[i] += s * ncy;
        z[i] += s * ncz;
        hits++;
        if (vx) { /* eq. (12): keep epsilon times the tangential velocity */
            double ux = ncx / len, uy = ncy / len, uz = ncz / len;
            double vn = vx[i] * ux + vy[i] * uy + vz[i] * uz;
            vx[i] = epsilon * (vx[i] - vn * ux);
            vy[i] = epsilon * (vy[i] - vn * uy);
            vz[i] = epsilon * (vz[i] - vn * uz);
        }
    }
    return hits;
}
