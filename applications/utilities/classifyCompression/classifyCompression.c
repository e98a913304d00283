/*
 * classifyCompression: where the compression of a written time sits, near
 * the walls or in the bulk, and what the walls do to the particles there --
 * the measures of Ihmsen et al. 2010, Sec. 4.1 (cases/boundaryComparison).
 *
 * For every fluid particle i of <time>/fluid.vtu the density is recomputed
 * with the wall's share from the boundary particles and masses of
 * <time>/boundary.vtu (eq. 13, whatever boundary method the run used):
 *
 *     rho_i = m sum_j W(x_ij, h) + sum_b m_b W(x_ib, h),   m = rho0 r0^3,
 *
 * the cubic spline of the solver with its support h (kernelSupport, 2 r0
 * by default), and its compression
 * e_i = max(rho_i - rho0, 0) / rho0 (the solver's volErr of the end-of-step
 * positions).  The particles are split by their distance d to the nearest
 * wall surface into the near-wall band d < h and the bulk d >= h:
 *
 *   compressionAvg        mean e_i over all particles (percent): the
 *                         paper's "overall volume compression"
 *   nearWallShare         share of that sum carried by the near-wall band
 *   nearWallAvg, bulkAvg  mean e_i within each (percent)
 *   nearWallP99, bulkP99  99th percentile of e_i within each (percent)
 *   penetrated            particles beyond a wall surface (d < 0)
 *   pressed               particles closer than r0/2 to a wall (a resting
 *                         layer sits at r0/2; boundarySmoothness "stacked")
 *   stacked               near-wall particles with another fluid particle
 *                         closer than r0/2 (particles piled on each other)
 *   nearWallPressureRatio, bulkPressureRatio
 *                         p99 / median of the written pressures p > 0
 *
 *   classifyCompression -case <dir> [-time <times> | -latestTime | -allTimes]
 *
 * One time: "key value" lines.  Several (-allTimes or a -time range): a
 * table postProcessing/classifyCompression/<first time>/classifyCompression.dat
 * and the row of the time with the largest compressionAvg.
 */
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/app.h"
#include "case/case.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "geometry/geometry.h"
#include "io/atomic_file.h"
#include "io/time_dir.h"
#include "io/vtk_reader.h"
#include "kernel/kernel.h"
#include "solver/pcisph.h"

typedef struct classified {
    double time;
    size_t n, near, bulk;
    double avg, near_share, near_avg, bulk_avg, near_p99, bulk_p99, max;
    size_t penetrated, pressed, stacked;
    double near_pratio, bulk_pratio;
} classified;

static const app_option options[] = {
    APP_CASE,
    APP_TIMES,
    {.name = "allTimes",
     .help = "every time directory: a table in\n"
             "postProcessing/classifyCompression/<first time>/classifyCompression.dat"},
    APP_END};

static const app_info info = {
    .name = "classifyCompression",
    .what = "Compression of the fluid.vtu of a time directory (default: the latest), with\n"
            "the wall's share from boundary.vtu (eq. 13 of Ihmsen et al. 2010, whatever\n"
            "the run's boundary method), split into the band within h (2 r0) of a wall\n"
            "and the bulk; particles beyond a wall (penetrated), closer than r0/2 to it\n"
            "(pressed) and piled closer than r0/2 on another near the wall (stacked);\n"
            "p99 / median of the pressure near walls and in the bulk.",
    .options = options};

/* A uniform cell grid of size h over a point set (counting sort). */
typedef struct grid {
    double lo[3], inv;
    long dim[3];
    size_t *start; /* dim0 dim1 dim2 + 1 */
    uint32_t *idx;
} grid;

static long cell_of(const grid *g, const double *p, int a)
{
    long c = (long)floor((p[a] - g->lo[a]) * g->inv);
    return c < 0 ? 0 : c >= g->dim[a] ? g->dim[a] - 1 : c;
}

