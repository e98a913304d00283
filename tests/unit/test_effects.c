/* Effects: a case gets exactly the effects it names (call counts in the
 * log), adding one changes the result, and surface tension rounds a cube of
 * fluid without gravity into a droplet. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "case_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Number of calls the log reports for an effect; -1 if not listed. */
static long effect_calls(const char *name, const char *effect)
{
    char path[512], line[512], key[128];
    long calls = -1;
    snprintf(path, sizeof path, "tests/output/%s/log.pcisph", name);
    snprintf(key, sizeof key, "  effect %s ", effect);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, key, strlen(key))) calls = strtol(line + strlen(key), NULL, 10);
    fclose(f);
    return calls;
}

static const char *short_tank =
    "sed -i 's/^endTime .*/endTime 0.05;/; s/^writeInterval .*/writeInterval 0.05;/' system/controlDict";

static void test_unnamed_effect_is_never_called(void **state)
{
    (void)state;
    assert_int_equal(run_edited("tests/cases/hydrostaticTank", "effectsPlain", short_tank), 0);
    assert_int_equal(effect_calls("effectsPlain", "surfaceTension"), -1);
    assert_int_equal(effect_calls("effectsPlain", "surfaceDensityCorrection"), -1);
    assert_true(effect_calls("effectsPlain", "viscosity") == 25); /* named: every step */
    assert_true(effect_calls("effectsPlain", "gravity") == 25);
}

static void test_named_effect_changes_result(void **state)
{
    (void)state;
    char edit[1024];
    snprintf(edit, sizeof edit,
             "%s && printf 'surfaceTension { kappa 0.005; }\\n' >> constant/fluidProperties", short_tank);
    assert_int_equal(run_edited("tests/cases/hydrostaticTank", "effectsTension", edit), 0);
    assert_int_equal(effect_calls("effectsTension", "surfaceTension"), 25);
    assert_int_not_equal(system("cmp -s tests/output/effectsPlain/0.05/fluid.vtu "
                                "tests/output/effectsTension/0.05/fluid.vtu"), 0);
    snprintf(edit, sizeof edit,
             "%s && printf 'surfaceDensityCorrection { }\\n' >> constant/fluidProperties", short_tank);
    assert_int_equal(run_edited("tests/cases/hydrostaticTank", "effectsBK", edit), 0);
    assert_true(effect_calls("effectsBK", "surfaceDensityCorrection") >= 25 * 3);
    assert_int_not_equal(system("cmp -s tests/output/effectsPlain/0.05/fluid.vtu "
                                "tests/output/effectsBK/0.05/fluid.vtu"), 0);
}

/* A 10^3 cube without gravity: the sphericity r_eq / r_98 grows. */
static void test_droplet_rounds(void **state)
{
    (void)state;
    assert_int_equal(run_edited("tutorials/droplet", "droplet",
                                "sed -i 's/min (-0.1 -0.1 -0.1); max (0.1 0.1 0.1)/min (-0.05 -0.05 -0.05); "
                                "max (0.05 0.05 0.05)/' constant/fluidProperties && "
                                "sed -i 's/^endTime .*/endTime 0.2;/' system/controlDict"),
                     0);
    FILE *p = popen("/usr/bin/python3 tests/cases/sphericity.py tests/output/droplet", "r");
    assert_non_null(p);
    double t, s, spread, s0 = -1, s_end = -1;
    while (fscanf(p, "%lf %lf %lf", &t, &s, &spread) == 3) {
        if (s0 < 0) s0 = s;
        s_end = s;
    }
    assert_int_equal(pclose(p), 0);
    print_message("droplet sphericity %.3f -> %.3f\n", s0, s_end);
    assert_true(s0 > 0.7 && s0 < 0.82); /* a cube */
    assert_true(s_end > s0 + 0.05);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unnamed_effect_is_never_called),
        cmocka_unit_test(test_named_effect_changes_result),
        cmocka_unit_test(test_droplet_rounds),
    };
    return cmocka_run_group_tests_name("effects", tests, NULL, NULL);
}
