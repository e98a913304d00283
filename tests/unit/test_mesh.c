/* Unit tests: triangle meshes (libsrc/geometry/mesh*.c, mesh_sample.c).
 * Readers on the files under tests/data/mesh/ (good ones and hostile ones,
 * whose errors must name the file and line or byte), validation and its
 * repairs, transforms, primitives, signed distance against analytic spheres
 * and boxes and against a winding-number reference on a concave body, the
 * filling speed, and boundary sampling (spacing bounds, offset r0/2 behind
 * the wall, normals into the fluid).  Run from the repository root. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/sl_log.h"
#include "geometry/mesh.h"
#include "geometry/mesh_sample.h"
#include "hostile_table.h"

#define DATA "tests/data/mesh/"
#define BAD  "tests/data/mesh/bad/"

static void assert_has(const char *msg, const char *part)
{
    if (!strstr(msg, part)) fail_msg("message '%s'\n  does not contain '%s'", msg, part);
}

/* A small deterministic generator for test points (xorshift64*). */
static double uniform(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 0x2545F4914F6CDD1Dull) >> 11) / 9007199254740992.0;
}

static double norm3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* A unit cube read from a file: welded, closed, volume 1, area 6. */
static void check_unit_cube(const char *path)
{
    mesh m;
    mesh_report r;
    sl_err err = {{0}};
    double lo[3], hi[3];
    if (mesh_read(path, &m, &err)) fail_msg("%s", err.msg);
    assert_int_equal(m.nv, 8);
    assert_int_equal(m.nt, 12);
    if (mesh_validate(&m, path, MESH_REQUIRE_CLOSED, &r, &err)) fail_msg("%s", err.msg);
    assert_int_equal(r.degenerate + r.unused + r.reoriented + (size_t)r.inverted, 0);
    assert_true(r.closed);
    assert_true(fabs(r.volume - 1.0) < 1e-12);
    assert_true(fabs(r.area - 6.0) < 1e-12);
    mesh_bounds(&m, lo, hi);
    for (int d = 0; d < 3; d++) assert_true(lo[d] == 0.0 && hi[d] == 1.0);
    mesh_free(&m);
}

static void test_read_ascii_stl(void **state)
{
    (void)state;
    check_unit_cube(DATA "cube_ascii.stl");
}

/* Its header starts with "solid": the size alone says binary. */
static void test_read_binary_stl(void **state)
{
    (void)state;
    check_unit_cube(DATA "cube_binary.stl");
}

/* Quads as fans, negative indices, i/t/n and i//n items, vt/vn/g/o/s/usemtl. */
static void test_read_obj_quads(void **state)
{
    (void)state;
    check_unit_cube(DATA "cube_quads.obj");
}

static void test_bad_files(void **state)
{
    static const struct {
        const char *file, *msg;
    } cases[] = {
        {BAD "truncated.stl",
         "truncated.stl: byte 80: not an STL file, or a truncated one: as "
         "binary STL it declares 12 triangles (684 bytes) but has 351 bytes"},
        {BAD "huge_count.stl", "declares 4294967295 triangles (214748364834 bytes) but has 184"},
        {BAD "garbage.stl", "garbage.stl: byte 80: not an STL file"},
        {BAD "nan.stl", "nan.stl: byte 250: triangle 4 has a non-finite coordinate"},
        {BAD "ascii_typo.stl", "ascii_typo.stl:19: expected 'vertex', found 'vertx'"},
        {BAD "ascii_truncated.stl", "expected 'vertex', found the end of the file"},
        {BAD "garbage.obj", "garbage.obj:2: invalid byte 0x1a (binary or corrupt file?)"},
        {BAD "not_a_mesh.obj",
         "no faces found; not an OBJ file? (line 1: unknown statement "
         "'hello')"},
        {BAD "index_out_of_range.obj",
         "index_out_of_range.obj:14: vertex index '9' out of range "
         "(1..8 or -1..-8 defined so far)"},
        {BAD "zero_index.obj", "zero_index.obj:9: vertex index 0 in '0' (OBJ indices start at 1)"},
        {BAD "nan.obj", "nan.obj:8: vertex coordinate 'nan' is not a finite number"},
        {BAD "short_face.obj", "short_face.obj:12: face has 2 vertices, expected at least 3"},
        {BAD "missing.obj", "cannot open file 'tests/data/mesh/bad/missing.obj': No such file"},
        {BAD "cube.ply", "cube.ply: unknown mesh format '.ply' (expected .obj or .stl)"},
        {BAD, "cannot open file 'tests/data/mesh/bad/': not a regular file"},
    };
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        mesh m;
        sl_err err = {{0}};
        int rc = strcmp(cases[i].file, BAD) == 0 ? mesh_read_stl(cases[i].file, &m, &err)
                                                 : mesh_read(cases[i].file, &m, &err);
        if (rc == 0) fail_msg("%s: read without error", cases[i].file);
        assert_has(err.msg, cases[i].msg);
        assert_true(m.nv == 0 && m.nt == 0 && m.v == NULL && m.t == NULL);
        const char *base = strrchr(cases[i].file, '/');
        hostile_record("mesh file (mesh_read)", base[1] ? base + 1 : "a folder", err.msg);
    }
}

