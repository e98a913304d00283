/*
 * particle_shifting: a small displacement of every fluid particle each
 * step down the gradient of its particle concentration, against the
 * disorder a strained flow leaves (Xu, Stansby & Laurence 2009; the
 * Fickian form of Lind, Xu, Stansby & Rogers 2012), an EFF_SHIFT-stage
 * effect:
 *
 *   x_i <- x_i - D h^2 grad C_i,   grad C_i = sum_j V_j grad W_ij,
 *
 * at x(t), after the pressure solve and before the integration adds the
 * step's dt v (V_j = m_j / rho0, fluid and boundary neighbours; D the
 * coefficient, h the support radius).  grad C_i is zero on a uniform
 * lattice and points towards crowded neighbours, so a particle moves into
 * the gaps.  With velocityCorrection each particle's velocity is carried
 * to its new position by its Taylor term (Xu et al. 2009, Lind et al.
 * 2012), v_i <- v_i + (dr_i . grad) v_i, dr_i the shift, with the kernel
 * gradient correction of Bonet & Lok (kernel/kernel_correction.h: exact
 * for a linear field on any packing), at x(t) from every neighbour's v(t).
 *
 *   particleShifting { coefficient 0.1; velocityCorrection on; }
 *       // D, default 0.1; velocityCorrection default on
 *
 * No free-surface treatment (there C falls off and grad C would push the
 * surface particles out of the fluid; Lind et al.'s surface rule is not
 * implemented): the case reader refuses it unless every axis is periodic.
 */
#ifndef SL_PARTICLE_SHIFTING_H
#define SL_PARTICLE_SHIFTING_H

#include "effects/effects.h"

extern const eff_type eff_particle_shifting;

/* "file:line" of the effect's entry, for the case reader's refusals. */
const char *eff_particle_shifting_where(const void *state);

#endif
