/*
 * case: reads a case directory (OpenFOAM layout) and builds the world.
 *
 *   system/controlDict          run controls (times, writing, threads)
 *   system/timeStepDict         time-step mode and constants
 *   constant/fluidProperties    rho0, particleSpacing, gravity, eta,
 *                               iteration limits, fluidRegions
 *   constant/boundaryProperties boundary method, epsilon, geometry
 *
 * Every optional key has a compiled default equal to the annotated file in
 * etc/caseDicts/ (a test checks they agree).  A missing required key, a
 * malformed value or an impossible set-up stops the run with a message
 * naming the file, line and key; an unknown key is a warning naming the
 * nearest valid one.  Nothing is written before the case has been read.
 */
#ifndef SL_CASE_H
#define SL_CASE_H

#include <stddef.h>
#include <stdint.h>

#include "dictionary/dict.h"
#include "geometry/geometry.h"
#include "motion/motion.h"
#include "effects/emitter.h"
#include "particles/particles.h"
#include "solver/pcisph.h"
#include "timestep/timestep.h"

typedef enum { CASE_START_TIME, CASE_LATEST_TIME } case_start;
/* writeControl: adjustableRunTime (steps evened out to land on each write
 * time) or runTime (write at the first step at or past it). */
typedef enum { CASE_ADJUSTABLE_RUN_TIME, CASE_RUN_TIME } case_write_control;

typedef struct case_controls {
    case_start start_from;
    case_write_control write_control;
    double start_time, end_time, write_interval;
    int ascii, compress, time_precision, purge_write, nthreads, write_boundary;
} case_controls;

/* Where an entry was written, for messages: "<file>:<line>". */
typedef struct case_where {
    char text[320];
} case_where;

typedef struct case_region {
    char name[64];
    case_where where; /* of its entry in fluidRegions */
    geo_shape shape;  /* box, sphere, cylinder or closed mesh */
    double velocity[3];
    /* velocityField { type taylorGreen | standingWave; amplitude; length; }
     * added to velocity (verification cases, doc/verification.md) */
    int field; /* CASE_FIELD_* */
    double field_amplitude, field_length;
    uint32_t id0, id1; /* its particles' ids at t = 0: [id0, id1) (case_build) */
} case_region;

/* initialPacking (constant/fluidProperties): the particles start on the
 * cubic lattice they are built on, or relaxed on it before t = 0
 * (solver/pcs_relax.h: the lattice displaced by up to jitter r0, then
 * steps damped steps of the case's own forces and pressure solve, the
 * velocity zeroed before each; then the regions' initial velocities at the
 * relaxed positions, case_initial_velocity). */
typedef struct case_packing {
    int relaxed;
    long steps;       /* the steps, or with tolerance > 0 their cap */
    double tolerance; /* 0: none; else the residual stop (pcs_relax.h), fraction of r0 per step */
    double jitter;    /* fraction of r0 */
    case_where where;
} case_packing;

/* initialPacking's compiled defaults (etc/caseDicts/fluidProperties) */
#define CASE_RELAX_STEPS  300
#define CASE_RELAX_JITTER 0.1
/* pressureSource mixed: the density error's weight (densityWeight) */
#define CASE_SOURCE_MIX 0.05

enum { CASE_FIELD_NONE, CASE_FIELD_TAYLOR_GREEN, CASE_FIELD_STANDING_WAVE };

typedef struct sl_case {
    char *dir;
    case_controls ctl;
    ts_params ts; /* system/timeStepDict */
    pcs_params prm;
    eff_set effects; /* the effects the case names, in the order they act */
    geo_shape *shapes;
    mot_motion *motions; /* one per shape; type MOT_NONE for static bodies */
    size_t nshapes;
    case_region *regions;
    size_t nregions;
    case_packing packing;
    emt_emitter *emitters;     /* constant/fluidProperties: emitters { } */
    case_where *emitter_where; /* of each emitter's entry */
    size_t nemitters;
    case_where mean_where; /* pressureSource's meanPressure entry (the periodic check) */
    sl_fluid fluid;
    sl_boundary boundary;
    double lo[3], hi[3]; /* scene bounds for the neighbour grid */
    /* the particles of the whole case at t = 0 (with part: of every rank;
     * fluid and boundary hold this rank's share, case_part.h) */
    size_t nfluid, nboundary;
    int part;
} sl_case;

/* Read all dictionaries of the case in `dir`; exits with a clear error on
 * bad input. */
void case_read(sl_case *c, const char *dir);
/* Sample the geometry and fill the fluid regions; exits with an error if the
 * scene is empty or impossible. */
void case_build(sl_case *c);
/* case_build in its three steps, for a build in passes (case_part.h):
 * the checks (once); the particles made, stored through the filters
 * (NULL: every one; what: CASE_FLUID and/or CASE_BOUNDARY; nfluid and
 * nboundary set to the particles made, ids their creation indices, the
 * same in every pass); the bounds of the scene and the emitters (once,
 * after the particles were made once). */
enum { CASE_FLUID = 1, CASE_BOUNDARY = 2 };
void case_build_prepare(sl_case *c);
void case_build_particles(sl_case *c, prt_filter *fluid, prt_filter *boundary, int what);
void case_build_finish(sl_case *c);
void case_free(sl_case *c);
/* The initial velocity of each fluid particle at its present position: its
 * region's velocity and velocityField (by the particle's id, any order),
 * after a relaxed initialPacking moved the particles off the lattice. */
void case_initial_velocity(const sl_case *c, sl_fluid *f);

/* Distance from p to the nearest wall surface of the case's shapes:
 * positive on the fluid side, negative beyond a wall; open container faces
 * are no walls (boundarySmoothness, classifyCompression). */
double case_wall_distance(const sl_case *c, const double p[3]);
/* The top-level keys of each case file ("system/controlDict", ...; ends
 * with where == NULL), for messages about misplaced or misspelt keys. */
const dict_key_home *case_key_homes(void);

#endif
