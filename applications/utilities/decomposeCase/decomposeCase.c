/*
 * decomposeCase: how a case's initial fluid would be shared out over N
 * ranks, and what each rank would have to exchange (issue 17,
 * doc/parallel.md).  Not a step a run needs: `mpirun -np N pcisph
 * -parallel` decomposes by itself.
 *
 *   decomposeCase [-case <dir>] -np <N> [-unit row|block|block:N[,...]]
 *
 * Four partitions of the fluid at the start time, by particle count:
 *   domain runs of the grid's units (whole x-rows of cells in Morton order
 *          of (y, z), or blocks of cells along a Hilbert curve: -unit,
 *          SLUICE_GRID_UNIT, neighbours.h) cut by count: what pcisph
 *          -parallel's domain mode owns per rank (phase 2,
 *          solver/pcs_domain.h); it also prints the particles a rank
 *          stores there (own + the halo, the cells within one cell of its
 *          own, two with surface tension); -unit row,block prints a line
 *          and the storage for each;
 *   rows   contiguous ranges of the cell-sorted rows: what the halo and
 *          gather modes compute per rank (phase 1, replicated state);
 *   slabs  slabs along the longest axis of the fluid's bounding box;
 *   rcb    recursive coordinate bisection (each cut across the longest
 *          axis of its part, at the count that gives each side its share
 *          of ranks).
 * For each: particles per rank (min, max, max/mean), and the halo a rank
 * would need under a domain decomposition: the particles of other ranks
 * within h of its own (fluid; the boundary particles within h of its
 * fluid), the ranks they belong to, and the bytes an iteration would
 * exchange (x* and p/rho^2: 4 doubles per halo particle) against the
 * replicated phase's gathers (7 doubles per row of every other rank).
 * Writes <case>/postProcessing/decomposeCase/fluid.vtu (point data
 * domainRank, rowsRank, slabsRank, rcbRank) for ParaView.
 */
#include "app/app.h"
#include "case/case.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "io/time_dir.h"
#include "io/vtk_writer.h"
#include "solver/pcisph.h"
#include "solver/pcs_domain.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bytes per stored particle of the particle arrays (particles.h); the
 * neighbour lists and the grid's cells come on top (the End summary of a
 * run reports them with the arrays, and the resident memory). */
#define FLUID_BYTES    PRT_FLUID_BYTES
#define BOUNDARY_BYTES PRT_BOUNDARY_BYTES

static const app_option options[] = {APP_CASE,
                                     {.name = "np",
                                      .kind = APP_INT,
                                      .arg = "<N>",
                                      .help = "the number of ranks",
                                      .def = "2",
                                      .min = 1,
                                      .max = 65536},
                                     {.name = "unit",
                                      .kind = APP_STRING,
                                      .arg = "<units>",
                                      .help = "the grid's units for the domain partition, as "
                                              "SLUICE_GRID_UNIT: row, block or block:N; a "
                                              "comma-separated list compares them (row,block)",
                                      .def = "SLUICE_GRID_UNIT, else row"},
                                     APP_END};

static const app_info info = {
    .name = "decomposeCase",
    .what = "Prints how the case's fluid at the start would be shared out over N ranks\n"
            "(the rows pcisph -parallel computes per rank, slabs along the longest axis,\n"
            "recursive coordinate bisection), with particles per rank and the halo each\n"
            "rank would exchange; writes postProcessing/decomposeCase/fluid.vtu (the rank\n"
            "of each particle for each partition) for ParaView.  mpirun -np N pcisph\n"
            "-parallel needs no decomposition step.",
    .options = options};

/* ---- partitions ---- */

static const double *key_; /* the coordinate qsort compares */

static int by_key(const void *a, const void *b)
{
    const uint32_t i = *(const uint32_t *)a, j = *(const uint32_t *)b;
    if (key_[i] != key_[j]) return key_[i] < key_[j] ? -1 : 1;
    return i < j ? -1 : (i > j); /* ties by index: the same cut every run */
}

/* The axis of the largest extent of particles idx[0..n). */
static int longest_axis(const sl_fluid *f, const uint32_t *idx, size_t n)
{
    const double *c[3] = {f->x, f->y, f->z};
    double best = -1;
    int axis = 0;
    for (int d = 0; d < 3; d++) {
        double lo = INFINITY, hi = -INFINITY;
        for (size_t k = 0; k < n; k++) {
            lo = fmin(lo, c[d][idx[k]]);
            hi = fmax(hi, c[d][idx[k]]);
        }
        if (n && hi - lo > best) {
            best = hi - lo;
            axis = d;
        }
    }
    return axis;
}

