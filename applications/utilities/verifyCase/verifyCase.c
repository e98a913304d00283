/*
 * verifyCase: the error of a finished case against its exact answer
 * (system/verifyDict, see vc.h), from its written times.
 *
 *   verifyCase [-case <dir>] [-time <times> | -latestTime] [-table <file>] [-label <text>]
 *
 * Prints one line per written time (its error and the measures behind it),
 * then the case's error over the times at or after `from`: the largest
 * (poiseuille, taylorGreen), the mean (hydrostatic, translatingTank: they
 * oscillate about their settled state), or for standingWave the period's
 * relative error, from the zero crossings of the velocity's projection on
 * the linear mode (all written times, the first included), and its
 * amplitude's decay rate against the viscous 2 nu k^2 (summary.dat's
 * decayRate, decayExact, decayError), and both again from a least-squares
 * fit of the whole record to a damped cosine (vc_fit.c; periodFit,
 * fitError, decayFit and their one-sigma uncertainties).  With
 * -table a row "label kind r0 particles error wallTime steps" is appended
 * to <file> (a header first when the file is new); wallTime is the sum of
 * the steps' wall seconds of postProcessing/timeStep/0/timeStep.dat (the
 * stepping, without output).  Exit 1 when the error is above the
 * verifyDict's tolerance, 2 on a bad command line.
 */
#include "app/app.h"
#include "case/case.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "functionObjects/fo_post.h"
#include "vc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const app_option options[] = {
    APP_CASE,
    APP_TIMES,
    {.name = "table", .kind = APP_PATH, .help = "append the case's row to this file"},
    {.name = "label",
     .kind = APP_STRING,
     .help = "the row's first column",
     .def = "the case's folder name"},
    {.name = "quiet", .help = "print only the case's error"},
    APP_END};

static const app_info info = {
    .name = "verifyCase",
    .what = "Error of a case against its exact answer, named in system/verifyDict\n"
            "(exact hydrostatic | translatingTank | poiseuille | taylorGreen | standingWave),\n"
            "from the written times; see doc/verification.md.",
    .options = options,
    .notes = "Example: verifyCase -case cases/verification/poiseuille/r0.005 -table errors.dat"};

/* Sum of the wallTime column (9th) and the number of steps of the case's
 * step record; NAN and 0 when there is none. */
static double wall_time(const char *dir, long *steps)
{
    char path[4096], line[1024];
    snprintf(path, sizeof path, "%s/postProcessing/timeStep/0/timeStep.dat", dir);
    FILE *f = fopen(path, "r");
    *steps = 0;
    if (!f) return NAN;
    double sum = 0.0;
    while (fgets(line, sizeof line, f)) {
        double v[9];
        if (line[0] == '#') continue;
        if (sscanf(line, "%lf %lf %lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                   &v[5], &v[6], &v[7], &v[8]) == 9) {
            sum += v[8];
            (*steps)++;
        }
    }
    fclose(f);
    return sum;
}

/* The zero crossings of the standing wave's velocity projection on the
 * linear mode (A w cos(w t) for the exact answer), by linear interpolation
 * between written times: their times tc[] and the sample before each,
 * at[] (at most n - 1).  One closer than a quarter period Te / 4 to the
 * previous one is noise and left out.  Returns their number. */
static int wave_crossings(const vc_sample *s, size_t n, double Te, double *tc, size_t *at)
{
    double last = -INFINITY;
    int j = 0;
    for (size_t i = 1; i < n; i++) {
        const double m0 = s[i - 1].mode, m1 = s[i].mode;
        if (!(m0 * m1 < 0.0 || (m1 == 0.0 && m0 != 0.0))) continue;
        const double t = s[i - 1].t + (s[i].t - s[i - 1].t) * m0 / (m0 - m1);
        if (t - last < 0.25 * Te) continue;
        tc[j] = t;
        at[j] = i - 1;
        j++;
        last = t;
    }
    return j;
}

/* The period from the crossings: successive crossings are half a period
 * apart, T / 2 is the slope of the least-squares line through the
 * crossing times against their number (a phase shift of the start does
 * not enter; with one crossing, at T / 4, T = 4 t).  NAN when none. */
static double wave_period(const double *tc, int nc)
{
    double sj = 0.0, st = 0.0, sjj = 0.0, sjt = 0.0;
    if (nc == 0) return (double)NAN;
    if (nc == 1) return 4.0 * tc[0];
    for (int j = 0; j < nc; j++) {
        sj += j;
        st += tc[j];
        sjj += (double)j * j;
        sjt += j * tc[j];
    }
    return 2.0 * (nc * sjt - sj * st) / (nc * sjj - sj * sj);
}

/* The amplitude's decay rate (1/s): the extremes of the mode's projection,
 * one per half period (the start, where the wave is set up at its largest
 * velocity, then the largest |mode| between two crossings, or after the
 * last one if the run goes past it, refined by the parabola through it
 * and its neighbours), and minus the slope of the least-squares line
 * through log |extreme| against its time.  NAN with fewer than two. */
static double wave_decay(const vc_sample *s, size_t n, const size_t *at, int nc, int *npeaks)
{
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    int m = 0;
    for (int j = 0; j <= nc && n > 0; j++) {
        const size_t a = j == 0 ? 0 : at[j - 1] + 1, b = j < nc ? at[j] : n - 1;
        size_t k = a;
        for (size_t i = a; i <= b; i++)
            if (fabs(s[i].mode) > fabs(s[k].mode)) k = i;
        double t = s[k].t, y = fabs(s[k].mode);
        if (k > a && k < b) { /* the parabola through k - 1, k, k + 1 */
            const double y0 = fabs(s[k - 1].mode), y2 = fabs(s[k + 1].mode),
                         den = y0 - 2.0 * y + y2, h = 0.5 * (s[k + 1].t - s[k - 1].t);
            if (den < 0.0) {
                const double d = 0.5 * (y0 - y2) / den;
                t += d * h;
                y -= 0.25 * (y0 - y2) * d;
            }
        } else if (k != 0 || j != 0) {
            continue; /* at a crossing or the run's end: no extreme in this half period */
        }
        const double ly = log(y);
        sx += t;
        sy += ly;
        sxx += t * t;
        sxy += t * ly;
        m++;
    }
    *npeaks = m;
    if (m < 2) return (double)NAN;
    return -(m * sxy - sx * sy) / (m * sxx - sx * sx);
}

/* taylorGreen: the amplitude's decay rate (1/s), minus the slope of the
 * least-squares line through log(mode) against t over the written times
 * (the projection on the vortex's shape; exactly 2 nu k^2).  NAN with
 * fewer than two or a mode that is not positive. */
static double vortex_decay(const vc_sample *s, size_t n)
{
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (!(s[i].mode > 0.0)) return (double)NAN;
        const double ly = log(s[i].mode);
        sx += s[i].t;
        sy += ly;
        sxx += s[i].t * s[i].t;
        sxy += s[i].t * ly;
    }
    if (n < 2) return (double)NAN;
    const double m = (double)n;
    return -(m * sxy - sx * sy) / (m * sxx - sx * sx);
}

