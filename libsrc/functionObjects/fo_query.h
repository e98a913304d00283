/*
 * fo_query: SPH values at arbitrary points, from the solver's particles and
 * neighbour grid (read only; libsrc/neighbours is not changed).
 *
 * Interpolation is Shepard-normalised:
 *     A(x) = sum_j V_j A_j W(x - x_j) / sum_j V_j W(x - x_j),  V_j = m_j / rho_j
 * over fluid particles and the boundary particles that are active (that had
 * a fluid neighbour at the solver's last neighbour search: the others hold
 * stale pressures).  A boundary particle's velocity is zero (static walls).
 * A density of zero or less (never computed) counts as rho0 in V_j.
 *
 * The colour of the fluid is the unnormalised c(x) = sum_j V_j W(x - x_j)
 * over fluid particles only: about 1 inside the fluid, 1/2 at a flat free
 * surface (the kernel is symmetric), 0 in air.
 *
 * Search: the particles of the cells within ceil(h / cell) + 1 of the
 * point's cell are tested; the extra ring allows for particles that moved
 * (less than one cell) since they were sorted, as they have after a step.
 * fo_index_update checks, in one pass over the particles, that the grid
 * still describes the particle arrays that way (counts equal, every
 * particle within one cell of the cell it is sorted in).  If not -- no sort
 * yet, a restored state in an older order, a particle faster than a cell
 * per step -- every particle is tested instead: slower, never wrong.
 */
#ifndef SL_FO_QUERY_H
#define SL_FO_QUERY_H

#include <stdint.h>

#include "solver/pcisph.h"

typedef struct fo_index {
    const pcs_view *s;
    int use_grid;           /* the grid describes s->f and s->b (see above) */
    uint32_t *cell_of_rank; /* inverse of grid.rank, built on first use */
    size_t ncells;
} fo_index;

/* Check s's grid against its particles (O(particles + cells)); allocates
 * only the first time (or if the grid grows). */
void fo_index_update(fo_index *ix, const pcs_view *s);
void fo_index_free(fo_index *ix);

typedef struct fo_sample {
    int n;                                 /* particles within h */
    double pressure, density, velocity[3]; /* NaN when n == 0 */
} fo_sample;

void fo_query_sample(const fo_index *ix, double x, double y, double z, fo_sample *out);
double fo_query_colour(const fo_index *ix, double x, double y, double z);

#endif
