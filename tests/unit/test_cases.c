/* Case tests: run bin/pcisph on the cases in tests/cases/ and check the
 * results against analytic values (hydrostatics) and invariants (no NaN,
 * no particle through a wall).  The written VTK files are read back with
 * VTK by tests/cases/inspect_case.py. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "case_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAXV 64

typedef struct facts {
    int n;
    char key[MAXV][32];
    double val[MAXV];
} facts;

/* Copy tests/cases/<name> to tests/output/<name> and run the solver there. */
static int run_case(const char *name, const char *extra)
{
    char cmd[1024];
    snprintf(
        cmd, sizeof cmd,
        "rm -rf tests/output/%s && mkdir -p tests/output && cp -r tests/cases/%s tests/output/%s"
        " && %s/pcisph -case tests/output/%s -quiet %s > tests/output/%s/log.pcisph 2>&1",
        name, name, name, bin_dir(), name, extra ? extra : "", name);
    return system(cmd);
}

/* Rows of postProcessing/timeStep/0/timeStep.dat (10 columns). */
typedef struct record {
    size_t n;
    double (*row)[10];
} record;

static record read_record(const char *name, const char *start)
{
    char path[512], line[1024];
    record r = {0, NULL};
    size_t cap = 0;
    snprintf(path, sizeof path, "tests/output/%s/postProcessing/timeStep/%s/timeStep.dat", name,
             start);
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("no record %s", path);
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') continue;
        if (r.n == cap) {
            cap = cap ? 2 * cap : 1024;
            r.row = realloc(r.row, cap * sizeof *r.row);
        }
        char *s = line;
        for (int k = 0; k < 10; k++) r.row[r.n][k] = strtod(s, &s);
        r.n++;
    }
    fclose(f);
    return r;
}

static int files_equal(const char *a, const char *b)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "cmp -s %s %s", a, b);
    return system(cmd) == 0;
}

static facts inspect(const char *name, const char *args)
{
    char cmd[1024], line[256];
    facts f = {0};
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/cases/inspect_case.py tests/output/%s %s",
             name, args);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    while (fgets(line, sizeof line, p) && f.n < MAXV) {
        char *eq = strchr(line, '=');
        if (!eq) continue;
        *eq = 0;
        snprintf(f.key[f.n], sizeof f.key[f.n], "%.31s", line);
        f.val[f.n] = strtod(eq + 1, NULL);
        f.n++;
    }
    assert_int_equal(pclose(p), 0);
    return f;
}

static double fact(const facts *f, const char *key)
{
    for (int i = 0; i < f->n; i++)
        if (!strcmp(f->key[i], key)) return f->val[i];
    fail_msg("inspect_case.py printed no '%s'", key);
    return NAN;
}

/* Largest value of a column of postProcessing/timeStep/0/timeStep.dat over
 * rows with time >= t_from. */
static double record_max(const char *name, int column, double t_from)
{
    char path[512], line[512];
    double m = -INFINITY;
    snprintf(path, sizeof path, "tests/output/%s/postProcessing/timeStep/0/timeStep.dat", name);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    int rows = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') continue;
        double v[9];
        char *s = line;
        for (int k = 0; k < 9; k++) v[k] = strtod(s, &s);
        if (v[0] < t_from) continue;
        if (!(v[column] <= m)) m = v[column];
        rows++;
    }
    fclose(f);
    assert_true(rows > 0);
    return m;
}

/* A 0.4 m column in a 0.3 x 0.3 m tank held for 1 s (eta = 1 %). */
static void test_hydrostatic_tank(void **state)
{
    (void)state;
    const double rho0 = 1000, g = 9.81, H = 0.4, r0 = 0.025;
    assert_int_equal(run_case("hydrostaticTank", NULL), 0);
    /* average density error below eta after the initial settling */
    assert_true(record_max("hydrostaticTank", 3, 0.05) < 1.0);
    /* bottom pressure within 10 % of rho0 g H, averaged over the last
     * three writes (the column still breathes a little) */
    double p = 0;
    const char *times[3] = {"0.5", "0.75", "1"};
    for (int k = 0; k < 3; k++) {
        char args[128];
        snprintf(args, sizeof args, "%s --r0 %g --lo 0 0 0 --hi 0.3 0.3 0.6", times[k], r0);
        facts f = inspect("hydrostaticTank", args);
        assert_int_equal((int)fact(&f, "nan"), 0);
        assert_int_equal((int)fact(&f, "outside"), 0);
        p += fact(&f, "p_bottom") / 3;
        if (k == 2) {
            /* nearly at rest: 5 % of the free-fall speed over H */
            assert_true(fact(&f, "vmax") < 0.05 * sqrt(2 * g * H));
        }
    }
    print_message("hydrostatic bottom pressure %.1f Pa, rho0 g H = %.1f Pa\n", p, rho0 * g * H);
    assert_true(fabs(p - rho0 * g * H) < 0.1 * rho0 * g * H);
}