static void sort_along(const sl_fluid *f, uint32_t *idx, size_t n, int axis)
{
    const double *c[3] = {f->x, f->y, f->z};
    key_ = c[axis];
    qsort(idx, n, sizeof *idx, by_key);
}

/* Ranks [r0, r0 + p) for particles idx[0..n): cut across the longest
 * axis at the count of the first half's share of ranks. */
static void rcb(const sl_fluid *f, uint32_t *idx, size_t n, int r0, int p, int *rank)
{
    if (p == 1) {
        for (size_t k = 0; k < n; k++) rank[idx[k]] = r0;
        return;
    }
    const int pl = p / 2;
    sort_along(f, idx, n, longest_axis(f, idx, n));
    const size_t nl = (size_t)((double)n * pl / p + 0.5);
    rcb(f, idx, nl, r0, pl, rank);
    rcb(f, idx + nl, n - nl, r0 + pl, p - pl, rank);
}

static void slabs(const sl_fluid *f, uint32_t *idx, size_t n, int p, int *rank)
{
    sort_along(f, idx, n, longest_axis(f, idx, n));
    for (int r = 0; r < p; r++)
        for (size_t k = n * (size_t)r / (size_t)p; k < n * (size_t)(r + 1) / (size_t)p; k++)
            rank[idx[k]] = r;
}

static void rows(size_t n, int p, int *rank)
{
    for (int r = 0; r < p; r++)
        for (size_t i = n * (size_t)r / (size_t)p; i < n * (size_t)(r + 1) / (size_t)p; i++)
            rank[i] = r;
}

/* ---- what a partition costs ---- */

typedef struct part_stats {
    size_t own_min, own_max;
    double own_mean;
    size_t halo_min, halo_max, bhalo_max;
    double halo_mean;
    int nbr_max; /* ranks a rank would exchange with */
    double nbr_mean;
} part_stats;

/* The original of list entry j (periodic images map to theirs). */
static inline uint32_t original(const pcs_solver *s, uint32_t j)
{
    return j < s->f->n ? j : s->halo.src[j - s->f->n];
}

/* The domain mode's overlap: the own particles whose lists hold another
 * rank's fluid particle or a boundary particle of another rank's cells
 * (the border rows, computed after the halo arrives); the others are
 * computed while it travels.  Printed per rank, as shares of its own. */
static void border_rows(const pcs_solver *s, const int *rank, const int *brank, int p)
{
    size_t *own = calloc((size_t)p, sizeof *own), *bord = calloc((size_t)p, sizeof *bord);
    if (!own || !bord) sl_fatal("out of memory");
    for (size_t i = 0; i < s->f->n; i++) {
        const int r = rank[i];
        int in = 1;
        for (uint32_t q = s->ff.start[i]; in && q < s->ff.start[i + 1]; q++)
            in = rank[original(s, s->ff.idx[q])] == r;
        for (uint32_t q = s->fb.start[i]; in && q < s->fb.start[i + 1]; q++)
            in = brank[s->fb.idx[q]] == r;
        own[r]++;
        bord[r] += !in;
    }
    double lo = HUGE_VAL, hi = 0.0, sum = 0.0;
    for (int r = 0; r < p; r++) {
        const double f = own[r] ? (double)bord[r] / (double)own[r] : 0.0;
        lo = f < lo ? f : lo;
        hi = f > hi ? f : hi;
        sum += (double)bord[r];
    }
    printf("overlap: own particles reading a halo value (border rows, computed after the halo\n"
           "arrives) per rank %.0f-%.0f %% of its own (all ranks: %.0f %%); the rest computed "
           "while it travels\n",
           100 * lo, 100 * hi, s->f->n ? 100 * sum / (double)s->f->n : 0.0);
    free(own);
    free(bord);
}

