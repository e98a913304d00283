/*
 * sph_sums: the neighbour loops of the solver, written once.
 *
 * Each function sums a pair term over one compressed neighbour-list row
 * [q0, q1) of indices into the target arrays.  They are static inline and
 * take restrict pointers and the kernel by value, so that the compiler
 * vectorises the loop (indexed loads become gathers): these loops are
 * where a PCISPH step spends its time.
 */
#ifndef SL_SPH_SUMS_H
#define SL_SPH_SUMS_H

#include <math.h>
#include <stdint.h>

#include "kernel/kernel.h"

/* sum_j W(|p - x_j|) */
static inline double sph_sum_w(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                               uint32_t q1, double px, double py, double pz,
                               const double *restrict x, const double *restrict y,
                               const double *restrict z)
{
    double s = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        s += krn_w(&k, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return s;
}

/* sum_j m_j W(|p - x_j|) */
static inline double sph_sum_mw(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                uint32_t q1, double px, double py, double pz,
                                const double *restrict x, const double *restrict y,
                                const double *restrict z, const double *restrict m)
{
    double s = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        s += m[j] * krn_w(&k, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return s;
}

/* sum_j W(|p - x_j|) / rho_j: with the mass, the Shepard sum of volumes */
static inline double sph_sum_w_over(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                    uint32_t q1, double px, double py, double pz,
                                    const double *restrict x, const double *restrict y,
                                    const double *restrict z, const double *restrict rho)
{
    double s = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        s += krn_w(&k, sqrt(dx * dx + dy * dy + dz * dz)) / rho[j];
    }
    return s;
}

/* a += -sum_j m_j (pi + pt_j) grad W(p - x_j): the symmetric pressure
 * force of eq. (6) per unit mass, with pt = p / rho^2.  mj == NULL means
 * every m_j = mconst. */
static inline void sph_sum_pressure(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                    uint32_t q1, double px, double py, double pz, double pi,
                                    const double *restrict x, const double *restrict y,
                                    const double *restrict z, const double *restrict pt,
                                    const double *restrict mj, double mconst, double a[3])
{
    double ax = 0.0, ay = 0.0, az = 0.0;
    if (mj) {
        for (uint32_t q = q0; q < q1; q++) {
            const uint32_t j = idx[q];
            const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
            const double c = mj[j] * (pi + pt[j]) * krn_gradf(&k, sqrt(dx * dx + dy * dy + dz * dz));
            ax -= c * dx;
            ay -= c * dy;
            az -= c * dz;
        }
    } else {
        for (uint32_t q = q0; q < q1; q++) {
            const uint32_t j = idx[q];
            const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
            const double c = (pi + pt[j]) * krn_gradf(&k, sqrt(dx * dx + dy * dy + dz * dz));
            ax -= c * dx;
            ay -= c * dy;
            az -= c * dz;
        }
        ax *= mconst;
        ay *= mconst;
        az *= mconst;
    }
    a[0] += ax;
    a[1] += ay;
    a[2] += az;
}

#endif
