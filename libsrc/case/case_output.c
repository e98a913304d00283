/* case_output: time directories and collections (see case_output.h). */
#include "case/case_output.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "case/case_restart.h"
#include "io/time_dir.h"
#include "io/vtk_collection.h"
#include "io/vtk_writer.h"
#include "solver/pcs_domain.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *join(const char *a, const char *b)
{
    size_t n = strlen(a) + strlen(b) + 2;
    char *s = sl_malloc(n, "path");
    snprintf(s, n, "%s/%s", a, b);
    return s;
}

/* Remove a time directory: its files and sub-directories (uniform/). */
static void remove_dir(const char *path) { tdir_remove_tree(path); }

static void push_time(case_output *o, double t, const char *name)
{
    if (o->n == o->cap) {
        o->cap = o->cap ? 2 * o->cap : 64;
        o->times = sl_realloc(o->times, o->cap * sizeof *o->times, "time list");
        o->names = sl_realloc(o->names, o->cap * sizeof *o->names, "time list");
    }
    o->times[o->n] = t;
    o->names[o->n] = sl_strdup(name);
    o->n++;
}

void out_init(case_output *o, const sl_case *c, double start_time)
{
    tdir_list l;
    sl_err err;
    memset(o, 0, sizeof *o);
    o->c = c;
    o->precision = c->ctl.time_precision;
    if (tdir_list_read(c->dir, "fluid.vtu", &l, &err)) sl_fatal("%s", err.msg);
    for (size_t i = 0; i < l.n; i++)
        /* up to and including the start time: a restart does not rewrite
         * the folder it started from, and a new run replaces it */
        if (l.time[i] <= start_time + 1e-12 * (1.0 + fabs(start_time)))
            push_time(o, l.time[i], l.name[i]);
    tdir_list_free(&l);
}

void out_free(case_output *o)
{
    for (size_t i = 0; i < o->n; i++) free(o->names[i]);
    free(o->names);
    free(o->times);
    memset(o, 0, sizeof *o);
}

/* -parallel's domain mode: the arrays streamed from the ranks in the
 * serial order (pcd_output_source), never whole on rank 0. */
static int write_fluid_streamed(const char *path, pcs_solver *s, const vtk_options *opt,
                                sl_err *err)
{
    const int F = PCD_SET_FLUID;
    vtk_stream_field fields[] = {
        {"velocity", 3, VTK_FLOAT64, pcd_output_source(s, F, 3, PCD_VX, PCD_VY, PCD_VZ)},
        {"pressure", 1, VTK_FLOAT64, pcd_output_source(s, F, 1, PCD_P, 0, 0)},
        {"density", 1, VTK_FLOAT64, pcd_output_source(s, F, 1, PCD_RHO, 0, 0)},
        {"densityError", 1, VTK_FLOAT64, pcd_output_source(s, F, 1, PCD_DERR, 0, 0)},
        {"pressureRatio", 1, VTK_FLOAT64, pcd_output_source(s, F, 1, PCD_PR, 0, 0)},
        {"id", 1, VTK_UINT32, pcd_output_source(s, F, 1, PCD_ID, 0, 0)},
    };
    return vtk_write_points_from(path, pcd_output_count(s, F),
                                 pcd_output_source(s, F, 3, PCD_X, PCD_Y, PCD_Z), fields,
                                 sizeof fields / sizeof *fields, opt, err);
}

static int write_fluid(const char *path, pcs_solver *s, const vtk_options *opt, sl_err *err)
{
    if (s->split.domain) return write_fluid_streamed(path, s, opt, err);
    const sl_fluid *f = pcs_view_of(s).f; /* -parallel's halo and gather modes: every rank's */
    const double rho0 = s->prm.rho0;
    double *derr = sl_alloc_aligned(f->n * sizeof *derr, "density error output");
    double *pr = sl_alloc_aligned(f->n * sizeof *pr, "pressure ratio output");
    double pmax = 0.0;
    for (size_t i = 0; i < f->n; i++) {
        derr[i] = pcs_density_error_percent(f->rho[i], rho0);
        if (f->p[i] > pmax) pmax = f->p[i];
    }
    for (size_t i = 0; i < f->n; i++) pr[i] = pcs_pressure_ratio(f->p[i], pmax);
    vtk_field fields[] = {
        {"velocity", 3, VTK_FLOAT64, {f->vx, f->vy, f->vz}},
        {"pressure", 1, VTK_FLOAT64, {f->p, NULL, NULL}},
        {"density", 1, VTK_FLOAT64, {f->rho, NULL, NULL}},
        {"densityError", 1, VTK_FLOAT64, {derr, NULL, NULL}},
        {"pressureRatio", 1, VTK_FLOAT64, {pr, NULL, NULL}},
        {"id", 1, VTK_UINT32, {f->id, NULL, NULL}},
    };
    int rc = vtk_write_points(path, f->n, f->x, f->y, f->z, fields, sizeof fields / sizeof *fields,
                              opt, err);
    sl_free_aligned(derr);
    sl_free_aligned(pr);
    return rc;
}

