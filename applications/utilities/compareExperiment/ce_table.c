/*
 * ce_table: the two kinds of table compareExperiment reads, and series
 * taken from them (see ce.h).  Experimental CSV files: '#' lines (source,
 * geometry, normalisation), then a header row, then comma-separated rows.
 * Function-object files: '#' lines whose last names the columns, then
 * tab-separated rows with "nan" where a value does not exist.
 */
#include "ce.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Splits line in place at commas, tabs and spaces (runs of blanks are one
 * separator; a comma always separates, so ",," gives an empty field).
 * Surrounding double quotes of a field are removed. */
static size_t split(char *line, char ***f, size_t *cap)
{
    size_t n = 0;
    char *p = line;
    for (;;) {
        while (*p == ' ' || *p == '\t') p++;
        if (!*p || *p == '\n' || *p == '\r') break;
        char *start = p;
        while (*p && !strchr(",\t \r\n", *p)) p++;
        char *end = p;
        while (*p == ' ' || *p == '\t') p++;
        int comma = *p == ',';
        char c = *p;
        *end = '\0';
        if (end - start >= 2 && *start == '"' && end[-1] == '"') {
            start++;
            end[-1] = '\0';
        }
        if (n == *cap) {
            *cap = *cap ? 2 * *cap : 32;
            *f = sl_realloc(*f, *cap * sizeof **f, "table fields");
        }
        (*f)[n++] = start;
        if (comma) p++;
        else if (!c || c == '\n' || c == '\r') break;
    }
    return n;
}

static void set_header(ce_table *t, char **f, size_t n)
{
    for (size_t i = 0; i < t->ncol; i++) free(t->name[i]);
    free(t->name);
    t->ncol = n;
    t->name = sl_malloc((n ? n : 1) * sizeof *t->name, "column names");
    for (size_t i = 0; i < n; i++) t->name[i] = sl_strdup(f[i]);
}

static void add_row(ce_table *t, char **f, size_t n, size_t *cap)
{
    if (t->nrow == *cap) {
        *cap = *cap ? 2 * *cap : 1024;
        t->v = sl_realloc(t->v, *cap * t->ncol * sizeof *t->v, "table rows");
    }
    double *row = t->v + t->nrow * t->ncol;
    for (size_t c = 0; c < t->ncol; c++) {
        char *end = NULL;
        double x = c < n ? strtod(f[c], &end) : (double)NAN;
        row[c] = c < n && end != f[c] && !*end ? x : (double)NAN;
    }
    t->nrow++;
}

void ce_table_read(ce_table *t, const char *path, ce_format format)
{
    memset(t, 0, sizeof *t);
    FILE *fp = fopen(path, "r");
    if (!fp) sl_fatal("cannot read '%s': %s", path, strerror(errno));
    char *line = NULL, **f = NULL;
    size_t len = 0, fcap = 0, cap = 0;
    int have_header = 0;
    long lineno = 0;
    while (getline(&line, &len, fp) >= 0) {
        lineno++;
        char *s = line;
        while (isspace((unsigned char)*s)) s++;
        if (!*s) continue;
        if (*s == '#') {
            if (format == CE_DAT && t->nrow == 0) {
                size_t n = split(s + 1, &f, &fcap);
                if (n) {
                    set_header(t, f, n);
                    have_header = 1;
                }
            }
            continue;
        }
        size_t n = split(s, &f, &fcap);
        if (!have_header) {
            if (format == CE_DAT)
                sl_fatal("%s:%ld: data before a '#' line naming the columns", path, lineno);
            set_header(t, f, n);
            have_header = 1;
            continue;
        }
        if (n != t->ncol)
            sl_fatal("%s:%ld: %zu fields where the header names %zu columns", path, lineno, n,
                     t->ncol);
        add_row(t, f, n, &cap);
    }
    int bad = ferror(fp);
    fclose(fp);
    free(line);
    free(f);
    if (bad) sl_fatal("cannot read '%s': %s", path, strerror(errno));
    if (!have_header || t->ncol < 2)
        sl_fatal("'%s' names no columns (need a time column and at least one value column)",
                 path);
    if (t->nrow == 0) sl_fatal("'%s' holds no data row", path);
    t->path = sl_strdup(path);
}

void ce_table_free(ce_table *t)
{
    for (size_t i = 0; i < t->ncol; i++) free(t->name[i]);
    free(t->name);
    free(t->v);
    free(t->path);
    memset(t, 0, sizeof *t);
}

int ce_table_column(const ce_table *t, const char *name)
{
    for (size_t i = 0; i < t->ncol; i++)
        if (!strcmp(t->name[i], name)) return (int)i;
    return -1;
}

/* ---- series ------------------------------------------------------------------ */

void ce_series_from_table(ce_series *s, const ce_table *t, int col, double tscale, double tshift,
                          double vscale, double nan_as, size_t *nan_count)
{
    s->t = sl_malloc(t->nrow * sizeof *s->t, "series");
    s->v = sl_malloc(t->nrow * sizeof *s->v, "series");
    s->n = 0;
    size_t nans = 0;
    for (size_t r = 0; r < t->nrow; r++) {
        const double *row = t->v + r * t->ncol;
        if (!isfinite(row[0])) continue;
        double v = row[col];
        if (!isfinite(v)) {
            nans++;
            if (isnan(nan_as)) continue;
            v = nan_as;
        } else {
            v *= vscale;
        }
        s->t[s->n] = row[0] * tscale + tshift;
        s->v[s->n] = v;
        s->n++;
    }
    if (nan_count) *nan_count = nans;
}

void ce_series_clean(ce_series *s)
{
    size_t k = 0;
    for (size_t i = 0; i < s->n; i++) {
        while (k > 0 && !(s->t[i] > s->t[k - 1])) k--;
        s->t[k] = s->t[i];
        s->v[k] = s->v[i];
        k++;
    }
    s->n = k;
}

void ce_series_copy(ce_series *dst, const ce_series *src)
{
    size_t n = src->n ? src->n : 1;
    dst->n = src->n;
    dst->t = sl_malloc(n * sizeof *dst->t, "series");
    dst->v = sl_malloc(n * sizeof *dst->v, "series");
    if (src->n) {
        memcpy(dst->t, src->t, src->n * sizeof *dst->t);
        memcpy(dst->v, src->v, src->n * sizeof *dst->v);
    }
}

void ce_series_free(ce_series *s)
{
    free(s->t);
    free(s->v);
    memset(s, 0, sizeof *s);
}

char *ce_join(const char *a, const char *b)
{
    size_t n = strlen(a) + strlen(b) + 2;
    char *s = sl_malloc(n, "path");
    snprintf(s, n, "%s/%s", a, b);
    return s;
}
