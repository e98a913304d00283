/*
 * sampleBoundary: build a case's particles without running it and write
 * them for a look in ParaView before a long run, with the sampling quality
 * of every boundary body (nearest-neighbour spacing, min/mean/max).
 *
 *   sampleBoundary [-case <dir>]
 *
 * Writes <case>/constant/sampled/boundary.vtu (normals, body index) and
 * <case>/constant/sampled/fluid.vtu.
 */
#include "app/app.h"
#include "case/case.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "geometry/mesh_sample.h"
#include "io/time_dir.h"
#include "io/vtk_writer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const app_option options[] = {APP_CASE, APP_END};

static const app_info info = {
    .name = "sampleBoundary",
    .what = "Samples the case's geometry and fluid regions and writes them to\n"
            "<dir>/constant/sampled/{boundary,fluid}.vtu; prints the spacing of\n"
            "each boundary body's particles.",
    .options = options};

/* Spacing quality of body k's particles. */
static void report_body(const sl_case *c, uint32_t k)
{
    const sl_boundary *b = &c->boundary;
    size_t n = 0;
    for (size_t i = 0; i < b->n; i++) n += b->body[i] == k;
    double *x = sl_malloc((n + 1) * 3 * sizeof *x, "body positions"), *y = x + n + 1,
           *z = y + n + 1;
    size_t q = 0;
    for (size_t i = 0; i < b->n; i++)
        if (b->body[i] == k) {
            x[q] = b->x[i];
            y[q] = b->y[i];
            z[q] = b->z[i];
            q++;
        }
    msample_quality s = msample_spacing(n, x, y, z);
    sl_info("  %-16s %8zu particles   spacing min %.3g  mean %.3g  max %.3g  (r0 = %g: %.2f / %.2f "
            "/ %.2f r0)",
            c->shapes[k].name, n, s.min, s.mean, s.max, c->prm.r0, s.min / c->prm.r0,
            s.mean / c->prm.r0, s.max / c->prm.r0);
    free(x);
}

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case(&a);
    sl_case c;
    sl_err err;
    case_read(&c, dir);
    case_build(&c);
    sl_info("Case %s: %zu fluid particles, %zu boundary particles in %zu bodies", c.dir, c.fluid.n,
            c.boundary.n, c.nshapes);
    for (uint32_t k = 0; k < c.nshapes; k++) report_body(&c, k);
    size_t len = strlen(dir) + 64;
    char *out = sl_malloc(len, "path"), *path = sl_malloc(len + 32, "path");
    snprintf(out, len, "%s/constant/sampled", dir);
    if (tdir_mkdirs(out, &err)) sl_fatal("%s", err.msg);
    vtk_options opt;
    vtk_options_default(&opt);
    const sl_boundary *b = &c.boundary;
    vtk_field bf[] = {{"normal", 3, VTK_FLOAT64, {b->nx, b->ny, b->nz}},
                      {"body", 1, VTK_UINT32, {b->body, NULL, NULL}}};
    snprintf(path, len + 32, "%s/boundary.vtu", out);
    if (vtk_write_points(path, b->n, b->x, b->y, b->z, bf, 2, &opt, &err)) sl_fatal("%s", err.msg);
    sl_info("Wrote %s", path);
    const sl_fluid *f = &c.fluid;
    vtk_field ff[] = {{"velocity", 3, VTK_FLOAT64, {f->vx, f->vy, f->vz}},
                      {"id", 1, VTK_UINT32, {f->id, NULL, NULL}}};
    snprintf(path, len + 32, "%s/fluid.vtu", out);
    if (vtk_write_points(path, f->n, f->x, f->y, f->z, ff, 2, &opt, &err)) sl_fatal("%s", err.msg);
    sl_info("Wrote %s", path);
    free(out);
    free(path);
    case_free(&c);
    app_free(&a);
    return 0;
}
