/*
 * ce_report: compares one simulated series with its experimental one
 * (ce_result_compute) and writes the results: table.md for people and
 * table.csv (group,series,metric,unit,value; one metric per line) for
 * scripts and tests.
 *
 * Heights are compared as they are; pressures after the same low-pass
 * filter on both sides (SPH pressure is noisy, and the experiment's
 * single-run peaks scatter widely), see the conventions written at the top
 * of table.md.
 */
#include "ce.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* [a, b] cut to the time ranges of both series. */
static void common_window(double out[2], const double w[2], const ce_series *a, const ce_series *b)
{
    out[0] = fmax(w[0], fmax(a->t[0], b->t[0]));
    out[1] = fmin(w[1], fmin(a->t[a->n - 1], b->t[b->n - 1]));
}

void ce_result_compute(ce_result *r, double filter)
{
    const ce_entry *e = r->e;
    const int p = r->g->kind == CE_PRESSURE;
    const double w = p ? filter : 0.0;
    ce_filter(&r->simf, &r->sim, w);
    ce_filter(&r->expf, &r->exp, w);
    common_window(r->window, e->window, &r->sim, &r->exp);
    r->t_sim = ce_crossing(&r->simf, e->threshold);
    r->t_exp = ce_crossing(&r->expf, e->threshold);
    ce_compare(&r->err, &r->simf, &r->expf, r->window[0], r->window[1]);
    r->plateau_sim = r->plateau_exp = NAN;
    r->peak_sim = r->peak_exp = r->rpeak_sim = r->rpeak_exp = NAN;
    r->inside = NAN;
    for (int k = 0; k < 3; k++) r->band_peak[k] = r->band_rpeak[k] = NAN;
    if (!p) return;
    if (isfinite(e->plateau[0])) {
        double pl[2];
        common_window(pl, e->plateau, &r->sim, &r->exp);
        /* An interval the run does not cover entirely has no plateau. */
        if (pl[0] == e->plateau[0] && pl[1] == e->plateau[1]) {
            r->plateau_sim = ce_mean(&r->sim, pl[0], pl[1]);
            r->plateau_exp = ce_mean(&r->exp, pl[0], pl[1]);
        }
    }
    const double a = r->window[0], b = r->window[1];
    r->peak_sim = ce_peak(&r->simf, a, b, &r->peak_sim_at);
    r->peak_exp = ce_peak(&r->expf, a, b, &r->peak_exp_at);
    r->rpeak_sim = ce_peak(&r->sim, a, b, &r->rpeak_sim_at);
    r->rpeak_exp = ce_peak(&r->exp, a, b, &r->rpeak_exp_at);
    if (r->lo_raw.n) {
        double at;
        ce_filter(&r->lo, &r->lo_raw, w);
        ce_filter(&r->hi, &r->hi_raw, w);
        r->band_peak[0] = ce_peak(&r->lo, a, b, &at);
        r->band_peak[1] = r->peak_exp;
        r->band_peak[2] = ce_peak(&r->hi, a, b, &at);
        r->band_rpeak[0] = ce_peak(&r->lo_raw, a, b, &at);
        r->band_rpeak[1] = r->rpeak_exp;
        r->band_rpeak[2] = ce_peak(&r->hi_raw, a, b, &at);
        r->inside = ce_inside_band(&r->simf, &r->lo, &r->hi, a, b);
    }
}

void ce_result_free(ce_result *r)
{
    ce_series *s[] = {&r->sim, &r->exp, &r->simf, &r->expf, &r->lo, &r->hi, &r->lo_raw, &r->hi_raw};
    for (size_t i = 0; i < sizeof s / sizeof *s; i++) ce_series_free(s[i]);
}

/* ---- table.md ------------------------------------------------------------------ */

/* A number for the Markdown table ("-" for none). */
static const char *num(char *buf, size_t len, double x, int prec)
{
    if (!isfinite(x)) snprintf(buf, len, "-");
    else snprintf(buf, len, "%.*f", prec, x);
    return buf;
}

