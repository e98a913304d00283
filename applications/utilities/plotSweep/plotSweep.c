/*
 * plotSweep: one column of a sweepCase table (results.csv) against another,
 * as a gnuplot PNG with each point labelled by its case, e.g. wall time
 * against the largest average density error.  With -by, one series per
 * value of a parameter; with -where, only the rows of one subset.  With
 * -pareto, the Pareto front for "less is better on both axes" is marked on
 * the plot, printed, and written as <picture>_pareto.csv (the input's header
 * and the front's rows, as they are in the input, sorted by x).
 *
 *   plotSweep [-output file.png] [-by <column>] [-where <column>=<value>]...
 *             [-pareto] [-logX] [-logY] [-dumb] <results.csv> <x> <y>
 *
 * Rows without finite numbers in x and y (nan, inf, empty, '-') are left
 * out and counted on stderr.  Every check is made before anything is
 * written, and the files are written to temporary names and renamed, so an
 * error leaves no partial output.
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
#include <unistd.h>

typedef struct options {
    const char *csv, *x, *y, *out, *by;
    const char **where; /* "column=value", checked by parse_args */
    size_t nwhere;
    int logx, logy, dumb, pareto;
} options;

/* A CSV file: row 0 is the header. */
typedef struct table {
    size_t nrow, ncol;
    char **cell; /* nrow x ncol */
    char **line; /* nrow: each row as it is in the file, without its newline */
} table;

/* One row with numbers in x and y. */
typedef struct point {
    double x, y;
    size_t row;
} point;

/* What is plotted: the points in table order, and the Pareto front sorted
 * by x (nfront = 0 without -pareto). */
typedef struct plotted {
    point *pts, *front;
    size_t npts, nfront;
} plotted;

static const app_option table_options[] = {
    {.name = "output",
     .kind = APP_PATH,
     .arg = "<file.png>",
     .help = "the picture",
     .def = "<y>_vs_<x>.png beside the table,\nwith _<column>_<value> for each -where",
     .aliases = "o",
     .glob = "*.png"},
    {.name = "by",
     .kind = APP_STRING,
     .arg = "<column>",
     .help = "one series per value of this column (e.g. a parameter)"},
    {.name = "where",
     .kind = APP_STRING,
     .arg = "<c>=<v>",
     .help = "only the rows whose column c is the string v; repeat\n"
             "to combine (all must hold)",
     .repeat = 1},
    {.name = "pareto",
     .help = "mark the Pareto front, less being better on both axes:\n"
             "the rows no other row beats on one axis without losing\n"
             "on the other (over all series).  Prints it (case, x, y)\n"
             "and writes it as <picture name>_pareto.csv: the table's\n"
             "header and the front's rows, sorted by x"},
    {.name = "logX", .help = "logarithmic x axis", .aliases = "logx"},
    {.name = "logY", .help = "logarithmic y axis", .aliases = "logy"},
    {.name = "dumb", .help = "draw in the terminal instead of a PNG"},
    APP_END};

static const app_info info = {
    .name = "plotSweep",
    .what = "Plots one column of a sweepCase table against another with gnuplot,\n"
            "each point labelled with its case; e.g.\n"
            "  plotSweep -pareto -where mode=adaptive results.csv wallTime maxRhoErrAvg\n"
            "Rows without finite numbers in both columns (nan, inf, empty, '-') are\n"
            "left out, and counted on stderr.",
    .options = table_options,
    .args = "<results.csv> <x column> <y column>",
    .min_args = 3,
    .max_args = 3,
    .args_kind = APP_PATH};

/* A -where argument must be <column>=<value> (the value may be empty). */
static void check_where(const app *a, const char *w)
{
    const char *eq = strchr(w, '=');
    if (eq && eq != w) return;
    app_error(a, "bad -where '%s': expected <column>=<value>, e.g. -where mode=adaptive", w);
}

