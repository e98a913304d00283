/*
 * pcs_parallel: -parallel's halo mode (doc/parallel.md, "phase 1b"):
 * SLUICE_PARALLEL_EXCHANGE=halo, and the periodic cases the domain mode
 * refuses (pcd_periodic_refusal: moving walls, emitters, two cells of
 * halo, probes and waterGauges).
 *
 * The state stays whole on every rank at the start of a step (every rank
 * sorts, searches and computes the forces of all particles), but within
 * the step each rank computes only its own rows [row[r], row[r+1]): the
 * prediction, the collision, the density and pressure-force passes and
 * the integration.  What its rows read of other ranks' rows is its halo,
 * found at each search from the lists: the fluid neighbours of its rows,
 * and the fluid neighbours of the boundary particles its rows see (whose
 * density and pressure it computes itself, as every rank that sees them
 * does, with the same bits).  Per PCISPH iteration the halo's predicted
 * positions (after the prediction) and p/rho^2 (after the density pass)
 * (and density) are exchanged (MPI_Alltoallv), the density error's block sums are made
 * from every rank's whole blocks and the rows of the blocks it shares
 * (summed in the serial order), and the largest compression is reduced;
 * after the integration the new state (x, v, p, rho and the active
 * boundary's density and pressure) is gathered on every rank once.
 *
 * Periodic images are refreshed from their originals as in the serial
 * code (dom_periodic.h): an image in a rank's lists brings its original
 * into the halo, a boundary image its original into the boundary set.
 * The halo's density travels with its p/rho^2, for the EFF_DENSITY
 * effects of the next pass (surfaceDensityCorrection reads the
 * neighbours' density of the previous pass).  The boundary methods
 * without wall density (becker2009, harada2007) also measure the
 * compression with the wall's share, summed over every row by sl_sum's
 * vectorised blocks: that array is gathered whole after each density
 * pass (one O(N) gather per iteration, where the gather mode has seven).
 * SLUICE_PARALLEL_EXCHANGE=gather selects the gather mode (pcisph.c).  Otherwise,
 * and with SLUICE_PARALLEL_EXCHANGE=gather, the replicated gathers of
 * phase 1 (pcisph.c) are used.
 */
#ifndef SL_PCS_PARALLEL_H
#define SL_PCS_PARALLEL_H

#include "solver/pcisph.h"

/* Whether s (ranks > 1) can run in halo mode. */
int pcx_usable(const pcs_solver *s);
/* After each search (split done): the halo lists, collectively. */
void pcx_build(pcs_solver *s);
/* After the prediction of the own rows: the halo's x*. */
void pcx_exchange_predicted(pcs_solver *s);
/* The block sums part[0..nb) of a per-row array over every rank's rows,
 * in the serial association (SL_REDUCE_BLOCK rows a block, each summed
 * from 0 one row at a time), on every rank; on entry part holds this
 * rank's own blocks' sums as the density pass makes them (rows holds its
 * own rows).  Collective; in the domain mode pcd_block_sums. */
void pcx_block_sums(pcs_solver *s, const double *rows, double *part);
/* After the density pass of the own rows: the block sums of every rank,
 * the halo's p/rho^2; returns the largest compression of all. */
double pcx_after_density(pcs_solver *s, double emax);
/* After the integration of the own rows: the state made whole. */
void pcx_after_integrate(pcs_solver *s);
void pcx_free(pcs_solver *s);

#endif
