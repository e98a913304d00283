/*
 * monitorCase: watch a run, in the habit of OpenFOAM's foamMonitor -- plots
 * the per-step record of every session of the case (postProcessing/
 * timeStep/<startTime>/timeStep.dat of the first run and of each restart,
 * joined in time order by cf_record_read) or any function-object file with
 * gnuplot, in the terminal or as a PNG that is redrawn every few seconds
 * (written atomically, so an image viewer never shows half a picture).
 * Axes carry units; -print writes the joined record as a table instead.
 *
 *   monitorCase [-case <dir>] [-columns a,b] [-png file] [-refresh s] [-idle s] [-once]
 *               [-print] [<file>]
 */
#include "app/app.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

typedef struct options {
    const char *dir, *file, *columns, *png, *script;
    double refresh, idle;
    int once, logy, print;
} options;

/* The default picture: one panel per group of columns the record has. */
static const char *const default_panels[] = {"rhoErrAvg,rhoErrMax", "iterations", "deltaT", "vMax"};

static const app_option table[] = {
    APP_CASE,
    {.name = "columns",
     .kind = APP_STRING,
     .arg = "<a,b>",
     .help = "plot these columns (names or 1-based numbers) in one panel"},
    {.name = "png",
     .kind = APP_PATH,
     .help = "draw into a PNG instead of the terminal",
     .glob = "*.png"},
    {.name = "refresh",
     .kind = APP_DOUBLE,
     .arg = "<s>",
     .help = "seconds between redraws",
     .def = "5",
     .min = 0,
     .max = INFINITY,
     .above_min = 1},
    {.name = "idle",
     .kind = APP_DOUBLE,
     .arg = "<s>",
     .help = "stop when the file has not changed for this long",
     .min = 0,
     .max = INFINITY,
     .above_min = 1},
    {.name = "script",
     .kind = APP_PATH,
     .arg = "<file.gp>",
     .help = "draw with this gnuplot script instead (with -png): it is run as\n"
             "gnuplot -c <file.gp> <table> <png> <title>, <table> holding the\n"
             "(joined) record as -print writes it; e.g. etc/plotTimeStep.gp",
     .glob = "*.gp"},
    {.name = "once", .help = "draw once and exit"},
    {.name = "logScale", .help = "logarithmic y axes", .aliases = "logscale"},
    {.name = "print", .help = "print the (joined) record as a table and exit"},
    APP_END};

static const app_info info = {
    .name = "monitorCase",
    .what = "Plots the per-step record of a case (postProcessing/timeStep/<startTime>/\n"
            "timeStep.dat of the first run and of every restart, joined in time order)\n"
            "or any OpenFOAM function-object <file> against its first\n"
            "column with gnuplot, redrawing until interrupted (Ctrl-C).  By default\n"
            "four panels: density error (rhoErrAvg, rhoErrMax), iterations, deltaT, vMax.",
    .options = table,
    .args = "[<file>]",
    .max_args = 1,
    .args_kind = APP_PATH};

static options parse_args(int argc, char **argv)
{
    app a;
    options o = {0};
    app_parse(&a, &info, argc, argv);
    o.dir = app_case(&a);
    o.file = a.nargs ? a.args[0] : NULL;
    o.columns = app_string(&a, "columns", NULL);
    o.png = app_string(&a, "png", NULL);
    o.script = app_string(&a, "script", NULL);
    if (o.script && !o.png) app_error(&a, "-script draws into a PNG: give -png <file> too");
    o.refresh = app_double(&a, "refresh", 5);
    o.idle = app_double(&a, "idle", 0);
    o.once = app_found(&a, "once");
    o.logy = app_found(&a, "logScale");
    o.print = app_found(&a, "print");
    app_free(&a);
    return o;
}

/* ---- drawing ---------------------------------------------------------------- */

/* Column numbers of a comma-separated list; missing ones are left out
 * (required: an error naming them and the columns there are). */
