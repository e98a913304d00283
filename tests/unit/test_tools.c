/* Tests of the case tools: editDictionary, cloneCase, listTimes, cleanCase,
 * sweepCase, plotSweep and monitorCase, run as programs (from $SLUICE_BIN,
 * default bin/) on files written under tests/output/tools/.  The sweep test
 * runs the solver on a tiny hydrostatic tank (about a second); the plotSweep
 * tests (-pareto, -where) use a hand-written table with a known front. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "hostile_table.h"
#include "tool_run.h"

#include "core/sl_progress.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#define OUT "tests/output/tools"

/* Runs a tool of $SLUICE_BIN with arguments. */
#define tool(name, ...) run("%s/" name " " __VA_ARGS__)

static void fresh(const char *dir)
{
    assert_int_equal(run("rm -rf %s && mkdir -p %s", dir, dir), 0);
}

/* ---- editDictionary ---------------------------------------------------------- */

static const char *dict_text =
    "FoamFile { version 2.0; format ascii; class dictionary; object props; }\n"
    "/* block comment */\n"
    "#include \"common\"\n"
    "rho0            $rhoWater;      // from common\n"
    "eta             1;              // percent\n"
    "gravity         (0 0 -9.81);\n"
    "viscosity\n"
    "{\n"
    "    alpha       0.05;   // Becker & Teschner\n"
    "    soundSpeed  20;\n"
    "}\n"
    "\n"
    "// ****** //\n";
static const char *common_text = "// shared\nrhoWater   1000;   // kg/m^3\n";

static void write_dict(void)
{
    fresh(OUT "/dict");
    spit(OUT "/dict/props", dict_text);
    spit(OUT "/dict/common", common_text);
}

