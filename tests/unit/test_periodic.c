/* Periodic boundaries (issue 17): a block flowing through a fully
 * periodic box keeps its mass exactly and its momentum to round-off; a
 * block in a periodic channel (walls across y and z, gravity) gives the
 * same motion wherever along the period it starts (translation by 12
 * particle spacings, across the face); the result does not depend on the
 * thread count; the reader refuses what periodic images cannot honour,
 * naming file, line and keyword. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "case_run.h"
#include "io/vtk_reader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct state_at {
    size_t n;
    double *x, *v; /* by id: x[3 id + k] */
} state_at;

static void read_state(const char *name, const char *time, state_at *s)
{
    char path[512];
    vtkr_file f;
    sl_err err;
    snprintf(path, sizeof path, "tests/output/%s/%s/fluid.vtu", name, time);
    if (vtkr_read(path, &f, &err)) fail_msg("%s", err.msg);
    const vtkr_array *id = vtkr_find(&f, "id"), *v = vtkr_find(&f, "velocity");
    assert_non_null(id);
    assert_non_null(v);
    s->n = f.npoints;
    s->x = calloc(3 * s->n, sizeof *s->x);
    s->v = calloc(3 * s->n, sizeof *s->v);
    for (size_t i = 0; i < s->n; i++) {
        const size_t k = (size_t)id->data[i];
        assert_true(k < s->n); /* ids are 0..n-1: no particle lost or doubled */
        for (int d = 0; d < 3; d++) {
            s->x[3 * k + d] = f.points[3 * i + d];
            s->v[3 * k + d] = v->data[3 * i + d];
        }
    }
    vtkr_free(&f);
}

static void free_state(state_at *s)
{
    free(s->x);
    free(s->v);
}

static const char *threads1 =
    "sed -i 's/^numberOfThreads .*/numberOfThreads 1;/' system/controlDict";

static void test_box_keeps_mass_and_momentum(void **state)
{
    (void)state;
    state_at a, b;
    assert_int_equal(run_edited("tests/cases/periodicBox", "periodicBox", threads1), 0);
    read_state("periodicBox", "0", &a);
    read_state("periodicBox", "0.3", &b);
    assert_int_equal(a.n, b.n);
    assert_int_equal(a.n, 1100);
    double pa[3] = {0, 0, 0}, pb[3] = {0, 0, 0}, xmin = INFINITY, vmax = 0;
    for (size_t i = 0; i < a.n; i++)
        for (int d = 0; d < 3; d++) {
            pa[d] += a.v[3 * i + d];
            pb[d] += b.v[3 * i + d];
            vmax = fmax(vmax, fabs(a.v[3 * i + d]));
            if (d == 0) xmin = fmin(xmin, b.x[3 * i]);
            assert_true(b.x[3 * i + d] >= 0.0 && b.x[3 * i + d] < (d ? 0.2 : 0.4)); /* wrapped */
        }
    /* round-off: 1e-12 of the largest sum a particle's velocities could make */
    for (int d = 0; d < 3; d++) {
        print_message("momentum/m %c: %.17g -> %.17g\n", "xyz"[d], pa[d], pb[d]);
        assert_true(fabs(pb[d] - pa[d]) <= 1e-12 * (double)a.n * vmax);
    }
    assert_true(xmin < 0.1); /* the fast block crossed the face (it started at x >= 0.28) */
    free_state(&a);
    free_state(&b);
}

/* The largest change of the fluid's momentum per unit mass over the box's
 * run (edit: on top of one thread), in units of the largest sum a
 * particle's velocities could make (n vmax). */
