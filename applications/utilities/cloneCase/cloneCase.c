/*
 * cloneCase: copy the input of a case -- system/, constant/, the scripts and
 * other files at its root, input files of a time directory "0" -- but not
 * its results (time directories, collections, logs, postProcessing/).
 *
 *   cloneCase [-force] <source case> <new case>
 */
#include "app/app.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const app_option options[] = {
    {.name = "force", .help = "replace <new case> if it exists (it is removed first)"}, APP_END};

static const app_info info = {
    .name = "cloneCase",
    .what = "Copies system/, constant/ and the files at the root of a case (Allrun,\n"
            "Allclean, ...), but no results: no time directories (only the input\n"
            "files of a time directory 0, if it holds any), '*.tmp.*', collections\n"
            "(*.pvd, *.vtu.series), logs (log.*) or postProcessing/.",
    .options = options,
    .args = "<source case> <new case>",
    .min_args = 2,
    .max_args = 2,
    .args_kind = APP_DIR};

/* Refuse to replace the source, a folder holding it, or a non-case. */
static void check_target(const char *src, const char *dst, int force)
{
    char rs[PATH_MAX], rd[PATH_MAX];
    sl_err err;
    if (!cf_exists(dst)) return;
    if (!force) sl_fatal("'%s' exists: remove it or use -force", dst);
    if (!realpath(src, rs) || !realpath(dst, rd))
        sl_fatal("cannot resolve '%s' or '%s': %s", src, dst, strerror(errno));
    size_t n = strlen(rd);
    if (!strncmp(rs, rd, n) && (rs[n] == '/' || rs[n] == '\0'))
        sl_fatal("'%s' is or holds the source case '%s': not replacing it", dst, src);
    if (cf_is_dir(dst) && !cf_is_case(dst))
        sl_fatal("'%s' exists and is not a case (no system/controlDict): not replacing it", dst);
    if (cf_remove_tree(dst, &err)) sl_fatal("%s", err.msg);
}

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *src = a.args[0], *dst = a.args[1];
    int force = app_found(&a, "force");
    check_target(src, dst, force);
    sl_err err;
    int copied;
    if (cf_clone_case(src, dst, &copied, &err)) sl_fatal("%s", err.msg);
    printf("Cloned %s to %s (%d entries of input)\n", src, dst, copied);
    app_free(&a);
    return 0;
}
