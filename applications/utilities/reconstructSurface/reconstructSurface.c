/*
 * reconstructSurface: the water as a surface, one per written time, for
 * ParaView and for measurements (issue 19; method in libsrc/surface and
 * doc/surface.md).
 *
 *   reconstructSurface [-case <dir>] [-time <times> | -latestTime] [-parallel]
 *                      [-gauge '<x> <y>']...
 *
 * For each selected time directory holding fluid.vtu (the initial state
 * included) writes <time>/surface.vtp: triangles with velocity and pressure
 * interpolated to their vertices.  Then <case>/surface.pvd and
 * surface.vtp.series, beside fluid.pvd, list every time that has a
 * surface.vtp (so that -latestTime after a full run keeps the whole
 * series).  Options come from system/surfaceDict (optional; annotated
 * defaults in etc/caseDicts/surfaceDict).  Each time's line gives the
 * surface's area and enclosed volume beside the fluid's N r0^3; the same
 * numbers go to postProcessing/surface/<firstTime>/surface.dat, one row per
 * time in time order, as the function objects' tables, with a column per
 * -gauge: the free-surface height above that point.
 *
 * Threads (numberOfThreads of system/controlDict, 0: all cores) work inside
 * one time; with -parallel they take one time each instead, which is faster
 * for many small frames.  Either way the files are the same.
 */
#include "app/app.h"
#include "case/case.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_progress.h"
#include "core/sl_threads.h"
#include "io/atomic_file.h"
#include "io/time_dir.h"
#include "io/vtk_collection.h"
#include "io/vtk_reader.h"
#include "io/vtk_writer.h"
#include "surface/surface.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static const app_option options[] = {
    APP_CASE,
    APP_TIMES,
    {.name = "parallel", .help = "one time per thread (default: the threads share each time)"},
    {.name = "gauge",
     .kind = APP_STRING,
     .arg = "'<x> <y>'",
     .help = "also measure the free-surface height along the vertical line\n"
             "through (x, y) (a column heightN of surface.dat); repeat for several",
     .repeat = 1},
    APP_END};

static const app_info info = {
    .name = "reconstructSurface",
    .what = "Reconstructs the fluid's free surface of every written time into\n"
            "<time>/surface.vtp (triangles with velocity and pressure) and lists them\n"
            "in surface.pvd beside fluid.pvd; options in system/surfaceDict.",
    .options = options};

/* "a/b" or "a/b/c" (c empty: the former). */
static char *path_of(const char *a, const char *b, const char *c)
{
    size_t n = strlen(a) + strlen(b) + strlen(c) + 3;
    char *s = sl_malloc(n, "path");
    snprintf(s, n, "%s/%s%s%s", a, b, *c ? "/" : "", c);
    return s;
}

/* The component k of the point array `name` of f as its own array (NULL if
 * f has no such array with ncomp components). */
static double *component(const vtkr_file *f, const char *name, int ncomp, int k)
{
    const vtkr_array *a = vtkr_find(f, name);
    if (!a || a->ncomp != ncomp) return NULL;
    double *v = sl_malloc((f->npoints ? f->npoints : 1) * sizeof *v, "a surface input field");
    for (size_t i = 0; i < f->npoints; i++) v[i] = a->data[i * (size_t)ncomp + (size_t)k];
    return v;
}

/* The most -gauge lines. */
#define RS_MAX_GAUGES 64

typedef struct gauges {
    size_t n;
    double xy[RS_MAX_GAUGES][2];
} gauges;

typedef struct frame_stats {
    size_t n, nt;
    double area, volume, seconds;
    double height[RS_MAX_GAUGES]; /* NAN: the line misses the surface */
} frame_stats;

