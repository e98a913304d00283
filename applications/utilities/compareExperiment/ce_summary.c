/*
 * ce_summary: postProcessing/compareExperiment/summary.dat, the accuracy of
 * a run in one row, so that a parameter sweep can tabulate it per case
 * (sweepDict: results (postProcessing/compareExperiment/summary.dat:
 * heightRms ...), which reads the last row).  The format is an OpenFOAM
 * function-object table: '#' lines defining the columns, the last '#' line
 * naming them (tab-separated), then the row.
 *
 * Every value is a mean (or largest value) over series of the groups whose
 * 'summary' is yes, of numbers table.csv holds for them: a group with a
 * second experimental reference or a second way of probing the same sensors
 * says 'summary no' so that no sensor counts twice.
 */
#include "ce.h"

#include "core/sl_log.h"
#include "io/atomic_file.h"

#include <math.h>
#include <stdlib.h>

/* A running mean and maximum. */
typedef struct acc {
    double sum, max;
    size_t n;
} acc;

static void acc_add(acc *a, double x)
{
    a->sum += x;
    a->max = a->n ? fmax(a->max, x) : x;
    a->n++;
}

static double acc_mean(const acc *a) { return a->n ? a->sum / (double)a->n : (double)NAN; }
static double acc_max(const acc *a) { return a->n ? a->max : (double)NAN; }

/* Above the threshold at the first sample: no arrival to time. */
static int wet_at_start(const ce_series *s, double threshold)
{
    return s->n > 0 && s->v[0] > threshold;
}

/* Which series each mean takes (besides kind and 'summary'). */
static int has_arrival(const ce_result *x)
{
    return isfinite(x->t_sim) && isfinite(x->t_exp) && !wet_at_start(&x->simf, x->e->threshold) &&
        !wet_at_start(&x->expf, x->e->threshold);
}

static int has_height_error(const ce_result *x) { return isfinite(x->err.rms); }

static int has_plateau(const ce_result *x)
{
    return isfinite(x->plateau_sim) && isfinite(x->plateau_exp) && x->plateau_exp != 0.0;
}

static int has_peak(const ce_result *x)
{
    return isfinite(x->peak_sim) && isfinite(x->peak_exp) && x->peak_exp > 0.0;
}

/* Series x of kind enters the mean that pick stands for. */
static int counted(const ce_result *x, ce_kind kind, int (*pick)(const ce_result *))
{
    return x->g->summary && x->g->kind == kind && pick(x);
}

void ce_summary_compute(ce_summary *m, const ce_result *r, size_t n)
{
    acc rms = {0}, max = {0}, arrival = {0}, plateau = {0}, peak = {0};
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        if (counted(x, CE_HEIGHT, has_height_error)) {
            acc_add(&rms, x->err.rms);
            acc_add(&max, x->err.max);
        }
        if (counted(x, CE_HEIGHT, has_arrival)) acc_add(&arrival, fabs(x->t_sim - x->t_exp));
        if (counted(x, CE_PRESSURE, has_plateau))
            acc_add(&plateau, fabs(x->plateau_sim - x->plateau_exp) / fabs(x->plateau_exp));
        if (counted(x, CE_PRESSURE, has_peak))
            acc_add(&peak, fabs(x->peak_sim - x->peak_exp) / x->peak_exp);
    }
    m->height_rms = acc_mean(&rms);
    m->height_max = acc_max(&max);
    m->arrival = acc_mean(&arrival);
    m->arrival_max = acc_max(&arrival);
    m->plateau = acc_mean(&plateau);
    m->peak = acc_mean(&peak);
    m->nheight = rms.n;
    m->npressure = peak.n;
}

static void value(FILE *f, double x)
{
    if (isfinite(x)) fprintf(f, "%.10g\t", x);
    else fputs("nan\t", f);
}

void ce_summary_print(FILE *f, const ce_summary *m)
{
    fputs("# heightRms\theightMaxAbs\tarrivalError\tarrivalErrorMax\tplateauError\tpeakError\t"
          "nHeights\tnPressures\n",
          f);
    value(f, m->height_rms);
    value(f, m->height_max);
    value(f, m->arrival);
    value(f, m->arrival_max);
    value(f, m->plateau);
    value(f, m->peak);
    fprintf(f, "%zu\t%zu\n", m->nheight, m->npressure);
}

/* The interval listed with a series: none, its window, its plateau. */
typedef enum { SPAN_NONE, SPAN_WINDOW, SPAN_PLATEAU } span;

static const double *span_of(const ce_result *x, span sp)
{
    return sp == SPAN_WINDOW ? x->window : x->e->plateau;
}