static options parse_args(int argc, char **argv)
{
    app a;
    options o = {0};
    app_parse(&a, &info, argc, argv);
    o.csv = a.args[0];
    o.x = a.args[1];
    o.y = a.args[2];
    o.out = app_string(&a, "output", NULL);
    o.by = app_string(&a, "by", NULL);
    o.nwhere = app_count(&a, "where");
    o.where = sl_malloc((o.nwhere + 1) * sizeof *o.where, "-where");
    for (size_t i = 0; i < o.nwhere; i++) {
        o.where[i] = app_value_at(&a, "where", i);
        check_where(&a, o.where[i]);
    }
    o.pareto = app_found(&a, "pareto");
    o.logx = app_found(&a, "logX");
    o.logy = app_found(&a, "logY");
    o.dumb = app_found(&a, "dumb");
    app_free(&a);
    return o;
}

/* ---- the table ------------------------------------------------------------- */

/* One CSV field starting at *p ("quoted ""like"" this" or plain). */
static char *csv_field(const char **p)
{
    const char *s = *p;
    char *out = sl_malloc(strlen(s) + 1, "a CSV field");
    size_t o = 0;
    if (*s == '"') {
        for (s++; *s; s++) {
            if (*s == '"' && s[1] == '"') out[o++] = *s++;
            else if (*s == '"') {
                s++;
                break;
            } else out[o++] = *s;
        }
    }
    while (*s && *s != ',' && *s != '\n' && *s != '\r') out[o++] = *s++;
    out[o] = '\0';
    *p = *s == ',' ? s + 1 : s + strlen(s);
    return out;
}

/* Splits one CSV line into fields; returns how many. */
static size_t csv_split(const char *line, char ***fields, size_t *cap)
{
    size_t n = 0;
    const char *p = line;
    do {
        if (n == *cap) {
            *cap = *cap ? 2 * *cap : 16;
            *fields = sl_realloc(*fields, *cap * sizeof **fields, "CSV fields");
        }
        (*fields)[n++] = csv_field(&p);
    } while (*p);
    return n;
}

/* Rows are cut or padded to the header's number of columns. */
static table read_table(const char *path)
{
    table t = {0};
    char *line = NULL, **f = NULL;
    size_t len = 0, fcap = 0;
    FILE *in = fopen(path, "r");
    if (!in) sl_fatal("cannot open '%s': %s", path, strerror(errno));
    while (getline(&line, &len, in) >= 0) {
        line[strcspn(line, "\r\n")] = '\0';
        if (line[strspn(line, " ")] == '\0') continue;
        size_t n = csv_split(line, &f, &fcap);
        if (t.nrow == 0) t.ncol = n;
        t.cell = sl_realloc(t.cell, (t.nrow + 1) * t.ncol * sizeof *t.cell, "a table");
        t.line = sl_realloc(t.line, (t.nrow + 1) * sizeof *t.line, "a table");
        for (size_t c = 0; c < t.ncol; c++)
            t.cell[t.nrow * t.ncol + c] = c < n ? f[c] : sl_strdup("");
        for (size_t c = t.ncol; c < n; c++) free(f[c]);
        t.line[t.nrow++] = sl_strdup(line);
    }
    free(f);
    free(line);
    fclose(in);
    if (t.nrow < 2) sl_fatal("%s: no rows (run sweepCase first)", path);
    return t;
}

static void free_table(table *t)
{
    for (size_t i = 0; i < t->nrow * t->ncol; i++) free(t->cell[i]);
    for (size_t r = 0; r < t->nrow; r++) free(t->line[r]);
    free(t->cell);
    free(t->line);
}

static const char *cell(const table *t, size_t row, int col)
{
    return t->cell[row * t->ncol + (size_t)col];
}

/* The column named `name`; `what` says where the name came from. */
static int column(const table *t, const char *name, const char *path, const char *what)
{
    for (size_t c = 0; c < t->ncol; c++)
        if (!strcmp(t->cell[c], name)) return (int)c;
    fprintf(stderr, "Columns of %s:", path);
    for (size_t c = 0; c < t->ncol; c++) fprintf(stderr, " %s", t->cell[c]);
    fputc('\n', stderr);
    sl_fatal("%s: no column '%s' (%s)", path, name, what);
}

