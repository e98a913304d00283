/*
 * pcs_domain: -parallel's domain mode (doc/parallel.md, "phase 2"), the
 * default where it applies (pcd_usable; a periodic case but for what
 * pcd_periodic_refusal names).
 *
 * Ownership by position.  The grid's cells are numbered unit by unit
 * (neighbours.h, SLUICE_GRID_UNIT: whole x-rows of cells, the rows in
 * Morton order of (y, z), or blocks of cells along a Hilbert curve); rank
 * r owns the units [cut[r], cut[r+1]) of that order (cut where the fluid
 * counts balance), and so the fluid particles in them.  Because the fluid
 * is sorted by the key (cell, id), a rank's own particles are a
 * contiguous range of the serial run's sorted array, and its own plus
 * halo particles a sub-sequence of it.  ("Rows" below: the own units.)
 *
 * Storage: between steps a rank holds its own particles only; at the start
 * of a step (before the sort) particles whose cell left its rows migrate
 * to their new owner, and the halo is received from its owners: the
 * particles of the cells within one cell of the own cells (with rows:
 * the rows within one cell in y and z of the own rows).  The
 * neighbour lists over that window hold each own particle's serial
 * neighbours in the serial order, so every per-particle sum is the serial
 * sum.  The boundary particles are distributed by cell as well: a rank
 * stores those of its own rows and of its halo rows; the active ones in
 * its own cells (whose lists are complete) are computed by it and their
 * p/rho^2 sent to the ranks whose rows see them, so their owner holds
 * their serial density and pressure; walls that move carry them across
 * the rows, and they then migrate to their new owner with all their
 * fields (pcd_distribute; also when rebalancing moves the cuts).  Surface
 * tension reads its neighbours' normals: with it the halo is two cells
 * deep and every rank computes the boundary particles its rows see.
 *
 * Periodic axes (domain/dom_periodic.h): the images of a particle within
 * h of a periodic face lie across the period, in pieces another rank may
 * own.  A rank's halo also holds every piece one of whose *image pieces*
 * (the pieces a band of it within h of a face, shifted by the period,
 * meets: conservative, a cell more either way) is an own or halo piece of
 * the rank; the exchanges (migration, halo, x*, p/rho^2 and rho, the
 * boundary's p/rho^2) need nothing else.  After the sort each rank makes
 * the images of its own and halo particles (dom_fluid_images): its
 * particles are a sub-sequence of the serial sorted array, and the images
 * are sorted by cell stably in that order, so the images an own row sees
 * are the serial ones in the serial order.  They are refreshed from their
 * originals when the halo's values arrive (pcd_wait); the rows reading an
 * image (fluid or boundary) are border rows of the overlap.  The boundary
 * images are boundary particles of their cells as any other, their
 * values refreshed from their originals, which the rank stores (an image
 * piece of the original's piece); they are not written.  Positions are
 * wrapped after the integration, so a particle crossing a periodic face
 * migrates to the owner of the cells it enters.
 *
 * Per PCISPH iteration: x* of the halo after the prediction, p/rho^2 and
 * rho after the density pass (and the boundary's p/rho^2, in the same
 * message), point-to-point from the owners (par_exchange_start / wait:
 * the passes compute the own rows whose lists hold no halo particle while
 * the messages travel, then the others); the density error's block sums in the serial
 * order (the blocks of SL_REDUCE_BLOCK rows of the serial array, made
 * from every rank's whole blocks and the rows of the blocks it shares);
 * the largest compression by a max-reduction.
 *
 * Rebalancing: when the largest rank's count passes the mean by more than
 * SLUICE_PARALLEL_REBALANCE (a fraction, default 0.05), the cuts are
 * computed again from the global counts per row (one reduction of a count
 * per row) and the particles move by the migration of the next step.
 *
 * Output and function objects: time directories and restart files are
 * streamed to rank 0 in the serial order (pcd_output_begin); probes and
 * gauges get on rank 0 the particles near their points (pcd_gather_near;
 * pcd_gather, the whole state, for an object reading every particle
 * otherwise: none does), each boundary particle from its owner, sorted
 * again on rank 0 by (cell, creation index), the serial order;
 * densityError and energy reduce each rank's own rows (pcd_sum_rows,
 * pcd_sum_longs, pcd_max_doubles: solver/pcs_sums.h).
 */
