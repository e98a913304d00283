/*
 * viscosity: the artificial viscosity of Becker & Teschner 2007 (eq. 11-12
 * there), used by the paper (Sec. 3.4), a forces-stage effect:
 *
 *   a_i += -sum_j m_j Pi_ij grad W_ij,
 *   Pi_ij = -nu_ij (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2)  if v_ij . x_ij < 0
 *         = 0                                             otherwise,
 *   nu_ij = 2 alpha h c_s / (rho_i + rho_j)  ~  alpha h c_s / rho0
 *
 * (we use rho_i + rho_j = 2 rho0, which PCISPH keeps within eta).  Only
 * approaching pairs are damped, so rigid rotation and separation are free.
 * Against boundary particles the same form applies with its own alpha and
 * the boundary velocity (zero for static walls).
 *
 * constant/fluidProperties:
 *   viscosity { alpha a; soundSpeed c; [boundaryAlpha ab;] }   alpha h c_s = a h c
 *   viscosity { nu n; [boundaryNu nb;] }                        alpha h c_s = 10 n
 * (a kinematic viscosity nu maps to alpha h c_s = 10 nu: Monaghan 2005,
 * 3D, with h the support radius).
 */
#ifndef SL_VISCOSITY_H
#define SL_VISCOSITY_H

#include "effects/effects.h"

typedef struct visc_params {
    double coef;          /* alpha h c_s (m^2/s), fluid-fluid */
    double coef_boundary; /* alpha_b h c_s, fluid-boundary */
} visc_params;

extern const eff_type eff_viscosity;

/* Add the viscous acceleration to f->ax, ay, az. */
/* Rows [i0, i1) (-parallel's halo mode: a rank's own rows). */
void visc_apply(const visc_params *p, const krn_kernel *k, double mass, double rho0, sl_fluid *f,
                const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i0, size_t i1);

#endif
