/*
 * surface_density: the constant correction of Bonet & Kulasegaram 2002
 * for the density of particles with a deficient neighbourhood (the free
 * surface), an EFF_DENSITY-stage effect:
 *
 *   rho_i <- rho_i / S_i  where  S_i = sum_j (m_j / rho_j) W_ij < 1,
 *
 * with rho_j the densities of the previous pass (a copy, so that every
 * thread reads the same values) and, for a boundary method whose walls add
 * density, the boundary neighbours' volumes sum_b m_b W_ib / rho0 in S_i.
 *
 *   surfaceDensityCorrection { }   or   surfaceDensityCorrection on;
 */
#ifndef SL_SURFACE_DENSITY_H
#define SL_SURFACE_DENSITY_H

#include "effects/effects.h"

extern const eff_type eff_surface_density;

#endif