static void test_open_mesh(void **state)
{
    mesh m;
    mesh_report r;
    sl_err err = {{0}};
    (void)state;
    assert_int_equal(mesh_read(BAD "open.obj", &m, &err), 0);
    assert_int_not_equal(mesh_validate(&m, "open.obj", MESH_REQUIRE_CLOSED, &r, &err), 0);
    assert_has(err.msg,
               "open.obj: mesh is not closed: 4 edges are used by one triangle only, "
               "e.g. (");
    assert_int_equal(mesh_validate(&m, "open.obj", 0, &r, &err), 0);
    assert_int_equal(r.open_edges, 4);
    assert_int_equal(r.closed, 0);
    mesh_free(&m);
}

static void test_degenerate(void **state)
{
    mesh m;
    mesh_report r;
    sl_err err = {{0}};
    (void)state;
    assert_int_equal(mesh_read(BAD "degenerate.obj", &m, &err), 0);
    assert_int_equal(m.nt, 14);
    if (mesh_validate(&m, "degenerate.obj", MESH_REQUIRE_CLOSED | MESH_QUIET, &r, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(r.degenerate, 2); /* a repeated corner; three collinear corners */
    assert_int_equal(r.unused, 1);     /* the midpoint vertex */
    assert_int_equal(m.nt, 12);
    assert_int_equal(m.nv, 8);
    assert_true(r.closed && fabs(r.volume - 1.0) < 1e-12);
    mesh_free(&m);
}

static void test_inverted_and_inconsistent(void **state)
{
    mesh m;
    mesh_report r;
    sl_err err = {{0}};
    double c[3] = {0.5, 0.5, 0.5};
    (void)state;
    assert_int_equal(mesh_read(BAD "inverted.obj", &m, &err), 0);
    assert_true(mesh_volume(&m) < 0.0);
    assert_int_equal(mesh_validate(&m, "inverted.obj", MESH_QUIET, &r, &err), 0);
    assert_int_equal(r.inverted, 1);
    assert_int_equal(r.reoriented, 0);
    assert_true(fabs(r.volume - 1.0) < 1e-12 && fabs(mesh_volume(&m) - 1.0) < 1e-12);
    assert_true(fabs(mesh_signed_distance(&m, c) + 0.5) < 1e-12);
    mesh_free(&m);

    assert_int_equal(mesh_read(BAD "inconsistent.obj", &m, &err), 0);
    assert_int_equal(mesh_validate(&m, "inconsistent.obj", MESH_QUIET, &r, &err), 0);
    assert_int_equal(r.reoriented, 2);
    assert_int_equal(r.inverted, 0);
    assert_true(fabs(r.volume - 1.0) < 1e-12);
    mesh_free(&m);
}

/* A Moebius strip cannot be oriented; an empty or broken mesh is refused. */
static void test_validate_errors(void **state)
{
    mesh m;
    sl_err err = {{0}};
    const int n = 12;
    (void)state;
    mesh_init(&m);
    for (int i = 0; i < n; i++) {
        double a = 2.0 * M_PI * i / n, t = 0.5 * a; /* half a turn over the loop */
        for (int s = -1; s <= 1; s += 2)
            mesh_add_vertex(&m, (1.0 + 0.2 * s * cos(t)) * cos(a),
                            (1.0 + 0.2 * s * cos(t)) * sin(a), 0.2 * s * sin(t));
    }
    for (uint32_t i = 0; i < (uint32_t)n; i++) {
        uint32_t a = 2 * i, b = 2 * i + 1, c, d;
        if (i + 1 < (uint32_t)n) {
            c = 2 * i + 2;
            d = 2 * i + 3;
        } else {
            c = 1;
            d = 0;
        } /* the twist: the rails swap */
        mesh_add_triangle(&m, a, c, b);
        mesh_add_triangle(&m, b, c, d);
    }
    assert_int_not_equal(mesh_validate(&m, "moebius", MESH_QUIET, NULL, &err), 0);
    assert_has(err.msg, "moebius: mesh is not orientable");
    mesh_free(&m);

    assert_int_not_equal(mesh_validate(&m, "empty", 0, NULL, &err), 0);
    assert_has(err.msg, "empty: mesh has no triangles");

    mesh_add_vertex(&m, 0, 0, 0);
    mesh_add_vertex(&m, 1, 0, 0);
    mesh_add_vertex(&m, 0, 1, 0);
    mesh_add_triangle(&m, 0, 1, 7);
    assert_int_not_equal(mesh_validate(&m, "wild", 0, NULL, &err), 0);
    assert_has(err.msg, "wild: triangle 1 uses vertex 8, but there are only 3");
    m.t[2] = 2;
    m.v[4] = NAN;
    assert_int_not_equal(mesh_validate(&m, "nan", 0, NULL, &err), 0);
    assert_has(err.msg, "nan: vertex 2 has a non-finite coordinate");
    m.v[4] = -1e200;
    assert_int_not_equal(mesh_validate(&m, "far", 0, NULL, &err), 0);
    assert_has(err.msg, "far: vertex 2 at (1 -1e+200 0) is beyond 1e+100 (wrong units?)");
    m.v[4] = 0.0;
    m.v[6] = 2.0; /* vertex 3 on the line of 1 and 2 */
    m.v[7] = 0.0;
    assert_int_not_equal(mesh_validate(&m, "flat", MESH_QUIET, NULL, &err), 0);
    assert_has(err.msg, "flat: mesh has no triangles (all of them are degenerate)");
    mesh_free(&m);
}

static void test_transforms(void **state)
{
    mesh m;
    sl_err err = {{0}};
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, blo[3], bhi[3];
    (void)state;
    assert_int_equal(mesh_make_box(&m, lo, hi, &err), 0);
    assert_non_null(m.index);
    assert_int_equal(mesh_scale(&m, (double[3]){2, 3, 4}, &err), 0);
    assert_null(m.index); /* every change drops the index */
    mesh_bounds(&m, blo, bhi);
    assert_true(bhi[0] == 2.0 && bhi[1] == 3.0 && bhi[2] == 4.0);
    assert_true(fabs(mesh_volume(&m) - 24.0) < 1e-12);
    /* a mirror keeps the normals outward */
    assert_int_equal(mesh_scale(&m, (double[3]){-1, 1, 1}, &err), 0);
    assert_true(fabs(mesh_volume(&m) - 24.0) < 1e-12);
    assert_int_equal(mesh_scale_uniform(&m, 0.5, &err), 0);
    assert_true(fabs(mesh_volume(&m) - 3.0) < 1e-12);
    assert_int_equal(mesh_translate(&m, (double[3]){1, -2, 3}, &err), 0);
    mesh_bounds(&m, blo, bhi);
    assert_true(fabs(blo[0] - 0.0) < 1e-15 && fabs(bhi[1] - (-0.5)) < 1e-15 &&
                fabs(bhi[2] - 5.0) < 1e-15);
    assert_int_not_equal(mesh_scale(&m, (double[3]){1, 0, 1}, &err), 0);
    assert_has(err.msg, "mesh scale factor along y is 0");
    assert_int_not_equal(mesh_rotate(&m, (double[3]){0, NAN, 0}, &err), 0);
    assert_has(err.msg, "expected finite angles in degrees");
    assert_int_not_equal(mesh_translate(&m, (double[3]){INFINITY, 0, 0}, &err), 0);
    mesh_free(&m);

    /* Euler angles: x first, then y, then z, about fixed axes. */
    mesh_init(&m);
    mesh_add_vertex(&m, 0, 1, 0);
    assert_int_equal(mesh_rotate(&m, (double[3]){90, 90, 0}, &err), 0);
    assert_true(fabs(m.v[0] - 1.0) < 1e-15 && fabs(m.v[1]) < 1e-15 && fabs(m.v[2]) < 1e-15);
    assert_int_equal(mesh_rotate(&m, (double[3]){0, 0, 90}, &err), 0); /* x -> y */
    assert_true(fabs(m.v[0]) < 1e-15 && fabs(m.v[1] - 1.0) < 1e-15 && fabs(m.v[2]) < 1e-15);
    mesh_free(&m);
}

static void test_weld(void **state)
{
    mesh m;
    (void)state;
    mesh_init(&m);
    mesh_add_vertex(&m, 0, 0, 0);
    mesh_add_vertex(&m, 1, 0, 0);
    mesh_add_vertex(&m, 0, 1, 0);
    mesh_add_vertex(&m, 1e-9, 0, 0);    /* = 0 */
    mesh_add_vertex(&m, 1, 0, 1e-9);    /* = 1 */
    mesh_add_vertex(&m, 0.5, 0.5, 0.0); /* kept */
    mesh_add_triangle(&m, 3, 4, 5);
    assert_int_equal(mesh_weld(&m, 1e-6), 2);
    assert_int_equal(m.nv, 4);
    assert_true(m.t[0] == 0 && m.t[1] == 1 && m.t[2] == 3);
    assert_true(m.v[9] == 0.5 && m.v[10] == 0.5);
    assert_int_equal(mesh_weld(&m, 0.0), 0);
    mesh_free(&m);
}

static void test_write_read_obj(void **state)
{
    mesh a, b;
    sl_err err = {{0}};
    const char *path = "tests/output/mesh_roundtrip.obj";
    (void)state;
    assert_int_equal(mesh_make_sphere(&a, (double[3]){0.1, 0.2, 0.3}, 0.7, 2, &err), 0);
    if (mesh_write_obj(&a, path, "icosphere level 2\nfor the round trip", &err))
        fail_msg("%s", err.msg);
    if (mesh_read(path, &b, &err)) fail_msg("%s", err.msg);
    assert_int_equal(a.nv, b.nv);
    assert_int_equal(a.nt, b.nt);
    assert_memory_equal(a.v, b.v, 3 * a.nv * sizeof *a.v);
    assert_memory_equal(a.t, b.t, 3 * a.nt * sizeof *a.t);
    assert_int_not_equal(mesh_write_obj(&a, "tests/output/no/such/dir/x.obj", NULL, &err), 0);
    assert_has(err.msg, "cannot write 'tests/output/no/such/dir/x.obj'");
    mesh_free(&a);
    mesh_free(&b);
}

static void test_primitives(void **state)
{
    mesh m;
    mesh_report r;
    sl_err err = {{0}};
    double c[3] = {1, 2, 3};
    (void)state;
    assert_int_equal(mesh_make_sphere(&m, c, 2.0, 4, &err), 0);
    assert_int_equal(m.nt, 20 * 256);
    for (size_t i = 0; i < m.nv; i++) {
        double d[3] = {m.v[3 * i] - c[0], m.v[3 * i + 1] - c[1], m.v[3 * i + 2] - c[2]};
        assert_true(fabs(norm3(d) - 2.0) < 1e-12);
    }
    assert_int_equal(mesh_validate(&m, "sphere", MESH_REQUIRE_CLOSED, &r, &err), 0);
    assert_int_equal(r.inverted + (int)r.reoriented + (int)r.degenerate, 0);
    assert_true(fabs(r.volume / (4.0 / 3.0 * M_PI * 8.0) - 1.0) < 0.01);
    mesh_free(&m);

    assert_int_equal(
        mesh_make_cylinder(&m, (double[3]){0, 0, 0}, (double[3]){1, 1, 1}, 0.25, 128, &err), 0);
    assert_int_equal(mesh_validate(&m, "cylinder", MESH_REQUIRE_CLOSED, &r, &err), 0);
    assert_int_equal(r.inverted + (int)r.reoriented, 0);
    assert_true(fabs(r.volume / (M_PI * 0.0625 * sqrt(3.0)) - 1.0) < 0.001);
    mesh_free(&m);

    assert_int_not_equal(mesh_make_sphere(&m, c, 1.0, 10, &err), 0);
    assert_has(err.msg, "level 0..9");
    assert_int_not_equal(mesh_make_sphere(&m, c, -1.0, 1, &err), 0);
    assert_int_not_equal(mesh_make_box(&m, (double[3]){0, 0, 0}, (double[3]){1, 0, 1}, &err), 0);
    assert_has(err.msg, "lo < hi");
    assert_int_not_equal(mesh_make_cylinder(&m, c, c, 1.0, 8, &err), 0);
    assert_int_not_equal(mesh_make_cylinder(&m, (double[3]){0, 0, 0}, c, 1.0, 2, &err), 0);
    assert_has(err.msg, "3..1000000 segments");
    mesh_free(&m);
}

/* ---- signed distance ------------------------------------------------------- */

static double box_distance(const double lo[3], const double hi[3], const double p[3])
{
    double out2 = 0.0, in = -INFINITY;
    for (int d = 0; d < 3; d++) {
        double a = lo[d] - p[d], b = p[d] - hi[d], m = a > b ? a : b;
        if (m > 0) out2 += m * m;
        if (m > in) in = m;
    }
    return out2 > 0 ? sqrt(out2) : in;
}

/* 12 triangles: exact up to round-off, also next to edges, corners and the
 * face diagonals (coplanar edges). */
static void test_distance_box(void **state)
{
    mesh m;
    sl_err err = {{0}};
    double lo[3] = {-0.3, 0.1, 0.2}, hi[3] = {0.7, 0.6, 1.4};
    uint64_t s = 42;
    (void)state;
    assert_int_equal(mesh_make_box(&m, lo, hi, &err), 0);
    for (int i = 0; i < 20000; i++) {
        double p[3];
        for (int d = 0; d < 3; d++) {
            p[d] = lo[d] - 0.5 + 2.0 * (hi[d] - lo[d] + 1.0) * uniform(&s) / 2.0;
            if (i % 4 == 0) p[d] = uniform(&s) < 0.5 ? lo[d] : hi[d]; /* on edges/corners */
        }
        if (i % 4 == 0) p[i / 4 % 3] += 1e-7 * (uniform(&s) - 0.5);
        double e = box_distance(lo, hi, p), d = mesh_signed_distance(&m, p);
        if (fabs(d - e) > 1e-12)
            fail_msg("(%g %g %g): %.17g, expected %.17g", p[0], p[1], p[2], d, e);
    }
    /* on the face diagonals, just inside and just outside */
    for (int i = 0; i <= 100; i++) {
        double t = i / 100.0,
               pin[3] = {lo[0] + t * (hi[0] - lo[0]), lo[1] + t * (hi[1] - lo[1]), lo[2] + 1e-9},
               pout[3] = {pin[0], pin[1], lo[2] - 1e-9};
        if (i == 0 || i == 100) continue;
        assert_true(mesh_signed_distance(&m, pin) < 0.0);
        assert_true(mesh_signed_distance(&m, pout) > 0.0);
    }
    mesh_free(&m);
}

/* Largest gap between the unit icosphere and the unit sphere. */
static double sag(const mesh *m)
{
    double s = 0.0;
    for (size_t j = 0; j < m->nt; j++) {
        double n[3];
        const double *a = m->v + 3 * m->t[3 * j];
        mesh_triangle_normal(m, j, n);
        s = fmax(s, 1.0 - fabs(n[0] * a[0] + n[1] * a[1] + n[2] * a[2]));
    }
    return s;
}

static void test_distance_sphere(void **state)
{
    mesh m;
    sl_err err = {{0}};
    uint64_t s = 7;
    double tol;
    size_t checked = 0;
    (void)state;
    assert_int_equal(mesh_make_sphere(&m, (double[3]){0, 0, 0}, 1.0, 5, &err), 0);
    tol = 2.0 * sag(&m);
    assert_true(tol < 2e-3);
    for (int i = 0; i < 20000; i++) {
        double p[3], r, d, b;
        for (int k = 0; k < 3; k++) p[k] = 4.0 * uniform(&s) - 2.0;
        if (i % 2) /* half of them close to the surface */
            for (int k = 0; k < 3; k++) p[k] *= (1.0 + 0.02 * (uniform(&s) - 0.5)) / norm3(p);
        r = norm3(p);
        d = mesh_signed_distance(&m, p);
        if (fabs(d - (r - 1.0)) > tol) fail_msg("r = %.17g: distance %.17g", r, d);
        if (fabs(r - 1.0) > tol) {
            assert_int_equal(mesh_inside(&m, p), r < 1.0);
            checked++;
        }
        /* the bounded query: exact below dmax, else the right sign */
        b = mesh_signed_distance_bounded(&m, p, 0.05);
        if (fabs(d) < 0.05) assert_true(b == d);
        else assert_true((b < 0) == (d < 0) && fabs(b) >= 0.05);
    }
    assert_true(checked > 10000);
    mesh_free(&m);
}

/* Generalised winding number (sum of solid angles / 4 pi), the reference
 * inside test for a closed mesh: 1 inside, 0 outside. */
static double winding(const mesh *m, const double p[3])
{
    double w = 0.0;
    for (size_t j = 0; j < m->nt; j++) {
        double a[3], b[3], c[3], la, lb, lc, num, den;
        for (int d = 0; d < 3; d++) {
            a[d] = m->v[3 * m->t[3 * j] + d] - p[d];
            b[d] = m->v[3 * m->t[3 * j + 1] + d] - p[d];
            c[d] = m->v[3 * m->t[3 * j + 2] + d] - p[d];
        }
        la = norm3(a);
        lb = norm3(b);
        lc = norm3(c);
        num = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
            a[2] * (b[0] * c[1] - b[1] * c[0]);
        den = la * lb * lc + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * lc +
            (a[0] * c[0] + a[1] * c[1] + a[2] * c[2]) * lb +
            (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]) * la;
        w += 2.0 * atan2(num, den);
    }
    return w / (4.0 * M_PI);
}

/* A sphere with a deep dent (concave), rotated: the sign of the distance
 * agrees with the winding number at random points, including points close
 * to the surface, its edges and vertices. */
static void test_inside_concave(void **state)
{
    mesh m;
    mesh_report r;
    sl_err err = {{0}};
    uint64_t s = 99;
    size_t inside = 0;
    (void)state;
    assert_int_equal(mesh_make_sphere(&m, (double[3]){0, 0, 0}, 1.0, 3, &err), 0);
    for (size_t i = 0; i < m.nv; i++) {
        double *v = m.v + 3 * i, d2 = (v[0] - 1) * (v[0] - 1) + v[1] * v[1] + v[2] * v[2];
        double f = 1.0 - 0.6 * exp(-d2 / 0.3);
        for (int d = 0; d < 3; d++) v[d] *= f;
    }
    assert_int_equal(mesh_rotate(&m, (double[3]){10, 20, 30}, &err), 0);
    assert_int_equal(mesh_validate(&m, "dented", MESH_REQUIRE_CLOSED, &r, &err), 0);
    for (int i = 0; i < 3000; i++) {
        double p[3], w, d;
        if (i % 3 == 0) { /* near a random vertex */
            const double *v = m.v + 3 * (size_t)(uniform(&s) * (double)m.nv);
            for (int k = 0; k < 3; k++) p[k] = v[k] + 1e-3 * (uniform(&s) - 0.5);
        } else {
            for (int k = 0; k < 3; k++) p[k] = 2.4 * uniform(&s) - 1.2;
        }
        d = mesh_signed_distance(&m, p);
        if (fabs(d) < 1e-9) continue;
        w = winding(&m, p);
        assert_true(fabs(w - 1.0) < 1e-6 || fabs(w) < 1e-6);
        if ((d < 0) != (w > 0.5))
            fail_msg("(%g %g %g): distance %g but winding number %g", p[0], p[1], p[2], d, w);
        assert_int_equal(mesh_inside(&m, p), d < 0);
        inside += d < 0;
    }
    assert_true(inside > 300);
    mesh_free(&m);
}

/* Filling: 100k lattice points against a 20k-triangle mesh in well under a
 * second (the timing is checked in release builds only). */
static void test_fill_speed(void **state)
{
    mesh m;
    sl_err err = {{0}};
    const int n = 47;
    const double h = 2.4 / n;
    size_t inside = 0;
    clock_t t0;
    double secs, vol;
    (void)state;
    assert_int_equal(mesh_make_sphere(&m, (double[3]){0, 0, 0}, 1.0, 5, &err), 0);
    t0 = clock();
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int k = 0; k < n; k++) {
                double p[3] = {-1.2 + (i + 0.5) * h, -1.2 + (j + 0.5) * h, -1.2 + (k + 0.5) * h};
                inside += mesh_signed_distance_bounded(&m, p, 0.5 * h) <= -0.5 * h;
            }
    secs = (double)(clock() - t0) / CLOCKS_PER_SEC;
    print_message("fill: %d lattice points against %zu triangles in %.3f s\n", n * n * n, m.nt,
                  secs);
    /* points at least h/2 inside a sphere of radius 1 - sag */
    vol = 4.0 / 3.0 * M_PI * pow(1.0 - 0.5 * h, 3);
    assert_true(fabs((double)inside * h * h * h / vol - 1.0) < 0.03);
#ifndef SL_DEBUG
    assert_true(secs < 1.0);
#endif
    mesh_free(&m);
}

