/*
 * Tests of the surface reconstruction (libsrc/surface, reconstructSurface,
 * vtk_write_triangles; issue 19):
 *   - every one of the 256 cube patterns, in random fields, gives a closed
 *     surface whose every edge is used once in each direction (so it is
 *     consistently oriented), for a 1-thread and a 2-thread run alike;
 *   - a resting ball of fluid (a lattice ball, no gravity) reconstructs to a
 *     closed surface with area and volume within 2 % of the sphere of the
 *     fluid's volume N r0^3, the error falling as the grid is refined;
 *   - the .vtp reads back in VTK (tests/unit/surface_check.py with
 *     /usr/bin/python3) as the same closed surface, with velocity and
 *     pressure;
 *   - over a short dam break (bin/pcisph then bin/reconstructSurface) every
 *     written surface is closed, encloses N r0^3 within SRF_DAM_VOLUME and no
 *     particle lies more than r0 outside it (VTK's ray casting and signed
 *     distance); the table postProcessing/surface/0/surface.dat has a row per
 *     time, and a -gauge column the column's height at t = 0;
 *     -parallel writes the same files;
 *   - a bad system/surfaceDict stops with file, line and keyword.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "hostile_table.h"
#include "tool_run.h"

#include "core/sl_mem.h"
#include "io/vtk_writer.h"
#include "surface/surface.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OUT "tests/output/surface"
#define PY  "/usr/bin/python3 tests/unit/surface_check.py"
/* The dam break's surfaces enclose N r0^3 within this fraction. */
#define SRF_DAM_VOLUME 0.03

/* ---- helpers ---- */

