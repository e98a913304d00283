/* particles: growth and permutation of the SoA particle sets (see particles.h). */
#include "particles/particles.h"
#include "core/sl_mem.h"

#include <string.h>

#define FLUID_DOUBLES    18
#define BOUNDARY_DOUBLES 20

static void fluid_doubles(sl_fluid *f, double **a[FLUID_DOUBLES])
{
    double **list[FLUID_DOUBLES] = {&f->x,   &f->y,   &f->z,   &f->vx,  &f->vy, &f->vz,
                                    &f->xs,  &f->ys,  &f->zs,  &f->ax,  &f->ay, &f->az,
                                    &f->apx, &f->apy, &f->apz, &f->rho, &f->p,  &f->pt};
    memcpy(a, list, sizeof list);
}

static void grow_double(double **p, size_t n, size_t cap)
{
    double *q = sl_alloc_aligned(cap * sizeof *q, "particle field");
    if (*p && n) memcpy(q, *p, n * sizeof *q);
    sl_free_aligned(*p);
    *p = q;
}

static void grow_u32(uint32_t **p, size_t n, size_t cap)
{
    uint32_t *q = sl_alloc_aligned(cap * sizeof *q, "particle field");
    if (*p && n) memcpy(q, *p, n * sizeof *q);
    sl_free_aligned(*p);
    *p = q;
}

void prt_fluid_init(sl_fluid *f) { memset(f, 0, sizeof *f); }

void prt_fluid_reserve(sl_fluid *f, size_t cap)
{
    double **a[FLUID_DOUBLES];
    if (cap <= f->cap) return;
    fluid_doubles(f, a);
    for (int k = 0; k < FLUID_DOUBLES; k++) grow_double(a[k], f->n, cap);
    grow_u32(&f->id, f->n, cap);
    grow_u32(&f->cell, f->n, cap);
    grow_double(&f->scratch, 0, cap);
    grow_u32(&f->scratch_u, 0, cap);
    f->cap = cap;
}

void prt_fluid_free(sl_fluid *f)
{
    double **a[FLUID_DOUBLES];
    fluid_doubles(f, a);
    for (int k = 0; k < FLUID_DOUBLES; k++) sl_free_aligned(*a[k]);
    sl_free_aligned(f->id);
    sl_free_aligned(f->cell);
    sl_free_aligned(f->scratch);
    sl_free_aligned(f->scratch_u);
    memset(f, 0, sizeof *f);
}

/* The id of the next push (its index, or through a filter its creation
 * index); 0 when the filter drops it. */
static int next_id(prt_filter *flt, size_t n, double x, double y, double z, uint32_t *id)
{
    if (!flt) {
        *id = (uint32_t)n;
        return 1;
    }
    *id = (uint32_t)flt->made++;
    return flt->keep(flt->ctx, x, y, z);
}

void prt_fluid_push(sl_fluid *f, double x, double y, double z, double vx, double vy, double vz)
{
    uint32_t id;
    if (!next_id(f->filter, f->n, x, y, z, &id)) return;
    if (f->n == f->cap) prt_fluid_reserve(f, f->cap ? 2 * f->cap : 1024);
    size_t i = f->n++;
    f->x[i] = x;
    f->y[i] = y;
    f->z[i] = z;
    f->vx[i] = vx;
    f->vy[i] = vy;
    f->vz[i] = vz;
    f->xs[i] = x;
    f->ys[i] = y;
    f->zs[i] = z;
    f->ax[i] = f->ay[i] = f->az[i] = 0.0;
    f->apx[i] = f->apy[i] = f->apz[i] = 0.0;
    f->rho[i] = 0.0;
    f->p[i] = 0.0;
    f->pt[i] = 0.0;
    f->id[i] = id;
    f->cell[i] = 0;
}

static void permute_double(double *restrict a, double *restrict tmp, const uint32_t *restrict perm,
                           size_t n)
{
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) tmp[i] = a[perm[i]];
    if (n) memcpy(a, tmp, n * sizeof *a);
}

static void permute_u32(uint32_t *restrict a, uint32_t *restrict tmp, const uint32_t *restrict perm,
                        size_t n)
{
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) tmp[i] = a[perm[i]];
    if (n) memcpy(a, tmp, n * sizeof *a);
}

void prt_fluid_permute(sl_fluid *f, const uint32_t *perm)
{
    double **a[FLUID_DOUBLES];
    fluid_doubles(f, a);
    for (int k = 0; k < FLUID_DOUBLES; k++) permute_double(*a[k], f->scratch, perm, f->n);
    permute_u32(f->id, f->scratch_u, perm, f->n);
    permute_u32(f->cell, f->scratch_u, perm, f->n);
}