/* ---- sampling --------------------------------------------------------------- */

static msample_quality sample(const mesh *m, double r0, msample_side side, sl_boundary *b)
{
    sl_err err = {{0}};
    msample_params p = msample_defaults(r0, side);
    size_t added;
    msample_quality q;
    prt_boundary_init(b);
    if (msample_surface(m, &p, 3, b, &added, &err)) fail_msg("%s", err.msg);
    assert_int_equal(added, b->n);
    q = msample_spacing(b->n, b->x, b->y, b->z);
    print_message("%s, r0 = %g: %zu particles, nearest-neighbour spacing min %.3f mean %.3f max "
                  "%.3f r0\n",
                  side == MSAMPLE_OBSTACLE ? "obstacle" : "container", r0, b->n, q.min / r0,
                  q.mean / r0, q.max / r0);
    assert_true(q.min >= 0.6 * r0 && q.max <= 1.4 * r0);
    assert_true(q.mean >= 0.85 * r0 && q.mean <= 1.15 * r0);
    for (size_t i = 0; i < b->n; i++) {
        double n[3] = {b->nx[i], b->ny[i], b->nz[i]};
        assert_true(fabs(norm3(n) - 1.0) < 1e-12);
        assert_int_equal(b->body[i], 3);
    }
    return q;
}