#ifndef SL_PCS_DOMAIN_H
#define SL_PCS_DOMAIN_H

#include "core/sl_source.h"
#include "solver/pcisph.h"
#include "solver/pcs_snapshot.h"
#include "solver/pcs_sums.h"

/* Whether s (ranks > 1) can run in domain mode. */
int pcd_usable(const pcs_solver *s);
/* A periodic case runs in the domain mode (the halo holds the pieces
 * where its images lie, the images are made by every rank from its own
 * and halo particles, in the serial order) but for what this names, kept
 * in the halo mode: NULL when nothing stops it (or no periodic axis). */
const char *pcd_periodic_refusal(const pcs_solver *s);
/* A set-up in parts (case/case_part.h): no rank makes or reads the whole
 * case.  The plan holds the solver's grid for the whole case's counts (the
 * same grid pcs_init makes), every rank counts the fluid of the whole case
 * by row (pcd_plan_count: generated again, or read from a restart file,
 * without storing it), the cuts follow from the counts as pcd_init makes
 * them from the particles, and the rank then stores the fluid of its own
 * rows (pcd_plan_fluid) and the boundary particles of the rows within the
 * halo depth and two supports of them (pcd_plan_boundary: the rows it
 * stores, and those their masses and rest densities read), with the ids
 * of the whole case.  pcd_plan_built drops the grid; pcs_init_part hands
 * the cuts to the solver.  Usable where the domain mode is: ranks > 1, no
 * periodic axis (a periodic case is built whole on every rank, then each
 * keeps its part), SLUICE_PARALLEL_EXCHANGE neither gather nor halo. */
typedef struct pcd_plan pcd_plan;
int pcd_plan_usable(const pcs_params *p);
pcd_plan *pcd_plan_new(const pcs_params *p, const eff_set *eff, const double lo[3],
                       const double hi[3], size_t nfluid, size_t nboundary);
void pcd_plan_count(pcd_plan *pl, double x, double y, double z);
void pcd_plan_cut(pcd_plan *pl);
int pcd_plan_fluid(const pcd_plan *pl, double x, double y, double z);
/* Whether a point of the box [lo, hi] may be own (conservative: yes when
 * any cell it meets is own), and the counts of ranks that each counted a
 * part of the fluid summed over the ranks (collective; a restart file's
 * records, case_part.c). */
int pcd_plan_fluid_box(const pcd_plan *pl, const double lo[3], const double hi[3]);
void pcd_plan_count_sum(pcd_plan *pl);
int pcd_plan_boundary(const pcd_plan *pl, double x, double y, double z);
void pcd_plan_built(pcd_plan *pl);
void pcd_plan_free(pcd_plan *pl);
size_t pcd_plan_fluid_total(const pcd_plan *pl);
size_t pcd_plan_boundary_total(const pcd_plan *pl);
/* At set-up: the cuts (from the particles, when every rank holds every
 * one; or the plan's), and the rank keeps its own particles. */
void pcd_init(pcs_solver *s, pcd_plan *plan);
void pcd_free(pcs_solver *s);
/* decomposeCase: the cuts this mode makes of s's fluid (sorted, in one
 * process) over p ranks: each particle's rank, and per rank the fluid
 * particles its halo holds and those it stores (own + halo), and the
 * boundary particles it stores (those of its own and halo rows), and
 * each boundary particle's owner (brank). */
void pcd_partition(const pcs_solver *s, int p, int *rank, size_t *stored, size_t *halo,
                   size_t *bstored, int *brank);
/* Before the sort: migration, rebalancing, halo received. */
void pcd_distribute(pcs_solver *s);
/* After the sort and the lists: own rows, exchange lists, the boundary
 * particles this rank computes, counts. */
