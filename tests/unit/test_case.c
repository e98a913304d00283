/* Case reader tests: the annotated defaults in etc/caseDicts are the
 * compiled defaults, and bad input stops the solver with a message naming
 * the file, line and keyword, a non-zero exit and no output written. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "case/case.h"
#include "core/sl_log.h"
#include "hostile_table.h"

static const char *bin_dir(void)
{
    const char *b = getenv("SLUICE_BIN");
    return b ? b : "bin";
}

static void sh(const char *cmd)
{
    int rc = system(cmd);
    if (rc != 0) fail_msg("command failed (%d): %s", rc, cmd);
}

/* Minimal case: only the required keys. */
static void write_minimal(const char *dir)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "rm -rf %s && mkdir -p %s/system %s/constant && cd %s && "
             "printf 'endTime 1;\\nwriteInterval 0.05;\\n' > system/controlDict && "
             "printf 'deltaT 0.001;\\n' > system/timeStepDict && "
             "printf 'rho0 1000;\\nparticleSpacing 0.02;\\n"
             "fluidRegions { column { type box; min (0 0 0); max (0.4 0.6 0.6); } }\\n' "
             "> constant/fluidProperties && "
             "printf 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } }\\n' "
             "> constant/boundaryProperties",
             dir, dir, dir, dir);
    sh(cmd);
}

/* Reading etc/caseDicts gives the same parameters as the defaults. */
static void test_etc_defaults_are_compiled_defaults(void **state)
{
    (void)state;
    sl_case a, b;
    write_minimal("tests/output/case_minimal");
    sh("rm -rf tests/output/case_etc && mkdir -p tests/output/case_etc/system "
       "tests/output/case_etc/constant && "
       "cp etc/caseDicts/controlDict etc/caseDicts/timeStepDict tests/output/case_etc/system/ && "
       "cp etc/caseDicts/fluidProperties etc/caseDicts/boundaryProperties "
       "tests/output/case_etc/constant/");
    case_read(&a, "tests/output/case_minimal");
    case_read(&b, "tests/output/case_etc");
    assert_memory_equal(&a.ctl, &b.ctl, sizeof a.ctl);
    assert_memory_equal(&a.prm, &b.prm, sizeof a.prm); /* every parameter, restitution too */
    assert_int_equal(a.effects.n, b.effects.n);         /* the same effects, in order */
    for (size_t k = 0; k < a.effects.n; k++)
        assert_ptr_equal(a.effects.e[k].type, b.effects.e[k].type);
    assert_int_equal(b.nshapes, 3);
    case_free(&a);
    case_free(&b);
}

typedef struct bad_input {
    const char *file;     /* file to change in the minimal case */
    const char *append;   /* text appended to it (or NULL) */
    const char *replace;  /* whole new content (or NULL) */
    const char *expect1;  /* substrings the error must contain */
    const char *expect2;
} bad_input;

static const bad_input bad_inputs[] = {
    {"constant/fluidProperties", NULL, "particleSpacing 0.02;\nfluidRegions { a { type box; min (0 0 0); max (1 1 1); } }\n",
     "constant/fluidProperties", "'rho0'"},
    {"constant/fluidProperties", "particleSpacing -0.01;\n", NULL, "fluidProperties:4", "particleSpacing"},
    {"constant/fluidProperties", "particleSpacing 0;\n", NULL, "fluidProperties:4", "particleSpacing"},
    {"constant/fluidProperties", "eta nan;\n", NULL, "fluidProperties:4", "eta"},
    {"constant/fluidProperties", "eta 1e999;\n", NULL, "fluidProperties:4", "eta"},
    {"constant/fluidProperties", "gravity (0 0);\n", NULL, "fluidProperties:4", "gravity"},
    {"constant/fluidProperties", "maxIterations 2;\n", NULL, "fluidProperties:4", "maxIterations"},
    {"constant/fluidProperties", "rho0 1000\nrho0 2;\n", NULL, "fluidProperties:4", "rho0"},
    {"constant/fluidProperties", NULL,
     "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { a { type box; min (5 5 5); max (6 6 6); } }\n",
     "fluid region 'a'", "no particle"},
    {"constant/fluidProperties", NULL, "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { }\n",
     "fluidProperties", "fluidRegions"},
    {"constant/fluidProperties", NULL,
     "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { a { type cone; min (0 0 0); max (1 1 1); } }\n",
     "fluidProperties:3", "'cone'"},
    {"constant/boundaryProperties", "method magic;\n", NULL, "boundaryProperties:2", "magic"},
    {"constant/boundaryProperties", "epsilon 2;\n", NULL, "boundaryProperties:2", "epsilon"},
    {"constant/boundaryProperties", "geometry { t { type container; min (0 0 0); max (1 -1 1); } }\n", NULL,
     "boundaryProperties:2", "max"},
    {"constant/boundaryProperties", "geometry { t { type container; min (0 0 0); max (1 1 1); open (top); } }\n", NULL,
     "boundaryProperties:2", "top"},
    {"system/controlDict", "endTime -1;\n", NULL, "controlDict:3", "endTime"},
    {"system/controlDict", "writeFormat xml;\n", NULL, "controlDict:3", "xml"},
    {"system/controlDict", "timePrecision 40;\n", NULL, "controlDict:3", "timePrecision"},
    {"system/controlDict", "startFrom { a 1; }\n", NULL, "controlDict:3", "startFrom"},
    {"system/timeStepDict", NULL, "mode constant;\n", "timeStepDict", "'deltaT'"},
    {"system/timeStepDict", "deltaT -1;\n", NULL, "timeStepDict:2", "deltaT"},
    {"system/timeStepDict", "deltaT 0.001 /* unterminated\n", NULL, "timeStepDict:2", "comment"},
    {"constant/boundaryProperties", "geometry { t { type container; min (0 0 0) max (1 1 1); } }\n", NULL,
     "boundaryProperties:2", "min"},
    {"constant/fluidProperties", "#include \"nowhere\"\n", NULL, "fluidProperties:4", "nowhere"},
    {"constant/fluidProperties", "x $undefinedVariable;\n", NULL, "fluidProperties:4", "undefinedVariable"},
};

