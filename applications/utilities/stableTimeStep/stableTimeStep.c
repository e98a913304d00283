/*
 * stableTimeStep: the boundary study of Ihmsen et al. 2010, Sec. 4.1.  For
 * each boundary method, the largest constant deltaT for which a run of the
 * case keeps the average volume compression below a bound at every step
 * (the paper: "the maximum time step which satisfied an overall volume
 * compression smaller than 1%"), found by bisection on a log scale; then
 * one run per method at a common deltaT, for the side-by-side picture of
 * Fig. 2 (etc/renderBoundaryMethods.py).
 *
 *   stableTimeStep -case <dir> [-method m1,m2,...] [-endTime T] [-bound 1]
 *                  [-dtMin a -dtMax b] [-tolerance 5%] [-jobs N] [-threads T]
 *                  [-commonDeltaT dt|none]
 *
 * Results in <dir>/postProcessing/stableTimeStep/ (see sts.h for a trial).
 */
#include "sts.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "app/app.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_proc.h"
#include "io/time_dir.h"

static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

static const app_option table[] = {
    APP_CASE,
    {.name = "method",
     .kind = APP_STRING,
     .arg = "<m1,m2,...>",
     .help = "boundary methods",
     .def = "ihmsen2010,becker2009,harada2007"},
    {.name = "endTime",
     .kind = APP_DOUBLE,
     .arg = "<T>",
     .help = "simulated time of every run, s",
     .def = "the case's",
     .min = 0,
     .max = INFINITY,
     .above_min = 1},
    {.name = "bound",
     .kind = APP_STRING,
     .arg = "<B>",
     .help = "bound on the measure, percent of rho0 ('1' or '1%')",
     .def = "1"},
    {.name = "measure",
     .kind = APP_STRING,
     .arg = "<M>",
     .help = "volErrAvg (default): compression with the wall's density from\n"
             "the boundary particles, alike for every method; rhoErrAvg:\n"
             "with each method's own density (becker2009's has no wall)"},
    {.name = "dtMin",
     .kind = APP_DOUBLE,
     .arg = "<a>",
     .help = "smallest deltaT searched, s",
     .def = "1e-4",
     .min = 0,
     .max = INFINITY,
     .above_min = 1},
    {.name = "dtMax",
     .kind = APP_DOUBLE,
     .arg = "<b>",
     .help = "largest deltaT searched, s",
     .def = "1e-2",
     .min = 0,
     .max = INFINITY,
     .above_min = 1},
    {.name = "tolerance",
     .kind = APP_STRING,
     .arg = "<x>",
     .help = "stop when (unstable / stable deltaT) <= 1 + x; '5%' or 0.05",
     .def = "5%"},
    APP_JOBS("trials run at a time"),
    APP_THREADS("OpenMP threads per trial", "OMP_NUM_THREADS, else cores / jobs"),
    {.name = "commonDeltaT",
     .kind = APP_STRING,
     .arg = "<dt>",
     .help = "deltaT of the runs for the pictures; 'none': no such runs",
     .def = "the smallest stable deltaT found"},
    APP_END};

static const app_info info = {
    .name = "stableTimeStep",
    .what = "For each boundary method, the largest constant deltaT that keeps the maximum over\n"
            "steps of the average volume compression (postProcessing/timeStep) below the\n"
            "bound, with the solver exiting 0 and no particle outside the tank at the end\n"
            "(Ihmsen et al. 2010, Sec. 4.1).  Bisection on log deltaT; every trial is a clone\n"
            "of system/ and constant/ in <dir>/postProcessing/stableTimeStep/trials/\n"
            "<method>_<deltaT>/, stopped as soon as a step is above the bound.  Then one run\n"
            "per method at a common deltaT in .../stableTimeStep/common/<method>/.\n"
            "Tables: stableTimeStep.md, stableTimeStep.csv and trials.csv there.",
    .options = table};

/* A positive number, or with percent_ok also "<x>%" (returned as x / 100). */
static double number_arg(const app *a, const char *opt, const char *s, int percent_ok)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    int percent = percent_ok && *end == '%' && end[1] == '\0';
    if (end == s || (*end && !percent) || errno || !isfinite(v) || !(v > 0.0))
        app_error(a, "-%s: '%s' is not a positive number", opt, s);
    return percent ? v / 100.0 : v;
}

/* "a,b,c" -> list of words */
static void split_methods(const app *a, sts_options *o, const char *list)
{
    char *copy = sl_strdup(list), *save = NULL;
    for (char *w = strtok_r(copy, ",", &save); w; w = strtok_r(NULL, ",", &save)) {
        if (strlen(w) >= sizeof((sts_search *)0)->method)
            app_error(a, "-method: method name '%s' is too long", w);
        o->methods = sl_realloc(o->methods, (o->nmethods + 1) * sizeof *o->methods, "methods");
        o->methods[o->nmethods++] = sl_strdup(w);
    }
    free(copy);
    if (!o->nmethods) app_error(a, "-method: no method in '%s'", list);
}

