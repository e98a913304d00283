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

static void apply(void *state, const eff_view *v)
{
    const double *g = state;
    const double gx = g[0], gy = g[1], gz = g[2];
    sl_fluid *f = v->f;
    double *restrict ax = f->ax, *restrict ay = f->ay, *restrict az = f->az;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < f->n; i++) {
        ax[i] += gx;
        ay[i] += gy;
        az[i] += gz;
    }
}

const eff_type eff_gravity = {
    .name = "gravity",
    .stage = EFF_FORCES,
    .apply = apply,
    .free = free,
};