/* The damBreak tutorial (coarser) for 0.25 s: no NaN, no particle lost. */
static void test_dam_break_short(void **state)
{
    (void)state;
    assert_int_equal(run_case("damBreakShort", NULL), 0);
    facts f = inspect("damBreakShort", "--lo 0 0 0 --hi 1.6 0.6 0.8");
    assert_int_equal((int)fact(&f, "nan"), 0);
    assert_int_equal((int)fact(&f, "outside"), 0);
    assert_int_equal((int)fact(&f, "n"), 16 * 24 * 24); /* 0.4 x 0.6 x 0.6 at r0 = 0.025 */
    /* the front has moved */
    assert_true(fact(&f, "xmax") > 0.8);
    assert_true(record_max("damBreakShort", 3, 0.0) < 1.0);
}

/* The Shock scene (coarse) in adaptive mode: the impact is detected as a
 * shock and handled; accepted steps keep rho_err_max below eta_max = 10 %;
 * outside shocks the controller changes dt by 0.2 % at most. */
static void test_shock_adaptive(void **state)
{
    (void)state;
    assert_int_equal(
        run_edited("cases/shock", "shock",
                   "sed -i 's/^r0 .*/r0 0.03;/' constant/fluidProperties && "
                   "sed -i 's/^endTime .*/endTime 0.7;/; s/^writeInterval .*/writeInterval 0.1;/' "
                   "system/controlDict"),
        0);
    record r = read_record("shock", "0");
    int shocks = 0;
    for (size_t i = 0; i < r.n; i++) {
        double *row = r.row[i];
        assert_true(isfinite(row[4]) && isfinite(row[5]));
        if (row[7] != 0.0) {
            shocks++;
            continue;
        }
        assert_true(row[4] < 10.0); /* rhoErrMax, percent */
        if (i > 0 && r.row[i - 1][7] == 0.0) {
            double q = row[9] / r.row[i - 1][9];
            assert_true(fabs(q - 1.0) < 1e-12 || fabs(q - 1.002) < 1e-12 ||
                        fabs(q - 0.998) < 1e-12);
        }
    }
    print_message("shock: %d shocks in %zu steps\n", shocks, r.n);
    assert_true(shocks >= 1);
    free(r.row);
    facts f = inspect("shock", "--lo 0 0 0 --hi 1 1 1.6");
    assert_int_equal((int)fact(&f, "nan"), 0);
    assert_int_equal((int)fact(&f, "outside"), 0);
}

/* The hydrostatic tank in adaptive mode: the step grows from the initial
 * estimate and the average density error stays below eta. */
static void test_hydrostatic_adaptive(void **state)
{
    (void)state;
    assert_int_equal(run_edited("tests/cases/hydrostaticTank", "hydrostaticAdaptive",
                                "printf 'mode adaptive;\\ndeltaT 0;\\n' > system/timeStepDict && "
                                "sed -i 's/^endTime .*/endTime 0.5;/' system/controlDict"),
                     0);
    record r = read_record("hydrostaticAdaptive", "0");
    assert_true(r.n > 10);
    assert_true(r.row[r.n - 1][9] > 1.05 * r.row[0][1]);
    for (size_t i = 0; i < r.n; i++)
        if (r.row[i][0] > 0.05) assert_true(r.row[i][3] < 1.0);
    free(r.row);
}

/* Stopping at a write time and restarting with startFrom latestTime gives
 * bit-identical output to an uninterrupted run (adaptive mode, so the
 * controller's state must survive too). */
static void test_restart_bit_identical(void **state)
{
    (void)state;
    const char *edit =
        "sed -i 's/^endTime .*/endTime 0.3;/; s/^writeInterval .*/writeInterval 0.1;/' "
        "system/controlDict && printf 'mode adaptive;\\ndeltaT 0;\\n' > system/timeStepDict";
    assert_int_equal(run_edited("tests/cases/damBreakShort", "restartA", edit), 0);
    assert_int_equal(
        run_edited(
            "tests/cases/damBreakShort", "restartB",
            "sed -i 's/^endTime .*/endTime 0.3;/; s/^writeInterval .*/writeInterval 0.1;/' "
            "system/controlDict && printf 'mode adaptive;\\ndeltaT 0;\\n' > "
            "system/timeStepDict && sed -i 's/^endTime .*/endTime 0.1;/' system/controlDict"),
        0);
    char cmd[1024];
    snprintf(
        cmd, sizeof cmd,
        "sed -i 's/^endTime .*/endTime 0.3;/; s/^startFrom .*/startFrom latestTime;/' "
        "tests/output/restartB/system/controlDict && %s/pcisph -case tests/output/restartB -quiet "
        "> tests/output/restartB/log.restart 2>&1",
        bin_dir());
    assert_int_equal(system(cmd), 0);
    assert_true(
        files_equal("tests/output/restartA/0.3/fluid.vtu", "tests/output/restartB/0.3/fluid.vtu"));
    assert_true(
        files_equal("tests/output/restartA/0.2/fluid.vtu", "tests/output/restartB/0.2/fluid.vtu"));
    /* the restarted run's record went to a new folder */
    record r = read_record("restartB", "0.1");
    assert_true(r.n > 0 && r.row[0][0] > 0.1);
    free(r.row);
}

