/*
 * fo_density_error: statistics of the density error of the fluid particles,
 * in percent of rho0, from the densities the solver holds (after a step the
 * last PCISPH prediction, which the solver's own statistics measure; at a
 * write time the density recomputed from the written positions, which is
 * the `density` of fluid.vtu).
 *
 * Two definitions, both in the header of the file:
 *   compression  max(rho - rho0, 0) / rho0   (the solver's measure, as in
 *                timeStep.dat: average, maximum, percentiles)
 *   signed       (rho - rho0) / rho0        (average, minimum, maximum;
 *                negative at the free surface, whose particles lack
 *                neighbours)
 * Percentiles use GSL (gsl_sort, gsl_stats_quantile_from_sorted_data:
 * linear interpolation between order statistics).  With `histogram on`
 * every write time also gets histogram_<time>.dat of the signed error
 * (gsl_histogram), over histogramRange or, by default, the data's range.
 *
 *   type densityError; percentiles (50 90 99); histogram off;
 *   histogramBins 50; histogramRange (-5 5);  // optional, percent
 */
#include "functionObjects/fo_type.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <gsl/gsl_histogram.h>
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DE_DEFAULT_BINS 50

static const char *const de_keys[] = {"percentiles", "histogram", "histogramBins", "histogramRange",
                                      NULL};

typedef struct de_state {
    double *pct; /* percentiles, 0..100 */
    size_t npct;
    int histogram;
    int fixed_range;
    double range[2];
    gsl_histogram *hist;
    double *buf; /* scratch: compression of every particle, sorted */
    size_t cap;
    char *path; /* histogram file path (sized on first use) */
    size_t path_cap;
} de_state;

static void *de_read(const dict *d)
{
    static const double def_pct[] = {50, 90, 99};
    de_state *st = sl_calloc(1, sizeof *st, "densityError");
    sl_err err;
    long bins;
    if (dict_has(d, "percentiles")) {
        fo_need(dict_get_scalar_list(d, "percentiles", &st->pct, &st->npct, &err), &err);
        for (size_t i = 0; i < st->npct; i++)
            if (!(st->pct[i] >= 0.0 && st->pct[i] <= 100.0))
                fo_bad_key(d, "percentiles", "every percentile must be between 0 and 100");
    } else {
        st->npct = sizeof def_pct / sizeof *def_pct;
        st->pct = sl_malloc(sizeof def_pct, "percentiles");
        memcpy(st->pct, def_pct, sizeof def_pct);
    }
    fo_need(dict_get_bool_or(d, "histogram", 0, &st->histogram, &err), &err);
    fo_need(dict_get_int_or(d, "histogramBins", DE_DEFAULT_BINS, &bins, &err), &err);
    if (bins < 1 || bins > 1000000) fo_bad_key(d, "histogramBins", "must be between 1 and 1000000");
    if (dict_has(d, "histogramRange")) {
        double *r;
        size_t n;
        fo_need(dict_get_scalar_list(d, "histogramRange", &r, &n, &err), &err);
        if (n != 2 || !(r[1] > r[0])) {
            free(r);
            fo_bad_key(d, "histogramRange", "must be (min max) with max > min, in percent of rho0");
        }
        st->fixed_range = 1;
        st->range[0] = r[0];
        st->range[1] = r[1];
        free(r);
    }
    if (st->histogram) {
        st->hist = gsl_histogram_alloc((size_t)bins);
        if (!st->hist) sl_fatal("out of memory for a histogram of %ld bins", bins);
    }
    return st;
}

static void de_header(const void *vs, const pcs_view *s, FILE *f)
{
    (void)vs;
    fprintf(f,
            "# Density error of the fluid particles in percent of rho0 = %g kg/m^3\n"
            "# average, maximum, pNN: compression max(rho - rho0, 0) / rho0 (the solver's "
            "measure, as in timeStep.dat); pNN: NN-th percentile\n"
            "# averageSigned, minimumSigned, maximumSigned: signed (rho - rho0) / rho0\n",
            s->rho0);
}

static void de_columns(const void *vs, FILE *f)
{
    const de_state *st = vs;
    fputs("\taverage\tmaximum\taverageSigned\tminimumSigned\tmaximumSigned", f);
    for (size_t i = 0; i < st->npct; i++) fprintf(f, "\tp%g", st->pct[i]);
}

static void de_reserve(de_state *st, size_t n)
{
    if (n <= st->cap) return;
    free(st->buf);
    st->cap = n + n / 8;
    st->buf = sl_malloc(st->cap * sizeof *st->buf, "density error scratch");
}

