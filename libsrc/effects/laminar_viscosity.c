/* laminar_viscosity: Morris, Fox & Zhu 1997 viscosity (see laminar_viscosity.h). */
#include "effects/laminar_viscosity.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"
#include "kernel/sph_sums.h"

void lvisc_apply(const lvisc_params *p, const krn_kernel *k, double mass, double rho0, sl_fluid *f,
                 const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i0, size_t i1)
{
    const double c = 2.0 * p->nu / rho0, cb = 2.0 * p->nu_boundary / rho0;
    const double eps_h2 = 0.01 * k->h * k->h;
    const krn_kernel kk = *k;
#pragma omp parallel for schedule(dynamic, 512)
    for (size_t i = i0; i < i1; i++) {
        const double pi[3] = {f->x[i], f->y[i], f->z[i]}, vi[3] = {f->vx[i], f->vy[i], f->vz[i]};
        double a[3] = {0.0, 0.0, 0.0};
        sph_sum_laminar(kk, ff->idx, ff->start[i], ff->start[i + 1], pi, vi, f->x, f->y, f->z,
                        f->vx, f->vy, f->vz, NULL, eps_h2, mass * c, a);
        if (cb > 0.0)
            sph_sum_laminar(kk, fb->idx, fb->start[i], fb->start[i + 1], pi, vi, b->x, b->y, b->z,
                            b->vx, b->vy, b->vz, b->mass, eps_h2, cb, a);
        f->ax[i] += a[0];
        f->ay[i] += a[1];
        f->az[i] += a[2];
    }
}

static const char *const keys[] = {"nu", "boundaryNu", NULL};

static void *read(const dict *d, const eff_setup *su)
{
    (void)su;
    sl_err err;
    const dict *v = dict_sub(d, "laminarViscosity");
    if (!v) dict_fatal(d, "laminarViscosity", "must be a dictionary { nu ..; [boundaryNu ..;] }");
    dict_warn_unknown(v, keys);
    lvisc_params *p = sl_malloc(sizeof *p, "laminarViscosity");
    dict_need(dict_get_scalar(v, "nu", &p->nu, &err), &err);
    if (!(p->nu >= 0.0)) dict_fatal(v, "nu", "must be zero or positive");
    dict_need(dict_get_scalar_or(v, "boundaryNu", p->nu, &p->nu_boundary, &err), &err);
    if (!(p->nu_boundary >= 0.0)) dict_fatal(v, "boundaryNu", "must be zero or positive");
    return p;
}

static void apply(void *state, const eff_view *v)
{
    lvisc_apply(state, &v->k, v->mass, v->rho0, v->f, v->b, v->ff, v->fb, eff_rows_from(v),
                eff_rows_to(v));
}

const eff_type eff_laminar_viscosity = {
    .name = "laminarViscosity",
    .keys = keys,
    .stage = EFF_FORCES,
    .read = read,
    .apply = apply,
    .free = free,
};