static part_stats measure(const pcs_solver *s, const int *rank, int p)
{
    const size_t n = s->f->n, nb = s->b->n;
    part_stats st = {.own_min = n, .halo_min = (size_t)-1};
    size_t *own = calloc((size_t)p, sizeof *own), *first = calloc((size_t)p + 1, sizeof *first);
    uint32_t *order = malloc((n + 1) * sizeof *order);
    int *stamp = malloc((n + 1) * sizeof *stamp), *bstamp = malloc((nb + 1) * sizeof *bstamp);
    int *rstamp = malloc(((size_t)p + 1) * sizeof *rstamp);
    if (!own || !first || !order || !stamp || !bstamp || !rstamp) sl_fatal("out of memory");
    for (size_t i = 0; i < n; i++) own[rank[i]]++;
    for (int r = 0; r < p; r++) first[r + 1] = first[r] + own[r];
    for (size_t i = 0; i < n; i++) order[first[rank[i] + 1] - own[rank[i]]--] = (uint32_t)i;
    for (int r = 0; r < p; r++) own[r] = first[r + 1] - first[r];
    for (size_t i = 0; i < n; i++) stamp[i] = -1;
    for (size_t i = 0; i < nb; i++) bstamp[i] = -1;
    for (int r = 0; r < p; r++) rstamp[r] = -1;
    double halo_sum = 0, nbr_sum = 0;
    for (int r = 0; r < p; r++) {
        size_t halo = 0, bhalo = 0;
        int nbrs = 0;
        for (size_t k = first[r]; k < first[r + 1]; k++) {
            const uint32_t i = order[k];
            for (uint32_t q = s->ff.start[i]; q < s->ff.start[i + 1]; q++) {
                const uint32_t j = original(s, s->ff.idx[q]);
                if (rank[j] == r || stamp[j] == r) continue;
                stamp[j] = r;
                halo++;
                if (rstamp[rank[j]] != r) {
                    rstamp[rank[j]] = r;
                    nbrs++;
                }
            }
            for (uint32_t q = s->fb.start[i]; q < s->fb.start[i + 1]; q++) {
                const uint32_t j = s->fb.idx[q];
                if (bstamp[j] != r) {
                    bstamp[j] = r;
                    bhalo++;
                }
            }
        }
        st.own_min = own[r] < st.own_min ? own[r] : st.own_min;
        st.own_max = own[r] > st.own_max ? own[r] : st.own_max;
        st.halo_min = halo < st.halo_min ? halo : st.halo_min;
        st.halo_max = halo > st.halo_max ? halo : st.halo_max;
        st.bhalo_max = bhalo > st.bhalo_max ? bhalo : st.bhalo_max;
        st.nbr_max = nbrs > st.nbr_max ? nbrs : st.nbr_max;
        halo_sum += (double)halo;
        nbr_sum += nbrs;
    }
    st.own_mean = (double)n / p;
    st.halo_mean = halo_sum / p;
    st.nbr_mean = nbr_sum / p;
    free(own);
    free(first);
    free(order);
    free(stamp);
    free(bstamp);
    free(rstamp);
    return st;
}

static void report(const char *name, const part_stats *st, size_t n, int p)
{
    /* per PCISPH iteration and rank: a halo exchange sends x* (3 doubles)
     * after the prediction and p/rho^2 (1) after the density pass; the
     * replicated phase receives rho, p, p/rho^2, error and the 3 force
     * components of every row it does not compute */
    const double halo_bytes = 4.0 * 8.0 * (double)st->halo_max;
    const double gather_bytes = 7.0 * 8.0 * (double)(n - st->own_min);
    printf("%-14s %9zu %9zu %6.3f  %9zu %9zu %10.0f %6.1f%%  %9zu  %4d %6.1f  %10.3g %10.3g\n",
           name, st->own_min, st->own_max,
           st->own_mean > 0 ? (double)st->own_max / st->own_mean : 0.0, st->halo_min, st->halo_max,
           st->halo_mean, st->own_mean > 0 ? 100 * st->halo_mean / st->own_mean : 0.0,
           st->bhalo_max, st->nbr_max, st->nbr_mean, halo_bytes, p > 1 ? gather_bytes : 0.0);
}

static void write_vtu(const sl_case *c, const pcs_solver *s, const int *r_dom, const int *r_rows,
                      const int *r_slabs, const int *r_rcb)
{
    sl_err err;
    char dir[4096], path[4200];
    snprintf(dir, sizeof dir, "%s/postProcessing/decomposeCase", c->dir);
    if (tdir_mkdirs(dir, &err)) sl_fatal("%s", err.msg);
    snprintf(path, sizeof path, "%s/fluid.vtu", dir);
    vtk_options opt;
    vtk_options_default(&opt);
    const vtk_field fields[] = {{"domainRank", 1, VTK_INT32, {r_dom, NULL, NULL}},
                                {"rowsRank", 1, VTK_INT32, {r_rows, NULL, NULL}},
                                {"slabsRank", 1, VTK_INT32, {r_slabs, NULL, NULL}},
                                {"rcbRank", 1, VTK_INT32, {r_rcb, NULL, NULL}}};
    const sl_fluid *f = s->f;
    if (vtk_write_points(path, f->n, f->x, f->y, f->z, fields, 4, &opt, &err))
        sl_fatal("%s", err.msg);
    printf("\nWrote %s (point data domainRank, rowsRank, slabsRank, rcbRank): open it in "
           "ParaView\n",
           path);
}

