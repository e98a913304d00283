/*
 * becker2009: direct forcing of Becker, Tessendorf & Teschner 2009
 * [BTT09], eq. (7)-(8) of the paper: the walls add no density to the
 * fluid and take no part in the pressure solve; each penetrated boundary
 * particle in turn puts the fluid particle back to distance r0 from its
 * plane (the iterative correction the paper contrasts with eq. 9-11) and,
 * with velocities, v = epsilon [v]_t - restitution [v]_n for the
 * approaching normal component.
 */
#ifndef SL_BECKER2009_H
#define SL_BECKER2009_H

#include "boundary/bnd_method.h"

extern const bnd_method_type becker2009_method;
enum { becker2009_wall_density = 0 };

static inline __attribute__((always_inline)) double
becker2009_density(const bnd_pass *c, size_t i, double x, double y, double z, double rb)
{
    (void)c;
    (void)i;
    (void)x;
    (void)y;
    (void)z;
    (void)rb;
    return 0.0;
}

static inline __attribute__((always_inline)) void becker2009_pressure(const bnd_pass *c, size_t i,
                                                                      double x, double y, double z,
                                                                      double pti, double a[3])
{
    (void)c;
    (void)i;
    (void)x;
    (void)y;
    (void)z;
    (void)pti;
    (void)a;
}

size_t bnd_collide_becker(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          double restitution, size_t n, double *x, double *y, double *z, double *vx,
                          double *vy, double *vz);

#endif
