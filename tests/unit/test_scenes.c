/* Scenes: every tutorial and case runs for a short time with no NaN and no
 * particle outside its tank; the moving paddle of the wave case pushes the
 * water without being penetrated. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "case_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int run_short(const char *src, const char *name, const char *end)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "rm -rf tests/output/%s && mkdir -p tests/output && cp -r %s tests/output/%s && "
             "sed -i 's/^endTime .*/endTime %s;/; s/^writeInterval .*/writeInterval %s;/' "
             "tests/output/%s/system/controlDict && %s/pcisph -case tests/output/%s -quiet "
             "> tests/output/%s/log.pcisph 2>&1",
             name, src, name, end, end, name, bin_dir(), name, name);
    return system(cmd);
}

typedef struct scene {
    const char *dir;
    const char *bounds; /* --lo ... --hi ...: the tank */
} scene;

static const scene scenes[] = {
    {"tutorials/damBreak", "--lo 0 0 0 --hi 1.6 0.6 0.8"},
    {"tutorials/hydrostaticTank", "--lo 0 0 0 --hi 0.3 0.3 0.6"},
    {"tutorials/droplet", "--lo -1 -1 -1 --hi 1 1 1"},
    {"tutorials/filling", "--lo 0 0 0 --hi 0.2 0.2 0.4"},
    {"tutorials/sloshingTank", "--lo -0.05 0 -0.05 --hi 0.65 0.15 0.35"},
    {"cases/shock", "--lo 0 0 0 --hi 1 1 1.6"},
    {"cases/cbdSmall", "--lo 0 0 0 --hi 1.2 1.2 1.2"},
    {"cases/wave", "--lo 0 0 0 --hi 4 0.5 1"},
    {"cases/glass", "--lo -0.3 -0.3 0 --hi 0.3 0.3 0.5"},
    {"cases/splishDamBreak", "--lo -2 -0.75 0 --hi 2 0.75 3"},
};

static void test_every_scene_runs(void **state)
{
    (void)state;
    char cmd[1024], name[128];
    for (size_t k = 0; k < sizeof scenes / sizeof *scenes; k++) {
        snprintf(name, sizeof name, "scene_%s", strrchr(scenes[k].dir, '/') + 1);
        if (run_short(scenes[k].dir, name, "0.1") != 0) fail_msg("%s did not run", scenes[k].dir);
        snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/cases/inspect_case.py tests/output/%s %s",
                 name, scenes[k].bounds);
        double nan = script_value(cmd, "nan"), out = script_value(cmd, "outside");
        if (nan != 0 || out != 0)
            fail_msg("%s: %g non-finite values, %g particles outside", scenes[k].dir, nan, out);
    }
}

/* The wave generator: by 0.4 s the paddle has moved 0.08 m into the water;
 * no particle is inside it at any written time. */
static void test_paddle_not_penetrated(void **state)
{
    (void)state;
    assert_int_equal(run_short("cases/wave", "paddle", "0.4"), 0);
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "sed -i 's/^writeInterval .*/writeInterval 0.1;/' "
             "tests/output/paddle/system/controlDict && "
             "rm -rf tests/output/paddle/0.4 && %s/pcisph -case tests/output/paddle -quiet > "
             "/dev/null 2>&1",
             bin_dir());
    assert_int_equal(system(cmd), 0);
    const char *times[] = {"0.1", "0.2", "0.3", "0.4"};
    double moved = 0;
    for (int k = 0; k < 4; k++) {
        snprintf(cmd, sizeof cmd,
                 "/usr/bin/python3 tests/cases/inside_body.py tests/output/paddle %s 1", times[k]);
        assert_true(script_value(cmd, "inside") == 0);
    }
    FILE *p = popen("/usr/bin/python3 tests/cases/inside_body.py tests/output/paddle 0.4 1", "r");
    char line[256];
    while (fgets(line, sizeof line, p))
        if (!strncmp(line, "lo=", 3))
            moved = strtod(line + 3, NULL) - 0.1125; /* x of the back face at rest */
    pclose(p);
    print_message("paddle moved %.3f m\n", moved);
    assert_true(moved > 0.05);
}

/* The number after `key` in the file `path` (the first match); -1 if none. */
static double log_number(const char *path, const char *key)
{
    char line[1024];
    double v = -1;
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("no %s", path);
    while (fgets(line, sizeof line, f)) {
        char *at = strstr(line, key);
        if (at) {
            v = strtod(at + strlen(key), NULL);
            break;
        }
    }
    fclose(f);
    return v;
}