/* One set-up: the case read and built, the solver's grid with the units
 * `unit` (SLUICE_GRID_UNIT's values; NULL: the setting as it is), the
 * fluid sorted by cell, the lists within h. */
typedef struct setup {
    sl_case c;
    pcs_solver s;
} setup;

static void setup_make(setup *u, const char *dir, const char *unit)
{
    if (unit) setenv("SLUICE_GRID_UNIT", unit, 1);
    sl_log_set_quiet(1);
    case_read(&u->c, dir);
    case_build(&u->c);
    sl_log_set_quiet(0);
    pcs_init(&u->s, &u->c.prm, &u->c.fluid, &u->c.boundary, u->c.lo, u->c.hi, 1e-4, &u->c.effects);
    pcs_find_neighbours(&u->s);
}

static void setup_free(setup *u)
{
    pcs_free(&u->s);
    case_free(&u->c);
}

/* The domain partition over p ranks: each fluid and boundary particle's
 * rank, and per rank the fluid particles stored (own + halo), those of
 * the halo, and the boundary particles stored (pcd_partition). */
typedef struct domain_part {
    int *rank, *brank;
    size_t *stored, *hstored, *bstored;
} domain_part;

static void domain_make(domain_part *d, const pcs_solver *s, int p)
{
    d->rank = sl_malloc((s->f->n + 1) * sizeof *d->rank, "ranks");
    d->brank = sl_malloc((s->b->n + 1) * sizeof *d->brank, "ranks");
    d->stored = sl_malloc(((size_t)p + 1) * sizeof *d->stored, "ranks");
    d->hstored = sl_malloc(((size_t)p + 1) * sizeof *d->hstored, "ranks");
    d->bstored = sl_malloc(((size_t)p + 1) * sizeof *d->bstored, "ranks");
    pcd_partition(s, p, d->rank, d->stored, d->hstored, d->bstored, d->brank);
}

static void domain_free(domain_part *d)
{
    free(d->rank), free(d->brank), free(d->stored), free(d->hstored), free(d->bstored);
}

/* What the domain mode's ranks store under the partition d of s. */
static void domain_details(const pcs_solver *s, const domain_part *d, int p, const char *unit)
{
    const size_t n = s->f->n;
    size_t smin = (size_t)-1, smax = 0, hmin = (size_t)-1, hmax = 0, bmin = (size_t)-1, bmax = 0;
    double hsum = 0.0, mmin = HUGE_VAL, mmax = 0.0;
    for (int r = 0; r < p; r++) {
        bmin = d->bstored[r] < bmin ? d->bstored[r] : bmin;
        bmax = d->bstored[r] > bmax ? d->bstored[r] : bmax;
        const double mem =
            (double)d->stored[r] * FLUID_BYTES + (double)d->bstored[r] * BOUNDARY_BYTES;
        mmin = mem < mmin ? mem : mmin;
        mmax = mem > mmax ? mem : mmax;
        smin = d->stored[r] < smin ? d->stored[r] : smin;
        smax = d->stored[r] > smax ? d->stored[r] : smax;
        hmin = d->hstored[r] < hmin ? d->hstored[r] : hmin;
        hmax = d->hstored[r] > hmax ? d->hstored[r] : hmax;
        hsum += (double)d->hstored[r];
    }
    printf("\ndomain (grid units: %s): pcisph -parallel's domain mode; each rank stores its own "
           "particles and the halo\naround them (the cells within one cell of its own; two with "
           "surface tension):\nstored per rank min %zu,\nmax %zu of %zu; stored halo per rank min "
           "%zu, max %zu, mean "
           "%.0f (%.0f %% of the mean own count)\n",
           unit, smin, smax, n, hmin, hmax, hsum / p, n ? 100.0 * hsum / (double)n : 0.0);
    const size_t nb = s->b->n - s->b->nimages;
    printf("boundary particles stored per rank (those of its own and halo cells) min %zu, max %zu "
           "of %zu\n(%.0f-%.0f %%); particle arrays per rank %.2f-%.2f MB (%d B per fluid, %d B "
           "per boundary\nparticle stored; the whole case in one process: %.2f MB)\n",
           bmin, bmax, nb, nb ? 100.0 * (double)bmin / (double)nb : 0.0,
           nb ? 100.0 * (double)bmax / (double)nb : 0.0, 1e-6 * mmin, 1e-6 * mmax, FLUID_BYTES,
           BOUNDARY_BYTES, 1e-6 * ((double)n * FLUID_BYTES + (double)nb * BOUNDARY_BYTES));
    border_rows(s, d->rank, d->brank, p);
}

