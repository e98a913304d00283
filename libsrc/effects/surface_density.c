/* surface_density: Bonet & Kulasegaram 2002 correction (see surface_density.h). */
#include "effects/surface_density.h"

#include <string.h>

#include "core/sl_log.h"
#include "kernel/sph_sums.h"

static void *read(const dict *d, const eff_setup *su)
{
    static int on_state = 1; /* the effect has no parameters */
    sl_err err;
    int on = 1;
    (void)su;
    if (!dict_sub(d, "surfaceDensityCorrection"))
        dict_need(dict_get_bool(d, "surfaceDensityCorrection", &on, &err), &err);
    if (on) { /* measured, not fixed: doc/verification.md */
        const dict_entry *e = dict_lookup(d, "surfaceDensityCorrection");
        sl_warning("%s:%d: keyword 'surfaceDensityCorrection': a free surface at rest does not "
                   "stay at rest with it (its corrected density takes the neighbours' "
                   "compression, and that pressure pushes the surface out: a 0.1 m deep tank at "
                   "rest rises by 2-7 cm within 0.2 s at r0 0.01 m); see doc/verification.md, "
                   "\"surfaceDensityCorrection and a free surface at rest\"",
                   dict_entry_file(e), dict_entry_line(e));
    }
    return on ? &on_state : NULL;
}

/* Before a density pass: keep the densities of the previous one (in the
 * fluid's scratch array, which is free outside the sort). */
static void apply(void *state, const eff_view *v)
{
    (void)state;
    const size_t n = v->f->n + v->f->nhalo; /* halo copies are neighbours too */
    if (n) memcpy(v->f->scratch, v->f->rho, n * sizeof *v->f->rho);
}

static void correct(const void *state, const eff_view *v, size_t i, double x, double y, double z,
                    double rb, double *r, double *rv)
{
    const double *restrict rho_prev = v->f->scratch;
    const nbr_list *ff = v->ff;
    (void)state;
    const double shf = v->mass *
        (krn_w(&v->k, 0.0) / rho_prev[i] +
         sph_sum_w_over(v->k, ff->idx, ff->start[i], ff->start[i + 1], x, y, z, v->px, v->py, v->pz,
                        rho_prev));
    const double shv = shf + rb / v->rho0;
    const double sh = v->wall_density ? shv : shf;
    if (sh < 1.0 && sh > 0.0) *r /= sh;
    if (shv < 1.0 && shv > 0.0) *rv /= shv;
}

const eff_type eff_surface_density = {
    .name = "surfaceDensityCorrection",
    .stage = EFF_DENSITY,
    .read = read,
    .apply = apply,
    .correct = correct,
};