/* cases/splishDamBreak places SPlisHSPlasH's DamBreak particles: 19^3 =
 * 6,859 at spacing 0.05 m, and after ./setLevel 59319 39^3 = 59,319 at
 * 0.025 m; ./setLevel 6859 goes back.  One step each. */
static void test_splish_levels(void **state)
{
    (void)state;
    static const struct {
        const char *level;
        double n, r0;
    } levels[] = {{"59319", 59319, 0.025}, {"6859", 6859, 0.05}};
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "rm -rf tests/output/splishLevels && mkdir -p tests/output && "
             "cp -r cases/splishDamBreak tests/output/splishLevels && "
             "sed -i 's/^endTime .*/endTime 0.0001;/; s/^writeInterval .*/writeInterval 0.0001;/' "
             "tests/output/splishLevels/system/controlDict");
    assert_int_equal(system(cmd), 0);
    for (size_t k = 0; k < sizeof levels / sizeof *levels; k++) {
        snprintf(cmd, sizeof cmd,
                 "SLUICE_BIN=%s tests/output/splishLevels/setLevel %s && "
                 "%s/pcisph -case tests/output/splishLevels -quiet > tests/output/splishLevels/log "
                 "2>&1",
                 bin_dir(), levels[k].level, bin_dir());
        if (system(cmd) != 0) fail_msg("level %s did not run", levels[k].level);
        double n = log_number("tests/output/splishLevels/log", "fluid particles");
        double r0 = log_number("tests/output/splishLevels/log", "particle spacing r0");
        if (n != levels[k].n || r0 != levels[k].r0)
            fail_msg("level %s: %g fluid particles at r0 %g, expected %g at %g", levels[k].level, n,
                     r0, levels[k].n, levels[k].r0);
    }
    assert_int_equal(system("SLUICE_BIN=bin tests/output/splishLevels/setLevel 1000 "
                            "> /dev/null 2>&1") == 0,
                     0);
}

/* cases/glass at ./setLevel 75k (the paper's Glass scale, doc/timestep-cost.md):
 * r0 0.01 m and the emitter's 80 lattice points at 0.9375 m/s, so the first
 * 0.05 s emit 4 layers, 320 particles (74,960 in 10 s); ./setLevel 6k gives
 * back the committed case byte for byte. */
static void test_glass_levels(void **state)
{
    (void)state;
    char cmd[4096];
    snprintf(
        cmd, sizeof cmd,
        "rm -rf tests/output/glassLevels && mkdir -p tests/output && "
        "cp -r cases/glass tests/output/glassLevels && "
        "SLUICE_BIN=%s tests/output/glassLevels/setLevel 75k > /dev/null && "
        "%s/editDictionary -entry endTime -set 0.05 tests/output/glassLevels/system/controlDict "
        "> /dev/null && %s/editDictionary -entry writeInterval -set 0.05 "
        "tests/output/glassLevels/system/controlDict > /dev/null && "
        "%s/pcisph -case tests/output/glassLevels -quiet > tests/output/glassLevels/log 2>&1",
        bin_dir(), bin_dir(), bin_dir(), bin_dir());
    if (system(cmd) != 0) fail_msg("cases/glass at level 75k did not run");
    double r0 = log_number("tests/output/glassLevels/log", "particle spacing r0");
    if (r0 != 0.01) fail_msg("level 75k: r0 %g, expected 0.01", r0);
    /* the number of fluid particles written at 0.05 s (the .vtu header) */
    FILE *f = popen("grep -a -o 'NumberOfPoints=\"[0-9]*\"' "
                    "tests/output/glassLevels/0.05/fluid.vtu | head -1 | tr -dc 0-9",
                    "r");
    assert_non_null(f);
    long n = -1;
    if (fscanf(f, "%ld", &n) != 1) n = -1;
    pclose(f);
    if (n != 320) fail_msg("level 75k: %ld fluid particles at 0.05 s, expected 320", n);
    snprintf(cmd, sizeof cmd,
             "SLUICE_BIN=%s tests/output/glassLevels/setLevel 6k > /dev/null && "
             "diff -r cases/glass/constant tests/output/glassLevels/constant > /dev/null && "
             "diff -r cases/glass/system tests/output/glassLevels/system > /dev/null",
             bin_dir());
    if (system(cmd) != 0) fail_msg("setLevel 6k after 75k does not give back cases/glass");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_scene_runs),
        cmocka_unit_test(test_paddle_not_penetrated),
        cmocka_unit_test(test_splish_levels),
        cmocka_unit_test(test_glass_levels),
    };
    return cmocka_run_group_tests_name("scenes", tests, NULL, NULL);
}