static void test_sample_sphere(void **state)
{
    mesh m;
    sl_err err = {{0}};
    sl_boundary b;
    const double r0 = 0.05, c[3] = {0.2, -0.1, 0.3};
    (void)state;
    assert_int_equal(mesh_make_sphere(&m, c, 1.0, 4, &err), 0);
    for (int side = 0; side < 2; side++) {
        double s = side ? -1.0 : 1.0, R = 1.0 - s * 0.5 * r0;
        sample(&m, r0, side ? MSAMPLE_CONTAINER : MSAMPLE_OBSTACLE, &b);
        /* about one particle per r0^2 of the offset sphere */
        assert_true(fabs((double)b.n * r0 * r0 / (4.0 * M_PI * R * R) - 1.0) < 0.1);
        for (size_t i = 0; i < b.n; i++) {
            double d[3] = {b.x[i] - c[0], b.y[i] - c[1], b.z[i] - c[2]}, r = norm3(d);
            double cosang = s * (d[0] * b.nx[i] + d[1] * b.ny[i] + d[2] * b.nz[i]) / r;
            assert_true(fabs(r - R) < 0.05 * r0); /* r0/2 behind the wall */
            assert_true(cosang > 0.99);           /* out of the body / into the tank */
        }
        prt_boundary_free(&b);
    }
    mesh_free(&m);
}

