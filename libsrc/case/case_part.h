/*
 * case_part: a rank's part of a case, built without the whole case on any
 * rank (-parallel's domain mode; solver/pcs_domain.h, pcd_plan;
 * doc/parallel.md, "Phase 2").
 *
 * The generators of the case (geometry sampling, region filling) are
 * deterministic, so every rank can make the whole case's particles one at
 * a time and store only some:
 *
 *   census   every particle made, none stored: the counts of the whole
 *            case (fluid, boundary), its checks and bounds (case_build's);
 *   rows     the fluid made again and counted by row of the solver's grid
 *            (or, for a restart, the positions of the file's first state:
 *            each rank counts its part of the records, the counts summed
 *            over the ranks): the cuts, the serial run's cuts, on every
 *            rank alike;
 *   keep     made again, and stored: the fluid of the own rows, the
 *            boundary particles of the rows around them that the set-up
 *            reads (pcd_plan_boundary), with the ids of the whole case;
 *            for a restart the file's records of the own rows instead of
 *            the fluid (and of the state before, for a rollback).
 *
 * So a rank's set-up holds its own share, not the case: the price is the
 * fluid made three times and the boundary twice (a restart file of format
 * 3: each rank decompresses its part of the positions and the pieces
 * holding its own records, case_restart.h; of format 2: the whole file
 * several times over, one stream per field).  initialPacking relaxed relaxes the whole
 * case on every rank before the split (main, relax): such a case (not
 * restarted) is built whole, the documented exception.
 */
#ifndef SL_CASE_PART_H
#define SL_CASE_PART_H

#include "case/case.h"
#include "solver/pcs_domain.h"
#include "solver/pcs_snapshot.h"

/* Whether c is built in parts under -parallel: the domain mode applies
 * (pcd_plan_usable) and no relaxed packing is made (restarting: none);
 * SLUICE_PARALLEL_SETUP=whole builds the whole case on every rank instead
 * (the way before, for comparisons). */
int case_part_applies(const sl_case *c, int restarting);
/* The census: case_build's checks and bounds, every particle made and
 * none stored (c->nfluid, c->nboundary the whole case's; c->part set). */
void case_part_census(sl_case *c);
/* The rows and keep passes.  restart NULL: from the case; else the time
 * directory whose restart file (probed: heads[0..nsnaps), headers only)
 * holds the state (the own records into c->fluid, their carried p and
 * rho too when the file has them), and prev (NULL: not wanted) receives
 * this rank's part of its second snapshot.  Returns the plan for pcs_init_part (free it
 * with pcd_plan_free after). */
pcd_plan *case_part_build(sl_case *c, const char *restart, const pcs_snapshot *heads, int nsnaps,
                          pcs_snapshot *prev);

#endif