static void grid_build(grid *g, const double *pts, size_t n, const double lo[3], const double hi[3],
                       double h)
{
    g->inv = 1.0 / h;
    size_t ncell = 1;
    for (int a = 0; a < 3; a++) {
        g->lo[a] = lo[a];
        g->dim[a] = (long)floor((hi[a] - lo[a]) * g->inv) + 1;
        ncell *= (size_t)g->dim[a];
    }
    g->start = sl_calloc(ncell + 1, sizeof *g->start, "cell starts");
    g->idx = sl_malloc((n + 1) * sizeof *g->idx, "cell index");
    size_t *cell = sl_malloc((n + 1) * sizeof *cell, "cells");
    for (size_t i = 0; i < n; i++) {
        const double *p = &pts[3 * i];
        cell[i] = ((size_t)cell_of(g, p, 2) * (size_t)g->dim[1] + (size_t)cell_of(g, p, 1)) *
                (size_t)g->dim[0] +
            (size_t)cell_of(g, p, 0);
        g->start[cell[i] + 1]++;
    }
    for (size_t c = 0; c < ncell; c++) g->start[c + 1] += g->start[c];
    size_t *fill = sl_malloc((ncell + 1) * sizeof *fill, "cell fill");
    memcpy(fill, g->start, ncell * sizeof *fill);
    for (size_t i = 0; i < n; i++) g->idx[fill[cell[i]]++] = (uint32_t)i;
    free(fill);
    free(cell);
}

static void grid_free(grid *g)
{
    free(g->start);
    free(g->idx);
}

/* sum over the points of g within h of p of w_j W(r); *rmin receives the
 * smallest distance to a point other than `self` (SIZE_MAX: none). */
static double grid_sum(const grid *g, const double *pts, const double *w, double wconst,
                       const krn_kernel *k, const double *p, size_t self, double *rmin)
{
    double s = 0.0, h2 = k->h * k->h;
    long c[3];
    for (int a = 0; a < 3; a++) c[a] = (long)floor((p[a] - g->lo[a]) * g->inv);
    for (long z = c[2] - 1; z <= c[2] + 1; z++) {
        if (z < 0 || z >= g->dim[2]) continue;
        for (long y = c[1] - 1; y <= c[1] + 1; y++) {
            if (y < 0 || y >= g->dim[1]) continue;
            for (long x = c[0] - 1; x <= c[0] + 1; x++) {
                if (x < 0 || x >= g->dim[0]) continue;
                size_t cell =
                    ((size_t)z * (size_t)g->dim[1] + (size_t)y) * (size_t)g->dim[0] + (size_t)x;
                for (size_t q = g->start[cell]; q < g->start[cell + 1]; q++) {
                    size_t j = g->idx[q];
                    const double *pj = &pts[3 * j];
                    double dx = p[0] - pj[0], dy = p[1] - pj[1], dz = p[2] - pj[2];
                    double r2 = dx * dx + dy * dy + dz * dz;
                    if (r2 >= h2) continue;
                    double r = sqrt(r2);
                    if (j != self && rmin && r < *rmin) *rmin = r;
                    s += (w ? w[j] : wconst) * krn_w(k, r);
                }
            }
        }
    }
    return s;
}

static double p99_of(double *v, size_t n)
{
    if (!n) return nan("");
    gsl_sort(v, 1, n);
    return gsl_stats_quantile_from_sorted_data(v, 1, n, 0.99);
}

static double ratio_of(double *v, size_t n)
{
    if (!n) return nan("");
    gsl_sort(v, 1, n);
    return gsl_stats_quantile_from_sorted_data(v, 1, n, 0.99) /
        gsl_stats_median_from_sorted_data(v, 1, n);
}

