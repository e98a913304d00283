/*
 * postProcess: runs function objects after the fact on the written time
 * directories of a case, as OpenFOAM's postProcess does.
 *
 *   postProcess [-case <dir>] [-func <name>]... [-time <times> | -latestTime]
 *
 * Each -func names an entry of the `functions` dictionary of
 * system/controlDict, or a type (densityError, probes, waterGauges, energy,
 * power) run with its defaults; without -func every entry of `functions`
 * runs.  power's columns of the forces are nan here: a written time holds
 * no forces (only the kinetic energy is read).
 * For each selected time the fluid (and, for probes, the boundary) particles
 * are read from <time>/fluid.vtu and boundary.vtu and the objects write
 * postProcessing/<name>/<firstTime>/<type>.dat, one row per time, exactly as
 * during a run (every processed time counts as a write time).
 */
#include "app/app.h"
#include "case/case.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "functionObjects/fo.h"
#include "functionObjects/fo_post.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const app_option options[] = {
    APP_CASE,
    {.name = "func",
     .kind = APP_STRING,
     .arg = "<name>",
     .help = "an entry of 'functions' in system/controlDict, or a type run\n"
             "with its defaults (densityError, probes, waterGauges, energy,\n"
             "power: its powers nan, a written time holds no forces);\n"
             "repeat for several",
     .def = "every entry of 'functions'",
     .repeat = 1},
    APP_TIMES,
    APP_END};

static const app_info info = {
    .name = "postProcess",
    .what = "Runs function objects on the written time directories of a case.",
    .options = options};

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case(&a), *spec = app_string(&a, "time", NULL);
    size_t nfuncs = app_count(&a, "func");
    const char **funcs = sl_malloc((nfuncs + 1) * sizeof *funcs, "arguments");
    for (size_t i = 0; i < nfuncs; i++) funcs[i] = app_value_at(&a, "func", i);
    int latest = app_found(&a, "latestTime");
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
    app_free(&a);
    return 0;
}
