/*
 * cleanCase: remove the results of a case so that it can be run afresh:
 * time directories, "*.tmp.*" leftovers of interrupted writes, collections
 * (*.pvd, *.vtu.series), postProcessing/ and log.*.  A time directory 0
 * holding input files (initial conditions) is kept; only the solver's
 * output (fluid.vtu, boundary.vtu, uniform/) is removed from it.
 *
 *   cleanCase [-case <dir>] [-dryRun] [<case>]
 */
#include "app/app.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int dry_run;

static const app_option options[] = {
    APP_CASE,
    {.name = "dryRun", .help = "only print what would be removed", .aliases = "dry-run n"},
    APP_END};

static const app_info info = {
    .name = "cleanCase",
    .what = "Removes the results of a case: time directories, '*.tmp.*' folders and\n"
            "files, collections (*.pvd, *.vtu.series), postProcessing/ and log.*.\n"
            "A time directory 0 that holds input files is kept (only the solver's\n"
            "fluid.vtu, boundary.vtu and uniform/ are removed from it).  Prints what\n"
            "it removes.  The case may also be given as the argument.",
    .options = options,
    .args = "[<case>]",
    .max_args = 1,
    .args_kind = APP_DIR};

static void remove_path(const char *path)
{
    sl_err err;
    printf("%s%s\n", dry_run ? "would remove " : "removed ", path);
    if (!dry_run && cf_remove_tree(path, &err)) sl_fatal("%s", err.msg);
}

/* A time directory: all of it, or only the solver output of an input 0. */
static void clean_time(const char *path, const char *name)
{
    double t = -1;
    DIR *d;
    struct dirent *de;
    cf_time_name(name, &t);
    if (t != 0 || !cf_time_has_input(path)) {
        remove_path(path);
        return;
    }
    if (!(d = opendir(path))) sl_fatal("cannot read '%s': %s", path, strerror(errno));
    while ((de = readdir(d)))
        if (cf_is_output_file(de->d_name)) {
            char *p = cf_join(path, de->d_name);
            remove_path(p);
            free(p);
        }
    closedir(d);
}

static void clean_entry(const char *dir, const char *name)
{
    char *path = cf_join(dir, name);
    switch (cf_root_kind(dir, name)) {
    case CF_TIME:
        clean_time(path, name);
        break;
    case CF_TMP:
    case CF_COLLECTION:
    case CF_LOG:
    case CF_POSTPROCESSING:
        remove_path(path);
        break;
    case CF_INPUT:
    case CF_HIDDEN:
        break;
    }
    free(path);
}

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case_or_arg(&a);
    dry_run = app_found(&a, "dryRun");
    if (!cf_is_case(dir)) sl_fatal("'%s' is not a case: it has no system/controlDict", dir);

    DIR *d = opendir(dir);
    struct dirent *de;
    if (!d) sl_fatal("cannot read '%s': %s", dir, strerror(errno));
    while ((de = readdir(d)))
        if (strcmp(de->d_name, ".") && strcmp(de->d_name, "..")) clean_entry(dir, de->d_name);
    closedir(d);
    app_free(&a);
    return 0;
}
