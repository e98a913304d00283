/* The boundary study of Ihmsen et al. 2010, Sec. 4.1, in small: a coarse
 * version of cases/boundaryComparison (the corner breaking dam with r0 =
 * 0.05 m: 2880 particles, 0.6 s) run with each boundary method.
 *
 *   - every method keeps every particle inside the tank;
 *   - at the same deltaT, ihmsen2010 has a smoother near-wall pressure
 *     (lower 99th percentile / median) and fewer particles pressed into the
 *     walls than becker2009 (boundarySmoothness; Fig. 2 of the paper);
 *   - stableTimeStep, judging every method by the same measure of volume
 *     compression (volErrAvg: the density with the wall's share from the
 *     boundary particles), finds dt(ihmsen2010) >= 2 x dt(becker2009), the
 *     issue's floor (the paper reports 0.0045 / 0.0008 = 5.6 at 23k
 *     particles).  becker2009 leaves the wall out of its own density, so
 *     fluid pressed into a wall is compressed without its solver seeing
 *     it; we measure 0.0055 s for ihmsen2010 and no stable step for
 *     becker2009 down to the search's 0.002 s on this coarse case (ratio
 *     above 2.7), and the same on the full cases/boundaryComparison (see
 *     its README).  When becker2009 has no stable step, the ratio is
 *     bounded below by dt(ihmsen2010) / dtMin, and that bound must be >= 2.
 *
 * Programs come from $SLUICE_BIN (default bin/), files go to
 * tests/output/boundaryStudy/.  A method the solver does not know yet
 * ("is not one of") fails the test that needs it with that message; every
 * run is under `timeout`, so nothing hangs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "tool_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "case/case.h"
#include "core/sl_log.h"
#include "dictedit/dictedit.h"
#include "geometry/geometry.h"
#include "io/time_dir.h"
#include "io/vtk_reader.h"

#define OUT       "tests/output/boundaryStudy"
#define BASE      "cases/boundaryComparison"
#define R0        "0.05" /* coarse: 12 x 12 x 20 particles */
#define END_TIME  "0.6"  /* the front hits the far walls at about 0.3 s */
#define COMMON_DT "0.004"

static const char *const methods[] = {"ihmsen2010", "becker2009", "harada2007"};
enum { NMETHODS = 3 };

static void set(const char *dir, const char *file, const char *entry, const char *value)
{
    char path[512];
    sl_err err;
    snprintf(path, sizeof path, "%s/%s", dir, file);
    if (dedit_set(path, entry, value, NULL, &err)) fail_msg("%s", err.msg);
}

/* The coarse corner breaking dam in dir, with `method` at a constant dt. */
static void make_case(const char *dir, const char *method, const char *dt, const char *write)
{
    if (run("rm -rf %s && mkdir -p %s && cp -r " BASE "/system " BASE "/constant %s", dir, dir,
            dir))
        fail_msg("cannot copy " BASE " to %s: %s", dir, output);
    set(dir, "constant/fluidProperties", "particleSpacing", R0);
    set(dir, "constant/boundaryProperties", "method", method);
    set(dir, "system/timeStepDict", "deltaT", dt);
    set(dir, "system/controlDict", "endTime", END_TIME);
    set(dir, "system/controlDict", "writeInterval", write);
    set(dir, "system/controlDict", "numberOfThreads", "1");
}

/* Fail with the solver's own words if it does not know the method. */
static void require_method(const char *method, const char *log_path)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "grep -h 'is not one of' %s", log_path);
    if (run("%s", cmd) == 0)
        fail_msg("boundary method %s is not available in this solver yet: %s", method, output);
}

/* ---- the three runs at a common deltaT (group setup) --------------------------- */

static int status_of[NMETHODS];

static int run_methods(void **state)
{
    (void)state;
    char dir[256];
    for (int m = 0; m < NMETHODS; m++) {
        snprintf(dir, sizeof dir, OUT "/%s", methods[m]);
        make_case(dir, methods[m], COMMON_DT, "0.05");
    }
    /* in parallel, one thread each */
    run("for m in ihmsen2010 becker2009 harada2007; do "
        "( timeout 300 %s/pcisph -case " OUT "/$m -quiet > " OUT "/$m/log.pcisph 2>&1; "
        "echo $? > " OUT "/$m/status ) & done; wait",
        bin_dir());
    for (int m = 0; m < NMETHODS; m++) {
        snprintf(dir, sizeof dir, OUT "/%s/status", methods[m]);
        FILE *f = fopen(dir, "r");
        status_of[m] = -1;
        if (f) {
            if (fscanf(f, "%d", &status_of[m]) != 1) status_of[m] = -1;
            fclose(f);
        }
    }
    return 0;
}

