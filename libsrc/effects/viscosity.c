/* viscosity: Becker & Teschner 2007 artificial viscosity (see viscosity.h). */
#include "effects/viscosity.h"

#include <math.h>

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