/* -bound, -measure, -tolerance, -commonDeltaT: words the table leaves to us. */
static void parse_words(const app *a, sts_options *o)
{
    const char *v;
    if ((v = app_string(a, "bound", NULL))) /* percent, with or without the sign */
        o->bound = number_arg(a, "bound", v, 1) * (strchr(v, '%') ? 100.0 : 1.0);
    if ((v = app_string(a, "measure", NULL))) {
        if (!strcmp(v, "volErrAvg")) o->measure = STS_VOL_ERR_AVG;
        else if (!strcmp(v, "rhoErrAvg")) o->measure = STS_RHO_ERR_AVG;
        else app_error(a, "-measure %s: give volErrAvg or rhoErrAvg", v);
    }
    if ((v = app_string(a, "tolerance", NULL))) {
        o->tolerance = number_arg(a, "tolerance", v, 1);
        if (o->tolerance >= 1.0 && !strchr(v, '%'))
            app_error(a, "-tolerance %s: give a fraction (0.05) or a percentage (5%%)", v);
    }
    if ((v = app_string(a, "commonDeltaT", NULL)))
        o->common_dt = !strcmp(v, "none") ? -1.0 : number_arg(a, "commonDeltaT", v, 0);
}

static sts_options parse_args(int argc, char **argv)
{
    app a;
    sts_options o = {0};
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    app_parse(&a, &info, argc, argv);
    o.case_dir = app_case(&a);
    o.bound = 1.0;
    o.tolerance = 0.05;
    o.end_time = app_double(&a, "endTime", 0);
    o.dt_min = app_double(&a, "dtMin", 1e-4);
    o.dt_max = app_double(&a, "dtMax", 1e-2);
    o.jobs = (int)app_int(&a, "jobs", 0);
    o.threads = (int)app_int(&a, "threads", 0);
    split_methods(&a, &o, app_string(&a, "method", "ihmsen2010,becker2009,harada2007"));
    parse_words(&a, &o);
    if (!(o.dt_min < o.dt_max))
        app_error(&a, "-dtMin %g must be below -dtMax %g", o.dt_min, o.dt_max);
    if (o.tolerance < 0.002)
        app_error(&a, "-tolerance below 0.2%% is finer than deltaT is written");
    app_free(&a);
    if (!o.jobs) o.jobs = cores > 0 ? (int)cores : 1;
    if (!o.threads) {
        const char *env = getenv("OMP_NUM_THREADS");
        long e = env ? strtol(env, NULL, 10) : 0, t = cores / o.jobs;
        o.threads = e > 0 && e < 4096 ? (int)e : t > 1 ? (int)t : 1;
    }
    return o;
}

/* ---- the pool of runs ---------------------------------------------------------- */

static int in_flight(const sts_trial *t)
{
    return t->status == STS_PENDING || t->status == STS_RUNNING;
}

static int method_in_flight(const sts_run *r, size_t m)
{
    for (size_t i = 0; i < r->ntrial; i++)
        if (r->trial[i].method == m && !r->trial[i].common && in_flight(&r->trial[i])) return 1;
    return 0;
}

/* Start a round for every unfinished method with nothing in flight; the
 * jobs are shared among the unfinished methods. */
static void plan_rounds(sts_run *r)
{
    size_t active = 0;
    for (size_t m = 0; m < r->nsearch; m++) active += !r->search[m].done;
    if (!active) return;
    size_t k = (size_t)r->opt.jobs / active;
    if (k < 1) k = 1;
    for (size_t m = 0; m < r->nsearch; m++)
        if (!r->search[m].done && !method_in_flight(r, m)) sts_search_plan(r, m, k);
}

static void report(const sts_run *r, const sts_trial *t)
{
    const sts_search *s = &r->search[t->method];
    printf("  %-12s deltaT %-9.6g %-11s %s (%.1f s)\n", s->method, t->dt,
           sts_status_name(t->status), t->reason, t->wall);
    if (!t->common && (t->status == STS_STABLE || t->status == STS_UNSTABLE)) {
        printf("  %-12s largest stable deltaT in %s%.6g, %.6g%s\n", s->method,
               s->lo_stable ? "[" : "(", s->lo, s->hi, s->hi_unstable ? ")" : "]");
    }
    fflush(stdout);
}

static void stop_all(sts_run *r)
{
    for (size_t i = 0; i < r->ntrial; i++)
        if (in_flight(&r->trial[i])) sts_trial_cancel(&r->trial[i], "interrupted");
}

static void pause_a_little(void)
{
    struct timespec ts = {0, 200 * 1000 * 1000};
    nanosleep(&ts, NULL);
}

/* Run the trials, opt.jobs at a time, until none is left (searching: until
 * every search is done). */