/* "# <what>: group/series, ... (<span> a-b s)" for the series of kind that
 * take part (pick(x)), the interval after each series when they differ;
 * "none" if no series takes part. */
static void list_series(FILE *f, const char *what, const ce_result *r, size_t n, ce_kind kind,
                        int (*pick)(const ce_result *), span sp)
{
    const char *label = sp == SPAN_WINDOW ? "window" : "plateau";
    const ce_result *first = NULL;
    int same = 1;
    for (size_t i = 0; i < n && sp != SPAN_NONE; i++) {
        if (!counted(&r[i], kind, pick)) continue;
        if (!first) first = &r[i];
        const double *a = span_of(&r[i], sp), *b = span_of(first, sp);
        same &= a[0] == b[0] && a[1] == b[1];
    }
    size_t k = 0;
    fprintf(f, "# %s:", what);
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        if (!counted(x, kind, pick)) continue;
        fprintf(f, "%s %s/%s", k++ ? "," : "", x->g->name, x->e->name);
        if (sp != SPAN_NONE && !same)
            fprintf(f, " (%s %g-%g s)", label, span_of(x, sp)[0], span_of(x, sp)[1]);
    }
    if (k == 0) fputs(" none", f);
    else if (sp != SPAN_NONE && same)
        fprintf(f, " (%s %g-%g s)", label, span_of(first, sp)[0], span_of(first, sp)[1]);
    fputc('\n', f);
}

static void write_comments(FILE *f, const char *case_dir, const ce_setup *s,
                           const char *const *data_files, size_t ndata, const ce_result *r,
                           size_t n)
{
    fprintf(f, "# compareExperiment summary: %s against", case_dir);
    for (size_t i = 0; i < ndata; i++) fprintf(f, " %s", data_files[i]);
    fprintf(f, " (%s); the numbers are table.csv's.\n", s->path);
    fputs("# e = simulation - experiment at the experiment's sample times inside each "
          "series' window (cut to the times both cover).\n"
          "# heightRms: mean over the height series of each series' RMS error (rms_error), m; "
          "heights unfiltered.\n"
          "# heightMaxAbs: largest max |e| (max_error) over the height series, m.\n"
          "# arrivalError, arrivalErrorMax: mean and largest |arrival sim - arrival exp| "
          "(arrival_diff) over the height series where both arrive, gauges wet at their first "
          "sample excluded, s.\n"
          "# plateauError: mean over the pressure series with a plateau of |plateau sim - "
          "plateau exp| / |plateau exp| (time averages of the unfiltered pressure), fraction.\n",
          f);
    if (s->filter > 0)
        fprintf(f,
                "# peakError: mean over the pressure series of |peak sim - peak exp| / peak "
                "exp, peaks over the window of the pressures filtered by a centred moving "
                "average of %g s (peak_filtered_*), fraction.\n",
                s->filter);
    else
        fputs("# peakError: mean over the pressure series of |peak sim - peak exp| / peak exp, "
              "peaks over the window of the unfiltered pressures (filter 0), fraction.\n",
              f);
    fputs("# nHeights, nPressures: the number of series in heightRms and in peakError.  nan: "
          "no series for that mean.\n",
          f);
    list_series(f, "height series", r, n, CE_HEIGHT, has_height_error, SPAN_WINDOW);
    list_series(f, "arrivals of", r, n, CE_HEIGHT, has_arrival, SPAN_NONE);
    list_series(f, "pressure series (peaks)", r, n, CE_PRESSURE, has_peak, SPAN_WINDOW);
    list_series(f, "plateaus of", r, n, CE_PRESSURE, has_plateau, SPAN_PLATEAU);
    size_t k = 0;
    fputs("# groups not counted (summary no):", f);
    for (size_t g = 0; g < s->ngrp; g++)
        if (!s->grp[g].summary) fprintf(f, "%s %s", k++ ? "," : "", s->grp[g].name);
    fputs(k ? "\n" : " none\n", f);
}

void ce_summary_write(const char *dir, const char *case_dir, const ce_setup *s,
                      const char *const *data_files, size_t ndata, const ce_result *r, size_t n,
                      const ce_summary *m)
{
    char *path = ce_join(dir, "summary.dat");
    sl_err err;
    afile a;
    FILE *f = afile_open(&a, path, &err);
    if (!f) sl_fatal("%s", err.msg);
    write_comments(f, case_dir, s, data_files, ndata, r, n);
    ce_summary_print(f, m);
    if (afile_commit(&a, &err)) sl_fatal("%s", err.msg);
    sl_info("Wrote %s", path);
    free(path);
}
