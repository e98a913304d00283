/* particle_shifting: Xu et al. 2009 / Lind et al. 2012 shifting (see particle_shifting.h). */
#include "effects/particle_shifting.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/sl_mem.h"
#include "kernel/kernel_correction.h"

/* The default D: the best of 0.005-0.5 on the Taylor-Green vortex
 * (doc/verification.md, "Particle shifting"). */
#define SHIFT_COEFFICIENT 0.1

/* The default of velocityCorrection: on, since it lowers the Taylor-Green
 * error at every level (0.0158, 0.0071, 0.0062 against 0.0198, 0.0101,
 * 0.0071 at r0 0.01, 0.005, 0.0025; doc/verification.md, "Particle
 * shifting"). */
#define SHIFT_VELOCITY_CORRECTION 1

typedef struct shift_state {
    double coefficient; /* D */
    int vcorr;          /* velocityCorrection: v_i += (dr_i . grad) v_i */
    char where[256];    /* file:line of the entry */
    double *d;          /* the shifts, 3 per fluid particle (and 3 velocity changes) */
    size_t cap;
} shift_state;

static const char *const keys[] = {"coefficient", "velocityCorrection", NULL};

static void *read(const dict *d, const eff_setup *su)
{
    (void)su;
    sl_err err;
    const dict *v = dict_sub(d, "particleShifting");
    if (!v)
        dict_fatal(d, "particleShifting",
                   "must be a dictionary { [coefficient 0.1;] [velocityCorrection on;] }");
    dict_warn_unknown(v, keys);
    shift_state *s = sl_calloc(1, sizeof *s, "particleShifting");
    dict_need(dict_get_scalar_or(v, "coefficient", SHIFT_COEFFICIENT, &s->coefficient, &err), &err);
    if (!(s->coefficient > 0.0 && s->coefficient <= 1.0))
        dict_fatal(v, "coefficient",
                   "must be D of the shift -D h^2 grad C per step, above 0 and at most 1 "
                   "(default %g; 0.2 and above damp the Taylor-Green vortex at r0 0.01)",
                   SHIFT_COEFFICIENT);
    dict_need(dict_get_bool_or(v, "velocityCorrection", SHIFT_VELOCITY_CORRECTION, &s->vcorr, &err),
              &err);
    const dict_entry *e = dict_lookup(d, "particleShifting");
    snprintf(s->where, sizeof s->where, "%s:%d", dict_entry_file(e), dict_entry_line(e));
    return s;
}

const char *eff_particle_shifting_where(const void *state)
{
    return ((const shift_state *)state)->where;
}

/* velocityCorrection off: the shifts alone, d[3 i + a] (the loop of the
 * shift before the correction, kept as it was: the same bits). */
static void shifts_plain(const eff_view *v, double c, double *restrict d)
{
    const sl_fluid *f = v->f;
    const sl_boundary *b = v->b;
    const size_t i0 = eff_rows_from(v), i1 = eff_rows_to(v);
    const krn_kernel k = v->k;
    const double vf = v->mass / v->rho0, irho0 = 1.0 / v->rho0;
    const nbr_list *ff = v->ff, *fb = v->fb;
#pragma omp parallel for schedule(dynamic, 1024)
    for (size_t i = i0; i < i1; i++) {
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
}

/* The shift of fluid particle i at x(t): d[0..2] = -D h^2 grad C_i and,
 * with velocityCorrection, d[3..5] = (d . grad) v_i with the corrected
 * gradient grad v_i = sum_j V_j (v_j - v_i) (L_i grad W_ij)^T (neighbours
 * in their lists' order: the same bits on any thread count). */
static inline void shift_corrected(const eff_view *v, size_t i, double c, double *restrict d)
{
    const sl_fluid *f = v->f;
    const sl_boundary *b = v->b;
    const krn_kernel k = v->k;
    const double vf = v->mass / v->rho0, irho0 = 1.0 / v->rho0;
    const nbr_list *ff = v->ff, *fb = v->fb;
    const double xi = f->x[i], yi = f->y[i], zi = f->z[i];
    const double ui[3] = {f->vx[i], f->vy[i], f->vz[i]};
    double g[3] = {0.0, 0.0, 0.0};
    double A[9] = {0}, G[9] = {0}; /* sum V grad W (x_j - x_i)^T, sum V (v_j - v_i) grad W^T */
    for (uint32_t q = ff->start[i]; q < ff->start[i + 1]; q++) {
        const uint32_t j = ff->idx[q];
        const double r[3] = {xi - f->x[j], yi - f->y[j], zi - f->z[j]};
        const double w = vf * krn_gradf(&k, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]));
        for (int a = 0; a < 3; a++) g[a] += w * r[a];
        const double du[3] = {f->vx[j] - ui[0], f->vy[j] - ui[1], f->vz[j] - ui[2]};
        krn_correction_add(A, w, r);
        for (int a = 0; a < 3; a++)
            for (int e = 0; e < 3; e++) G[3 * a + e] += w * du[a] * r[e];
    }
    for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
        const uint32_t j = fb->idx[q];
        const double r[3] = {xi - b->x[j], yi - b->y[j], zi - b->z[j]};
        const double w =
            b->mass[j] * irho0 * krn_gradf(&k, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]));
        for (int a = 0; a < 3; a++) g[a] += w * r[a];
        const double du[3] = {b->vx[j] - ui[0], b->vy[j] - ui[1], b->vz[j] - ui[2]};
        krn_correction_add(A, w, r);
        for (int a = 0; a < 3; a++)
            for (int e = 0; e < 3; e++) G[3 * a + e] += w * du[a] * r[e];
    }
    for (int a = 0; a < 3; a++) d[a] = c * g[a];
    double L[9];
    krn_correction_invert(A, L);
    /* grad v (row a: the gradient of v_a) = G L; d[3 + a] = (G L d)_a */
    double Ld[3];
    for (int e = 0; e < 3; e++) Ld[e] = L[3 * e] * d[0] + L[3 * e + 1] * d[1] + L[3 * e + 2] * d[2];
    for (int a = 0; a < 3; a++)
        d[3 + a] = G[3 * a] * Ld[0] + G[3 * a + 1] * Ld[1] + G[3 * a + 2] * Ld[2];
}

/* The shifts of every fluid particle at x(t) (under -parallel a rank's
 * own rows, its halo read as neighbours), then the positions moved (and,
 * with velocityCorrection, the velocities carried to them). */
static void apply(void *state, const eff_view *v)
{
    shift_state *s = state;
    sl_fluid *f = v->f;
    const size_t n = f->n, i0 = eff_rows_from(v), i1 = eff_rows_to(v);
    const int m = s->vcorr ? 6 : 3; /* doubles per particle */
    if (s->cap < n) {               /* grows with the fluid (emitters), not every step */
        free(s->d);
        s->cap = f->cap > n ? f->cap : n;
        s->d = sl_malloc(6 * s->cap * sizeof *s->d, "particle shifts");
    }
    const double c = -s->coefficient * v->h * v->h;
    double *restrict d = s->d;
    if (m == 6) {
#pragma omp parallel for schedule(dynamic, 1024)
        for (size_t i = i0; i < i1; i++) shift_corrected(v, i, c, d + 6 * i);
    } else shifts_plain(v, c, d);
#pragma omp parallel for schedule(static)
    for (size_t i = i0; i < i1; i++) {
        const double *di = d + (size_t)m * i;
        f->x[i] += di[0];
        f->y[i] += di[1];
        f->z[i] += di[2];
        if (m == 6) {
            f->vx[i] += di[3];
            f->vy[i] += di[4];
            f->vz[i] += di[5];
        }
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
