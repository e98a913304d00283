/* viscosity: Becker & Teschner 2007 artificial viscosity (see viscosity.h). */
#include "effects/viscosity.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"
#include "kernel/sph_sums.h"

void visc_apply(const visc_params *p, const krn_kernel *k, double mass, double rho0, sl_fluid *f,
                const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i0, size_t i1)
{
    const double nu = p->coef / rho0;
    const double nub = p->coef_boundary / rho0;
    const double eps_h2 = 0.01 * k->h * k->h;
    const krn_kernel kk = *k;
    /* -m Pi grad W with Pi = -nu pr: + m nu pr gradf x_ij */
#pragma omp parallel for schedule(dynamic, 512)
    for (size_t i = i0; i < i1; i++) {
        const double pi[3] = {f->x[i], f->y[i], f->z[i]}, vi[3] = {f->vx[i], f->vy[i], f->vz[i]};
        double a[3] = {0.0, 0.0, 0.0};
        sph_sum_viscosity(kk, ff->idx, ff->start[i], ff->start[i + 1], pi, vi, f->x, f->y, f->z,
                          f->vx, f->vy, f->vz, NULL, eps_h2, mass * nu, a);
        if (nub > 0.0)
            sph_sum_viscosity(kk, fb->idx, fb->start[i], fb->start[i + 1], pi, vi, b->x, b->y, b->z,
                              b->vx, b->vy, b->vz, b->mass, eps_h2, nub, a);
        f->ax[i] += a[0];
        f->ay[i] += a[1];
        f->az[i] += a[2];
    }
}

static const char *const keys[] = {"alpha", "boundaryAlpha", "soundSpeed",
                                   "nu",    "boundaryNu",    NULL};

static void *read(const dict *d, const eff_setup *su)
{
    sl_err err;
    const dict *v = dict_sub(d, "viscosity");
    if (!v)
        dict_fatal(d, "viscosity",
                   "must be a dictionary { alpha ..; soundSpeed ..; } or { nu ..; }");
    dict_warn_unknown(v, keys);
    visc_params q; /* read and checked before it is allocated: a refusal leaks nothing */
    if (dict_has(v, "nu")) {
        double nu, nub;
        dict_need(dict_get_scalar(v, "nu", &nu, &err), &err);
        if (!(nu >= 0.0)) dict_fatal(v, "nu", "must be zero or positive");
        dict_need(dict_get_scalar_or(v, "boundaryNu", 0.0, &nub, &err), &err);
        if (!(nub >= 0.0)) dict_fatal(v, "boundaryNu", "must be zero or positive");
        q.coef = 10.0 * nu;
        q.coef_boundary = 10.0 * nub;
    } else {
        double alpha, alphab, cs;
        dict_need(dict_get_scalar(v, "alpha", &alpha, &err), &err);
        if (!(alpha >= 0.0 && alpha <= 10.0)) dict_fatal(v, "alpha", "must be in [0, 10]");
        dict_need(dict_get_scalar_or(v, "boundaryAlpha", 0.0, &alphab, &err), &err);
        if (!(alphab >= 0.0 && alphab <= 10.0))
            dict_fatal(v, "boundaryAlpha", "must be in [0, 10]");
        dict_need(dict_get_scalar(v, "soundSpeed", &cs, &err), &err);
        dict_need_positive(v, "soundSpeed", cs);
        q.coef = alpha * su->h * cs;
        q.coef_boundary = alphab * su->h * cs;
    }
    visc_params *p = sl_malloc(sizeof *p, "viscosity");
    *p = q;
    return p;
}

static void apply(void *state, const eff_view *v)
{
    visc_apply(state, &v->k, v->mass, v->rho0, v->f, v->b, v->ff, v->fb, eff_rows_from(v),
               eff_rows_to(v));
}

const eff_type eff_viscosity = {
    .name = "viscosity",
    .keys = keys,
    .stage = EFF_FORCES,
    .read = read,
    .apply = apply,
    .free = free,
};
