/*
 * fo: function objects, OpenFOAM's way of sampling a run while it goes.
 *
 * A case names them in the `functions` sub-dictionary of system/controlDict
 * (every type and key, with defaults, is in etc/caseDicts/functions):
 *
 *   functions
 *   {
 *       rhoErr { type densityError; writeControl timeStep; writeInterval 10;
 *                percentiles (50 90 99); histogram on; }
 *       probes { type probes; fields (pressure density velocity);
 *                probeLocations ((0.5 0.3 0.1) (1.6 0.3 0.05)); }
 *       gauges { type waterGauges; gaugeLocations ((0.5 0.3) (1.0 0.3)); }
 *       energy { type energy; writeControl writeTime; }
 *   }
 *
 * Common keys: type (required), writeControl timeStep (every writeInterval
 * steps, step 0 included; the default) or writeTime (every writeInterval-th
 * time the solver writes), writeInterval (default 1), enabled (default on).
 *
 * Each object writes postProcessing/<name>/<startTime>/<type>.dat, where
 * startTime is the time of the first fo_execute (or fo_start) call: '#'
 * header lines, the last naming the tab-separated columns, one row per
 * execution, flushed, so gnuplot can follow a running case.  A restart
 * (another start time) opens a new folder; the same start time overwrites.
 *
 * The types (fo_density_error.c, fo_probes.c, fo_water_gauges.c,
 * fo_energy.c) sit behind one contract (fo_type.h); an unknown type stops
 * the run with the list of valid ones.
 *
 * Cost: fo_read returns NULL when the case names no (enabled) function
 * object, and fo_execute(NULL, ...) returns at once.  fo_execute allocates
 * only on its first call (files, scratch sized for the particle count),
 * again only if the particle count or the grid grows, and at write times
 * for per-time files (densityError's histograms).
 */
#ifndef SL_FO_H
#define SL_FO_H

#include "case/case.h"
#include "dictionary/dict.h"
#include "solver/pcisph.h"

typedef struct fo_list fo_list;

/* What the objects of a list read from the solver (for post-processing,
 * which rebuilds only what is needed from the VTK files). */
#define FO_NEED_BOUNDARY 1u /* boundary particles with pressure, density, mass */
#define FO_NEED_GRID     2u /* the neighbour grid, for point queries */
#define FO_NEED_POWER    4u /* the solver's power of the forces (pcs_want_power) */

/* The function objects of <case>/system/controlDict; NULL when there is no
 * `functions` dictionary or every entry is disabled.  Exits with
 * "<file>:<line>: ..." on a malformed entry (unknown type: the list of
 * valid types; a missing required key: its name). */
fo_list *fo_read(const sl_case *c);

/* The same from a `functions` dictionary already read; time_precision names
 * the start-time folders.  NULL-safe (functions NULL gives NULL). */
fo_list *fo_read_dict(const dict *functions, const char *case_dir, int time_precision);

/* For post-processing: the objects called names[0..n) -- each the entry of
 * that name in the case's functions, else a type of that name with its
 * defaults (exits when it has required keys) -- or, with n == 0, every
 * entry of the case's functions (exits when there is none).  Every
 * fo_execute call of such a list executes every object (each call is a
 * processed time) and is treated as a write time. */
fo_list *fo_select(const sl_case *c, const char *const *names, size_t n);

/* Run the objects that are due after a step (and once at the start with
 * step 0), s being the state at `time`; write_time tells whether the solver
 * has just written this time.  The first call opens the files (its time
 * names the start-time folder).  A call at or before the previous call's
 * time is the solver going back after a shock: the rows after that time
 * are dropped and nothing is executed (that state was recorded when first
 * reached), so the files hold the accepted trajectory.
 * The particles of s->f should be sorted in s->grid (as after pcs_step or
 * pcs_compute_density); point queries allow for positions that moved up to
 * one cell since the sort and otherwise search all particles (fo_query.h).
 * A write error is a warning, and that object stops writing. */
void fo_execute(fo_list *l, const pcs_view *s, double time, long step, int write_time);
/* Whether that call would read the state (its first call, or an object
 * due); changes nothing.  -parallel's domain mode gathers the state on
 * rank 0 only then. */
int fo_wants_state(const fo_list *l, double time, long step, int write_time);

/* What that call would read of rank 0's copy of the state:
 * FO_READS_NOTHING, FO_READS_NEAR (only point queries at points inside the
 * *nboxes boxes *boxes, 6 doubles each: lo x y z, hi x y z, infinite
 * bounds allowed; the list's memory, valid until the next call) or
 * FO_READS_ALL.  -parallel's domain mode gathers on rank 0 only the
 * particles near the boxes, or the whole state.  The objects that read
 * every particle through the view's sums (densityError, energy: fo_serve)
 * need nothing gathered and count as reading nothing here. */
enum { FO_READS_NOTHING, FO_READS_NEAR, FO_READS_ALL };
int fo_wants_region(fo_list *l, double time, long step, int write_time, const double **boxes,
                    size_t *nboxes);

/* -parallel's domain mode, every rank but 0: this list writes no file and
 * runs only the objects that read every particle through the view's sums
 * (densityError, energy), whose collective calls rank 0's list makes in
 * the same order (each rank sums its own rows, solver/pcs_sums.h); the
 * others (probes, waterGauges) read rank 0's gathered copy and run there
 * only.  Call before the first fo_execute or fo_start.  NULL-safe. */
void fo_serve(fo_list *l);

/* Open the files of a run starting at `time` without executing anything:
 * for a restart, whose first state was recorded by the previous run (and
 * whose densities and pressures are not computed yet).  No-op after the
 * first fo_execute; NULL-safe. */
void fo_start(fo_list *l, const pcs_view *s, double time);

/* Union of FO_NEED_* over the objects of l. */
unsigned fo_needs(const fo_list *l);
/* Number of objects; the name, type name and .dat path (NULL before the
 * first fo_execute) of object i. */
size_t fo_count(const fo_list *l);
const char *fo_name(const fo_list *l, size_t i);
const char *fo_type_name(const fo_list *l, size_t i);
const char *fo_dat_path(const fo_list *l, size_t i);

/* Close the files and free everything (NULL is fine). */
void fo_free(fo_list *l);

#endif
