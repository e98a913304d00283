/*
 * cf_clone: copy the input of a case, not its results (see caseFolder.h):
 * every root entry that cf_root_kind calls input, and the input files of a
 * time directory 0 (initial conditions), without the solver's output.
 */
#include "caseFolder/caseFolder.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/time_dir.h"

/* The entries of a time directory that are not solver output. */
static int cf_copy_time_inputs(const char *src, const char *dst, sl_err *err)
{
    DIR *d = opendir(src);
    struct dirent *de;
    int rc = 0;
    if (!d) {
        sl_err_set(err, "cannot read folder '%s': %s", src, strerror(errno));
        return 1;
    }
    if (mkdir(dst, 0777) != 0 && errno != EEXIST) {
        sl_err_set(err, "cannot create '%s': %s", dst, strerror(errno));
        closedir(d);
        return 1;
    }
    while (!rc && (de = readdir(d))) {
        if (!strcmp(de->d_name, ".") || !strcmp(de->d_name, "..") || cf_is_output_file(de->d_name))
            continue;
        char *s = cf_join(src, de->d_name), *t = cf_join(dst, de->d_name);
        rc = cf_copy_tree(s, t, err);
        free(s);
        free(t);
    }
    closedir(d);
    return rc;
}

/* Copies one root entry if it is input; *copied counts it. */
static int cf_clone_entry(const char *src, const char *dst, const char *name, int *copied,
                          sl_err *err)
{
    char *s = cf_join(src, name), *t = cf_join(dst, name);
    double time = -1;
    int rc = 0;
    switch (cf_root_kind(src, name)) {
    case CF_INPUT:
        rc = cf_copy_tree(s, t, err);
        ++*copied;
        break;
    case CF_TIME:
        cf_time_name(name, &time);
        if (time == 0 && cf_time_has_input(s)) {
            rc = cf_copy_time_inputs(s, t, err);
            ++*copied;
        }
        break;
    default:
        break; /* results, logs, hidden files */
    }
    free(s);
    free(t);
    return rc;
}

int cf_clone_case(const char *src, const char *dst, int *copied, sl_err *err)
{
    DIR *d;
    struct dirent *de;
    int rc, n = 0;
    if (!cf_is_case(src)) {
        sl_err_set(err, "'%s' is not a case: it has no system/controlDict", src);
        return 1;
    }
    if ((rc = tdir_mkdirs(dst, err))) return rc;
    if (!(d = opendir(src))) {
        sl_err_set(err, "cannot read folder '%s': %s", src, strerror(errno));
        return 1;
    }
    while (!rc && (de = readdir(d)))
        if (strcmp(de->d_name, ".") && strcmp(de->d_name, ".."))
            rc = cf_clone_entry(src, dst, de->d_name, &n, err);
    closedir(d);
    if (copied) *copied = n;
    return rc;
}
