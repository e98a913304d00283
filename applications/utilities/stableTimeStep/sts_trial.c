/*
 * sts_trial: one run of the solver at one boundary method and one constant
 * deltaT -- cloned from the case, started, watched through its record
 * timeStep.dat (columns Time deltaT iterations rhoErrAvg rhoErrMax vMax
 * FMax shock ...), stopped early when a step is above the bound, and
 * judged: stable iff the solver exits 0, every step has rhoErrAvg below the
 * bound and no fluid particle of the last fluid.vtu is outside the fluid
 * space of the case.
 */
#include "sts.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_proc.h"
#include "dictedit/dictedit.h"
#include "dictionary/dict.h"
#include "geometry/geometry.h"
#include "io/time_dir.h"
#include "io/vtk_reader.h"

const char *sts_status_name(sts_status s)
{
    switch (s) {
    case STS_PENDING:
        return "pending";
    case STS_RUNNING:
        return "running";
    case STS_STABLE:
        return "stable";
    case STS_UNSTABLE:
        return "unstable";
    case STS_UNAVAILABLE:
        return "unavailable";
    case STS_CANCELLED:
        return "cancelled";
    }
    return "?";
}

size_t sts_trial_add(sts_run *r, size_t m, double dt, int common)
{
    char name[96], tname[32];
    if (r->ntrial == r->cap) {
        r->cap = r->cap ? 2 * r->cap : 64;
        r->trial = sl_realloc(r->trial, r->cap * sizeof *r->trial, "trials");
    }
    sts_trial *t = &r->trial[r->ntrial];
    memset(t, 0, sizeof *t);
    t->method = m;
    t->dt = dt;
    t->common = common;
    t->status = STS_PENDING;
    t->lost = -1;
    t->pid = -1;
    if (common) snprintf(name, sizeof name, "common/%s", r->search[m].method);
    else snprintf(name, sizeof name, "trials/%s_%.6g", r->search[m].method, dt);
    t->dir = cf_join(r->out_dir, name);
    tdir_name(r->base.ctl.start_time, r->base.ctl.time_precision, tname, sizeof tname);
    snprintf(name, sizeof name, "postProcessing/timeStep/%s/timeStep.dat", tname);
    t->record = cf_join(t->dir, name);
    t->log = cf_join(t->dir, "log.pcisph");
    return r->ntrial++;
}

void sts_trial_free(sts_trial *t)
{
    free(t->dir);
    free(t->record);
    free(t->log);
}

/* ---- preparing ---------------------------------------------------------------- */

/* Set `entry` of the trial's `file` to `value`, refused when it is written
 * outside the trial (it would change the case itself). */
static void set_entry(const sts_trial *t, const char *file, const char *entry, const char *value)
{
    char *path = cf_join(t->dir, file);
    sl_err err;
    if (dedit_set_inside(t->dir, path, entry, value, NULL, &err)) sl_fatal("%s", err.msg);
    free(path);
}

static void prepare(const sts_run *r, const sts_trial *t, int threads)
{
    static const char *const inputs[] = {"system", "constant"};
    char v[64];
    sl_err err;
    if (cf_remove_tree(t->dir, &err) || tdir_mkdirs(t->dir, &err)) sl_fatal("%s", err.msg);
    for (size_t k = 0; k < 2; k++) {
        char *src = cf_join(r->opt.case_dir, inputs[k]), *dst = cf_join(t->dir, inputs[k]);
        if (cf_copy_tree(src, dst, &err)) sl_fatal("%s", err.msg);
        free(src);
        free(dst);
    }
    set_entry(t, "constant/boundaryProperties", "method", r->search[t->method].method);
    set_entry(t, "system/timeStepDict", "mode", "constant");
    snprintf(v, sizeof v, "%.6g", t->dt);
    set_entry(t, "system/timeStepDict", "deltaT", v);
    snprintf(v, sizeof v, "%.9g", r->end_time);
    set_entry(t, "system/controlDict", "endTime", v);
    set_entry(t, "system/controlDict", "startFrom", "startTime");
    if (!t->common || r->base.ctl.write_interval > r->end_time - r->base.ctl.start_time) {
        /* a search trial needs only its last state */
        snprintf(v, sizeof v, "%.9g", r->end_time - r->base.ctl.start_time);
        set_entry(t, "system/controlDict", "writeInterval", v);
    }
    snprintf(v, sizeof v, "%d", threads);
    set_entry(t, "system/controlDict", "numberOfThreads", v);
}