/* ---- the rows plotted --------------------------------------------------------- */

/* Stops when -where `w` on column c keeps none of the n rows, listing the
 * values the column has in them. */
static _Noreturn void no_rows_left(const options *o, const table *t, const size_t *rows, size_t n,
                                   int c, const char *w)
{
    fprintf(stderr, "Values of '%s' in %s%s:", t->cell[c], o->csv,
            w == o->where[0] ? "" : " (in the rows the -where before it kept)");
    for (size_t i = 0; i < n; i++) {
        size_t j = 0;
        while (j < i && strcmp(cell(t, rows[j], c), cell(t, rows[i], c))) j++;
        if (j == i) fprintf(stderr, " '%s'", cell(t, rows[i], c));
    }
    fputc('\n', stderr);
    sl_fatal("%s: no row has -where %s", o->csv, w);
}

/* The data rows that pass every -where, in table order, into rows (room
 * for nrow - 1); returns how many. */
static size_t select_rows(const options *o, const table *t, size_t *rows)
{
    size_t n = 0;
    for (size_t r = 1; r < t->nrow; r++) rows[n++] = r;
    for (size_t w = 0; w < o->nwhere; w++) {
        const char *text = o->where[w], *eq = strchr(text, '=');
        char *name = sl_strdup(text), *what = sl_malloc(strlen(text) + 8, "a message");
        name[eq - text] = '\0';
        sprintf(what, "-where %s", text);
        int c = column(t, name, o->csv, what);
        free(what);
        free(name);
        size_t kept = 0;
        for (size_t i = 0; i < n; i++)
            if (!strcmp(cell(t, rows[i], c), eq + 1)) rows[kept++] = rows[i];
        if (kept == 0) no_rows_left(o, t, rows, n, c, text);
        n = kept;
    }
    return n;
}

/* 1 if s is a finite number (nan, inf, "" and "-" are not). */
static int finite_number(const char *s, double *v)
{
    char *end;
    *v = strtod(s, &end);
    return end != s && *end == '\0' && isfinite(*v);
}

/* The n rows with finite numbers in columns cx and cy, into pts (room for
 * n); returns how many.  The others are counted on stderr. */
static size_t finite_points(const options *o, const table *t, const size_t *rows, size_t n, int cx,
                            int cy, point *pts)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        point p = {0, 0, rows[i]};
        if (finite_number(cell(t, p.row, cx), &p.x) && finite_number(cell(t, p.row, cy), &p.y))
            pts[k++] = p;
    }
    if (k == 0)
        sl_fatal("%s: no row%s has finite numbers in both '%s' and '%s'", o->csv,
                 o->nwhere ? " left by -where" : "", o->x, o->y);
    if (k < n)
        fprintf(stderr, "Note: %zu of %zu rows of %s left out: no finite number in '%s' or '%s'\n",
                n - k, n, o->csv, o->x, o->y);
    return k;
}

static int by_x_then_y(const void *a, const void *b)
{
    const point *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    return (p->row > q->row) - (p->row < q->row);
}

/* The Pareto front of n finite points, less being better on both axes, into
 * front (room for n) sorted by x; returns its size.  A point is on the front
 * if no other point has x <= and y <= with one of the two strictly smaller,
 * so equal points are on it together.  Sorted by (x, y), a point can only be
 * beaten by earlier ones, and it is unbeaten iff its y is below the lowest y
 * so far (the last front point's) or it equals that point. */
static size_t pareto_front(const point *pts, size_t n, point *front)
{
    size_t k = 0;
    memcpy(front, pts, n * sizeof *front);
    qsort(front, n, sizeof *front, by_x_then_y);
    for (size_t i = 0; i < n; i++) {
        const point *last = k ? &front[k - 1] : NULL;
        if (!last || front[i].y < last->y || (front[i].y == last->y && front[i].x == last->x))
            front[k++] = front[i];
    }
    return k;
}

