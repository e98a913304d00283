/*
 * fo_post: what the post-processing tools need to run function objects on
 * written results instead of a live run.
 *
 * Time selection, as OpenFOAM's -time option: a comma-separated list of
 * times and ranges, "0.5", "0.5:1", ":0.2" (up to), "0.8:" (from), e.g.
 * "0,0.5:1".  Times match a time directory within 1e-9 (1 + |t|).
 *
 * A snapshot is a state (and its pcs_view) rebuilt from <case>/<time>/fluid.vtu (and
 * boundary.vtu when FO_NEED_BOUNDARY is asked for): rho0, r0, gravity from
 * the case, fluid mass rho0 r0^3 and h = 2 r0 as in pcs_init, the written
 * positions, velocities, pressures and densities, the boundary's written
 * pressures, densities and masses, a neighbour grid over the particles'
 * bounding box with both sets sorted, and the boundary -> fluid lists (which
 * mark active boundary particles).  It is what the solver holds at that
 * write time, as far as the function objects can tell.
 */
#ifndef SL_FO_POST_H
#define SL_FO_POST_H

#include "case/case.h"
#include "core/sl_log.h"
#include "io/time_dir.h"
#include "solver/pcisph.h"

/* Time directories of the case holding fluid.vtu, filtered by spec (NULL:
 * all) or only the latest (latest != 0).  Returns 0, or nonzero with err
 * filled (malformed spec, no matching time). */
int fo_post_times(const char *case_dir, const char *spec, int latest, tdir_list *out, sl_err *err);

typedef struct fo_snapshot {
    sl_fluid f;
    sl_boundary b;
    nbr_grid grid;
    nbr_list bf;
    uint32_t *active;
    size_t nactive;
    pcs_view v; /* what the function objects read */
} fo_snapshot;

/* Load <case>/<tname>/ into sn (needs: FO_NEED_*).  Returns 0, or nonzero
 * with err naming the file (unreadable, missing array, wrong sizes). */
int fo_snapshot_load(fo_snapshot *sn, const sl_case *c, const char *tname, unsigned needs,
                     sl_err *err);
void fo_snapshot_free(fo_snapshot *sn);

#endif
