/* case_step: the first time step of a case (see case_step.h). */
#include "case/case_step.h"

#include <math.h>
#include <stdio.h>

#include "core/sl_log.h"
#include "parallel/par.h"

/* Height of the fluid's top above the lowest boundary particle, along g. */
static double fluid_height(const sl_case *c)
{
    const double *g = c->prm.gravity;
    double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), top = -INFINITY, low = INFINITY;
    if (gn == 0.0) return 0.0;
    for (size_t i = 0; i < c->fluid.n; i++) {
        double u = -(g[0] * c->fluid.x[i] + g[1] * c->fluid.y[i] + g[2] * c->fluid.z[i]) / gn;
        if (u > top) top = u;
        if (u < low) low = u;
    }
    for (size_t i = 0; i < c->boundary.n; i++) {
        double u =
            -(g[0] * c->boundary.x[i] + g[1] * c->boundary.y[i] + g[2] * c->boundary.z[i]) / gn;
        if (u < low) low = u;
    }
    if (c->part) { /* built in parts: every rank's (maxima, exact in any order) */
        top = par_max_double(top);
        low = par_min_double(low);
    }
    return top > low ? top - low : 0.0;
}

double case_initial_step(const sl_case *c, char *rule, size_t len)
{
    double v2 = 0.0;
    for (size_t i = 0; i < c->fluid.n; i++) {
        double a = c->fluid.vx[i] * c->fluid.vx[i] + c->fluid.vy[i] * c->fluid.vy[i] +
            c->fluid.vz[i] * c->fluid.vz[i];
        if (a > v2) v2 = a;
    }
    if (c->part) v2 = par_max_double(v2);
    for (size_t e = 0; e < c->nemitters; e++)
        if (c->emitters[e].speed * c->emitters[e].speed > v2)
            v2 = c->emitters[e].speed * c->emitters[e].speed;
    const double *g = c->prm.gravity;
    double dt =
        ts_initial(&c->ts, pcs_support(&c->prm), sqrt(v2),
                   sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), fluid_height(c), rule, len);
    if (c->ts.mode == TS_ADAPTIVE && !(c->ts.delta_t > 0.0)) {
        krn_kernel k;
        const double m = pcs_mass(&c->prm), H = fluid_height(c);
        const double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        pcs_kernel(&c->prm, &k);
        double dtp = ts_initial_pressure(c->prm.eta, c->ts.iterations,
                                         pcs_delta(&k, c->prm.r0, m, c->prm.rho0, 1.0), gn, H);
        if (dtp < dt && dtp >= c->ts.delta_t_min) {
            dt = dtp;
            snprintf(rule, len,
                     "hydrostatic pressure: a %g m column held with %d iterations at "
                     "an average compression of eta/2",
                     H, c->ts.iterations);
        }
    }
    if (!(dt > 0.0))
        sl_fatal("%s/system/timeStepDict: no initial time step can be estimated (fluid at rest, no "
                 "gravity): give deltaT",
                 c->dir);
    return dt;
}
