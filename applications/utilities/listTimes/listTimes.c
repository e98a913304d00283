/*
 * listTimes: list (or remove) the complete time directories of a case, in
 * the habit of OpenFOAM's foamListTimes.  A time directory is complete
 * when it holds fluid.vtu (the solver renames a finished "*.tmp.*" folder to
 * its time name).  The first time, the initial state, is left out unless
 * -withZero, so `listTimes -rm` keeps it.  After -rm the collections
 * (fluid.pvd, boundary.pvd and their .vtu.series twins) are rewritten to
 * list the time directories that are left.
 *
 * With -check, each listed time's restart file is read whole (every
 * piece decompressed, every CRC checked): a damaged or missing one is
 * marked after the name, and the exit status is 1.
 *
 *   listTimes [-case <dir>] [-withZero] [-latestTime] [-time <list>] [-check] [-rm]
 */
#include "app/app.h"
#include "case/case_restart.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "io/time_dir.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const app_option options[] = {
    APP_CASE,
    {.name = "withZero", .help = "include the first time (the initial state, normally 0)"},
    APP_TIMES,
    {.name = "check",
     .help = "read each listed time's restart file (uniform/restart)\n"
             "whole, every CRC checked, and mark a damaged or missing\n"
             "one; exit 1 if any"},
    {.name = "rm",
     .help = "remove the listed time directories, then rewrite the\n"
             "collections (*.pvd, *.vtu.series) to list those left"},
    APP_END};

static const app_info info = {
    .name = "listTimes",
    .what = "Lists the complete time directories of a case (those holding fluid.vtu),\n"
            "one per line, in time order.  The case may also be given as the argument.",
    .options = options,
    .args = "[<case>]",
    .max_args = 1,
    .args_kind = APP_DIR};

static void remove_times(const char *dir, const tdir_list *l)
{
    sl_err err;
    int sets;
    for (size_t i = 0; i < l->n; i++) {
        char *p = cf_join(dir, l->name[i]);
        if (cf_remove_tree(p, &err)) sl_fatal("%s", err.msg);
        free(p);
    }
    if (cf_rewrite_collections(dir, &sets, &err)) sl_fatal("%s", err.msg);
    fprintf(stderr, "Removed %zu time directories from %s; rewrote %d collections\n", l->n, dir,
            sets);
}

/* Print the names, each checked with -check; returns how many are bad. */
static int print_times(const char *case_dir, int check, const tdir_list *l)
{
    int bad = 0;
    for (size_t i = 0; i < l->n; i++) {
        if (!check) {
            puts(l->name[i]);
            continue;
        }
        char *dir = cf_join(case_dir, l->name[i]);
        sl_err err;
        int n;
        rst_status st = rst_read(dir, NULL, 0, &n, NULL, 0, &err);
        static const char *const what[] = {"", "no restart file", "another version", "another case",
                                           "damaged"};
        if (st == RST_OK) printf("%s\n", l->name[i]);
        else printf("%s  %s: %s\n", l->name[i], what[st], err.msg);
        bad += st != RST_OK;
        free(dir);
    }
    return bad;
}

int main(int argc, char **argv)
{
    app a;
    tdir_list l;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case_or_arg(&a);
    if (!cf_is_case(dir)) sl_fatal("'%s' is not a case: it has no system/controlDict", dir);
    app_times(&a, dir, "fluid.vtu", app_found(&a, "withZero"), &l);
    int bad = print_times(dir, app_found(&a, "check"), &l);
    fflush(stdout);
    if (app_found(&a, "rm")) remove_times(dir, &l);
    tdir_list_free(&l);
    app_free(&a);
    return bad ? 1 : 0;
}
