/*
 * compareExperiment: a run against measured data.  Reads the water heights
 * and pressures a run's function objects wrote (postProcessing/<name>/
 * <startTime>/<type>.dat) and an experiment's CSV files, pairs their columns as
 * system/compareExperimentDict says (syntax in ce_setup.c), and reports for
 * each pair
 *   heights:   arrival time of the front (first time above a threshold),
 *              RMS, largest and mean error over a window;
 *   pressures: rise time, plateau (time average over a window), peaks
 *              (filtered and raw), RMS error of the filtered signals, and
 *              the peak against an experimental band (percentiles of
 *              repeated runs) where the dictionary names one;
 * in postProcessing/compareExperiment/table.md and table.csv, with one
 * overlay plot per group (<group>.png, through gnuplot), and the means of
 * these over the series in one row, summary.dat (ce_summary.c), for
 * sweepCase.
 *
 *   compareExperiment [-case <dir>] -data <csv> [-data <csv> ...]
 *                     [-dict <file>] [-window t0:t1] [-filter <s>] [-noPlot]
 *
 * A missing file or column stops with a message naming it (exit status 1).
 */
#include "ce.h"

#include "app/app.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct options {
    const char *case_dir, *dict;
    const char **data;
    size_t ndata;
    int have_window, plot;
    double window[2];
    double filter; /* < 0: the dictionary's */
} options;

static const app_option table[] = {
    APP_CASE,
    {.name = "data",
     .kind = APP_PATH,
     .arg = "<csv>",
     .help = "experimental data: '#' comment lines, a header row,\n"
             "comma-separated rows, time in the first column; repeat for\n"
             "several files (a column is taken from the first file that has it)",
     .repeat = 1,
     .glob = "*.csv"},
    {.name = "dict",
     .kind = APP_PATH,
     .help = "the dictionary",
     .def = "<dir>/system/compareExperimentDict"},
    {.name = "window",
     .kind = APP_STRING,
     .arg = "<t0:t1>",
     .help = "the window of errors and peaks, s, for every series\n"
             "(either side may be empty: 0.5:  :1.5)"},
    {.name = "filter",
     .kind = APP_DOUBLE,
     .arg = "<s>",
     .help = "width of the pressure filter (centred moving average), s;\n"
             "0: none",
     .def = "the dictionary's 'filter'",
     .min = 0,
     .max = INFINITY},
    {.name = "noPlot", .help = "write the data and gnuplot scripts, do not run gnuplot"},
    APP_END};

static const app_info info = {
    .name = "compareExperiment",
    .what = "Compares the water heights and pressures a run's function objects wrote\n"
            "(postProcessing/<name>/<startTime>/*.dat) with an experiment's CSV files,\n"
            "column by column as <dir>/system/compareExperimentDict says.  Writes\n"
            "<dir>/postProcessing/compareExperiment/table.md, table.csv, one PNG per\n"
            "group (gnuplot) and summary.dat: one row of means over the series (height\n"
            "RMS and largest error, arrival, plateau and peak errors) for sweepCase's\n"
            "'results'.  A group with 'summary no;' in the dictionary is left out of it\n"
            "(default yes); dictionary syntax: see ce_setup.c or\n"
            "cases/sphericTest2/system/compareExperimentDict.  -data is required.",
    .options = table};

static double window_end(const app *a, const char *s, const char *all)
{
    double x;
    if (app_parse_double(s, &x)) app_error(a, "-window: '%s' is not a number (in '%s')", s, all);
    return x;
}

static void parse_window(const app *a, const char *s, double w[2])
{
    const char *colon = strchr(s, ':');
    if (!colon) app_error(a, "-window: '%s' is not t0:t1", s);
    char *t0 = sl_strdup(s);
    t0[colon - s] = '\0';
    w[0] = *t0 ? window_end(a, t0, s) : -(double)INFINITY;
    w[1] = colon[1] ? window_end(a, colon + 1, s) : (double)INFINITY;
    free(t0);
    if (!(w[1] > w[0])) app_error(a, "-window: '%s' needs t1 > t0", s);
}

static void parse_options(options *o, int argc, char **argv)
{
    app a;
    memset(o, 0, sizeof *o);
    app_parse(&a, &info, argc, argv);
    o->case_dir = app_case(&a);
    o->dict = app_string(&a, "dict", NULL);
    o->plot = !app_found(&a, "noPlot");
    o->filter = app_double(&a, "filter", -1.0);
    o->ndata = app_count(&a, "data");
    o->data = sl_calloc(o->ndata + 1, sizeof *o->data, "options");
    for (size_t i = 0; i < o->ndata; i++) o->data[i] = app_value_at(&a, "data", i);
    if (app_found(&a, "window")) {
        parse_window(&a, app_string(&a, "window", NULL), o->window);
        o->have_window = 1;
    }
    if (o->ndata == 0) app_error(&a, "give the experimental data with -data <csv>");
    app_free(&a);
}

static void make_dir(const char *path)
{
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        sl_fatal("cannot create '%s': %s", path, strerror(errno));
}

/* The experimental columns of entry e (SI units) from the first data file
 * holding e->data; returns 0 (and warns) when no file has it. */