/* Each bad input: non-zero exit, the message names file/line and key, and
 * nothing was written into the case. */
static void test_bad_input_table(void **state)
{
    (void)state;
    const char *dir = "tests/output/case_bad";
    char cmd[4096], msg[4096];
    for (size_t k = 0; k < sizeof bad_inputs / sizeof *bad_inputs; k++) {
        const bad_input *b = &bad_inputs[k];
        write_minimal(dir);
        FILE *f = fopen(b->replace ? "tests/output/tmp_replace" : "tests/output/tmp_append", "w");
        assert_non_null(f);
        fputs(b->replace ? b->replace : b->append, f);
        fclose(f);
        snprintf(cmd, sizeof cmd, b->replace ? "cp tests/output/tmp_replace %s/%s"
                                             : "cat tests/output/tmp_append >> %s/%s",
                 dir, b->file);
        sh(cmd);
        snprintf(cmd, sizeof cmd, "%s/pcisph -case %s -quiet > %s/out.txt 2> %s/err.txt", bin_dir(),
                 dir, dir, dir);
        int rc = system(cmd);
        snprintf(cmd, sizeof cmd, "%s/err.txt", dir);
        f = fopen(cmd, "r");
        assert_non_null(f);
        size_t n = fread(msg, 1, sizeof msg - 1, f);
        msg[n] = 0;
        fclose(f);
        if (rc == 0 || !strstr(msg, b->expect1) || !strstr(msg, b->expect2) || strstr(msg, "Sanitizer"))
            fail_msg("bad input %zu (%s += %s): exit %d, message: %s", k, b->file,
                     b->replace ? b->replace : b->append, rc, msg);
        snprintf(cmd, sizeof cmd, "test ! -e %s/0 && test ! -e %s/fluid.pvd", dir, dir);
        assert_int_equal(system(cmd), 0);
        char input[512];
        snprintf(input, sizeof input, "%s%s", b->replace ? "whole file: " : "",
                 b->replace ? b->replace : b->append);
        hostile_record(b->file, input, msg);
    }
}

/* An unknown key is a warning naming the nearest valid one. */
static void test_unknown_key_warning(void **state)
{
    (void)state;
    const char *dir = "tests/output/case_warn";
    char cmd[1024], msg[4096];
    write_minimal(dir);
    snprintf(cmd, sizeof cmd,
             "printf 'endTime 0.002;\\nwriteIntervall 1;\\n' >> %s/system/controlDict && "
             "%s/pcisph -case %s -quiet > /dev/null 2> %s/err.txt",
             dir, bin_dir(), dir, dir);
    sh(cmd);
    snprintf(cmd, sizeof cmd, "%s/err.txt", dir);
    FILE *f = fopen(cmd, "r");
    size_t n = fread(msg, 1, sizeof msg - 1, f);
    msg[n] = 0;
    fclose(f);
    assert_non_null(strstr(msg, "controlDict:4"));
    assert_non_null(strstr(msg, "'writeIntervall'"));
    assert_non_null(strstr(msg, "'writeInterval'"));
}

int main(void)
{
    sl_log_set_quiet(1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_etc_defaults_are_compiled_defaults),
        cmocka_unit_test(test_bad_input_table),
        cmocka_unit_test(test_unknown_key_warning),
    };
    return cmocka_run_group_tests_name("case", tests, NULL, NULL);
}
