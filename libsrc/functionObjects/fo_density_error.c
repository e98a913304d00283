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
 * Percentiles interpolate linearly between order statistics, as
 * gsl_stats_quantile_from_sorted_data does: the NN-th of N values is
 * (1 - d) x_(l) + d x_(l+1), l + d = NN / 100 (N - 1).  The order
 * statistics are selected exactly without sorting or gathering: the
 * values' bit patterns (mapped to integers in the values' order) are
 * counted 4 bits at a time from the top, 16 bins per pass and per distinct
 * prefix of the wanted ones, each pass fixing the next 4 bits of each
 * (16 passes; in -parallel's domain mode the counts are summed over the
 * ranks: reductions of at most 2 x percentiles x 16 counts, no particle
 * travels).  The averages are block sums over the rows (solver/pcs_sums.h:
 * the same bits for any ranks x threads), divided by N.  With `histogram
 * on` every write time also gets histogram_<time>.dat of the signed error
 * (gsl_histogram), over histogramRange or, by default, the data's range
 * (a min and a max reduction; the bins' counts summed over the ranks).
 *
 *   type densityError; percentiles (50 90 99); histogram off;
 *   histogramBins 50; histogramRange (-5 5);  // optional, percent
 */
#include "functionObjects/fo_type.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "solver/pcs_sums.h"

#include <errno.h>
#include <gsl/gsl_histogram.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define DE_DEFAULT_BINS 50
/* The selection's digits: bits per pass, bins, passes (64 bits). */
#define DE_DIGIT  4
#define DE_BINS   16
#define DE_PASSES 16

static const char *const de_keys[] = {"percentiles", "histogram", "histogramBins", "histogramRange",
                                      NULL};

typedef struct de_state {
    double *pct; /* percentiles, 0..100 */
    size_t npct;
    int histogram;
    int fixed_range;
    double range[2];
    gsl_histogram *hist;
    long *hcount;  /* the histogram's counts, below and above (summed over the ranks) */
    uint64_t *key; /* scratch: the compression of every own row, as ordered keys */
    size_t cap;
    /* the selection: per wanted order statistic (at most 2 per percentile)
     * its rank, the prefix of its key fixed so far, its rank among those
     * with that prefix, its group; per group (distinct prefix) the prefix
     * and DE_BINS counts */
    size_t *want, *rem, *grp;
    uint64_t *pre, *gpre;
    long *count;
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
        st->hcount = sl_malloc(((size_t)bins + 2) * sizeof *st->hcount, "histogram");
    }
    const size_t m = 2 * st->npct + 1;
    st->want = sl_malloc(m * sizeof *st->want, "percentiles");
    st->rem = sl_malloc(m * sizeof *st->rem, "percentiles");
    st->grp = sl_malloc(m * sizeof *st->grp, "percentiles");
    st->pre = sl_malloc(m * sizeof *st->pre, "percentiles");
    st->gpre = sl_malloc(m * sizeof *st->gpre, "percentiles");
    st->count = sl_malloc(m * DE_BINS * sizeof *st->count, "percentiles");
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
    if (n <= st->cap && st->key) return;
    free(st->key);
    st->cap = n + n / 8 + 1;
    st->key = sl_malloc(st->cap * sizeof *st->key, "density error scratch");
}

/* Doubles to unsigned integers in the same order (negative ones: all bits
 * flipped; the others: the sign bit set), and back. */
static uint64_t de_key(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u >> 63 ? ~u : u | (UINT64_C(1) << 63);
}

static double de_value(uint64_t k)
{
    const uint64_t u = k >> 63 ? k & ~(UINT64_C(1) << 63) : ~k;
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* Whether p is among the sorted a[0..n). */
static int de_has(const uint64_t *a, size_t n, uint64_t p, size_t *at)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (a[mid] < p) lo = mid + 1;
        else hi = mid;
    }
    if (at) *at = lo;
    return lo < n && a[lo] == p;
}

