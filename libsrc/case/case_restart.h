/*
 * case_restart: what a restart needs, at full precision, in a file of its
 * own inside each time directory: <time>/uniform/restart (gzip, zlib), as
 * OpenFOAM keeps <time>/uniform/time.  It holds one or more step states
 * (pcs_snapshot: positions, velocities and ids in memory order, time, step,
 * deltaT) -- the state written and the state at the start of the step
 * before it, which a shock right after the restart goes back to -- and the
 * run's other state (time-step controller, emitters, write schedule) as an
 * opaque block, so that a run stopped and restarted from it continues
 * bit-identically.  The gzip trailer's CRC-32 covers every byte: a read
 * goes to the end of the file, so any damage is found before a restart.
 */
#ifndef SL_CASE_RESTART_H
#define SL_CASE_RESTART_H

#include <stddef.h>

#include "core/sl_log.h"
#include "core/sl_source.h"
#include "solver/pcs_snapshot.h"

#define RST_MAX_SNAPSHOTS 2

typedef enum {
    RST_OK,
    RST_MISSING,       /* no restart file (or it cannot be opened) */
    RST_OTHER_VERSION, /* a restart file of another version of Sluice */
    RST_MISMATCH,      /* written for a different case (its other state differs in size) */
    RST_DAMAGED        /* truncated or corrupt */
} rst_status;

/* Write into `dir` (created if needed) the file uniform/restart with
 * nsnaps (1..RST_MAX_SNAPSHOTS) snapshots, the first the state at the
 * directory's time, and ctrl (ctrl_size bytes). */
int rst_write(const char *dir, const pcs_snapshot *const *snaps, int nsnaps, const void *ctrl,
              size_t ctrl_size, sl_err *err);
/* One snapshot as the writer reads it: its header, and its seven arrays
 * (x, y, z, vx, vy, vz: n doubles each; id: n uint32) from sources, read
 * in bounded pieces (-parallel's domain mode streams them from the ranks,
 * solver/pcs_domain.h).  rst_write is rst_write_states of the snapshots'
 * arrays: the same pieces, so the same bytes. */
typedef struct rst_state {
    size_t n;
    double time, dt;
    long step;
    sl_source col[7];
} rst_state;
int rst_write_states(const char *dir, const rst_state *states, int nstates, const void *ctrl,
                     size_t ctrl_size, sl_err *err);
/* The state of a snapshot in memory (its sources read s's arrays). */
void rst_state_of(rst_state *st, const pcs_snapshot *s);

/* Read <dir>/uniform/restart: up to max snapshots into snaps[] (their
 * number into *nsnaps), and the other state into ctrl, which must be
 * ctrl_size bytes (ctrl NULL: any size, not kept -- to check a file).
 * Returns RST_OK, or the status with err saying what is wrong. */
rst_status rst_read(const char *dir, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                    size_t ctrl_size, sl_err *err);

#endif