/* Largest signed distance to the face planes of a box: -depth inside. */
static double box_linf(const double lo[3], const double hi[3], const double p[3])
{
    double m = -INFINITY;
    for (int d = 0; d < 3; d++) m = fmax(m, fmax(lo[d] - p[d], p[d] - hi[d]));
    return m;
}

/* A box: every particle r0/2 behind the nearest face plane (the mitred
 * offset, as geometry.c samples boxes), one at each of the 8 offset corners
 * with the diagonal normal, particles away from edges with the exact face
 * normal. */
static void test_sample_box(void **state)
{
    mesh m;
    sl_err err = {{0}};
    sl_boundary b;
    const double r0 = 0.05, h = 0.5 * r0, lo[3] = {0, 0, 0}, hi[3] = {1.0, 0.6, 0.4};
    (void)state;
    assert_int_equal(mesh_make_box(&m, lo, hi, &err), 0);
    for (int side = 0; side < 2; side++) {
        double s = side ? -1.0 : 1.0; /* obstacle: inside the box, container: outside */
        int corners = 0;
        size_t faces = 0;
        sample(&m, r0, side ? MSAMPLE_CONTAINER : MSAMPLE_OBSTACLE, &b);
        for (size_t i = 0; i < b.n; i++) {
            double p[3] = {b.x[i], b.y[i], b.z[i]}, n[3] = {b.nx[i], b.ny[i], b.nz[i]};
            int near = 0, corner = 1;
            assert_true(fabs(box_linf(lo, hi, p) + s * h) < 1e-12);
            for (int k = 0; k < 3; k++) {
                double a = fabs(p[k] - (lo[k] + s * h)), z = fabs(p[k] - (hi[k] - s * h));
                near += fmin(a, z) < 1.5 * r0;
                corner &= fmin(a, z) < 1e-12;
            }
            if (corner) {
                corners++;
                for (int k = 0; k < 3; k++) {
                    double c = p[k] - 0.5 * (lo[k] + hi[k]);
                    assert_true(fabs(n[k] - s * copysign(1.0 / sqrt(3.0), c)) < 1e-12);
                }
            }
            if (near == 1) { /* away from edges: a face normal, pointing into the fluid */
                double out[3] = {0, 0, 0};
                for (int k = 0; k < 3; k++)
                    if (fabs(p[k] - (lo[k] + s * h)) < 1e-12) out[k] = -1.0;
                    else if (fabs(p[k] - (hi[k] - s * h)) < 1e-12) out[k] = 1.0;
                for (int k = 0; k < 3; k++) assert_true(fabs(n[k] - s * out[k]) < 1e-12);
                faces++;
            }
        }
        assert_int_equal(corners, 8);
        assert_true(faces > b.n / 2);
        prt_boundary_free(&b);
    }
    mesh_free(&m);
}

