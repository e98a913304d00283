/* viscosity: Becker & Teschner 2007 artificial viscosity (see viscosity.h). */
#include "effects/viscosity.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"

/* Pi_ij-weighted pair term; zero for separating pairs. */
static inline double visc_pair(double vx, double vy, double vz, double dx, double dy, double dz,
                               double eps_h2)
{
    double vr = vx * dx + vy * dy + vz * dz;
    double r2 = dx * dx + dy * dy + dz * dz;
    return vr < 0.0 ? vr / (r2 + eps_h2) : 0.0;
}

void visc_apply(const visc_params *p, const krn_kernel *k, double mass, double rho0,
                sl_fluid *f, const sl_boundary *b, const nbr_list *ff, const nbr_list *fb)
{
    const double nu = p->coef / rho0;
    const double nub = p->coef_boundary / rho0;
    const double eps_h2 = 0.01 * k->h * k->h;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < f->n; i++) {
        double ax = 0, ay = 0, az = 0;
        for (uint32_t q = ff->start[i]; q < ff->start[i + 1]; q++) {
            uint32_t j = ff->idx[q];
            double dx = f->x[i] - f->x[j], dy = f->y[i] - f->y[j], dz = f->z[i] - f->z[j];
            double pr = visc_pair(f->vx[i] - f->vx[j], f->vy[i] - f->vy[j], f->vz[i] - f->vz[j],
                                  dx, dy, dz, eps_h2);
            double c = mass * nu * pr * krn_gradf(k, sqrt(dx * dx + dy * dy + dz * dz));
            ax += c * dx; /* -m Pi grad W with Pi = -nu pr */
            ay += c * dy;
            az += c * dz;
        }
        if (nub > 0.0)
            for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
                uint32_t j = fb->idx[q];
                double dx = f->x[i] - b->x[j], dy = f->y[i] - b->y[j], dz = f->z[i] - b->z[j];
                double pr = visc_pair(f->vx[i] - b->vx[j], f->vy[i] - b->vy[j], f->vz[i] - b->vz[j],
                                      dx, dy, dz, eps_h2);
                double c = b->mass[j] * nub * pr * krn_gradf(k, sqrt(dx * dx + dy * dy + dz * dz));
                ax += c * dx;
                ay += c * dy;
                az += c * dz;
            }
        f->ax[i] += ax;
        f->ay[i] += ay;
        f->az[i] += az;
    }
}

static const char *const keys[] = {"alpha", "boundaryAlpha", "soundSpeed", "nu", "boundaryNu",
                                   NULL};

static void *read(const dict *d, const eff_setup *su)
{
    sl_err err;
    const dict *v = dict_sub(d, "viscosity");
    if (!v) dict_fatal(d, "viscosity", "must be a dictionary { alpha ..; soundSpeed ..; } or { nu ..; }");
    dict_warn_unknown(v, keys);
    visc_params *p = sl_malloc(sizeof *p, "viscosity");
    if (dict_has(v, "nu")) {
        double nu, nub;
        dict_need(dict_get_scalar(v, "nu", &nu, &err), &err);
        if (!(nu >= 0.0)) dict_fatal(v, "nu", "must be zero or positive");
        dict_need(dict_get_scalar_or(v, "boundaryNu", 0.0, &nub, &err), &err);
        if (!(nub >= 0.0)) dict_fatal(v, "boundaryNu", "must be zero or positive");
        p->coef = 10.0 * nu;
        p->coef_boundary = 10.0 * nub;
        return p;
    }
    double alpha, alphab, cs;
    dict_need(dict_get_scalar(v, "alpha", &alpha, &err), &err);
    if (!(alpha >= 0.0 && alpha <= 10.0)) dict_fatal(v, "alpha", "must be in [0, 10]");
    dict_need(dict_get_scalar_or(v, "boundaryAlpha", 0.0, &alphab, &err), &err);
    if (!(alphab >= 0.0 && alphab <= 10.0)) dict_fatal(v, "boundaryAlpha", "must be in [0, 10]");
    dict_need(dict_get_scalar(v, "soundSpeed", &cs, &err), &err);
    dict_need_positive(v, "soundSpeed", cs);
    p->coef = alpha * su->h * cs;
    p->coef_boundary = alphab * su->h * cs;
    return p;
}

static void apply(void *state, const eff_view *v)
{
    visc_apply(state, &v->k, v->mass, v->rho0, v->f, v->b, v->ff, v->fb);
}

const eff_type eff_viscosity = {
    .name = "viscosity",
    .keys = keys,
    .stage = EFF_FORCES,
    .read = read,
    .apply = apply,
    .free = free,
};
