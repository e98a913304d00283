/* case_part: a rank's part of a case (see case_part.h). */
#include "case/case_part.h"
#include "case/case_restart.h"
#include "core/sl_log.h"
#include "parallel/par.h"

#include <stdlib.h>
#include <string.h>

static int keep_none(void *ctx, double x, double y, double z)
{
    (void)ctx, (void)x, (void)y, (void)z;
    return 0;
}

static int count_row(void *ctx, double x, double y, double z)
{
    pcd_plan_count(ctx, x, y, z);
    return 0;
}

static int keep_fluid(void *ctx, double x, double y, double z)
{
    return pcd_plan_fluid(ctx, x, y, z);
}

static int keep_boundary(void *ctx, double x, double y, double z)
{
    return pcd_plan_boundary(ctx, x, y, z);
}

int case_part_applies(const sl_case *c, int restarting)
{
    const char *e = getenv("SLUICE_PARALLEL_SETUP");
    if (e && *e && strcmp(e, "parts") && strcmp(e, "whole"))
        sl_fatal("SLUICE_PARALLEL_SETUP=%s: parts (the default: each rank builds its part of the "
                 "case) or whole (every rank builds the whole case, then keeps its part)",
                 e);
    if (e && !strcmp(e, "whole")) return 0;
    return pcd_plan_usable(&c->prm) && (restarting || !c->packing.relaxed);
}

void case_part_census(sl_case *c)
{
    prt_filter fluid = {keep_none, NULL, 0}, boundary = {keep_none, NULL, 0};
    case_build_prepare(c);
    case_build_particles(c, &fluid, &boundary, CASE_FLUID | CASE_BOUNDARY);
    c->part = 1;
    case_build_finish(c);
}

/* ---- a restart file's records, chunk by chunk ---- */

typedef struct scan_ctx {
    pcd_plan *plan;
    sl_fluid *f;        /* the own records into it, or */
    pcs_snapshot *snap; /* into it, or (both NULL) counted by row */
} scan_ctx;

static void scan_chunk(void *ctx, size_t n, const double *const a[8], const uint32_t *id)
{
    scan_ctx *k = ctx;
    for (size_t i = 0; i < n; i++) {
        const double x = a[0][i], y = a[1][i], z = a[2][i];
        if (!k->f && !k->snap) {
            pcd_plan_count(k->plan, x, y, z);
            continue;
        }
        if (!pcd_plan_fluid(k->plan, x, y, z)) continue;
        if (k->snap) {
            snap_push(k->snap, x, y, z, a[3][i], a[4][i], a[5][i], id[i]);
            if (a[6]) k->snap->p[k->snap->n - 1] = a[6][i], k->snap->rho[k->snap->n - 1] = a[7][i];
            continue;
        }
        prt_fluid_push(k->f, x, y, z, a[3][i], a[4][i], a[5][i]);
        k->f->id[k->f->n - 1] = id[i];
        if (a[6]) k->f->p[k->f->n - 1] = a[6][i], k->f->rho[k->f->n - 1] = a[7][i];
    }
}

static int scan_box(void *ctx, const double lo[3], const double hi[3])
{
    return pcd_plan_fluid_box(((scan_ctx *)ctx)->plan, lo, hi);
}

static int scan_want(void *ctx, double x, double y, double z)
{
    return pcd_plan_fluid(((scan_ctx *)ctx)->plan, x, y, z);
}

/* Snapshot k's records: counted by row (this rank's part of the records,
 * positions only: the ranks' counts are summed after), or the own ones
 * kept (the blocks that may hold one: their box, then their positions). */
static void scan(const char *dir, const pcs_snapshot *heads, int k, scan_ctx *ctx)
{
    sl_err err;
    rst_select count = {.positions = 1, .part = par_rank(), .parts = par_size()};
    rst_select keep = {.box = scan_box, .want = scan_want};
    const rst_select *sel = ctx->f || ctx->snap ? &keep : &count;
    if (rst_scan(dir, heads, k, sel, scan_chunk, ctx, &err))
        sl_fatal("%s: this time directory cannot be continued (listTimes -check marks the damaged "
                 "ones; remove it to restart from the one before, or set startFrom startTime)",
                 err.msg);
}

pcd_plan *case_part_build(sl_case *c, const char *restart, const pcs_snapshot *heads, int nsnaps,
                          pcs_snapshot *prev)
{
    const size_t nf = restart ? heads[0].n : c->nfluid, nb = c->nboundary;
    pcd_plan *pl = pcd_plan_new(&c->prm, &c->effects, c->lo, c->hi, nf, nb);
    scan_ctx sc = {.plan = pl};
    if (restart) {
        scan(restart, heads, 0, &sc);
        pcd_plan_count_sum(pl);
    } else {
        prt_filter rows = {count_row, pl, 0};
        case_build_particles(c, &rows, NULL, CASE_FLUID);
    }
    pcd_plan_cut(pl);
    prt_filter fluid = {keep_fluid, pl, 0}, boundary = {keep_boundary, pl, 0};
    case_build_particles(c, &fluid, &boundary,
                         restart ? CASE_BOUNDARY : CASE_FLUID | CASE_BOUNDARY);
    if (c->nboundary != nb || (!restart && c->nfluid != nf))
        sl_fatal("%s: the case made %zu fluid and %zu boundary particles, then %zu and %zu "
                 "(internal error: its generators must be deterministic)",
                 c->dir, nf, nb, c->nfluid, c->nboundary);
    if (restart) {
        sc.f = &c->fluid;
        scan(restart, heads, 0, &sc);
        if (prev && nsnaps > 1) {
            sc.f = NULL;
            sc.snap = prev;
            prev->n = 0;
            prev->time = heads[1].time;
            prev->dt = heads[1].dt;
            prev->step = heads[1].step;
            prev->carried = heads[1].carried;
            scan(restart, heads, 1, &sc);
        }
        rst_scan_end();
    }
    pcd_plan_built(pl);
    return pl;
}
