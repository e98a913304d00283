/*
 * sweep_run: one case per point -- cloned from the base case, its values
 * set in place with libsrc/dictedit -- and the solver run on them, a few at
 * a time, each writing <case>/log.<application>.  A point whose log holds
 * the solver's closing "End:" line is finished and is not run again; one
 * whose log says it was stopped by a signal is resumed.
 */
#include "sweep.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_proc.h"
#include "core/sl_progress.h"
#include "dictedit/dictedit.h"
#include "dictionary/dict.h"
#include "io/time_dir.h"

static char *sweep_log_path(const sweep *s, const char *dir)
{
    char name[300];
    snprintf(name, sizeof name, "log.%s", s->application);
    return cf_join(dir, name);
}

sweep_status sweep_case_status(const sweep *s, size_t point)
{
    char *dir = sweep_case_dir(s, point), *log = sweep_log_path(s, dir), *line = NULL;
    size_t len = 0;
    sweep_status st = SWEEP_NOT_RUN;
    FILE *f = fopen(log, "r");
    if (f) {
        st = SWEEP_FAILED;
        while (st == SWEEP_FAILED && getline(&line, &len, f) >= 0)
            if (!strncmp(line, "Stopped by a signal", 19) ||
                !strncmp(line, "Stopped by the file stopNow", 27))
                st = SWEEP_STOPPED;
            else if (!strncmp(line, "End:", 4)) st = SWEEP_FINISHED;
        fclose(f);
    }
    free(line);
    free(log);
    free(dir);
    return st;
}

/* ---- preparing a case ------------------------------------------------------------ */

/* path renamed <path><tag><n>, n the first number not taken (nothing
 * overwritten); the new name, allocated. */
static char *keep_numbered(const char *path, const char *tag)
{
    const size_t len = strlen(path) + strlen(tag) + 16;
    char *kept = sl_malloc(len, "kept name");
    for (int n = 1;; n++) {
        snprintf(kept, len, "%s%s%d", path, tag, n);
        if (access(kept, F_OK) != 0) break;
    }
    if (rename(path, kept)) sl_fatal("%s: cannot rename it to %s: %s", path, kept, strerror(errno));
    return kept;
}

/* A failed point's folder (a log without the solver's End: line: it died,
 * or was killed, part-way), before the point is run again: kept as
 * <case>.failed.<n>, so that what it wrote is not deleted. */
static void keep_failed(const sweep *s, size_t point, const char *dir)
{
    char *kept = keep_numbered(dir, ".failed.");
    fprintf(stderr, "%s: the failed run kept as %s\n", s->name[point], kept);
    free(kept);
}

void sweep_prepare(const sweep *s, size_t point)
{
    char *dir = sweep_case_dir(s, point);
    sl_err err;
    if (sweep_case_status(s, point) == SWEEP_FAILED) keep_failed(s, point, dir);
    if (cf_remove_tree(dir, &err) || tdir_mkdirs(s->cases, &err) ||
        cf_clone_case(s->base, dir, NULL, &err))
        sl_fatal("%s", err.msg);
    for (size_t k = 0; k < s->nparam; k++) {
        const sweep_param *p = &s->param[k];
        char *file = cf_join(dir, p->file);
        if (dedit_set_inside(dir, file, p->entry, sweep_value(s, point, k), NULL, &err))
            sl_fatal("case %s: parameter '%s': %s", s->name[point], p->key, err.msg);
        free(file);
    }
    free(dir);
}

char *sweep_solver(const sweep *s)
{
    sl_err err;
    char *bin = cf_self_dir(&err), *solver;
    if (!bin) sl_fatal("%s", err.msg);
    solver = cf_join(bin, s->application);
    free(bin);
    if (access(solver, X_OK) != 0)
        sl_fatal("no solver '%s' beside sweepCase (application '%s' of %s/system/controlDict): "
                 "run make",
                 solver, s->application, s->base);
    return solver;
}

/* ---- the job list ------------------------------------------------------------------- */

/* Writes s for a POSIX shell, quoted only when it has to be. */
static void sweep_shell_word(FILE *f, const char *s)
{
    static const char safe[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                               "0123456789_+-./=:@,";
    if (*s && strspn(s, safe) == strlen(s)) {
        fputs(s, f);
        return;
    }
    fputc('\'', f);
    for (; *s; s++) {
        if (*s == '\'') fputs("'\\''", f);
        else fputc(*s, f);
    }
    fputc('\'', f);
}

/* A stopped point's log, before it is resumed: kept as log.<application>.<n>. */
static void keep_log(const sweep *s, size_t point)
{
    char *dir = sweep_case_dir(s, point), *log = sweep_log_path(s, dir);
    free(keep_numbered(log, "."));
    free(log);
    free(dir);
}

void sweep_print_jobs(const sweep *s, int threads, int force)
{
    char *solver = sweep_solver(s);
    for (size_t i = 0; i < s->npoint; i++) {
        const sweep_status st = sweep_case_status(s, i);
        if (!force && st == SWEEP_FINISHED) {
            fprintf(stderr, "%s: finished already\n", s->name[i]);
            continue;
        }
        const int resume = !force && st == SWEEP_STOPPED;
        if (resume) keep_log(s, i);
        else sweep_prepare(s, i);
        char *dir = sweep_case_dir(s, i), *abs = realpath(dir, NULL);
        char *log = sweep_log_path(s, abs);
        if (threads > 0) printf("OMP_NUM_THREADS=%d ", threads);
        sweep_shell_word(stdout, solver);
        fputs(" -case ", stdout);
        sweep_shell_word(stdout, abs);
        if (resume) fputs(" -resume", stdout);
        fputs(" > ", stdout);
        sweep_shell_word(stdout, log);
        fputs(" 2>&1\n", stdout);
        free(log);
        free(abs);
        free(dir);
    }
    free(solver);
}

/* ---- running ------------------------------------------------------------------------ */

typedef struct sweep_job {
    pid_t pid;
    size_t point;
    struct timespec start;
} sweep_job;

static double sweep_seconds_since(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - t0->tv_sec) + 1e-9 * (double)(t.tv_nsec - t0->tv_nsec);
}