#define MAX_UNITS 8

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case(&a);
    const int p = (int)app_int(&a, "np", 2);
    /* the grid units to compare: -unit's comma-separated list, or the setting */
    char ulist[256], *units[MAX_UNITS];
    int nu = 0;
    snprintf(ulist, sizeof ulist, "%s", app_string(&a, "unit", ""));
    for (char *t = strtok(ulist, ","); t && nu < MAX_UNITS; t = strtok(NULL, ",")) units[nu++] = t;
    if (nu == 0) units[nu++] = NULL;
    setup *set = sl_calloc((size_t)nu, sizeof *set, "set-ups");
    domain_part *dom = sl_calloc((size_t)nu, sizeof *dom, "partitions");
    char(*uname)[64] = sl_calloc((size_t)nu, sizeof *uname, "unit names");
    for (int k = 0; k < nu; k++) {
        setup_make(&set[k], dir, units[k]);
        domain_make(&dom[k], &set[k].s, p);
        nbr_unit_name(&set[k].s.grid, uname[k], sizeof uname[k]);
    }
    const pcs_solver *s = &set[0].s;
    const size_t n = s->f->n;
    int *r_rows = sl_malloc((n + 1) * sizeof(int), "ranks");
    int *r_slabs = sl_malloc((n + 1) * sizeof(int), "ranks");
    int *r_rcb = sl_malloc((n + 1) * sizeof(int), "ranks");
    uint32_t *idx = sl_malloc((n + 1) * sizeof *idx, "particles");
    rows(n, p, r_rows);
    for (size_t i = 0; i < n; i++) idx[i] = (uint32_t)i;
    slabs(s->f, idx, n, p, r_slabs);
    for (size_t i = 0; i < n; i++) idx[i] = (uint32_t)i;
    rcb(s->f, idx, n, 0, p, r_rcb);
    printf("Case %s: %zu fluid and %zu boundary particles, h = %g m, %d ranks\n\n", set[0].c.dir, n,
           s->b->n, s->h, p);
    printf("                ---- particles per rank ----  ------- fluid halo per rank -------  "
           "boundary  -- ranks --  ---- bytes / iteration / rank ----\n"
           "                %9s %9s %6s  %9s %9s %10s %7s  %9s  %4s %6s  %10s %10s\n",
           "min", "max", "max/av", "min", "max", "mean", "/owned", "max", "max", "mean", "halo",
           "replicated");
    for (int k = 0; k < nu; k++) {
        char name[80];
        snprintf(name, sizeof name, nu > 1 ? "domain/%s" : "domain", uname[k]);
        report(name, (part_stats[]){measure(&set[k].s, dom[k].rank, p)}, n, p);
    }
    report("rows", (part_stats[]){measure(s, r_rows, p)}, n, p);
    report("slabs", (part_stats[]){measure(s, r_slabs, p)}, n, p);
    report("rcb", (part_stats[]){measure(s, r_rcb, p)}, n, p);
    printf("\nrows: what the halo and gather modes compute per rank (every rank holds every "
           "particle;\nthe gather mode receives the rows of the others each iteration: "
           "'replicated'); domain,\nslabs and rcb: a domain decomposition exchanges only the halo "
           "(x* and p/rho^2 of the\nfluid within h: 'halo').\n");
    for (int k = 0; k < nu; k++) domain_details(&set[k].s, &dom[k], p, uname[k]);
    write_vtu(&set[0].c, s, dom[0].rank, r_rows, r_slabs, r_rcb);
    free(r_rows);
    free(r_slabs);
    free(r_rcb);
    free(idx);
    for (int k = 0; k < nu; k++) {
        domain_free(&dom[k]);
        setup_free(&set[k]);
    }
    free(set);
    free(dom);
    free(uname);
    app_free(&a);
    return 0;
}
