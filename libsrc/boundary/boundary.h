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
 *
 * The masses serve every boundary method (the others measure the wall's
 * share of the density with them); the methods themselves are
 * boundary/<name>.{h,c} behind the contract of bnd_method.h.
 */
#ifndef SL_BOUNDARY_H
#define SL_BOUNDARY_H

#include <math.h>
#include <stdint.h>

#include "kernel/kernel.h"
#include "neighbours/neighbours.h"
#include "particles/particles.h"

typedef struct bnd_calibration {
    double gamma;     /* boundary mass factor */
    double c_static;  /* factor of the boundary-boundary density */
    double fluid_sum; /* prototype: fluid contribution to the first layer */
} bnd_calibration;

/* The prototype calibration (see above). */
bnd_calibration bnd_calibrate(const krn_kernel *k, double r0, double mfluid, double rho0);

/* Set m_b and rho_static for all boundary particles; b must be sorted in g. */
void bnd_set_mass(const nbr_grid *g, const krn_kernel *k, const bnd_calibration *c, double rho0,
                  sl_boundary *b);

#endif
