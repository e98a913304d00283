/*
 * sts_search: the bisection of one method's largest stable deltaT, on a log
 * scale.  A round places k trials evenly (in log deltaT) inside the bracket
 * (lo, hi), so that k runs at a time shrink it by a factor k + 1.  The
 * bracket is closed when hi / lo <= 1 + tolerance; then the ends that were
 * never run (deltaTMin, deltaTMax) are run once, so that the answer is
 * always a deltaT that was seen to be stable.
 *
 * Every deltaT tried divides the simulated time: the solver spreads a
 * remainder over the steps (it lands exactly on write times), so a deltaT
 * that does not divide it would not be the step actually taken.
 */
#include "sts.h"

#include <math.h>
#include <stdio.h>

#include "core/sl_log.h"

double sts_snap_dt(double span, double dt)
{
    double k = round(span / dt);
    return span / (k > 1.0 ? k : 1.0);
}

void sts_search_init(sts_search *s, const char *method, double dt_min, double dt_max)
{
    snprintf(s->method, sizeof s->method, "%s", method);
    s->lo = dt_min;
    s->hi = dt_max;
    s->lo_stable = s->hi_unstable = 0;
    s->best = s->worst = -1;
    s->ntrials = 0;
    s->done = s->unavailable = s->nonmonotonic = 0;
}

static int in_flight(const sts_trial *t)
{
    return t->status == STS_PENDING || t->status == STS_RUNNING;
}

/* 1 if search m already has a trial (finished or in flight) at dt. */
static int has_trial(const sts_run *r, size_t m, double dt)
{
    for (size_t i = 0; i < r->ntrial; i++) {
        const sts_trial *t = &r->trial[i];
        if (t->method == m && !t->common && t->status != STS_CANCELLED && t->dt == dt) return 1;
    }
    return 0;
}

size_t sts_search_plan(sts_run *r, size_t m, size_t k)
{
    sts_search *s = &r->search[m];
    if (s->done) return 0;
    if (s->hi / s->lo <= 1.0 + r->opt.tolerance) {
        /* closed: make sure the answer was run */
        double end = !s->lo_stable ? s->lo : !s->hi_unstable ? s->hi : 0.0;
        if (end > 0.0 && !(s->hi_unstable && s->hi <= s->lo) && !has_trial(r, m, end)) {
            sts_trial_add(r, m, end, 0);
            return 1;
        }
        s->done = 1;
        return 0;
    }
    size_t added = 0;
    const double ratio = s->hi / s->lo;
    for (size_t i = 1; i <= k; i++) {
        double dt = sts_snap_dt(r->end_time - r->base.ctl.start_time,
                                s->lo * pow(ratio, (double)i / (double)(k + 1)));
        if (!(dt > s->lo && dt < s->hi) || has_trial(r, m, dt)) continue;
        sts_trial_add(r, m, dt, 0);
        added++;
    }
    if (!added) s->done = 1; /* no whole number of steps between lo and hi */
    return added;
}

void sts_search_update(sts_run *r, size_t m)
{
    sts_search *s = &r->search[m];
    double hi = r->opt.dt_max, lo = r->opt.dt_min;
    int hi_unstable = 0, lo_stable = 0;
    long worst = -1, best = -1;
    s->ntrials = 0;
    for (size_t i = 0; i < r->ntrial; i++) {
        const sts_trial *t = &r->trial[i];
        if (t->method != m || t->common) continue;
        if (t->status == STS_STABLE || t->status == STS_UNSTABLE || t->status == STS_UNAVAILABLE)
            s->ntrials++;
        if (t->status == STS_UNAVAILABLE) s->unavailable = 1;
        if (t->status == STS_UNSTABLE && (!hi_unstable || t->dt < hi)) {
            hi = t->dt;
            hi_unstable = 1;
            worst = (long)i;
        }
    }
    for (size_t i = 0; i < r->ntrial; i++) {
        const sts_trial *t = &r->trial[i];
        if (t->method != m || t->common || t->status != STS_STABLE) continue;
        if (hi_unstable && t->dt >= hi) {
            s->nonmonotonic = 1; /* stable above an unstable deltaT: ignored */
            continue;
        }
        if (!lo_stable || t->dt > lo) {
            lo = t->dt;
            lo_stable = 1;
            best = (long)i;
        }
    }
    s->lo = lo;
    s->hi = hi;
    s->lo_stable = lo_stable;
    s->hi_unstable = hi_unstable;
    s->best = best;
    s->worst = worst;
    if (s->unavailable) s->done = 1;
    for (size_t i = 0; i < r->ntrial; i++) {
        sts_trial *t = &r->trial[i];
        if (t->method != m || t->common || !in_flight(t)) continue;
        char why[128];
        if (s->unavailable)
            snprintf(why, sizeof why, "the solver does not know method %s", s->method);
        else if (lo_stable && t->dt <= lo)
            snprintf(why, sizeof why, "not needed: %.6g s is stable", lo);
        else if (hi_unstable && t->dt >= hi)
            snprintf(why, sizeof why, "not needed: %.6g s is unstable", hi);
        else continue;
        sts_trial_cancel(t, why);
    }
}
