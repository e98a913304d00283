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
 *   laminarViscosity { nu n; [boundaryNu nb;] [normalized on | tensor;] }
 *
 * normalized (default off): on divides particle i's sum by the second
 * moment of its weights, tau_i = -1/3 sum_j V_j gradf r^4 / (r^2 + 0.01
 * h^2) (1 for the continuous kernel without the 0.01 h^2; 0.9915 on the
 * cubic lattice at h = 2 r0, 0.96-0.97 on the disordered packing of a
 * strained flow), so that the sum is nu Laplacian v on any isotropic
 * packing to leading order; a_i / tau_i.  A strained packing is not
 * isotropic: the sum of a smooth field is 2 nu (D . grad v + 1/2 M : H), M
 * = sum_j w_ij r r^T (w_ij = -V_j gradf r^2 / (r^2 + 0.01 h^2)), H the
 * Hessian, and tau_i = tr(M) / 3 cannot make M : H the Laplacian when M
 * is anisotropic (the Taylor-Green vortex's packing: 0.96-0.97 in its
 * plane, 0.987 across it).  tensor corrects each pair's weight by r^T A_i
 * r / r^2, A_i symmetric with sum_j w_ij (r^T A_i r / r^2) r r^T = I
 * (six equations in the fourth moment Q_abcd = sum_j w_ij r_a r_b r_c
 * r_d / r^2, solved per particle per step), so that M : H is tr(H) on any
 * packing: exact for a quadratic field where grad v = 0 (the first moment
 * D is left), A_i = I / tau_i on the cubic lattice; where A_i is not
 * positive definite or the system singular, tau_i as with on.
 * tensorLimit L > 0 caps the correction's departure from the scalar
 * normalization: where |tau_i A_i - I| (Frobenius) exceeds L, tau_i A_i =
 * I + (L / |tau_i A_i - I|) (tau_i A_i - I), so A_i stays between the two
 * (0: the scalar normalization, as with on; none, the default: no limit)
 * (a study knob: on the Taylor-Green vortex's finest level the packing's
 * rearrangement sets A_i apart from particle to particle;
 * doc/verification.md, "What tensor corrects at the finest level").  Neither is
 * pairwise symmetric (momentum not conserved to the bit); tensor costs
 * a second pass over the neighbours and a 6x6 solve per particle
 * (doc/verification.md: its time).
 *
 * Which to use when (doc/verification.md): laminarViscosity where the
 * viscous answer matters (shear flows, boundary layers, decay rates);
 * viscosity (artificial) as a stabiliser of splashing flows, as the paper.
 */
#ifndef SL_LAMINAR_VISCOSITY_H
#define SL_LAMINAR_VISCOSITY_H

#include "effects/effects.h"

/* normalized tensor: each pair's weight corrected by the fourth moment. */
#define LVISC_TENSOR 2

typedef struct lvisc_params {
    double nu;           /* m^2/s, fluid-fluid */
    double nu_boundary;  /* m^2/s, fluid-boundary */
    int normalized;      /* 0; 1: a_i over the packing's second moment tau_i; LVISC_TENSOR */
    double tensor_limit; /* tensorLimit: the largest |tau_i A_i - I| (Frobenius); HUGE_VAL none */
} lvisc_params;

extern const eff_type eff_laminar_viscosity;

/* Add the viscous acceleration to f->ax, ay, az. */
/* Rows [i0, i1) (-parallel's halo mode: a rank's own rows). */
void lvisc_apply(const lvisc_params *p, const krn_kernel *k, double mass, double rho0, sl_fluid *f,
                 const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i0,
                 size_t i1);

#endif
