/* particle_shifting: Xu et al. 2009 / Lind et al. 2012 shifting (see particle_shifting.h). */
#include "effects/particle_shifting.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/sl_mem.h"
#include "parallel/par.h"

/* The default D: the best of 0.005-0.5 on the Taylor-Green vortex
 * (doc/verification.md, "Particle shifting"). */
#define SHIFT_COEFFICIENT 0.1

typedef struct shift_state {
    double coefficient; /* D */
    char where[256];    /* file:line of the entry */
    double *d;          /* the shifts, 3 per fluid particle */
    size_t cap;
} shift_state;

static const char *const keys[] = {"coefficient", NULL};

static void *read(const dict *d, const eff_setup *su)
{
    (void)su;
    sl_err err;
    const dict *v = dict_sub(d, "particleShifting");
    if (!v) dict_fatal(d, "particleShifting", "must be a dictionary { [coefficient 0.1;] }");
    dict_warn_unknown(v, keys);
    shift_state *s = sl_calloc(1, sizeof *s, "particleShifting");
    dict_need(dict_get_scalar_or(v, "coefficient", SHIFT_COEFFICIENT, &s->coefficient, &err), &err);
    if (!(s->coefficient > 0.0 && s->coefficient <= 1.0))
        dict_fatal(v, "coefficient",
                   "must be D of the shift -D h^2 grad C per step, above 0 and at most 1 "
                   "(default %g; 0.2 and above damp the Taylor-Green vortex at r0 0.01)",
                   SHIFT_COEFFICIENT);
    if (par_size() > 1)
        dict_fatal(d, "particleShifting", "is not yet parallel: run without -parallel");
    const dict_entry *e = dict_lookup(d, "particleShifting");
    snprintf(s->where, sizeof s->where, "%s:%d", dict_entry_file(e), dict_entry_line(e));
    return s;
}

const char *eff_particle_shifting_where(const void *state)
{
    return ((const shift_state *)state)->where;
}

/* The shifts of every fluid particle at x(t) (neighbours in their lists'
 * order: the same bits on any thread count), then the positions moved. */
static void apply(void *state, const eff_view *v)
{
    shift_state *s = state;
    sl_fluid *f = v->f;
    const sl_boundary *b = v->b;
    const size_t n = f->n;
    if (s->cap < n) { /* grows with the fluid (emitters), not every step */
        free(s->d);
        s->cap = f->cap > n ? f->cap : n;
        s->d = sl_malloc(3 * s->cap * sizeof *s->d, "particle shifts");
    }
    const krn_kernel k = v->k;
    const double vf = v->mass / v->rho0, irho0 = 1.0 / v->rho0;
    const double c = -s->coefficient * v->h * v->h;
    const nbr_list *ff = v->ff, *fb = v->fb;
    double *restrict d = s->d;
#pragma omp parallel for schedule(dynamic, 1024)
    for (size_t i = 0; i < n; i++) {
        const double xi = f->x[i], yi = f->y[i], zi = f->z[i];
        double g[3] = {0.0, 0.0, 0.0};
        for (uint32_t q = ff->start[i]; q < ff->start[i + 1]; q++) {
            const uint32_t j = ff->idx[q];
            const double r[3] = {xi - f->x[j], yi - f->y[j], zi - f->z[j]};
            const double w = vf * krn_gradf(&k, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]));
            for (int a = 0; a < 3; a++) g[a] += w * r[a];
        }
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
            const uint32_t j = fb->idx[q];
            const double r[3] = {xi - b->x[j], yi - b->y[j], zi - b->z[j]};
            const double w =
                b->mass[j] * irho0 * krn_gradf(&k, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]));
            for (int a = 0; a < 3; a++) g[a] += w * r[a];
        }
        for (int a = 0; a < 3; a++) d[3 * i + a] = c * g[a];
    }
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        f->x[i] += d[3 * i];
        f->y[i] += d[3 * i + 1];
        f->z[i] += d[3 * i + 2];
    }
}

static void release(void *state)
{
    shift_state *s = state;
    free(s->d);
    free(s);
}

const eff_type eff_particle_shifting = {
    .name = "particleShifting",
    .keys = keys,
    .stage = EFF_SHIFT,
    .read = read,
    .apply = apply,
    .free = release,
};
