/*
 * ihmsen2010: the boundary handling of this paper (Ihmsen et al. 2010,
 * Sec. 3.2).  Boundary particles add density to fluid particles and carry
 * a predicted density and pressure of their own, which enter the pressure
 * solve (eq. 13) and push on the fluid through the symmetric pressure
 * force (eq. 6); the world collision pushes penetrating particles out
 * along the weighted mean normal (eq. 9-11) and removes their normal
 * velocity relative to the wall (eq. 12).
 */
#ifndef SL_IHMSEN2010_H
#define SL_IHMSEN2010_H

#include "boundary/bnd_method.h"
#include "kernel/sph_sums.h"

extern const bnd_method_type ihmsen2010_method;
enum { ihmsen2010_wall_density = 1 };

/* eq. (13): the boundary neighbours' mass-weighted kernel sum. */
static inline __attribute__((always_inline)) double
ihmsen2010_density(const bnd_pass *c, size_t i, double x, double y, double z, double rb)
{
    (void)c;
    (void)i;
    (void)x;
    (void)y;
    (void)z;
    return rb;
}

/* eq. (6) over the boundary neighbours, with their pressures of eq. (13). */
static inline __attribute__((always_inline)) void ihmsen2010_pressure(const bnd_pass *c, size_t i,
                                                                      double x, double y, double z,
                                                                      double pti, double a[3])
{
    const sl_boundary *b = c->b;
    sph_sum_pressure(c->k, c->fbi, c->fbs[i], c->fbs[i + 1], x, y, z, pti, b->x, b->y, b->z, b->pt,
                     b->mass, 0.0, a);
}

/* World collision, eq. (9)-(11) on positions (x, y, z) of the fluid, using
 * the fluid -> boundary lists; if vx != NULL also eq. (12) on velocities
 * with friction factor epsilon.  Returns the number of corrected particles. */
size_t bnd_collide(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon, size_t n,
                   double *x, double *y, double *z, double *vx, double *vy, double *vz);

#endif
