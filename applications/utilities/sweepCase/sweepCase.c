/*
 * sweepCase: a parameter study.  Reads a sweep dictionary (syntax in
 * sweep.h), clones the base case once per point into <sweep dir>/cases/
 * <name>, sets the point's values in place (as editDictionary -set does),
 * runs the solver on the unfinished cases N at a time and collects one
 * table of parameters against results (results.csv, results.md).
 *
 *   sweepCase [-jobs N] [-threads T] [-force] [-print-jobs | -collect] <sweepDict>
 */
#include "sweep.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/sl_log.h"

typedef struct options {
    const char *dict;
    int jobs, threads, force, print_jobs, collect;
} options;

static void usage(int status)
{
    fprintf(status ? stderr : stdout,
            "Usage: sweepCase [options] <sweepDict>\n"
            "  Runs one case per point of a parameter sweep and tabulates the results.\n"
            "  The cases are <sweep dir>/cases/<name> (names from the values, e.g.\n"
            "  eta_0.5-mode_adaptive); a case whose log.<application> holds the solver's\n"
            "  'End:' line is finished and is not run again.  The table of parameters\n"
            "  against wallTime, steps, meanIterations, maxRhoErrAvg, maxRhoErrMax, shocks,\n"
            "  meanRhoErrAvg, maxVolErrAvg\n"
            "  (from postProcessing/timeStep/<startTime>/timeStep.dat) and the 'results'\n"
            "  columns is written to <sweep dir>/results.csv and results.md.\n"
            "  -jobs N        run N cases at a time (default: the number of cores)\n"
            "  -threads T     OpenMP threads per case (default: cores / jobs, unless\n"
            "                 OMP_NUM_THREADS is set)\n"
            "  -force         clone and run every point again, finished or not\n"
            "  -print-jobs    prepare the unfinished cases and print one shell command per\n"
            "                 case instead of running them (for GNU parallel or a cluster)\n"
            "  -collect       only gather the results of the existing cases\n"
            "  -help          print this help\n"
            "Sweep dictionary (OpenFOAM syntax, paths relative to its folder):\n"
            "  baseCase    ../../tutorials/damBreak;\n"
            "  combine     product;          // or zip (the i-th values together)\n"
            "  parameters\n"
            "  {\n"
            "      \"constant/fluidProperties/eta\"   (0.5 1 2);   // \"<file>/<entry>\" (values)\n"
            "      \"system/timeStepDict/mode\"       (adaptive constant);\n"
            "  }\n"
            "  results     (postProcessing/densityError/0/densityError.dat:rhoErrAvg);\n"
            "              // optional: <file>:<column>, its last row\n");
    exit(status);
}

static int positive_int(const char *opt, const char *s)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (*end || v < 1 || v > 4096) {
        fprintf(stderr, "sweepCase: %s needs a positive number, not '%s'\n", opt, s);
        usage(2);
    }
    return (int)v;
}

static options parse_args(int argc, char **argv)
{
    options o = {0};
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-jobs") && i + 1 < argc) o.jobs = positive_int(a, argv[++i]);
        else if (!strcmp(a, "-threads") && i + 1 < argc) o.threads = positive_int(a, argv[++i]);
        else if (!strcmp(a, "-force")) o.force = 1;
        else if (!strcmp(a, "-print-jobs")) o.print_jobs = 1;
        else if (!strcmp(a, "-collect")) o.collect = 1;
        else if (!strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (a[0] != '-' && !o.dict) o.dict = a;
        else {
            fprintf(stderr, "sweepCase: unknown or incomplete option '%s'\n", a);
            usage(2);
        }
    }
    if (!o.dict) {
        fprintf(stderr, "sweepCase: no sweep dictionary given\n");
        usage(2);
    }
    if (o.print_jobs && o.collect) {
        fprintf(stderr, "sweepCase: use -print-jobs or -collect, not both\n");
        usage(2);
    }
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