static int cmp_edge(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Every directed edge a->b has exactly one b->a and is itself used once:
 * closed and consistently oriented. */
static void assert_closed_oriented(const srf_mesh *m)
{
    size_t ne = 3 * m->nt;
    uint64_t *fw = malloc((ne + 1) * sizeof *fw), *bw = malloc((ne + 1) * sizeof *bw);
    for (size_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = (uint64_t)m->tri[3 * t + k], b = (uint64_t)m->tri[3 * t + (k + 1) % 3];
            fw[3 * t + k] = a << 32 | b;
            bw[3 * t + k] = b << 32 | a;
        }
    qsort(fw, ne, sizeof *fw, cmp_edge);
    qsort(bw, ne, sizeof *bw, cmp_edge);
    for (size_t i = 0; i < ne; i++) {
        if (i > 0) assert_true(fw[i] != fw[i - 1]);
        assert_true(fw[i] == bw[i]);
    }
    assert_int_equal(srf_open_edges(m, NULL), 0);
    free(fw);
    free(bw);
}

static void assert_same_mesh(const srf_mesh *a, const srf_mesh *b)
{
    assert_int_equal(a->nv, b->nv);
    assert_int_equal(a->nt, b->nt);
    assert_memory_equal(a->x, b->x, a->nv * sizeof(double));
    assert_memory_equal(a->y, b->y, a->nv * sizeof(double));
    assert_memory_equal(a->z, b->z, a->nv * sizeof(double));
    assert_memory_equal(a->tri, b->tri, 3 * a->nt * sizeof(int64_t));
}

/* ---- marching cubes on random fields ---- */

static void test_random_fields_closed(void **state)
{
    (void)state;
    const int n = 14;
    srf_grid g = {{0, 0, 0}, 1.0, {n, n, n}, malloc((size_t)(n * n * n) * sizeof(float))};
    int seen[256] = {0}, patterns = 0;
    unsigned seed = 12345;
    for (int trial = 0; trial < 40; trial++) {
        for (int k = 0; k < n; k++)
            for (int j = 0; j < n; j++)
                for (int i = 0; i < n; i++) {
                    seed = seed * 1103515245u + 12345u;
                    const int border =
                        i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
                    g.f[(k * n + j) * n + i] =
                        border ? 0.0f : (float)((seed >> 16) % 1000) / 1000.0f;
                }
        for (int k = 0; k + 1 < n; k++)
            for (int j = 0; j + 1 < n; j++)
                for (int i = 0; i + 1 < n; i++) {
                    int pat = 0;
                    for (int c = 0; c < 8; c++)
                        pat |= (g.f[((k + (c >> 2 & 1)) * n + j + (c >> 1 & 1)) * n + i + (c & 1)] >
                                0.5f)
                            << c;
                    if (!seen[pat]++) patterns++;
                }
        srf_mesh m1, m2;
        omp_set_num_threads(1);
        srf_contour(&g, 0.5, &m1);
        omp_set_num_threads(2);
        srf_contour(&g, 0.5, &m2);
        assert_true(m1.nt > 0);
        assert_closed_oriented(&m1);
        assert_same_mesh(&m1, &m2);
        assert_true(srf_volume(&m1) > 0);
        srf_mesh_free(&m1);
        srf_mesh_free(&m2);
    }
    print_message("random fields: %d of 256 patterns met, every surface closed and oriented\n",
                  patterns);
    assert_int_equal(patterns, 256);
    free(g.f);
}

/* ---- the resting ball ---- */

typedef struct ball {
    size_t n;
    double *x, *y, *z, *vx, *vy, *vz, *p;
    double r0;
} ball;

/* Lattice points of spacing r0 within radius R r0 of a point off the
 * lattice; velocity (1, 2, 3) and pressure 5 everywhere. */
static ball make_ball(double R, double r0)
{
    ball b = {0};
    int m = (int)R + 2;
    size_t cap = (size_t)(2 * m + 1) * (size_t)(2 * m + 1) * (size_t)(2 * m + 1);
    b.r0 = r0;
    b.x = malloc(cap * sizeof(double));
    b.y = malloc(cap * sizeof(double));
    b.z = malloc(cap * sizeof(double));
    b.vx = malloc(cap * sizeof(double));
    b.vy = malloc(cap * sizeof(double));
    b.vz = malloc(cap * sizeof(double));
    b.p = malloc(cap * sizeof(double));
    const double c[3] = {0.31, 0.17, 0.23};
    for (int k = -m; k <= m; k++)
        for (int j = -m; j <= m; j++)
            for (int i = -m; i <= m; i++) {
                double dx = i - c[0], dy = j - c[1], dz = k - c[2];
                if (dx * dx + dy * dy + dz * dz > R * R) continue;
                b.x[b.n] = i * r0 + 1.0;
                b.y[b.n] = j * r0 - 2.0;
                b.z[b.n] = k * r0 + 0.5;
                b.vx[b.n] = 1;
                b.vy[b.n] = 2;
                b.vz[b.n] = 3;
                b.p[b.n] = 5;
                b.n++;
            }
    return b;
}

static void free_ball(ball *b)
{
    free(b->x);
    free(b->y);
    free(b->z);
    free(b->vx);
    free(b->vy);
    free(b->vz);
    free(b->p);
}

static srf_particles ball_particles(const ball *b)
{
    srf_particles p = {b->n, b->x, b->y, b->z, b->vx, b->vy, b->vz, b->p, b->r0};
    return p;
}

/* The ball's volume and area errors (fractions) against the sphere of
 * volume N r0^3, at grid spacing `dx` and kernel radius `h` (units of r0). */
static void ball_errors(const ball *b, double dx, double h, double drop, int aniso, double *ev,
                        double *ea)
{
    srf_particles p = ball_particles(b);
    const double vol = (double)b->n * pow(b->r0, 3), R = cbrt(3 * vol / (4 * M_PI));
    srf_params prm;
    srf_mesh m;
    sl_err err;
    srf_params_default(&prm);
    prm.grid_spacing = dx;
    prm.kernel_radius = h;
    prm.droplet_radius = drop;
    prm.anisotropic = aniso;
    assert_int_equal(srf_reconstruct(&p, &prm, &m, &err), 0);
    assert_closed_oriented(&m);
    *ev = srf_volume(&m) / vol - 1;
    *ea = srf_area(&m) / (4 * M_PI * R * R) - 1;
    print_message("ball of %zu particles, %s kernel radius %.1f r0, dropletRadius %.1f r0, grid "
                  "%.2f r0: %zu triangles, volume %+.3f %%, area %+.3f %% of the sphere of volume "
                  "N r0^3\n",
                  b->n, aniso ? "anisotropic" : "isotropic", h, drop, dx, m.nt, 100 * *ev,
                  100 * *ea);
    for (size_t v = 0; v < m.nv; v++) {
        assert_true(fabs(m.vx[v] - 1) < 1e-12 && fabs(m.vy[v] - 2) < 1e-12);
        assert_true(fabs(m.vz[v] - 3) < 1e-12 && fabs(m.p[v] - 5) < 1e-12);
    }
    srf_mesh_free(&m);
}

/* A ball of radius 12 r0 (7245 particles) with kernelRadius 3 (and no
 * droplet balls: the colour field alone): area and volume within 2 %, both
 * errors falling as the grid goes 1, 1/2, 1/4 r0.
 * Yu & Turk's anisotropic kernels at h = 2 r0 within 2 % at grid r0/2.
 * With the solver's h = 2 r0 (the default) the lattice's terraces show in
 * the colour field itself, so the area error does not fall below about
 * +1.2 % (R = 8 r0) with the grid: the defaults are checked within 2 % at
 * the default grid. */
static void test_ball_area_volume(void **state)
{
    (void)state;
    ball b = make_ball(12.0, 0.01);
    const double spacing[] = {1.0, 0.5, 0.25};
    double ev[3], ea[3];
    for (int s = 0; s < 3; s++) {
        ball_errors(&b, spacing[s], 3.0, 0.0, 0, &ev[s], &ea[s]);
        assert_true(fabs(ev[s]) < 0.02);
        assert_true(fabs(ea[s]) < 0.02);
        if (s > 0) {
            assert_true(fabs(ev[s]) < fabs(ev[s - 1]));
            assert_true(fabs(ea[s]) < fabs(ea[s - 1]));
        }
    }
    /* Yu & Turk's kernels at the solver's h (measured +1.16 %, +1.54 %) */
    ball_errors(&b, 0.5, 2.0, 0.5, 1, &ev[0], &ea[0]);
    assert_true(fabs(ev[0]) < 0.02);
    assert_true(fabs(ea[0]) < 0.02);
    free_ball(&b);
    b = make_ball(8.0, 0.01);
    ball_errors(&b, 0.5, 2.0, 0.5, 0, &ev[0], &ea[0]);
    assert_true(fabs(ev[0]) < 0.02);
    assert_true(fabs(ea[0]) < 0.02);
    free_ball(&b);
}

/* A lone particle beside a ball: its colour stays below isoValue, yet it
 * keeps a closed ball of its own of radius dropletRadius (and with
 * dropletRadius 0 it vanishes). */
static void test_lone_drop_kept(void **state)
{
    (void)state;
    ball b = make_ball(5.0, 0.01);
    b.x[b.n] = 1.0 + 0.2; /* 20 r0 from the ball's centre */
    b.y[b.n] = -2.0;
    b.z[b.n] = 0.5;
    b.vx[b.n] = b.vy[b.n] = b.vz[b.n] = 0;
    b.p[b.n] = 0;
    b.n++;
    srf_particles p = ball_particles(&b);
    for (int on = 0; on < 2; on++) {
        srf_params prm;
        srf_mesh m;
        sl_err err;
        srf_params_default(&prm);
        if (!on) prm.droplet_radius = 0;
        assert_int_equal(srf_reconstruct(&p, &prm, &m, &err), 0);
        assert_closed_oriented(&m);
        size_t near = 0;
        double far = 0;
        for (size_t v = 0; v < m.nv; v++) {
            double d = hypot(hypot(m.x[v] - 1.2, m.y[v] + 2.0), m.z[v] - 0.5);
            if (d < 0.01) {
                near++;
                if (d > far) far = d;
            }
        }
        if (on) {
            assert_true(near >= 6);
            assert_true(fabs(far - 0.5 * 0.01) < 0.2 * 0.01);
        } else {
            assert_int_equal(near, 0);
        }
        print_message("lone particle, dropletRadius %.1f r0 (at least the grid step r0/2): %zu "
                      "vertices within r0 of it, the farthest %.2f r0\n",
                      on ? 0.5 : 0.0, near, far / 0.01);
        srf_mesh_free(&m);
    }
    free_ball(&b);
}

static void test_ball_same_for_any_threads(void **state)
{
    (void)state;
    ball b = make_ball(6.0, 0.02);
    srf_particles p = ball_particles(&b);
    srf_params prm;
    srf_mesh m1, m2;
    sl_err err;
    for (int aniso = 0; aniso < 2; aniso++) {
        srf_params_default(&prm);
        prm.smoothing = 2;
        prm.anisotropic = aniso;
        omp_set_num_threads(1);
        assert_int_equal(srf_reconstruct(&p, &prm, &m1, &err), 0);
        omp_set_num_threads(2);
        assert_int_equal(srf_reconstruct(&p, &prm, &m2, &err), 0);
        assert_same_mesh(&m1, &m2);
        assert_memory_equal(m1.vx, m2.vx, m1.nv * sizeof(double));
        assert_memory_equal(m1.p, m2.p, m1.nv * sizeof(double));
        assert_closed_oriented(&m1);
        srf_mesh_free(&m1);
        srf_mesh_free(&m2);
    }
    free_ball(&b);
}

static int have_vtk(void)
{
    return run("/usr/bin/python3 -c 'import vtkmodules.vtkIOXML, vtkmodules.vtkFiltersCore'") == 0;
}

static double value_of(const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "%s=", key);
    const char *at = output;
    double v = NAN;
    while ((at = strstr(at, pat))) {
        if (at == output || at[-1] == '\n') v = strtod(at + strlen(pat), NULL);
        at++;
    }
    return v;
}

