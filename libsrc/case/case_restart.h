/*
 * case_restart: what a restart needs, at full precision, in a file of its
 * own inside each time directory: <time>/uniform/restart (gzip, zlib), as
 * OpenFOAM keeps <time>/uniform/time.  It holds the step state
 * (pcs_snapshot: positions, velocities and ids in memory order, time, step,
 * deltaT) and the time-step controller's state as an opaque block, so that
 * a run stopped and restarted from it continues bit-identically.
 */
#ifndef SL_CASE_RESTART_H
#define SL_CASE_RESTART_H

#include <stddef.h>

#include "core/sl_log.h"
#include "solver/pcs_snapshot.h"

/* Write into `dir` (created if needed) the file uniform/restart. */
int rst_write(const char *dir, const pcs_snapshot *s, const void *ctrl, size_t ctrl_size,
              sl_err *err);
/* Read <dir>/uniform/restart into s; ctrl must be ctrl_size bytes. */
int rst_read(const char *dir, pcs_snapshot *s, void *ctrl, size_t ctrl_size, sl_err *err);

#endif
