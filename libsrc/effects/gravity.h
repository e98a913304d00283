/*
 * gravity: the body force g of constant/fluidProperties (`gravity`), a
 * forces-stage effect: a_i += g, a uniform acceleration that the solver
 * sets where it resets the forces (no pass over the particles of its own).  The vector itself stays a parameter of
 * the fluid (the initial time step and the hydrostatic estimates read it
 * too); the effect is in the set only when g is not zero.
 */
#ifndef SL_GRAVITY_H
#define SL_GRAVITY_H

#include "effects/effects.h"

extern const eff_type eff_gravity;

/* The gravity effect's state for g, NULL when g is zero. */
void *eff_gravity_new(const double g[3]);

#endif
