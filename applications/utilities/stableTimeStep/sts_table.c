/*
 * sts_table: the results of stableTimeStep -- one row per method (printed,
 * and written as stableTimeStep.md and stableTimeStep.csv) and one row per
 * trial (trials.csv), in postProcessing/stableTimeStep/ of the case.
 */
#include "sts.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "io/atomic_file.h"

/* Ihmsen et al. 2010, Sec. 4.1: "the following time steps could be used". */
double sts_paper_dt(const char *method)
{
    if (!strcmp(method, "becker2009")) return 0.0008;
    if (!strcmp(method, "harada2007")) return 0.0015;
    if (!strcmp(method, "ihmsen2010")) return 0.0045;
    return 0.0;
}

static const sts_trial *best_trial(const sts_run *r, const sts_search *s)
{
    return s->best >= 0 ? &r->trial[s->best] : NULL;
}

static double mean_iterations(const sts_trial *t)
{
    return t->steps > 0 ? t->iterations / (double)t->steps : nan("");
}

/* The largest stable deltaT as a table cell. */
static void cell_stable(const sts_run *r, const sts_search *s, char *buf, size_t len)
{
    if (s->unavailable) snprintf(buf, len, "not available");
    else if (!s->lo_stable) snprintf(buf, len, "< %.6g", r->opt.dt_min);
    else if (!s->hi_unstable) snprintf(buf, len, ">= %.6g", s->lo);
    else snprintf(buf, len, "%.6g", s->lo);
}

static void cell_unstable(const sts_search *s, char *buf, size_t len)
{
    if (s->hi_unstable) snprintf(buf, len, "%.6g", s->hi);
    else snprintf(buf, len, "-");
}

/* v with `digits` decimals (fixed) or significant digits (digits < 0), or "-". */
static void cell_number(double v, int digits, char *buf, size_t len)
{
    if (!isfinite(v)) snprintf(buf, len, "-");
    else if (digits < 0) snprintf(buf, len, "%.*g", -digits, v);
    else snprintf(buf, len, "%.*f", digits, v);
}

static void write_markdown(const sts_run *r, FILE *f)
{
    const sts_search *ref = NULL;
    fprintf(f,
            "| method | largest stable deltaT (s) | smallest unstable deltaT (s) | paper (s) | "
            "mean iterations | max volErrAvg (%%) | max rhoErrAvg (%%) | wall time (s) | "
            "trials |\n"
            "|---|---|---|---|---|---|---|---|---|\n");
    for (size_t m = 0; m < r->nsearch; m++) {
        const sts_search *s = &r->search[m];
        const sts_trial *b = best_trial(r, s);
        char st[64], un[64], pa[64], it[64], ev[64], er[64], wa[64];
        cell_stable(r, s, st, sizeof st);
        cell_unstable(s, un, sizeof un);
        cell_number(sts_paper_dt(s->method) > 0 ? sts_paper_dt(s->method) : nan(""), -4, pa,
                    sizeof pa);
        cell_number(b ? mean_iterations(b) : nan(""), 2, it, sizeof it);
        cell_number(b ? b->vol_avg_max : nan(""), 3, ev, sizeof ev);
        cell_number(b ? b->own_avg_max : nan(""), 3, er, sizeof er);
        cell_number(b ? b->wall : nan(""), 1, wa, sizeof wa);
        fprintf(f, "| %s | %s | %s | %s | %s | %s | %s | %s | %d |\n", s->method, st, un, pa, it,
                ev, er, wa, s->ntrials);
        if (!strcmp(s->method, "ihmsen2010") && s->lo_stable) ref = s;
    }
    fprintf(f,
            "\nStable: the solver exits 0, max over steps of %s < %g %% and no particle "
            "outside the tank at t = %g s; bisection on log deltaT in [%g, %g] s to %g %%.\n"
            "volErrAvg: the average compression with the wall's density from the boundary "
            "particles, alike for every method; rhoErrAvg: with the method's own density "
            "(the same for ihmsen2010).\n",
            sts_measure_name(r->opt.measure), r->opt.bound, r->end_time, r->opt.dt_min,
            r->opt.dt_max, 100 * r->opt.tolerance);
    for (size_t m = 0; ref && m < r->nsearch; m++) {
        const sts_search *s = &r->search[m];
        double p = sts_paper_dt(s->method), pref = sts_paper_dt("ihmsen2010");
        if (s == ref || s->unavailable) continue;
        if (!s->lo_stable) /* unstable at every deltaT tried: a lower bound on the ratio */
            fprintf(f, "dt(ihmsen2010) / dt(%s) > %.2f (no stable deltaT down to %g s)", s->method,
                    ref->lo / r->opt.dt_min, r->opt.dt_min);
        else fprintf(f, "dt(ihmsen2010) / dt(%s) = %.2f", s->method, ref->lo / s->lo);
        if (p > 0) fprintf(f, " (paper: %.1f)", pref / p);
        fprintf(f, "\n");
    }
    for (size_t m = 0; m < r->nsearch; m++) {
        const sts_search *s = &r->search[m];
        if (s->unavailable && s->worst < 0) {
            for (size_t i = 0; i < r->ntrial; i++)
                if (r->trial[i].method == m && r->trial[i].status == STS_UNAVAILABLE) {
                    fprintf(f, "%s: %s\n", s->method, r->trial[i].reason);
                    break;
                }
        }
        if (s->nonmonotonic)
            fprintf(f,
                    "%s: a deltaT above an unstable one was stable; the smaller answer is "
                    "kept\n",
                    s->method);
    }
    if (r->common_dt > 0)
        fprintf(f,
                "Runs at the common deltaT %.6g s for the pictures: "
                "postProcessing/stableTimeStep/common/<method>/\n",
                r->common_dt);
}

