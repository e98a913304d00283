/*
 * case_restart: what a restart needs, at full precision, in a file of its
 * own inside each time directory: <time>/uniform/restart, as OpenFOAM
 * keeps <time>/uniform/time.  It holds one or more step states
 * (pcs_snapshot: positions, velocities and ids in memory order, time, step,
 * deltaT) -- the state written and the state at the start of the step
 * before it, which a shock right after the restart goes back to -- and the
 * run's other state (time-step controller, emitters, write schedule) as an
 * opaque block, so that a run stopped and restarted from it continues
 * bit-identically.
 *
 * Format 3 (SLUICE-RESTART-3, written since 2026-12-04) is a sequence of
 * gzip members, so that `zcat` and `gzip -t` read it as one file:
 *
 *   head    magic, number of states, run-state size, RST_RECORDS, and
 *           each state's header (n, time, dt, step);
 *   pieces  for each state, each field (x, y, z, vx, vy, vz: doubles; id:
 *           uint32) in pieces of RST_RECORDS records, each piece its own
 *           member (records [p R, (p + 1) R) of that field);
 *   index   one entry per piece in file order: its offset, length, the
 *           CRC-32 of its bytes, the least and largest value it holds;
 *   state   the run's other state;
 *   tail    an uncompressed (stored) member of fixed size at the very end:
 *           where the head, index and state members are, the CRC-32s of
 *           their bytes.
 *
 * The pieces depend on the records only (not on who fed the writer), so
 * the file is the same bytes whatever rank count wrote it.  A reader finds
 * the tail at the end, checks it, reads the index, and can then decompress
 * only the pieces of the records it wants: a rank of -parallel's set-up in
 * parts (case_part.h) reads its share of the positions to count the rows,
 * and then the pieces holding its own records.  A member's bytes are
 * checked against the CRC-32 the index (or the tail) records before it is
 * decompressed, and its data against its own gzip trailer after; the tail
 * is checked whole and says where every member ends: so any damaged byte,
 * a short file or bytes after the tail are refused, naming the file (and
 * the state, field and records of a damaged piece).
 *
 * Format 2 (SLUICE-RESTART-2, one gzip stream of the same fields, whose
 * trailer's CRC-32 covers every byte) is still read (case_restart_v2.h),
 * and written when the environment sets SLUICE_RESTART_FORMAT=2.
 * Numbers are stored in the machine's byte order (x86-64: little-endian).
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

/* A restart file read in bounded chunks (-parallel's set-up in parts,
 * case_part.h: no rank holds the whole file's state).  rst_probe keeps only
 * the snapshots' headers (n, time, dt, step: into snaps[], their arrays
 * left empty) and the other state; format 3: it reads the tail, head,
 * index and run state (their CRC-32s checked), not the pieces; format 2:
 * it reads the whole file through (its CRC-32 checked, as rst_read).
 * rst_scan then calls fn for snapshot k's records in file order, at most
 * RST_CHUNK at a time, as sel selects them (NULL: every record, every
 * field); a damaged piece is an error naming the file.  fn's arrays: x,
 * y, z, vx, vy, vz (a[3..5] and id NULL when sel asks for positions). */
#define RST_CHUNK   16384
#define RST_RECORDS 8192 /* records per piece (format 3): 64 KiB of doubles */
rst_status rst_probe(const char *dir, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                     size_t ctrl_size, sl_err *err);
typedef void (*rst_chunk_fn)(void *ctx, size_t n, const double *const a[6], const uint32_t *id);
typedef struct rst_select {
    int positions; /* x, y, z only */
    /* parts > 1: only the records of part `part` (0 .. parts - 1): the
     * blocks [B part / parts, B (part + 1) / parts) of the B blocks of the
     * file's pieces (format 2: of RST_RECORDS records); the parts of 0 ..
     * parts - 1 are every record once */
    int part, parts;
    /* NULL, or whether a record within [lo, hi] (the box of a block's
     * positions, from the index) may be wanted: blocks it refuses are not
     * decompressed (format 3; format 2 reads them all) */
    int (*box)(void *ctx, const double lo[3], const double hi[3]);
    /* NULL, or whether the record at (x, y, z) is wanted: a block with none
     * has only its positions decompressed (format 3) */
    int (*want)(void *ctx, double x, double y, double z);
} rst_select;
int rst_scan(const char *dir, const pcs_snapshot *snaps, int k, const rst_select *sel,
             rst_chunk_fn fn, void *ctx, sl_err *err);
/* rst_probe and rst_scan keep a file of format 3 open, its index read,
 * for the scans of the same file that follow (the file must not change
 * meanwhile): rst_scan_end closes it (so do rst_read, another probe and
 * the writers). */
void rst_scan_end(void);

/* What this process's reads of restart files cost so far: bytes
 * decompressed (a format 2 stream's skips included), compressed bytes
 * read, and the wall and CPU seconds inside rst_read, rst_probe and
 * rst_scan. */
typedef struct rst_counts {
    double inflated, read, wall, cpu;
} rst_counts;
rst_counts rst_counters(void);

#endif
