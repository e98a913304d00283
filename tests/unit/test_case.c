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
    assert_int_equal(a.effects.n, b.effects.n);        /* the same effects, in order */
    for (size_t k = 0; k < a.effects.n; k++)
        assert_ptr_equal(a.effects.e[k].type, b.effects.e[k].type);
    assert_int_equal(b.nshapes, 3);
    case_free(&a);
    case_free(&b);
}

typedef struct bad_input {
    const char *file;    /* file to change in the minimal case */
    const char *append;  /* text appended to it (or NULL) */
    const char *replace; /* whole new content (or NULL) */
    const char *expect1; /* substrings the error must contain */
    const char *expect2;
} bad_input;

static const bad_input bad_inputs[] = {
    {"constant/fluidProperties", NULL,
     "particleSpacing 0.02;\nfluidRegions { a { type box; min (0 0 0); max (1 1 1); } }\n",
     "constant/fluidProperties", "'rho0'"},
    {"constant/fluidProperties", "particleSpacing -0.01;\n", NULL, "fluidProperties:4",
     "particleSpacing"},
    {"constant/fluidProperties", "particleSpacing 0;\n", NULL, "fluidProperties:4",
     "particleSpacing"},
    {"constant/fluidProperties", "eta nan;\n", NULL, "fluidProperties:4", "eta"},
    {"constant/fluidProperties", "eta 1e999;\n", NULL, "fluidProperties:4", "eta"},
    {"constant/fluidProperties", "gravity (0 0);\n", NULL, "fluidProperties:4", "gravity"},
    {"constant/fluidProperties", "maxIterations 2;\n", NULL, "fluidProperties:4", "maxIterations"},
    {"constant/fluidProperties", "kernelSupport 1.5;\n", NULL, "fluidProperties:4",
     "'kernelSupport'"},
    {"constant/fluidProperties", "pressureSource { type divergence; meanPressure 0; }\n", NULL,
     "fluidProperties:4", "'meanPressure': only in a box periodic along every axis"},
    {"constant/fluidProperties", "pressureSource { type mixed; meanPressure 0; }\n", NULL,
     "fluidProperties:4", "'meanPressure': is an option of type divergence only"},
    {"constant/fluidProperties", "pressureSource { type divergence; meanPressure low; }\n", NULL,
     "fluidProperties:4", "'meanPressure'"},
    {"constant/fluidProperties", "laminarViscosity { nu 0.001; normalized scalar; }\n", NULL,
     "fluidProperties:4",
     "'normalized': must be off, on (the sum over the scalar second moment) or tensor"},
    {"constant/fluidProperties",
     "laminarViscosity { nu 0.001; normalized on; tensorLimit 0.02; }\n", NULL, "fluidProperties:4",
     "'tensorLimit': applies to normalized tensor only"},
    {"constant/fluidProperties",
     "laminarViscosity { nu 0.001; normalized tensor; tensorLimit -1; }\n", NULL,
     "fluidProperties:4",
     "'tensorLimit': must be none, zero (the scalar normalization) or positive"},
    {"constant/fluidProperties", "kernel gaussian;\n", NULL, "fluidProperties:4",
     "must be cubicSpline (Monaghan 1992, the paper's) or wendlandC2"},
    {"constant/fluidProperties", "initialPacking hexagonal;\n", NULL, "fluidProperties:4",
     "'hexagonal' is not one of: cubic relaxed"},
    {"constant/fluidProperties", "initialPacking (relaxed);\n", NULL, "fluidProperties:4",
     "initialPacking"},
    {"constant/fluidProperties", "initialPacking { type relaxed; steps 0; }\n", NULL,
     "fluidProperties:4", "'steps'"},
    {"constant/fluidProperties", "initialPacking { type relaxed; jitter 0.6; }\n", NULL,
     "fluidProperties:4", "'jitter'"},
    {"constant/fluidProperties", "initialPacking { type relaxed; tolerance 0; }\n", NULL,
     "fluidProperties:4", "'tolerance'"},
    {"constant/fluidProperties", "initialPacking { type relaxed; tolerance -1e-4; }\n", NULL,
     "fluidProperties:4", "'tolerance'"},
    {"constant/fluidProperties", "initialPacking { type relaxed; tolerance small; }\n", NULL,
     "fluidProperties:4", "tolerance"},
    {"constant/fluidProperties", "rho0 1000\nrho0 2;\n", NULL, "fluidProperties:4", "rho0"},
    {"constant/fluidProperties", NULL,
     "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { a { type box; min (5 5 5); max (6 6 6); } "
     "}\n",
     "fluidProperties:3: fluid region 'a' lies outside the container ('tank')", "beyond the walls"},
    {"constant/fluidProperties", NULL, "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { }\n",
     "fluidProperties", "fluidRegions"},
    {"constant/fluidProperties", NULL,
     "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { a { type cone; min (0 0 0); max (1 1 1); } "
     "}\n",
     "fluidProperties:3", "'cone'"},
    {"constant/boundaryProperties", "method magic;\n", NULL, "boundaryProperties:2", "magic"},
    {"constant/boundaryProperties", "epsilon 2;\n", NULL, "boundaryProperties:2", "epsilon"},
    {"constant/boundaryProperties", "massFactor 0;\n", NULL, "boundaryProperties:2", "massFactor"},
    {"constant/boundaryProperties",
     "geometry { t { type container; min (0 0 0); max (1 -1 1); } }\n", NULL,
     "boundaryProperties:2", "max"},
    {"constant/boundaryProperties",
     "geometry { t { type container; min (0 0 0); max (1 1 1); open (top); } }\n", NULL,
     "boundaryProperties:2", "top"},
    {"system/controlDict", "endTime -1;\n", NULL, "controlDict:3", "endTime"},
    {"system/controlDict", "writeFormat xml;\n", NULL, "controlDict:3", "xml"},
    {"system/controlDict", "timePrecision 40;\n", NULL, "controlDict:3", "timePrecision"},
    {"system/controlDict", "startFrom { a 1; }\n", NULL, "controlDict:3", "startFrom"},
    {"system/timeStepDict", NULL, "mode constant;\n", "timeStepDict", "'deltaT'"},
    {"system/timeStepDict", "deltaT -1;\n", NULL, "timeStepDict:2", "deltaT"},
    {"system/timeStepDict", "deltaT 0.001 /* unterminated\n", NULL, "timeStepDict:2", "comment"},
    {"system/timeStepDict", "controller fastest;\n", NULL, "timeStepDict:2",
     "'fastest' is not one of: ihmsen2010 cost"},
    {"system/timeStepDict", NULL, "mode adaptive;\ncontroller cost;\ncostMaxDensity 12;\n",
     "timeStepDict:3", "costMaxDensity"},
    {"constant/boundaryProperties", "geometry { t { type container; min (0 0 0) max (1 1 1); } }\n",
     NULL, "boundaryProperties:2", "min"},
    {"constant/fluidProperties", "#include \"nowhere\"\n", NULL, "fluidProperties:4", "nowhere"},
    {"constant/fluidProperties", "x $undefinedVariable;\n", NULL, "fluidProperties:4",
     "undefinedVariable"},
    /* issue 13, item 9: a region reaching out of the tank (z to 1.2 in a
     * 0.8 m tank) is refused, naming file, line and region */
    {"constant/fluidProperties", NULL,
     "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { a { type box; min (0 0 0); max (0.4 0.6 "
     "1.2); } }\n",
     "fluidProperties:3: fluid region 'a' reaches outside the container ('tank')",
     "beyond the walls"},
    {"constant/fluidProperties", NULL,
     "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions { b { type sphere; centre (1.5 0.3 0.4); "
     "radius 0.2; } }\n",
     "fluidProperties:3: fluid region 'b' reaches outside", "'tank'"},
    /* item 10: an emitter outside the tank, or inside a solid */
    {"constant/fluidProperties",
     "emitters { jet { type disc; centre (2 0.3 0.5); direction (0 0 -1); radius 0.05; speed 1; } "
     "}\n",
     NULL, "fluidProperties:4: emitter 'jet' opens outside the container geometry 'tank'",
     "beyond the walls"},
    /* siblings: regions over one another; an emitter pointing out of the
     * tank; an emitter that ends before it starts */
    {"constant/fluidProperties", NULL,
     "rho0 1000;\nparticleSpacing 0.02;\nfluidRegions\n{\n    a { type box; min (0 0 0); max (0.4 "
     "0.6 0.4); }\n"
     "    b { type sphere; centre (0.2 0.3 0.4); radius 0.1; }\n}\n",
     "fluidProperties:6: fluid region 'b' overlaps fluid region 'a'", "double the density"},
    {"constant/fluidProperties",
     "emitters { jet { type disc; centre (0.8 0.3 0.01); direction (0 0 -1); radius 0.05; speed 1; "
     "} }\n",
     NULL, "fluidProperties:4: emitter 'jet' points out of the container geometry 'tank'",
     "downstream"},
    {"constant/fluidProperties",
     "emitters { jet { type disc; centre (0.8 0.3 0.5); direction (0 0 -1); radius 0.05; speed 1; "
     "startTime 2; endTime 1; } }\n",
     NULL, "fluidProperties:4: keyword 'endTime'", "never emit"},
    /* item 16: the messages say the limits */
    {"system/controlDict", "numberOfThreads 5000;\n", NULL, "controlDict:3", "from 1 to 4096"},
    {"constant/fluidProperties", "eta 100;\n", NULL, "fluidProperties:4", "below 100"},
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
        snprintf(cmd, sizeof cmd,
                 b->replace ? "cp tests/output/tmp_replace %s/%s"
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
        if (rc == 0 || !strstr(msg, b->expect1) || !strstr(msg, b->expect2) ||
            strstr(msg, "Sanitizer"))
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

/* ---- issue 13: warnings and refusals that need more than one file ---- */

/* Runs `setup` (shell, in the fresh minimal case `dir`), then `tool`
 * (sampleBoundary reads and builds the case without running it; pcisph
 * runs to endTime 1); returns its exit status, stderr in msg. */
static int run_minimal(const char *dir, const char *setup, const char *tool, char *msg, size_t len)
{
    char cmd[8192];
    write_minimal(dir);
    snprintf(cmd, sizeof cmd, "cd %s && %s", dir, setup);
    sh(cmd);
    snprintf(cmd, sizeof cmd, "%s/%s -case %s %s > %s/out.txt 2> %s/err.txt", bin_dir(), tool, dir,
             strcmp(tool, "pcisph") ? "" : "-quiet", dir, dir);
    int rc = system(cmd);
    snprintf(cmd, sizeof cmd, "%s/err.txt", dir);
    FILE *f = fopen(cmd, "r");
    assert_non_null(f);
    size_t n = fread(msg, 1, len - 1, f);
    msg[n] = 0;
    fclose(f);
    return rc;
}

static size_t count_of(const char *text, const char *part)
{
    size_t n = 0;
    for (const char *at = text; (at = strstr(at, part)) != NULL; at += strlen(part)) n++;
    return n;
}

typedef struct warned_input {
    const char *what;    /* for the table */
    const char *setup;   /* shell commands in the minimal case */
    const char *expect1; /* substrings the warning must contain */
    const char *expect2;
} warned_input;

/* Legal input that is almost surely a mistake: the run goes on, with a
 * warning naming file, line and key (items 13, 16 and their siblings). */
static const warned_input warned_inputs[] = {
    {"eta 1; ... eta 5; (a key set twice)",
     "printf 'eta 1;\nminIterations 3;\neta 5;\n' >> constant/fluidProperties",
     "fluidProperties:6: keyword 'eta' in dictionary 'fluidProperties' is set twice, at lines 4 "
     "and 6",
     "the value of line 6 is used"},
    {"a fluid region named twice",
     "printf 'fluidRegions { a { type box; min (0 0 0); max (0.2 0.2 0.2); }\n"
     " a { type box; min (1 0 0); max (1.2 0.2 0.2); } }\n' >> constant/fluidProperties",
     "fluidProperties:5: keyword 'a' in dictionary 'fluidRegions' is set twice, at lines 4 and 5",
     ""},
    {"eta 0.5; in system/controlDict", "echo 'eta 0.5;' >> system/controlDict",
     "controlDict:3: unknown keyword 'eta' in dictionary 'controlDict'",
     "belongs in constant/fluidProperties"},
    {"deltaT 0.001; in system/controlDict", "echo 'deltaT 0.001;' >> system/controlDict",
     "controlDict:3: unknown keyword 'deltaT'", "belongs in system/timeStepDict"},
    {"eta 50;", "echo 'eta 50;' >> constant/fluidProperties",
     "fluidProperties:4: keyword 'eta': 50 %", "is it a percentage?"},
    {"gravity (0 0 -981); (cm/s^2)", "echo 'gravity (0 0 -981);' >> constant/fluidProperties",
     "fluidProperties:4: keyword 'gravity'", "wrong units (cm/s^2)?"},
    {"numberOfThreads 4000; on a machine with fewer cores",
     "echo 'numberOfThreads 4000;' >> system/controlDict",
     "controlDict:3: keyword 'numberOfThreads'", "cores run slower"},
    {"an open obstacle mesh (a box without a lid)",
     "cp ../../data/mesh/bad/open.obj constant/ && echo 'geometry { tank { type container; "
     "min (0 0 0); max (1.6 0.6 0.8); } lidless { type mesh; file \"open.obj\"; scale 0.2; "
     "translate (1 0.2 0); } }' >> constant/boundaryProperties",
     "constant/open.obj: mesh is not closed: 4 edges are used by one triangle only", "open sheet"},
    {"an obstacle wholly outside the tank (wrong translate)",
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "b { type box; min (5 0 0); max (5.2 0.2 0.2); } }' >> constant/boundaryProperties",
     "geometry 'b' (5 0 0)-(5.2 0.2 0.2) lies wholly outside the container ('tank')",
     "wrong translate"},
    {"an emitter that starts after endTime",
     "echo 'emitters { jet { type disc; centre (1 0.3 0.5); direction (0 0 -1); radius 0.05; "
     "speed 1; startTime 3; } }' >> constant/fluidProperties",
     "fluidProperties:4: keyword 'startTime': 3 s is at or after the run's endTime (1 s",
     "never emits"},
    {"an emitter that delivers more than the tank holds",
     "echo 'emitters { jet { type disc; centre (1 0.3 0.5); direction (0 0 -1); radius 0.1; "
     "speed 100; } }' >> constant/fluidProperties",
     "fluidProperties:4: emitter 'jet' delivers", "the fluid will overflow"},
};

static void test_warned_inputs(void **state)
{
    (void)state;
    const char *dir = "tests/output/case_warned";
    static char msg[1 << 16];
    for (size_t k = 0; k < sizeof warned_inputs / sizeof *warned_inputs; k++) {
        const warned_input *w = &warned_inputs[k];
        int rc = run_minimal(dir, w->setup, "sampleBoundary", msg, sizeof msg);
        if (rc != 0 || !strstr(msg, w->expect1) || !strstr(msg, w->expect2) ||
            !strstr(msg, "Warning:"))
            fail_msg("'%s': exit %d, wanted a warning with '%s' and '%s'; got: %.600s", w->what, rc,
                     w->expect1, w->expect2, msg);
        size_t len = 0; /* the warning checked, not an earlier one */
        const char *line = hostile_line_with(msg, w->expect1, &len);
        char row[2048];
        snprintf(row, sizeof row, "%.*s", (int)(len < sizeof row ? len : sizeof row - 1), line);
        hostile_record("warned (the run goes on)", w->what, row);
    }
}

/* Overriding what an #include brought in is OpenFOAM's idiom: no warning;
 * neither for `$sub;` merged entries nor for a key set once. */
static void test_override_is_not_a_duplicate(void **state)
{
    (void)state;
    static char msg[1 << 16];
    int rc =
        run_minimal("tests/output/case_override",
                    "echo 'eta 1; minIterations 3;' > constant/defaults && "
                    "(echo '#include \"defaults\"'; echo 'eta 2;'; echo 'base { alpha 0.1; }'; "
                    "echo 'viscosity { $base; alpha 0.2; soundSpeed 20; }') "
                    ">> constant/fluidProperties",
                    "sampleBoundary", msg, sizeof msg);
    if (rc != 0 || strstr(msg, "twice") || strstr(msg, "Error"))
        fail_msg("exit %d, message: %s", rc, msg);
}

/* Item 15: 20000 unknown keys give a few lines and a count, not 20000. */
static void test_unknown_keys_capped(void **state)
{
    (void)state;
    static char msg[1 << 16];
    int rc = run_minimal("tests/output/case_manykeys",
                         "awk 'BEGIN { for (i = 0; i < 20000; i++) printf \"stray%d 1;\\n\", i }' "
                         ">> system/controlDict",
                         "sampleBoundary", msg, sizeof msg);
    assert_int_equal(rc, 0);
    size_t lines = count_of(msg, "unknown keyword 'stray");
    if (lines < 1 || lines > 10) fail_msg("%zu unknown-key lines: %.2000s", lines, msg);
    assert_non_null(strstr(msg,
                           "... and 19990 more unknown keywords in dictionary 'controlDict' "
                           "(the last at line 20002)"));
    hostile_record("warned (the run goes on)", "20000 unknown keys in system/controlDict",
                   strstr(msg, "Warning: ") ? strstr(msg, "... and") : msg);
}

/* Item 10: an emitter inside a solid is refused; one above an open top,
 * pouring in, is accepted. */
static void test_emitter_places(void **state)
{
    (void)state;
    static char msg[1 << 16];
    const char *jet = "echo 'emitters { jet { type disc; centre (1.1 0.3 0.5); direction (0 0 -1); "
                      "radius 0.05; speed 1; } }' >> constant/fluidProperties && ";
    char setup[2048];
    snprintf(
        setup, sizeof setup,
        "%s echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
        "post { type box; min (1 0.2 0); max (1.2 0.4 0.7); } }' >> constant/boundaryProperties",
        jet);
    int rc = run_minimal("tests/output/case_emitter", setup, "pcisph", msg, sizeof msg);
    if (rc == 0 ||
        !strstr(msg, "fluidProperties:4: emitter 'jet' opens inside the solid geometry 'post'"))
        fail_msg("exit %d, message: %s", rc, msg);
    assert_null(strstr(msg, "Progress"));
    hostile_record("constant/fluidProperties", "an emitter inside an obstacle", msg);
    rc = run_minimal("tests/output/case_emitter",
                     "echo 'emitters { jet { type disc; centre (1.1 0.3 1.0); direction (0 0 -1); "
                     "radius 0.05; speed 1; } }' >> constant/fluidProperties && "
                     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); "
                     "open (zMax); } }' >> constant/boundaryProperties",
                     "sampleBoundary", msg, sizeof msg);
    if (rc != 0) fail_msg("a jet pouring in through the open top was refused: %s", msg);
}

int main(void)
{
    sl_log_set_quiet(1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_etc_defaults_are_compiled_defaults),
        cmocka_unit_test(test_bad_input_table),
        cmocka_unit_test(test_unknown_key_warning),
        cmocka_unit_test(test_warned_inputs),
        cmocka_unit_test(test_override_is_not_a_duplicate),
        cmocka_unit_test(test_unknown_keys_capped),
        cmocka_unit_test(test_emitter_places),
    };
    return cmocka_run_group_tests_name("case", tests, NULL, NULL);
}
