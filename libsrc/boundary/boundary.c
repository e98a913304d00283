/* boundary: calibration, masses and world collision (see boundary.h). */
#include "boundary/boundary.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"

/* Sum of W over a square lattice (spacing r0, |i|,|j| <= 4) in the plane
 * z = 0, seen from (0, 0, zq). */
static inline __attribute__((always_inline)) double wall_sum_t(int type, const krn_kernel *k,
                                                               double r0, double zq)
{
    double s = 0.0;
    for (int i = -4; i <= 4; i++)
        for (int j = -4; j <= 4; j++)
            s += krn_w_t(k, type, sqrt((i * i + j * j) * r0 * r0 + zq * zq));
    return s;
}

static double wall_sum(const krn_kernel *k, double r0, double zq)
{
    return k->type == KRN_WENDLAND_C2 ? wall_sum_t(KRN_WENDLAND_C2, k, r0, zq)
                                      : wall_sum_t(KRN_CUBIC_SPLINE, k, r0, zq);
}

/* Sum of W over a cubic fluid lattice filling z >= r0, seen from (0,0,zq). */
static inline __attribute__((always_inline)) double fluid_sum_t(int type, const krn_kernel *k,
                                                                double r0, double zq)
{
    double s = 0.0;
    for (int i = -4; i <= 4; i++)
        for (int j = -4; j <= 4; j++)
            for (int l = 1; l <= 6; l++) {
                double dz = l * r0 - zq;
                s += krn_w_t(k, type, sqrt((i * i + j * j) * r0 * r0 + dz * dz));
            }
    return s;
}

static double fluid_sum(const krn_kernel *k, double r0, double zq)
{
    return k->type == KRN_WENDLAND_C2 ? fluid_sum_t(KRN_WENDLAND_C2, k, r0, zq)
                                      : fluid_sum_t(KRN_CUBIC_SPLINE, k, r0, zq);
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

/* sum_j W_ij (m == NULL) or sum_j m_j W_ij over boundary particle i's
 * boundary neighbours, for a constant kernel type (the loop holds that
 * kernel's formula alone). */
static inline __attribute__((always_inline)) double bb_sum(int type, const krn_kernel *k,
                                                           const nbr_list *bb, const sl_boundary *b,
                                                           const double *m, size_t i)
{
    double s = 0.0;
    for (uint32_t q = bb->start[i]; q < bb->start[i + 1]; q++) {
        uint32_t j = bb->idx[q];
        double dx = b->x[i] - b->x[j], dy = b->y[i] - b->y[j], dz = b->z[i] - b->z[j];
        const double w = krn_w_t(k, type, sqrt(dx * dx + dy * dy + dz * dz));
        s += m ? m[j] * w : w;
    }
    return s;
}

void bnd_set_mass(const nbr_grid *g, const krn_kernel *k, const bnd_calibration *c, double rho0,
                  sl_boundary *b)
{
    nbr_list bb;
    nbr_list_init(&bb);
    nbr_build_bb(g, b, &bb);
    const int wc2 = k->type == KRN_WENDLAND_C2;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        const double s = wc2 ? bb_sum(KRN_WENDLAND_C2, k, &bb, b, NULL, i)
                             : bb_sum(KRN_CUBIC_SPLINE, k, &bb, b, NULL, i);
        b->mass[i] = c->gamma * rho0 / s; /* s > 0: the list holds the particle itself */
    }
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        const double s = wc2 ? bb_sum(KRN_WENDLAND_C2, k, &bb, b, b->mass, i)
                             : bb_sum(KRN_CUBIC_SPLINE, k, &bb, b, b->mass, i);
        b->rho_static[i] = c->c_static * s;
    }
    nbr_list_free(&bb);
}
