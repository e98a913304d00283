/*
 * time_dir: OpenFOAM-style time names and time directories (see time_dir.h).
 *
 * A name counts as a time only if it is made of number characters and
 * strtod consumes all of it to a finite value, so "constant", "nan",
 * "0x10" or "0.1.tmp.123" never do.
 */
#include "io/time_dir.h"

#include "core/sl_mem.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void tdir_name(double t, int precision, char *buf, size_t len)
{
    if (len == 0) return;
    if (precision <= 0) precision = 6;
    if (precision > 17) precision = 17;
    snprintf(buf, len, "%.*g", precision, t);
    /* -0 is named "0"; done on the text because -fno-signed-zeros lets the
     * compiler drop arithmetic that would clear the sign. */
    if (strcmp(buf, "-0") == 0) memmove(buf, buf + 1, 2);
}

int tdir_name_within(double t, int precision, double resolution, char *buf, size_t len)
{
    int p = precision <= 0 ? 6 : precision > 17 ? 17 : precision;
    for (;; p++) {
        tdir_name(t, p, buf, len);
        if (p >= 17 || fabs(strtod(buf, NULL) - t) <= resolution) return p;
    }
}

/* "dir/name", allocated. */
static char *tdir_join(const char *dir, const char *name)
{
    size_t len = strlen(dir) + strlen(name) + 2;
    char *s = sl_malloc(len, "a path");
    snprintf(s, len, "%s/%s", dir, name);
    return s;
}

/* The time a directory name stands for; 0 if it is not a time name. */
static int tdir_parse(const char *name, double *t)
{
    char *end;
    if (!*name || strspn(name, "0123456789.eE+-") != strlen(name)) return 0;
    *t = strtod(name, &end);
    return *end == '\0' && isfinite(*t);
}

static int tdir_is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

static int tdir_has_file(const char *dir, const char *name)
{
    struct stat st;
    char *path = tdir_join(dir, name);
    int ok = stat(path, &st) == 0 && S_ISREG(st.st_mode);
    free(path);
    return ok;
}

/* Whether entry `name` of case_dir is a complete time directory. */
static int tdir_accept(const char *case_dir, const char *name, const char *marker, double *t)
{
    char *path;
    int ok;
    if (name[0] == '.' || strstr(name, ".tmp") || !tdir_parse(name, t)) return 0;
    path = tdir_join(case_dir, name);
    ok = tdir_is_dir(path) && (!marker || tdir_has_file(path, marker));
    free(path);
    return ok;
}

/* Entries are collected as pairs so that qsort keeps time and name together. */
typedef struct tdir_entry {
    double time;
    char *name;
} tdir_entry;

static int tdir_cmp(const void *a, const void *b)
{
    const tdir_entry *x = a, *y = b;
    if (x->time != y->time) return x->time < y->time ? -1 : 1;
    return strcmp(x->name, y->name);
}

/* Read the accepted entries of an open folder into a growing array. */
static tdir_entry *tdir_scan(DIR *d, const char *case_dir, const char *marker, size_t *n)
{
    tdir_entry *e = NULL;
    size_t cap = 0;
    struct dirent *de;
    double t;
    *n = 0;
    while ((de = readdir(d)) != NULL) {
        if (!tdir_accept(case_dir, de->d_name, marker, &t)) continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 16;
            e = sl_realloc(e, cap * sizeof *e, "time directory entries");
        }
        e[*n].time = t;
        e[*n].name = sl_strdup(de->d_name);
        (*n)++;
    }
    return e;
}

int tdir_list_read(const char *case_dir, const char *complete_marker, tdir_list *out, sl_err *err)
{
    DIR *d = opendir(case_dir);
    tdir_entry *e;
    size_t n;
    memset(out, 0, sizeof *out);
    if (!d) {
        sl_err_set(err, "cannot read '%s': %s", case_dir, strerror(errno));
        return 1;
    }
    e = tdir_scan(d, case_dir, complete_marker, &n);
    closedir(d);
    if (n) qsort(e, n, sizeof *e, tdir_cmp);
    out->n = n;
    out->time = sl_malloc(n * sizeof *out->time, "time directory times");
    out->name = sl_malloc(n * sizeof *out->name, "time directory names");
    for (size_t i = 0; i < n; i++) {
        out->time[i] = e[i].time;
        out->name[i] = e[i].name;
    }
    free(e);
    return 0;
}

void tdir_list_free(tdir_list *l)
{
    for (size_t i = 0; i < l->n; i++) free(l->name[i]);
    free(l->time);
    free(l->name);
    memset(l, 0, sizeof *l);
}

/* ---- time selection ---- */