static frame_stats one_time(const sl_case *c, const srf_params *prm, const gauges *gs,
                            const char *tname, double t)
{
    frame_stats st = {0, 0, 0, 0, omp_get_wtime(), {0}};
    char *in = path_of(c->dir, tname, "fluid.vtu"), *out = path_of(c->dir, tname, "surface.vtp");
    vtkr_file f;
    srf_mesh m;
    sl_err err;
    if (vtkr_read(in, &f, &err)) sl_fatal("%s", err.msg);
    double *px = sl_malloc((f.npoints ? f.npoints : 1) * sizeof *px, "positions");
    double *py = sl_malloc((f.npoints ? f.npoints : 1) * sizeof *py, "positions");
    double *pz = sl_malloc((f.npoints ? f.npoints : 1) * sizeof *pz, "positions");
    for (size_t i = 0; i < f.npoints; i++) {
        px[i] = f.points[3 * i];
        py[i] = f.points[3 * i + 1];
        pz[i] = f.points[3 * i + 2];
    }
    srf_particles p = {.n = f.npoints, .x = px, .y = py, .z = pz, .r0 = c->prm.r0};
    p.vx = component(&f, "velocity", 3, 0);
    p.vy = component(&f, "velocity", 3, 1);
    p.vz = component(&f, "velocity", 3, 2);
    p.p = component(&f, "pressure", 1, 0);
    if (srf_reconstruct(&p, prm, &m, &err)) sl_fatal("%s: %s", in, err.msg);
    vtk_field fields[2];
    size_t nf = 0;
    if (m.vx) fields[nf++] = (vtk_field){"velocity", 3, VTK_FLOAT64, {m.vx, m.vy, m.vz}};
    if (m.p) fields[nf++] = (vtk_field){"pressure", 1, VTK_FLOAT64, {m.p, NULL, NULL}};
    vtk_options o;
    vtk_options_default(&o);
    o.ascii = c->ctl.ascii;
    o.compress = c->ctl.compress;
    o.time = t;
    if (vtk_write_triangles(out, m.nv, m.x, m.y, m.z, m.nt, m.tri, fields, nf, &o, &err))
        sl_fatal("%s", err.msg);
    st.n = f.npoints;
    st.nt = m.nt;
    st.area = srf_area(&m);
    st.volume = srf_volume(&m);
    for (size_t g = 0; g < gs->n; g++) st.height[g] = srf_height_at(&m, gs->xy[g][0], gs->xy[g][1]);
    st.seconds = omp_get_wtime() - st.seconds;
    srf_mesh_free(&m);
    free((void *)p.vx);
    free((void *)p.vy);
    free((void *)p.vz);
    free((void *)p.p);
    free(px);
    free(py);
    free(pz);
    vtkr_free(&f);
    free(in);
    free(out);
    return st;
}

/* postProcessing/surface/<first>/surface.dat: one row per time. */
static void write_table(const sl_case *c, const tdir_list *times, const gauges *gs,
                        const frame_stats *st)
{
    const double v0 = c->prm.r0 * c->prm.r0 * c->prm.r0;
    char *dir = path_of(c->dir, "postProcessing/surface", times->name[0]);
    char *path = path_of(dir, "surface.dat", "");
    sl_err err;
    afile af;
    if (tdir_mkdirs(dir, &err)) sl_fatal("%s", err.msg);
    FILE *f = afile_open(&af, path, &err);
    if (!f) sl_fatal("%s", err.msg);
    fprintf(f,
            "# Free-surface measurements (Sluice reconstructSurface), one row per time\n"
            "# area: of the reconstructed surface (m^2); volume: the volume it encloses (m^3)\n"
            "# fluidVolume: particles times r0^3 (m^3); volumeRatio = volume / fluidVolume\n");
    for (size_t g = 0; g < gs->n; g++)
        fprintf(f,
                "# height%zu: the highest surface point above (x, y) = (%g, %g) (m; nan: none)\n",
                g + 1, gs->xy[g][0], gs->xy[g][1]);
    fprintf(f, "# Time\tparticles\ttriangles\tarea\tvolume\tfluidVolume\tvolumeRatio");
    for (size_t g = 0; g < gs->n; g++) fprintf(f, "\theight%zu", g + 1);
    fprintf(f, "\n");
    for (size_t i = 0; i < times->n; i++) {
        const double fv = (double)st[i].n * v0;
        fprintf(f, "%s\t%zu\t%zu\t%.10g\t%.10g\t%.10g\t%.10g", times->name[i], st[i].n, st[i].nt,
                st[i].area, st[i].volume, fv, fv > 0 ? st[i].volume / fv : 0.0);
        for (size_t g = 0; g < gs->n; g++) fprintf(f, "\t%.10g", st[i].height[g]);
        fprintf(f, "\n");
    }
    if (afile_commit(&af, &err)) sl_fatal("%s", err.msg);
    sl_info("Measurements: %s", path);
    free(path);
    free(dir);
}

/* surface.pvd and surface.vtp.series: every time with a surface.vtp. */
static void write_collection(const char *dir)
{
    tdir_list l;
    sl_err err;
    if (tdir_list_read(dir, "surface.vtp", &l, &err)) sl_fatal("%s", err.msg);
    const char **files = sl_malloc((l.n ? l.n : 1) * sizeof *files, "collection");
    for (size_t i = 0; i < l.n; i++) files[i] = path_of(l.name[i], "surface.vtp", "");
    char *pvd = path_of(dir, "surface.pvd", ""), *series = path_of(dir, "surface.vtp.series", "");
    if (vtk_collection_write(pvd, series, l.time, files, l.n, &err)) sl_fatal("%s", err.msg);
    sl_info("Open %s in ParaView (%zu time%s).", pvd, l.n, l.n == 1 ? "" : "s");
    for (size_t i = 0; i < l.n; i++) free((void *)files[i]);
    free(files);
    free(pvd);
    free(series);
    tdir_list_free(&l);
}