int prt_fluid_state_pairs(sl_fluid *f, double **state[PRT_STATE_PAIRS],
                          double **spare[PRT_STATE_PAIRS])
{
    double **st[PRT_STATE_PAIRS] = {&f->x, &f->y, &f->z, &f->vx, &f->vy, &f->vz, &f->rho, &f->p};
    double **sp[PRT_STATE_PAIRS] = {&f->xs, &f->ys, &f->zs,  &f->ax,
                                    &f->ay, &f->az, &f->apx, &f->apy};
    memcpy(state, st, sizeof st);
    memcpy(spare, sp, sizeof sp);
    return PRT_STATE_PAIRS;
}

/* ---- boundary ---- */

static void boundary_doubles(sl_boundary *b, double **a[BOUNDARY_DOUBLES])
{
    double **list[BOUNDARY_DOUBLES] = {
        &b->x,  &b->y,  &b->z,  &b->nx, &b->ny, &b->nz, &b->mass, &b->rho_static, &b->rho, &b->p,
        &b->pt, &b->vx, &b->vy, &b->vz, &b->x0, &b->y0, &b->z0,   &b->nx0,        &b->ny0, &b->nz0};
    memcpy(a, list, sizeof list);
}

void prt_boundary_init(sl_boundary *b) { memset(b, 0, sizeof *b); }

void prt_boundary_reserve(sl_boundary *b, size_t cap)
{
    double **a[BOUNDARY_DOUBLES];
    if (cap <= b->cap) return;
    boundary_doubles(b, a);
    for (int k = 0; k < BOUNDARY_DOUBLES; k++) grow_double(a[k], b->n, cap);
    grow_u32(&b->body, b->n, cap);
    grow_u32(&b->id, b->n, cap);
    b->cap = cap;
}

void prt_boundary_copy(sl_boundary *dst, const sl_boundary *src)
{
    prt_boundary_init(dst);
    prt_boundary_reserve(dst, src->n ? src->n : 1);
    double **a[BOUNDARY_DOUBLES], **from[BOUNDARY_DOUBLES];
    boundary_doubles(dst, a);
    boundary_doubles((sl_boundary *)src, from);
    for (int k = 0; k < BOUNDARY_DOUBLES; k++) memcpy(*a[k], *from[k], src->n * sizeof(double));
    memcpy(dst->body, src->body, src->n * sizeof *dst->body);
    memcpy(dst->id, src->id, src->n * sizeof *dst->id);
    dst->n = src->n;
    dst->nimages = src->nimages;
}

void prt_boundary_free(sl_boundary *b)
{
    double **a[BOUNDARY_DOUBLES];
    boundary_doubles(b, a);
    for (int k = 0; k < BOUNDARY_DOUBLES; k++) sl_free_aligned(*a[k]);
    sl_free_aligned(b->body);
    sl_free_aligned(b->id);
    sl_free_aligned(b->scratch);
    sl_free_aligned(b->scratch_u);
    memset(b, 0, sizeof *b);
}

void prt_boundary_push(sl_boundary *b, double x, double y, double z, double nx, double ny,
                       double nz, uint32_t body)
{
    uint32_t id;
    if (!next_id(b->filter, b->n, x, y, z, &id)) return;
    if (b->n == b->cap) prt_boundary_reserve(b, b->cap ? 2 * b->cap : 1024);
    size_t i = b->n++;
    b->x[i] = x;
    b->y[i] = y;
    b->z[i] = z;
    b->nx[i] = nx;
    b->ny[i] = ny;
    b->nz[i] = nz;
    b->mass[i] = 0.0;
    b->rho_static[i] = 0.0;
    b->rho[i] = 0.0;
    b->p[i] = 0.0;
    b->pt[i] = 0.0;
    b->vx[i] = b->vy[i] = b->vz[i] = 0.0;
    b->x0[i] = x;
    b->y0[i] = y;
    b->z0[i] = z;
    b->nx0[i] = nx;
    b->ny0[i] = ny;
    b->nz0[i] = nz;
    b->body[i] = body;
    b->id[i] = id;
}

void prt_boundary_permute(sl_boundary *b, const uint32_t *perm)
{
    double **a[BOUNDARY_DOUBLES];
    size_t n = b->n;
    if (b->scratch_cap < n) { /* once; moving bodies permute every step */
        sl_free_aligned(b->scratch);
        sl_free_aligned(b->scratch_u);
        b->scratch = sl_alloc_aligned(n * sizeof *b->scratch, "boundary permutation");
        b->scratch_u = sl_alloc_aligned(n * sizeof *b->scratch_u, "boundary permutation");
        b->scratch_cap = n;
    }
    boundary_doubles(b, a);
    for (int k = 0; k < BOUNDARY_DOUBLES; k++) permute_double(*a[k], b->scratch, perm, n);
    permute_u32(b->body, b->scratch_u, perm, n);
    permute_u32(b->id, b->scratch_u, perm, n);
}