static double box_momentum_drift(const char *name, const char *edit)
{
    char cmd[1024];
    state_at a, b;
    snprintf(cmd, sizeof cmd, "%s && %s", threads1, edit);
    assert_int_equal(run_edited("tests/cases/periodicBox", name, cmd), 0);
    read_state(name, "0", &a);
    read_state(name, "0.3", &b);
    assert_int_equal(a.n, b.n);
    double pa[3] = {0, 0, 0}, pb[3] = {0, 0, 0}, vmax = 0, drift = 0;
    for (size_t i = 0; i < a.n; i++)
        for (int d = 0; d < 3; d++) {
            pa[d] += a.v[3 * i + d];
            pb[d] += b.v[3 * i + d];
            vmax = fmax(vmax, fabs(a.v[3 * i + d]));
        }
    for (int d = 0; d < 3; d++) drift = fmax(drift, fabs(pb[d] - pa[d]));
    drift /= (double)a.n * vmax;
    print_message("%s: momentum drift %.3g of n vmax\n", name, drift);
    free_state(&a);
    free_state(&b);
    return drift;
}

/* pressureForce correctedConservative (each pair's term times (L_i + L_j)
 * / 2) keeps the box's momentum to round-off, as the symmetric force;
 * corrected (L_i on i's force alone, where the neighbourhood is isotropic:
 * the blocks' surfaces are not) does not, so the bound can fail. */
static void test_conservative_force_keeps_momentum(void **state)
{
    (void)state;
    const char *cons = "echo 'pressureForce correctedConservative;' >> constant/fluidProperties";
    const char *corr = "echo 'pressureForce corrected;' >> constant/fluidProperties";
    assert_true(box_momentum_drift("periodicBoxConservative", cons) <= 1e-12);
    assert_true(box_momentum_drift("periodicBoxCorrected", corr) > 1e-6);
}

static void test_channel_is_translation_invariant(void **state)
{
    (void)state;
    state_at a, b;
    char edit[512];
    snprintf(edit, sizeof edit,
             "%s && sed -i 's/min (0.24 0 0); max (0.4 0.12 0.1)/min (0 0 0); "
             "max (0.16 0.12 0.1)/' constant/fluidProperties",
             threads1);
    assert_int_equal(run_edited("tests/cases/periodicChannel", "periodicChannelA", threads1), 0);
    assert_int_equal(run_edited("tests/cases/periodicChannel", "periodicChannelB", edit), 0);
    read_state("periodicChannelA", "0.1", &a);
    read_state("periodicChannelB", "0.1", &b);
    assert_int_equal(a.n, 240);
    assert_int_equal(b.n, 240);
    double dmax = 0, crossed = 0;
    for (size_t i = 0; i < a.n; i++) {
        double dx = a.x[3 * i] - b.x[3 * i] - 0.24;
        dx -= 0.4 * round(dx / 0.4);
        dmax = fmax(dmax, fabs(dx));
        dmax = fmax(dmax, fabs(a.x[3 * i + 1] - b.x[3 * i + 1]));
        dmax = fmax(dmax, fabs(a.x[3 * i + 2] - b.x[3 * i + 2]));
        crossed += a.x[3 * i] < 0.2; /* block A started at x >= 0.24 */
    }
    print_message("translated channel: largest difference %.3g m, %g particles crossed\n", dmax,
                  crossed);
    assert_true(crossed > 0);
    assert_true(dmax < 1e-11); /* 100 steps; measured 5e-15 */
    free_state(&a);
    free_state(&b);
}

static void test_threads_give_identical_files(void **state)
{
    (void)state;
    const char *two = "sed -i 's/^numberOfThreads .*/numberOfThreads 2;/' system/controlDict";
    assert_int_equal(run_edited("tests/cases/periodicChannel", "periodicChannel1", threads1), 0);
    assert_int_equal(run_edited("tests/cases/periodicChannel", "periodicChannel2", two), 0);
    assert_int_equal(system("cmp tests/output/periodicChannel1/0.3/fluid.vtu "
                            "tests/output/periodicChannel2/0.3/fluid.vtu"),
                     0);
}

/* Function objects see across a periodic face: a probe within h of the
 * face x = 0 reads the fluid at the other end (the block starts against
 * x = 0.4 and no fluid is near x = 0), and postProcess on the written
 * times (which hold no images) reads what the running solver read. */