static int load_experiment(ce_result *r, const ce_setup *s, const ce_table *data, size_t ndata)
{
    const ce_entry *e = r->e;
    const double ts = ce_time_scale(s), vs = ce_value_scale(s, r->g->kind);
    for (size_t i = 0; i < ndata; i++) {
        const ce_table *t = &data[i];
        int c = ce_table_column(t, e->data);
        if (c < 0) continue;
        r->data_file = t->path;
        ce_series_from_table(&r->exp, t, c, ts, s->time_shift, vs, NAN, NULL);
        ce_series_clean(&r->exp);
        if (r->exp.n < 2) sl_fatal("%s: column '%s' has fewer than two rows", t->path, e->data);
        if (!e->band[0]) return 1;
        int lo = ce_table_column(t, e->band[0]), hi = ce_table_column(t, e->band[1]);
        if (lo < 0 || hi < 0)
            sl_fatal("%s: series '%s' of group '%s': band column '%s' is not in '%s', which "
                     "holds its data column '%s'",
                     s->path, e->name, r->g->name, lo < 0 ? e->band[0] : e->band[1], t->path,
                     e->data);
        ce_series_from_table(&r->lo_raw, t, lo, ts, s->time_shift, vs, NAN, NULL);
        ce_series_from_table(&r->hi_raw, t, hi, ts, s->time_shift, vs, NAN, NULL);
        ce_series_clean(&r->lo_raw);
        ce_series_clean(&r->hi_raw);
        if (r->lo_raw.n != r->hi_raw.n)
            sl_fatal("%s: band columns '%s' and '%s' have different rows", t->path, e->band[0],
                     e->band[1]);
        return 1;
    }
    sl_warning("%s: series '%s' of group '%s': no data file has a column '%s'; skipped", s->path,
               e->name, r->g->name, e->data);
    return 0;
}

/* Prints a text file to stdout. */
static void show(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) return;
    char buf[4096];
    size_t n;
    fflush(stdout);
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) fwrite(buf, 1, n, stdout);
    fclose(f);
}

int main(int argc, char **argv)
{
    options o;
    parse_options(&o, argc, argv);
    gsl_set_error_handler_off(); /* GSL errors come back as status codes */
    struct stat st;
    if (stat(o.case_dir, &st) != 0 || !S_ISDIR(st.st_mode))
        sl_fatal("no case folder '%s'", o.case_dir);
    char *dict_path =
        o.dict ? sl_strdup(o.dict) : ce_join(o.case_dir, "system/compareExperimentDict");
    if (stat(dict_path, &st) != 0)
        sl_fatal("no dictionary '%s' (it pairs the experiment's columns with the run's; see "
                 "cases/sphericTest2/system/compareExperimentDict)",
                 dict_path);
    ce_setup s;
    ce_setup_read(&s, dict_path);
    free(dict_path);
    if (o.filter >= 0) s.filter = o.filter;

    /* Every file is checked before anything is computed. */
    for (size_t i = 0; i < o.ndata; i++)
        if (stat(o.data[i], &st) != 0 || !S_ISREG(st.st_mode))
            sl_fatal("no experimental data file '%s'", o.data[i]);
    ce_table *data = sl_calloc(o.ndata, sizeof *data, "data files");
    for (size_t i = 0; i < o.ndata; i++) ce_table_read(&data[i], o.data[i], CE_CSV);

    size_t total = 0;
    for (size_t g = 0; g < s.ngrp; g++) total += s.grp[g].n;
    ce_result *res = sl_calloc(total, sizeof *res, "results");
    size_t n = 0;
    for (size_t gi = 0; gi < s.ngrp; gi++) {
        ce_group *g = &s.grp[gi];
        ce_run run;
        ce_run_read(&run, o.case_dir, g->fo);
        for (size_t k = 0; k < g->n; k++) {
            ce_result *r = &res[n];
            r->g = g;
            r->e = &g->e[k];
            if (o.have_window) memcpy(g->e[k].window, o.window, sizeof o.window);
            if (!load_experiment(r, &s, data, o.ndata)) continue;
            ce_run_series(&r->sim, &run, r->e->column, &r->sim_nan);
            ce_result_compute(r, s.filter);
            n++;
        }
        ce_run_free(&run);
    }
    if (n == 0) {
        fprintf(stderr,
                "Error: none of the experimental columns named in %s is in the data "
                "file%s given:",
                s.path, o.ndata > 1 ? "s" : "");
        for (size_t i = 0; i < o.ndata; i++) fprintf(stderr, " %s", o.data[i]);
        fputc('\n', stderr);
        return 1;
    }

    char *pp = ce_join(o.case_dir, "postProcessing");
    char *out = ce_join(pp, "compareExperiment");
    make_dir(pp);
    make_dir(out);
    ce_report_write(out, o.case_dir, &s, o.data, o.ndata, res, n);
    ce_summary sum;
    ce_summary_compute(&sum, res, n);
    ce_summary_write(out, o.case_dir, &s, o.data, o.ndata, res, n, &sum);
    for (size_t gi = 0, first = 0; gi < s.ngrp; gi++) {
        size_t count = 0;
        while (first + count < n && res[first + count].g == &s.grp[gi]) count++;
        ce_plot_group(out, &s.grp[gi], res + first, count, s.filter, o.plot);
        first += count;
    }
    char *md = ce_join(out, "table.md");
    show(md);
    free(md);
    printf("\nSummary (%s/summary.dat; 'summary no' groups left out):\n", out);
    ce_summary_print(stdout, &sum);

    for (size_t i = 0; i < n; i++) ce_result_free(&res[i]);
    for (size_t i = 0; i < o.ndata; i++) ce_table_free(&data[i]);
    free(res);
    free(data);
    free(out);
    free(pp);
    free(o.data);
    ce_setup_free(&s);
    return 0;
}