static const char *verdict(double x, double lo, double hi)
{
    if (!isfinite(x) || !isfinite(lo) || !isfinite(hi)) return "-";
    return x < lo ? "below" : x > hi ? "above" : "inside";
}

static const char *quantity_name(ce_kind k) { return k == CE_HEIGHT ? "height" : "pressure"; }

static void md_heights(FILE *f, const ce_result *r, size_t n)
{
    char b[10][32];
    fputs("| gauge | threshold (m) | arrival sim (s) | arrival exp (s) | sim - exp (s) | "
          "window (s) | RMS error (m) | median abs error (m) | max abs error (m) | at t (s) | "
          "bias (m) | samples |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|\n",
          f);
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        fprintf(f, "| %s | %g | %s | %s | %s | %s-%s | %s | %s | %s | %s | %s | %zu |\n",
                x->e->name, x->e->threshold, num(b[0], 32, x->t_sim, 3), num(b[1], 32, x->t_exp, 3),
                num(b[2], 32, x->t_sim - x->t_exp, 3), num(b[3], 32, x->window[0], 2),
                num(b[4], 32, x->window[1], 2), num(b[5], 32, x->err.rms, 4),
                num(b[6], 32, x->err.median, 4), num(b[7], 32, x->err.max, 4),
                num(b[8], 32, x->err.max_at, 3), num(b[9], 32, x->err.bias, 4), x->err.n);
    }
}

static void md_pressures(FILE *f, const ce_result *r, size_t n)
{
    char b[10][32];
    fputs("| probe | threshold (Pa) | rise sim (s) | rise exp (s) | sim - exp (s) | "
          "plateau window (s) | plateau sim (Pa) | plateau exp (Pa) | sim / exp |\n"
          "|---|---|---|---|---|---|---|---|---|\n",
          f);
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        fprintf(f, "| %s | %g | %s | %s | %s | %s-%s | %s | %s | %s |\n", x->e->name,
                x->e->threshold, num(b[0], 32, x->t_sim, 3), num(b[1], 32, x->t_exp, 3),
                num(b[2], 32, x->t_sim - x->t_exp, 3), num(b[3], 32, x->e->plateau[0], 2),
                num(b[4], 32, x->e->plateau[1], 2), num(b[5], 32, x->plateau_sim, 0),
                num(b[6], 32, x->plateau_exp, 0),
                num(b[7], 32, x->plateau_sim / x->plateau_exp, 2));
    }
    fputs("\n| probe | window (s) | filtered peak sim (Pa) | at t (s) | filtered peak exp (Pa) | "
          "at t (s) | raw peak sim (Pa) | raw peak exp (Pa) | RMS error, filtered (Pa) | "
          "bias (Pa) |\n"
          "|---|---|---|---|---|---|---|---|---|---|\n",
          f);
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        fprintf(f, "| %s | %s-%s | %s | %s | %s | %s | %s | %s | %s | %s |\n", x->e->name,
                num(b[0], 32, x->window[0], 2), num(b[1], 32, x->window[1], 2),
                num(b[2], 32, x->peak_sim, 0), num(b[3], 32, x->peak_sim_at, 3),
                num(b[4], 32, x->peak_exp, 0), num(b[5], 32, x->peak_exp_at, 3),
                num(b[6], 32, x->rpeak_sim, 0), num(b[7], 32, x->rpeak_exp, 0),
                num(b[8], 32, x->err.rms, 0), num(b[9], 32, x->err.bias, 0));
    }
    int band = 0;
    for (size_t i = 0; i < n; i++) band |= r[i].lo_raw.n > 0;
    if (!band) return;
    fputs("\nPeaks against the experimental band (the largest value over the window of the "
          "lower, central and upper band curves):\n\n"
          "| probe | band | filtered: exp low / central / high (Pa) | sim (Pa) | sim is | "
          "raw: exp low / central / high (Pa) | sim (Pa) | sim is | time inside the filtered "
          "band |\n"
          "|---|---|---|---|---|---|---|---|---|\n",
          f);
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        if (!x->lo_raw.n) continue;
        fprintf(f, "| %s | %s / %s / %s | %s / %s / %s | %s | %s | %s / %s / %s | %s | %s | ",
                x->e->name, x->e->band[0], x->e->data, x->e->band[1],
                num(b[0], 32, x->band_peak[0], 0), num(b[1], 32, x->band_peak[1], 0),
                num(b[2], 32, x->band_peak[2], 0), num(b[3], 32, x->peak_sim, 0),
                verdict(x->peak_sim, x->band_peak[0], x->band_peak[2]),
                num(b[4], 32, x->band_rpeak[0], 0), num(b[5], 32, x->band_rpeak[1], 0),
                num(b[6], 32, x->band_rpeak[2], 0), num(b[7], 32, x->rpeak_sim, 0),
                verdict(x->rpeak_sim, x->band_rpeak[0], x->band_rpeak[2]));
        if (isfinite(x->inside)) fprintf(f, "%.0f %% |\n", 100 * x->inside);
        else fputs("- |\n", f);
    }
}

