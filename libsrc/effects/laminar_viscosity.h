/*
 * laminar_viscosity: the physical (laminar) viscosity of Morris, Fox & Zhu
 * 1997 (J. Comput. Phys. 136, eq. 8 there), a forces-stage effect:
 *
 *   a_i += sum_j m_j (mu_i + mu_j) / (rho_i rho_j)
 *                    (x_ij . grad W_ij) / (|x_ij|^2 + 0.01 h^2) v_ij
 *
 * with mu = rho0 nu and rho_i = rho_j = rho0 (PCISPH keeps the density
 * within eta), i.e. a_i += 2 nu / rho0 sum_j m_j gradf(r) r^2 / (r^2 +
 * 0.01 h^2) (v_i - v_j).  Unlike the artificial viscosity (viscosity.h),
 * which damps only approaching pairs and maps nu to alpha h c_s = 10 nu,
 * every pair is damped, shear included: nu is the kinematic viscosity of
 * the Navier-Stokes equations (the Poiseuille profile of
 * cases/verification/poiseuille converges to g z (d - z) / (2 nu)).
 * Against boundary particles the same form with their masses and
 * velocities (no-slip walls), with boundaryNu (default nu; 0: free slip).
 *
 * constant/fluidProperties:
 *   laminarViscosity { nu n; [boundaryNu nb;] [normalized on;] }
 *
 * normalized (default off) divides particle i's sum by the second moment
 * of its weights, tau_i = -1/3 sum_j V_j gradf r^4 / (r^2 + 0.01 h^2)
 * (1 for the continuous kernel without the 0.01 h^2; 0.9915 on the cubic
 * lattice at h = 2 r0, 0.96-0.97 on the disordered packing of a strained
 * flow), so that the sum is nu Laplacian v on any packing to leading
 * order; a_i / tau_i, not pairwise symmetric (momentum not conserved to
 * the bit).
 *
 * Which to use when (doc/verification.md): laminarViscosity where the
 * viscous answer matters (shear flows, boundary layers, decay rates);
 * viscosity (artificial) as a stabiliser of splashing flows, as the paper.
 */
#ifndef SL_LAMINAR_VISCOSITY_H
#define SL_LAMINAR_VISCOSITY_H

#include "effects/effects.h"

typedef struct lvisc_params {
    double nu;          /* m^2/s, fluid-fluid */
    double nu_boundary; /* m^2/s, fluid-boundary */
    int normalized;     /* a_i over the packing's second moment tau_i */
} lvisc_params;

extern const eff_type eff_laminar_viscosity;

/* Add the viscous acceleration to f->ax, ay, az. */
/* Rows [i0, i1) (-parallel's halo mode: a rank's own rows). */
void lvisc_apply(const lvisc_params *p, const krn_kernel *k, double mass, double rho0, sl_fluid *f,
                 const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i0,
                 size_t i1);

#endif
