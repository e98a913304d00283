/* surface_tension: Becker & Teschner 2007 cohesion (see surface_tension.h). */
#include "effects/surface_tension.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"

void st_apply(double kappa, const krn_kernel *kp, sl_fluid *f, const nbr_list *ff)
{
    const krn_kernel k = *kp;
    const double *restrict x = f->x, *restrict y = f->y, *restrict z = f->z;
    const uint32_t *restrict st = ff->start, *restrict idx = ff->idx;
    double *restrict ax = f->ax, *restrict ay = f->ay, *restrict az = f->az;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < f->n; i++) {
        double sx = 0, sy = 0, sz = 0;
        for (uint32_t q = st[i]; q < st[i + 1]; q++) {
            const uint32_t j = idx[q];
            const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
            const double w = krn_w(&k, sqrt(dx * dx + dy * dy + dz * dz));
            sx += dx * w;
            sy += dy * w;
            sz += dz * w;
        }
        ax[i] -= kappa * sx; /* equal masses: m_j / m_i = 1 */
        ay[i] -= kappa * sy;
        az[i] -= kappa * sz;
    }
}

static const char *const keys[] = {"kappa", NULL};

static void *read(const dict *d, const eff_setup *su)
{
    sl_err err;
    double kappa;
    (void)su;
    const dict *st = dict_sub(d, "surfaceTension");
    if (!st) dict_fatal(d, "surfaceTension", "must be a dictionary { kappa ..; }");
    dict_warn_unknown(st, keys);
    dict_need(dict_get_scalar(st, "kappa", &kappa, &err), &err);
    if (!(kappa >= 0.0)) dict_fatal(st, "kappa", "must be zero or positive");
    if (!(kappa > 0.0)) return NULL;
    double *p = sl_malloc(sizeof *p, "surface tension");
    *p = kappa;
    return p;
}

static void apply(void *state, const eff_view *v)
{
    st_apply(*(const double *)state, &v->k, v->f, v->ff);
}

const eff_type eff_surface_tension = {
    .name = "surfaceTension",
    .keys = keys,
    .stage = EFF_FORCES,
    .read = read,
    .apply = apply,
    .free = free,
};