static void require_run(int m)
{
    char log[256];
    snprintf(log, sizeof log, OUT "/%s/log.pcisph", methods[m]);
    require_method(methods[m], log);
    if (status_of[m] != 0) {
        run("tail -3 %s", log);
        fail_msg("%s: the solver exited with %d at deltaT " COMMON_DT ": %s", methods[m],
                 status_of[m], output);
    }
}

/* Every particle of the last fluid.vtu inside the container (and finite),
 * and none missing. */
static void test_methods_keep_particles_in_tank(void **state)
{
    (void)state;
    for (int m = 0; m < NMETHODS; m++) {
        char dir[256], path[512];
        sl_err err;
        tdir_list l;
        vtkr_file first, last;
        sl_case c;
        require_run(m);
        snprintf(dir, sizeof dir, OUT "/%s", methods[m]);
        case_read(&c, dir);
        assert_int_equal(tdir_list_read(dir, "fluid.vtu", &l, &err), 0);
        assert_true(l.n >= 2);
        assert_true(fabs(l.time[l.n - 1] - atof(END_TIME)) < 1e-9);
        snprintf(path, sizeof path, "%s/%s/fluid.vtu", dir, l.name[0]);
        if (vtkr_read(path, &first, &err)) fail_msg("%s", err.msg);
        snprintf(path, sizeof path, "%s/%s/fluid.vtu", dir, l.name[l.n - 1]);
        if (vtkr_read(path, &last, &err)) fail_msg("%s", err.msg);
        assert_int_equal(first.npoints, last.npoints);
        const geo_shape *tank = NULL;
        for (size_t k = 0; k < c.nshapes; k++)
            if (c.shapes[k].kind == GEO_CONTAINER) tank = &c.shapes[k];
        assert_non_null(tank);
        size_t outside = 0;
        for (size_t i = 0; i < last.npoints; i++)
            for (int d = 0; d < 3; d++) {
                double x = last.points[3 * i + d];
                if (!(x >= tank->lo[d] && x <= tank->hi[d])) {
                    outside++;
                    break;
                }
            }
        printf("  %-11s %zu particles, %zu outside the tank at t = %s s (deltaT " COMMON_DT " s)\n",
               methods[m], last.npoints, outside, l.name[l.n - 1]);
        assert_int_equal(outside, 0);
        vtkr_free(&first);
        vtkr_free(&last);
        tdir_list_free(&l);
        case_free(&c);
    }
}

/* Max over the steps of columns a and b of the run's timeStep.dat, and
 * whether they are equal on every row. */
static int record_columns(int m, int a, int b, double *amax, double *bmax)
{
    char path[256], line[1024];
    int equal = 1;
    snprintf(path, sizeof path, OUT "/%s/postProcessing/timeStep/0/timeStep.dat", methods[m]);
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("no record %s", path);
    *amax = *bmax = 0.0;
    while (fgets(line, sizeof line, f)) {
        double v[12];
        char *s = line, *end;
        int k;
        if (line[0] == '#') continue;
        for (k = 0; k < 12; k++, s = end) {
            v[k] = strtod(s, &end);
            if (end == s) break;
        }
        if (k < 12) fail_msg("%s: a row with %d columns, not 12: %s", path, k, line);
        if (v[a] > *amax) *amax = v[a];
        if (v[b] > *bmax) *bmax = v[b];
        if (v[a] != v[b]) equal = 0;
    }
    fclose(f);
    return equal;
}

/* volErrAvg (column 10) is rhoErrAvg (3) for ihmsen2010, which solves with
 * the wall's density; becker2009 solves without it, and the fluid it
 * presses into the walls is more compressed than its own density says. */