/* The front: the table's header and the front's rows as they are in it. */
static void write_front(const char *path, const table *t, const plotted *d)
{
    FILE *f = fopen(path, "w");
    if (!f) sl_fatal("cannot write '%s': %s", path, strerror(errno));
    fprintf(f, "%s\n", t->line[0]);
    for (size_t i = 0; i < d->nfront; i++) fprintf(f, "%s\n", t->line[d->front[i].row]);
    if (ferror(f) | fclose(f)) sl_fatal("cannot write '%s': %s", path, strerror(errno));
}

static void print_front(const options *o, const table *t, const plotted *d)
{
    printf("Pareto front (%zu of %zu rows):\n  %s %s %s\n", d->nfront, d->npts, t->cell[0], o->x,
           o->y);
    int cx = column(t, o->x, o->csv, "the x column"), cy = column(t, o->y, o->csv, "the y column");
    for (size_t i = 0; i < d->nfront; i++) {
        size_t r = d->front[i].row;
        printf("  %s %s %s\n", cell(t, r, 0), cell(t, r, cx), cell(t, r, cy));
    }
}

/* ---- the plot --------------------------------------------------------------- */

/* Appends s to the path p, characters other than [A-Za-z0-9.+-] as '_'. */
static void append_safe(char *p, const char *s)
{
    p += strlen(p);
    for (; *s; s++)
        *p++ = (strchr("+-.", *s) || (*s >= '0' && *s <= '9') || (*s >= 'a' && *s <= 'z') ||
                (*s >= 'A' && *s <= 'Z'))
            ? *s
            : '_';
    *p = '\0';
}

/* <y>_vs_<x>[_<column>_<value>...].png beside the table. */
static char *default_output(const options *o)
{
    const char *slash = strrchr(o->csv, '/');
    size_t n = strlen(o->csv) + strlen(o->x) + strlen(o->y) + 16;
    for (size_t w = 0; w < o->nwhere; w++) n += strlen(o->where[w]) + 1;
    char *s = sl_malloc(n, "a path");
    snprintf(s, n, "%.*s%s_vs_%s", slash ? (int)(slash - o->csv + 1) : 0, o->csv, o->y, o->x);
    for (size_t w = 0; w < o->nwhere; w++) {
        strcat(s, "_");
        append_safe(s, o->where[w]);
    }
    strcat(s, ".png");
    return s;
}

/* <picture without its extension>_pareto.csv */
static char *front_path(const char *picture)
{
    const char *slash = strrchr(picture, '/'), *dot = strrchr(picture, '.');
    size_t stem = dot && (!slash || dot > slash + 1) ? (size_t)(dot - picture) : strlen(picture);
    char *s = sl_malloc(stem + 16, "a path");
    sprintf(s, "%.*s_pareto.csv", (int)stem, picture);
    return s;
}

/* The points of one series (all if by < 0) as an inline data block. */
static void write_series(FILE *p, const table *t, const plotted *d, int by, const char *group,
                         int k)
{
    fprintf(p, "$s%d << EOD\n", k);
    for (size_t i = 0; i < d->npts; i++) {
        if (by >= 0 && strcmp(cell(t, d->pts[i].row, by), group)) continue;
        fprintf(p, "%.17g %.17g \"%s\"\n", d->pts[i].x, d->pts[i].y, cell(t, d->pts[i].row, 0));
    }
    fputs("EOD\n", p);
}

/* 1 if no earlier point has point i's value in column by (by < 0: one group). */
static int first_of_group(const table *t, const plotted *d, int by, size_t i)
{
    if (by < 0) return i == 0;
    for (size_t j = 0; j < i; j++)
        if (!strcmp(cell(t, d->pts[j].row, by), cell(t, d->pts[i].row, by))) return 0;
    return 1;
}