static void de_execute(void *vs, const fo_call *call)
{
    de_state *st = vs;
    const sl_fluid *f = call->s->f;
    const double rho0 = call->s->rho0, scale = 100.0 / rho0;
    const size_t n = f->n;
    double max_c = -INFINITY, sum_s = 0.0, min_s = INFINITY, max_s = -INFINITY;
    de_reserve(st, n);
    for (size_t i = 0; i < n; i++) {
        double e = (f->rho[i] - rho0) * scale, c = e > 0.0 ? e : 0.0;
        sum_s += e;
        if (e < min_s) min_s = e;
        if (e > max_s) max_s = e;
        if (c > max_c) max_c = c;
        st->buf[i] = c;
    }
    if (n == 0) {
        for (size_t k = 0; k < 5 + st->npct; k++) fo_put(call->dat, NAN);
        return;
    }
    fo_put(call->dat, gsl_stats_mean(st->buf, 1, n));
    fo_put(call->dat, max_c);
    fo_put(call->dat, sum_s / (double)n);
    fo_put(call->dat, min_s);
    fo_put(call->dat, max_s);
    if (!st->npct) return;
    gsl_sort(st->buf, 1, n);
    for (size_t k = 0; k < st->npct; k++)
        fo_put(call->dat, gsl_stats_quantile_from_sorted_data(st->buf, 1, n, st->pct[k] / 100.0));
}

static void de_write_histogram(de_state *st, const fo_call *call)
{
    const sl_fluid *f = call->s->f;
    const double rho0 = call->s->rho0, scale = 100.0 / rho0;
    double lo = st->range[0], hi = st->range[1];
    size_t below = 0, above = 0;
    if (!st->fixed_range) {
        lo = INFINITY;
        hi = -INFINITY;
        for (size_t i = 0; i < f->n; i++) {
            double e = (f->rho[i] - rho0) * scale;
            if (e < lo) lo = e;
            if (e > hi) hi = e;
        }
        if (!(hi > lo)) { /* no particle, or all alike: a unit-wide range around them */
            double mid = f->n && isfinite(lo) ? lo : 0.0;
            lo = mid - 0.5;
            hi = mid + 0.5;
        }
        hi = nextafter(hi, INFINITY); /* bins are [lo, hi): keep the maximum */
    }
    gsl_histogram_set_ranges_uniform(st->hist, lo, hi);
    for (size_t i = 0; i < f->n; i++) {
        double e = (f->rho[i] - rho0) * scale;
        if (e < lo) below++;
        else if (e >= hi) above++;
        else gsl_histogram_increment(st->hist, e);
    }
    size_t need = strlen(call->dir) + strlen(call->time_name) + 32;
    if (need > st->path_cap) {
        free(st->path);
        st->path_cap = need + 64;
        st->path = sl_malloc(st->path_cap, "path");
    }
    snprintf(st->path, st->path_cap, "%s/histogram_%s.dat", call->dir, call->time_name);
    FILE *h = fopen(st->path, "w");
    if (!h) {
        sl_warning("densityError: cannot write '%s': %s", st->path, strerror(errno));
        return;
    }
    fprintf(h,
            "# Histogram of the signed density error (rho - rho0) / rho0 in percent of "
            "rho0 = %g kg/m^3\n"
            "# time %.10g, %zu fluid particles, %zu below and %zu above the range\n"
            "# binStart\tbinEnd\tcount\tfraction\n",
            rho0, call->time, f->n, below, above);
    for (size_t b = 0; b < gsl_histogram_bins(st->hist); b++) {
        double b0, b1, c = gsl_histogram_get(st->hist, b);
        gsl_histogram_get_range(st->hist, b, &b0, &b1);
        fprintf(h, "%.10g\t%.10g\t%.0f\t%.10g\n", b0, b1, c, f->n ? c / (double)f->n : 0.0);
    }
    if (ferror(h) | fclose(h)) sl_warning("densityError: cannot write '%s'", st->path);
}

static void de_at_write(void *vs, const fo_call *call)
{
    de_state *st = vs;
    if (st->histogram) de_write_histogram(st, call);
}

static void de_free(void *vs)
{
    de_state *st = vs;
    if (!st) return;
    if (st->hist) gsl_histogram_free(st->hist);
    free(st->pct);
    free(st->buf);
    free(st->path);
    free(st);
}

const fo_type fo_type_density_error = {
    .name = "densityError",
    .keys = de_keys,
    .needs = 0,
    .read = de_read,
    .header = de_header,
    .columns = de_columns,
    .execute = de_execute,
    .at_write = de_at_write,
    .free = de_free,
};