static void test_ball_vtp_reads_back_in_vtk(void **state)
{
    (void)state;
    if (!have_vtk()) {
        print_message("no python3-vtk9 for /usr/bin/python3: skipped\n");
        skip();
    }
    assert_int_equal(run("rm -rf " OUT "/ball && mkdir -p " OUT "/ball"), 0);
    ball b = make_ball(8.0, 0.01);
    srf_particles p = ball_particles(&b);
    srf_params prm;
    srf_mesh m;
    sl_err err;
    srf_params_default(&prm);
    assert_int_equal(srf_reconstruct(&p, &prm, &m, &err), 0);
    vtk_field f[2] = {{"velocity", 3, VTK_FLOAT64, {m.vx, m.vy, m.vz}},
                      {"pressure", 1, VTK_FLOAT64, {m.p, NULL, NULL}}};
    for (int ascii = 0; ascii < 2; ascii++) {
        vtk_options o;
        vtk_options_default(&o);
        o.ascii = ascii;
        o.time = 0.5;
        assert_int_equal(vtk_write_triangles(OUT "/ball/surface.vtp", m.nv, m.x, m.y, m.z, m.nt,
                                             m.tri, f, 2, &o, &err),
                         0);
        assert_int_equal(run(PY " " OUT "/ball/surface.vtp"), 0);
        assert_int_equal((size_t)value_of("points"), m.nv);
        assert_int_equal((size_t)value_of("triangles"), m.nt);
        assert_int_equal(value_of("open_edges"), 0);
        assert_true(fabs(value_of("volume") / srf_volume(&m) - 1) < 1e-9);
        assert_true(fabs(value_of("area") / srf_area(&m) - 1) < 1e-9);
        assert_int_equal(value_of("velocity"), 1);
        assert_int_equal(value_of("pressure"), 1);
    }
    /* a triangle naming a point that is not there is refused, nothing written */
    m.tri[5] = (int64_t)m.nv;
    assert_int_not_equal(vtk_write_triangles(OUT "/ball/bad.vtp", m.nv, m.x, m.y, m.z, m.nt, m.tri,
                                             f, 2, NULL, &err),
                         0);
    assert_non_null(strstr(err.msg, "refers to point"));
    assert_int_not_equal(run("test -e " OUT "/ball/bad.vtp"), 0);
    srf_mesh_free(&m);
    free_ball(&b);
}