void pcd_after_search(pcs_solver *s);
/* Per PCISPH iteration: the halo's x* after the prediction, and after the
 * density pass the block sums, the halo's p/rho^2 and rho (and the
 * boundary's p/rho^2), the largest compression.  With the overlap
 * (split.overlap) the point-to-point messages are only started: the
 * passes compute the rows that read no halo value, then pcd_wait
 * completes them (a no-op when nothing is in flight). */
void pcd_exchange_predicted(pcs_solver *s);
/* Rows of width doubles per fluid particle (a[width * i ...]) of the halo
 * from their owners, completed before it returns (collective; once a
 * step: pressureForce correctedConservative's L_j). */
void pcd_exchange_rows(pcs_solver *s, double *a, int width);
double pcd_after_density(pcs_solver *s, double emax);
void pcd_wait(pcs_solver *s);
/* After the integration (and after the density for output): the own
 * rows to the front, the halo dropped. */
void pcd_keep_own(pcs_solver *s);
/* After the post-step effects appended particles from n0 on (emitters,
 * on every rank alike): each rank keeps those in its rows. */
void pcd_keep_emitted(pcs_solver *s, size_t n0);
/* The state on rank 0 (see pcs_gather). */
void pcd_gather(pcs_solver *s);
/* Only the particles near nboxes boxes (see pcs_gather_near). */
void pcd_gather_near(pcs_solver *s, const double *boxes, size_t nboxes);
/* The function objects' sums, counts and maxima over every fluid row
 * (solver/pcs_sums.h; collective): no row travels but those appended since
 * the sort (to rank 0, with their terms). */
void pcd_sum_rows(const pcs_solver *s, size_t k, pcs_row_terms terms, const void *ctx, double *sum);
void pcd_sum_longs(const pcs_solver *s, long *c, size_t n);
void pcd_max_doubles(const pcs_solver *s, double *m, size_t n);
/* The whole fluid's z extent at the last gather (rank 0; NULL before). */
const double *pcd_mirror_zext(const pcs_solver *s);
/* What rank 0 shows (NULL elsewhere, and before a gather). */
const sl_fluid *pcd_mirror(const pcs_solver *s);
const nbr_grid *pcd_mirror_grid(const pcs_solver *s);
const nbr_list *pcd_mirror_bf(const pcs_solver *s);
const sl_boundary *pcd_mirror_boundary(const pcs_solver *s);
/* A snapshot of the whole state (a restart file read by every rank) cut
 * down to this rank's particles. */
void pcd_localize_snapshot(const pcs_solver *s, pcs_snapshot *snap);
/* Streamed output (time directories and restart files) without the
 * whole state on rank 0.  Collective: every rank calls
 * pcd_output_begin after the density of the written positions
 * (pcs_compute_density); on rank 0 it returns 1, and rank 0 then writes
 * its files from pcd_output_source()s and calls pcd_output_end; on the
 * others it serves their parts to rank 0 until pcd_output_end and returns
 * 0.  A source is one set's array in the serial order, tuples of ncomp
 * columns (PCD_ID and PCD_BODY uint32, the others doubles) in VTK's
 * interleaved layout: fluid (rank order is the serial order; the
 * particles emitted since the last sort, from every rank, after them by
 * id), boundary (each rank's own ones by (cell, creation index): rank
 * order again) and prev, the snapshot given (restart files: the state at
 * the start of the step before; rank order).  Rank 0 holds one window of
 * OUT_WINDOW tuples of the array being written, the requests' tuples
 * asked of their rank one piece at a time, and the ids of the particles
 * emitted since the last sort (none after a search). */