/* Feature loops (cylinder rims), reproducibility, open meshes, errors. */
static void test_sample_misc(void **state)
{
    mesh m;
    sl_err err = {{0}};
    sl_boundary a, b;
    msample_params p = msample_defaults(0.04, MSAMPLE_OBSTACLE);
    (void)state;
    assert_int_equal(
        mesh_make_cylinder(&m, (double[3]){0, 0, 0}, (double[3]){0, 0, 0.5}, 0.3, 96, &err), 0);
    sample(&m, 0.04, MSAMPLE_OBSTACLE, &a);
    sample(&m, 0.04, MSAMPLE_OBSTACLE, &b);
    assert_int_equal(a.n, b.n);
    assert_memory_equal(a.x, b.x, a.n * sizeof *a.x);
    assert_memory_equal(a.nz, b.nz, a.n * sizeof *a.nz);
    prt_boundary_free(&a);
    prt_boundary_free(&b);

    p.r0 = -1.0;
    prt_boundary_init(&a);
    assert_int_not_equal(msample_surface(&m, &p, 0, &a, NULL, &err), 0);
    assert_has(err.msg, "spacing r0 = -1");
    p = msample_defaults(0.04, MSAMPLE_OBSTACLE);
    p.relax = -3;
    assert_int_not_equal(msample_surface(&m, &p, 0, &a, NULL, &err), 0);
    assert_has(err.msg, "relax -3");
    assert_int_equal(a.n, 0);
    mesh_free(&m);

    /* an open box (no lid) still samples, lid rim as a feature line */
    assert_int_equal(mesh_read(BAD "open.obj", &m, &err), 0);
    assert_int_equal(mesh_validate(&m, "open.obj", 0, NULL, &err), 0);
    sample(&m, 0.1, MSAMPLE_CONTAINER, &a);
    assert_true(a.n > 400);
    prt_boundary_free(&a);
    mesh_free(&m);
}

