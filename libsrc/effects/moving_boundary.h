/*
 * moving_boundary: prescribed rigid motion of boundary bodies (motion/),
 * a pre-step effect: before the neighbour search of the step from t to
 * t + dt the moving bodies are put where they are at t + dt, with their
 * velocities, and the boundary is sorted again (by cell, and within a cell
 * by creation index, so that sums do not depend on the history of moves).
 * In the set when at least one body of constant/boundaryProperties has a
 * `motion { }`.
 */
#ifndef SL_MOVING_BOUNDARY_H
#define SL_MOVING_BOUNDARY_H

#include "effects/effects.h"
#include "motion/motion.h"

extern const eff_type eff_moving_boundary;

/* The effect's state for motions[body] (MOT_NONE for static bodies; the
 * array is not copied and must outlive the set), NULL if nothing moves. */
void *eff_moving_boundary_new(const mot_motion *motions, size_t nbodies);
/* Whether every body of the state translates without moving along
 * `axes` (mot_translates_across). */
int eff_moving_boundary_translates_across(const void *state, unsigned axes);

#endif
