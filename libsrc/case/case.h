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
} case_region;

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
    emt_emitter *emitters;     /* constant/fluidProperties: emitters { } */
    case_where *emitter_where; /* of each emitter's entry */
    size_t nemitters;
    sl_fluid fluid;
    sl_boundary boundary;
    double lo[3], hi[3]; /* scene bounds for the neighbour grid */
} sl_case;

/* Read all dictionaries of the case in `dir`; exits with a clear error on
 * bad input. */
void case_read(sl_case *c, const char *dir);
/* Sample the geometry and fill the fluid regions; exits with an error if the
 * scene is empty or impossible. */
void case_build(sl_case *c);
void case_free(sl_case *c);
/* The top-level keys of each case file ("system/controlDict", ...; ends
 * with where == NULL), for messages about misplaced or misspelt keys. */
const dict_key_home *case_key_homes(void);

#endif