/* Everything f(arg) prints on stderr (malloc'd). */
static char *stderr_of(void (*f)(void *), void *arg)
{
    fflush(stderr);
    FILE *tmp = tmpfile();
    assert_non_null(tmp);
    int saved = dup(2);
    dup2(fileno(tmp), 2);
    f(arg);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    long n = ftell(tmp);
    char *text = calloc((size_t)(n > 0 ? n : 0) + 1, 1);
    rewind(tmp);
    if (n > 0 && fread(text, 1, (size_t)n, tmp) != (size_t)n) text[0] = 0;
    fclose(tmp);
    return text;
}

/* A box of side 0.2 with each face cut into n x n squares (two triangles
 * each), outward; without its top face when `lid` is 0. */
static void fine_box(mesh *m, int n, int lid)
{
    static const double o[6][3] = {{0, 0, 0}, {0, 0, 0},   {0, 0.2, 0},
                                   {0, 0, 0}, {0.2, 0, 0}, {0, 0, 0.2}};
    static const double u[6][3] = {{0, .2, 0}, {.2, 0, 0}, {0, 0, .2},
                                   {0, 0, .2}, {0, .2, 0}, {.2, 0, 0}};
    static const double v[6][3] = {{.2, 0, 0}, {0, 0, .2}, {.2, 0, 0},
                                   {0, .2, 0}, {0, 0, .2}, {0, .2, 0}};
    mesh_init(m);
    for (int f = 0; f < (lid ? 6 : 5); f++)
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                uint32_t c[4];
                for (int k = 0; k < 4; k++) {
                    double a = (double)(i + (k == 1 || k == 2)) / n, b = (double)(j + (k >= 2)) / n;
                    c[k] = mesh_add_vertex(m, o[f][0] + a * u[f][0] + b * v[f][0],
                                           o[f][1] + a * u[f][1] + b * v[f][1],
                                           o[f][2] + a * u[f][2] + b * v[f][2]);
                }
                mesh_add_triangle(m, c[0], c[1], c[2]);
                mesh_add_triangle(m, c[0], c[2], c[3]);
            }
    mesh_weld(m, 1e-9);
}

typedef struct validate_job {
    mesh *m;
    int rc;
    size_t n;
} validate_job;

