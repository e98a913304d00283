/*
 * case_lock: one solver per case.  The solver holds an flock(2) on
 * <case>/.sluice.lock, which holds its pid, host and start time, for as long
 * as it runs; the kernel drops the lock when the process ends, however it
 * ends (kill -9 included), so a lock is never stale.  A second solver in
 * the same case is refused with the first one's pid and host.
 */
#ifndef SL_CASE_LOCK_H
#define SL_CASE_LOCK_H

#include "core/sl_log.h"

typedef struct case_lock {
    int fd; /* -1 when not held */
    char *path;
} case_lock;

/* Take the lock of case `dir`; returns 0, or nonzero with err naming the
 * holder ("case <dir> is being run by pcisph (pid 1234 on host h since
 * ...)") or why the lock file cannot be made. */
int case_lock_take(case_lock *l, const char *dir, sl_err *err);
/* Release it and remove the lock file. */
void case_lock_release(case_lock *l);

#endif
