/* moving_boundary: bodies at t + dt before the search (see moving_boundary.h). */
#include "effects/moving_boundary.h"

#include <stdlib.h>

#include "core/sl_mem.h"

typedef struct moving {
    const mot_motion *motions;
    size_t nbodies;
} moving;

void *eff_moving_boundary_new(const mot_motion *motions, size_t nbodies)
{
    int any = 0;
    for (size_t k = 0; k < nbodies; k++) any |= motions[k].type != MOT_NONE;
    if (!any) return NULL;
    moving *m = sl_malloc(sizeof *m, "moving boundaries");
    m->motions = motions;
    m->nbodies = nbodies;
    return m;
}

int eff_moving_boundary_translates_across(const void *state, unsigned axes)
{
    const moving *m = state;
    for (size_t k = 0; m && k < m->nbodies; k++)
        if (!mot_translates_across(&m->motions[k], axes)) return 0;
    return 1;
}

static void apply(void *state, const eff_view *v)
{
    const moving *m = state;
    const double t = v->t + v->dt;
    for (size_t k = 0; k < m->nbodies; k++)
        if (m->motions[k].type != MOT_NONE) mot_apply(&m->motions[k], (uint32_t)k, t, v->b);
    nbr_sort_boundary(v->grid, v->b);
}

const eff_type eff_moving_boundary = {
    .name = "movingBoundary",
    .stage = EFF_PRE_STEP,
    .apply = apply,
    .free = free,
};
