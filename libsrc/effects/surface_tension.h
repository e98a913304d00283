/*
 * surface_tension: the cohesion force of Becker & Teschner 2007 (eq. 13
 * there), used by the paper (Sec. 3.4):
 *
 *   a_i += -(kappa / m_i) sum_j m_j (x_i - x_j) W(|x_i - x_j|)
 *
 * It pulls neighbours together; at the free surface the missing
 * neighbours make it a net force towards the fluid, which rounds droplets.
 * kappa has units of 1/s^2 * m^3 (W is 1/m^3).  A forces-stage effect:
 *   surfaceTension { kappa k; }     (kappa 0 turns it off)
 */
#ifndef SL_SURFACE_TENSION_H
#define SL_SURFACE_TENSION_H

#include "effects/effects.h"

extern const eff_type eff_surface_tension;

void st_apply(double kappa, const krn_kernel *k, sl_fluid *f, const nbr_list *ff);

#endif
