/*
 * ce_table: the two kinds of table compareExperiment reads, and series
 * taken from them (see ce.h).  Experimental CSV files: '#' lines (source,
 * geometry, normalisation), then a header row, then comma-separated rows.
 * Function-object files: '#' lines whose last names the columns, then
 * tab-separated rows with "nan" where a value does not exist.  Both are
 * read by caseFolder' cf_table_read_as (strict: a ragged row is an error);
 * this adds the path and the checks that compareExperiment needs.
 */
#include "ce.h"

#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ce_table_read(ce_table *t, const char *path, ce_format format)
{
    cf_table c;
    sl_err err;
    if (cf_table_read_as(path, format == CE_CSV ? CF_TABLE_CSV : CF_TABLE_DAT, 1, &c, &err))
        sl_fatal("%s", err.msg);
    if (c.ncol < 2)
        sl_fatal("'%s' names no columns (need a time column and at least one value column)", path);
    if (c.nrow == 0) sl_fatal("'%s' holds no data row", path);
    memset(t, 0, sizeof *t);
    t->ncol = c.ncol;
    t->nrow = c.nrow;
    t->name = c.name; /* the table's arrays are ours now */
    t->v = c.v;
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