static void write_csv(const sts_run *r, FILE *f)
{
    fprintf(f,
            "method,largestStableDeltaT,smallestUnstableDeltaT,paperDeltaT,meanIterations,"
            "maxRhoErrAvg,wallTime,trials,status,maxVolErrAvg,smallestDeltaTTried\n");
    for (size_t m = 0; m < r->nsearch; m++) {
        const sts_search *s = &r->search[m];
        const sts_trial *b = best_trial(r, s);
        const char *status = s->unavailable ? "unavailable"
            : !s->lo_stable                 ? "belowDeltaTMin"
            : !s->hi_unstable               ? "atDeltaTMax"
                                            : "bracketed";
        fprintf(f, "%s,%.6g,%.6g,%.6g,%.4g,%.6g,%.4g,%d,%s,%.6g,%.6g\n", s->method,
                s->lo_stable ? s->lo : nan(""), s->hi_unstable ? s->hi : nan(""),
                sts_paper_dt(s->method) > 0 ? sts_paper_dt(s->method) : nan(""),
                b ? mean_iterations(b) : nan(""), b ? b->own_avg_max : nan(""),
                b ? b->wall : nan(""), s->ntrials, status, b ? b->vol_avg_max : nan(""),
                r->opt.dt_min);
    }
}

static void write_trials(const sts_run *r, FILE *f)
{
    fprintf(f,
            "method,deltaT,kind,status,maxJudged,timeOfMax,meanIterations,steps,lost,"
            "wallTime,reason,maxVolErrAvg,maxRhoErrAvg\n");
    for (size_t i = 0; i < r->ntrial; i++) {
        const sts_trial *t = &r->trial[i];
        fprintf(f, "%s,%.6g,%s,%s,%.6g,%.6g,%.4g,%ld,%ld,%.4g,\"", r->search[t->method].method,
                t->dt, t->common ? "common" : "search", sts_status_name(t->status), t->err_avg_max,
                t->t_err_avg_max, mean_iterations(t), t->steps, t->lost, t->wall);
        for (const char *c = t->reason; *c; c++) {
            if (*c == '"') fputc('"', f);
            fputc(*c, f);
        }
        fprintf(f, "\",%.6g,%.6g\n", t->vol_avg_max, t->own_avg_max);
    }
}

static void write_file(const sts_run *r, const char *name, void (*fill)(const sts_run *, FILE *))
{
    afile a;
    sl_err err;
    char *path = cf_join(r->out_dir, name);
    FILE *f = afile_open(&a, path, &err);
    if (!f) sl_fatal("%s", err.msg);
    fill(r, f);
    if (afile_commit(&a, &err)) sl_fatal("%s", err.msg);
    free(path);
}

void sts_table_write(const sts_run *r)
{
    write_file(r, "stableTimeStep.md", write_markdown);
    write_file(r, "stableTimeStep.csv", write_csv);
    write_file(r, "trials.csv", write_trials);
    printf("\n");
    write_markdown(r, stdout);
    printf("\nWritten: %s/stableTimeStep.md, stableTimeStep.csv, trials.csv\n", r->out_dir);
    fflush(stdout);
}
