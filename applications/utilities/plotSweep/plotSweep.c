/*
 * plotSweep: one column of a sweepCase table (results.csv) against another,
 * as a gnuplot PNG with each point labelled by its case, e.g. wall time
 * against the largest average density error.  With -by, one series per
 * value of a parameter.
 *
 *   plotSweep [-o file.png] [-by <column>] [-logx] [-logy] [-dumb] <results.csv> <x> <y>
 */
#include "casefiles/casefiles.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct options {
    const char *csv, *x, *y, *out, *by;
    int logx, logy, dumb;
} options;

/* A CSV file: row 0 is the header. */
typedef struct table {
    size_t nrow, ncol;
    char **cell; /* nrow x ncol */
} table;

static void usage(int status)
{
    fprintf(status ? stderr : stdout,
            "Usage: plotSweep [options] <results.csv> <x column> <y column>\n"
            "  Plots one column of a sweepCase table against another with gnuplot,\n"
            "  each point labelled with its case; e.g.\n"
            "    plotSweep results.csv wallTime maxRhoErrAvg\n"
            "  -o <file.png>  the picture (default: <y>_vs_<x>.png beside the table)\n"
            "  -by <column>   one series per value of this column (e.g. a parameter)\n"
            "  -logx, -logy   logarithmic axes\n"
            "  -dumb          draw in the terminal instead of a PNG\n"
            "  -help          print this help\n");
    exit(status);
}

static options parse_args(int argc, char **argv)
{
    options o = {0};
    const char **pos[] = {&o.csv, &o.x, &o.y};
    int npos = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-o") && i + 1 < argc) o.out = argv[++i];
        else if (!strcmp(a, "-by") && i + 1 < argc) o.by = argv[++i];
        else if (!strcmp(a, "-logx")) o.logx = 1;
        else if (!strcmp(a, "-logy")) o.logy = 1;
        else if (!strcmp(a, "-dumb")) o.dumb = 1;
        else if (!strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (a[0] != '-' && npos < 3) *pos[npos++] = a;
        else {
            fprintf(stderr, "plotSweep: unknown or incomplete option '%s'\n", a);
            usage(2);
        }
    }
    if (npos < 3) usage(2);
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
            else if (*s == '"') { s++; break; }
            else out[o++] = *s;
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
        if (line[strspn(line, " \r\n")] == '\0') continue;
        size_t n = csv_split(line, &f, &fcap);
        if (t.nrow == 0) t.ncol = n;
        t.cell = sl_realloc(t.cell, (t.nrow + 1) * t.ncol * sizeof *t.cell, "a table");
        for (size_t c = 0; c < t.ncol; c++)
            t.cell[t.nrow * t.ncol + c] = c < n ? f[c] : sl_strdup("");
        for (size_t c = t.ncol; c < n; c++) free(f[c]);
        t.nrow++;
    }
    free(f);
    free(line);
    fclose(in);
    if (t.nrow < 2) sl_fatal("%s: no rows (run sweepCase first)", path);
    return t;
}

static int column(const table *t, const char *name, const char *path)
{
    for (size_t c = 0; c < t->ncol; c++)
        if (!strcmp(t->cell[c], name)) return (int)c;
    fprintf(stderr, "Columns of %s:", path);
    for (size_t c = 0; c < t->ncol; c++) fprintf(stderr, " %s", t->cell[c]);
    fputc('\n', stderr);
    sl_fatal("%s: no column '%s'", path, name);
}

static int is_number(const char *s)
{
    char *end;
    if (!*s) return 0;
    (void)strtod(s, &end);
    return *end == '\0';
}

/* ---- the plot --------------------------------------------------------------- */

static char *default_output(const options *o)
{
    const char *slash = strrchr(o->csv, '/');
    size_t n = strlen(o->csv) + strlen(o->x) + strlen(o->y) + 16;
    char *s = sl_malloc(n, "a path");
    snprintf(s, n, "%.*s%s_vs_%s.png", slash ? (int)(slash - o->csv + 1) : 0, o->csv, o->y, o->x);
    return s;
}