/* ---- the dam break, through the programs ---- */

#define DAM OUT "/damBreak"

static void run_dam_break(void)
{
    static int done;
    if (done) return;
    /* the tutorial with a coarser lattice, 0.3 s written every 0.05 s */
    assert_int_equal(
        run("rm -rf " DAM " && mkdir -p " OUT " && cp -r tutorials/damBreak " DAM " && cd " DAM
            " && sed -i 's/^particleSpacing .*/particleSpacing 0.03;/' constant/fluidProperties"
            " && sed -i 's/^endTime .*/endTime 0.3;/; s/^writeInterval .*/writeInterval 0.05;/'"
            " system/controlDict && %s/pcisph -case . -quiet > log.pcisph 2>&1",
            bin_dir()),
        0);
    done = 1;
}

static void test_dam_break_surfaces(void **state)
{
    (void)state;
    if (!have_vtk()) {
        print_message("no python3-vtk9 for /usr/bin/python3: skipped\n");
        skip();
    }
    run_dam_break();
    assert_int_equal(run("cd " DAM " && %s/reconstructSurface -gauge '0.2 0.3' -gauge '5 5' "
                         "> log.reconstructSurface 2>&1",
                         bin_dir()),
                     0);
    assert_int_equal(run("test -f " DAM "/surface.pvd && test -f " DAM "/surface.vtp.series"), 0);
    /* the measurements table: a header, then one row per time in time order */
    assert_int_equal(run("grep -v '^#' " DAM "/postProcessing/surface/0/surface.dat | cut -f1 | "
                         "tr '\\n' ' '"),
                     0);
    assert_string_equal(output, "0 0.05 0.1 0.15 0.2 0.25 0.3 ");
    /* the gauge in the column: at t = 0 its top, 0.6 m (the colour field puts a
     * flat surface half a spacing beyond the last layer, at 0.6 - r0/2);
     * the line through (5, 5) misses the fluid */
    assert_int_equal(
        run("awk '$1 == \"0\" {print $8, $9}' " DAM "/postProcessing/surface/0/surface.dat"), 0);
    print_message("surface height above (0.2, 0.3) at t = 0 and beside the tank: %s", output);
    assert_true(fabs(strtod(output, NULL) - 0.6) < 0.25 * 0.03);
    assert_non_null(strstr(output, "nan"));
    const double r0 = 0.03;
    const char *times[] = {"0", "0.05", "0.1", "0.15", "0.2", "0.25", "0.3"};
    for (size_t i = 0; i < sizeof times / sizeof *times; i++) {
        assert_int_equal(run(PY " " DAM "/%s/surface.vtp " DAM "/%s/fluid.vtu", times[i], times[i]),
                         0);
        const double n = value_of("particles"), vol = value_of("volume") / (n * r0 * r0 * r0);
        const double out = value_of("max_outside") / r0;
        print_message("dam break t = %s: %.0f particles, %.0f triangles, volume %.2f %% of N r0^3, "
                      "%.0f particles outside, the farthest %.3f r0\n",
                      times[i], n, value_of("triangles"), 100 * vol, value_of("outside"), out);
        assert_int_equal(value_of("open_edges"), 0);
        assert_true(fabs(vol - 1) < SRF_DAM_VOLUME);
        assert_true(out < 1.0);
        assert_int_equal(run("grep -c 'file=\"%s/surface.vtp\"' " DAM "/surface.pvd", times[i]), 0);
    }
}