static pid_t sweep_launch(const sweep *s, const char *solver, size_t point, int threads, int resume)
{
    char *dir = sweep_case_dir(s, point), *log = sweep_log_path(s, dir), n[32];
    const char *argv[] = {solver, "-case", dir, resume ? "-resume" : NULL, NULL};
    sl_proc p = {.argv = argv, .log = log};
    sl_err err;
    if (threads > 0) {
        snprintf(n, sizeof n, "%d", threads);
        p.env_name = "OMP_NUM_THREADS";
        p.env_value = n;
    }
    pid_t pid = sl_proc_start(&p, NULL, &err);
    if (pid < 0) sl_fatal("%s", err.msg);
    free(log);
    free(dir);
    return pid;
}

/* "; 3 of 12 done, about 1 min 05 s left": from the mean rate since the
 * sweep started (which counts the cases run side by side). */
static void sweep_eta(char *buf, size_t len, const sl_progress *prog, size_t done, size_t n)
{
    char left[32];
    double el = sl_progress_elapsed(prog);
    if (done >= n) {
        sl_progress_duration(el, left, sizeof left);
        snprintf(buf, len, "; %zu of %zu done, all in %s", done, n, left);
        return;
    }
    sl_progress_duration(el / (double)done * (double)(n - done), left, sizeof left);
    snprintf(buf, len, "; %zu of %zu done, about %s left", done, n, left);
}

static int sweep_report(const sweep *s, const sweep_job *j, int status, size_t done, size_t n,
                        const sl_progress *prog)
{
    double secs = sweep_seconds_since(&j->start);
    char eta[128];
    sweep_eta(eta, sizeof eta, prog, done, n);
    const sweep_status st = sweep_case_status(s, j->point);
    int ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && st == SWEEP_FINISHED;
    if (ok) {
        printf("[%zu/%zu] %s: finished in %.1f s%s\n", done, n, s->name[j->point], secs, eta);
    } else if (st == SWEEP_STOPPED) {
        printf("[%zu/%zu] %s: stopped by a signal after %.1f s, its state written: the next "
               "sweepCase resumes it%s\n",
               done, n, s->name[j->point], secs, eta);
    } else {
        char *dir = sweep_case_dir(s, j->point), *log = sweep_log_path(s, dir);
        if (WIFSIGNALED(status))
            printf("[%zu/%zu] %s: killed by signal %d after %.1f s: see %s%s\n", done, n,
                   s->name[j->point], WTERMSIG(status), secs, log, eta);
        else
            printf("[%zu/%zu] %s: failed (exit status %d) after %.1f s: see %s%s\n", done, n,
                   s->name[j->point], WEXITSTATUS(status), secs, log, eta);
        free(log);
        free(dir);
    }
    fflush(stdout);
    return !ok;
}

int sweep_run(const sweep *s, int jobs, int threads, int force)
{
    size_t *todo = sl_malloc((s->npoint + 1) * sizeof *todo, "sweep points"), ntodo = 0;
    int *resume = sl_calloc(s->npoint + 1, sizeof *resume, "sweep points");
    sweep_job *run = sl_calloc((size_t)jobs, sizeof *run, "sweep jobs");
    size_t next = 0, done = 0;
    int nrun = 0, failed = 0;
    char *solver = sweep_solver(s);
    size_t nresume = 0;
    for (size_t i = 0; i < s->npoint; i++) {
        const sweep_status st = sweep_case_status(s, i);
        if (force || st != SWEEP_FINISHED) todo[ntodo++] = i;
        if (!force && st == SWEEP_STOPPED) resume[i] = 1, nresume++;
    }
    printf("Sweep %s: %zu points, %zu to run (%zu finished already", s->path, s->npoint, ntodo,
           s->npoint - ntodo);
    if (nresume) printf("; %zu stopped by a signal, resumed", nresume);
    printf("), %d at a time", jobs);
    if (threads > 0) printf(", %d threads each", threads);
    printf("\n");
    for (size_t i = 0; i < ntodo; i++) /* errors before any run */
        if (resume[todo[i]]) keep_log(s, todo[i]);
        else sweep_prepare(s, todo[i]);
    sl_progress prog;
    sl_progress_start(&prog, stdout, 0, (double)ntodo, 10.0);
    while (next < ntodo || nrun > 0) {
        while (nrun < jobs && next < ntodo) {
            sweep_job *j = &run[nrun++];
            j->point = todo[next++];
            clock_gettime(CLOCK_MONOTONIC, &j->start);
            j->pid = sweep_launch(s, solver, j->point, threads, resume[j->point]);
        }
        int status, k;
        pid_t pid = waitpid(-1, &status, 0);
        if (pid < 0) {
            if (errno == EINTR) continue;
            sl_fatal("waiting for the solver runs: %s", strerror(errno));
        }
        for (k = 0; k < nrun && run[k].pid != pid; k++) continue;
        if (k == nrun) continue; /* not one of ours */
        failed += sweep_report(s, &run[k], status, ++done, ntodo, &prog);
        run[k] = run[--nrun];
    }
    free(solver);
    free(run);
    free(resume);
    free(todo);
    return failed;
}
