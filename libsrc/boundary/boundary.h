/*
 * boundary: the boundary handling of Ihmsen et al. 2010, Sec. 3.2.
 *
 * Boundary particles add density to fluid particles and carry a density
 * and pressure of their own (eq. 13); penetrating fluid particles are
 * pushed out along the weighted mean normal (eq. 9-11) and lose their
 * normal velocity (eq. 12).
 *
 * Boundary mass (the paper leaves it open).  A single layer of boundary
 * particles must stand in for the fluid missing behind a wall.  We set
 *     m_b = gamma * rho0 * V_b,   V_b = 1 / sum_k W_bk
 * (V_b is the volume estimate of Akinci et al. 2012, which makes m_b
 * adapt to the local sampling density, e.g. smaller at corners), and pick
 * gamma once per run from a prototype: a flat wall sampled on a square
 * lattice of spacing r0 and fluid on a cubic lattice whose first layer is
 * r0 above it.  gamma makes the first fluid layer sit exactly at rho0.
 * The boundary particle's own density is
 *     rho_b = c * sum_k m_k W_bk + sum_j m_j W_bj
 * with c chosen on the same prototype so that rho_b = rho0 there: fluid at
 * rest against a flat wall is at rest density on both sides.
 */
#ifndef SL_BOUNDARY_H
#define SL_BOUNDARY_H

/* The boundary methods a case can choose (constant/boundaryProperties,
 * `method`).  See boundary_methods.c for the formulas of each. */
typedef enum {
    BND_IHMSEN2010, /* this paper: boundary density and pressure in the solve */
    BND_BECKER2009, /* direct forcing [BTT09], eq. (7)-(8): no boundary density */
    BND_HARADA2007  /* wall weight [HKK07]: density from the wall distance */
} bnd_method;

const char *bnd_method_name(bnd_method m);

#include <math.h>
#include <stdint.h>

#include "kernel/kernel.h"
#include "neighbours/neighbours.h"
#include "particles/particles.h"

typedef struct bnd_calibration {
    double gamma;       /* boundary mass factor */
    double c_static;    /* factor of the boundary-boundary density */
    double fluid_sum;   /* prototype: fluid contribution to the first layer */
} bnd_calibration;

/* The prototype calibration (see above). */
bnd_calibration bnd_calibrate(const krn_kernel *k, double r0, double mfluid, double rho0);

/* Set m_b and rho_static for all boundary particles; b must be sorted in g. */
void bnd_set_mass(const nbr_grid *g, const krn_kernel *k, const bnd_calibration *c,
                  double rho0, sl_boundary *b);

/* Wall-weight table of Harada et al. 2007: the density Z(d) that a wall
 * adds to a fluid particle at distance d from the plane of the boundary
 * particles, and dZ/dd, on [0, h]. */
typedef struct bnd_wall_table {
    size_t n;
    double dmax, inv_step;
    double *z, *dz;
} bnd_wall_table;

/* Z(d) = m sum over a solid half-space lattice (spacing r0, layers at plane
 * distance 0, -r0, -2 r0, ...; averaged over in-plane offsets) of W. */
void bnd_wall_table_build(bnd_wall_table *t, const krn_kernel *k, double r0, double mass,
                          size_t n);
void bnd_wall_table_free(bnd_wall_table *t);
static inline void bnd_wall_lookup(const bnd_wall_table *t, double d, double *z, double *dz)
{
    double u = d * t->inv_step;
    if (!(u > 0.0)) u = 0.0;
    if (u >= (double)(t->n - 1)) { *z = 0.0; *dz = 0.0; return; }
    size_t i = (size_t)u;
    double w = u - (double)i;
    *z = (1.0 - w) * t->z[i] + w * t->z[i + 1];
    *dz = (1.0 - w) * t->dz[i] + w * t->dz[i + 1];
}

/* Direct forcing of Becker et al. 2009, eq. (7)-(8), applied to each
 * penetrated boundary particle in turn (the iterative correction the paper
 * contrasts with eq. 9-11): the particle is put back to distance r0 from
 * the boundary particle's plane; with velocities, v = epsilon [v]_t -
 * restitution [v]_n for the approaching normal component. */
size_t bnd_collide_becker(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          double restitution, size_t n, double *x, double *y, double *z,
                          double *vx, double *vy, double *vz);

/* Distance-based position constraint of Harada et al. 2007: a particle
 * closer than r0 to the plane of its nearest boundary particle is put back
 * to r0 along that particle's normal; with velocities, the approaching
 * normal component is removed and epsilon times the tangential kept. */
size_t bnd_collide_harada(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          size_t n, double *x, double *y, double *z,
                          double *vx, double *vy, double *vz);

/* Nearest boundary particle of a row (UINT32_MAX if none) and the distance
 * to its plane, (x - x_b) . n_b. */
static inline uint32_t bnd_nearest(const nbr_list *fb, const sl_boundary *b, size_t i, double x,
                                   double y, double z, double *plane_d)
{
    uint32_t best = UINT32_MAX;
    double d2 = INFINITY;
    for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
        uint32_t j = fb->idx[q];
        double dx = x - b->x[j], dy = y - b->y[j], dz = z - b->z[j];
        double r2 = dx * dx + dy * dy + dz * dz;
        if (r2 < d2) { d2 = r2; best = j; }
    }
    if (best != UINT32_MAX)
        *plane_d = (x - b->x[best]) * b->nx[best] + (y - b->y[best]) * b->ny[best] +
                   (z - b->z[best]) * b->nz[best];
    return best;
}

/* World collision, eq. (9)-(11) on positions (x, y, z) of the fluid, using
 * the fluid -> boundary lists; if vx != NULL also eq. (12) on velocities
 * with friction factor epsilon.  Returns the number of corrected particles. */
size_t bnd_collide(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                   size_t n, double *x, double *y, double *z,
                   double *vx, double *vy, double *vz);

#endif
