/*
 * sweep_table: one row per point -- its parameter values, its status, and
 * what its per-step record postProcessing/timeStep/<startTime>/timeStep.dat
 * says (steps = rows, wall time = sum of wallTime, mean of iterations, max
 * of rhoErrAvg and rhoErrMax, sum of shock) plus the last value of any
 * named function-object column -- written as <dir>/results.csv and
 * <dir>/results.md.
 */
#include "sweep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "io/atomic_file.h"

/* Columns computed from the per-step record, in table order. */
enum { R_WALL, R_STEPS, R_ITER, R_AVG, R_MAX, R_SHOCK, R_MEAN_AVG, R_VOL, R_N };
static const char *const record_label[R_N] = {"wallTime",      "steps",        "meanIterations",
                                              "maxRhoErrAvg",  "maxRhoErrMax", "shocks",
                                              "meanRhoErrAvg", "maxVolErrAvg"};

typedef struct sweep_row {
    sweep_status status;
    double v[R_N];
    double *extra; /* one per sweep_result */
} sweep_row;

static const char *status_name(sweep_status st)
{
    return st == SWEEP_FINISHED ? "finished"
        : st == SWEEP_FAILED    ? "failed"
        : st == SWEEP_STOPPED   ? "stopped"
                                : "not run";
}

/* Sum, mean or max of one column (NaN if the record lacks it). */
static double column_reduce(const cf_table *t, const char *name, char how)
{
    int c = cf_table_column(t, name);
    double acc = how == 'M' ? -(double)INFINITY : 0.0;
    if (c < 0 || t->nrow == 0) return NAN;
    for (size_t r = 0; r < t->nrow; r++) {
        double x = t->v[r * t->ncol + (size_t)c];
        if (how == 'M') acc = x > acc ? x : acc;
        else acc += x;
    }
    return how == 'm' ? acc / (double)t->nrow : acc;
}

static void read_record(const char *dir, sweep_row *row)
{
    sl_err err;
    cf_table t;
    if (cf_record_read(dir, &t, NULL, NULL, &err)) return; /* every session of the case */
    row->v[R_STEPS] = (double)t.nrow;
    row->v[R_WALL] = column_reduce(&t, "wallTime", 's');
    row->v[R_ITER] = column_reduce(&t, "iterations", 'm');
    row->v[R_AVG] = column_reduce(&t, "rhoErrAvg", 'M');
    row->v[R_MAX] = column_reduce(&t, "rhoErrMax", 'M');
    row->v[R_SHOCK] = column_reduce(&t, "shock", 's');
    row->v[R_MEAN_AVG] = column_reduce(&t, "rhoErrAvg", 'm');
    row->v[R_VOL] = column_reduce(&t, "volErrAvg", 'M');
    cf_table_free(&t);
}

/* The last row's value of a function-object column; NaN with a warning. */
static double read_extra(const char *dir, const char *name, const sweep_result *r)
{
    char *path = cf_join(dir, r->file);
    sl_err err;
    cf_table t;
    double v = NAN;
    if (cf_table_read(path, &t, &err) == 0) {
        int c = cf_table_column(&t, r->column);
        if (c >= 0 && t.nrow) v = t.v[(t.nrow - 1) * t.ncol + (size_t)c];
        else if (c < 0) {
            char *names = cf_table_names(&t);
            sl_warning("%s: no column '%s' in %s (columns: %s)", name, r->column, path, names);
            free(names);
        }
        cf_table_free(&t);
    } else {
        sl_warning("%s: %s", name, err.msg);
    }
    free(path);
    return v;
}

static sweep_row *collect_rows(const sweep *s)
{
    sweep_row *rows = sl_calloc(s->npoint, sizeof *rows, "sweep rows");
    for (size_t i = 0; i < s->npoint; i++) {
        char *dir = sweep_case_dir(s, i);
        sweep_row *row = &rows[i];
        for (int k = 0; k < R_N; k++) row->v[k] = NAN;
        row->extra = sl_malloc((s->nresult + 1) * sizeof *row->extra, "sweep results");
        row->status = sweep_case_status(s, i);
        int ran = row->status != SWEEP_NOT_RUN; /* it has a log */
        if (ran) read_record(dir, row);
        for (size_t k = 0; k < s->nresult; k++)
            row->extra[k] = ran ? read_extra(dir, s->name[i], &s->result[k]) : (double)NAN;
        free(dir);
    }
    return rows;
}

/* ---- writing ------------------------------------------------------------------------- */

static void put_number(FILE *f, double x, const char *missing)
{
    if (isnan(x)) fputs(missing, f);
    else fprintf(f, "%.6g", x);
}

/* A CSV field, quoted when it holds a comma, quote or space. */
static void put_csv(FILE *f, const char *s)
{
    if (!strpbrk(s, ",\" \t\n")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"') fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

/* A Markdown cell ('|' escaped). */
static void put_md(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '|') fputc('\\', f);
        fputc(*s, f);
    }
}

/* One table in Markdown (md) or CSV: a header, then one row per point. */
static void write_table(FILE *f, const sweep *s, const sweep_row *rows, int md)
{
    const char *sep = md ? " | " : ",", *missing = md ? "-" : "";
    void (*put)(FILE *, const char *) = md ? put_md : put_csv;
    fputs(md ? "| case" : "case", f);
    for (size_t k = 0; k < s->nparam; k++) {
        fputs(sep, f);
        put(f, s->param[k].label);
    }
    fprintf(f, "%sstatus", sep);
    for (int k = 0; k < R_N; k++) fprintf(f, "%s%s", sep, record_label[k]);
    for (size_t k = 0; k < s->nresult; k++) {
        fputs(sep, f);
        put(f, s->result[k].label);
    }
    fputs(md ? " |\n" : "\n", f);
    if (md) {
        for (size_t k = 0; k < 2 + s->nparam + R_N + s->nresult; k++) fputs("|---", f);
        fputs("|\n", f);
    }
    for (size_t i = 0; i < s->npoint; i++) {
        fputs(md ? "| " : "", f);
        put(f, s->name[i]);
        for (size_t k = 0; k < s->nparam; k++) {
            fputs(sep, f);
            put(f, sweep_value(s, i, k));
        }
        fprintf(f, "%s%s", sep, status_name(rows[i].status));
        for (int k = 0; k < R_N; k++) {
            fputs(sep, f);
            put_number(f, rows[i].v[k], missing);
        }
        for (size_t k = 0; k < s->nresult; k++) {
            fputs(sep, f);
            put_number(f, rows[i].extra[k], missing);
        }
        fputs(md ? " |\n" : "\n", f);
    }
}

static void write_file(const sweep *s, const sweep_row *rows, const char *name, int md)
{
    char *path = cf_join(s->dir, name);
    sl_err err;
    afile a;
    FILE *f = afile_open(&a, path, &err);
    if (!f) sl_fatal("%s", err.msg);
    write_table(f, s, rows, md);
    if (afile_commit(&a, &err)) sl_fatal("%s", err.msg);
    free(path);
}

void sweep_collect(const sweep *s)
{
    sweep_row *rows = collect_rows(s);
    size_t finished = 0;
    write_file(s, rows, "results.csv", 0);
    write_file(s, rows, "results.md", 1);
    write_table(stdout, s, rows, 1);
    for (size_t i = 0; i < s->npoint; i++) finished += rows[i].status == SWEEP_FINISHED;
    printf("\n%zu of %zu points finished; table in %s/results.csv and results.md\n", finished,
           s->npoint, s->dir);
    for (size_t i = 0; i < s->npoint; i++) free(rows[i].extra);
    free(rows);
}
