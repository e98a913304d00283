/* laminar_viscosity: Morris, Fox & Zhu 1997 viscosity (see laminar_viscosity.h). */
#include "effects/laminar_viscosity.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"
#include "kernel/sph_sums.h"

/* laminarViscosity normalized: particle i's second moment of the viscous
 * weights, tau_i = -1/3 sum_j V_j F_ij |r_ij|^2 (F = gradf r^2 / (r^2 +
 * eps), V_j = m_j / rho0, fluid and boundary neighbours in their lists'
 * order): the factor by which the sum misses nu Laplacian v on the packing
 * (0.9915 on the cubic lattice at h = 2 r0). */
static double second_moment(const krn_kernel *k, double vf, double irho0, const sl_fluid *f,
                            const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i,
                            double eps_h2)
{
    const double xi = f->x[i], yi = f->y[i], zi = f->z[i];
    double sf = 0.0, sb = 0.0;
    for (uint32_t q = ff->start[i]; q < ff->start[i + 1]; q++) {
        const uint32_t j = ff->idx[q];
        const double dx = xi - f->x[j], dy = yi - f->y[j], dz = zi - f->z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        sf += krn_gradf(k, sqrt(r2)) * r2 * r2 / (r2 + eps_h2);
    }
    for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
        const uint32_t j = fb->idx[q];
        const double dx = xi - b->x[j], dy = yi - b->y[j], dz = zi - b->z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        sb += b->mass[j] * krn_gradf(k, sqrt(r2)) * r2 * r2 / (r2 + eps_h2);
    }
    return -(vf * sf + irho0 * sb) / 3.0;
}

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
        if (p->normalized) { /* a deficient sum (tau <= 1/2) is left as it is */
            const double tau = second_moment(&kk, mass / rho0, 1.0 / rho0, f, b, ff, fb, i, eps_h2);
            if (tau > 0.5)
                for (int e = 0; e < 3; e++) a[e] /= tau;
        }
        f->ax[i] += a[0];
        f->ay[i] += a[1];
        f->az[i] += a[2];
    }
}

static const char *const keys[] = {"nu", "boundaryNu", "normalized", NULL};

static void *read(const dict *d, const eff_setup *su)
{
    (void)su;
    sl_err err;
    const dict *v = dict_sub(d, "laminarViscosity");
    if (!v)
        dict_fatal(d, "laminarViscosity",
                   "must be a dictionary { nu ..; [boundaryNu ..;] [normalized on;] }");
    dict_warn_unknown(v, keys);
    lvisc_params *p = sl_malloc(sizeof *p, "laminarViscosity");
    dict_need(dict_get_scalar(v, "nu", &p->nu, &err), &err);
    if (!(p->nu >= 0.0)) dict_fatal(v, "nu", "must be zero or positive");
    dict_need(dict_get_scalar_or(v, "boundaryNu", p->nu, &p->nu_boundary, &err), &err);
    if (!(p->nu_boundary >= 0.0)) dict_fatal(v, "boundaryNu", "must be zero or positive");
    dict_need(dict_get_bool_or(v, "normalized", 0, &p->normalized, &err), &err);
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
