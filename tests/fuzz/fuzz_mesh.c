/*
 * fuzz_mesh: libFuzzer target for the mesh readers (libsrc/geometry/mesh_io.c).
 *
 * Built twice: -DFUZZ_OBJ reads each input as an OBJ file, -DFUZZ_STL as an
 * STL file (ascii or binary, chosen by the reader from the size).  A mesh
 * that reads is validated (repairs, orientation, distance index) and then
 * queried, so that a hostile mesh reaches every stage a case would use.
 *
 * Contract checked on top of the sanitizers: a failure fills the error
 * message and leaves the mesh empty; a mesh that reads has finite
 * coordinates and indices in range; a validated mesh gives finite distances.
 */
#include "geometry/mesh.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#if defined(FUZZ_OBJ)
#define EXT  "obj"
#define READ mesh_read_obj
#elif defined(FUZZ_STL)
#define EXT  "stl"
#define READ mesh_read_stl
#else
#error "define FUZZ_OBJ or FUZZ_STL"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_mesh (" EXT "): contract violated: %s\n", what);
        abort();
    }
}

static void check_err(const sl_err *err)
{
    check(memchr(err->msg, '\0', sizeof err->msg) != NULL, "error message not terminated");
    check(err->msg[0] != '\0', "failure with an empty error message");
}

static void check_read(const mesh *m)
{
    for (size_t i = 0; i < 3 * m->nv; i++) check(isfinite(m->v[i]), "non-finite coordinate read");
    for (size_t i = 0; i < 3 * m->nt; i++) check(m->t[i] < m->nv, "vertex index out of range");
}

/* Distances at the corners and the centre of the bounding box. */
static void query(const mesh *m)
{
    double lo[3], hi[3];
    mesh_bounds(m, lo, hi);
    for (int k = 0; k < 9; k++) {
        double p[3];
        for (int d = 0; d < 3; d++)
            p[d] = k == 8 ? 0.5 * (lo[d] + hi[d]) : ((k >> d) & 1) ? hi[d] + 0.1 : lo[d] - 0.1;
        double s = mesh_signed_distance(m, p);
        double c[3];
        size_t tri = 0;
        double u = mesh_closest_point(m, p, c, &tri);
        if (!isfinite(lo[0] + hi[0] + lo[1] + hi[1] + lo[2] + hi[2])) continue;
        check(!isnan(s) && !isnan(u), "NaN distance");
        check(tri < m->nt, "closest triangle out of range");
        (void)mesh_inside(m, p);
        (void)mesh_signed_distance_bounded(m, p, 0.05);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[64];
    sl_err err;
    mesh m;
    /* in the cwd: run_fuzz runs the targets in a tmpfs folder */
    if (!path[0]) snprintf(path, sizeof path, "fuzz_input.%ld." EXT, (long)getpid());
    FILE *f = fopen(path, "wb");
    check(f != NULL, "cannot write the temporary input file");
    fwrite(data, 1, size, f);
    fclose(f);
    err.msg[0] = '\0';
    if (READ(path, &m, &err)) {
        check_err(&err);
        check(m.nv == 0 && m.nt == 0, "a failed read left a mesh behind");
        mesh_free(&m);
        return 0;
    }
    check_read(&m);
    (void)mesh_area(&m);
    (void)mesh_volume(&m);
    mesh_report rep;
    err.msg[0] = '\0';
    if (mesh_validate(&m, "fuzz", MESH_QUIET, &rep, &err) == 0) {
        check_read(&m);
        check(m.nt > 0, "a validated mesh has no triangle");
        query(&m);
    } else {
        check_err(&err);
    }
    mesh_free(&m);
    return 0;
}
