/*
 * sweepCase: a parameter study.  Reads a sweep dictionary (syntax in
 * sweep.h), clones the base case once per point into <sweep dir>/cases/
 * <name>, sets the point's values in place (as editDictionary -set does),
 * runs the solver on the unfinished cases N at a time and collects one
 * table of parameters against results (results.csv, results.md).
 *
 *   sweepCase [-jobs N] [-threads T] [-force] [-printJobs | -collect] <sweepDict>
 */
#include "sweep.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/app.h"
#include "core/sl_log.h"

typedef struct options {
    const char *dict;
    int jobs, threads, force, print_jobs, collect;
} options;

static const app_option table[] = {
    APP_JOBS("run N cases at a time"),
    APP_THREADS("OpenMP threads per case", "cores / jobs, unless OMP_NUM_THREADS is set"),
    {.name = "force", .help = "clone and run every point again, finished or not"},
    {.name = "printJobs",
     .help = "prepare the unfinished cases and print one shell command per\n"
             "case instead of running them (for GNU parallel or a cluster)",
     .aliases = "print-jobs"},
    {.name = "collect", .help = "only gather the results of the existing cases"},
    APP_END};

static const app_info info = {
    .name = "sweepCase",
    .what = "Runs one case per point of a parameter sweep and tabulates the results.\n"
            "The cases are <sweep dir>/cases/<name> (names from the values, e.g.\n"
            "eta_0.5-mode_adaptive); a case whose log.<application> holds the solver's\n"
            "'End:' line is finished and is not run again; one stopped by a signal or\n"
            "stopNow (its 'Stopped by' line) is resumed from its last time (-resume),\n"
            "its log kept as log.<application>.<n>; one that failed is run again from a\n"
            "fresh clone, its folder kept as <name>.failed.<n>.  The table of parameters\n"
            "against wallTime, steps, meanIterations, maxRhoErrAvg, maxRhoErrMax, shocks,\n"
            "meanRhoErrAvg, maxVolErrAvg\n"
            "(from postProcessing/timeStep/<startTime>/timeStep.dat) and the 'results'\n"
            "columns is written to <sweep dir>/results.csv and results.md.",
    .options = table,
    .args = "<sweepDict>",
    .min_args = 1,
    .max_args = 1,
    .args_kind = APP_PATH,
    .notes =
        "Sweep dictionary (OpenFOAM syntax, paths relative to its folder):\n"
        "  baseCase    ../../tutorials/damBreak;\n"
        "  combine     product;          // or zip (the i-th values together)\n"
        "  parameters\n"
        "  {\n"
        "      \"constant/fluidProperties/eta\"   (0.5 1 2);   // \"<file>/<entry>\" (values)\n"
        "      \"system/timeStepDict/mode\"       (adaptive constant);\n"
        "  }\n"
        "  results     (postProcessing/densityError/0/densityError.dat:rhoErrAvg);\n"
        "              // optional: <file>:<column>, its last row"};

static options parse_args(int argc, char **argv)
{
    app a;
    options o = {0};
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    app_parse(&a, &info, argc, argv);
    o.dict = a.args[0];
    o.jobs = (int)app_int(&a, "jobs", 0);
    o.threads = (int)app_int(&a, "threads", 0);
    o.force = app_found(&a, "force");
    o.print_jobs = app_found(&a, "printJobs");
    o.collect = app_found(&a, "collect");
    if (o.print_jobs && o.collect) app_error(&a, "use -printJobs or -collect, not both");
    app_free(&a);
    if (cores < 1) cores = 1;
    if (!o.jobs) o.jobs = (int)cores;
    if (!o.threads && !getenv("OMP_NUM_THREADS") && !o.print_jobs)
        o.threads = cores / o.jobs > 1 ? (int)(cores / o.jobs) : 1;
    return o;
}

int main(int argc, char **argv)
{
    options o = parse_args(argc, argv);
    sweep s;
    int failed = 0;
    sweep_read(&s, o.dict);
    if (o.print_jobs) {
        sweep_print_jobs(&s, o.threads, o.force);
    } else {
        if (!o.collect) failed = sweep_run(&s, o.jobs, o.threads, o.force);
        sweep_collect(&s);
    }
    sweep_free(&s);
    if (failed) sl_fatal("%d of the runs failed", failed);
    return 0;
}