static void test_volume_compression_alike(void **state)
{
    (void)state;
    double own[NMETHODS], vol[NMETHODS];
    for (int m = 0; m < NMETHODS; m++) {
        require_run(m);
        int equal = record_columns(m, 3, 10, &own[m], &vol[m]);
        printf("  %-11s max rhoErrAvg %.3f %%, max volErrAvg %.3f %%\n", methods[m], own[m],
               vol[m]);
        if (m == 0) assert_true(equal);
    }
    assert_true(vol[1] > 2.0 * own[1]); /* becker2009: blind to the wall */
    assert_true(vol[1] > vol[0]);
    assert_true(vol[2] >= own[2]); /* harada2007's table holds a share of the wall */
}

/* A "key value" line of the last output. */
static double output_value(const char *key)
{
    size_t n = strlen(key);
    for (const char *s = output; s && *s; s = strchr(s, '\n'), s = s ? s + 1 : NULL)
        if (!strncmp(s, key, n) && (s[n] == ' ' || s[n] == '\t')) return strtod(s + n, NULL);
    fail_msg("no '%s' in:\n%s", key, output);
    return NAN;
}

/* Fig. 2: the proposed method's near-wall pressure is smoother and it does
 * not stack particles; over every written time of the same run. */
static void test_ihmsen_smoother_than_becker(void **state)
{
    (void)state;
    double ratio[2], stacked[2];
    for (int m = 0; m < 2; m++) {
        require_run(m);
        if (run("timeout 120 %s/boundarySmoothness -case " OUT "/%s -allTimes", bin_dir(),
                methods[m]))
            fail_msg("boundarySmoothness failed on %s: %s", methods[m], output);
        ratio[m] = output_value("meanPressureRatio");
        stacked[m] = output_value("meanStacked");
        printf("  %-11s near-wall p99/median %.3f, stacked particles %.1f (mean over times)\n",
               methods[m], ratio[m], stacked[m]);
    }
    assert_true(ratio[0] < ratio[1]);
    assert_true(stacked[0] < stacked[1]);
}

/* ---- what limits each method (classifyCompression) ------------------------------ */

/* volErrAvg (column 10) of the timeStep.dat row of `method` nearest time t. */
static double vol_err_at(int m, double t)
{
    char path[256], line[1024];
    double best = NAN, dbest = INFINITY;
    snprintf(path, sizeof path, OUT "/%s/postProcessing/timeStep/0/timeStep.dat", methods[m]);
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("no record %s", path);
    while (fgets(line, sizeof line, f)) {
        double v[11];
        char *s = line, *end;
        int k;
        if (line[0] == '#') continue;
        for (k = 0; k < 11; k++, s = end) {
            v[k] = strtod(s, &end);
            if (end == s) break;
        }
        if (k == 11 && fabs(v[0] - t) < dbest) {
            dbest = fabs(v[0] - t);
            best = v[10];
        }
    }
    fclose(f);
    return best;
}

/* Sec. 4.1 measured: where each method's compression sits at the written
 * time of its largest average compression.  becker2009 leaves the wall out
 * of its density: its compression is in the band within h of the walls
 * (over 90 % of it; 10 % average there against 0.03 % in the bulk at this
 * step), with particles piled closer than r0/2 on each other, the stacking
 * of the paper; ihmsen2010 compresses the bulk and the band alike, and none
 * of the three lets a particle through a wall.  The tool's own average
 * (the density recomputed from the written positions with eq. 13) agrees
 * with the solver's volErrAvg of that step. */
static void test_where_the_compression_sits(void **state)
{
    (void)state;
    double share[NMETHODS], near[NMETHODS], bulk[NMETHODS], stacked[NMETHODS];
    for (int m = 0; m < NMETHODS; m++) {
        require_run(m);
        if (run("timeout 120 %s/classifyCompression -case " OUT "/%s -allTimes", bin_dir(),
                methods[m]))
            fail_msg("classifyCompression failed on %s: %s", methods[m], output);
        double t = output_value("time"), avg = output_value("compressionAvg");
        share[m] = output_value("nearWallShare");
        near[m] = output_value("nearWallAvg");
        bulk[m] = output_value("bulkAvg");
        stacked[m] = output_value("stacked");
        double pen = output_value("penetrated"), solver = vol_err_at(m, t);
        printf("  %-11s t %.2f s: compression %.3f %% (solver %.3f %%), near walls %.0f %% of it "
               "(%.3f %% there, %.3f %% in the bulk), stacked %.0f, penetrated %.0f\n",
               methods[m], t, avg, solver, 100.0 * share[m], near[m], bulk[m], stacked[m], pen);
        assert_true(pen == 0.0);
        assert_true(fabs(avg - solver) <= 0.15 * solver + 0.02);
    }
    assert_true(share[1] > 0.9);           /* becker2009: at the walls */
    assert_true(near[1] > 20.0 * bulk[1]); /* and not in the bulk */
    assert_true(share[0] < 0.8);           /* ihmsen2010: the band's share of... */
    assert_true(near[0] < 2.0 * bulk[0]);  /* ...the particles, about */
    assert_true(stacked[1] > 3.0 * stacked[0]);
}