static void test_dam_break_parallel_same_files(void **state)
{
    (void)state;
    run_dam_break();
    assert_int_equal(run("cd " DAM " && %s/reconstructSurface -time 0.1,0.3 > /dev/null 2>&1 && "
                         "cp 0.1/surface.vtp s1 && cp 0.3/surface.vtp s3 && "
                         "%s/reconstructSurface -parallel -time 0.1,0.3 > /dev/null 2>&1 && "
                         "cmp s1 0.1/surface.vtp && cmp s3 0.3/surface.vtp",
                         bin_dir(), bin_dir()),
                     0);
    /* the collection still lists every surface, not only the two redone */
    assert_int_equal(run("grep -c DataSet " DAM "/surface.pvd"), 0);
    assert_int_equal(atoi(output), 7);
}

static void test_bad_surface_dict(void **state)
{
    (void)state;
    run_dam_break();
    static const struct {
        const char *text, *key, *why;
    } bad[] = {
        {"isoValue 1.5;", "isoValue", "between 0 and 1"},
        {"gridSpacing 0;", "gridSpacing", "positive"},
        {"gridSpacing abc;", "gridSpacing", "expected a number"},
        {"smoothing 50;", "smoothing", "between 0 and"},
        {"kernelRadius 0.5;", "kernelRadius", "between 1 and 6"},
        {"dropletRadius 1.5;", "dropletRadius", "kernelRadius / 2"},
        {"kernel elliptic;", "kernel", "isotropic anisotropic"},
        {"maxStretch 0.5;", "maxStretch", "between 1 and 16"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char text[256];
        snprintf(text, sizeof text, "FoamFile { object surfaceDict; }\n\n%s\n", bad[i].text);
        spit(DAM "/system/surfaceDict", text);
        assert_int_not_equal(run("%s/reconstructSurface -case " DAM " -latestTime", bin_dir()), 0);
        assert_non_null(strstr(output, "surfaceDict:3"));
        assert_non_null(strstr(output, bad[i].key));
        assert_non_null(strstr(output, bad[i].why));
        hostile_record("surfaceDict value", bad[i].text, output);
    }
    spit(DAM "/system/surfaceDict", "FoamFile { object surfaceDict; }\nisoValu 0.4;\n");
    assert_int_equal(run("%s/reconstructSurface -case " DAM " -latestTime", bin_dir()), 0);
    assert_non_null(strstr(output, "did you mean 'isoValue'"));
    hostile_record("surfaceDict value", "isoValu 0.4; (misspelt)", output);
    assert_int_equal(run("rm " DAM "/system/surfaceDict"), 0);
}

/* etc/caseDicts/surfaceDict holds exactly the compiled defaults. */
static void test_annotated_dict_is_the_defaults(void **state)
{
    (void)state;
    sl_err err;
    dict *d = dict_read_file("etc/caseDicts/surfaceDict", &err);
    assert_non_null(d);
    srf_params a, def;
    srf_params_read(d, &a);
    srf_params_default(&def);
    assert_true(a.grid_spacing == def.grid_spacing && a.iso_value == def.iso_value);
    assert_true(a.kernel_radius == def.kernel_radius && a.smoothing == def.smoothing);
    assert_true(a.droplet_radius == def.droplet_radius && a.anisotropic == def.anisotropic);
    assert_true(a.anisotropy_radius == def.anisotropy_radius && a.max_stretch == def.max_stretch);
    assert_true(a.min_neighbours == def.min_neighbours);
    for (const char *const *k = srf_keys; *k; k++) assert_true(dict_has(d, *k));
    dict_free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_annotated_dict_is_the_defaults),
        cmocka_unit_test(test_random_fields_closed),
        cmocka_unit_test(test_ball_area_volume),
        cmocka_unit_test(test_lone_drop_kept),
        cmocka_unit_test(test_ball_same_for_any_threads),
        cmocka_unit_test(test_ball_vtp_reads_back_in_vtk),
        cmocka_unit_test(test_dam_break_surfaces),
        cmocka_unit_test(test_dam_break_parallel_same_files),
        cmocka_unit_test(test_bad_surface_dict),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
