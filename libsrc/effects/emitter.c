/* emitter: inflow through a rectangle or disc (see emitter.h). */
#include "effects/emitter.h"
#include "core/sl_mem.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void normalise(double a[3])
{
    double n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; k++) a[k] /= n;
}

size_t emt_setup(emt_emitter *e, double r0)
{
    normalise(e->dir);
    /* u: the axis least aligned with dir, made perpendicular */
    double ref[3] = {fabs(e->dir[0]) < 0.9 ? 1.0 : 0.0, fabs(e->dir[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    double d = ref[0] * e->dir[0] + ref[1] * e->dir[1] + ref[2] * e->dir[2];
    for (int k = 0; k < 3; k++) e->u[k] = ref[k] - d * e->dir[k];
    normalise(e->u);
    e->v[0] = e->dir[1] * e->u[2] - e->dir[2] * e->u[1];
    e->v[1] = e->dir[2] * e->u[0] - e->dir[0] * e->u[2];
    e->v[2] = e->dir[0] * e->u[1] - e->dir[1] * e->u[0];
    double a = e->disc ? e->radius : 0.5 * e->size[0], b = e->disc ? e->radius : 0.5 * e->size[1];
    long na = (long)floor(a / r0 + 1e-9), nb = (long)floor(b / r0 + 1e-9);
    size_t cap = (size_t)(2 * na + 1) * (size_t)(2 * nb + 1);
    e->pu = sl_malloc(cap * sizeof *e->pu, "emitter lattice");
    e->pv = sl_malloc(cap * sizeof *e->pv, "emitter lattice");
    e->np = 0;
    /* points at (i + 1/2) r0 from the centre lines, inside the opening */
    for (long i = -na; i < na; i++)
        for (long j = -nb; j < nb; j++) {
            double pu = ((double)i + 0.5) * r0, pv = ((double)j + 0.5) * r0;
            if (e->disc && pu * pu + pv * pv > e->radius * e->radius * (1.0 + 1e-12))
                continue; /* lattice points whose centre lies in the disc */
            e->pu[e->np] = pu;
            e->pv[e->np] = pv;
            e->np++;
        }
    return e->np;
}

void emt_free(emt_emitter *e)
{
    free(e->pu);
    free(e->pv);
    e->pu = e->pv = NULL;
    e->np = 0;
}

size_t emt_emit(const emt_emitter *e, emt_state *st, double t, double dt, double r0, sl_fluid *f,
                uint32_t *next_id)
{
    if (t + dt <= e->t0 || t >= e->t1) return 0;
    size_t added = 0;
    st->travelled += e->speed * dt;
    while (st->travelled >= r0) {
        const double off = st->travelled - r0; /* how far the new layer has come */
        for (size_t q = 0; q < e->np; q++) {
            double p[3];
            for (int k = 0; k < 3; k++)
                p[k] = e->centre[k] + e->pu[q] * e->u[k] + e->pv[q] * e->v[k] + off * e->dir[k];
            prt_fluid_push(f, p[0], p[1], p[2], e->speed * e->dir[0], e->speed * e->dir[1],
                           e->speed * e->dir[2]);
            f->id[f->n - 1] = (*next_id)++;
            f->rho[f->n - 1] = e->rho0;
            added++;
        }
        st->travelled -= r0;
    }
    return added;
}

typedef struct emitters {
    const emt_emitter *e;
    size_t n;
    uint32_t next_id; /* saved: next_id, then st[0..n) */
    emt_state *st;
} emitters;

void *eff_emitter_new(const emt_emitter *e, size_t n, uint32_t next_id)
{
    if (n == 0) return NULL;
    emitters *m = sl_malloc(sizeof *m, "emitters");
    m->e = e;
    m->n = n;
    m->next_id = next_id;
    m->st = sl_malloc(n * sizeof *m->st, "emitter state");
    memset(m->st, 0, n * sizeof *m->st);
    return m;
}

static void apply(void *state, const eff_view *v)
{
    emitters *m = state;
    for (size_t k = 0; k < m->n; k++)
        emt_emit(&m->e[k], &m->st[k], v->t, v->dt, v->r0, v->f, &m->next_id);
}

static void release(void *state)
{
    emitters *m = state;
    if (!m) return;
    free(m->st);
    free(m);
}

static size_t state_size(const void *state)
{
    const emitters *m = state;
    return sizeof m->next_id + m->n * sizeof *m->st;
}

static void save(const void *state, void *buf)
{
    const emitters *m = state;
    memcpy(buf, &m->next_id, sizeof m->next_id);
    memcpy((unsigned char *)buf + sizeof m->next_id, m->st, m->n * sizeof *m->st);
}

static void load(void *state, const void *buf)
{
    emitters *m = state;
    memcpy(&m->next_id, buf, sizeof m->next_id);
    memcpy(m->st, (const unsigned char *)buf + sizeof m->next_id, m->n * sizeof *m->st);
}

const eff_type eff_emitter = {
    .name = "emitter",
    .stage = EFF_POST_STEP,
    .apply = apply,
    .free = release,
    .state_size = state_size,
    .save = save,
    .load = load,
};