static int panel_columns(const cf_table *t, const char *list, int *col, int max, int required,
                         const char *path)
{
    char *copy = sl_strdup(list), *save = NULL;
    int n = 0;
    for (char *name = strtok_r(copy, ",", &save); name && n < max;
         name = strtok_r(NULL, ",", &save)) {
        int c = cf_table_column(t, name);
        if (c < 0 && required) {
            char *names = cf_table_names(t);
            sl_fatal("%s: no column '%s' (columns: %s)", path, name, names);
        }
        if (c >= 0) col[n++] = c;
    }
    free(copy);
    return n;
}

/* The unit of a column of the record or of a function object, by name. */
static const char *unit_of(const char *name)
{
    static const char *const units[][2] = {
        {"Time", "s"},       {"deltaT", "s"},   {"controllerDeltaT", "s"}, {"wallTime", "s"},
        {"iterations", "-"}, {"shock", "-"},    {"rhoErr", "%"},           {"volErr", "%"},
        {"vMax", "m/s"},     {"FMax", "m/s^2"}, {"pressure", "Pa"},        {"density", "kg/m^3"},
        {"velocity", "m/s"}, {"height", "m"},   {"kinetic", "J"},          {"potential", "J"},
        {"total", "J"},      {"average", "%"},  {"maximum", "%"},          {"minimum", "%"},
        {"p", "%"}};
    for (size_t i = 0; i < sizeof units / sizeof *units; i++) {
        size_t n = strlen(units[i][0]);
        if (!strncmp(name, units[i][0], n) &&
            (strlen(units[i][0]) > 1 || (name[1] >= '0' && name[1] <= '9')))
            return units[i][1];
    }
    return NULL;
}

/* "deltaT [s]", or the name alone when its unit is not known. */
static void label(char *buf, size_t len, const char *name, const char *unit)
{
    if (unit) snprintf(buf, len, "%s [%s]", name, unit);
    else snprintf(buf, len, "%s", name);
}

/* A tick step of 1, 2 or 5 times a power of ten giving at most `max`
 * ticks over [lo, hi], so that labels do not run together. */
static double tick_step(double lo, double hi, int max)
{
    double range = hi - lo;
    if (!(range > 0) || max < 1) return 0;
    double raw = range / max, p = pow(10.0, floor(log10(raw))), m = raw / p;
    return (m <= 1 ? 1 : m <= 2 ? 2 : m <= 5 ? 5 : 10) * p;
}

/* Range of the first column (the x axis). */
static void x_range(const cf_table *t, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (size_t r = 0; r < t->nrow; r++) {
        double x = t->v[r * t->ncol];
        if (x < *lo) *lo = x;
        if (x > *hi) *hi = x;
    }
}

/* One panel: the given columns against the first one, as inline data;
 * its y label is their common unit. */
static void draw_panel(FILE *p, const cf_table *t, const int *col, int n, int png)
{
    char ylabel[256];
    const char *unit = unit_of(t->name[col[0]]);
    for (int k = 1; k < n; k++)
        if (!unit || !unit_of(t->name[col[k]]) || strcmp(unit, unit_of(t->name[col[k]])))
            unit = NULL;
    label(ylabel, sizeof ylabel, n == 1 ? t->name[col[0]] : "", unit);
    fputs("set ylabel ", p); /* in a terminal the key says it: no room beside the ticks */
    cf_plot_string(p, !png ? "" : n == 1 || !unit ? ylabel : ylabel + 1);
    fputc('\n', p);
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < n; k++)
        for (size_t r = 0; r < t->nrow; r++) {
            double y = t->v[r * t->ncol + (size_t)col[k]];
            if (y < lo) lo = y;
            if (y > hi) hi = y;
        }
    if (hi - lo <= 1e-9 * fmax(fabs(lo), fabs(hi))) { /* constant (deltaT): not an empty range */
        double d = lo != 0 ? 0.05 * fabs(lo) : 1;
        fprintf(p, "set yrange [%.10g:%.10g]\n", lo - d, hi + d);
    } else {
        fputs("set autoscale y\n", p);
    }
    fputs("plot ", p);
    for (int k = 0; k < n; k++) {
        char title[256];
        label(title, sizeof title, t->name[col[k]], unit_of(t->name[col[k]]));
        fprintf(p, "%s'-' using 1:2 with lines lw 2 title ", k ? ", " : "");
        cf_plot_string(p, title);
    }
    fputc('\n', p);
    for (int k = 0; k < n; k++) {
        for (size_t r = 0; r < t->nrow; r++)
            fprintf(p, "%.10g %.10g\n", t->v[r * t->ncol], t->v[r * t->ncol + (size_t)col[k]]);
        fputs("e\n", p);
    }
}