/* A number filling [s, e) (surrounding blanks allowed); empty gives def. */
static int tdir_spec_number(const char *s, const char *e, double def, double *out)
{
    while (s < e && isspace((unsigned char)*s)) s++;
    while (e > s && isspace((unsigned char)e[-1])) e--;
    if (s == e) {
        *out = def;
        return 0;
    }
    char buf[64], *end;
    if ((size_t)(e - s) >= sizeof buf) return 1;
    memcpy(buf, s, (size_t)(e - s));
    buf[e - s] = '\0';
    *out = strtod(buf, &end);
    return *end != '\0' || !isfinite(*out);
}

/* Does t match spec?  -1 on a malformed spec. */
static int tdir_spec_match(const char *spec, double t)
{
    const char *s = spec;
    int hit = 0;
    for (;;) {
        const char *e = strchr(s, ',');
        if (!e) e = s + strlen(s);
        const char *colon = memchr(s, ':', (size_t)(e - s));
        double a, b, tol = 1e-9 * (1.0 + fabs(t));
        if (colon) {
            if (tdir_spec_number(s, colon, -INFINITY, &a) ||
                tdir_spec_number(colon + 1, e, INFINITY, &b))
                return -1;
            if (t >= a - tol && t <= b + tol) hit = 1;
        } else {
            if (tdir_spec_number(s, e, NAN, &a) || isnan(a)) return -1;
            if (fabs(t - a) <= tol) hit = 1;
        }
        if (!*e) return hit;
        s = e + 1;
    }
}

int tdir_select(tdir_list *l, const char *spec, int latest, int with_first, sl_err *err)
{
    if (spec && tdir_spec_match(spec, 0.0) < 0) {
        sl_err_set(err,
                   "-time '%s': expected times and ranges such as 0.5, 0.5:1, :1, 0.5: "
                   "separated by commas",
                   spec);
        return 1;
    }
    size_t k = 0;
    for (size_t i = 0; i < l->n; i++) {
        if ((i > 0 || with_first) && (!spec || tdir_spec_match(spec, l->time[i]) == 1)) {
            l->time[k] = l->time[i];
            l->name[k++] = l->name[i];
        } else {
            free(l->name[i]);
        }
    }
    l->n = k;
    if (latest && k > 1) {
        for (size_t i = 0; i + 1 < k; i++) free(l->name[i]);
        l->time[0] = l->time[k - 1];
        l->name[0] = l->name[k - 1];
        l->n = 1;
    }
    return 0;
}

/* mkdir that accepts an existing directory. */
static int tdir_mkdir1(const char *path)
{
    if (mkdir(path, 0777) == 0) return 0;
    if (errno == EEXIST && tdir_is_dir(path)) return 0;
    if (errno == EEXIST) errno = ENOTDIR;
    return -1;
}

int tdir_mkdirs(const char *path, sl_err *err)
{
    char *p;
    int rc = 0;
    if (!*path) {
        sl_err_set(err, "cannot create '': empty path");
        return 1;
    }
    p = sl_strdup(path);
    /* Create each ancestor in turn by cutting the path at every '/' after
     * the first character (a leading '/' is the root; "a//b" repeats "a"). */
    for (char *s = strchr(p + 1, '/'); rc == 0 && s; s = strchr(s + 1, '/')) {
        *s = '\0';
        rc = tdir_mkdir1(p);
        *s = '/';
    }
    if (rc == 0) rc = tdir_mkdir1(p);
    if (rc != 0) sl_err_set(err, "cannot create '%s': %s", path, strerror(errno));
    free(p);
    return rc != 0;
}

void tdir_remove_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0) return;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        struct dirent *e;
        while (d && (e = readdir(d)))
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
                char *p = tdir_join(path, e->d_name);
                tdir_remove_tree(p);
                free(p);
            }
        if (d) closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

/* The pid of a temporary's name "<name>.tmp.<pid>[.<ext>]"; 0 if none. */
static long tdir_tmp_pid(const char *name)
{
    const char *at = strstr(name, ".tmp.");
    char *end;
    if (!at || at == name) return 0;
    long pid = strtol(at + 5, &end, 10);
    return pid > 0 && (*end == '\0' || *end == '.') ? pid : 0;
}

size_t tdir_remove_stale(const char *case_dir, char *names, size_t len)
{
    DIR *d = opendir(case_dir);
    struct dirent *e;
    size_t n = 0, off = 0;
    if (len) names[0] = '\0';
    if (!d) return 0;
    while ((e = readdir(d))) {
        long pid = tdir_tmp_pid(e->d_name);
        if (!pid || pid == (long)getpid() || kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue;
        char *p = tdir_join(case_dir, e->d_name);
        tdir_remove_tree(p);
        free(p);
        n++;
        if (off < len)
            off += (size_t)snprintf(names + off, len - off, "%s%s", off ? " " : "", e->d_name);
    }
    closedir(d);
    return n;
}