/* The period and decay from the fit of the whole record (vc_fit.c),
 * seeded from the zero crossings' period T and the extremes' rate; one
 * line of output.  A fit that does not converge is a warning, not an
 * error: the zero crossings' figures stand. */
static void wave_fit(const vc_sample *s, size_t n, double T, double rate, double Te,
                     double exact_rate, vc_wave_fit *fit)
{
    double *t = sl_malloc(2 * n * sizeof *t, "wave record"), *y = t + n;
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(s[i].mode)) {
            t[m] = s[i].t;
            y[m++] = s[i].mode;
        }
    if (vc_fit_wave(t, y, m, T, rate, fit))
        sl_warning("the fit of the wave's record (%zu written times) to a damped cosine did not "
                   "converge: only the zero crossings' period",
                   m);
    else
        printf("# period fit %.6g +- %.2g s (%+.4g of linear theory), decay %.6g +- %.2g /s "
               "(viscous %.6g), from a damped cosine through %zu written times, residual rms "
               "%.3g of its amplitude\n",
               fit->period, fit->dperiod, (fit->period - Te) / Te, fit->decay, fit->ddecay,
               exact_rate, m, fit->residual);
    free(t);
}

/* <case>/postProcessing/verifyCase/summary.dat: one row, for sweepCase's
 * results (e.g. postProcessing/verifyCase/summary.dat:error). */
