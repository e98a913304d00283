/* fo_post: time selection and snapshots of written times (see fo_post.h). */
#include "functionObjects/fo_post.h"
#include "functionObjects/fo.h"

#include "core/sl_mem.h"
#include "io/vtk_reader.h"
#include "kernel/kernel.h"
#include "neighbours/neighbours.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- time selection ---- */

int fo_post_times(const char *case_dir, const char *spec, int latest, tdir_list *out, sl_err *err)
{
    if (tdir_list_read(case_dir, "fluid.vtu", out, err)) return 1;
    if (tdir_select(out, spec, latest, 1, err)) {
        tdir_list_free(out);
        return 1;
    }
    if (out->n == 0) {
        tdir_list_free(out);
        if (spec)
            sl_err_set(err, "no time directory of '%s' with fluid.vtu matches -time '%s'", case_dir,
                       spec);
        else sl_err_set(err, "no time directory with fluid.vtu in '%s'", case_dir);
        return 1;
    }
    return 0;
}

/* ---- snapshots ---- */

static char *file_path(const sl_case *c, const char *tname, const char *file)
{
    size_t n = strlen(c->dir) + strlen(tname) + strlen(file) + 3;
    char *p = sl_malloc(n, "path");
    snprintf(p, n, "%s/%s/%s", c->dir, tname, file);
    return p;
}

/* The array `name` of ncomp components, or NULL with err filled. */
static const double *array(const vtkr_file *v, const char *path, const char *name, int ncomp,
                           sl_err *err)
{
    const vtkr_array *a = vtkr_find(v, name);
    if (!a || a->ncomp != ncomp) {
        sl_err_set(err, "%s: no point-data array '%s' of %d component%s", path, name, ncomp,
                   ncomp > 1 ? "s" : "");
        return NULL;
    }
    return a->data;
}

static int load_fluid(fo_snapshot *sn, const char *path, sl_err *err)
{
    vtkr_file v;
    if (vtkr_read(path, &v, err)) return 1;
    const double *vel = array(&v, path, "velocity", 3, err);
    const double *p = vel ? array(&v, path, "pressure", 1, err) : NULL;
    const double *rho = p ? array(&v, path, "density", 1, err) : NULL;
    if (!rho) {
        vtkr_free(&v);
        return 1;
    }
    prt_fluid_reserve(&sn->f, v.npoints ? v.npoints : 1);
    for (size_t i = 0; i < v.npoints; i++) {
        const double *x = v.points + 3 * i, *u = vel + 3 * i;
        prt_fluid_push(&sn->f, x[0], x[1], x[2], u[0], u[1], u[2]);
        sn->f.p[i] = p[i];
        sn->f.rho[i] = rho[i];
    }
    vtkr_free(&v);
    return 0;
}

static int load_boundary(fo_snapshot *sn, const char *path, sl_err *err)
{
    vtkr_file v;
    if (access(path, F_OK) != 0 && errno == ENOENT) {
        sl_warning("%s does not exist (writeBoundary off?): walls are left out", path);
        return 0;
    }
    if (vtkr_read(path, &v, err)) return 1;
    const double *p = array(&v, path, "pressure", 1, err);
    const double *rho = p ? array(&v, path, "density", 1, err) : NULL;
    const double *m = rho ? array(&v, path, "mass", 1, err) : NULL;
    if (!m) {
        vtkr_free(&v);
        return 1;
    }
    prt_boundary_reserve(&sn->b, v.npoints ? v.npoints : 1);
    for (size_t i = 0; i < v.npoints; i++) {
        const double *x = v.points + 3 * i;
        prt_boundary_push(&sn->b, x[0], x[1], x[2], 0.0, 0.0, 0.0, 0);
        sn->b.p[i] = p[i];
        sn->b.rho[i] = rho[i];
        sn->b.mass[i] = m[i];
    }
    vtkr_free(&v);
    return 0;
}

static void grow_bounds(double lo[3], double hi[3], const double *x, const double *y,
                        const double *z, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        const double q[3] = {x[i], y[i], z[i]};
        for (int d = 0; d < 3; d++) {
            if (q[d] < lo[d]) lo[d] = q[d];
            if (q[d] > hi[d]) hi[d] = q[d];
        }
    }
}

/* The grid (and the boundary -> fluid lists) the point queries use. */
static void build_grid(fo_snapshot *sn, unsigned needs)
{
    const double h = sn->v.h;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    grow_bounds(lo, hi, sn->f.x, sn->f.y, sn->f.z, sn->f.n);
    grow_bounds(lo, hi, sn->b.x, sn->b.y, sn->b.z, sn->b.n);
    for (int d = 0; d < 3; d++) {
        if (!(hi[d] >= lo[d])) lo[d] = hi[d] = 0.0; /* no finite position */
        lo[d] -= h;
        hi[d] += h;
    }
    nbr_grid_init(&sn->grid, lo, hi, h, 8 * (sn->f.n + sn->b.n) + ((size_t)1 << 20));
    nbr_sort_boundary(&sn->grid, &sn->b);
    nbr_sort_fluid(&sn->grid, &sn->f);
    if (needs & FO_NEED_BOUNDARY) {
        sn->active = sl_alloc_aligned((sn->b.n + 1) * sizeof *sn->active, "active boundary list");
        nbr_build_bf(&sn->grid, &sn->f, &sn->b, &sn->bf, sn->active, &sn->nactive);
    }
}

int fo_snapshot_load(fo_snapshot *sn, const sl_case *c, const char *tname, unsigned needs,
                     sl_err *err)
{
    memset(sn, 0, sizeof *sn);
    prt_fluid_init(&sn->f);
    prt_boundary_init(&sn->b);
    nbr_list_init(&sn->bf);
    pcs_view *v = &sn->v;
    v->f = &sn->f;
    v->b = &sn->b;
    v->grid = &sn->grid;
    v->bf = &sn->bf;
    v->r0 = c->prm.r0;
    v->rho0 = c->prm.rho0;
    v->gravity = c->prm.gravity;
    v->h = pcs_support(&c->prm);
    v->mass = pcs_mass(&c->prm);
    v->periodic = c->prm.periodic.axes ? &c->prm.periodic : NULL;
    v->boundary_images = 0; /* boundary.vtu holds the real particles only */
    pcs_kernel(&c->prm, &v->k);
    char *path = file_path(c, tname, "fluid.vtu");
    int rc = load_fluid(sn, path, err);
    free(path);
    if (!rc && (needs & FO_NEED_BOUNDARY)) {
        path = file_path(c, tname, "boundary.vtu");
        rc = load_boundary(sn, path, err);
        free(path);
    }
    if (!rc && (needs & (FO_NEED_GRID | FO_NEED_BOUNDARY))) build_grid(sn, needs);
    if (rc) fo_snapshot_free(sn);
    return rc;
}

void fo_snapshot_free(fo_snapshot *sn)
{
    if (sn->grid.ncells) nbr_grid_free(&sn->grid);
    nbr_list_free(&sn->bf);
    sl_free_aligned(sn->active);
    prt_fluid_free(&sn->f);
    prt_boundary_free(&sn->b);
    memset(sn, 0, sizeof *sn);
}
