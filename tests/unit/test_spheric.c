/* SPHERIC Test 2 (Kleefsman et al. 2005, cases/sphericTest2) in the test
 * suite: the front of the collapsing column against the measured arrival
 * times at the gauges H3 (x = 1.488 m) and H2 (x = 0.992 m).
 *
 * The run: the case at r0 = 0.025 m (43k fluid particles; the coarsest level
 * whose gauges resolve the front, see below), shortened to 0.5 s -- the
 * front passes H2 at about 0.39 s -- writing only at the end.  Then
 * compareExperiment on the measured data with the case's own
 * compareExperimentDict: the arrival at a gauge is the first time its height
 * exceeds 0.02 m (3.6 % of the 0.55 m column), the same rule for the run and
 * the experiment.
 *
 * Tolerance: +-0.05 s, as the issue asks.  The issue quotes the experiment's
 * arrivals as 0.19 s (H3) and 0.36 s (H2): those are the times the measured
 * height first passes 5-10 mm (0.190 and 0.354 s at 5 mm).  An SPH gauge sees
 * no water layer thinner than about r0 (the colour field stays below 0.5),
 * so the run and the experiment are compared at one threshold both can
 * resolve, 0.02 m, where the experiment gives 0.218 and 0.368 s; the test
 * checks that these are within 0.03 s of the quoted values, so that the
 * comparison is still against the same event.  We measure 0.248 s (H3) and
 * 0.388 s (H2) at r0 = 0.025, 0.244 / 0.383 s at 0.0125 (doc/validation.md):
 * late by 0.02-0.03 s, and at r0 = 0.05 by 0.05 s (H3), which is why this
 * test runs the finer level.
 *
 * With SLUICE_QUICK=1 (the sanitizer build) the run is the coarse level r0 =
 * 0.05 m to 0.45 s and only the pipeline is checked (the run ends, the table
 * holds finite arrivals in order H3 before H2).  The measured data come from
 * $SLUICE_VALIDATION_DATA (default /work/shared/validation); without them
 * the test is skipped with a message. */
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
#include <unistd.h>

#define OUT   "tests/output/spheric"
#define CASE  OUT "/case"
#define TABLE CASE "/postProcessing/compareExperiment/table.csv"

static int quick(void)
{
    const char *q = getenv("SLUICE_QUICK");
    return q && q[0] == '1';
}

static const char *data_dir(void)
{
    const char *d = getenv("SLUICE_VALIDATION_DATA");
    return d && *d ? d : "/work/shared/validation";
}

static void test_front_arrival(void **state)
{
    (void)state;
    char csv_path[512];
    snprintf(csv_path, sizeof csv_path, "%s/spheric_test2_kleefsman2005_exp.csv", data_dir());
    if (access(csv_path, R_OK) != 0) {
        printf("  no measured data %s (set SLUICE_VALIDATION_DATA): skipped\n", csv_path);
        skip();
    }
    const char *r0 = quick() ? "0.05" : "0.025", *end = quick() ? "0.45" : "0.5";
    if (run("rm -rf " CASE " && mkdir -p " OUT " && %s/cloneCase cases/sphericTest2 " CASE,
            bin_dir()))
        fail_msg("cloneCase: %s", output);
    if (run("%s/editDictionary -entry r0 -set %s " CASE "/constant/fluidProperties && "
            "%s/editDictionary -entry endTime -set %s " CASE "/system/controlDict && "
            "%s/editDictionary -entry writeInterval -set %s " CASE "/system/controlDict",
            bin_dir(), r0, bin_dir(), end, bin_dir(), end))
        fail_msg("editDictionary: %s", output);
    if (run("timeout 900 %s/pcisph -case " CASE " -quiet > " CASE "/log.pcisph 2>&1", bin_dir())) {
        run("tail -5 " CASE "/log.pcisph");
        fail_msg("the solver failed on sphericTest2 at r0 = %s: %s", r0, output);
    }
    if (run("%s/compareExperiment -case " CASE " -data %s -noPlot -window 0:%s", bin_dir(),
            csv_path, end))
        fail_msg("compareExperiment: %s", output);
    char *t = slurp(TABLE);
    const double thr = table_metric(t, "heights,H3,threshold");
    const double h3_sim = table_metric(t, "heights,H3,arrival_sim");
    const double h3_exp = table_metric(t, "heights,H3,arrival_exp");
    const double h2_sim = table_metric(t, "heights,H2,arrival_sim");
    const double h2_exp = table_metric(t, "heights,H2,arrival_exp");
    free(t);
    printf("  r0 = %s m, arrival at %.3g m: H3 %.3f s (experiment %.3f s), H2 %.3f s "
           "(experiment %.3f s)\n",
           r0, thr, h3_sim, h3_exp, h2_sim, h2_exp);
    assert_true(isfinite(h3_sim) && isfinite(h2_sim));
    assert_true(h3_sim > 0.1 && h3_sim < h2_sim);
    if (quick()) return;
    /* the same events as the 0.19 s and 0.36 s */
    assert_true(fabs(thr - 0.02) < 1e-12);
    assert_true(fabs(h3_exp - 0.19) <= 0.03);
    assert_true(fabs(h2_exp - 0.36) <= 0.03);
    if (!(fabs(h3_sim - h3_exp) <= 0.05))
        fail_msg("the front reaches H3 at %.3f s, the experiment at %.3f s: more than 0.05 s "
                 "apart",
                 h3_sim, h3_exp);
    if (!(fabs(h2_sim - h2_exp) <= 0.05))
        fail_msg("the front reaches H2 at %.3f s, the experiment at %.3f s: more than 0.05 s "
                 "apart",
                 h2_sim, h2_exp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_front_arrival),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
