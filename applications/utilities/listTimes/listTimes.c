/*
 * listTimes: list (or remove) the complete time directories of a case, in
 * the habit of OpenFOAM's foamListTimes.  A time directory is complete
 * when it holds fluid.vtu (the solver renames a finished "*.tmp.*" folder to
 * its time name).  The first time, the initial state, is left out unless
 * -withZero, so `listTimes -rm` keeps it.  After -rm the collections
 * (fluid.pvd, boundary.pvd and their .vtu.series twins) are rewritten to
 * list the time directories that are left.
 *
 * With -check, each listed time's restart file is read to its end (its
 * CRC checked): a damaged or missing one is marked after the name, and the
 * exit status is 1.
 *
 *   listTimes [-case <dir>] [-withZero] [-latestTime] [-time <list>] [-check] [-rm]
 */
#include "case/case_restart.h"
#include "casefiles/casefiles.h"
#include "core/sl_log.h"
#include "io/time_dir.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct options {
    const char *dir, *times;
    int with_zero, latest, rm, check;
} options;

static void usage(int status)
{
    fprintf(status ? stderr : stdout,
            "Usage: listTimes [options] [<case>]\n"
            "  Lists the complete time directories of a case (those holding fluid.vtu),\n"
            "  one per line, in time order.\n"
            "  -case <dir>     the case (default: the current directory)\n"
            "  -withZero       include the first time (the initial state, normally 0)\n"
            "  -latestTime     only the latest time\n"
            "  -time <list>    only these times: a comma-separated list of times and\n"
            "                  ranges 'a:b', ':b', 'a:' (inclusive), e.g. '0.1,0.5:1'\n"
            "  -check          read each listed time's restart file (uniform/restart) to\n"
            "                  its end and mark a damaged or missing one; exit 1 if any\n"
            "  -rm             remove the listed time directories, then rewrite the\n"
            "                  collections (*.pvd, *.vtu.series) to list those left\n"
            "  -help           print this help\n");
    exit(status);
}

static options parse_args(int argc, char **argv)
{
    options o = {.dir = "."};
    int positional = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-case") && i + 1 < argc) o.dir = argv[++i];
        else if (!strcmp(a, "-time") && i + 1 < argc) o.times = argv[++i];
        else if (!strcmp(a, "-withZero")) o.with_zero = 1;
        else if (!strcmp(a, "-latestTime")) o.latest = 1;
        else if (!strcmp(a, "-rm")) o.rm = 1;
        else if (!strcmp(a, "-check")) o.check = 1;
        else if (!strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (a[0] != '-' && !positional++) o.dir = a;
        else {
            fprintf(stderr, "listTimes: unknown or incomplete option '%s'\n", a);
            usage(2);
        }
    }
    return o;
}

/* Number at s (up to end), or `def` if empty; exits on a bad number. */
static double parse_time(const char *s, const char *end, double def, const char *sel)
{
    char buf[64], *stop;
    double t;
    size_t n = (size_t)(end - s);
    if (n == 0) return def;
    if (n >= sizeof buf) sl_fatal("-time '%s': '%.*s' is not a time", sel, (int)n, s);
    memcpy(buf, s, n);
    buf[n] = '\0';
    t = strtod(buf, &stop);
    if (*stop || !isfinite(t)) sl_fatal("-time '%s': '%s' is not a time", sel, buf);
    return t;
}

/* Whether t is selected by the -time list ("0.1,0.5:1,2:"). */
static int selected(double t, const char *sel)
{
    const char *p = sel;
    if (!sel) return 1;
    while (*p) {
        const char *comma = strchr(p, ','), *end = comma ? comma : p + strlen(p);
        const char *colon = memchr(p, ':', (size_t)(end - p));
        double tol = 1e-9 * (1.0 + fabs(t)), lo, hi;
        if (colon) {
            lo = parse_time(p, colon, -INFINITY, sel);
            hi = parse_time(colon + 1, end, INFINITY, sel);
        } else {
            lo = hi = parse_time(p, end, NAN, sel);
        }
        if (t >= lo - tol && t <= hi + tol) return 1;
        p = comma ? comma + 1 : end;
    }
    return 0;
}

/* Keeps in l the times the options select (names moved, others freed). */
static void select_times(tdir_list *l, const options *o)
{
    size_t k = 0;
    for (size_t i = 0; i < l->n; i++) {
        int keep = (o->with_zero || i > 0) && selected(l->time[i], o->times);
        if (keep) {
            l->time[k] = l->time[i];
            l->name[k++] = l->name[i];
        } else {
            free(l->name[i]);
        }
    }
    l->n = k;
    if (o->latest && l->n > 1) {
        for (size_t i = 0; i + 1 < l->n; i++) free(l->name[i]);
        l->time[0] = l->time[l->n - 1];
        l->name[0] = l->name[l->n - 1];
        l->n = 1;
    }
}

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
static int print_times(const options *o, const tdir_list *l)
{
    int bad = 0;
    for (size_t i = 0; i < l->n; i++) {
        if (!o->check) {
            puts(l->name[i]);
            continue;
        }
        char *dir = cf_join(o->dir, l->name[i]);
        sl_err err;
        int n;
        rst_status st = rst_read(dir, NULL, 0, &n, NULL, 0, &err);
        static const char *const what[] = {"", "no restart file", "another version",
                                           "another case", "damaged"};
        if (st == RST_OK) printf("%s\n", l->name[i]);
        else printf("%s  %s: %s\n", l->name[i], what[st], err.msg);
        bad += st != RST_OK;
        free(dir);
    }
    return bad;
}

int main(int argc, char **argv)
{
    options o = parse_args(argc, argv);
    tdir_list l;
    sl_err err;
    if (!cf_is_case(o.dir)) sl_fatal("'%s' is not a case: it has no system/controlDict", o.dir);
    if (tdir_list_read(o.dir, "fluid.vtu", &l, &err)) sl_fatal("%s", err.msg);
    select_times(&l, &o);
    int bad = print_times(&o, &l);
    fflush(stdout);
    if (o.rm) remove_times(o.dir, &l);
    tdir_list_free(&l);
    return bad ? 1 : 0;
}