/* The unit of a column of a sweep table: sweepCase's own columns, the
 * compareExperiment summary and the usual parameters; NULL if not known. */
static const char *sweep_unit(const char *column)
{
    static const char *const units[][2] = {{"wallTime", "s"},
                                           {"steps", "-"},
                                           {"meanIterations", "-"},
                                           {"maxRhoErrAvg", "%"},
                                           {"maxRhoErrMax", "%"},
                                           {"meanRhoErrAvg", "%"},
                                           {"maxVolErrAvg", "%"},
                                           {"shocks", "-"},
                                           {"heightRms", "m"},
                                           {"heightMaxAbs", "m"},
                                           {"arrivalError", "s"},
                                           {"arrivalErrorMax", "s"},
                                           {"plateauError", "fraction"},
                                           {"peakError", "fraction"},
                                           {"nHeights", "-"},
                                           {"nPressures", "-"},
                                           {"eta", "% of rho0"},
                                           {"particleSpacing", "m"},
                                           {"r0", "m"},
                                           {"deltaT", "s"},
                                           {"deltaTMin", "s"},
                                           {"deltaTMax", "s"},
                                           {"endTime", "s"},
                                           {"writeInterval", "s"},
                                           {"rho0", "kg/m^3"},
                                           {"soundSpeed", "m/s"},
                                           {"nu", "m^2/s"},
                                           {"alpha", "-"},
                                           {"epsilon", "-"},
                                           {"iterations", "-"},
                                           {"minIterations", "-"},
                                           {"maxIterations", "-"},
                                           {"numberOfThreads", "-"},
                                           {"kappa", "-"}};
    for (size_t i = 0; i < sizeof units / sizeof *units; i++)
        if (!strcmp(column, units[i][0])) return units[i][1];
    return NULL;
}

/* The column and its unit, "wallTime [s]". */
static const char *with_unit(const char *column, char *text, size_t len)
{
    const char *unit = sweep_unit(column);
    if (unit) snprintf(text, len, "%s [%s]", column, unit);
    else snprintf(text, len, "%s", column);
    return text;
}

static void axis_label(FILE *p, const char *column)
{
    char text[256];
    cf_plot_string(p, with_unit(column, text, sizeof text));
}

static void plot_header(FILE *p, const options *o, const char *out)
{
    if (o->dumb) fputs("set terminal dumb 100 30\n", p);
    else
        fprintf(p, "set terminal %s size 900,600 noenhanced\nset output '%s'\n",
                cf_plot_png_terminal(), out);
    fputs("set grid\nset offsets graph 0.05, graph 0.05, graph 0.08, graph 0.05\nset xlabel ", p);
    axis_label(p, o->x);
    fputs("\nset ylabel ", p);
    axis_label(p, o->y);
    char title[512], ux[128], uy[128];
    int n = snprintf(title, sizeof title, "%s against %s (%s", with_unit(o->y, uy, sizeof uy),
                     with_unit(o->x, ux, sizeof ux), o->csv);
    for (size_t w = 0; w < o->nwhere && n >= 0 && (size_t)n < sizeof title; w++)
        n += snprintf(title + n, sizeof title - (size_t)n, ", %s", o->where[w]);
    if (n >= 0 && (size_t)n < sizeof title) snprintf(title + n, sizeof title - (size_t)n, ")");
    fputs("\nset title ", p);
    cf_plot_string(p, title);
    fprintf(p, "\n%s%s", o->logx ? "set logscale x\n" : "", o->logy ? "set logscale y\n" : "");
    if (!o->by && !o->pareto) fputs("set key off\n", p);
    else fputs("set key outside right\n", p);
}

