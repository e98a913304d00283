/*
 * emitter: an inflow that injects fluid particles through a rectangle or a
 * disc at a given speed (the emitter effect; the paper's Glass scene is
 * filled this way).
 *
 * The opening is covered by a square lattice of spacing r0 in its plane.
 * Each step the emitted column advances by speed dt; whenever the last
 * layer has moved r0 away from the opening, a new layer is placed (at the
 * distance it would have travelled), with velocity speed * direction, so
 * the inflow is speed * area * rho0 kg/s.  The particle arrays grow by
 * doubling when full: growth is the only allocation, and it is safe.
 * The state (distance travelled since the last layer, next id) is plain
 * data, saved with rollbacks and restart files.
 */
#ifndef SL_EMITTER_H
#define SL_EMITTER_H

#include <stddef.h>
#include <stdint.h>

#include "effects/effects.h"
#include "particles/particles.h"

typedef struct emt_emitter {
    char name[64];
    int disc;                 /* 0 rectangle, 1 disc */
    double centre[3], dir[3]; /* dir: unit flow direction, normal to the opening */
    double u[3], v[3];        /* unit axes in the opening's plane */
    double size[2], radius;   /* rectangle widths along u, v; disc radius */
    double speed, t0, t1;     /* m/s; active for t0 <= t < t1 */
    double rho0;
    size_t np;       /* lattice points of the opening */
    double *pu, *pv; /* their in-plane coordinates */
} emt_emitter;

typedef struct emt_state {
    double travelled; /* since the last layer, m */
} emt_state;

/* Set the in-plane axes and the lattice for spacing r0; returns the number
 * of points (0: the opening is smaller than one particle). */
size_t emt_setup(emt_emitter *e, double r0);
void emt_free(emt_emitter *e);

/* After a step from t to t + dt: add the layers due; returns how many
 * particles were added (ids from *next_id on). */
size_t emt_emit(const emt_emitter *e, emt_state *st, double t, double dt, double r0, sl_fluid *f,
                uint32_t *next_id);

/* The emitter effect (post-step: after each accepted step from t to
 * t + dt, every emitter adds the layers due).  Its saved state is the id
 * of the next particle and each emitter's emt_state. */
extern const eff_type eff_emitter;

/* The effect's state for emitters e[0..n) (not copied: they must outlive
 * the set); ids of emitted particles start at next_id.  NULL if n == 0. */
void *eff_emitter_new(const emt_emitter *e, size_t n, uint32_t next_id);

#endif
