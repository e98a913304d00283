/*
 * boundarySmoothness: how smooth the pressure is where the fluid meets the
 * walls -- the property Fig. 2 of Ihmsen et al. 2010 shows by colour.  For
 * the fluid particles of a time directory's fluid.vtu within h = 2 r0 of a
 * wall surface (of any shape of constant/boundaryProperties; an open face
 * of a container is no wall):
 *
 *   pressureRatio  99th percentile / median of the pressure (GSL) of those
 *                  of them that carry pressure (p > 0): high where a few
 *                  particles carry far more pressure than their neighbours
 *                  ("high pressure ratios", Sec. 4.1).  Pressures are
 *                  clamped at zero; near the free surface, and with
 *                  becker2009 in the whole first layer (the wall adds no
 *                  density there), most near-wall pressures are exactly 0,
 *                  so over all of them the median would be 0 and the ratio
 *                  meaningless.  zeroPressure counts those left out.
 *   stacked        fluid particles closer than r0 / 2 to a wall surface.
 *                  A resting fluid layer sits exactly r0 / 2 from the wall
 *                  (the README's convention), so these are particles pressed
 *                  into the wall ("stacking of particles", Sec. 2 and 4.1);
 *                  one put back exactly to r0 / 2 by a position correction
 *                  (to within 1e-9 r0, rounding) counts as touching
 *
 *   boundarySmoothness -case <dir> [-time <times> | -latestTime | -allTimes]
 *
 * Prints "key value" lines; with -allTimes (or a -time selecting several
 * times) also one row per time to
 * postProcessing/boundarySmoothness/<first time>/boundarySmoothness.dat and
 * a summary over the times.
 */
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>
#include <math.h>
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

typedef struct smooth {
    double time;
    size_t n;           /* fluid particles */
    size_t near;        /* within h of a wall */
    size_t zero;        /* of them with p = 0 */
    double median, p99; /* of the near-wall pressures p > 0, Pa */
    double ratio;       /* p99 / median */
    size_t stacked;     /* closer than r0 / 2 to a wall */
    double dmin;        /* smallest distance of a fluid particle to a wall, m */
} smooth;

static const app_option options[] = {
    APP_CASE,
    APP_TIMES,
    {.name = "allTimes",
     .help = "every time directory: a table in\n"
             "postProcessing/boundarySmoothness/<first time>/boundarySmoothness.dat\n"
             "and its mean and maximum (so does a -time selecting several)"},
    APP_END};

static const app_info info = {
    .name = "boundarySmoothness",
    .what = "Near-wall pressure smoothness of the fluid.vtu of a time directory (default:\n"
            "the latest): for the fluid particles within h = 2 r0 of a wall surface, the\n"
            "ratio of the 99th percentile of their pressures p > 0 to the median, and the\n"
            "number of fluid particles closer than r0/2 to a wall surface (stacked).",
    .options = options};

static smooth measure(const sl_case *c, const char *vtu)
{
    vtkr_file f;
    sl_err err;
    smooth m = {0};
    const double r0 = c->prm.r0, h = pcs_support(&c->prm);
    /* a particle put exactly at the contact distance by a position
     * correction (becker2009, harada2007) touches the wall: only the
     * rounding of that correction is forgiven */
    const double stack_d = 0.5 * r0 * (1.0 - 1e-9);
    if (vtkr_read(vtu, &f, &err)) sl_fatal("%s", err.msg);
    const vtkr_array *p = vtkr_find(&f, "pressure");
    if (!p || p->ncomp != 1) sl_fatal("%s: no scalar point array 'pressure'", vtu);
    double *near = sl_malloc((f.npoints + 1) * sizeof *near, "near-wall pressures");
    size_t nloaded = 0;
    m.time = f.time;
    m.n = f.npoints;
    m.dmin = INFINITY;
    for (size_t i = 0; i < f.npoints; i++) {
        double d = case_wall_distance(c, &f.points[3 * i]);
        if (!(d >= m.dmin)) m.dmin = d;
        if (!(d >= stack_d)) m.stacked++; /* NaN positions count */
        if (!(d < h)) continue;
        m.near++;
        if (p->data[i] > 0.0) near[nloaded++] = p->data[i];
        else m.zero++;
    }
    m.median = m.p99 = m.ratio = nan("");
    if (nloaded) {
        gsl_sort(near, 1, nloaded);
        m.median = gsl_stats_median_from_sorted_data(near, 1, nloaded);
        m.p99 = gsl_stats_quantile_from_sorted_data(near, 1, nloaded, 0.99);
        m.ratio = m.p99 / m.median;
    }
    free(near);
    vtkr_free(&f);
    return m;
}

