/* gravity: a_i += g (see gravity.h). */
#include "effects/gravity.h"

#include <stdlib.h>

#include "core/sl_mem.h"

void *eff_gravity_new(const double g[3])
{
    if (g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0) return NULL;
    double *s = sl_malloc(3 * sizeof *s, "gravity");
    s[0] = g[0];
    s[1] = g[1];
    s[2] = g[2];
    return s;
}

static void uniform(const void *state, double a[3])
{
    const double *g = state;
    a[0] += g[0];
    a[1] += g[1];
    a[2] += g[2];
}

const eff_type eff_gravity = {
    .name = "gravity",
    .stage = EFF_FORCES,
    .uniform = uniform,
    .free = free,
};
