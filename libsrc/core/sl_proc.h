/*
 * sl_proc: the one way a Sluice program starts another one (the solver
 * runs of sweepCase and stableTimeStep, gnuplot for the plotting tools).
 *
 * fork + execvp, with the child's folder, its stdout and stderr sent to a
 * log file, its stdin from a file or a pipe, and one environment variable
 * set.  A program that cannot be run (not found, not executable) is
 * reported to the caller as an error ("cannot run gnuplot: No such file or
 * directory"), through a close-on-exec pipe, instead of a child exiting
 * 127 that the caller must interpret.
 */
#ifndef SL_PROC_H
#define SL_PROC_H

#include <stddef.h>
#include <stdio.h>
#include <sys/types.h>

#include "core/sl_log.h"

typedef struct sl_proc {
    const char *const *argv; /* argv[0]: a path, or a name looked up in PATH; NULL-terminated */
    const char *dir;         /* run in this folder (NULL: the current one) */
    const char *log;         /* stdout and stderr into this file, truncated (NULL: inherited) */
    const char *input;       /* stdin from this file ("/dev/null"; NULL: inherited) */
    int pipe_input;          /* stdin from a pipe instead: sl_proc_start gives its write end */
    const char *env_name;    /* set in the child (NULL: none) */
    const char *env_value;
} sl_proc;

/* Start p; returns the child's pid, or -1 with err filled (fork failed,
 * the folder, log or input cannot be opened, the program cannot be run).
 * With pipe_input, *to gets the pipe to the child's stdin (fclose it to
 * end the input). */
pid_t sl_proc_start(const sl_proc *p, FILE **to, sl_err *err);

/* Wait for the child (retrying on EINTR); with nohang only look.  Returns
 * 1 when it has ended (*status set as by waitpid), 0 while it runs
 * (nohang), -1 with err filled. */
int sl_proc_wait(pid_t pid, int *status, int nohang, sl_err *err);

/* Start and wait; returns 0 with *status set, -1 with err filled. */
int sl_proc_run(const sl_proc *p, int *status, sl_err *err);

/* Whether status is a clean exit 0. */
int sl_proc_ok(int status);

/* "exit status 3", "killed by signal 9" */
void sl_proc_describe(int status, char *buf, size_t len);

#endif