static void md_conventions(FILE *f, const ce_setup *s)
{
    fputs("Conventions:\n\n"
          "- Errors are simulation - experiment, at the experiment's sample times inside the "
          "window (the simulation interpolated linearly with GSL); windows are cut to the "
          "times both cover.\n"
          "- Heights are compared unfiltered; the arrival is the first time the height exceeds "
          "the threshold (interpolated linearly between samples).  A dry gauge (nan) counts as "
          "height 0.\n",
          f);
    if (s->filter > 0)
        fprintf(f,
                "- Pressures of both sides are low-pass filtered by a centred moving average "
                "of width %g s (the time average of the piecewise-linear signal over "
                "[t - %g, t + %g] s, cut at the ends); ",
                s->filter, s->filter / 2, s->filter / 2);
    else fputs("- Pressures are not filtered; ", f);
    fputs("the rise is the first time the filtered pressure exceeds the threshold; peaks and "
          "RMS errors are taken over the window; the plateau is the time average of the "
          "unfiltered pressure over the plateau window.  A probe with no particle within h "
          "(nan) counts as pressure 0 (gauge pressure).\n",
          f);
    if (s->normalised)
        fprintf(f,
                "- The experimental columns are normalised; converted with H = %g m, rho = %g "
                "kg/m^3, g = %g m/s^2: t = t* sqrt(H/g), p = p* rho g H, h = h* H.\n",
                s->H, s->rho, s->g);
    if (s->time_shift != 0.0)
        fprintf(f, "- The experiment's times are shifted by %+g s.\n", s->time_shift);
}

static void write_md(const char *path, const char *case_dir, const ce_setup *s,
                     const char *const *data, size_t ndata, const ce_result *r, size_t n)
{
    FILE *f = fopen(path, "w");
    if (!f) sl_fatal("cannot write '%s': %s", path, strerror(errno));
    fprintf(f,
            "# Comparison with experiment: %s\n\nWritten by compareExperiment (Sluice) from "
            "%s.\n\nExperimental data:\n\n",
            case_dir, s->path);
    for (size_t i = 0; i < ndata; i++) fprintf(f, "- %s\n", data[i]);
    fputc('\n', f);
    md_conventions(f, s);
    for (size_t gi = 0; gi < s->ngrp; gi++) {
        const ce_group *g = &s->grp[gi];
        size_t first = 0, count = 0;
        while (first < n && r[first].g != g) first++;
        while (first + count < n && r[first + count].g == g) count++;
        fprintf(f, "\n## %s: %s (%s, function object '%s')\n\n", g->name, g->title,
                quantity_name(g->kind), g->fo);
        if (count == 0) {
            fputs("No series of this group is in the given data files.\n", f);
            continue;
        }
        if (g->kind == CE_HEIGHT) md_heights(f, r + first, count);
        else md_pressures(f, r + first, count);
        for (size_t i = first; i < first + count; i++)
            if (r[i].sim_nan)
                fprintf(f, "\n%s: %zu rows of the run were nan (taken as 0).\n", r[i].e->name,
                        r[i].sim_nan);
    }
    if (fclose(f) != 0) sl_fatal("cannot write '%s': %s", path, strerror(errno));
}