/* The real boundary particles (periodic images left out), compacted
 * in b's order; returns a copy the caller frees. */
static sl_boundary real_boundary(const sl_boundary *b)
{
    sl_boundary r;
    prt_boundary_init(&r);
    const uint32_t nreal = (uint32_t)(b->n - b->nimages);
    for (size_t i = 0; i < b->n; i++)
        if (b->id[i] < nreal) {
            prt_boundary_push(&r, b->x[i], b->y[i], b->z[i], b->nx[i], b->ny[i], b->nz[i],
                              b->body[i]);
            r.p[r.n - 1] = b->p[i];
            r.rho[r.n - 1] = b->rho[i];
            r.mass[r.n - 1] = b->mass[i];
        }
    return r;
}

static int write_boundary(const char *path, pcs_solver *s, const vtk_options *opt, sl_err *err)
{
    if (s->split.domain) { /* streamed from the owners (no periodic image in this mode) */
        const int B = PCD_SET_BOUNDARY;
        vtk_stream_field fields[] = {
            {"normal", 3, VTK_FLOAT64, pcd_output_source(s, B, 3, PCD_NX, PCD_NY, PCD_NZ)},
            {"pressure", 1, VTK_FLOAT64, pcd_output_source(s, B, 1, PCD_P, 0, 0)},
            {"density", 1, VTK_FLOAT64, pcd_output_source(s, B, 1, PCD_RHO, 0, 0)},
            {"mass", 1, VTK_FLOAT64, pcd_output_source(s, B, 1, PCD_MASS, 0, 0)},
            {"body", 1, VTK_UINT32, pcd_output_source(s, B, 1, PCD_BODY, 0, 0)},
        };
        return vtk_write_points_from(path, pcd_output_count(s, B),
                                     pcd_output_source(s, B, 3, PCD_X, PCD_Y, PCD_Z), fields,
                                     sizeof fields / sizeof *fields, opt, err);
    }
    sl_boundary real;
    const sl_boundary *b = pcs_view_of(s).b;
    if (b->nimages) {
        real = real_boundary(b);
        b = &real;
    }
    vtk_field fields[] = {
        {"normal", 3, VTK_FLOAT64, {b->nx, b->ny, b->nz}},
        {"pressure", 1, VTK_FLOAT64, {b->p, NULL, NULL}},
        {"density", 1, VTK_FLOAT64, {b->rho, NULL, NULL}},
        {"mass", 1, VTK_FLOAT64, {b->mass, NULL, NULL}},
        {"body", 1, VTK_UINT32, {b->body, NULL, NULL}},
    };
    int rc = vtk_write_points(path, b->n, b->x, b->y, b->z, fields, sizeof fields / sizeof *fields,
                              opt, err);
    if (b == &real) prt_boundary_free(&real);
    return rc;
}

static int write_collections(case_output *o, sl_err *err)
{
    const char *sets[2] = {"fluid", "boundary"};
    int nsets = o->c->ctl.write_boundary ? 2 : 1;
    for (int k = 0; k < nsets; k++) {
        char pvd[64], series[64], file[128];
        const char **files = sl_malloc((o->n + 1) * sizeof *files, "collection");
        char **own = sl_malloc((o->n + 1) * sizeof *own, "collection");
        snprintf(pvd, sizeof pvd, "%s.pvd", sets[k]);
        snprintf(series, sizeof series, "%s.vtu.series", sets[k]);
        for (size_t i = 0; i < o->n; i++) {
            snprintf(file, sizeof file, "%s/%s.vtu", o->names[i], sets[k]);
            own[i] = sl_strdup(file);
            files[i] = own[i];
        }
        char *pp = join(o->c->dir, pvd), *sp = join(o->c->dir, series);
        int rc = vtk_collection_write(pp, sp, o->times, files, o->n, err);
        for (size_t i = 0; i < o->n; i++) free(own[i]);
        free(own);
        free(files);
        free(pp);
        free(sp);
        if (rc) return rc;
    }
    return 0;
}

