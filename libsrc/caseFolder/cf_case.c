/*
 * cf_case: what the entries of a case folder are, the collections that
 * index its time directories, and where its per-step record is (see
 * caseFolder.h).
 */
#include "caseFolder/caseFolder.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"
#include "dictionary/dict.h"
#include "io/time_dir.h"
#include "io/vtk_collection.h"

static int cf_ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n > m && strcmp(s + n - m, tail) == 0;
}

int cf_time_name(const char *name, double *t)
{
    char *end;
    double v;
    if (!*name || strspn(name, "0123456789.eE+-") != strlen(name)) return 0;
    v = strtod(name, &end);
    if (*end || !isfinite(v)) return 0;
    if (t) *t = v;
    return 1;
}

cf_kind cf_root_kind(const char *case_dir, const char *name)
{
    char *p;
    int dir;
    if (name[0] == '.') return CF_HIDDEN;
    if (strstr(name, ".tmp.")) return CF_TMP;
    if (cf_ends_with(name, ".pvd") || cf_ends_with(name, ".vtu.series")) return CF_COLLECTION;
    if (!strncmp(name, "log.", 4)) return CF_LOG;
    if (!strcmp(name, "postProcessing")) return CF_POSTPROCESSING;
    p = cf_join(case_dir, name);
    dir = cf_is_dir(p);
    free(p);
    return dir && cf_time_name(name, NULL) ? CF_TIME : CF_INPUT;
}

int cf_is_output_file(const char *name)
{
    return !strcmp(name, "fluid.vtu") || !strcmp(name, "boundary.vtu") || !strcmp(name, "uniform");
}

int cf_time_has_input(const char *time_dir)
{
    DIR *d = opendir(time_dir);
    struct dirent *de;
    int input = 0;
    if (!d) return 0;
    while (!input && (de = readdir(d)))
        input =
            strcmp(de->d_name, ".") && strcmp(de->d_name, "..") && !cf_is_output_file(de->d_name);
    closedir(d);
    return input;
}

/* ---- collections ----------------------------------------------------------------- */

/* Rewrite (or remove) the collection of one set, e.g. "fluid". */
static int cf_rewrite_set(const char *case_dir, const char *set, sl_err *err)
{
    char pvd[512], series[512], vtu[512];
    char *pp, *sp;
    tdir_list l;
    int rc;
    snprintf(pvd, sizeof pvd, "%s.pvd", set);
    snprintf(series, sizeof series, "%s.vtu.series", set);
    snprintf(vtu, sizeof vtu, "%s.vtu", set);
    pp = cf_join(case_dir, pvd);
    sp = cf_join(case_dir, series);
    rc = tdir_list_read(case_dir, vtu, &l, err);
    int listed = !rc;
    if (!rc && l.n == 0) {
        rc = cf_remove_tree(pp, err) || cf_remove_tree(sp, err);
    } else if (!rc) {
        char **files = sl_malloc(l.n * sizeof *files, "a collection");
        for (size_t i = 0; i < l.n; i++) files[i] = cf_join(l.name[i], vtu);
        rc = vtk_collection_write(cf_exists(pp) ? pp : NULL, cf_exists(sp) ? sp : NULL, l.time,
                                  (const char *const *)files, l.n, err);
        for (size_t i = 0; i < l.n; i++) free(files[i]);
        free(files);
    }
    if (listed) tdir_list_free(&l);
    free(pp);
    free(sp);
    return rc;
}

int cf_rewrite_collections(const char *case_dir, int *sets, sl_err *err)
{
    DIR *d = opendir(case_dir);
    struct dirent *de;
    char **done = NULL;
    size_t ndone = 0;
    int rc = 0;
    if (sets) *sets = 0;
    if (!d) {
        sl_err_set(err, "cannot read folder '%s': %s", case_dir, strerror(errno));
        return 1;
    }
    while (!rc && (de = readdir(d))) {
        const char *n = de->d_name;
        size_t len = strlen(n), cut;
        int seen = 0;
        if (cf_root_kind(case_dir, n) != CF_COLLECTION) continue;
        cut = cf_ends_with(n, ".pvd") ? len - 4 : len - 11;
        char *set = sl_malloc(cut + 1, "a name");
        memcpy(set, n, cut);
        set[cut] = '\0';
        for (size_t i = 0; i < ndone && !seen; i++) seen = !strcmp(done[i], set);
        if (seen) {
            free(set);
            continue;
        }
        done = sl_realloc(done, (ndone + 1) * sizeof *done, "names");
        done[ndone++] = set;
        rc = cf_rewrite_set(case_dir, set, err);
    }
    closedir(d);
    for (size_t i = 0; i < ndone; i++) free(done[i]);
    free(done);
    if (sets) *sets = (int)ndone;
    return rc;
}

