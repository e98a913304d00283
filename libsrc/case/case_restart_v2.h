/*
 * case_restart_v2: the restart file of format 2 (SLUICE-RESTART-2), the
 * format before the pieces of format 3 (case_restart.c): one gzip stream
 * of the header, each snapshot (its header, then x of every particle, y,
 * ..., id: field-major) and the run's other state, the trailer's CRC-32
 * covering every byte.  Kept so that every restart file written before
 * still restarts (rst_read, rst_probe and rst_scan read both formats), and
 * written when SLUICE_RESTART_FORMAT=2 asks for it (for a Sluice that
 * reads format 2 only, and for the tests of this reader).  Internal to
 * case_restart.c.
 */
#ifndef SL_CASE_RESTART_V2_H
#define SL_CASE_RESTART_V2_H

#include <zlib.h>

#include "case/case_restart.h"

#define RST_FAMILY "SLUICE-RESTART-"
#define RST_MAGIC2 RST_FAMILY "2"

/* Write the file `path` in format 2. */
int rst2_write(const char *path, const rst_state *states, int nstates, const void *ctrl,
               size_t ctrl_size, sl_err *err);
/* Read g (opened on `path`, at its start) as rst_read (arrays) or
 * rst_probe (!arrays) do. */
rst_status rst2_read(gzFile g, const char *path, pcs_snapshot *snaps, int max, int *nsnaps,
                     void *ctrl, size_t ctrl_size, int arrays, sl_err *err);
/* rst_scan of a file of format 2: one zlib stream per field, each started
 * at its field (the file decompressed up to each field's end); sel's part
 * is kept, its box and want are not used (fn is given every record of the
 * part). */
int rst2_scan(const char *path, const pcs_snapshot *snaps, int k, const rst_select *sel,
              rst_chunk_fn fn, void *ctx, sl_err *err);
/* The bytes a gzip stream decompressed and read so far (before its close),
 * into the counters of rst_counters. */
void rst_count_gz(gzFile g);

#endif