static void terminal_size(int *w, int *h)
{
    struct winsize ws;
    *w = 100;
    *h = 32;
    if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 20 && ws.ws_row > 10) {
        *w = ws.ws_col;
        *h = ws.ws_row - 1;
    }
}

/* Draws the table into `out` (a PNG path) or the terminal (out NULL). */
static void draw(const options *o, const cf_table *t, const char *path, const char *out)
{
    const char *single[1] = {o->columns};
    const char *const *panels = o->columns ? single : default_panels;
    int npanels = o->columns ? 1 : 4, col[4][16], ncol[4], shown = 0, w = 100, h = 32;
    sl_err err;
    for (int i = 0; i < npanels; i++) {
        ncol[i] = panel_columns(t, panels[i], col[i], 16, o->columns != NULL, path);
        shown += ncol[i] > 0;
    }
    if (!shown)
        sl_fatal("%s: none of the columns rhoErrAvg, rhoErrMax, iterations, deltaT, vMax: "
                 "choose some with -columns",
                 path);
    FILE *p = cf_plot_open(&err);
    if (!p) sl_fatal("%s", err.msg);
    if (out) {
        fprintf(p, "set terminal %s size 1000,%d noenhanced\nset output ", cf_plot_png_terminal(),
                shown > 1 ? 800 : 500);
        cf_plot_string(p, out);
        fputc('\n', p);
    } else {
        terminal_size(&w, &h);
        fprintf(p, "set terminal dumb %d %d\n", w, h);
    }
    char xlabel[256];
    double lo, hi;
    label(xlabel, sizeof xlabel, t->name[0], unit_of(t->name[0]));
    x_range(t, &lo, &hi);
    /* columns of the panel, and ~11 characters per tick label */
    double step = tick_step(lo, hi, out ? (shown > 1 ? 5 : 8) : (shown > 1 ? w / 2 : w) / 11);
    fprintf(p, "set grid\nset key top left opaque\nset format x '%%g'\nset format y '%%g'\n");
    if (step > 0) fprintf(p, "set xtics %.10g\n", step);
    fputs("set xlabel ", p);
    cf_plot_string(p, xlabel);
    fprintf(p, "\n%s", o->logy ? "set logscale y\n" : "");
    if (shown > 1) {
        fprintf(p, "set multiplot layout 2,2 title ");
        cf_plot_string(p, path);
        fputc('\n', p);
    } else {
        fputs("set title ", p);
        cf_plot_string(p, path);
        fputc('\n', p);
    }
    for (int i = 0; i < npanels; i++)
        if (ncol[i] > 0) draw_panel(p, t, col[i], ncol[i], out != NULL);
    if (shown > 1) fputs("unset multiplot\n", p);
    if (cf_plot_close(p, &err)) sl_fatal("%s", err.msg);
}

/* The table to show: the file given, or the case's whole record; *title
 * names it and *watch is the file that grows (both allocated). */
static void load(const options *o, cf_table *t, char **title, char **watch)
{
    sl_err err;
    if (o->file) {
        if (cf_table_read(o->file, t, &err)) sl_fatal("%s", err.msg);
        *title = sl_strdup(o->file);
        *watch = sl_strdup(o->file);
        return;
    }
    char *folders, *abs = realpath(o->dir, NULL), *base;
    if (cf_record_read(o->dir, t, &folders, watch, &err)) sl_fatal("%s", err.msg);
    base =
        abs && strrchr(abs, '/') && strrchr(abs, '/')[1] ? strrchr(abs, '/') + 1 : (char *)o->dir;
    size_t n = strlen(base) + strlen(folders) + 8;
    *title = sl_malloc(n, "a title"); /* the case's own name, never "." */
    snprintf(*title, n, "%s: %s", base, folders);
    free(folders);
    free(abs);
}