static void read_params(const sl_case *c, srf_params *prm)
{
    char *path = path_of(c->dir, "system", "surfaceDict");
    struct stat st;
    if (stat(path, &st) != 0) {
        srf_params_default(prm);
        sl_info("No %s: the defaults (gridSpacing 0.5, isoValue 0.5, smoothing 0)", path);
    } else {
        sl_err err;
        dict *d = dict_read_file(path, &err);
        if (!d) sl_fatal("%s", err.msg);
        srf_params_read(d, prm);
        dict_free(d);
    }
    free(path);
}

/* CPU seconds of the process (all threads). */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The -gauge options: two finite numbers each. */
static void read_gauges(const app *a, gauges *gs)
{
    gs->n = app_count(a, "gauge");
    if (gs->n > RS_MAX_GAUGES) app_error(a, "at most %d -gauge lines", RS_MAX_GAUGES);
    for (size_t g = 0; g < gs->n; g++) {
        const char *v = app_value_at(a, "gauge", g);
        char x[64], y[64], extra;
        if (sscanf(v, "%63s %63s %c", x, y, &extra) != 2 || app_parse_double(x, &gs->xy[g][0]) ||
            app_parse_double(y, &gs->xy[g][1]))
            app_error(a, "-gauge: '%s' is not two numbers '<x> <y>'", v);
    }
}

int main(int argc, char **argv)
{
    sl_threads_passive(argv); /* before any parallel region */
    app a;
    gauges gs;
    app_parse(&a, &info, argc, argv);
    read_gauges(&a, &gs);
    const int par = app_found(&a, "parallel");
    sl_case c;
    tdir_list times;
    srf_params prm;
    case_read(&c, app_case(&a));
    if (c.ctl.nthreads > 0) omp_set_num_threads(c.ctl.nthreads);
    read_params(&c, &prm);
    app_times(&a, c.dir, "fluid.vtu", 1, &times);
    if (times.n == 0) sl_fatal("%s: no time directory with fluid.vtu selected", c.dir);
    sl_progress prog;
    sl_progress_start(&prog, stdout, 0, (double)times.n, 10);
    double t0 = omp_get_wtime(), c0 = cpu_seconds(), particle_sum = 0;
    size_t done = 0;
    frame_stats *all = sl_calloc(times.n, sizeof *all, "surface statistics");
#pragma omp parallel for schedule(dynamic, 1) if (par)
    for (size_t i = 0; i < times.n; i++) {
        frame_stats st = one_time(&c, &prm, &gs, times.name[i], times.time[i]);
        all[i] = st;
        const double fluid = (double)st.n * c.prm.r0 * c.prm.r0 * c.prm.r0;
#pragma omp critical
        {
            char what[64];
            sl_info("Time = %s: %zu particles -> %zu triangles, area %.6g m^2, volume %.6g m^3 "
                    "(%.2f %% of N r0^3), %.3f s",
                    times.name[i], st.n, st.nt, st.area, st.volume,
                    fluid > 0 ? 100.0 * st.volume / fluid : 0.0, st.seconds);
            particle_sum += (double)st.n;
            done++;
            snprintf(what, sizeof what, "surface %zu of %zu", done, times.n);
            sl_progress_update(&prog, (double)done, what);
        }
    }
    sl_progress_end(&prog);
    const double wall = omp_get_wtime() - t0, cpu = cpu_seconds() - c0;
    write_collection(c.dir);
    write_table(&c, &times, &gs, all);
    free(all);
    const double mega = particle_sum / 1e6;
    sl_info("reconstructSurface: %zu time%s in %.2f s wall, %.2f CPU s (%s, %d thread%s): "
            "%.3f s wall and %.3f CPU s per frame; per frame per million particles %.3g s wall, "
            "%.3g CPU s",
            times.n, times.n == 1 ? "" : "s", wall, cpu, par ? "-parallel" : "threads per frame",
            omp_get_max_threads(), omp_get_max_threads() == 1 ? "" : "s", wall / (double)times.n,
            cpu / (double)times.n, mega > 0 ? wall / mega : 0.0, mega > 0 ? cpu / mega : 0.0);
    tdir_list_free(&times);
    case_free(&c);
    app_free(&a);
    return 0;
}