static void print_one(const sl_case *c, const char *vtu, const smooth *m)
{
    printf("file            %s\n", vtu);
    printf("time            %.9g\n", m->time);
    printf("fluidParticles  %zu\n", m->n);
    printf("nearWallBand    %.6g\n", 2.0 * c->prm.r0);
    printf("nearWall        %zu\n", m->near);
    printf("zeroPressure    %zu\n", m->zero);
    printf("pressureMedian  %.6g\n", m->median);
    printf("pressureP99     %.6g\n", m->p99);
    printf("pressureRatio   %.6g\n", m->ratio);
    printf("stackedBelow    %.6g\n", 0.5 * c->prm.r0);
    printf("stacked         %zu\n", m->stacked);
    printf("minWallDistance %.6g\n", m->dmin);
}

static char *vtu_of(const char *dir, const char *tname)
{
    char *sub = cf_join(dir, tname), *vtu = cf_join(sub, "fluid.vtu");
    free(sub);
    return vtu;
}

/* Every time directory: a table, and the mean and maximum over the times
 * (the ratio's mean over the times where it is finite). */
static void all_times(const sl_case *c, const char *dir, const tdir_list *l)
{
    char *pp = cf_join(dir, "postProcessing/boundarySmoothness"), *out = cf_join(pp, l->name[0]);
    char *path = cf_join(out, "boundarySmoothness.dat");
    sl_err err;
    afile a;
    FILE *f;
    if (tdir_mkdirs(out, &err) || !(f = afile_open(&a, path, &err))) sl_fatal("%s", err.msg);
    fprintf(f,
            "# Near-wall smoothness (boundarySmoothness): fluid particles within h = %g m of "
            "a wall\n# pressureRatio: 99th percentile / median of their pressures p > 0; stacked: "
            "particles closer than r0/2 = %g m to a wall\n"
            "# Time\tnearWall\tzeroPressure\tpressureMedian\tpressureP99\tpressureRatio\tstacked\n",
            2.0 * c->prm.r0, 0.5 * c->prm.r0);
    double rsum = 0.0, rmax = -INFINITY, ssum = 0.0;
    size_t rn = 0, smax = 0;
    for (size_t k = 0; k < l->n; k++) {
        char *vtu = vtu_of(dir, l->name[k]);
        smooth m = measure(c, vtu);
        fprintf(f, "%.9g\t%zu\t%zu\t%.6g\t%.6g\t%.6g\t%zu\n", l->time[k], m.near, m.zero, m.median,
                m.p99, m.ratio, m.stacked);
        if (isfinite(m.ratio)) {
            rsum += m.ratio;
            rn++;
        }
        if (!(m.ratio <= rmax)) rmax = m.ratio;
        ssum += (double)m.stacked;
        if (m.stacked > smax) smax = m.stacked;
        free(vtu);
    }
    if (afile_commit(&a, &err)) sl_fatal("%s", err.msg);
    printf("times              %zu\n", l->n);
    printf("meanPressureRatio  %.6g\n", rn ? rsum / (double)rn : nan(""));
    printf("maxPressureRatio   %.6g\n", rmax);
    printf("meanStacked        %.6g\n", ssum / (double)l->n);
    printf("maxStacked         %zu\n", smax);
    printf("table              %s\n", path);
    free(path);
    free(out);
    free(pp);
}

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case(&a);
    sl_case c;
    tdir_list l;
    case_read(&c, dir);
    app_times(&a, dir, "fluid.vtu", 1, &l);
    if (!l.n)
        sl_fatal("%s: no time directory with a fluid.vtu%s%s", dir,
                 app_found(&a, "time") ? " matches -time " : "", app_string(&a, "time", ""));
    if (app_found(&a, "allTimes") || (app_found(&a, "time") && l.n > 1)) {
        all_times(&c, dir, &l);
    } else {
        char *vtu = vtu_of(dir, l.name[l.n - 1]);
        smooth m = measure(&c, vtu);
        print_one(&c, vtu, &m);
        free(vtu);
    }
    tdir_list_free(&l);
    case_free(&c);
    app_free(&a);
    return 0;
}