static void run_pool(sts_run *r, int searching)
{
    for (;;) {
        size_t running = 0;
        if (searching) plan_rounds(r);
        for (size_t i = 0; i < r->ntrial; i++) running += r->trial[i].status == STS_RUNNING;
        for (size_t i = 0; i < r->ntrial && running < (size_t)r->opt.jobs; i++)
            if (r->trial[i].status == STS_PENDING) {
                sts_trial_start(r, &r->trial[i], r->opt.threads);
                running++;
            }
        if (!running) return;
        pause_a_little();
        for (size_t i = 0; i < r->ntrial; i++) {
            sts_trial *t = &r->trial[i];
            int status, ended = 0;
            if (t->status != STS_RUNNING) continue;
            sl_err err;
            int ended_now = sl_proc_wait(t->pid, &status, 1, &err);
            if (ended_now < 0) sl_fatal("%s: %s", t->dir, err.msg);
            if (ended_now) {
                sts_trial_finish(r, t, status);
                ended = 1;
            } else {
                ended = sts_trial_monitor(r, t);
            }
            if (!ended) continue;
            if (searching && !t->common) sts_search_update(r, t->method);
            report(r, t);
        }
        if (interrupted) {
            stop_all(r);
            sts_table_write(r);
            sl_fatal("interrupted; the runs were stopped");
        }
    }
}

/* One run per method at a common deltaT, writing at the case's interval. */
static void run_common(sts_run *r)
{
    double dt = r->opt.common_dt;
    if (dt < 0) return;
    if (dt == 0) {
        for (size_t m = 0; m < r->nsearch; m++) {
            const sts_search *s = &r->search[m];
            if (s->lo_stable && (dt == 0 || s->lo < dt)) dt = s->lo;
        }
    }
    if (!(dt > 0)) {
        printf("No stable deltaT found: no runs at a common deltaT.\n");
        return;
    }
    /* the largest deltaT <= dt that divides the write interval, so that
     * the steps are not stretched to land on write times */
    double w = r->base.ctl.write_interval, span = r->end_time - r->base.ctl.start_time;
    if (w > span) w = span;
    dt = w / ceil(w / dt * (1.0 - 1e-12));
    r->common_dt = dt;
    printf("\nRuns at the common deltaT %.6g s (for the pictures):\n", dt);
    for (size_t m = 0; m < r->nsearch; m++)
        if (!r->search[m].unavailable) sts_trial_add(r, m, dt, 1);
    run_pool(r, 0);
}

int main(int argc, char **argv)
{
    static sts_run r;
    sl_err err;
    r.opt = parse_args(argc, argv);
    case_read(&r.base, r.opt.case_dir);
    r.end_time = r.opt.end_time > 0 ? r.opt.end_time : r.base.ctl.end_time;
    if (!(r.end_time > r.base.ctl.start_time))
        sl_fatal("-endTime %g is not after the case's startTime %g", r.end_time,
                 r.base.ctl.start_time);
    const double span = r.end_time - r.base.ctl.start_time;
    r.opt.dt_min = sts_snap_dt(span, r.opt.dt_min);
    r.opt.dt_max = sts_snap_dt(span, r.opt.dt_max);
    if (!(r.opt.dt_min < r.opt.dt_max))
        sl_fatal("-dtMin and -dtMax give the same whole number of steps in %g s", span);
    char *self = cf_self_dir(&err), *pp = cf_join(r.opt.case_dir, "postProcessing");
    if (!self) sl_fatal("%s", err.msg);
    r.solver = cf_join(self, "pcisph");
    if (access(r.solver, X_OK) != 0)
        sl_fatal("no solver %s beside stableTimeStep: run make", r.solver);
    r.out_dir = cf_join(pp, "stableTimeStep");
    char *trials = cf_join(r.out_dir, "trials"), *common = cf_join(r.out_dir, "common");
    if (cf_remove_tree(trials, &err) || cf_remove_tree(common, &err) ||
        tdir_mkdirs(r.out_dir, &err))
        sl_fatal("%s", err.msg);
    r.nsearch = r.opt.nmethods;
    r.search = sl_calloc(r.nsearch, sizeof *r.search, "searches");
    for (size_t m = 0; m < r.nsearch; m++)
        sts_search_init(&r.search[m], r.opt.methods[m], r.opt.dt_min, r.opt.dt_max);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGHUP, on_signal);

    printf("stableTimeStep: case %s, %zu fluid regions, endTime %g s\n", r.opt.case_dir,
           r.base.nregions, r.end_time);
    printf("  stable: exit 0, max %s < %g %%, no particle outside the tank\n",
           sts_measure_name(r.opt.measure), r.opt.bound);
    printf("  deltaT in [%g, %g] s to %g %%, %d trials at a time with %d threads each\n",
           r.opt.dt_min, r.opt.dt_max, 100 * r.opt.tolerance, r.opt.jobs, r.opt.threads);
    fflush(stdout);
    run_pool(&r, 1);
    run_common(&r);
    sts_table_write(&r);

    int unavailable = 0;
    for (size_t m = 0; m < r.nsearch; m++) unavailable += r.search[m].unavailable;
    for (size_t i = 0; i < r.ntrial; i++) sts_trial_free(&r.trial[i]);
    for (size_t m = 0; m < r.opt.nmethods; m++) free(r.opt.methods[m]);
    free(r.opt.methods);
    free(r.trial);
    free(r.search);
    free(trials);
    free(common);
    free(r.out_dir);
    free(r.solver);
    free(self);
    free(pp);
    case_free(&r.base);
    return unavailable ? 3 : 0;
}
