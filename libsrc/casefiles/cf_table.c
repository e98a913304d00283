/*
 * cf_table: reads OpenFOAM function-object tables (timeStep.dat and the
 * like): '#' comment lines, the last of them naming the columns ("# Time
 * deltaT ..."), then rows of numbers separated by tabs or spaces.  Values
 * OpenFOAM writes as "(1 2 3)" are split into their numbers, as gnuplot
 * users strip them; the header then has fewer names than numbers and the
 * extra columns are called "colN".
 */
#include "casefiles/casefiles.h"

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

int cf_table_read(const char *path, cf_table *t, sl_err *err)
{
    FILE *f = fopen(path, "r");
    char *line = NULL, **words = NULL;
    size_t len = 0, cap = 0, wcap = 0;
    ssize_t got;
    memset(t, 0, sizeof *t);
    if (!f) {
        sl_err_set(err, "cannot open '%s': %s", path, strerror(errno));
        return 1;
    }
    while ((got = getline(&line, &len, f)) >= 0) {
        char *s = line;
        while (isspace((unsigned char)*s)) s++;
        if (*s == '#') {
            if (t->nrow == 0) { /* the last comment before the data names the columns */
                size_t n = cf_split(s + 1, &words, &wcap);
                if (n) cf_table_set_header(t, words, n);
            }
        } else if (*s) {
            size_t n = cf_split(s, &words, &wcap);
            if (n) cf_table_add_row(t, words, n, &cap);
        }
    }
    free(line);
    free(words);
    fclose(f);
    if (!t->name) cf_table_set_header(t, NULL, 0);
    return 0;
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
