/*
 * ce_run: the function-object files a run wrote, as compareExperiment
 * needs them.  A function object writes postProcessing/<name>/<startTime>/
 * <type>.dat, and a run restarted from a later time opens another
 * <startTime> folder (libsrc/functionObjects/fo.h); the series of a column
 * is the rows of every folder in the order of their start times, a later
 * folder replacing the rows of earlier ones from its start on.
 */
#include "ce.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* 1 if name is a time ("0", "0.5", "1e-05") and then *t is its value. */
static int time_name(const char *name, double *t)
{
    char *end;
    if (!*name || name[0] == '.' || name[0] == '-' || name[0] == '+') return 0;
    *t = strtod(name, &end);
    return !*end && isfinite(*t);
}

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n >= m && !strcmp(s + n - m, tail);
}

typedef struct folder {
    double t;
    char *name;
} folder;

static int by_time(const void *a, const void *b)
{
    double x = ((const folder *)a)->t, y = ((const folder *)b)->t;
    return (x > y) - (x < y);
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The .dat files of one start-time folder, in name order (the histogram
 * files of densityError are not series). */
static void read_folder(ce_run *r, const char *path, double t)
{
    DIR *d = opendir(path);
    if (!d) sl_fatal("cannot read folder '%s': %s", path, strerror(errno));
    char **names = NULL;
    size_t n = 0, cap = 0;
    struct dirent *de;
    while ((de = readdir(d))) {
        if (!ends_with(de->d_name, ".dat") || !strncmp(de->d_name, "histogram_", 10)) continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 4;
            names = sl_realloc(names, cap * sizeof *names, "file names");
        }
        names[n++] = sl_strdup(de->d_name);
    }
    closedir(d);
    if (n) qsort(names, n, sizeof *names, by_name);
    r->tab = sl_realloc(r->tab, (r->ntab + n + 1) * sizeof *r->tab, "tables");
    r->start = sl_realloc(r->start, (r->ntab + n + 1) * sizeof *r->start, "tables");
    for (size_t i = 0; i < n; i++) {
        char *file = ce_join(path, names[i]);
        ce_table_read(&r->tab[r->ntab], file, CE_DAT);
        r->start[r->ntab++] = t;
        free(file);
        free(names[i]);
    }
    free(names);
}

void ce_run_read(ce_run *r, const char *case_dir, const char *fo)
{
    memset(r, 0, sizeof *r);
    char *pp = ce_join(case_dir, "postProcessing");
    r->dir = ce_join(pp, fo);
    free(pp);
    if (!is_dir(r->dir))
        sl_fatal("no folder '%s': the case has no output of a function object '%s' (name it in "
                 "the functions of system/controlDict and run the solver, or run postProcess "
                 "-func %s)",
                 r->dir, fo, fo);
    DIR *d = opendir(r->dir);
    if (!d) sl_fatal("cannot read folder '%s': %s", r->dir, strerror(errno));
    folder *f = NULL;
    size_t n = 0, cap = 0;
    struct dirent *de;
    while ((de = readdir(d))) {
        double t;
        if (!time_name(de->d_name, &t)) continue;
        char *path = ce_join(r->dir, de->d_name);
        int dir = is_dir(path);
        free(path);
        if (!dir) continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 4;
            f = sl_realloc(f, cap * sizeof *f, "folders");
        }
        f[n].t = t;
        f[n++].name = sl_strdup(de->d_name);
    }
    closedir(d);
    if (n) qsort(f, n, sizeof *f, by_time);
    for (size_t i = 0; i < n; i++) {
        char *path = ce_join(r->dir, f[i].name);
        read_folder(r, path, f[i].t);
        free(path);
        free(f[i].name);
    }
    free(f);
    if (r->ntab == 0)
        sl_fatal("no .dat file in a start-time folder of '%s' (expected %s/<startTime>/"
                 "<type>.dat)",
                 r->dir, r->dir);
}

void ce_run_series(ce_series *s, const ce_run *r, const char *column, size_t *nan_count)
{
    memset(s, 0, sizeof *s);
    size_t rows = 0, nans = 0;
    for (size_t i = 0; i < r->ntab; i++) rows += r->tab[i].nrow;
    s->t = sl_malloc(rows * sizeof *s->t, "series");
    s->v = sl_malloc(rows * sizeof *s->v, "series");
    int found = 0;
    double used = NAN; /* one file per start time: the first that has the column */
    for (size_t i = 0; i < r->ntab; i++) {
        int c = ce_table_column(&r->tab[i], column);
        if (c < 0 || r->start[i] == used) continue;
        used = r->start[i];
        ce_series part;
        size_t nn;
        ce_series_from_table(&part, &r->tab[i], c, 1.0, 0.0, 1.0, 0.0, &nn);
        memcpy(s->t + s->n, part.t, part.n * sizeof *s->t);
        memcpy(s->v + s->n, part.v, part.n * sizeof *s->v);
        s->n += part.n;
        nans += nn;
        ce_series_free(&part);
        found = 1;
    }
    if (!found) {
        size_t len = 1;
        for (size_t i = 0; i < r->ntab; i++)
            for (size_t k = 1; k < r->tab[i].ncol; k++) len += strlen(r->tab[i].name[k]) + 1;
        char *names = sl_malloc(len, "names");
        names[0] = '\0';
        for (size_t i = 0; i < r->ntab; i++)
            for (size_t k = 1; k < r->tab[i].ncol; k++) {
                if (*names) strcat(names, " ");
                strcat(names, r->tab[i].name[k]);
            }
        sl_fatal("no column '%s' in the files of '%s' (columns: %s)", column, r->dir, names);
    }
    ce_series_clean(s);
    if (s->n < 2) sl_fatal("column '%s' of '%s' has fewer than two rows", column, r->dir);
    if (nan_count) *nan_count = nans;
}

void ce_run_free(ce_run *r)
{
    for (size_t i = 0; i < r->ntab; i++) ce_table_free(&r->tab[i]);
    free(r->tab);
    free(r->start);
    free(r->dir);
    memset(r, 0, sizeof *r);
}