static void validate_and_sample(void *arg)
{
    validate_job *j = arg;
    sl_err err = {{0}};
    sl_boundary b;
    msample_params p = msample_defaults(0.025, MSAMPLE_OBSTACLE);
    prt_boundary_init(&b);
    j->rc = mesh_validate(j->m, "openbox.stl", MESH_WARN_OPEN, NULL, &err);
    if (j->rc == 0) j->rc = msample_surface(j->m, &p, 0, &b, &j->n, &err);
    prt_boundary_free(&b);
}

/* Issue 13, item 11: an open obstacle is reported as open, naming the
 * file; triangles that fold next to edges of a fine mesh are not blamed on
 * "parts thinner than r0" (a closed fine box says nothing of the kind). */
static void test_open_obstacle_reported(void **state)
{
    (void)state;
    mesh m;
    validate_job j = {&m, -1, 0};
    fine_box(&m, 30, 0);
    char *out = stderr_of(validate_and_sample, &j);
    assert_int_equal(j.rc, 0);
    assert_has(out,
               "Warning: openbox.stl: mesh is not closed: 120 edges are used by one "
               "triangle only");
    assert_has(out, "open sheet");
    if (strstr(out, "turns")) {
        assert_has(out, "at open rims");
        assert_has(out, " 0 in parts thinner than r0");
    }
    hostile_record("warned (the run goes on)", "an open obstacle mesh (a box without a lid)", out);
    free(out);
    mesh_free(&m);
    fine_box(&m, 30, 1);
    out = stderr_of(validate_and_sample, &j);
    assert_int_equal(j.rc, 0);
    if (strstr(out, "Warning")) fail_msg("a closed fine box warns: %s", out);
    free(out);
    mesh_free(&m);
}

typedef struct big_job {
    const char *path;
    mesh *m;
    int rc;
} big_job;

static void read_and_validate(void *arg)
{
    big_job *j = arg;
    sl_err err = {{0}};
    j->rc = mesh_read(j->path, j->m, &err);
    if (j->rc == 0) j->rc = mesh_validate(j->m, j->path, MESH_QUIET, NULL, &err);
}

/* Long mesh work shows progress and the time left (sl_progress lines, due
 * at once here through SLUICE_PROGRESS_PERIOD); small meshes stay silent. */
static void test_mesh_progress(void **state)
{
    (void)state;
    mesh m;
    sl_err err = {{0}};
    fine_box(&m, 100, 1); /* 120000 triangles */
    assert_int_equal(mesh_write_obj(&m, "tests/output/mesh_big.obj", NULL, &err), 0);
    mesh_free(&m);
    setenv("SLUICE_PROGRESS", "plain", 1);
    setenv("SLUICE_PROGRESS_PERIOD", "1e-9", 1);
    big_job j = {"tests/output/mesh_big.obj", &m, -1};
    char *out = stderr_of(read_and_validate, &j);
    assert_int_equal(j.rc, 0);
    assert_int_equal(m.nt, 120000);
    assert_has(out, "Progress: reading tests/output/mesh_big.obj (");
    assert_has(out, "Progress: indexing a mesh of 120000 triangles");
    assert_has(out, " %  wall ");
    assert_has(out, "ETA ");
    free(out);
    mesh_free(&m);
    j.path = DATA "cube_ascii.stl";
    out = stderr_of(read_and_validate, &j);
    assert_int_equal(j.rc, 0);
    if (strstr(out, "Progress")) fail_msg("a 12-triangle mesh shows progress: %s", out);
    free(out);
    mesh_free(&m);
    unsetenv("SLUICE_PROGRESS");
    unsetenv("SLUICE_PROGRESS_PERIOD");
}

static void test_spacing(void **state)
{
    double x[100], y[100], z[100];
    msample_quality q;
    (void)state;
    for (int i = 0; i < 100; i++) {
        x[i] = 0.1 * (i % 10);
        y[i] = 0.1 * (i / 10);
        z[i] = 5.0;
    }
    q = msample_spacing(100, x, y, z);
    assert_true(fabs(q.min - 0.1) < 1e-12 && fabs(q.mean - 0.1) < 1e-12 &&
                fabs(q.max - 0.1) < 1e-12);
    x[99] = 5.0; /* an outlier far away */
    q = msample_spacing(100, x, y, z);
    assert_true(q.max > 4.0);
    q = msample_spacing(1, x, y, z);
    assert_true(q.min == 0.0 && q.max == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_read_ascii_stl),
        cmocka_unit_test(test_read_binary_stl),
        cmocka_unit_test(test_read_obj_quads),
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_open_mesh),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_inverted_and_inconsistent),
        cmocka_unit_test(test_validate_errors),
        cmocka_unit_test(test_transforms),
        cmocka_unit_test(test_weld),
        cmocka_unit_test(test_write_read_obj),
        cmocka_unit_test(test_primitives),
        cmocka_unit_test(test_distance_box),
        cmocka_unit_test(test_distance_sphere),
        cmocka_unit_test(test_inside_concave),
        cmocka_unit_test(test_fill_speed),
        cmocka_unit_test(test_sample_sphere),
        cmocka_unit_test(test_sample_box),
        cmocka_unit_test(test_sample_misc),
        cmocka_unit_test(test_open_obstacle_reported),
        cmocka_unit_test(test_mesh_progress),
        cmocka_unit_test(test_spacing),
    };
    sl_log_set_quiet(1);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