enum { PCD_SET_FLUID, PCD_SET_BOUNDARY, PCD_SET_PREV };
enum {
    PCD_X,
    PCD_Y,
    PCD_Z,
    PCD_VX,
    PCD_VY,
    PCD_VZ,
    PCD_P,
    PCD_RHO,
    PCD_DERR, /* fluid: 100 (rho - rho0) / rho0 */
    PCD_PR,   /* fluid: sqrt(p / p_max) */
    PCD_ID,
    PCD_NX,
    PCD_NY,
    PCD_NZ,
    PCD_MASS,
    PCD_BODY,
    PCD_PT /* boundary: p / rho^2 (restart files) */
};
int pcd_output_begin(pcs_solver *s, const pcs_snapshot *prev);
const sl_source *pcd_output_source(pcs_solver *s, int set, int ncomp, int c0, int c1, int c2);
size_t pcd_output_count(const pcs_solver *s, int set);
void pcd_output_end(pcs_solver *s);

/* The block sums part[0..nb) of a per-row array over every rank's own
 * rows in the serial association, on every rank: part holds on entry
 * this rank's whole blocks and the start of the block its rows end in
 * (rows: the solver's row array, own rows from d->lo); the block its rows
 * begin in goes on from the lower ranks' running sum (collective;
 * pcx_block_sums). */
void pcd_block_sums(pcs_solver *s, const double *rows, double *part);

/* The methods without wall density, after the pressure solve: the block
 * sums of the measured compression (err_vol) of the last density pass in
 * s->vol_block, every block on every rank (made as the density error's:
 * no row travels); returns the largest (collective). */
double pcd_vol_blocks(pcs_solver *s);

/* For the End summary. */
typedef struct pcd_counts {
    long searches, migrated_up, migrated_down, rebalances, gathers;
    size_t stored_min, stored_max, halo_min, halo_max; /* last search, over the ranks */
    double stored_mean, halo_mean;                     /* over searches, this rank */
    size_t cap;                                        /* this rank's fluid capacity */
    double imbalance_max;                              /* largest max/mean of a search */
    double gather_seconds, gather_bytes; /* bytes: received by this rank (rank 0: all) */
    double mem_min, mem_max;             /* resident bytes at the end, over the ranks */
    /* bytes of the particle arrays (capacities) and neighbour lists at the
     * end, over the ranks */
    double arrays_min, arrays_max;
    /* boundary particles: stored per rank at the last distribution (own +
     * halo rows), this rank's mean over searches, of nb_global; how often
     * they were distributed (walls moving, cuts moved) and how many changed
     * owner (all ranks) */
    size_t bstored_min, bstored_max, nb_global;
    double bstored_mean;
    long bdistributions, bmigrated;
    /* the overlap: on (split.overlap); the share of the own rows computed
     * while the halo travels, mean over the searches, smallest over the
     * ranks */
    int overlap;
    double inner_share;
    /* the set-up: built in parts (pcd_plan) or whole; particles this rank
     * held when the solver was made, and over the ranks; peak resident
     * bytes (VmHWM) at the end of the set-up, over the ranks */
    int parts;
    size_t setup_fluid, setup_boundary;
    size_t setup_fluid_min, setup_fluid_max, setup_boundary_min, setup_boundary_max;
    double peak_setup_min, peak_setup_max;
    /* streamed output (rank 0's): writes, bytes received for them, the
     * window's tuples, the largest output buffers held (bytes), seconds */
    long out_writes;
    long out_prefetched, out_discarded;       /* windows asked for ahead; dropped unread */
    long out_zblocks_ranks, out_zblocks_root; /* zlib blocks compressed by their ranks; by rank 0 */
    double out_bytes;
    size_t out_window;
    double out_held, out_seconds;
    /* peak resident memory (VmHWM): rank 0's, and the others' range */
    double peak_root, peak_others_min, peak_others_max;
    /* gathers near the function objects' points, and the cells marked at
     * the last one */
    long near_gathers;
    size_t near_cells;
    /* the reductions of the function objects that read every particle
     * (densityError, energy: pcd_sum_rows, pcd_sum_longs, pcd_max_doubles):
     * calls, bytes received by this rank, seconds */
    long fo_reductions;
    double fo_bytes, fo_seconds;
} pcd_counts;
pcd_counts pcd_counters(const pcs_solver *s);

#endif