static void plot(const options *o, const table *t, const plotted *d, int by, const char *out)
{
    int k = 0;
    sl_err err;
    FILE *p = cf_plot_open(&err);
    if (!p) sl_fatal("%s", err.msg);
    plot_header(p, o, out);
    /* one data block per series (value of `by`), the front, one plot command */
    const char **groups = sl_malloc(d->npts * sizeof *groups, "groups");
    for (size_t i = 0; i < d->npts; i++) {
        if (!first_of_group(t, d, by, i)) continue;
        groups[k] = by >= 0 ? cell(t, d->pts[i].row, by) : "";
        write_series(p, t, d, by, groups[k], k);
        k++;
    }
    fputs("$front << EOD\n", p);
    for (size_t i = 0; i < d->nfront; i++)
        fprintf(p, "%.17g %.17g\n", d->front[i].x, d->front[i].y);
    fputs("EOD\nplot ", p);
    for (int i = 0; i < k; i++) {
        char key[256];
        if (o->by) snprintf(key, sizeof key, "%s %s", o->by, groups[i]);
        else snprintf(key, sizeof key, "cases");
        fprintf(p, "%s$s%d using 1:2 with points pt 7 ps 1.5 title ", i ? ", " : "", i);
        cf_plot_string(p, key);
        fprintf(p, ", $s%d using 1:2:3 with labels offset 0,1 font ',8' notitle", i);
    }
    if (d->nfront)
        fputs(", $front using 1:2 with steps lw 2 lc rgb '#d62728' title 'Pareto front'"
              ", $front using 1:2 with points pt 6 ps 3 lw 2 lc rgb '#d62728' notitle",
              p);
    fputs("\n", p);
    free((void *)groups);
    if (cf_plot_close(p, &err)) sl_fatal("%s", err.msg);
}

/* ---- main ---------------------------------------------------------------------- */

/* The temporary files, removed if anything fails. */
static const char *temporary[2];

static void remove_temporaries(void)
{
    for (int i = 0; i < 2; i++)
        if (temporary[i]) remove(temporary[i]);
}

static char *temporary_name(const char *path, const char *ext)
{
    char *s = sl_malloc(strlen(path) + 48, "a path");
    sprintf(s, "%s.tmp.%ld.%s", path, (long)getpid(), ext);
    return s;
}

static void rename_or_stop(const char *from, const char *to)
{
    if (rename(from, to) != 0) sl_fatal("cannot write '%s': %s", to, strerror(errno));
    printf("Wrote %s\n", to);
}

int main(int argc, char **argv)
{
    options o = parse_args(argc, argv);
    table t = read_table(o.csv);
    int cx = column(&t, o.x, o.csv, "the x column"), cy = column(&t, o.y, o.csv, "the y column");
    int by = o.by ? column(&t, o.by, o.csv, "-by") : -1;
    size_t *rows = sl_malloc(t.nrow * sizeof *rows, "rows");
    size_t nrow = select_rows(&o, &t, rows);
    plotted d = {0};
    d.pts = sl_malloc(nrow * sizeof *d.pts, "points");
    d.npts = finite_points(&o, &t, rows, nrow, cx, cy, d.pts);
    if (o.pareto) {
        d.front = sl_malloc(d.npts * sizeof *d.front, "the Pareto front");
        d.nfront = pareto_front(d.pts, d.npts, d.front);
    }

    char *out = o.out ? sl_strdup(o.out) : default_output(&o);
    char *csv = o.pareto ? front_path(out) : NULL;
    char *tmp = temporary_name(out, "png"), *tmp_csv = csv ? temporary_name(csv, "csv") : NULL;
    temporary[0] = tmp;
    temporary[1] = tmp_csv;
    sl_log_set_fatal_hook(remove_temporaries);
    if (csv) write_front(tmp_csv, &t, &d);
    plot(&o, &t, &d, by, tmp);
    fflush(stdout);
    if (!o.dumb) rename_or_stop(tmp, out);
    if (csv) rename_or_stop(tmp_csv, csv);
    if (csv) print_front(&o, &t, &d);

    free_table(&t);
    free(rows);
    free(d.pts);
    free(d.front);
    free((void *)o.where);
    free(tmp_csv);
    free(csv);
    free(tmp);
    free(out);
    return 0;
}