static void purge(case_output *o)
{
    int keep = o->c->ctl.purge_write;
    while (keep > 0 && o->n > (size_t)keep) {
        char *p = join(o->c->dir, o->names[0]);
        remove_dir(p);
        free(p);
        free(o->names[0]);
        memmove(o->names, o->names + 1, (o->n - 1) * sizeof *o->names);
        memmove(o->times, o->times + 1, (o->n - 1) * sizeof *o->times);
        o->n--;
    }
}

/* Two times are the same time (a write repeated after a rollback). */
static int same_time(double a, double b) { return fabs(a - b) <= 1e-12 * (1.0 + fabs(a)); }

/* Whether `name` is taken by a time written before other than t. */
static int name_taken(const case_output *o, const char *name, double t)
{
    for (size_t i = 0; i < o->n; i++)
        if (!strcmp(o->names[i], name) && !same_time(o->times[i], t)) return 1;
    return 0;
}

void out_name(case_output *o, double t, char *name, size_t len)
{
    const double resolution = 1e-3 * o->c->ctl.write_interval;
    int p = tdir_name_within(t, o->precision, resolution, name, len);
    while (p < 17 && name_taken(o, name, t)) tdir_name(t, ++p, name, len);
    if (p > o->precision) {
        char before[64];
        tdir_name(t, o->precision, before, sizeof before);
        sl_warning("%s/system/controlDict: timePrecision %d names time %.17g \"%s\"%s; "
                   "writing it as \"%s\" and later times with %d digits (raise timePrecision "
                   "to keep the names you chose)",
                   o->c->dir, o->precision, t, before,
                   name_taken(o, before, t) ? ", the name of an earlier time" : ", not close to it",
                   name, p);
        o->precision = p;
    }
}

int out_discard_after(case_output *o, double t, sl_err *err)
{
    size_t n0 = o->n;
    while (o->n && o->times[o->n - 1] > t && !same_time(o->times[o->n - 1], t)) {
        char *p = join(o->c->dir, o->names[o->n - 1]);
        remove_dir(p);
        free(p);
        free(o->names[--o->n]);
    }
    return o->n != n0 ? write_collections(o, err) : 0;
}

int out_write(case_output *o, pcs_solver *s, double t, const rst_state *states, int nstates,
              const rst_bstate *bnd, const void *ctrl, size_t ctrl_size, sl_err *err)
{
    const case_controls *k = &o->c->ctl;
    char name[64], tmpname[96];
    vtk_options opt;
    int rc;
    out_name(o, t, name, sizeof name);
    snprintf(tmpname, sizeof tmpname, "%s.tmp.%ld", name, (long)getpid());
    char *dir = join(o->c->dir, name), *tmp = join(o->c->dir, tmpname);
    char *fpath = join(tmp, "fluid.vtu"), *bpath = join(tmp, "boundary.vtu");
    vtk_options_default(&opt);
    opt.ascii = k->ascii;
    opt.compress = k->compress;
    opt.time = t;
    remove_dir(tmp);
    rc = tdir_mkdirs(tmp, err);
    if (!rc) rc = write_fluid(fpath, s, &opt, err);
    if (!rc && k->write_boundary) rc = write_boundary(bpath, s, &opt, err);
    if (!rc && nstates) rc = rst_write_states(tmp, states, nstates, bnd, ctrl, ctrl_size, err);
    if (!rc) {
        remove_dir(dir); /* an older run's directory of the same time */
        if (rename(tmp, dir) != 0) {
            sl_err_set(err, "cannot rename '%s' to '%s': %s", tmp, dir, strerror(errno));
            rc = 1;
        }
    }
    if (rc) {
        remove_dir(tmp);
    } else {
        if (o->n && o->times[o->n - 1] >= t) {      /* rewritten time: replace */
            if (strcmp(o->names[o->n - 1], name)) { /* under another name: that one goes */
                char *old = join(o->c->dir, o->names[o->n - 1]);
                remove_dir(old);
                free(old);
            }
            free(o->names[--o->n]);
        }
        push_time(o, t, name);
        snprintf(o->last_name, sizeof o->last_name, "%s", name);
        purge(o);
        rc = write_collections(o, err);
    }
    free(dir);
    free(tmp);
    free(fpath);
    free(bpath);
    return rc;
}
