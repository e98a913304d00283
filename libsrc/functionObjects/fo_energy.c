/*
 * fo_energy: kinetic and potential energy of the fluid, in J:
 *     kinetic   = sum_i m v_i^2 / 2
 *     potential = -sum_i m g . (x_i - x_ref)      (m |g| z for g = (0 0 -g))
 * with x_ref = referencePoint, the origin by default, and m the fluid
 * particle mass rho0 r0^3.  The sums run over the particles in the
 * solver's order in blocks of 4096 rows, each block row by row, the block
 * sums in order (solver/pcs_sums.h): the same bits for any ranks x threads,
 * and -parallel's domain mode sums each rank's own rows without gathering
 * them.
 *
 *   type energy; referencePoint (0 0 0);  // optional
 */
#include "functionObjects/fo_type.h"

#include "core/sl_mem.h"
#include "solver/pcs_sums.h"

#include <stdlib.h>

static const char *const en_keys[] = {"referencePoint", NULL};

typedef struct en_state {
    double ref[3];
} en_state;

static void *en_read(const dict *d)
{
    static const double origin[3] = {0, 0, 0};
    en_state *st = sl_calloc(1, sizeof *st, "energy");
    sl_err err;
    fo_need(dict_get_vector_or(d, "referencePoint", origin, st->ref, &err), &err);
    return st;
}

static void en_header(const void *vs, const pcs_view *s, FILE *f)
{
    const en_state *st = vs;
    fprintf(f,
            "# Energy of the fluid in J: kinetic sum m v^2/2; potential -sum m g.(x - x_ref), "
            "g = (%g %g %g), x_ref = (%g %g %g); m = %.10g kg\n",
            s->gravity[0], s->gravity[1], s->gravity[2], st->ref[0], st->ref[1], st->ref[2],
            s->mass);
}

static void en_columns(const void *vs, FILE *f)
{
    (void)vs;
    fputs("\tkinetic\tpotential\ttotal", f);
}

/* A row's v^2 and g . (x - x_ref); ctx: g and x_ref, 6 doubles. */
static void en_terms(const void *ctx, const sl_fluid *f, size_t i, double *t)
{
    const double *g = ctx, *ref = g + 3;
    t[0] = f->vx[i] * f->vx[i] + f->vy[i] * f->vy[i] + f->vz[i] * f->vz[i];
    t[1] = g[0] * (f->x[i] - ref[0]) + g[1] * (f->y[i] - ref[1]) + g[2] * (f->z[i] - ref[2]);
}

static void en_execute(void *vs, const fo_call *call)
{
    const en_state *st = vs;
    const pcs_view *s = call->s;
    const double ctx[6] = {s->gravity[0], s->gravity[1], s->gravity[2],
                           st->ref[0],    st->ref[1],    st->ref[2]};
    double sum[2];
    pcs_view_sum_rows(s, 2, en_terms, ctx, sum); /* collective; on rank 0 */
    if (!call->dat) return;
    double kin = 0.5 * s->mass * sum[0], pot = -s->mass * sum[1];
    fo_put(call->dat, kin);
    fo_put(call->dat, pot);
    fo_put(call->dat, kin + pot);
}

static void en_free(void *vs) { free(vs); }

const fo_type fo_type_energy = {
    .name = "energy",
    .keys = en_keys,
    .needs = 0,
    .read = en_read,
    .header = en_header,
    .columns = en_columns,
    .execute = en_execute,
    .at_write = NULL,
    .free = en_free,
    .collective = 1,
};
