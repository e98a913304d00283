/*
 * fo_power: the power of the forces on the fluid over the step just taken,
 * in W, and the kinetic energy, in J:
 *     pressurePower = m sum_i a^p_i . v_i(t + dt)    (eq. 6's force)
 *     otherPower    = m sum_i a_i . v_i(t + dt)      (body forces, viscosity,
 *                                                     the effects' forces)
 *     kinetic       = m sum_i v_i^2 / 2
 * with v(t + dt) the velocity of Euler-Cromer's update before the world's
 * collision, m the fluid particle mass rho0 r0^3.  Over a step of dt the
 * kinetic energy changes by dt (pressurePower + otherPower) less
 * dt^2 m sum |a|^2 / 2 (Euler-Cromer's own loss), and by what collisions and
 * particleShifting's velocity correction change: with `writeInterval 1`
 * the sum of dt times each column is the work of each force, which shows
 * where the energy goes (the exact pressure of an incompressible flow does
 * no work).  The solver sums the powers (solver/pcisph.h, pcs_want_power)
 * in the density error's association, the same bits on any ranks x
 * threads.  Only a running solver has them: on written times (postProcess)
 * the power columns are nan, and so is the row of the initial state.
 *
 *   type power;
 */
#include "functionObjects/fo_type.h"

#include "solver/pcs_sums.h"

#include <math.h>

static const char *const pw_keys[] = {NULL};

static void *pw_read(const dict *d)
{
    (void)d;
    static int none;
    return &none;
}

static void pw_header(const void *vs, const pcs_view *s, FILE *f)
{
    (void)vs;
    fprintf(f,
            "# Power of the forces on the fluid over the step just taken, W: pressurePower m sum "
            "a^p . v(t + dt) (eq. 6), otherPower m sum a . v(t + dt) (body forces, viscosity, "
            "effects), v(t + dt) before the world's collision; kinetic m sum v^2/2, J; "
            "m = %.10g kg.  nan: no step taken (the initial state; postProcess on written times)\n",
            s->mass);
}

static void pw_columns(const void *vs, FILE *f)
{
    (void)vs;
    fputs("\tkinetic\tpressurePower\totherPower", f);
}

static void pw_terms(const void *ctx, const sl_fluid *f, size_t i, double *t)
{
    (void)ctx;
    t[0] = f->vx[i] * f->vx[i] + f->vy[i] * f->vy[i] + f->vz[i] * f->vz[i];
}

static void pw_execute(void *vs, const fo_call *call)
{
    (void)vs;
    const pcs_view *s = call->s;
    double sum[1];
    pcs_view_sum_rows(s, 1, pw_terms, NULL, sum); /* collective; on rank 0 */
    if (!call->dat) return;
    fo_put(call->dat, 0.5 * s->mass * sum[0]);
    fo_put(call->dat, s->power ? s->power[0] : (double)NAN);
    fo_put(call->dat, s->power ? s->power[1] : (double)NAN);
}

static void pw_free(void *vs) { (void)vs; }

const fo_type fo_type_power = {
    .name = "power",
    .keys = pw_keys,
    .needs = FO_NEED_POWER,
    .read = pw_read,
    .header = pw_header,
    .columns = pw_columns,
    .execute = pw_execute,
    .at_write = NULL,
    .free = pw_free,
    .collective = 1,
};