static classified classify(const sl_case *c, const char *dir, const char *tname,
                           const char *boundary0)
{
    char *sub = cf_join(dir, tname), *fpath = cf_join(sub, "fluid.vtu");
    char *bpath = cf_join(sub, "boundary.vtu");
    vtkr_file f, b;
    sl_err err;
    classified m = {0};
    if (vtkr_read(fpath, &f, &err)) sl_fatal("%s", err.msg);
    /* the walls are static: a time without its own boundary.vtu uses the
     * first one */
    FILE *probe = fopen(bpath, "rb");
    if (probe) fclose(probe);
    if (vtkr_read(probe ? bpath : boundary0, &b, &err)) sl_fatal("%s", err.msg);
    const vtkr_array *bm = vtkr_find(&b, "mass"), *pr = vtkr_find(&f, "pressure");
    if (!bm || bm->ncomp != 1)
        sl_fatal("%s: no scalar point array 'mass'", probe ? bpath : boundary0);
    if (!pr || pr->ncomp != 1) sl_fatal("%s: no scalar point array 'pressure'", fpath);
    const double r0 = c->prm.r0, rho0 = c->prm.rho0, mass = pcs_mass(&c->prm);
    krn_kernel k;
    pcs_kernel(&c->prm, &k);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < f.npoints + b.npoints; i++) {
        const double *p = i < f.npoints ? &f.points[3 * i] : &b.points[3 * (i - f.npoints)];
        for (int a = 0; a < 3; a++) {
            if (!isfinite(p[a])) sl_fatal("%s: a particle with a non-finite position", fpath);
            if (p[a] < lo[a]) lo[a] = p[a];
            if (p[a] > hi[a]) hi[a] = p[a];
        }
    }
    grid gf, gb;
    grid_build(&gf, f.points, f.npoints, lo, hi, k.h);
    grid_build(&gb, b.points, b.npoints, lo, hi, k.h);
    size_t n = f.npoints;
    double *en = sl_malloc((n + 1) * sizeof *en, "near-wall errors");
    double *eb = sl_malloc((n + 1) * sizeof *eb, "bulk errors");
    double *pn = sl_malloc((n + 1) * sizeof *pn, "near-wall pressures");
    double *pb = sl_malloc((n + 1) * sizeof *pb, "bulk pressures");
    size_t npn = 0, npb = 0;
    double sum = 0.0, sum_near = 0.0;
    m.time = f.time;
    m.n = n;
    for (size_t i = 0; i < n; i++) {
        const double *p = &f.points[3 * i];
        double rmin = INFINITY;
        double rho = grid_sum(&gf, f.points, NULL, mass, &k, p, i, &rmin) +
            grid_sum(&gb, b.points, bm->data, 0.0, &k, p, SIZE_MAX, NULL);
        double e = rho > rho0 ? (rho - rho0) / rho0 : 0.0, d = case_wall_distance(c, p);
        sum += e;
        if (e > m.max) m.max = e;
        if (d < 0.0) m.penetrated++;
        if (d < 0.5 * r0 * (1.0 - 1e-9)) m.pressed++;
        if (d < k.h) {
            en[m.near++] = e;
            sum_near += e;
            if (rmin < 0.5 * r0) m.stacked++;
            if (pr->data[i] > 0.0) pn[npn++] = pr->data[i];
        } else {
            eb[m.bulk++] = e;
            if (pr->data[i] > 0.0) pb[npb++] = pr->data[i];
        }
    }
    m.avg = n ? 100.0 * sum / (double)n : nan("");
    m.near_share = sum > 0.0 ? sum_near / sum : nan("");
    m.near_avg = m.near ? 100.0 * sum_near / (double)m.near : nan("");
    m.bulk_avg = m.bulk ? 100.0 * (sum - sum_near) / (double)m.bulk : nan("");
    m.near_p99 = 100.0 * p99_of(en, m.near);
    m.bulk_p99 = 100.0 * p99_of(eb, m.bulk);
    m.max *= 100.0;
    m.near_pratio = ratio_of(pn, npn);
    m.bulk_pratio = ratio_of(pb, npb);
    free(en);
    free(eb);
    free(pn);
    free(pb);
    grid_free(&gf);
    grid_free(&gb);
    vtkr_free(&f);
    vtkr_free(&b);
    free(bpath);
    free(fpath);
    free(sub);
    return m;
}

