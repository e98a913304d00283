/* surface_tension: Becker & Teschner 2007 cohesion (see surface_tension.h). */
#include "effects/surface_tension.h"

#include <math.h>

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