/* ---- the per-step record ------------------------------------------------------------- */

char *cf_record_path(const char *case_dir, sl_err *err)
{
    char *ctl = cf_join(case_dir, "system/controlDict"), *dir, *path = NULL;
    char tname[64] = "0", rel[128];
    double start = 0;
    long prec = 6;
    sl_err ignore;
    dict *d = dict_read_file(ctl, &ignore);
    if (d && !dict_get_scalar_or(d, "startTime", 0, &start, &ignore) &&
        !dict_get_int_or(d, "timePrecision", 6, &prec, &ignore))
        tdir_name(start, (int)prec, tname, sizeof tname);
    dict_free(d);
    free(ctl);
    snprintf(rel, sizeof rel, "postProcessing/timeStep/%s/timeStep.dat", tname);
    path = cf_join(case_dir, rel);
    if (cf_is_file(path)) return path;
    free(path);
    path = NULL;
    dir = cf_join(case_dir, "postProcessing/timeStep");
    tdir_list l;
    if (cf_is_dir(dir) && !tdir_list_read(dir, "timeStep.dat", &l, &ignore)) {
        if (l.n) {
            char *t = cf_join(dir, l.name[l.n - 1]);
            path = cf_join(t, "timeStep.dat");
            free(t);
        }
        tdir_list_free(&l);
    }
    if (!path)
        sl_err_set(err,
                   "%s: no per-step record postProcessing/timeStep/*/timeStep.dat "
                   "(has the case been run?)",
                   case_dir);
    free(dir);
    return path;
}

/* Append the rows of u with time <= until to t, columns matched by name. */
static void cf_record_append(cf_table *t, const cf_table *u, double until)
{
    int *map = sl_malloc((t->ncol + 1) * sizeof *map, "column map");
    size_t keep = 0;
    for (size_t c = 0; c < t->ncol; c++) map[c] = cf_table_column(u, t->name[c]);
    for (size_t r = 0; r < u->nrow; r++) keep += u->v[r * u->ncol] <= until;
    t->v = sl_realloc(t->v, (t->nrow + keep + 1) * t->ncol * sizeof *t->v, "record rows");
    for (size_t r = 0; r < u->nrow; r++) {
        if (!(u->v[r * u->ncol] <= until)) continue;
        double *row = t->v + t->nrow++ * t->ncol;
        for (size_t c = 0; c < t->ncol; c++)
            row[c] = map[c] >= 0 ? u->v[r * u->ncol + (size_t)map[c]] : (double)NAN;
    }
    free(map);
}

int cf_record_read(const char *case_dir, cf_table *t, char **folders, char **newest, sl_err *err)
{
    char *dir = cf_join(case_dir, "postProcessing/timeStep");
    tdir_list l;
    sl_err ignore;
    memset(t, 0, sizeof *t);
    if (folders) *folders = NULL;
    if (newest) *newest = NULL;
    if (!cf_is_dir(dir) || tdir_list_read(dir, "timeStep.dat", &l, &ignore) || l.n == 0) {
        if (cf_is_dir(dir)) tdir_list_free(&l);
        free(dir);
        sl_err_set(err,
                   "%s: no per-step record postProcessing/timeStep/*/timeStep.dat (has the "
                   "case been run?)",
                   case_dir);
        return 1;
    }
    size_t len = 64;
    for (size_t i = 0; i < l.n; i++) len += strlen(l.name[i]) + 1;
    char *names = sl_malloc(len, "record folders");
    names[0] = '\0';
    int rc = 0;
    for (size_t i = 0; i < l.n && !rc; i++) {
        char *sub = cf_join(dir, l.name[i]), *path = cf_join(sub, "timeStep.dat");
        cf_table u;
        double until = i + 1 < l.n ? l.time[i + 1] : (double)INFINITY;
        rc = cf_table_read(path, &u, err);
        if (!rc && i == 0) {
            *t = u; /* the first one's columns */
            memset(&u, 0, sizeof u);
            size_t keep = 0;
            while (keep < t->nrow && t->v[keep * t->ncol] <= until) keep++;
            t->nrow = keep;
        } else if (!rc) {
            cf_record_append(t, &u, until);
        }
        cf_table_free(&u);
        if (newest && i + 1 == l.n) *newest = sl_strdup(path);
        strcat(names, i ? "," : "");
        strcat(names, l.name[i]);
        free(path);
        free(sub);
    }
    if (folders) {
        *folders = sl_malloc(len + 64, "record folders");
        snprintf(*folders, len + 64,
                 l.n > 1 ? "postProcessing/timeStep/{%s}/timeStep.dat"
                         : "postProcessing/timeStep/%s/timeStep.dat",
                 names);
    }
    free(names);
    tdir_list_free(&l);
    free(dir);
    if (rc) cf_table_free(t);
    return rc;
}