void sts_trial_start(sts_run *r, sts_trial *t, int threads)
{
    prepare(r, t, threads);
    clock_gettime(CLOCK_MONOTONIC, &t->start);
    const char *argv[] = {r->solver, "-case", t->dir, "-quiet", NULL};
    sl_proc p = {.argv = argv, .log = t->log};
    sl_err err;
    pid_t pid = sl_proc_start(&p, NULL, &err);
    if (pid < 0) sl_fatal("%s", err.msg);
    t->pid = pid;
    t->status = STS_RUNNING;
}

/* ---- watching ------------------------------------------------------------------ */

static double seconds_since(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - t0->tv_sec) + 1e-9 * (double)(t.tv_nsec - t0->tv_nsec);
}

/* Read the complete rows of the record written since the last call. */
const char *sts_measure_name(int measure)
{
    return measure == STS_RHO_ERR_AVG ? "rhoErrAvg" : "volErrAvg";
}

static void read_record(const sts_run *r, sts_trial *t)
{
    FILE *f = fopen(t->record, "r");
    char *line = NULL;
    size_t cap = 0;
    ssize_t len;
    if (!f) return; /* not written yet */
    if (fseek(f, t->record_offset, SEEK_SET) != 0) {
        fclose(f);
        return;
    }
    while ((len = getline(&line, &cap, f)) > 0) {
        if (line[len - 1] != '\n') break; /* being written: read it next time */
        t->record_offset += (long)len;
        if (line[0] == '#') continue;
        /* Time deltaT iterations rhoErrAvg rhoErrMax vMax FMax shock wallTime
         * controllerDeltaT volErrAvg volErrMax */
        double v[12];
        char *s = line, *end;
        int k;
        for (k = 0; k < 12; k++, s = end) {
            v[k] = strtod(s, &end);
            if (end == s) break;
        }
        if (k < 12 || v[7] != 0.0) continue; /* short row, or a step discarded by a shock */
        const double judged = r->opt.measure == STS_RHO_ERR_AVG ? v[3] : v[10];
        t->steps++;
        t->iterations += v[2];
        t->t_reached = v[0];
        if (!(judged <= t->err_avg_max)) { /* NaN wins */
            t->err_avg_max = judged;
            t->t_err_avg_max = v[0];
        }
        if (!(v[3] <= t->own_avg_max)) t->own_avg_max = v[3];
        if (!(v[10] <= t->vol_avg_max)) t->vol_avg_max = v[10];
    }
    free(line);
    fclose(f);
}

static int above_bound(const sts_run *r, const sts_trial *t)
{
    return t->steps > 0 && !(t->err_avg_max < r->opt.bound);
}

static void set_above_bound_reason(const sts_run *r, sts_trial *t)
{
    snprintf(t->reason, sizeof t->reason, "%s %.4g %% >= %g %% at t = %.4g s",
             sts_measure_name(r->opt.measure), t->err_avg_max, r->opt.bound, t->t_err_avg_max);
}

/* SIGKILL our own child and reap it. */
static void kill_child(sts_trial *t)
{
    int st;
    if (t->pid > 0) {
        kill(t->pid, SIGKILL);
        sl_proc_wait(t->pid, &st, 0, NULL);
    }
    t->pid = -1;
}

int sts_trial_monitor(const sts_run *r, sts_trial *t)
{
    if (t->status != STS_RUNNING) return 0;
    read_record(r, t);
    if (t->common || !above_bound(r, t)) return 0; /* a common run (pictures) goes to the end */
    kill_child(t);
    t->wall = seconds_since(&t->start);
    t->status = STS_UNSTABLE;
    set_above_bound_reason(r, t);
    size_t n = strlen(t->reason);
    snprintf(t->reason + n, sizeof t->reason - n, " (stopped there)");
    return 1;
}

void sts_trial_cancel(sts_trial *t, const char *why)
{
    if (t->status == STS_RUNNING) {
        kill_child(t);
        t->wall = seconds_since(&t->start);
    }
    t->status = STS_CANCELLED;
    snprintf(t->reason, sizeof t->reason, "%s", why);
}

/* ---- judging ------------------------------------------------------------------- */