/* The order statistics st->want[0..m) (ranks from 0, ascending, distinct)
 * of the keys of every row (this rank's: st->key[0..nc), overwritten), into
 * st->pre[0..m) as keys: DE_PASSES passes, each counting the next DE_DIGIT
 * bits of the candidates -- the keys whose bits so far are a wanted one's --
 * per distinct prefix, the counts summed over the ranks (collective). */
static void de_select(de_state *st, const pcs_view *v, size_t nc, size_t m)
{
    uint64_t *key = st->key;
    for (size_t j = 0; j < m; j++) st->pre[j] = 0, st->rem[j] = st->want[j];
    for (int pass = 0; pass < DE_PASSES; pass++) {
        const int shift = 64 - DE_DIGIT * (pass + 1);
        size_t ng = 0; /* groups: the distinct prefixes (ascending, as the ranks) */
        for (size_t j = 0; j < m; j++) {
            if (!ng || st->pre[j] != st->gpre[ng - 1]) st->gpre[ng++] = st->pre[j];
            st->grp[j] = ng - 1;
        }
        memset(st->count, 0, ng * DE_BINS * sizeof *st->count);
        for (size_t i = 0; i < nc; i++) {
            size_t g = 0;
            if (pass && !de_has(st->gpre, ng, key[i] >> (shift + DE_DIGIT), &g)) continue;
            st->count[g * DE_BINS + ((key[i] >> shift) & (DE_BINS - 1))]++;
        }
        pcs_view_sum_counts(v, st->count, ng * DE_BINS);
        for (size_t j = 0; j < m; j++) {
            const long *c = st->count + st->grp[j] * DE_BINS;
            size_t below = 0;
            unsigned d = 0;
            while (d < DE_BINS && below + (size_t)c[d] <= st->rem[j]) below += (size_t)c[d++];
            if (d == DE_BINS)
                sl_fatal("densityError: order statistic %zu beyond the counts (internal error)",
                         st->want[j]);
            st->rem[j] -= below;
            st->pre[j] = st->pre[j] << DE_DIGIT | d;
        }
        size_t kept = 0; /* the candidates of the next pass */
        for (size_t i = 0; i < nc; i++)
            if (shift && de_has(st->pre, m, key[i] >> shift, NULL)) key[kept++] = key[i];
        nc = kept;
    }
}

/* A row's compression and signed error in percent; ctx: rho0 and 100 / rho0. */
static void de_terms(const void *ctx, const sl_fluid *f, size_t i, double *t)
{
    const double *c = ctx;
    const double e = (f->rho[i] - c[0]) * c[1];
    t[0] = e > 0.0 ? e : 0.0;
    t[1] = e;
}

/* The percentiles of the compression of every row (collective), written. */
static void de_percentiles(de_state *st, const pcs_view *v, size_t nc, size_t N, FILE *dat)
{
    size_t m = 0;
    for (size_t k = 0; k < st->npct; k++) { /* as gsl_stats_quantile_from_sorted_data */
        const double index = st->pct[k] / 100.0 * (double)(N - 1);
        const size_t lhs = (size_t)index;
        st->want[m++] = lhs;
        if (lhs < N - 1) st->want[m++] = lhs + 1;
    }
    size_t *w = st->want, u = 0; /* sorted, distinct (m is small) */
    for (size_t a = 1; a < m; a++)
        for (size_t b = a; b > 0 && w[b - 1] > w[b]; b--) {
            const size_t t = w[b];
            w[b] = w[b - 1], w[b - 1] = t;
        }
    for (size_t a = 0; a < m; a++)
        if (!u || w[a] != w[u - 1]) w[u++] = w[a];
    de_select(st, v, nc, u);
    if (!dat) return;
    for (size_t k = 0; k < st->npct; k++) {
        const double index = st->pct[k] / 100.0 * (double)(N - 1);
        const size_t lhs = (size_t)index;
        const double delta = index - (double)lhs;
        size_t at = 0;
        while (w[at] != lhs) at++; /* w holds lhs (and lhs + 1 after it, when below N - 1) */
        const double lo = de_value(st->pre[at]);
        fo_put(dat, lhs == N - 1 ? lo : (1 - delta) * lo + delta * de_value(st->pre[at + 1]));
    }
}

