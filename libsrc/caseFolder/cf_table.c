/*
 * cf_table: reads OpenFOAM function-object tables (timeStep.dat and the
 * like): '#' comment lines, the last of them naming the columns ("# Time
 * deltaT ..."), then rows of numbers separated by tabs or spaces.  Values
 * OpenFOAM writes as "(1 2 3)" are split into their numbers, as gnuplot
 * users strip them; the header then has fewer names than numbers and the
 * extra columns are called "colN".
 *
 * cf_table_read_as also reads CSV files (compareExperiment's experimental
 * data: '#' lines, a header row, comma-separated rows, quotes stripped) and,
 * strict, refuses rows whose field count differs from the header's.
 */
#include "caseFolder/caseFolder.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

/* Splits line in place at tabs, spaces and brackets; returns the count. */
static size_t cf_split(char *line, char ***words, size_t *cap)
{
    size_t n = 0;
    for (char *tok = strtok(line, " \t\r\n()"); tok; tok = strtok(NULL, " \t\r\n()")) {
        if (n == *cap) {
            *cap = *cap ? 2 * *cap : 16;
            *words = sl_realloc(*words, *cap * sizeof **words, "a table row");
        }
        (*words)[n++] = tok;
    }
    return n;
}

static void cf_table_set_header(cf_table *t, char **words, size_t n)
{
    for (size_t i = 0; i < t->ncol; i++) free(t->name[i]);
    free(t->name);
    t->ncol = n;
    t->name = sl_malloc((n ? n : 1) * sizeof *t->name, "column names");
    for (size_t i = 0; i < n; i++) t->name[i] = sl_strdup(words[i]);
}

static void cf_table_widen(cf_table *t, size_t ncol, size_t *cap)
{
    char name[32];
    double *v;
    if (ncol <= t->ncol) return;
    t->name = sl_realloc(t->name, ncol * sizeof *t->name, "column names");
    for (size_t i = t->ncol; i < ncol; i++) {
        snprintf(name, sizeof name, "col%zu", i + 1);
        t->name[i] = sl_strdup(name);
    }
    v = sl_malloc((*cap ? *cap : 1) * ncol * sizeof *v, "a table");
    for (size_t r = 0; r < t->nrow; r++)
        for (size_t c = 0; c < ncol; c++)
            v[r * ncol + c] = c < t->ncol ? t->v[r * t->ncol + c] : (double)NAN;
    free(t->v);
    t->v = v;
    t->ncol = ncol;
}

static void cf_table_add_row(cf_table *t, char **words, size_t n, size_t *cap)
{
    cf_table_widen(t, n, cap);
    if (t->nrow == *cap) {
        *cap = *cap ? 2 * *cap : 256;
        t->v = sl_realloc(t->v, *cap * t->ncol * sizeof *t->v, "a table");
    }
    for (size_t c = 0; c < t->ncol; c++) {
        char *end = NULL;
        double x = c < n ? strtod(words[c], &end) : (double)NAN;
        t->v[t->nrow * t->ncol + c] = c < n && end != words[c] && !*end ? x : (double)NAN;
    }
    t->nrow++;
}

/* Splits a CSV line in place at commas, tabs and spaces (runs of blanks are
 * one separator; a comma always separates, so ",," gives an empty field);
 * surrounding double quotes of a field are removed. */
static size_t cf_split_csv(char *line, char ***f, size_t *cap)
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
        if (c == ',') p++;
        else if (!c || c == '\n' || c == '\r') break;
    }
    return n;
}

/* One line (not blank); nonzero with err filled when strict refuses it. */
static int cf_table_line(cf_table *t, char *s, cf_table_format fmt, int strict, char ***words,
                         size_t *wcap, size_t *cap, int *header, const char *where, sl_err *err)
{
    size_t (*split)(char *, char ***, size_t *) = fmt == CF_TABLE_CSV ? cf_split_csv : cf_split;
    if (*s == '#') {
        if (fmt == CF_TABLE_DAT && t->nrow == 0) { /* the last comment before the data */
            size_t n = split(s + 1, words, wcap);
            if (n) cf_table_set_header(t, *words, n);
            *header |= n > 0;
        }
        return 0;
    }
    size_t n = split(s, words, wcap);
    if (!n) return 0;
    if (!*header && fmt == CF_TABLE_CSV) {
        cf_table_set_header(t, *words, n);
        *header = 1;
        return 0;
    }
    if (strict && !*header) {
        sl_err_set(err, "%s: data before a '#' line naming the columns", where);
        return 1;
    }
    if (strict && n != t->ncol) {
        sl_err_set(err, "%s: %zu fields where the header names %zu columns", where, n, t->ncol);
        return 1;
    }
    cf_table_add_row(t, *words, n, cap);
    return 0;
}

int cf_table_read_as(const char *path, cf_table_format fmt, int strict, cf_table *t, sl_err *err)
{
    FILE *f = fopen(path, "r");
    char *line = NULL, **words = NULL, where[4200];
    size_t len = 0, cap = 0, wcap = 0;
    long lineno = 0;
    int header = 0, bad = 0;
    memset(t, 0, sizeof *t);
    if (!f) {
        sl_err_set(err, "cannot open '%s': %s", path, strerror(errno));
        return 1;
    }
    while (!bad && getline(&line, &len, f) >= 0) {
        char *s = line;
        snprintf(where, sizeof where, "%s:%ld", path, ++lineno);
        while (isspace((unsigned char)*s)) s++;
        if (*s) bad = cf_table_line(t, s, fmt, strict, &words, &wcap, &cap, &header, where, err);
    }
    if (!bad && ferror(f)) {
        sl_err_set(err, "cannot read '%s': %s", path, strerror(errno));
        bad = 1;
    }
    free(line);
    free(words);
    fclose(f);
    if (!t->name) cf_table_set_header(t, NULL, 0);
    if (bad) cf_table_free(t);
    return bad;
}

int cf_table_read(const char *path, cf_table *t, sl_err *err)
{
    return cf_table_read_as(path, CF_TABLE_DAT, 0, t, err);
}

void cf_table_free(cf_table *t)
{
    for (size_t i = 0; i < t->ncol; i++) free(t->name[i]);
    free(t->name);
    free(t->v);
    memset(t, 0, sizeof *t);
}

int cf_table_column(const cf_table *t, const char *name)
{
    char *end;
    long k;
    for (size_t i = 0; i < t->ncol; i++)
        if (!strcmp(t->name[i], name)) return (int)i;
    k = strtol(name, &end, 10);
    return *name && !*end && k >= 1 && (size_t)k <= t->ncol ? (int)(k - 1) : -1;
}

char *cf_table_names(const cf_table *t)
{
    size_t n = 1;
    char *s;
    for (size_t i = 0; i < t->ncol; i++) n += strlen(t->name[i]) + 2;
    s = sl_malloc(n, "column names");
    s[0] = '\0';
    for (size_t i = 0; i < t->ncol; i++) {
        if (i) strcat(s, ", ");
        strcat(s, t->name[i]);
    }
    return s;
}
