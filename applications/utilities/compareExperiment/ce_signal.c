/*
 * ce_signal: what compareExperiment measures on a time series (see ce.h).
 *
 * A series is taken as the piecewise-linear curve through its samples, so
 * that the results do not depend on how unevenly the samples lie in time
 * (the solver's adaptive step writes a probe row per step, dense during an
 * impact; the experiments sample evenly).  Averages are exact integrals of
 * that curve: a constant stays exactly constant and a straight line
 * exactly straight under the filter, which the tests check.
 */
#include "ce.h"

#include "core/sl_mem.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_interp.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Index k of the segment [t_k, t_k+1] holding x (0 <= k <= n-2), n >= 2. */
static size_t segment(const ce_series *s, double x)
{
    size_t lo = 0, hi = s->n - 1;
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (s->t[mid] <= x) lo = mid;
        else hi = mid;
    }
    return lo;
}

double ce_value_at(const ce_series *s, double t)
{
    if (s->n == 0) return NAN;
    if (s->n == 1 || t <= s->t[0]) return s->v[0];
    if (t >= s->t[s->n - 1]) return s->v[s->n - 1];
    size_t k = segment(s, t);
    double u = (t - s->t[k]) / (s->t[k + 1] - s->t[k]);
    return s->v[k] + u * (s->v[k + 1] - s->v[k]);
}

/* Cumulative trapezoid integral at the samples: c[k] = int_t0^tk s dt. */
static double *cumulative(const ce_series *s)
{
    double *c = sl_malloc((s->n ? s->n : 1) * sizeof *c, "integral");
    c[0] = 0.0;
    for (size_t k = 1; k < s->n; k++)
        c[k] = c[k - 1] + 0.5 * (s->t[k] - s->t[k - 1]) * (s->v[k] + s->v[k - 1]);
    return c;
}

/* int_t0^x s dt for x in [t_0, t_n-1] (n >= 2): exact for the linear curve. */
static double integral_to(const ce_series *s, const double *c, double x)
{
    if (x <= s->t[0]) return 0.0;
    if (x >= s->t[s->n - 1]) return c[s->n - 1];
    size_t k = segment(s, x);
    double u = (x - s->t[k]) / (s->t[k + 1] - s->t[k]);
    double vx = s->v[k] + u * (s->v[k + 1] - s->v[k]);
    return c[k] + 0.5 * (x - s->t[k]) * (s->v[k] + vx);
}

void ce_filter(ce_series *out, const ce_series *s, double w)
{
    ce_series f;
    ce_series_copy(&f, s);
    if (w > 0.0 && s->n >= 2) {
        double *c = cumulative(s);
        const double t0 = s->t[0], t1 = s->t[s->n - 1];
        for (size_t i = 0; i < s->n; i++) {
            double a = fmax(s->t[i] - 0.5 * w, t0), b = fmin(s->t[i] + 0.5 * w, t1);
            if (b > a) f.v[i] = (integral_to(s, c, b) - integral_to(s, c, a)) / (b - a);
        }
        free(c);
    }
    if (out == s) ce_series_free(out);
    *out = f;
}

double ce_crossing(const ce_series *s, double thr)
{
    for (size_t k = 0; k < s->n; k++) {
        if (!(s->v[k] > thr)) continue;
        if (k == 0) return s->t[0];
        double u = (thr - s->v[k - 1]) / (s->v[k] - s->v[k - 1]);
        return s->t[k - 1] + u * (s->t[k] - s->t[k - 1]);
    }
    return NAN;
}

double ce_mean(const ce_series *s, double a, double b)
{
    if (s->n == 0) return NAN;
    if (s->n == 1) return b > a ? s->v[0] : (double)NAN;
    a = fmax(a, s->t[0]);
    b = fmin(b, s->t[s->n - 1]);
    if (!(b > a)) return NAN;
    double *c = cumulative(s);
    double m = (integral_to(s, c, b) - integral_to(s, c, a)) / (b - a);
    free(c);
    return m;
}

double ce_peak(const ce_series *s, double a, double b, double *at)
{
    double best = NAN;
    *at = NAN;
    for (size_t k = 0; k < s->n; k++)
        if (s->t[k] >= a && s->t[k] <= b && !(s->v[k] <= best)) {
            best = s->v[k];
            *at = s->t[k];
        }
    return best;
}

/* A GSL linear interpolant of s (n >= 2). */
typedef struct interp {
    gsl_interp *f;
    gsl_interp_accel *acc;
} interp;

static int interp_init(interp *ip, const ce_series *s)
{
    if (s->n < 2) return 1;
    ip->f = gsl_interp_alloc(gsl_interp_linear, s->n);
    ip->acc = gsl_interp_accel_alloc();
    if (!ip->f || !ip->acc || gsl_interp_init(ip->f, s->t, s->v, s->n) != GSL_SUCCESS) {
        gsl_interp_free(ip->f);
        gsl_interp_accel_free(ip->acc);
        return 1;
    }
    return 0;
}

static void interp_free(interp *ip)
{
    gsl_interp_free(ip->f);
    gsl_interp_accel_free(ip->acc);
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void ce_compare(ce_error *e, const ce_series *sim, const ce_series *exp, double a, double b)
{
    interp ip;
    memset(e, 0, sizeof *e);
    e->rms = e->max = e->max_at = e->median = e->bias = NAN;
    if (interp_init(&ip, sim)) return;
    a = fmax(a, sim->t[0]);
    b = fmin(b, sim->t[sim->n - 1]);
    double sum2 = 0.0, sum = 0.0, max = -1.0, max_at = NAN;
    double *abs_e = sl_malloc((exp->n ? exp->n : 1) * sizeof *abs_e, "errors");
    size_t n = 0;
    for (size_t k = 0; k < exp->n; k++) {
        double t = exp->t[k], y;
        if (t < a || t > b) continue;
        if (gsl_interp_eval_e(ip.f, sim->t, sim->v, t, ip.acc, &y) != GSL_SUCCESS) continue;
        double d = y - exp->v[k];
        sum += d;
        sum2 += d * d;
        if (fabs(d) > max) {
            max = fabs(d);
            max_at = t;
        }
        abs_e[n++] = fabs(d);
    }
    interp_free(&ip);
    e->n = n;
    if (n > 0) {
        qsort(abs_e, n, sizeof *abs_e, by_value);
        e->median = n % 2 ? abs_e[n / 2] : 0.5 * (abs_e[n / 2 - 1] + abs_e[n / 2]);
        e->rms = sqrt(sum2 / (double)n);
        e->bias = sum / (double)n;
        e->max = max;
        e->max_at = max_at;
    }
    free(abs_e);
}

double ce_inside_band(const ce_series *sim, const ce_series *lo, const ce_series *hi, double a,
                      double b)
{
    interp ip;
    if (lo->n != hi->n || interp_init(&ip, sim)) return NAN;
    a = fmax(a, sim->t[0]);
    b = fmin(b, sim->t[sim->n - 1]);
    size_t n = 0, in = 0;
    for (size_t k = 0; k < lo->n; k++) {
        double t = lo->t[k], y;
        if (t < a || t > b) continue;
        if (gsl_interp_eval_e(ip.f, sim->t, sim->v, t, ip.acc, &y) != GSL_SUCCESS) continue;
        n++;
        if (y >= lo->v[k] && y <= hi->v[k]) in++;
    }
    interp_free(&ip);
    return n ? (double)in / (double)n : (double)NAN;
}
