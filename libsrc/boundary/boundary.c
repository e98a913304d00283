/* boundary: calibration, masses and world collision (see boundary.h). */
#include "boundary/boundary.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"

/* Sum of W over a square lattice (spacing r0, |i|,|j| <= 4) in the plane
 * z = 0, seen from (0, 0, zq). */
static double wall_sum(const krn_kernel *k, double r0, double zq)
{
    double s = 0.0;
    for (int i = -4; i <= 4; i++)
        for (int j = -4; j <= 4; j++) s += krn_w(k, sqrt((i * i + j * j) * r0 * r0 + zq * zq));
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

void bnd_set_mass(const nbr_grid *g, const krn_kernel *k, const bnd_calibration *c, double rho0,
                  sl_boundary *b)
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
