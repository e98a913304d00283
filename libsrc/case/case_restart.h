/*
 * case_restart: what a restart needs, at full precision, in a file of its
 * own inside each time directory: <time>/uniform/restart, as OpenFOAM
 * keeps <time>/uniform/time.  It holds one or more step states
 * (pcs_snapshot: positions, velocities, ids, and the pressure and density
 * each particle carries to the next step, in memory order, time, step,
 * deltaT) -- the state written and the state at the start of the step
 * before it, which a shock right after the restart goes back to -- the
 * boundary particles' pressure, p / rho^2 and density (carried between
 * steps too: the warm start of pressureSource divergence and mixed starts
 * from them, and every boundary particle keeps the last values it was
 * given, which boundary.vtu shows), and the run's other state (time-step
 * controller, emitters, write schedule) as an opaque block, so that a run
 * stopped and restarted from it continues bit-identically.
 *
 * Format 4 (SLUICE-RESTART-4, written since 2026-12-04 22:00 UTC) is
 * format 3 with the carried fields; format 3 (SLUICE-RESTART-3) has no p,
 * rho nor boundary, and still restarts (the warm start then starts from
 * p = 0: the log says so).  Both are a sequence of gzip members, so that
 * `zcat` and `gzip -t` read them as one file:
 *
 *   head    magic, number of states, run-state size, RST_RECORDS, and
 *           each state's header (n, time, dt, step); format 4: the number
 *           of boundary records;
 *   pieces  for each state, each field (x, y, z, vx, vy, vz: doubles; id:
 *           uint32; format 4: p, rho: doubles) in pieces of RST_RECORDS
 *           records, each piece its own member (records [p R, (p + 1) R)
 *           of that field); format 4: after the first state's pieces
 *           the boundary's fields (id: uint32; p, pt = p / rho^2, rho:
 *           doubles) in the serial run's memory order (by cell and
 *           creation index: the order boundary.vtu lists them in), in
 *           pieces alike;
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
 * Format 2 (SLUICE-RESTART-2, one gzip stream of format 3's fields, whose
 * trailer's CRC-32 covers every byte) is still read (case_restart_v2.h).
 * SLUICE_RESTART_FORMAT=2 or 3 writes those formats (for a Sluice that
 * reads only them, and for the tests of their readers).
 * Numbers are stored in the machine's byte order (x86-64: little-endian).
 */
#ifndef SL_CASE_RESTART_H
#define SL_CASE_RESTART_H

#include <stddef.h>

#include "core/sl_log.h"
#include "core/sl_source.h"
#include "solver/pcs_snapshot.h"

#define RST_MAX_SNAPSHOTS 2
#define RST_FIELDS        9 /* a state's: x, y, z, vx, vy, vz, id, p, rho */
#define RST_BFIELDS       4 /* the boundary's: id, p, pt, rho */

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
/* One snapshot as the writer reads it: its header, and its nine arrays
 * (x, y, z, vx, vy, vz: n doubles each; id: n uint32; p, rho: n doubles)
 * from sources, read in bounded pieces (-parallel's domain mode streams
 * them from the ranks, solver/pcs_domain.h); the boundary's (id: uint32;
 * p, pt, rho: doubles) likewise.  rst_write is rst_write_states of the
 * snapshots' arrays without a boundary: the same pieces, so the same
 * bytes. */
typedef struct rst_state {
    size_t n;
    double time, dt;
    long step;
    sl_source col[RST_FIELDS];
} rst_state;
typedef struct rst_bstate {
    size_t n;
    sl_source col[RST_BFIELDS];
} rst_bstate;
/* bnd: NULL, none (0 boundary records). */
int rst_write_states(const char *dir, const rst_state *states, int nstates, const rst_bstate *bnd,
                     const void *ctrl, size_t ctrl_size, sl_err *err);
/* The state of a snapshot in memory (its sources read s's arrays), and of
 * a boundary in memory (its n particles in its order). */
void rst_state_of(rst_state *st, const pcs_snapshot *s);
void rst_bstate_of(rst_bstate *st, const sl_boundary *b);

/* Read <dir>/uniform/restart: up to max snapshots into snaps[] (their
 * number into *nsnaps; carried 0 when the file has no p and rho: formats
 * 2 and 3), and the other state into ctrl, which must be ctrl_size bytes
 * (ctrl NULL: any size, not kept -- to check a file; the boundary's pieces
 * are checked too).  Returns RST_OK, or the status with err saying what is
 * wrong. */
rst_status rst_read(const char *dir, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                    size_t ctrl_size, sl_err *err);

/* A restart file read in bounded chunks (-parallel's set-up in parts,
 * case_part.h: no rank holds the whole file's state).  rst_probe keeps only
 * the snapshots' headers (n, time, dt, step: into snaps[], their arrays
 * left empty) and the other state; formats 3 and 4: it reads the tail, head,
 * index and run state (their CRC-32s checked), not the pieces; format 2:
 * it reads the whole file through (its CRC-32 checked, as rst_read).
 * rst_scan then calls fn for snapshot k's records in file order, at most
 * RST_CHUNK at a time, as sel selects them (NULL: every record, every
 * field); a damaged piece is an error naming the file.  fn's arrays: x,
 * y, z, vx, vy, vz, p, rho (a[3..7] and id NULL when sel asks for
 * positions; a[6..7] NULL when the file has no p and rho). */
#define RST_CHUNK   16384
#define RST_RECORDS 8192 /* records per piece (formats 3 and 4): 64 KiB of doubles */
rst_status rst_probe(const char *dir, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                     size_t ctrl_size, sl_err *err);
typedef void (*rst_chunk_fn)(void *ctx, size_t n, const double *const a[8], const uint32_t *id);
typedef struct rst_select {
    int positions; /* x, y, z only */
    /* parts > 1: only the records of part `part` (0 .. parts - 1): the
     * blocks [B part / parts, B (part + 1) / parts) of the B blocks of the
     * file's pieces (format 2: of RST_RECORDS records); the parts of 0 ..
     * parts - 1 are every record once */
    int part, parts;
    /* NULL, or whether a record within [lo, hi] (the box of a block's
     * positions, from the index) may be wanted: blocks it refuses are not
     * decompressed (formats 3 and 4; format 2 reads them all) */
    int (*box)(void *ctx, const double lo[3], const double hi[3]);
    /* NULL, or whether the record at (x, y, z) is wanted: a block with none
     * has only its positions decompressed (formats 3 and 4) */
    int (*want)(void *ctx, double x, double y, double z);
} rst_select;
int rst_scan(const char *dir, const pcs_snapshot *snaps, int k, const rst_select *sel,
             rst_chunk_fn fn, void *ctx, sl_err *err);
/* The boundary's records (format 4), in file order, one piece at a time:
 * *n the number in the file, set before fn is first called (0 for
 * formats 2 and 3: fn is not called); 1 on an error (a damaged piece),
 * naming the file. */
typedef void (*rst_bchunk_fn)(void *ctx, size_t n, const uint32_t *id, const double *p,
                              const double *pt, const double *rho);
int rst_scan_boundary(const char *dir, rst_bchunk_fn fn, void *ctx, size_t *n, sl_err *err);
/* rst_probe and rst_scan keep a file of format 3 or 4 open, its index read,
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