static void test_probes_across_the_face(void **state)
{
    (void)state;
    char edit[1024], cmd[2048];
    snprintf(edit, sizeof edit,
             "%s && printf 'functions\\n{\\n probes { type probes; fields (density pressure); "
             "probeLocations ((0.005 0.06 0.03) (0.395 0.06 0.03) (0.2 0.06 0.03)); }\\n}\\n' "
             ">> system/controlDict",
             threads1);
    assert_int_equal(run_edited("tests/cases/periodicChannel", "periodicProbes", edit), 0);
    snprintf(cmd, sizeof cmd,
             "cd tests/output/periodicProbes && mv postProcessing/probes/0/probes.dat live.dat && "
             "%s/postProcess -case . > log.postProcess 2>&1 && "
             "grep -v '^#' live.dat | awk '$1 == 0 || $1 == 0.1 || $1 == 0.2 || $1 == 0.3' > "
             "live.rows && grep -v '^#' postProcessing/probes/0/probes.dat > post.rows && "
             "paste live.rows post.rows | awk '{ n = NF / 2; if (n != 7) bad = 1; "
             "for (k = 1; k <= n; k++) { a = $k; b = $(k + n); "
             "if (a == \"nan\" || b == \"nan\") { if (a != b) bad = 1; continue } "
             "d = a - b; if (d < 0) d = -d; if (d > 1e-9 * (1 + (a < 0 ? -a : a))) bad = 1 } "
             "rows++ } END { exit bad || rows != 4 }' && "
             "awk '$1 == 0 { exit !($2 > 500 && $2 < 1500) }' live.rows",
             bin_dir());
    assert_int_equal(system(cmd), 0);
}

/* The case with edit applied must be refused with a message naming
 * boundaryProperties (and a line), the keyword and `why`. */
static void refused(const char *edit, const char *why)
{
    char cmd[2048], log[256], line[1024];
    assert_int_not_equal(run_edited("tests/cases/periodicChannel", "periodicBad", edit), 0);
    snprintf(log, sizeof log, "tests/output/periodicBad/log.pcisph");
    FILE *f = fopen(log, "r");
    assert_non_null(f);
    int found = 0;
    while (fgets(line, sizeof line, f))
        found |= strstr(line, why) != NULL && strstr(line, "periodic") != NULL;
    fclose(f);
    if (!found) {
        snprintf(cmd, sizeof cmd, "cat %s", log);
        if (system(cmd)) {}
    }
    assert_true(found);
    assert_int_not_equal(system("test -d tests/output/periodicBad/0"), 0); /* no half output */
}

static void test_reader_refuses(void **state)
{
    (void)state;
    refused("sed -i 's/periodic (x);/periodic (w);/' constant/boundaryProperties",
            "boundaryProperties:3: keyword 'periodic': 'w' is not one of: x y z");
    refused("sed -i 's/periodic (x);/periodic (x y);/' constant/boundaryProperties",
            "axis y: container 'channel' has walls across it");
    refused("sed -i 's/max (0.4 0.12 0.3)/max (0.41 0.12 0.3)/' constant/boundaryProperties",
            "must be a whole number of particle spacings");
    refused("sed -i 's/max (0.4 0.12 0.1)/max (0.44 0.12 0.1)/' constant/fluidProperties",
            "must lie inside the period");
    refused("sed -i 's/^ *channel {/    post { type box; min (0.35 0.04 0); max (0.45 0.08 0.1); "
            "}\\n&/' constant/boundaryProperties",
            "geometry 'post' (0.35 to 0.45) crosses the periodic face");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box_keeps_mass_and_momentum),
        cmocka_unit_test(test_conservative_force_keeps_momentum),
        cmocka_unit_test(test_channel_is_translation_invariant),
        cmocka_unit_test(test_threads_give_identical_files),
        cmocka_unit_test(test_probes_across_the_face),
        cmocka_unit_test(test_reader_refuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
