/* pcs_relax: a relaxed initial packing before t = 0 (see pcs_relax.h). */
#include "solver/pcs_relax.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* splitmix64 (Steele, Lea & Flood 2014): a well-mixed 64-bit hash. */
static uint64_t mix64(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* A number in [-1, 1) from particle id and axis k. */
static double unit_of(uint32_t id, int k)
{
    const uint64_t h = mix64(3u * (uint64_t)id + (uint64_t)k);
    return (double)(h >> 11) * (2.0 / 9007199254740992.0) - 1.0; /* 53 bits */
}

void pcs_jitter(pcs_solver *s, double jitter)
{
    sl_fluid *f = s->f;
    const double a = jitter * s->prm.r0;
    for (size_t i = 0; i < f->n; i++) {
        f->x[i] += a * unit_of(f->id[i], 0);
        f->y[i] += a * unit_of(f->id[i], 1);
        f->z[i] += a * unit_of(f->id[i], 2);
    }
    if (s->prm.periodic.axes) dom_periodic_wrap(&s->prm.periodic, f->n, f->x, f->y, f->z);
}

static void zero_velocity(sl_fluid *f)
{
    memset(f->vx, 0, f->n * sizeof *f->vx);
    memset(f->vy, 0, f->n * sizeof *f->vy);
    memset(f->vz, 0, f->n * sizeof *f->vz);
}

/* FIRE's state (Bitzek et al. 2006, with a fixed step). */
typedef struct fire {
    double alpha;
    long positive; /* steps since the power was last negative */
} fire;

#define FIRE_ALPHA0  0.1  /* alpha_start */
#define FIRE_F_ALPHA 0.99 /* alpha's factor after each downhill step */
#define FIRE_N_MIN   5    /* downhill steps before alpha falls */

/* After a step: P = F . v over every particle (in index order: the same
 * sum on every thread count); downhill (P > 0) the velocity turned
 * towards the force, v = (1 - alpha) v + alpha |v| F / |F|; uphill it is
 * zeroed (the descent restarts from rest).  Returns 1 when zeroed. */
static int fire_mix(fire *fr, sl_fluid *f)
{
    double pw = 0.0, v2 = 0.0, f2 = 0.0;
    for (size_t i = 0; i < f->n; i++) {
        const double ax = f->ax[i] + f->apx[i], ay = f->ay[i] + f->apy[i],
                     az = f->az[i] + f->apz[i];
        pw += ax * f->vx[i] + ay * f->vy[i] + az * f->vz[i];
        v2 += f->vx[i] * f->vx[i] + f->vy[i] * f->vy[i] + f->vz[i] * f->vz[i];
        f2 += ax * ax + ay * ay + az * az;
    }
    if (!(pw > 0.0) || !(f2 > 0.0)) {
        zero_velocity(f);
        fr->alpha = FIRE_ALPHA0;
        fr->positive = 0;
        return 1;
    }
    const double a = fr->alpha, c = a * sqrt(v2 / f2);
    for (size_t i = 0; i < f->n; i++) {
        f->vx[i] = (1.0 - a) * f->vx[i] + c * (f->ax[i] + f->apx[i]);
        f->vy[i] = (1.0 - a) * f->vy[i] + c * (f->ay[i] + f->apy[i]);
        f->vz[i] = (1.0 - a) * f->vz[i] + c * (f->az[i] + f->apz[i]);
    }
    if (++fr->positive > FIRE_N_MIN) fr->alpha *= FIRE_F_ALPHA;
    return 0;
}

void pcs_relax(pcs_solver *s, long steps, double tolerance, double jitter, long every,
               pcs_relax_stats *out)
{
    sl_boundary *b = s->b;
    const double t0 = omp_get_wtime();
    if (s->split.domain || s->split.size > 1)
        sl_fatal("pcs_relax: a solver of the whole case is needed (pcs_params.one_rank): "
                 "the relaxation runs before the ranks split the case");
    memset(out, 0, sizeof *out);
    const size_t nb = b->n;
    double *bv = sl_malloc(3 * (nb ? nb : 1) * sizeof *bv, "wall velocities");
    memcpy(bv, b->vx, nb * sizeof *bv);
    memcpy(bv + nb, b->vy, nb * sizeof *bv);
    memcpy(bv + 2 * nb, b->vz, nb * sizeof *bv);
    memset(b->vx, 0, nb * sizeof *bv);
    memset(b->vy, 0, nb * sizeof *bv);
    memset(b->vz, 0, nb * sizeof *bv);
    pcs_jitter(s, jitter);
    zero_velocity(s->f);
    fire fr = {FIRE_ALPHA0, 0};
    long restarts = 0, below = 0, k;
    for (k = 0; k < steps; k++) {
        pcs_stats st;
        pcs_step_in_place(s, &st);
        /* the step's largest displacement, dt |v(t + dt)| */
        const double move = st.vmax * s->dt / s->prm.r0;
        restarts += fire_mix(&fr, s->f);
        if (k == 0) out->move_first = move;
        out->move_last = move;
        out->move_max = fmax(out->move_max, move);
        out->err_avg = st.err_avg;
        out->err_max = st.err_max;
        below = move < tolerance ? below + 1 : 0;
        const int done = tolerance > 0.0 && below >= PCS_RELAX_WINDOW;
        if (k == 0 || k == steps - 1 || done || (every > 0 && (k + 1) % every == 0))
            sl_info("Relaxation step %ld of %ld: largest displacement %.3g r0, rho_err avg %.3f%% "
                    "max %.3f%%, iter %d, %ld restarts from rest",
                    k + 1, steps, move, 100 * st.err_avg, 100 * st.err_max, st.iterations,
                    restarts);
        if (done) {
            out->converged = 1;
            k++;
            break;
        }
    }
    zero_velocity(s->f);
    memcpy(b->vx, bv, nb * sizeof *bv);
    memcpy(b->vy, bv + nb, nb * sizeof *bv);
    memcpy(b->vz, bv + 2 * nb, nb * sizeof *bv);
    free(bv);
    out->steps = k;
    out->restarts = restarts;
    out->wall = omp_get_wtime() - t0;
}
