/*
 * effects: the physics a case names, and only those.
 *
 * The solver keeps the list of effects the case named (constant/
 * fluidProperties: `gravity` unless it is zero, `viscosity { }`,
 * `surfaceTension { }`, `surfaceDensityCorrection { }`; moving boundaries
 * and emitters where they are defined) and evaluates exactly those; an
 * effect that is not on the list is never called.  Each evaluation is
 * counted and timed, and the log prints the list at the start and calls and
 * wall time per effect at the end (a test reads the counts).
 */
#ifndef SL_EFFECTS_H
#define SL_EFFECTS_H

typedef enum {
    EFF_GRAVITY,
    EFF_VISCOSITY,          /* Becker & Teschner 2007 */
    EFF_SURFACE_TENSION,    /* Becker & Teschner 2007, cohesion */
    EFF_SURFACE_DENSITY,    /* Bonet & Kulasegaram 2002 constant correction */
    EFF_MOVING_BOUNDARY,    /* prescribed rigid motion of boundary bodies */
    EFF_EMITTER,            /* inflow */
    EFF_COUNT
} eff_kind;

typedef struct eff_list {
    int on[EFF_COUNT];      /* named by the case */
    long calls[EFF_COUNT];
    double time[EFF_COUNT]; /* wall-clock seconds */
} eff_list;

const char *eff_name(eff_kind k);

#endif