/* ---- the scene's size sets the step ------------------------------------------------ */

/* max volErrAvg of the coarse scene scaled by `scale` (same 2880 particles,
 * r0 = 0.05 scale, end time 0.6 sqrt(scale): the same phase of the flow in
 * Froude time) at a constant dt with three iterations. */
static double scaled_run(const char *method, double scale, const char *dt)
{
    char dir[256], v[64];
    double amax, bmax;
    snprintf(dir, sizeof dir, OUT "/scaled_%s_%g", method, scale);
    make_case(dir, method, dt, "0.6");
    snprintf(v, sizeof v, "%g", 0.05 * scale);
    set(dir, "constant/fluidProperties", "particleSpacing", v);
    snprintf(v, sizeof v, "(%g %g %g)", 1.5 * scale, 1.5 * scale, 1.2 * scale);
    set(dir, "constant/boundaryProperties", "geometry/tank/max", v);
    snprintf(v, sizeof v, "(%g %g %g)", 0.6 * scale, 0.6 * scale, 1.0 * scale);
    set(dir, "constant/fluidProperties", "fluidRegions/column/max", v);
    /* a whole number of steps and writes */
    const double end = 0.6 * sqrt(scale), step = atof(dt);
    snprintf(v, sizeof v, "%.10g", ceil(end / step - 1e-9) * step);
    set(dir, "system/controlDict", "endTime", v);
    set(dir, "system/controlDict", "writeInterval", v);
    if (run("timeout 300 %s/pcisph -case %s -quiet > %s/log.pcisph 2>&1", bin_dir(), dir, dir)) {
        run("tail -3 %s/log.pcisph", dir);
        fail_msg("%s (scene x %g, deltaT %s) failed: %s", method, scale, dt, output);
    }
    char rec[320], line[1024];
    snprintf(rec, sizeof rec, "%s/postProcessing/timeStep/0/timeStep.dat", dir);
    FILE *f = fopen(rec, "r");
    if (!f) fail_msg("no record %s", rec);
    amax = bmax = 0.0;
    while (fgets(line, sizeof line, f)) {
        double c[11];
        char *s = line, *e;
        int k;
        if (line[0] == '#') continue;
        for (k = 0; k < 11; k++, s = e) {
            c[k] = strtod(s, &e);
            if (e == s) break;
        }
        if (k == 11 && c[10] > amax) amax = c[10];
        if (k == 11 && c[1] > bmax) bmax = c[1];
    }
    fclose(f);
    if (!(bmax <= step * (1.0 + 1e-9))) fail_msg("%s: a step of %g s, not %s", dir, bmax, dt);
    return amax;
}

/* The paper states 23k particles but not the scene's size.  With the
 * particle count fixed, the compression three iterations leave at a given
 * step falls as the scene grows (about as 1 / size: the largest step grows
 * as sqrt(size)), so the paper's absolute steps say as much about its
 * scene's size as about the methods: at deltaT 0.006 s the coarse scene
 * fails the 1 % bound and the same particles in a scene 3x larger pass
 * it (1.22 % against 0.42 %, a factor 2.9; at 23k particles our 0.0025 s
 * becomes 0.0045 s, README).  And harada2007 stays close to ihmsen2010 at
 * both sizes (1.4 % and 0.65 %): the paper's threefold gap in the step
 * would need a ninefold gap in the compression at a common step. */
