/* effects: a case's set of effects and their stages (see effects.h). */
#include "effects/effects.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"
#include "effects/laminar_viscosity.h"
#include "effects/particle_shifting.h"
#include "effects/surface_density.h"
#include "effects/surface_tension.h"
#include "effects/viscosity.h"

const eff_type *const eff_fluid_effects[] = {&eff_viscosity,         &eff_laminar_viscosity,
                                             &eff_surface_tension,   &eff_surface_density,
                                             &eff_particle_shifting, NULL};

void eff_set_init(eff_set *s) { memset(s, 0, sizeof *s); }

void eff_set_free(eff_set *s)
{
    for (size_t i = 0; i < s->n; i++)
        if (s->e[i].type->free) s->e[i].type->free(s->e[i].state);
    free(s->e);
    memset(s, 0, sizeof *s);
}

eff_instance *eff_add(eff_set *s, const eff_type *t, void *state)
{
    s->e = sl_realloc(s->e, (s->n + 1) * sizeof *s->e, "effects");
    eff_instance *e = &s->e[s->n++];
    memset(e, 0, sizeof *e);
    e->type = t;
    e->state = state;
    return e;
}

eff_instance *eff_find(const eff_set *s, const char *name)
{
    for (size_t i = 0; s && i < s->n; i++)
        if (strcmp(s->e[i].type->name, name) == 0) return &s->e[i];
    return NULL;
}

void eff_run(eff_set *s, eff_stage st, const eff_view *v)
{
    for (size_t i = 0; s && i < s->n; i++) {
        eff_instance *e = &s->e[i];
        if (e->type->stage != st || !e->type->apply) continue;
        double t0 = omp_get_wtime();
        e->type->apply(e->state, v);
        e->calls++;
        e->time += omp_get_wtime() - t0;
    }
}

void eff_uniform(eff_set *s, double a[3])
{
    a[0] = a[1] = a[2] = 0.0;
    for (size_t i = 0; s && i < s->n; i++) {
        eff_instance *e = &s->e[i];
        if (e->type->stage != EFF_FORCES || !e->type->uniform) continue;
        e->type->uniform(e->state, a);
        e->calls++;
    }
}

void eff_read_fluid(eff_set *s, const dict *d, const eff_setup *su)
{
    for (size_t k = 0; eff_fluid_effects[k]; k++) {
        const eff_type *t = eff_fluid_effects[k];
        if (!dict_has(d, t->name)) continue;
        void *state = t->read(d, su);
        if (state) eff_add(s, t, state);
    }
}

size_t eff_state_size(const eff_set *s)
{
    size_t n = 0;
    for (size_t i = 0; i < s->n; i++)
        if (s->e[i].type->state_size) n += s->e[i].type->state_size(s->e[i].state);
    return n;
}

void eff_save(const eff_set *s, void *buf)
{
    unsigned char *p = buf;
    for (size_t i = 0; i < s->n; i++)
        if (s->e[i].type->state_size) {
            s->e[i].type->save(s->e[i].state, p);
            p += s->e[i].type->state_size(s->e[i].state);
        }
}

void eff_load(eff_set *s, const void *buf)
{
    const unsigned char *p = buf;
    for (size_t i = 0; i < s->n; i++)
        if (s->e[i].type->state_size) {
            s->e[i].type->load(s->e[i].state, p);
            p += s->e[i].type->state_size(s->e[i].state);
        }
}