/* The text with the first `from` replaced by `to`. */
static char *replaced(const char *text, const char *from, const char *to)
{
    const char *at = strstr(text, from);
    assert_non_null(at);
    char *s = malloc(strlen(text) + strlen(to) + 1);
    sprintf(s, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
    return s;
}

static void test_edit_set_then_value(void **state)
{
    (void)state;
    write_dict();
    assert_int_equal(
        tool("editDictionary", "-entry viscosity/alpha -set 0.1 " OUT "/dict/props", bin_dir()), 0);
    assert_int_equal(
        tool("editDictionary", "-entry viscosity/alpha -value " OUT "/dict/props", bin_dir()), 0);
    assert_string_equal(output, "0.1\n");
    /* only the value's bytes changed: comments, #include, $var as they were */
    char *text = slurp(OUT "/dict/props"), *want = replaced(dict_text, "0.05;", "0.1;");
    assert_string_equal(text, want);
    free(text);
    free(want);
    text = slurp(OUT "/dict/common");
    assert_string_equal(text, common_text);
    free(text);
    /* a vector, and -value of an entry given by $var */
    assert_int_equal(
        tool("editDictionary", "-entry gravity -set '(0 0 -1.62)' " OUT "/dict/props", bin_dir()),
        0);
    assert_int_equal(tool("editDictionary", "-entry gravity -value " OUT "/dict/props", bin_dir()),
                     0);
    assert_string_equal(output, "(0 0 -1.62)\n");
    assert_int_equal(tool("editDictionary", "-entry rho0 -value " OUT "/dict/props", bin_dir()), 0);
    assert_string_equal(output, "1000\n");
    assert_int_equal(tool("editDictionary", "-entry rho0 " OUT "/dict/props", bin_dir()), 0);
    assert_non_null(strstr(output, "$rhoWater"));
}

static void test_edit_set_in_included_file(void **state)
{
    (void)state;
    write_dict();
    assert_int_equal(
        tool("editDictionary", "-entry rhoWater -set 998 " OUT "/dict/props", bin_dir()), 0);
    assert_non_null(strstr(output, "included file"));
    char *text = slurp(OUT "/dict/common"), *want = replaced(common_text, "1000", "998");
    assert_string_equal(text, want);
    free(text);
    free(want);
    text = slurp(OUT "/dict/props");
    assert_string_equal(text, dict_text);
    free(text);
    assert_int_equal(tool("editDictionary", "-entry rho0 -value " OUT "/dict/props", bin_dir()), 0);
    assert_string_equal(output, "998\n");
}

static void test_edit_add_entries(void **state)
{
    (void)state;
    write_dict();
    assert_int_equal(
        tool("editDictionary", "-entry viscosity/model -set becker " OUT "/dict/props", bin_dir()),
        0);
    assert_int_equal(
        tool("editDictionary", "-entry minIterations -set 3 " OUT "/dict/props", bin_dir()), 0);
    char *text = slurp(OUT "/dict/props");
    assert_non_null(strstr(text, "    soundSpeed  20;\n    model       becker;\n}\n"));
    assert_non_null(strstr(text, "}\nminIterations   3;\n\n// ****** //\n"));
    free(text);
    /* the parent dictionary must exist */
    assert_int_not_equal(
        tool("editDictionary", "-entry solver/model -set x " OUT "/dict/props", bin_dir()), 0);
    assert_non_null(strstr(output, "solver"));
}

static void test_edit_missing_entry_and_bad_file(void **state)
{
    (void)state;
    write_dict();
    assert_int_not_equal(
        tool("editDictionary", "-entry viscosity/alpah -value " OUT "/dict/props", bin_dir()), 0);
    assert_non_null(strstr(output, "viscosity/alpah"));
    assert_non_null(strstr(output, "did you mean 'alpha'"));
    assert_int_not_equal(
        tool("editDictionary", "-entry nothing -remove " OUT "/dict/props", bin_dir()), 0);
    assert_non_null(strstr(output, "nothing"));
    spit(OUT "/dict/bad", "a 1;\nb (1 2;\n");
    assert_int_not_equal(tool("editDictionary", OUT "/dict/bad", bin_dir()), 0);
    assert_non_null(strstr(output, OUT "/dict/bad:2:"));
    /* two values, or a value that breaks the file, are refused and change nothing */
    assert_int_not_equal(
        tool("editDictionary", "-entry eta -set '1; b 2' " OUT "/dict/props", bin_dir()), 0);
    assert_int_not_equal(
        tool("editDictionary", "-entry eta -set '(1 2' " OUT "/dict/props", bin_dir()), 0);
    char *text = slurp(OUT "/dict/props");
    assert_string_equal(text, dict_text);
    free(text);
}

static void test_edit_remove_and_keywords(void **state)
{
    (void)state;
    write_dict();
    assert_int_equal(tool("editDictionary", "-entry eta -remove " OUT "/dict/props", bin_dir()), 0);
    const char *eta_line = "eta             1;              // percent\n";
    char *text = slurp(OUT "/dict/props"), *want = replaced(dict_text, eta_line, "");
    assert_string_equal(text, want);
    free(text);
    free(want);
    assert_int_equal(tool("editDictionary", "-keywords " OUT "/dict/props", bin_dir()), 0);
    assert_string_equal(output, "FoamFile\nrhoWater\nrho0\ngravity\nviscosity\n");
    assert_int_equal(
        tool("editDictionary", "-keywords -entry viscosity " OUT "/dict/props", bin_dir()), 0);
    assert_string_equal(output, "alpha\nsoundSpeed\n");
    assert_int_equal(tool("editDictionary", "-expand " OUT "/dict/props", bin_dir()), 0);
    assert_non_null(strstr(output, "rho0            1000;\n"));
}

/* ---- cloneCase, listTimes, cleanCase ------------------------------------------------ */

/* A case with results: time directories 0 0.1 0.2 0.3, collections, a log,
 * postProcessing/ and a leftover 0.4.tmp.1. */
static void fake_case(const char *dir)
{
    fresh(dir);
    assert_int_equal(run("cp -r tests/cases/hydrostaticTank/system tests/cases/hydrostaticTank/"
                         "constant %s/ && printf '#!/bin/sh\\n' > %s/Allrun && cd %s && "
                         "for t in 0 0.1 0.2 0.3; do mkdir $t && touch $t/fluid.vtu "
                         "$t/boundary.vtu; done && mkdir 0.4.tmp.1 postProcessing && "
                         "touch log.pcisph fluid.vtu.series",
                         dir, dir, dir),
                     0);
    spit(OUT "/pvd_template",
         "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\"><Collection>\n"
         "<DataSet timestep=\"0\" file=\"0/fluid.vtu\"/>\n</Collection></VTKFile>\n");
    assert_int_equal(run("cp " OUT "/pvd_template %s/fluid.pvd", dir), 0);
}

static void test_clone_copies_input_not_results(void **state)
{
    (void)state;
    fake_case(OUT "/src");
    run("rm -rf " OUT "/dst");
    assert_int_equal(tool("cloneCase", OUT "/src " OUT "/dst", bin_dir()), 0);
    assert_true(exists(OUT "/dst/system/controlDict"));
    assert_true(exists(OUT "/dst/constant/fluidProperties"));
    assert_true(exists(OUT "/dst/Allrun"));
    const char *results[] = {"0",          "0.1",       "0.4.tmp.1",       "postProcessing",
                             "log.pcisph", "fluid.pvd", "fluid.vtu.series"};
    for (size_t i = 0; i < sizeof results / sizeof *results; i++) {
        char p[256];
        snprintf(p, sizeof p, OUT "/dst/%s", results[i]);
        if (exists(p)) fail_msg("cloneCase copied the result %s", p);
    }
    assert_int_not_equal(tool("cloneCase", OUT "/src " OUT "/dst", bin_dir()), 0);
    assert_non_null(strstr(output, "-force"));
    assert_int_equal(tool("cloneCase", "-force " OUT "/src " OUT "/dst", bin_dir()), 0);
}

static void test_list_times_and_remove(void **state)
{
    (void)state;
    fake_case(OUT "/times");
    assert_int_equal(tool("listTimes", "-case " OUT "/times", bin_dir()), 0);
    assert_string_equal(output, "0.1\n0.2\n0.3\n");
    assert_int_equal(tool("listTimes", "-withZero " OUT "/times", bin_dir()), 0);
    assert_string_equal(output, "0\n0.1\n0.2\n0.3\n");
    assert_int_equal(tool("listTimes", "-latestTime " OUT "/times", bin_dir()), 0);
    assert_string_equal(output, "0.3\n");
    assert_int_equal(tool("listTimes", "-rm -time 0.1:0.2 " OUT "/times 2>/dev/null", bin_dir()),
                     0);
    assert_string_equal(output, "0.1\n0.2\n");
    assert_false(exists(OUT "/times/0.1") || exists(OUT "/times/0.2"));
    assert_true(exists(OUT "/times/0") && exists(OUT "/times/0.3"));
    /* the collections list exactly the times left */
    char *pvd = slurp(OUT "/times/fluid.pvd"), *series = slurp(OUT "/times/fluid.vtu.series");
    assert_non_null(strstr(pvd, "\"0/fluid.vtu\""));
    assert_non_null(strstr(pvd, "\"0.3/fluid.vtu\""));
    assert_null(strstr(pvd, "0.1/"));
    assert_null(strstr(series, "0.2/"));
    assert_non_null(strstr(series, "0.3/fluid.vtu"));
    free(pvd);
    free(series);
    assert_int_equal(tool("listTimes", "-rm " OUT "/times 2>/dev/null", bin_dir()), 0);
    assert_true(exists(OUT "/times/0") && !exists(OUT "/times/0.3"));
}

static void test_clean_case(void **state)
{
    (void)state;
    fake_case(OUT "/clean");
    assert_int_equal(tool("cleanCase", OUT "/clean", bin_dir()), 0);
    assert_int_equal(run("ls " OUT "/clean | tr '\\n' ' '"), 0);
    assert_string_equal(output, "Allrun constant system ");
    /* a 0 with initial conditions keeps them */
    fake_case(OUT "/clean");
    spit(OUT "/clean/0/U", "initial velocity\n");
    assert_int_equal(tool("cleanCase", "-case " OUT "/clean", bin_dir()), 0);
    assert_int_equal(run("ls " OUT "/clean/0 | tr '\\n' ' '"), 0);
    assert_string_equal(output, "U ");
    assert_int_not_equal(tool("cleanCase", OUT, bin_dir()), 0); /* not a case */
}

/* ---- sweepCase ---------------------------------------------------------------------- */

/* A tiny hydrostatic tank (288 particles, 0.1 s) and a sweep over eta. */
static void write_sweep(const char *dir, const char *results)
{
    char path[256];
    fresh(dir);
    assert_int_equal(run("cp -r tests/cases/hydrostaticTank %s/base && cd %s/base && "
                         "sed -i 's/^endTime .*/endTime 0.1;/; s/^writeInterval .*/writeInterval "
                         "0.05;/' system/controlDict && "
                         "sed -i 's/^particleSpacing .*/particleSpacing 0.05;/' "
                         "constant/fluidProperties",
                         dir, dir),
                     0);
    snprintf(path, sizeof path, "%s/sweepDict", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f,
            "baseCase base;\nparameters\n{\n"
            "    \"constant/fluidProperties/eta\" (0.1 1);\n}\n%s",
            results);
    fclose(f);
}

static void test_sweep_print_jobs(void **state)
{
    (void)state;
    write_sweep(OUT "/sweepJobs", "");
    assert_int_equal(
        tool("sweepCase", "-printJobs " OUT "/sweepJobs/sweepDict 2>/dev/null", bin_dir()), 0);
    char *line2 = strchr(output, '\n');
    assert_non_null(line2);
    assert_non_null(strstr(output, "/pcisph -case "));
    assert_true(strstr(output, "/cases/eta_0.1 > ") && strstr(output, "/cases/eta_1 > "));
    assert_non_null(strstr(output, "/cases/eta_1/log.pcisph 2>&1\n"));
    assert_string_equal(strchr(line2 + 1, '\n'), "\n"); /* two lines */
    assert_int_equal(tool("editDictionary",
                          "-entry eta -value " OUT
                          "/sweepJobs/cases/eta_0.1/constant/fluidProperties",
                          bin_dir()),
                     0);
    assert_string_equal(output, "0.1\n");
}

/* Issue 13, item 14: a misspelt parameter stops the sweep before any case
 * is made or run, naming the nearest key; a known key the base case leaves
 * at its default is accepted (it is added to each case). */
static void test_sweep_misspelt_parameter(void **state)
{
    (void)state;
    static const struct {
        const char *param, *expect;
    } bad[] = {
        {"\"constant/fluidProperties/etaa\" (0.5 2);",
         "parameter 'constant/fluidProperties/etaa': 'etaa' is not a keyword of "
         "constant/fluidProperties; did you mean 'eta'? (nothing was run)"},
        {"\"constant/fluidProperties/viscosity/alpah\" (0.01 0.1);",
         "'alpah' is not a keyword of constant/fluidProperties/viscosity; did you mean 'alpha'?"},
        {"\"system/controlDict/writeIntervall\" (0.01 0.02);", "did you mean 'writeInterval'?"},
        {"\"system/timeStepDict/temperature\" (1 2);",
         "'temperature' is not a keyword of system/timeStepDict (nothing was run)"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        write_sweep(OUT "/sweepBad", "");
        FILE *f = fopen(OUT "/sweepBad/sweepDict", "w");
        assert_non_null(f);
        fprintf(f, "baseCase base;\nparameters\n{\n    %s\n}\n", bad[k].param);
        fclose(f);
        int rc = tool("sweepCase", OUT "/sweepBad/sweepDict", bin_dir());
        if (rc == 0 || !strstr(output, bad[k].expect) || !strstr(output, "sweepDict:4:"))
            fail_msg("%s: exit %d, wanted '%s'; got: %s", bad[k].param, rc, bad[k].expect, output);
        assert_int_equal(run("test ! -e " OUT "/sweepBad/cases"), 0);
        hostile_record("sweepDict", bad[k].param, output);
    }
    write_sweep(OUT "/sweepBad", "");
    FILE *f = fopen(OUT "/sweepBad/sweepDict", "w");
    assert_non_null(f);
    fprintf(f,
            "baseCase base;\nparameters\n{\n    \"system/controlDict/timePrecision\" (6 8);\n}\n");
    fclose(f);
    if (tool("sweepCase", "-print-jobs " OUT "/sweepBad/sweepDict", bin_dir()) != 0)
        fail_msg("a known key at its default was refused: %s", output);
}

static void test_sweep_collect_fake_results(void **state)
{
    (void)state;
    write_sweep(OUT "/sweepFake", "results (postProcessing/probe/0/probe.dat:p);\n");
    assert_int_equal(tool("sweepCase", "-print-jobs " OUT "/sweepFake/sweepDict", bin_dir()), 0);
    const char *names[] = {"eta_0.1", "eta_1"};
    for (int i = 0; i < 2; i++) {
        char dir[256], p[320];
        snprintf(dir, sizeof dir, OUT "/sweepFake/cases/%s", names[i]);
        assert_int_equal(
            run("mkdir -p %s/postProcessing/timeStep/0 %s/postProcessing/probe/0", dir, dir), 0);
        snprintf(p, sizeof p, "%s/log.pcisph", dir);
        spit(p, "Time = 0.1\nEnd: 3 steps\n");
        snprintf(p, sizeof p, "%s/postProcessing/timeStep/0/timeStep.dat", dir);
        /* steps = rows, wall = sum, mean iterations, max errors, sum of shocks,
         * mean rhoErrAvg, max volErrAvg */
        const char *head = "# Time\tdeltaT\titerations\trhoErrAvg\trhoErrMax\tvMax\tFMax\t"
                           "shock\twallTime\tvolErrAvg\n";
        const char *rows = i == 0 ? "0.1\t0.1\t4\t0.05\t0.5\t1\t1\t0\t1.5\t0.9\n"
                                    "0.2\t0.1\t6\t0.07\t0.4\t1\t1\t1\t2.5\t1.25\n"
                                    "0.3\t0.1\t8\t0.06\t0.6\t1\t1\t1\t3\t1.1\n"
                                  : "0.1\t0.1\t3\t0.5\t0.9\t1\t1\t0\t1\t2\n";
        char record[512];
        snprintf(record, sizeof record, "%s%s", head, rows);
        spit(p, record);
        snprintf(p, sizeof p, "%s/postProcessing/probe/0/probe.dat", dir);
        spit(p, i == 0 ? "# Time p\n0.1 10\n0.3 12.5\n" : "# Time p\n0.1 20\n");
    }
    assert_int_equal(tool("sweepCase", "-collect " OUT "/sweepFake/sweepDict", bin_dir()), 0);
    char *csv = slurp(OUT "/sweepFake/results.csv");
    assert_string_equal(csv,
                        "case,eta,status,wallTime,steps,meanIterations,maxRhoErrAvg,"
                        "maxRhoErrMax,shocks,meanRhoErrAvg,maxVolErrAvg,p\n"
                        "eta_0.1,0.1,finished,7,3,6,0.07,0.6,2,0.06,1.25,12.5\n"
                        "eta_1,1,finished,1,1,3,0.5,0.9,0,0.5,2,20\n");
    free(csv);
    char *md = slurp(OUT "/sweepFake/results.md");
    assert_non_null(strstr(
        md, "| eta_0.1 | 0.1 | finished | 7 | 3 | 6 | 0.07 | 0.6 | 2 | 0.06 | 1.25 | 12.5 |"));
    free(md);
}

/* Reads column `col` (0-based) of row `row` (1-based) of a CSV without quotes. */
static double csv_number(const char *csv, int row, int col)
{
    const char *p = csv;
    for (int r = 0; r < row; r++) p = strchr(p, '\n') + 1;
    for (int c = 0; c < col; c++) p = strchr(p, ',') + 1;
    return strtod(p, NULL);
}

static void test_sweep_runs_the_solver(void **state)
{
    (void)state;
    write_sweep(OUT "/sweepRun", "");
    assert_int_equal(tool("sweepCase", "-jobs 2 " OUT "/sweepRun/sweepDict", bin_dir()), 0);
    assert_non_null(strstr(output, "eta_0.1: finished"));
    assert_non_null(strstr(output, "eta_1: finished"));
    /* item 17: progress, n of N and the time left */
    assert_non_null(strstr(output, "1 of 2 done, about "));
    assert_non_null(strstr(output, "2 of 2 done, all in "));
    char *csv = slurp(OUT "/sweepRun/results.csv");
    assert_non_null(strstr(csv, "eta_0.1,0.1,finished,"));
    assert_non_null(strstr(csv, "eta_1,1,finished,"));
    double err_small = csv_number(csv, 1, 7), err_large = csv_number(csv, 2, 7); /* maxRhoErrMax */
    assert_true(err_small > 0 && err_small < err_large);
    free(csv);
    /* finished points are not run again */
    assert_int_equal(tool("sweepCase", OUT "/sweepRun/sweepDict", bin_dir()), 0);
    assert_non_null(strstr(output, "0 to run (2 finished already)"));

    if (run("command -v gnuplot") != 0) {
        skip();
        return;
    }
    assert_int_equal(tool("plotSweep",
                          "-o " OUT "/sweepRun/plot.png " OUT
                          "/sweepRun/results.csv wallTime maxRhoErrAvg",
                          bin_dir()),
                     0);
    assert_int_equal(tool("monitorCase",
                          "-case " OUT "/sweepRun/cases/eta_1 -once -png " OUT
                          "/sweepRun/monitor.png",
                          bin_dir()),
                     0);
    const char *pngs[] = {OUT "/sweepRun/plot.png", OUT "/sweepRun/monitor.png"};
    for (int i = 0; i < 2; i++) {
        char *png = slurp(pngs[i]);
        assert_memory_equal(png, "\x89PNG", 4);
        free(png);
    }
    assert_int_equal(tool("monitorCase", "-case " OUT "/sweepRun/cases/eta_1 -once", bin_dir()), 0);
    assert_non_null(strstr(output, "rhoErrMax"));
}

/* ---- plotSweep -pareto and -where ------------------------------------------------- */

/* A results table with a known Pareto front for (wallTime, err), less being
 * better: a, b, c (b's exact tie) and e.  d loses to b (same err, slower), h
 * to a (same time, larger err), g to all of them; f, i, j and k have no
 * finite pair (nan, '-', inf, empty) and f would beat everything if it
 * counted.  The quoted note checks that rows are copied as they are. */
#define PARETO OUT "/pareto"
static const char *pareto_header = "case,mode,wallTime,err,note\n";
static const char *pareto_rows[] = {
    ['a'] = "a,adaptive,1,5,\"fast, rough\"\n",
    ['b'] = "b,adaptive,2,3,\n",
    ['c'] = "c,constant,2,3,tie with b\n",
    ['d'] = "d,adaptive,3,3,beaten by b\n",
    ['e'] = "e,constant,4,1,\n",
    ['f'] = "f,adaptive,nan,0.5,\n",
    ['g'] = "g,constant,5,4,\n",
    ['h'] = "h,adaptive,1,6,beaten by a\n",
    ['i'] = "i,constant,-,2,\n",
    ['j'] = "j,adaptive,6,inf,\n",
    ['k'] = "k,adaptive,4,,\n",
};

/* The header and the rows named by `names` (e.g. "abce"), in that order. */
static char *pareto_table(const char *names)
{
    char *s = malloc(4096);
    strcpy(s, pareto_header);
    for (const char *n = names; *n; n++) strcat(s, pareto_rows[(int)*n]);
    return s;
}

/* A fresh PARETO/ holding only results.csv (rows in the order f..k, a..e,
 * so that the front is not simply the first rows). */
static int write_pareto_table(void)
{
    if (run("command -v gnuplot") != 0) return 0;
    fresh(PARETO);
    char *table = pareto_table("fghijkabcde");
    spit(PARETO "/results.csv", table);
    free(table);
    return 1;
}

static void assert_file_is_table(const char *path, const char *names)
{
    char *text = slurp(path), *want = pareto_table(names);
    assert_string_equal(text, want);
    free(text);
    free(want);
}

static void test_plot_sweep_pareto(void **state)
{
    (void)state;
    if (!write_pareto_table()) {
        skip();
        return;
    }
    assert_int_equal(
        tool("plotSweep",
             "-pareto -output " PARETO "/front.png " PARETO "/results.csv wallTime err", bin_dir()),
        0);
    assert_file_is_table(PARETO "/front_pareto.csv", "abce");
    assert_non_null(strstr(output,
                           "Pareto front (4 of 7 rows):\n  case wallTime err\n"
                           "  a 1 5\n  b 2 3\n  c 2 3\n  e 4 1\n"));
    assert_non_null(strstr(output, "Note: 4 of 11 rows of " PARETO "/results.csv left out"));
    char *png = slurp(PARETO "/front.png");
    assert_memory_equal(png, "\x89PNG", 4);
    free(png);
    /* the front is in the legend; without -pareto no front is written */
    assert_int_equal(
        tool("plotSweep", "-pareto -dumb " PARETO "/results.csv wallTime err", bin_dir()), 0);
    assert_non_null(strstr(output, "Pareto front $"));
    assert_int_equal(run("rm " PARETO "/err_vs_wallTime_pareto.csv"), 0);
    assert_int_equal(tool("plotSweep", PARETO "/results.csv wallTime err", bin_dir()), 0);
    assert_true(exists(PARETO "/err_vs_wallTime.png"));
    assert_false(exists(PARETO "/err_vs_wallTime_pareto.csv"));
    assert_null(strstr(output, "Pareto"));
}

static void test_plot_sweep_where(void **state)
{
    (void)state;
    if (!write_pareto_table()) {
        skip();
        return;
    }
    assert_int_equal(tool("plotSweep",
                          "-pareto -where mode=constant -o " PARETO "/constant.png " PARETO
                          "/results.csv wallTime err",
                          bin_dir()),
                     0);
    assert_file_is_table(PARETO "/constant_pareto.csv", "ce"); /* g beaten, i left out */
    assert_non_null(strstr(output, "Note: 1 of 4 rows"));
    /* two conditions, both must hold; the default name tells the subset */
    assert_int_equal(tool("plotSweep",
                          "-pareto -where mode=adaptive -where wallTime=1 " PARETO
                          "/results.csv wallTime err",
                          bin_dir()),
                     0);
    assert_file_is_table(PARETO "/err_vs_wallTime_mode_adaptive_wallTime_1_pareto.csv", "a");
    assert_true(exists(PARETO "/err_vs_wallTime_mode_adaptive_wallTime_1.png"));
    assert_non_null(strstr(output, "(1 of 2 rows)")); /* a and h */
}

/* Each error names the file and the column or argument, exits non-zero and
 * leaves no file behind, even when gnuplot fails after the front is written. */
static void test_plot_sweep_where_errors(void **state)
{
    (void)state;
    if (!write_pareto_table()) {
        skip();
        return;
    }
    assert_int_not_equal(tool("plotSweep",
                              "-pareto -where mdoe=adaptive " PARETO "/results.csv wallTime err",
                              bin_dir()),
                         0);
    assert_non_null(strstr(output, PARETO "/results.csv: no column 'mdoe' (-where mdoe=adaptive)"));
    assert_int_not_equal(
        tool("plotSweep", "-pareto -where mode " PARETO "/results.csv wallTime err", bin_dir()), 0);
    assert_non_null(strstr(output, "bad -where 'mode'"));
    assert_int_not_equal(tool("plotSweep",
                              "-pareto -where mode=adaptve " PARETO "/results.csv wallTime err",
                              bin_dir()),
                         0);
    assert_non_null(strstr(output, PARETO "/results.csv: no row has -where mode=adaptve"));
    assert_non_null(strstr(output,
                           "Values of 'mode' in " PARETO "/results.csv: 'adaptive' "
                           "'constant'\n"));
    assert_int_not_equal(
        tool("plotSweep", "-pareto -where case=f " PARETO "/results.csv wallTime err", bin_dir()),
        0);
    assert_non_null(strstr(output, "no row left by -where has finite numbers"));
    /* gnuplot fails (no positive x on a log axis) after the front was written */
    spit(PARETO "/negative.csv", "case,x,y\na,-1,2\nb,-2,1\n");
    assert_int_not_equal(tool("plotSweep", "-pareto -logX " PARETO "/negative.csv x y", bin_dir()),
                         0);
    assert_non_null(strstr(output, "gnuplot failed"));
    assert_int_equal(run("ls -a " PARETO " | tr '\\n' ' '"), 0);
    assert_string_equal(output, ". .. negative.csv results.csv ");
}


/* Item 21: make demo says what it runs, where its log is, shows progress
 * with the time left, and where to look at the result (shortened here to
 * 0.004 s of simulated time, progress lines every 0.1 s). */
static void test_demo_says_what_and_where(void **state)
{
    (void)state;
    assert_int_equal(run("SLUICE_DEMO_DIR=$PWD/" OUT
                         "/demo SLUICE_DEMO_END=0.004 SLUICE_PROGRESS=plain "
                         "SLUICE_PROGRESS_PERIOD=0.1 OMP_NUM_THREADS=1 etc/runDemo"),
                     0);
    assert_non_null(strstr(output, "damBreak tutorial"));
    assert_non_null(strstr(
        output, "24k fluid particles, 0.004 s of simulated time, adaptive time step, all cores"));
    assert_non_null(strstr(output, "Per-step log: "));
    assert_non_null(strstr(output, OUT "/demo/log.pcisph"));
    const char *p = strstr(output, "Progress: t = ");
    if (!p) fail_msg("no progress line in:\n%s", output);
    assert_non_null(strstr(p, "ETA"));
    assert_non_null(strstr(output, OUT "/demo/fluid.pvd"));
}


/* core/sl_progress: durations as people read them, the time left from the
 * rate, a rate smoothed over wall time, and no line before one is due. */
static void test_progress_module(void **state)
{
    (void)state;
    char buf[64];
    sl_progress_duration(45.2, buf, sizeof buf);
    assert_string_equal(buf, "45 s");
    sl_progress_duration(185, buf, sizeof buf);
    assert_string_equal(buf, "3 min 05 s");
    sl_progress_duration(7620, buf, sizeof buf);
    assert_string_equal(buf, "2 h 07 min");
    sl_progress_duration(-1, buf, sizeof buf);
    assert_string_equal(buf, "?");
    FILE *f = tmpfile();
    assert_non_null(f);
    setenv("SLUICE_PROGRESS", "plain", 1);
    setenv("SLUICE_PROGRESS_PERIOD", "1000", 1);
    sl_progress p;
    sl_progress_start(&p, f, 0.5, 1.5, 10);
    assert_true(sl_progress_eta(&p, 0.5) < 0); /* not known yet */
    p.rate = 0.25;                             /* 0.25 per second */
    assert_true(fabs(sl_progress_eta(&p, 1.0) - 2.0) < 1e-12);
    sl_progress_text(&p, 1.0, "t = 1", buf, sizeof buf);
    assert_non_null(strstr(buf, "t = 1   50.0 %"));
    assert_non_null(strstr(buf, "ETA 2 s"));
    sl_progress_update(&p, 1.0, "t = 1"); /* plain lines every 1000 s: none yet */
    assert_int_equal(ftell(f), 0);
    fclose(f);
    unsetenv("SLUICE_PROGRESS");
    unsetenv("SLUICE_PROGRESS_PERIOD");
}

/* ---- monitoring after a restart, units on axes ------------------------------------ */

/* A case whose record has two sessions: the first run to 0.5 s, then a
 * restart from 0.3 s (the first run's rows after 0.3 are replaced). */
static void write_two_sessions(const char *dir)
{
    fresh(dir);
    assert_int_equal(run("mkdir -p %s/system %s/postProcessing/timeStep/0 "
                         "%s/postProcessing/timeStep/0.3 && echo 'endTime 1;' > "
                         "%s/system/controlDict",
                         dir, dir, dir, dir),
                     0);
    const char *head = "# Time\tdeltaT\titerations\trhoErrAvg\trhoErrMax\tvMax\tFMax\tshock\t"
                       "wallTime\tcontrollerDeltaT\tvolErrAvg\tvolErrMax\n";
    char text[2048], path[512];
    snprintf(text, sizeof text,
             "%s0.1\t0.1\t3\t0.1\t1\t1\t1\t0\t1\t0.1\t0.1\t1\n"
             "0.2\t0.1\t3\t0.2\t1\t1\t1\t0\t1\t0.1\t0.2\t1\n0.3\t0.1\t3\t0.3\t1\t1\t1\t0\t1\t0."
             "1\t0.3\t1\n"
             "0.4\t0.1\t3\t9\t1\t1\t1\t0\t1\t0.1\t9\t1\n0.5\t0.1\t3\t9\t1\t1\t1\t0\t1\t0.1\t9\t1\n",
             head);
    snprintf(path, sizeof path, "%s/postProcessing/timeStep/0/timeStep.dat", dir);
    spit(path, text);
    snprintf(text, sizeof text,
             "%s0.4\t0.1\t3\t0.4\t1\t1\t1\t0\t1\t0.1\t0.4\t1\n"
             "0.5\t0.1\t3\t0.5\t1\t1\t1\t0\t1\t0.1\t0.5\t1\n0.6\t0.1\t3\t0.6\t1\t1\t1\t0\t1\t0."
             "1\t0.6\t1\n",
             head);
    snprintf(path, sizeof path, "%s/postProcessing/timeStep/0.3/timeStep.dat", dir);
    spit(path, text);
}

/* A point stopped by a signal (the solver's "Stopped by a signal" line
 * before its "End:" line, its state written) is "stopped", not
 * "finished": the next sweepCase resumes it with -resume from its last
 * time instead of skipping it (or cloning it again, which would delete
 * what it wrote), and keeps the stopped session's log as log.pcisph.1.
 * The stop is made as the solver leaves it: eta_1's run cut back to its
 * 0.05 s time directory, the line put before its End line.  A run that
 * died part-way (its log without End:) is run again from a fresh clone,
 * its folder kept as <case>.failed.1, not deleted. */
static void test_sweep_resumes_a_stopped_point(void **state)
{
    (void)state;
    write_sweep(OUT "/sweepStop", "");
    assert_int_equal(tool("sweepCase", "-jobs 1 " OUT "/sweepStop/sweepDict", bin_dir()), 0);
    assert_int_equal(run("cd " OUT "/sweepStop/cases/eta_1 && rm -r 0.1 && sed -i 's/^End:/"
                         "Stopped by a signal at t = 0.05 (written to 0.05)\\n&/' log.pcisph && "
                         "grep -q '^Stopped by a signal' log.pcisph"),
                     0);
    assert_int_equal(tool("sweepCase", "-collect " OUT "/sweepStop/sweepDict", bin_dir()), 0);
    char *csv = slurp(OUT "/sweepStop/results.csv");
    assert_non_null(strstr(csv, "eta_1,1,stopped,"));
    assert_non_null(strstr(csv, "eta_0.1,0.1,finished,"));
    free(csv);
    assert_int_equal(tool("sweepCase", "-jobs 1 " OUT "/sweepStop/sweepDict", bin_dir()), 0);
    assert_non_null(
        strstr(output, "1 to run (1 finished already; 1 stopped by a signal, resumed)"));
    assert_non_null(strstr(output, "eta_1: finished"));
    assert_int_equal(run("cd " OUT "/sweepStop/cases/eta_1 && test -d 0.1 && grep -q '^Restarting "
                         "from .*0.05' log.pcisph && grep -q '^Stopped by a signal' log.pcisph.1"),
                     0);
    assert_int_equal(tool("sweepCase", "-collect " OUT "/sweepStop/sweepDict", bin_dir()), 0);
    csv = slurp(OUT "/sweepStop/results.csv");
    assert_non_null(strstr(csv, "eta_1,1,finished,"));
    free(csv);
    /* a run that died part-way (no End line) is run again, its folder kept */
    assert_int_equal(run("sed -i '/^End:/d' " OUT "/sweepStop/cases/eta_0.1/log.pcisph"), 0);
    assert_int_equal(tool("sweepCase", "-jobs 1 " OUT "/sweepStop/sweepDict", bin_dir()), 0);
    assert_non_null(strstr(output, "eta_0.1: the failed run kept as "));
    assert_int_equal(run("test -d " OUT
                         "/sweepStop/cases/eta_0.1.failed.1/0.1 && grep -q '^End:' " OUT
                         "/sweepStop/cases/eta_0.1/log.pcisph"),
                     0);
}

/* Item 18: monitorCase, plotTimeStep and sweepCase read every session of
 * the record in time order, not only postProcessing/timeStep/0. */
static void test_monitor_after_restart(void **state)
{
    (void)state;
    write_two_sessions(OUT "/twoSessions");
    assert_int_equal(tool("monitorCase", "-case " OUT "/twoSessions -print", bin_dir()), 0);
    /* times 0.1..0.6 once each, rhoErrAvg from the session that ran them */
    const char *at = output;
    for (int k = 1; k <= 6; k++) {
        char row[64];
        snprintf(row, sizeof row, "\n0.%d\t", k);
        at = strstr(at, row);
        if (!at) fail_msg("no row for t = 0.%d in order:\n%s", k, output);
        const char *tab = at ? strchr(at + 1, '\t') : NULL;
        assert_non_null(tab);
        assert_true(strtod(tab + 1, NULL) == 0.1); /* deltaT column */
    }
    assert_null(strstr(output, "\t9\t")); /* the replaced rows */
    if (run("command -v gnuplot") != 0) {
        skip();
        return;
    }
    assert_int_equal(run("SLUICE_BIN=%s etc/plotTimeStep " OUT "/twoSessions", bin_dir()), 0);
    char *png = slurp(OUT "/twoSessions/postProcessing/timeStep/timeStep.png");
    assert_memory_equal(png, "\x89PNG", 4);
    free(png);
    /* the terminal plot names both folders and the case, not "." */
    assert_int_equal(run("cd " OUT "/twoSessions && %s/monitorCase -once", bin_dir()), 0);
    assert_non_null(strstr(output, "twoSessions: postProcessing/timeStep/{0,0.3}/timeStep.dat"));
}

/* Item 20: axes carry units, and x tick labels are distinct (not every one
 * "0.0" in the terminal). */
static void test_plot_units(void **state)
{
    (void)state;
    if (run("command -v gnuplot") != 0) {
        skip();
        return;
    }
    write_two_sessions(OUT "/units");
    assert_int_equal(tool("monitorCase", "-case " OUT "/units -once", bin_dir()), 0);
    assert_non_null(strstr(output, "Time [s]"));
    assert_non_null(strstr(output, "deltaT [s]"));
    assert_non_null(strstr(output, "rhoErrAvg [%]"));
    assert_non_null(strstr(output, "vMax [m/s]"));
    assert_non_null(strstr(output, " 0.2 ") ? strstr(output, " 0.4 ") : NULL);
    fresh(OUT "/unitsSweep");
    spit(OUT "/unitsSweep/results.csv",
         "case,eta,wallTime,maxRhoErrAvg\na,0.5,10,0.2\nb,1,5,0.4\n");
    assert_int_equal(
        tool("plotSweep", "-dumb " OUT "/unitsSweep/results.csv wallTime maxRhoErrAvg", bin_dir()),
        0);
    assert_non_null(strstr(output, "wallTime [s]"));
    assert_non_null(strstr(output, "maxRhoErrAvg [%]"));
}

/* ---- tests/run_tests and the table of refused inputs --------------------------- */

/* A fake test program: prints what cmocka prints for `pass` passed, `skip`
 * skipped and `fail` failed tests, and records one refused input. */
static void fake_program(const char *path, int pass, int skip, int fail)
{
    char text[2048];
    snprintf(text, sizeof text,
             "#!/bin/sh\n"
             "printf 'fake input\\t%s input\\tError: tests/output/x_%s/system/controlDict:3: bad | "
             "pipe\\n' "
             ">> \"$SLUICE_HOSTILE_TSV\"\n"
             "echo '[==========] Running %d test(s).'\n"
             "echo '[  PASSED  ] %d test(s).'\n"
             "%s%s"
             "exit %d\n",
             path + strlen(path) - 1, path + strlen(path) - 1, pass + skip + fail, pass,
             skip ? "echo '[  SKIPPED ] 1 test(s), listed below:'\n" : "",
             fail ? "echo '[  FAILED  ] 1 test(s), listed below:'\n" : "", fail ? 1 : 0);
    spit(path, text);
    assert_int_equal(chmod(path, 0755), 0);
}

/* run_tests names each program before its output, counts skipped tests
 * apart from passed ones ("N passed, N failed, N skipped"), and after a
 * passing full run turns the recorded rows into the Markdown table. */
static void test_run_tests_names_and_skips(void **state)
{
    (void)state;
    fresh(OUT "/runtests/build/tests");
    fake_program(OUT "/runtests/build/tests/test_a", 2, 1, 0);
    fake_program(OUT "/runtests/build/tests/test_b", 3, 0, 0);
    int rc = run("SLUICE_HOSTILE_TSV=$PWD/" OUT "/runtests/rows.tsv SLUICE_HOSTILE_DOC=$PWD/" OUT
                 "/runtests/table.md tests/run_tests " OUT "/runtests/build %s",
                 bin_dir());
    assert_int_equal(rc, 0);
    const char *a = strstr(output, "==> test_a (1 of 2"), *b = strstr(output, "==> test_b (2 of 2");
    assert_non_null(a);
    assert_non_null(b);
    assert_true(a < strstr(output, "Running 3 test(s)") && b > a);
    assert_non_null(strstr(output, "<== test_a: 2 passed, 0 failed, 1 skipped"));
    assert_non_null(strstr(output, "5 passed, 0 failed, 1 skipped\n"));
    char *md = slurp(OUT "/runtests/table.md");
    assert_non_null(strstr(
        md, "| fake input | `a input` | `Error: <case>/system/controlDict:3: bad \\| pipe` |"));
    assert_non_null(strstr(md, "| fake input | `b input` |"));
    assert_non_null(strstr(md, "2 inputs in 1 classes"));
    free(md);
    /* a failure: counted, non-zero exit, and the table is left alone */
    fake_program(OUT "/runtests/build/tests/test_b", 3, 0, 1);
    assert_int_equal(run("rm %s/runtests/table.md && SLUICE_HOSTILE_TSV=$PWD/" OUT
                         "/runtests/rows.tsv SLUICE_HOSTILE_DOC=$PWD/" OUT "/runtests/table.md "
                         "tests/run_tests " OUT "/runtests/build %s",
                         OUT, bin_dir()),
                     1);
    assert_non_null(strstr(output, "5 passed, 1 failed, 1 skipped\n"));
    assert_false(exists(OUT "/runtests/table.md"));
}


/* ---- the application frame (libsrc/app) ------------------------------------------- */

/* Every program of bin/ (each applications/ folder builds one): the
 * frame's -help, -completionWords and errors.  A program that does not
 * answer -completionWords is not on the frame yet. */
static char program_names[64][64];
static int nprograms;

static void list_programs(void)
{
    if (nprograms) return;
    assert_int_equal(run("ls %s", bin_dir()), 0);
    for (char *w = strtok(output, "\n"); w && nprograms < 64; w = strtok(NULL, "\n"))
        snprintf(program_names[nprograms++], sizeof program_names[0], "%s", w);
    assert_true(nprograms >= 15);
}

/* The options of a program's table, as -completionWords lists them
 * ("-name kind [glob]" lines): the names, NUL-separated, into buf. */
static size_t table_options(const char *prog, char *buf, size_t len, char kinds[][16])
{
    if (run("%s/%s -completionWords", bin_dir(), prog) != 0)
        fail_msg("%s does not answer -completionWords: it is not on the application frame "
                 "(libsrc/app, see doc/architecture.md)",
                 prog);
    size_t n = 0, used = 0;
    for (char *line = strtok(output, "\n"); line; line = strtok(NULL, "\n")) {
        char name[64], kind[16];
        if (line[0] != '-') continue;
        assert_int_equal(sscanf(line, "%63s %15s", name, kind), 2);
        assert_true(used + strlen(name) + 1 < len);
        strcpy(buf + used, name);
        strcpy(kinds[n++], kind);
        used += strlen(name) + 1;
    }
    return n;
}

/* The generated -help lists every declared option, and no other, and exits 0. */
static void test_app_help_lists_every_option(void **state)
{
    (void)state;
    list_programs();
    for (int p = 0; p < nprograms; p++) {
        char names[4096], kinds[64][16];
        size_t n = table_options(program_names[p], names, sizeof names, kinds);
        assert_true(n >= 1); /* at least -help */
        assert_int_equal(run("%s/%s -help", bin_dir(), program_names[p]), 0);
        char want[128];
        snprintf(want, sizeof want, "Usage: %.60s [options]", program_names[p]);
        if (strncmp(output, want, strlen(want)))
            fail_msg("%s -help: %.200s", program_names[p], output);
        const char *opts = strstr(output, "\nOptions:\n"), *end;
        assert_non_null(opts);
        end = strstr(opts + 1, "\n\n");
        if (!end) end = opts + strlen(opts);
        const char *name = names;
        for (size_t k = 0; k < n; k++, name += strlen(name) + 1) {
            char line[128];
            snprintf(line, sizeof line, "\n  %.100s", name);
            const char *at = strstr(opts, line);
            if (!at || at > end || (at[strlen(line)] != ' ' && at[strlen(line)] != '\n'))
                fail_msg("%s -help does not list %s:\n%s", program_names[p], name, output);
        }
        size_t listed = 0; /* lines "  -x" of the Options section */
        for (const char *q = opts; (q = strstr(q + 1, "\n  -")) && q < end;) listed++;
        if (listed != n)
            fail_msg("%s -help lists %zu options, its table %zu", program_names[p], listed, n);
    }
}

/* A bad number is refused before anything is done, naming the option and
 * the value, with exit status 2 -- also out of range. */
static void test_app_bad_number_refused(void **state)
{
    (void)state;
    static const char *const bad[][3] = {
        {"benchPcisph", "-particles abc", "benchPcisph: -particles: 'abc' is not an integer"},
        {"benchPcisph", "-steps 1e3", "benchPcisph: -steps: '1e3' is not an integer"},
        {"benchPcisph", "-particles 10", "benchPcisph: -particles: '10' must be from 1000 to"},
        {"sweepCase", "-jobs x2 d", "sweepCase: -jobs: 'x2' is not an integer"},
        {"sweepCase", "-jobs 0 d", "sweepCase: -jobs: '0' must be from 1 to 4096"},
        {"monitorCase", "-refresh soon", "monitorCase: -refresh: 'soon' is not a number"},
        {"monitorCase", "-refresh 0", "monitorCase: -refresh: '0' must be above 0"},
        {"stableTimeStep", "-dtMin 1e-3x", "stableTimeStep: -dtMin: '1e-3x' is not a number"},
        {"stableTimeStep", "-tolerance 5%x",
         "stableTimeStep: -tolerance: '5%x' is not a positive number"},
        {"compareExperiment", "-filter nan -data x",
         "compareExperiment: -filter: 'nan' is not a number"},
        {"listTimes", "-time 0.1,x " OUT "/badNumber", "-time '0.1,x': expected times and ranges"},
        {"pcisph", "-case", "pcisph: -case needs an argument <dir>"},
    };
    fake_case(OUT "/badNumber");
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char want[160];
        int rc = run("%s/%s %s", bin_dir(), bad[i][0], bad[i][1]);
        if (rc != 2 || !strstr(output, bad[i][2]))
            fail_msg("%s %s: status %d, output\n%s\n(wanted '%s')", bad[i][0], bad[i][1], rc,
                     output, bad[i][2]);
        char input[256];
        snprintf(input, sizeof input, "%s %s", bad[i][0], bad[i][1]);
        hostile_record("command line", input, output);
        snprintf(want, sizeof want, "Usage: %s [options]", bad[i][0]);
        assert_non_null(strstr(output, want));
    }
}

/* Old spellings still work, each with a one-line warning naming the new
 * one; the new spelling gives no warning. */
static void test_app_old_spelling_warns(void **state)
{
    (void)state;
    fake_case(OUT "/alias");
    assert_int_equal(tool("cleanCase", "-dry-run -case " OUT "/alias", bin_dir()), 0);
    assert_non_null(
        strstr(output, "Warning: cleanCase: -dry-run is an old spelling: use -dryRun\n"));
    assert_non_null(strstr(output, "would remove " OUT "/alias/0.1"));
    assert_true(exists(OUT "/alias/0.1")); /* a dry run still */
    assert_int_equal(tool("cleanCase", "-n " OUT "/alias", bin_dir()), 0);
    assert_non_null(strstr(output, "-n is an old spelling: use -dryRun"));
    assert_int_equal(tool("cleanCase", "-dryRun " OUT "/alias", bin_dir()), 0);
    assert_null(strstr(output, "Warning"));
    assert_true(exists(OUT "/alias/0.1"));
    /* the -help lists them */
    assert_int_equal(tool("cleanCase", "-help", bin_dir()), 0);
    assert_non_null(strstr(output, "-dry-run, -n: use -dryRun"));
}

/* An unknown option is refused with the nearest declared one. */
static void test_app_unknown_did_you_mean(void **state)
{
    (void)state;
    static const char *const bad[][3] = {
        {"listTimes", "-latesttime",
         "listTimes: unknown option '-latesttime'; did you mean -latestTime?"},
        {"pcisph", "-quite", "pcisph: unknown option '-quite'; did you mean -quiet?"},
        {"sweepCase", "-printjobs d",
         "sweepCase: unknown option '-printjobs'; did you mean -printJobs?"},
        {"postProcess", "-hlep", "postProcess: unknown option '-hlep'; did you mean -help?"},
        {"cloneCase", "-frobnicate a b", "cloneCase: unknown option '-frobnicate'\n"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        int rc = run("%s/%s %s", bin_dir(), bad[i][0], bad[i][1]);
        if (rc != 2 || !strstr(output, bad[i][2]))
            fail_msg("%s %s: status %d, output\n%s", bad[i][0], bad[i][1], rc, output);
        char input[256];
        snprintf(input, sizeof input, "%s %s", bad[i][0], bad[i][1]);
        hostile_record("command line", input, output);
    }
    /* twice, missing and extra arguments */
    assert_int_equal(tool("listTimes", "-case a -case b", bin_dir()), 2);
    assert_non_null(strstr(output, "listTimes: -case is given twice"));
    assert_int_equal(tool("cloneCase", "a", bin_dir()), 2);
    assert_non_null(strstr(output, "cloneCase: missing argument: <source case> <new case>"));
    assert_int_equal(tool("cloneCase", "a b c", bin_dir()), 2);
    assert_non_null(strstr(output, "cloneCase: unexpected argument 'c'"));
    assert_int_equal(tool("cleanCase", "-case a b", bin_dir()), 2);
    assert_non_null(strstr(output, "give the case as -case or as the argument, not both"));
    assert_int_equal(tool("postProcess", "-time 1 -latestTime", bin_dir()), 2);
    assert_non_null(strstr(output, "give -time or -latestTime, not both"));
}

/* The completion words are the table's options (each with a kind), and
 * etc/bash_completion completes from them: options after '-', folders
 * after -case, PNG files after -png. */
static void test_app_completion_words(void **state)
{
    (void)state;
    static const char *const kinds[] = {"none", "int", "double", "string", "path", "dir"};
    list_programs();
    for (int p = 0; p < nprograms; p++) {
        char names[4096], kind[64][16];
        size_t n = table_options(program_names[p], names, sizeof names, kind);
        int help = 0;
        const char *name = names;
        for (size_t k = 0; k < n; k++, name += strlen(name) + 1) {
            int known = 0;
            for (size_t j = 0; j < sizeof kinds / sizeof *kinds; j++)
                known |= !strcmp(kind[k], kinds[j]);
            if (!known) fail_msg("%s: %s has kind '%s'", program_names[p], name, kind[k]);
            help |= !strcmp(name, "-help");
        }
        assert_true(help);
    }
    assert_int_equal(tool("cleanCase", "-completionWords", bin_dir()), 0);
    assert_string_equal(output, "-case dir\n-dryRun none\n-help none\n@args dir\n");
    /* bash, through etc/bash_completion */
    fresh(OUT "/complete");
    spit(OUT "/complete/a.png", "");
    spit(OUT "/complete/b.txt", "");
    spit(OUT "/complete/try.sh",
         ". etc/bash_completion\n"
         "c() { COMP_WORDS=(\"$@\"); COMP_CWORD=$(($# - 1)); _sluice_complete; "
         "echo \"${COMPREPLY[*]}\"; }\n"
         "c cleanCase -d\nc listTimes -la\nc monitorCase -png " OUT "/complete/\n"
         "c sweepCase -print\ncomplete -p pcisph\n");
    assert_int_equal(run("PATH=%s:$PATH bash " OUT "/complete/try.sh", bin_dir()), 0);
    assert_string_equal(output,
                        "-dryRun\n-latestTime\n" OUT "/complete/a.png\n-printJobs\n"
                        "complete -F _sluice_complete pcisph\n");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_edit_set_then_value),
        cmocka_unit_test(test_edit_set_in_included_file),
        cmocka_unit_test(test_edit_add_entries),
        cmocka_unit_test(test_edit_missing_entry_and_bad_file),
        cmocka_unit_test(test_edit_remove_and_keywords),
        cmocka_unit_test(test_clone_copies_input_not_results),
        cmocka_unit_test(test_list_times_and_remove),
        cmocka_unit_test(test_clean_case),
        cmocka_unit_test(test_sweep_print_jobs),
        cmocka_unit_test(test_sweep_misspelt_parameter),
        cmocka_unit_test(test_sweep_collect_fake_results),
        cmocka_unit_test(test_sweep_runs_the_solver),
        cmocka_unit_test(test_sweep_resumes_a_stopped_point),
        cmocka_unit_test(test_plot_sweep_pareto),
        cmocka_unit_test(test_plot_sweep_where),
        cmocka_unit_test(test_plot_sweep_where_errors),
        cmocka_unit_test(test_run_tests_names_and_skips),
        cmocka_unit_test(test_monitor_after_restart),
        cmocka_unit_test(test_plot_units),
        cmocka_unit_test(test_demo_says_what_and_where),
        cmocka_unit_test(test_progress_module),
        cmocka_unit_test(test_app_help_lists_every_option),
        cmocka_unit_test(test_app_bad_number_refused),
        cmocka_unit_test(test_app_old_spelling_warns),
        cmocka_unit_test(test_app_unknown_did_you_mean),
        cmocka_unit_test(test_app_completion_words),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
