/*
 * vtk_collection: the time index of a run for ParaView, written two ways
 * because readers differ: a ".pvd" Collection and a "<name>.vtu.series" JSON
 * file-series.  Both are rewritten whole, atomically (temp + fsync + rename),
 * at every output time, so a reader never sees a half-written index.
 */
#ifndef VTK_COLLECTION_H
#define VTK_COLLECTION_H

#include <stddef.h>

#include "core/sl_log.h"

/* Rewrite the .pvd at pvd_path and the series file at series_path (either may
 * be NULL to skip it) listing n (times[i], files[i]) pairs in the order given.
 * files[i] are written as given and must be relative to the folder of the
 * .pvd / series file (keep both in the same folder), e.g. "0.1/fluid.vtu".
 * Times must be finite; they are written as the shortest decimal that reads
 * back exactly.  Returns 0, or nonzero with err filled. */
int vtk_collection_write(const char *pvd_path, const char *series_path, const double *times,
                         const char *const *files, size_t n, sl_err *err);

#endif