static void test_scene_size_sets_the_step(void **state)
{
    (void)state;
    const double i1 = scaled_run("ihmsen2010", 1.0, "0.006"),
                 i3 = scaled_run("ihmsen2010", 3.0, "0.006"),
                 h1 = scaled_run("harada2007", 1.0, "0.006"),
                 h3 = scaled_run("harada2007", 3.0, "0.006");
    printf("  max volErrAvg at deltaT 0.006 s, 2880 particles: ihmsen2010 %.3f %% (scene x1), "
           "%.3f %% (x3); harada2007 %.3f %%, %.3f %%\n",
           i1, i3, h1, h3);
    assert_true(i1 > 1.0 && i3 < 1.0);
    assert_true(i1 > 2.0 * i3);
    assert_true(h1 < 2.5 * i1 && h3 < 2.5 * i3);
}

/* ---- the search ------------------------------------------------------------------ */

/* Column `col` (0-based) of the row of `method` in stableTimeStep.csv. */
static int csv_field(const char *csv, const char *method, int col, char *out, size_t len)
{
    FILE *f = fopen(csv, "r");
    char line[1024];
    int found = 0;
    if (!f) fail_msg("stableTimeStep wrote no %s:\n%s", csv, output);
    while (!found && fgets(line, sizeof line, f)) {
        char *save = NULL, *tok = strtok_r(line, ",\n", &save);
        if (!tok || strcmp(tok, method)) continue;
        for (int k = 0; k < col && tok; k++) tok = strtok_r(NULL, ",\n", &save);
        if (tok) {
            snprintf(out, len, "%s", tok);
            found = 1;
        }
    }
    fclose(f);
    return found;
}

static void test_stable_time_step_ratio(void **state)
{
    (void)state;
    const char *dir = OUT "/search",
               *csv = OUT "/search/postProcessing/stableTimeStep/stableTimeStep.csv";
    double dt[2];
    make_case(dir, "ihmsen2010", COMMON_DT, END_TIME);
    int rc = run("timeout 600 %s/stableTimeStep -case %s -method ihmsen2010,becker2009 "
                 "-dtMin 0.002 -dtMax 0.02 -tolerance 10%% -commonDeltaT none",
                 bin_dir(), dir);
    printf("%s", output);
    double dt_min = 0.002;
    int below[2] = {0, 0};
    for (int m = 0; m < 2; m++) {
        char status[64], value[64];
        if (!csv_field(csv, methods[m], 8, status, sizeof status))
            fail_msg("stableTimeStep (exit %d) gave no row for %s:\n%s", rc, methods[m], output);
        if (!strcmp(status, "unavailable"))
            fail_msg("boundary method %s is not available in this solver yet (see "
                     "%s/postProcessing/stableTimeStep/trials.csv)",
                     methods[m], dir);
        below[m] = !strcmp(status, "belowDeltaTMin");
        if (!csv_field(csv, methods[m], 1, value, sizeof value)) fail_msg("no deltaT");
        dt[m] = strtod(value, NULL);
        if (!below[m] && !(dt[m] > 0))
            fail_msg("%s: no stable deltaT found (%s)", methods[m], status);
    }
    assert_int_equal(rc, 0);
    if (below[0]) fail_msg("ihmsen2010: no stable deltaT down to %g s", dt_min);
    if (below[1]) /* unstable at every step tried: its largest stable step is below dtMin */
        printf("  largest stable deltaT: ihmsen2010 %.4g s, becker2009 below %g s: ratio above "
               "%.2f (paper, 23k particles: 0.0045 / 0.0008 = 5.6)\n",
               dt[0], dt_min, dt[0] / dt_min);
    else
        printf("  largest stable deltaT: ihmsen2010 %.4g s, becker2009 %.4g s: ratio %.2f "
               "(paper, 23k particles: 0.0045 / 0.0008 = 5.6)\n",
               dt[0], dt[1], dt[0] / dt[1]);
    const double ratio_low = dt[0] / (below[1] ? dt_min : dt[1]);
    if (!(ratio_low >= 2.0))
        fail_msg("dt(ihmsen2010) / dt(becker2009) %s %.2f, below 2 (the issue's floor; paper 5.6)",
                 below[1] ? ">" : "=", ratio_low);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_methods_keep_particles_in_tank),
        cmocka_unit_test(test_ihmsen_smoother_than_becker),
        cmocka_unit_test(test_stable_time_step_ratio),
        cmocka_unit_test(test_volume_compression_alike),
        cmocka_unit_test(test_where_the_compression_sits),
        cmocka_unit_test(test_scene_size_sets_the_step),
    };
    sl_log_set_quiet(1);
    return cmocka_run_group_tests(tests, run_methods, NULL);
}