/* pressureSource divergence, warm-started: each step starts from the last
 * step's pressures, and every boundary particle keeps the last values it
 * was given (boundary.vtu shows them): the restart file (format 4)
 * carries them, and a run stopped at 0.03 s and restarted gives the
 * uninterrupted run's 0.06 s files, fluid.vtu and boundary.vtu, bit for
 * bit, on another thread count.  A file of format 3 (without them) still
 * restarts, says so in the log, and the files differ (what the test
 * would see if the pressures were lost). */
static void test_restart_warm_start(void **state)
{
    (void)state;
    const char *edit = "sed -i 's/^endTime .*/endTime 0.06;/; s/^writeInterval .*/writeInterval "
                       "0.03;/; s/^numberOfThreads .*/numberOfThreads 2;/' system/controlDict && "
                       "echo 'pressureSource divergence;' >> constant/fluidProperties";
    char first[1024], cmd[2048];
    assert_int_equal(run_edited("tests/cases/damBreakShort", "warmA", edit), 0);
    snprintf(first, sizeof first,
             "%s && sed -i 's/^endTime .*/endTime 0.03;/; s/^numberOfThreads .*/numberOfThreads "
             "1;/' system/controlDict",
             edit);
    assert_int_equal(run_edited("tests/cases/damBreakShort", "warmB", first), 0);
    assert_int_equal(system("zcat tests/output/warmB/0.03/uniform/restart | head -c 16 | "
                            "grep -q SLUICE-RESTART-4"),
                     0);
    snprintf(cmd, sizeof cmd,
             "rm -rf tests/output/warmC && cp -r tests/output/warmB tests/output/warmC && "
             "rm -rf tests/output/warmC/0.03 && (cd tests/output/warmC && "
             "SLUICE_RESTART_FORMAT=3 %s/pcisph -case . -quiet > log.pcisph 2>&1) && "
             "sed -i 's/^endTime .*/endTime 0.06;/; s/^startFrom .*/startFrom latestTime;/' "
             "tests/output/warmB/system/controlDict tests/output/warmC/system/controlDict && "
             "%s/pcisph -case tests/output/warmB -quiet > tests/output/warmB/log.restart 2>&1 && "
             "%s/pcisph -case tests/output/warmC -quiet > tests/output/warmC/log.restart 2>&1",
             bin_dir(), bin_dir(), bin_dir());
    assert_int_equal(system(cmd), 0);
    assert_true(
        files_equal("tests/output/warmA/0.06/fluid.vtu", "tests/output/warmB/0.06/fluid.vtu"));
    assert_true(files_equal("tests/output/warmA/0.06/boundary.vtu",
                            "tests/output/warmB/0.06/boundary.vtu"));
    assert_int_equal(system("grep -q 'holds no pressures: the warm start' "
                            "tests/output/warmC/log.restart"),
                     0);
    assert_int_not_equal(system("grep -q 'holds no pressures' tests/output/warmB/log.restart"), 0);
    assert_false(
        files_equal("tests/output/warmA/0.06/fluid.vtu", "tests/output/warmC/0.06/fluid.vtu"));
}

/* Same case, same result, whatever the thread count. */
static void test_threads_bit_identical(void **state)
{
    (void)state;
    const char *one =
        "sed -i 's/^endTime .*/endTime 0.1;/; s/^writeInterval .*/writeInterval 0.1;/; "
        "s/^numberOfThreads .*/numberOfThreads 1;/' system/controlDict";
    const char *two =
        "sed -i 's/^endTime .*/endTime 0.1;/; s/^writeInterval .*/writeInterval 0.1;/; "
        "s/^numberOfThreads .*/numberOfThreads 2;/' system/controlDict";
    assert_int_equal(run_edited("tests/cases/damBreakShort", "threads1", one), 0);
    assert_int_equal(run_edited("tests/cases/damBreakShort", "threads2", two), 0);
    assert_true(
        files_equal("tests/output/threads1/0.1/fluid.vtu", "tests/output/threads2/0.1/fluid.vtu"));
    assert_true(files_equal("tests/output/threads1/0.1/boundary.vtu",
                            "tests/output/threads2/0.1/boundary.vtu"));
}