/* The shortest of 15-17 digits that reads back as v exactly. */
static void print_exact(FILE *out, double v, char end)
{
    char buf[40];
    for (int digits = 15; digits <= 17; digits++) {
        snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (strtod(buf, NULL) == v || isnan(v)) break;
    }
    fprintf(out, "%s%c", buf, end);
}

/* The table as text: a header naming the columns, then the rows. */
static void print_table(FILE *out, const cf_table *t)
{
    fputs("#", out);
    for (size_t c = 0; c < t->ncol; c++) fprintf(out, "%s%s", c ? "\t" : " ", t->name[c]);
    fputc('\n', out);
    for (size_t r = 0; r < t->nrow; r++)
        for (size_t c = 0; c < t->ncol; c++)
            print_exact(out, t->v[r * t->ncol + c], c + 1 < t->ncol ? '\t' : '\n');
}

/* -script: the table into a temporary file beside the picture, then
 * `gnuplot -c <script> <table> <out> <title>`. */
static void draw_script(const options *o, const cf_table *t, const char *title, const char *out)
{
    char *dat = sl_malloc(strlen(out) + 32, "a path");
    const char *args[] = {dat, out, title, NULL};
    sl_err err;
    sprintf(dat, "%s.tmp.%ld.dat", out, (long)getpid());
    FILE *f = fopen(dat, "w");
    if (!f) sl_fatal("cannot write '%s': %s", dat, strerror(errno));
    print_table(f, t);
    if (fclose(f) != 0) sl_fatal("cannot write '%s': %s", dat, strerror(errno));
    int bad = cf_plot_script(NULL, o->script, args, &err);
    remove(dat);
    free(dat);
    if (bad) sl_fatal("%s", err.msg);
}

/* Reads the record and draws it; 0 if it had no rows yet (nothing drawn).
 * *watch gets the file to watch for changes. */
static int draw_once(const options *o, char **watch)
{
    cf_table t;
    char *path;
    free(*watch);
    load(o, &t, &path, watch);
    if (t.nrow == 0) {
        cf_table_free(&t);
        free(path);
        return 0;
    }
    if (o->png) {
        char *tmp = sl_malloc(strlen(o->png) + 32, "a path");
        sprintf(tmp, "%s.tmp.%ld.png", o->png, (long)getpid());
        if (o->script) draw_script(o, &t, path, tmp);
        else draw(o, &t, path, tmp);
        if (rename(tmp, o->png) != 0) sl_fatal("cannot write '%s': %s", o->png, strerror(errno));
        free(tmp);
    } else {
        if (!o->once && isatty(STDOUT_FILENO)) fputs("\033[H\033[2J", stdout);
        draw(o, &t, path, NULL);
    }
    cf_table_free(&t);
    free(path);
    return 1;
}

static time_t modified(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? st.st_mtime : 0;
}

int main(int argc, char **argv)
{
    options o = parse_args(argc, argv);
    char *path = NULL;
    time_t last_change = time(NULL), seen = 0;
    if (o.print) {
        cf_table t;
        char *title;
        load(&o, &t, &title, &path);
        print_table(stdout, &t);
        cf_table_free(&t);
        free(title);
        free(path);
        return 0;
    }
    for (;;) {
        int drawn = draw_once(&o, &path);
        if (o.once) {
            if (!drawn) sl_fatal("%s: no data rows yet", path);
            break;
        }
        if (!drawn) fprintf(stderr, "%s: waiting for data\n", path);
        else if (o.png) fprintf(stderr, "\rUpdated %s", o.png);
        time_t whole = (time_t)o.refresh;
        struct timespec nap = {whole, (long)((o.refresh - (double)whole) * 1e9)};
        nanosleep(&nap, NULL);
        time_t m = modified(path);
        if (m != seen) {
            seen = m;
            last_change = time(NULL);
        } else if (o.idle > 0 && difftime(time(NULL), last_change) >= o.idle) {
            fprintf(stderr, "\n%s unchanged for %g s: stopping\n", path, o.idle);
            break;
        }
    }
    if (o.png) printf("Wrote %s\n", o.png);
    free(path);
    return 0;
}