/* ---- table.csv ------------------------------------------------------------------ */

static void csv_row(FILE *f, const ce_result *x, const char *metric, const char *unit, double v)
{
    fprintf(f, "%s,%s,%s,%s,", x->g->name, x->e->name, metric, unit);
    if (isfinite(v)) fprintf(f, "%.10g\n", v);
    else fputs("nan\n", f);
}

static void write_csv(const char *path, const ce_result *r, size_t n)
{
    FILE *f = fopen(path, "w");
    if (!f) sl_fatal("cannot write '%s': %s", path, strerror(errno));
    fputs("group,series,metric,unit,value\n", f);
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        const int p = x->g->kind == CE_PRESSURE;
        const char *u = p ? "Pa" : "m", *ev = p ? "rise" : "arrival";
        char m[64];
        csv_row(f, x, "threshold", u, x->e->threshold);
        snprintf(m, sizeof m, "%s_sim", ev);
        csv_row(f, x, m, "s", x->t_sim);
        snprintf(m, sizeof m, "%s_exp", ev);
        csv_row(f, x, m, "s", x->t_exp);
        snprintf(m, sizeof m, "%s_diff", ev);
        csv_row(f, x, m, "s", x->t_sim - x->t_exp);
        csv_row(f, x, "window_start", "s", x->window[0]);
        csv_row(f, x, "window_end", "s", x->window[1]);
        csv_row(f, x, "samples", "1", (double)x->err.n);
        csv_row(f, x, "rms_error", u, x->err.rms);
        csv_row(f, x, "median_abs_error", u, x->err.median);
        csv_row(f, x, "max_error", u, x->err.max);
        csv_row(f, x, "max_error_time", "s", x->err.max_at);
        csv_row(f, x, "bias", u, x->err.bias);
        csv_row(f, x, "nan_rows_sim", "1", (double)x->sim_nan);
        if (!p) continue;
        csv_row(f, x, "plateau_start", "s", x->e->plateau[0]);
        csv_row(f, x, "plateau_end", "s", x->e->plateau[1]);
        csv_row(f, x, "plateau_sim", u, x->plateau_sim);
        csv_row(f, x, "plateau_exp", u, x->plateau_exp);
        csv_row(f, x, "peak_filtered_sim", u, x->peak_sim);
        csv_row(f, x, "peak_filtered_sim_time", "s", x->peak_sim_at);
        csv_row(f, x, "peak_filtered_exp", u, x->peak_exp);
        csv_row(f, x, "peak_filtered_exp_time", "s", x->peak_exp_at);
        csv_row(f, x, "peak_raw_sim", u, x->rpeak_sim);
        csv_row(f, x, "peak_raw_exp", u, x->rpeak_exp);
        if (!x->lo_raw.n) continue;
        csv_row(f, x, "band_peak_filtered_low", u, x->band_peak[0]);
        csv_row(f, x, "band_peak_filtered_high", u, x->band_peak[2]);
        csv_row(f, x, "band_peak_raw_low", u, x->band_rpeak[0]);
        csv_row(f, x, "band_peak_raw_high", u, x->band_rpeak[2]);
        csv_row(f, x, "inside_band_fraction", "1", x->inside);
    }
    if (fclose(f) != 0) sl_fatal("cannot write '%s': %s", path, strerror(errno));
}

void ce_report_write(const char *dir, const char *case_dir, const ce_setup *s,
                     const char *const *data_files, size_t ndata, const ce_result *r, size_t n)
{
    char *md = ce_join(dir, "table.md"), *csv = ce_join(dir, "table.csv");
    write_md(md, case_dir, s, data_files, ndata, r, n);
    write_csv(csv, r, n);
    sl_info("Wrote %s and %s", md, csv);
    free(md);
    free(csv);
}