static void write_summary(const sl_case *c, const vc_setup *s, double error, double perr,
                          double vrms, double wall, long steps, double reached,
                          const double decay[3], const vc_wave_fit *fit, double Te, double gerr)
{
    const double nan = (double)NAN, ft = fit ? fit->period : nan, fd = fit ? fit->decay : nan;
    sl_err err;
    char path[4096];
    snprintf(path, sizeof path, "%s/postProcessing/verifyCase", c->dir);
    if (tdir_mkdirs(path, &err)) sl_fatal("%s", err.msg);
    snprintf(path, sizeof path, "%s/postProcessing/verifyCase/summary.dat", c->dir);
    FILE *f = fopen(path, "w");
    if (!f) sl_fatal("cannot write '%s'", path);
    fprintf(f,
            "# verifyCase: %s against its exact answer (system/verifyDict)\n"
            "# reached: the latest written time over endTime (< 1: the run stopped early)\n"
            "# decayRate, decayExact (1/s): standingWave's and taylorGreen's amplitude decay,\n"
            "#   measured and 2 nu k^2;\n"
            "#   decayError |decayRate - decayExact| / decayExact (NaN when nu is 0)\n"
            "# periodFit, periodFitSigma (s), decayFit, decayFitSigma (1/s): standingWave's\n"
            "#   least-squares fit of the whole record to A exp(-d t) cos(w t + phi) + c, with\n"
            "#   its one-sigma uncertainties; fitError |periodFit - linear| / linear,\n"
            "#   fitDecayError as decayError, fitResidual the residual rms over A\n"
            "# pressureError: the last written time's (taylorGreen: the rms of p against the\n"
            "#   exact pressure, each up to its mean, over rho0 U^2)\n"
            "# gradientError: hydrostatic's pressure gradient error, the mean over the times\n"
            "#   of the slope of p(z) more than h from the floor and the top, over rho0 g, less 1\n"
            "# error\tpressureError\tvelocityRms\tparticles\tr0\twallTime\tsteps\treached"
            "\tdecayRate\tdecayExact\tdecayError\tperiodFit\tperiodFitSigma\tfitError"
            "\tdecayFit\tdecayFitSigma\tfitDecayError\tfitResidual\tgradientError\n",
            vc_kind_names[s->kind]);
    fprintf(f, "%.8g\t%.8g\t%.8g\t%zu\t%g\t%.6g\t%ld\t%.6g\t%.8g\t%.8g\t%.8g", error, perr, vrms,
            s->nfluid, s->r0, wall, steps, reached, decay[0], decay[1], decay[2]);
    fprintf(f, "\t%.8g\t%.4g\t%.8g\t%.8g\t%.4g\t%.8g\t%.4g\t%.8g\n", ft, fit ? fit->dperiod : nan,
            fabs(ft - Te) / Te, fd, fit ? fit->ddecay : nan,
            s->nu > 0.0 ? fabs(fd - decay[1]) / decay[1] : nan, fit ? fit->residual : nan, gerr);
    if (fclose(f)) sl_fatal("cannot write '%s'", path);
}

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case(&a), *table = app_string(&a, "table", NULL);
    const int quiet = app_found(&a, "quiet");
    sl_case c;
    vc_setup s;
    tdir_list times;
    sl_err err;
    sl_log_set_quiet(1);
    case_read(&c, dir);
    sl_log_set_quiet(0);
    vc_read(&s, &c);
    const int with_first = s.kind == VC_WAVE;
    app_times(&a, c.dir, "fluid.vtu", with_first, &times);
    if (times.n == 0)
        sl_fatal("%s: no written time to verify (run the case first; the initial state does not "
                 "count)",
                 c.dir);
    vc_sample *smp = sl_malloc(times.n * sizeof *smp, "samples");
    const double area = (s.hi[0] - s.lo[0]) * (s.hi[1] - s.lo[1]);
    double worst = 0.0, mean = 0.0, gmean = 0.0;
    size_t counted = 0;
    if (!quiet)
        printf("# %s: %s\n# time\terror\tpressureError\tvelocityRms\tkineticEnergy\theight\tmode"
               "\tgradientError\n",
               c.dir, vc_kind_names[s.kind]);
    for (size_t i = 0; i < times.n; i++) {
        fo_snapshot sn;
        if (fo_snapshot_load(&sn, &c, times.name[i], 0, &err)) sl_fatal("%s", err.msg);
        s.nfluid = sn.f.n;
        s.depth = (double)sn.f.n * s.r0 * s.r0 * s.r0 / area;
        vc_measure(&s, &sn.f, times.time[i], &smp[i]);
        fo_snapshot_free(&sn);
        if (!quiet)
            printf("%s\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\n", times.name[i], smp[i].err,
                   smp[i].perr, smp[i].vrms, smp[i].ke, smp[i].height, smp[i].mode, smp[i].grad);
        if (times.time[i] >= s.from - 1e-9 && isfinite(smp[i].err)) {
            worst = fmax(worst, smp[i].err);
            mean += smp[i].err;
            gmean += smp[i].grad;
            counted++;
        }
    }
    double error = worst, decay[3] = {NAN, NAN, NAN}, Te = NAN;
    vc_wave_fit fit = {.ok = 0};
    const char *what = "largest over the times";
    gmean = s.kind == VC_HYDROSTATIC && counted ? gmean / (double)counted : (double)NAN;
    if (s.kind == VC_HYDROSTATIC || s.kind == VC_TRANSLATING) {
        error = counted ? mean / (double)counted : (double)NAN;
        what = "mean over the times";
        if (s.kind == VC_HYDROSTATIC)
            printf("# pressure gradient error %.6g (mean over the times: the slope of p(z) "
                   "more than h = %g m from the floor and the highest particle, over rho0 g, "
                   "less 1)\n",
                   gmean, s.support);
    } else if (s.kind == VC_WAVE) {
        Te = vc_wave_period(s.gmag, vc_wave_length(&s), s.depth);
        double *tc = sl_malloc(times.n * sizeof *tc, "crossings");
        size_t *at = sl_malloc(times.n * sizeof *at, "crossings");
        const int ncross = wave_crossings(smp, times.n, Te, tc, at);
        const double T = wave_period(tc, ncross);
        if (!isfinite(T))
            sl_fatal("%s: the velocity's projection on the wave's mode does not change sign in "
                     "the written times: write more often than a quarter period (%.4g s) and "
                     "run at least a quarter period",
                     c.dir, 0.25 * Te);
        error = fabs(T - Te) / Te;
        printf("# period %.6g s from %d zero crossings, linear theory %.6g s (L %g m, H %.6g m)\n",
               T, ncross, Te, vc_wave_length(&s), s.depth);
        const double k = 3.14159265358979323846 / vc_wave_length(&s);
        int npeaks;
        decay[0] = wave_decay(smp, times.n, at, ncross, &npeaks);
        decay[1] = 2.0 * s.nu * k * k;
        decay[2] = s.nu > 0.0 ? fabs(decay[0] - decay[1]) / decay[1] : (double)NAN;
        printf("# amplitude decay %.6g /s from %d extremes, viscous 2 nu k^2 %.6g /s (nu %g "
               "m^2/s of verifyDict), error %.6g of it\n",
               decay[0], npeaks, decay[1], s.nu, decay[2]);
        wave_fit(smp, times.n, T, decay[0], Te, decay[1], &fit);
        free(tc);
        free(at);
        what = "relative error of the period";
        counted = 1;
    } else if (s.kind == VC_TAYLOR_GREEN) {
        const double k = 2.0 * 3.14159265358979323846 / s.length;
        size_t w = 0; /* the time of the largest error */
        for (size_t i = 0; i < times.n; i++)
            if (smp[i].err > smp[w].err) w = i;
        decay[0] = vortex_decay(smp, times.n);
        decay[1] = 2.0 * s.nu * k * k;
        decay[2] = s.nu > 0.0 ? fabs(decay[0] - decay[1]) / decay[1] : (double)NAN;
        printf("# amplitude decay %.6g /s (the projection on the vortex's shape, least squares "
               "through %zu written times), viscous 2 nu k^2 %.6g /s, error %.6g of it; at the "
               "largest error (t = %g s) the amplitude is %.6g of the exact\n",
               decay[0], times.n, decay[1], decay[2], smp[w].t,
               smp[w].mode / (s.amplitude * exp(-decay[1] * smp[w].t)));
    }
    if (counted == 0) sl_fatal("%s: no written time at or after from = %g", c.dir, s.from);
    long steps;
    const double wall = wall_time(c.dir, &steps);
    printf("%s: %s error %.6g (%s), %zu particles, r0 %g m, %.3g s wall in %ld steps\n", c.dir,
           vc_kind_names[s.kind], error, what, s.nfluid, s.r0, wall, steps);
    const double last = times.time[times.n - 1], reached = last / c.ctl.end_time;
    if (last < c.ctl.end_time - 1e-9 * (1.0 + c.ctl.end_time))
        sl_warning("%s: the run stopped at t = %g s before its endTime %g s: the error is that "
                   "of the times written",
                   c.dir, last, c.ctl.end_time);
    write_summary(&c, &s, error, smp[times.n - 1].perr, smp[times.n - 1].vrms, wall, steps, reached,
                  decay, s.kind == VC_WAVE ? &fit : NULL, Te, gmean);
    if (table) {
        const char *label = app_string(&a, "label", NULL);
        if (!label) {
            label = strrchr(c.dir, '/');
            label = label && label[1] ? label + 1 : c.dir;
        }
        FILE *f = fopen(table, "a");
        if (!f) sl_fatal("cannot append to '%s'", table);
        if (ftell(f) == 0) fprintf(f, "# label\tkind\tr0\tparticles\terror\twallTime\tsteps\n");
        fprintf(f, "%s\t%s\t%g\t%zu\t%.6g\t%.4g\t%ld\n", label, vc_kind_names[s.kind], s.r0,
                s.nfluid, error, wall, steps);
        if (fclose(f)) sl_fatal("cannot write '%s'", table);
    }
    int bad = s.tolerance > 0.0 && !(error <= s.tolerance);
    if (bad)
        fprintf(stderr, "Error: %s: error %.6g above the tolerance %g of system/verifyDict\n",
                c.dir, error, s.tolerance);
    free(smp);
    tdir_list_free(&times);
    case_free(&c);
    app_free(&a);
    return bad;
}