/* The last "Error: ..." line of the solver's log, without the prefix. */
static void log_error(const sts_trial *t, char *buf, size_t len)
{
    FILE *f = fopen(t->log, "r");
    char *line = NULL;
    size_t cap = 0;
    buf[0] = '\0';
    if (!f) return;
    while (getline(&line, &cap, f) > 0) {
        if (strncmp(line, "Error: ", 7) != 0) continue;
        line[strcspn(line, "\n")] = '\0';
        snprintf(buf, len, "%s", line + 7);
    }
    free(line);
    fclose(f);
}

static int closed_face(const geo_shape *s, int axis, int high)
{
    return !(s->open_faces & (1u << (2 * axis + high)));
}

/* 1 if p is in the fluid space of the case. */
static int in_fluid_space(const sl_case *c, const double p[3])
{
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) return 0;
    for (size_t k = 0; k < c->nshapes; k++) {
        const geo_shape *s = &c->shapes[k];
        if (s->kind == GEO_CONTAINER) {
            for (int d = 0; d < 3; d++) {
                if (p[d] < s->lo[d] && closed_face(s, d, 0)) return 0;
                if (p[d] > s->hi[d] && closed_face(s, d, 1)) return 0;
            }
        } else if (geo_solid_distance(s, p) < 0.0) {
            return 0;
        }
    }
    return 1;
}

long sts_count_lost(const sl_case *c, const char *vtu, double *time, sl_err *err)
{
    vtkr_file f;
    long lost = 0;
    if (vtkr_read(vtu, &f, err)) return -1;
    for (size_t i = 0; i < f.npoints; i++) lost += !in_fluid_space(c, &f.points[3 * i]);
    if (time) *time = f.time;
    vtkr_free(&f);
    return lost;
}

/* Particles outside the fluid space in the newest fluid.vtu of the trial. */
static void check_particles(const sts_run *r, sts_trial *t)
{
    tdir_list l;
    sl_err err;
    t->status = STS_UNSTABLE;
    if (tdir_list_read(t->dir, "fluid.vtu", &l, &err)) {
        snprintf(t->reason, sizeof t->reason, "%.*s", (int)sizeof t->reason - 1, err.msg);
        return;
    }
    if (l.n == 0) {
        snprintf(t->reason, sizeof t->reason, "no time directory with a fluid.vtu");
        tdir_list_free(&l);
        return;
    }
    char *sub = cf_join(t->dir, l.name[l.n - 1]), *vtu = cf_join(sub, "fluid.vtu");
    double tv = l.time[l.n - 1];
    t->lost = sts_count_lost(&r->base, vtu, NULL, &err);
    if (t->lost < 0) {
        snprintf(t->reason, sizeof t->reason, "%.*s", (int)sizeof t->reason - 1, err.msg);
    } else if (tv < r->end_time - 1e-9 * (1.0 + fabs(r->end_time))) {
        snprintf(t->reason, sizeof t->reason, "the last time written is %.6g s, not endTime", tv);
    } else if (t->lost > 0) {
        snprintf(t->reason, sizeof t->reason, "%ld particles outside the tank at t = %.6g s",
                 t->lost, tv);
    } else {
        t->status = STS_STABLE;
        snprintf(t->reason, sizeof t->reason, "max %s %.4g %% at t = %.4g s",
                 sts_measure_name(r->opt.measure), t->err_avg_max, t->t_err_avg_max);
    }
    free(vtu);
    free(sub);
    tdir_list_free(&l);
}

void sts_trial_finish(const sts_run *r, sts_trial *t, int status)
{
    char why[sizeof t->reason - 64];
    t->pid = -1;
    t->wall = seconds_since(&t->start);
    read_record(r, t);
    if (WIFSIGNALED(status)) {
        t->status = STS_UNSTABLE;
        snprintf(t->reason, sizeof t->reason, "the solver was killed by signal %d",
                 WTERMSIG(status));
    } else if (WEXITSTATUS(status) != 0) {
        log_error(t, why, sizeof why);
        t->status = strstr(why, "is not one of") ? STS_UNAVAILABLE : STS_UNSTABLE;
        snprintf(t->reason, sizeof t->reason, "solver exit %d: %s", WEXITSTATUS(status),
                 why[0] ? why : "(no Error line in its log)");
    } else if (above_bound(r, t)) {
        t->status = STS_UNSTABLE;
        set_above_bound_reason(r, t);
    } else {
        check_particles(r, t);
    }
}
