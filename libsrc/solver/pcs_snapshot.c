/* pcs_snapshot: copies of the step state (see pcs_snapshot.h). */
#include "solver/pcs_snapshot.h"
#include "core/sl_mem.h"
#include "solver/pcs_domain.h"

#include <string.h>

void snap_init(pcs_snapshot *s) { memset(s, 0, sizeof *s); }

void snap_free(pcs_snapshot *s)
{
    double *a[8] = {s->x, s->y, s->z, s->vx, s->vy, s->vz, s->p, s->rho};
    for (int k = 0; k < 8; k++) sl_free_aligned(a[k]);
    sl_free_aligned(s->id);
    memset(s, 0, sizeof *s);
}

static void snap_reserve(pcs_snapshot *s, size_t n)
{
    if (n <= s->cap) return;
    snap_free(s);
    double **a[8] = {&s->x, &s->y, &s->z, &s->vx, &s->vy, &s->vz, &s->p, &s->rho};
    for (int k = 0; k < 8; k++) *a[k] = sl_alloc_aligned(n * sizeof(double), "state snapshot");
    s->id = sl_alloc_aligned(n * sizeof *s->id, "state snapshot");
    s->cap = n;
}

void snap_push(pcs_snapshot *s, double x, double y, double z, double vx, double vy, double vz,
               uint32_t id)
{
    if (s->n == s->cap) { /* grow, keeping the contents */
        pcs_snapshot g;
        snap_init(&g);
        snap_reserve(&g, s->cap ? 2 * s->cap : 1024);
        const double *from[8] = {s->x, s->y, s->z, s->vx, s->vy, s->vz, s->p, s->rho};
        double *to[8] = {g.x, g.y, g.z, g.vx, g.vy, g.vz, g.p, g.rho};
        for (int k = 0; k < 8 && s->n; k++) memcpy(to[k], from[k], s->n * sizeof(double));
        if (s->n) memcpy(g.id, s->id, s->n * sizeof *g.id);
        g.n = s->n, g.time = s->time, g.dt = s->dt, g.step = s->step, g.carried = s->carried;
        snap_free(s);
        *s = g;
    }
    const size_t i = s->n++;
    s->x[i] = x, s->y[i] = y, s->z[i] = z;
    s->vx[i] = vx, s->vy[i] = vy, s->vz[i] = vz;
    s->id[i] = id;
    s->p[i] = s->rho[i] = 0.0;
}

void snap_resize(pcs_snapshot *s, size_t n)
{
    snap_reserve(s, n);
    s->n = n;
}

void snap_take(pcs_snapshot *s, const sl_fluid *f, double time, double dt, long step)
{
    snap_reserve(s, f->cap);
    s->n = f->n;
    s->time = time;
    s->dt = dt;
    s->step = step;
    s->carried = 1;
    if (f->n == 0) return; /* nothing to copy (an emitter has not started yet) */
    const size_t bytes = f->n * sizeof(double);
    memcpy(s->x, f->x, bytes);
    memcpy(s->y, f->y, bytes);
    memcpy(s->z, f->z, bytes);
    memcpy(s->vx, f->vx, bytes);
    memcpy(s->vy, f->vy, bytes);
    memcpy(s->vz, f->vz, bytes);
    memcpy(s->p, f->p, bytes);
    memcpy(s->rho, f->rho, bytes);
    memcpy(s->id, f->id, f->n * sizeof *s->id);
}

void snap_restore(const pcs_snapshot *s, sl_fluid *f)
{
    prt_fluid_reserve(f, s->n);
    f->n = s->n;
    if (s->n == 0) return;
    const size_t bytes = s->n * sizeof(double);
    memcpy(f->x, s->x, bytes);
    memcpy(f->y, s->y, bytes);
    memcpy(f->z, s->z, bytes);
    memcpy(f->vx, s->vx, bytes);
    memcpy(f->vy, s->vy, bytes);
    memcpy(f->vz, s->vz, bytes);
    if (s->carried) {
        memcpy(f->p, s->p, bytes);
        memcpy(f->rho, s->rho, bytes);
    } else memset(f->p, 0, bytes);
    memcpy(f->id, s->id, s->n * sizeof *f->id);
}

int snap_equal(const pcs_snapshot *a, const pcs_snapshot *b)
{
    if (a->n != b->n || a->time != b->time || a->dt != b->dt || a->step != b->step ||
        a->carried != b->carried)
        return 0;
    if (a->n == 0) return 1;
    const size_t bytes = a->n * sizeof(double);
    return !memcmp(a->x, b->x, bytes) && !memcmp(a->y, b->y, bytes) && !memcmp(a->z, b->z, bytes) &&
        !memcmp(a->vx, b->vx, bytes) && !memcmp(a->vy, b->vy, bytes) &&
        !memcmp(a->vz, b->vz, bytes) && !memcmp(a->id, b->id, a->n * sizeof *a->id) &&
        (!a->carried || (!memcmp(a->p, b->p, bytes) && !memcmp(a->rho, b->rho, bytes)));
}

void pcs_own_snapshot(const pcs_solver *s, pcs_snapshot *snap)
{
    if (s->split.domain) pcd_localize_snapshot(s, snap);
}
