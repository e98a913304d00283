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
    };
    sl_log_set_quiet(1);
    return cmocka_run_group_tests(tests, run_methods, NULL);
}
