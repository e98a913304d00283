/*
 * sts: the parts of stableTimeStep -- one trial run of the solver
 * (sts_trial.c), the bisection of each method's time step (sts_search.c)
 * and the tables of results (sts_table.c).
 *
 * The study is the one of Ihmsen et al. 2010, Sec. 4.1: for each boundary
 * method, the largest constant time step for which the run keeps the
 * average volume compression below a bound (1 %) at every step.  By
 * default the compression is volErrAvg of timeStep.dat: the density with
 * the wall's share from the boundary particles, the same measure for every
 * method (becker2009 solves without the wall's density, so its own
 * rhoErrAvg cannot see fluid pressed into a wall); -measure rhoErrAvg
 * judges each method by its own density instead.  We also require that the solver exits 0 and that no
 * fluid particle has left the fluid space through a wall at the end.
 *
 * A trial is a copy of the case's system/ and constant/ in
 * postProcessing/stableTimeStep/trials/<method>_<deltaT>/ with `method`,
 * `mode constant`, `deltaT` (and endTime, writeInterval) set in place by
 * libsrc/dictedit.  It is stopped (SIGKILL to its own pid) as soon as its
 * record shows a step above the bound: the rest of such a run cannot change
 * the verdict.
 *
 * The search assumes that stability is monotonic in deltaT.  Its bracket is
 * recomputed from all finished trials of the method: hi is the smallest
 * unstable deltaT, lo the largest stable one below hi, so a non-monotonic
 * result makes the answer more conservative, never less.
 */
#ifndef STS_H
#define STS_H

#include <stddef.h>
#include <sys/types.h>
#include <time.h>

#include "case/case.h"

typedef enum sts_status {
    STS_PENDING, /* planned, not started */
    STS_RUNNING,
    STS_STABLE,      /* exit 0, max rhoErrAvg below the bound, no particle lost */
    STS_UNSTABLE,    /* anything else the solver did */
    STS_UNAVAILABLE, /* the solver does not know the method ("is not one of") */
    STS_CANCELLED    /* made useless by another trial of the same method */
} sts_status;

/* The column of timeStep.dat a trial is judged by. */
enum { STS_VOL_ERR_AVG, STS_RHO_ERR_AVG };
const char *sts_measure_name(int measure);

typedef struct sts_trial {
    size_t method; /* index into sts_run.search */
    double dt;
    int common; /* a run at the common deltaT (pictures), not a search trial */
    char *dir, *record, *log;
    sts_status status;
    pid_t pid;
    struct timespec start;
    double wall; /* s, elapsed time of the process */
    /* From the record (steps with shock 1 are not counted). */
    long record_offset; /* bytes of the record read so far */
    long steps;
    double iterations;    /* sum over steps */
    double err_avg_max;   /* max over steps of the measure judged, percent */
    double t_err_avg_max; /* time of that step */
    double own_avg_max;   /* max over steps of rhoErrAvg (the method's own density) */
    double vol_avg_max;   /* max over steps of volErrAvg (with the wall's density) */
    double t_reached;
    long lost; /* particles outside the fluid space at the end, -1 unknown */
    char reason[512];
} sts_trial;

typedef struct sts_search {
    char method[32];
    double lo, hi;   /* bracket of the largest stable deltaT */
    int lo_stable;   /* lo was run and is stable */
    int hi_unstable; /* hi was run and is unstable */
    long best;       /* the trial at lo (lo_stable), else -1 */
    long worst;      /* the trial at hi (hi_unstable), else -1 */
    int ntrials;     /* trials finished (cancelled ones not counted) */
    int done, unavailable;
    int nonmonotonic; /* a stable deltaT above an unstable one was seen */
} sts_search;

typedef struct sts_options {
    const char *case_dir;
    char **methods;
    size_t nmethods;
    double end_time; /* <= 0: the case's */
    double bound;    /* percent */
    int measure;     /* STS_VOL_ERR_AVG or STS_RHO_ERR_AVG */
    double dt_min, dt_max, tolerance;
    int jobs, threads;
    double common_dt; /* 0: the smallest stable deltaT found; < 0: no common runs */
} sts_options;

typedef struct sts_run {
    sts_options opt;
    sl_case base;    /* the case as read (geometry, start time) */
    char *out_dir;   /* <case>/postProcessing/stableTimeStep */
    char *solver;    /* pcisph beside this program */
    double end_time; /* of every trial */
    double common_dt;
    sts_search *search;
    size_t nsearch;
    sts_trial *trial;
    size_t ntrial, cap;
} sts_run;

/* ---- sts_trial.c ---- */

/* Add a pending trial of search m at dt; returns its index. */
size_t sts_trial_add(sts_run *r, size_t m, double dt, int common);
/* Clone the case for trial t, set its dictionary entries and start the
 * solver with `threads` OpenMP threads. */
void sts_trial_start(sts_run *r, sts_trial *t, int threads);
/* Read the new rows of a running trial's record; stops the run when a step
 * is above the bound.  Returns 1 if it was stopped. */
int sts_trial_monitor(const sts_run *r, sts_trial *t);
/* The run of trial t has ended with waitpid status `status`: judge it. */
void sts_trial_finish(const sts_run *r, sts_trial *t, int status);
/* Stop a running trial (SIGKILL to its pid, then reaped) or drop a pending
 * one: it is no longer needed. */
void sts_trial_cancel(sts_trial *t, const char *why);
void sts_trial_free(sts_trial *t);
const char *sts_status_name(sts_status s);
/* Fluid particles of a fluid.vtu that are not in the fluid space of the
 * case: not finite, beyond a closed face of a container or inside another
 * shape.  -1 (err filled) if the file cannot be read. */
long sts_count_lost(const sl_case *c, const char *vtu, double *time, sl_err *err);

/* ---- sts_search.c ---- */

void sts_search_init(sts_search *s, const char *method, double dt_min, double dt_max);
/* Plan the next round of search m: up to k new trials.  Marks the search
 * done when its bracket is closed.  Returns the number of trials added. */
size_t sts_search_plan(sts_run *r, size_t m, size_t k);
/* Update the bracket of search m from its finished trials and cancel its
 * trials in flight that can no longer narrow it. */
void sts_search_update(sts_run *r, size_t m);
/* The deltaT nearest to dt that divides span: span / round(span / dt). */
double sts_snap_dt(double span, double dt);

/* ---- sts_table.c ---- */

/* The deltaT reported for [Ihmsen et al. 2010] Sec. 4.1 for a method, or 0. */
double sts_paper_dt(const char *method);
/* Print the table and write stableTimeStep.md, stableTimeStep.csv and
 * trials.csv into r->out_dir. */
void sts_table_write(const sts_run *r);

#endif
