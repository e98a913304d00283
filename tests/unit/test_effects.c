/* Effects: a case gets exactly the effects it names (call counts in the
 * log), adding one changes the result in its physical direction (cohesion
 * lowers the free surface, the density correction raises the surface
 * density), and surface tension rounds a cube of
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

/* A fact of the top layer of a test case's last time (inspect_case.py). */
static double top_layer(const char *name, const char *key)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd,
             "/usr/bin/python3 tests/cases/inspect_case.py tests/output/%s --r0 0.025", name);
    double v = script_value(cmd, key);
    assert_true(v == v && v != -1.0); /* present and not NaN */
    return v;
}

static const char *short_tank = "sed -i 's/^endTime .*/endTime 0.05;/; s/^writeInterval "
                                ".*/writeInterval 0.05;/' system/controlDict";

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
             "%s && printf 'surfaceTension { kappa 0.005; }\\n' >> constant/fluidProperties",
             short_tank);
    assert_int_equal(run_edited("tests/cases/hydrostaticTank", "effectsTension", edit), 0);
    assert_int_equal(effect_calls("effectsTension", "surfaceTension"), 25);
    /* cohesion pulls the free surface into the fluid: the top layer sits lower */
    const double ztop_plain = top_layer("effectsPlain", "z_top");
    const double ztop_tension = top_layer("effectsTension", "z_top");
    print_message("top layer z: plain %.6f, surfaceTension %.6f\n", ztop_plain, ztop_tension);
    assert_true(ztop_plain > 0.3 && ztop_plain < 0.45);
    assert_true(ztop_tension < ztop_plain - 5e-6); /* 1.9e-5 m lower when written */
    snprintf(edit, sizeof edit,
             "%s && printf 'surfaceDensityCorrection { }\\n' >> constant/fluidProperties",
             short_tank);
    assert_int_equal(run_edited("tests/cases/hydrostaticTank", "effectsBK", edit), 0);
    assert_true(effect_calls("effectsBK", "surfaceDensityCorrection") >= 25 * 3);
    /* the correction restores the deficient density of the free surface */
    const double rho_plain = top_layer("effectsPlain", "rho_top");
    const double rho_bk = top_layer("effectsBK", "rho_top");
    print_message("top layer density: plain %.3f, surfaceDensityCorrection %.3f\n", rho_plain,
                  rho_bk);
    assert_true(rho_plain > 500.0 && rho_plain < 1000.0);
    assert_true(rho_bk > rho_plain + 10.0 && rho_bk < 1100.0);
}

/* A 10^3 cube without gravity: the sphericity r_eq / r_98 grows. */
static void test_droplet_rounds(void **state)
{
    (void)state;
    assert_int_equal(
        run_edited("tutorials/droplet", "droplet",
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
