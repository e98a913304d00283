/*
 * postProcess: runs function objects after the fact on the written time
 * directories of a case, as OpenFOAM's postProcess does.
 *
 *   postProcess [-case <dir>] [-func <name>]... [-time <times> | -latestTime]
 *
 * Each -func names an entry of the `functions` dictionary of
 * system/controlDict, or a type (densityError, probes, waterGauges, energy)
 * run with its defaults; without -func every entry of `functions` runs.
 * For each selected time the fluid (and, for probes, the boundary) particles
 * are read from <time>/fluid.vtu and boundary.vtu and the objects write
 * postProcessing/<name>/<firstTime>/<type>.dat, one row per time, exactly as
 * during a run (every processed time counts as a write time).
 */
#include "case/case.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "functionObjects/fo.h"
#include "functionObjects/fo_post.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(int status)
{
    fprintf(status ? stderr : stdout,
            "Usage: postProcess [-case <dir>] [-func <name>]... [-time <times> | -latestTime]\n"
            "  Runs function objects on the written time directories of a case.\n"
            "  -func <name>   an entry of 'functions' in system/controlDict, or a type run\n"
            "                 with its defaults (densityError, probes, waterGauges, energy);\n"
            "                 default: every entry of 'functions'\n"
            "  -time <times>  times and ranges, e.g. 0.5  0.5:1  :0.2  0.8:  0,0.5:1\n"
            "  -latestTime    only the latest time\n");
    exit(status);
}

int main(int argc, char **argv)
{
    const char *dir = ".", *spec = NULL;
    const char **funcs = sl_malloc((size_t)argc * sizeof *funcs, "arguments");
    size_t nfuncs = 0;
    int latest = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-case") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "-func") && i + 1 < argc) funcs[nfuncs++] = argv[++i];
        else if (!strcmp(argv[i], "-time") && i + 1 < argc) spec = argv[++i];
        else if (!strcmp(argv[i], "-latestTime")) latest = 1;
        else if (!strcmp(argv[i], "-help") || !strcmp(argv[i], "--help")) usage(0);
        else {
            fprintf(stderr, "postProcess: unknown or incomplete option '%s'\n", argv[i]);
            usage(2);
        }
    }
    if (spec && latest) {
        fprintf(stderr, "postProcess: give -time or -latestTime, not both\n");
        usage(2);
    }
    sl_case c;
    tdir_list times;
    sl_err err;
    case_read(&c, dir);
    fo_list *l = fo_select(&c, funcs, nfuncs);
    if (fo_post_times(c.dir, spec, latest, &times, &err)) sl_fatal("%s", err.msg);
    const unsigned needs = fo_needs(l);
    for (size_t i = 0; i < times.n; i++) {
        fo_snapshot sn;
        sl_info("Time = %s", times.name[i]);
        if (fo_snapshot_load(&sn, &c, times.name[i], needs, &err)) sl_fatal("%s", err.msg);
        fo_execute(l, &sn.v, times.time[i], (long)i, 1);
        fo_snapshot_free(&sn);
    }
    for (size_t i = 0; i < fo_count(l); i++)
        sl_info("%s (%s): %zu time%s -> %s", fo_name(l, i), fo_type_name(l, i), times.n,
                times.n == 1 ? "" : "s", fo_dat_path(l, i));
    fo_free(l);
    tdir_list_free(&times);
    case_free(&c);
    free(funcs);
    return 0;
}