/* The edits that put damBreakShort under the cost controller at eta 0.2 %
 * (3-50 iterations), endTime 0.3 s, writes every 0.1 s. */
#define COST_EDIT                                                                        \
    "sed -i 's/^endTime .*/endTime 0.3;/; s/^writeInterval .*/writeInterval 0.1;/' "     \
    "system/controlDict && printf 'mode adaptive;\\ndeltaT 0;\\ncontroller cost;\\n' > " \
    "system/timeStepDict && sed -i 's/^eta .*/eta 0.2;/' constant/fluidProperties"

/* controller cost: every kept step ends with rho_err avg <= eta (the
 * iterations go on until it does); the step grows by 1 % at most; the steps
 * iterate more than the paper's 3 and the step grows beyond the start. */
static void test_cost_controller(void **state)
{
    (void)state;
    assert_int_equal(run_edited("tests/cases/damBreakShort", "costA", COST_EDIT), 0);
    record r = read_record("costA", "0");
    assert_true(r.n > 20);
    double iters = 0, kmax = 0;
    int kept = 0;
    for (size_t i = 0; i < r.n; i++) {
        double *row = r.row[i];
        if (row[7] != 0.0) continue; /* shock: discarded */
        kept++;
        iters += row[2];
        if (row[2] > kmax) kmax = row[2];
        if (!(row[3] <= 0.2 + 1e-9))
            fail_msg("t = %g: rho_err avg %g %% above eta", row[0], row[3]);
        if (i > 0 && r.row[i - 1][7] == 0.0 && !(row[9] <= 1.01 * r.row[i - 1][9] * (1 + 1e-12)))
            fail_msg("t = %g: dt grew from %g to %g", row[0], r.row[i - 1][9], row[9]);
    }
    print_message("cost: %d steps kept, mean iterations %.2f, max %g, last dt %g (first %g)\n",
                  kept, iters / kept, kmax, r.row[r.n - 1][9], r.row[0][1]);
    assert_true(iters / kept > 3.0);
    assert_true(r.row[r.n - 1][9] > 1.5 * r.row[0][1]);
    free(r.row);
    facts f = inspect("costA", "--lo 0 0 0 --hi 1.6 0.6 0.8");
    assert_int_equal((int)fact(&f, "nan"), 0);
    assert_int_equal((int)fact(&f, "outside"), 0);
}

/* controller cost: a restart from 0.1 s gives the uninterrupted run's
 * output bit for bit (the controller's state is in the restart file), and
 * one thread gives the two threads' output. */
static void test_cost_restart_and_threads(void **state)
{
    (void)state;
    if (access("tests/output/costA/0.3/fluid.vtu", F_OK) != 0)
        assert_int_equal(run_edited("tests/cases/damBreakShort", "costA", COST_EDIT), 0);
    assert_int_equal(run_edited("tests/cases/damBreakShort", "costB",
                                COST_EDIT
                                " && sed -i 's/^endTime .*/endTime 0.1;/; "
                                "s/^numberOfThreads .*/numberOfThreads 1;/' system/controlDict"),
                     0);
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "sed -i 's/^endTime .*/endTime 0.3;/; s/^startFrom .*/startFrom latestTime;/; "
             "s/^numberOfThreads .*/numberOfThreads 2;/' tests/output/costB/system/controlDict && "
             "%s/pcisph -case tests/output/costB -quiet > tests/output/costB/log.restart 2>&1",
             bin_dir());
    assert_int_equal(system(cmd), 0);
    assert_true(
        files_equal("tests/output/costA/0.1/fluid.vtu", "tests/output/costB/0.1/fluid.vtu"));
    assert_true(
        files_equal("tests/output/costA/0.2/fluid.vtu", "tests/output/costB/0.2/fluid.vtu"));
    assert_true(
        files_equal("tests/output/costA/0.3/fluid.vtu", "tests/output/costB/0.3/fluid.vtu"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hydrostatic_tank),
        cmocka_unit_test(test_dam_break_short),
        cmocka_unit_test(test_shock_adaptive),
        cmocka_unit_test(test_hydrostatic_adaptive),
        cmocka_unit_test(test_restart_bit_identical),
        cmocka_unit_test(test_restart_warm_start),
        cmocka_unit_test(test_threads_bit_identical),
        cmocka_unit_test(test_cost_controller),
        cmocka_unit_test(test_cost_restart_and_threads),
    };
    /* SLUICE_TEST_FILTER=test_restart* runs the matching tests only */
    if (getenv("SLUICE_TEST_FILTER")) cmocka_set_test_filter(getenv("SLUICE_TEST_FILTER"));
    return cmocka_run_group_tests_name("cases", tests, NULL, NULL);
}