static void de_execute(void *vs, const fo_call *call)
{
    de_state *st = vs;
    const pcs_view *v = call->s;
    const sl_fluid *f = pcs_view_rows(v);
    const double rho0 = v->rho0, scale = 100.0 / rho0, ctx[2] = {rho0, scale};
    const size_t n = f->n, N = pcs_view_count(v);
    double max_c = -INFINITY, min_s = INFINITY, max_s = -INFINITY;
    de_reserve(st, n);
    for (size_t i = 0; i < n; i++) {
        double t[2];
        de_terms(ctx, f, i, t);
        if (t[1] < min_s) min_s = t[1];
        if (t[1] > max_s) max_s = t[1];
        if (t[0] > max_c) max_c = t[0];
        st->key[i] = de_key(t[0]);
    }
    if (N == 0) { /* on every rank alike */
        for (size_t k = 0; k < 5 + st->npct; k++) fo_put(call->dat, NAN);
        return;
    }
    double mx[3] = {max_c, max_s, -min_s}, sum[2];
    pcs_view_max(v, mx, 3);
    pcs_view_sum_rows(v, 2, de_terms, ctx, sum);
    fo_put(call->dat, sum[0] / (double)N);
    fo_put(call->dat, mx[0]);
    fo_put(call->dat, sum[1] / (double)N);
    fo_put(call->dat, -mx[2]);
    fo_put(call->dat, mx[1]);
    if (st->npct) de_percentiles(st, v, n, N, call->dat);
}

static void de_write_histogram(de_state *st, const fo_call *call)
{
    const pcs_view *v = call->s;
    const sl_fluid *f = pcs_view_rows(v);
    const size_t N = pcs_view_count(v);
    const double rho0 = v->rho0, scale = 100.0 / rho0;
    double lo = st->range[0], hi = st->range[1];
    if (!st->fixed_range) {
        lo = INFINITY;
        hi = -INFINITY;
        for (size_t i = 0; i < f->n; i++) {
            double e = (f->rho[i] - rho0) * scale;
            if (e < lo) lo = e;
            if (e > hi) hi = e;
        }
        double mx[2] = {hi, -lo};
        pcs_view_max(v, mx, 2);
        hi = mx[0], lo = -mx[1];
        if (!(hi > lo)) { /* no particle, or all alike: a unit-wide range around them */
            double mid = N && isfinite(lo) ? lo : 0.0;
            lo = mid - 0.5;
            hi = mid + 0.5;
        }
        hi = nextafter(hi, INFINITY); /* bins are [lo, hi): keep the maximum */
    }
    gsl_histogram_set_ranges_uniform(st->hist, lo, hi);
    const size_t nbins = gsl_histogram_bins(st->hist);
    long *cnt = st->hcount; /* bins, below, above */
    memset(cnt, 0, (nbins + 2) * sizeof *cnt);
    for (size_t i = 0; i < f->n; i++) {
        double e = (f->rho[i] - rho0) * scale;
        size_t b;
        if (e < lo) cnt[nbins]++;
        else if (e >= hi) cnt[nbins + 1]++;
        else if (gsl_histogram_find(st->hist, e, &b) == 0) cnt[b]++;
    }
    pcs_view_sum_counts(v, cnt, nbins + 2);
    if (!call->dat) return;
    const size_t below = (size_t)cnt[nbins], above = (size_t)cnt[nbins + 1];
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
            rho0, call->time, N, below, above);
    for (size_t b = 0; b < nbins; b++) {
        double b0, b1, c = (double)cnt[b];
        gsl_histogram_get_range(st->hist, b, &b0, &b1);
        fprintf(h, "%.10g\t%.10g\t%.0f\t%.10g\n", b0, b1, c, N ? c / (double)N : 0.0);
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
    free(st->key), free(st->hcount);
    free(st->want), free(st->rem), free(st->grp), free(st->pre), free(st->gpre), free(st->count);
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
    .collective = 1,
};