/* The rows of one series (all rows if by < 0) as an inline data block. */
static size_t write_series(FILE *p, const table *t, int cx, int cy, int by, const char *group,
                           int k)
{
    size_t n = 0;
    fprintf(p, "$s%d << EOD\n", k);
    for (size_t r = 1; r < t->nrow; r++) {
        const char *x = t->cell[r * t->ncol + (size_t)cx], *y = t->cell[r * t->ncol + (size_t)cy];
        if (by >= 0 && strcmp(t->cell[r * t->ncol + (size_t)by], group)) continue;
        if (!is_number(x) || !is_number(y)) continue;
        fprintf(p, "%s %s \"%s\"\n", x, y, t->cell[r * t->ncol]);
        n++;
    }
    fputs("EOD\n", p);
    return n;
}

/* 1 if no earlier row has row r's value in column by (by < 0: one group). */
static int first_of_group(const table *t, int by, size_t r)
{
    if (by < 0) return r == 1;
    for (size_t q = 1; q < r; q++)
        if (!strcmp(t->cell[q * t->ncol + (size_t)by], t->cell[r * t->ncol + (size_t)by])) return 0;
    return 1;
}

static void plot(const options *o, const table *t, const char *out)
{
    int cx = column(t, o->x, o->csv), cy = column(t, o->y, o->csv);
    int by = o->by ? column(t, o->by, o->csv) : -1, k = 0;
    size_t points = 0;
    sl_err err;
    FILE *p = cf_plot_open(&err);
    if (!p) sl_fatal("%s", err.msg);
    if (o->dumb) fputs("set terminal dumb 100 30\n", p);
    else fprintf(p, "set terminal %s size 900,600 noenhanced\nset output '%s'\n",
                 cf_plot_png_terminal(), out);
    fputs("set grid\nset offsets graph 0.05, graph 0.05, graph 0.08, graph 0.05\nset xlabel ", p);
    cf_plot_string(p, o->x);
    fputs("\nset ylabel ", p);
    cf_plot_string(p, o->y);
    char title[512];
    snprintf(title, sizeof title, "%s against %s (%s)", o->y, o->x, o->csv);
    fputs("\nset title ", p);
    cf_plot_string(p, title);
    fprintf(p, "\n%s%s", o->logx ? "set logscale x\n" : "", o->logy ? "set logscale y\n" : "");
    if (by < 0) fputs("set key off\n", p);
    else fputs("set key outside right\n", p);
    /* one data block per series (value of `by`), then one plot command */
    const char **groups = sl_malloc(t->nrow * sizeof *groups, "groups");
    for (size_t r = 1; r < t->nrow; r++) {
        const char *g = by >= 0 ? t->cell[r * t->ncol + (size_t)by] : "";
        if (!first_of_group(t, by, r)) continue;
        size_t n = write_series(p, t, cx, cy, by, g, k);
        groups[k] = g;
        points += n;
        k += n > 0; /* a series without numbers is left out of the plot */
        if (by < 0) break;
    }
    if (points == 0) sl_fatal("%s: no row has numbers in both '%s' and '%s'", o->csv, o->x, o->y);
    fputs("plot ", p);
    for (int i = 0; i < k; i++) {
        char key[256];
        snprintf(key, sizeof key, "%s %s", o->by ? o->by : "", groups[i]);
        fprintf(p, "%s$s%d using 1:2 with points pt 7 ps 1.5 title ", i ? ", " : "", i);
        cf_plot_string(p, key);
        fprintf(p, ", $s%d using 1:2:3 with labels offset 0,1 font ',8' notitle", i);
    }
    fputs("\n", p);
    free((void *)groups);
    if (cf_plot_close(p, &err)) sl_fatal("%s", err.msg);
}

int main(int argc, char **argv)
{
    options o = parse_args(argc, argv);
    table t = read_table(o.csv);
    char *out = o.out ? sl_strdup(o.out) : default_output(&o);
    char *tmp = sl_malloc(strlen(out) + 32, "a path");
    sprintf(tmp, "%s.tmp.%ld.png", out, (long)getpid());
    plot(&o, &t, tmp);
    if (!o.dumb) {
        if (rename(tmp, out) != 0) sl_fatal("cannot write '%s': %s", out, strerror(errno));
        printf("Wrote %s\n", out);
    }
    for (size_t i = 0; i < t.nrow * t.ncol; i++) free(t.cell[i]);
    free(t.cell);
    free(tmp);
    free(out);
    return 0;
}