static void print_one(const classified *m)
{
    printf("time                  %.9g\n", m->time);
    printf("fluidParticles        %zu\n", m->n);
    printf("compressionAvg        %.6g\n", m->avg);
    printf("compressionMax        %.6g\n", m->max);
    printf("nearWall              %zu\n", m->near);
    printf("nearWallShare         %.6g\n", m->near_share);
    printf("nearWallAvg           %.6g\n", m->near_avg);
    printf("nearWallP99           %.6g\n", m->near_p99);
    printf("bulk                  %zu\n", m->bulk);
    printf("bulkAvg               %.6g\n", m->bulk_avg);
    printf("bulkP99               %.6g\n", m->bulk_p99);
    printf("penetrated            %zu\n", m->penetrated);
    printf("pressed               %zu\n", m->pressed);
    printf("stacked               %zu\n", m->stacked);
    printf("nearWallPressureRatio %.6g\n", m->near_pratio);
    printf("bulkPressureRatio     %.6g\n", m->bulk_pratio);
}

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case(&a);
    sl_case c;
    tdir_list l, all;
    sl_err err;
    case_read(&c, dir);
    app_times(&a, dir, "fluid.vtu", 1, &l);
    if (!l.n)
        sl_fatal("%s: no time directory with a fluid.vtu%s%s", dir,
                 app_found(&a, "time") ? " matches -time " : "", app_string(&a, "time", ""));
    if (tdir_list_read(dir, "boundary.vtu", &all, &err)) sl_fatal("%s", err.msg);
    if (!all.n) sl_fatal("%s: no time directory with a boundary.vtu", dir);
    char *b0dir = cf_join(dir, all.name[0]), *b0 = cf_join(b0dir, "boundary.vtu");
    if (app_found(&a, "allTimes") || (app_found(&a, "time") && l.n > 1)) {
        char *pp = cf_join(dir, "postProcessing/classifyCompression"),
             *out = cf_join(pp, l.name[0]), *path = cf_join(out, "classifyCompression.dat");
        afile af;
        FILE *t;
        if (tdir_mkdirs(out, &err) || !(t = afile_open(&af, path, &err))) sl_fatal("%s", err.msg);
        fprintf(t,
                "# classifyCompression: compression (percent of rho0, wall share from the "
                "boundary particles) near walls (d < h = %g m) and in the bulk\n"
                "# Time\tcompressionAvg\tcompressionMax\tnearWall\tnearWallShare\tnearWallAvg"
                "\tnearWallP99\tbulkAvg\tbulkP99\tpenetrated\tpressed\tstacked"
                "\tnearWallPressureRatio\tbulkPressureRatio\n",
                pcs_support(&c.prm));
        classified worst = {.avg = -1.0};
        for (size_t k = 0; k < l.n; k++) {
            classified m = classify(&c, dir, l.name[k], b0);
            fprintf(
                t,
                "%.9g\t%.6g\t%.6g\t%zu\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%zu\t%zu\t%zu\t%.6g\t%.6g\n",
                l.time[k], m.avg, m.max, m.near, m.near_share, m.near_avg, m.near_p99, m.bulk_avg,
                m.bulk_p99, m.penetrated, m.pressed, m.stacked, m.near_pratio, m.bulk_pratio);
            if (m.avg > worst.avg) worst = m;
        }
        if (afile_commit(&af, &err)) sl_fatal("%s", err.msg);
        printf("times                 %zu\n", l.n);
        printf("table                 %s\n", path);
        printf("# the time of the largest compressionAvg:\n");
        print_one(&worst);
        free(path);
        free(out);
        free(pp);
    } else {
        classified m = classify(&c, dir, l.name[l.n - 1], b0);
        print_one(&m);
    }
    free(b0);
    free(b0dir);
    tdir_list_free(&all);
    tdir_list_free(&l);
    case_free(&c);
    app_free(&a);
    return 0;
}
