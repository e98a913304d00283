/*
 * effects: the physics a case names, and only those, behind one contract
 * (the shape of functionObjects/fo_type.h).
 *
 * An effect is an eff_type: its name, the dictionary keys it owns, the
 * stage of the step where it acts, how it reads its entry of
 * constant/fluidProperties (and with it its physics, e.g. the mapping of a
 * kinematic viscosity to the Becker-Teschner coefficient), what it does,
 * and the plain data it needs saved with rollbacks and restart files.
 * One file per effect: gravity, viscosity, laminar_viscosity, surface_tension,
 * surface_density, particle_shifting, moving_boundary, emitter.
 *
 * A case's effects form an eff_set, in a fixed order (the order of
 * EFF_FLUID_EFFECTS after gravity, then moving boundaries and emitters),
 * which is also the order in which a stage applies them.  An effect the
 * case does not name is not in the set and is never called; each call is
 * counted and timed (the log lists the set at the start and calls and wall
 * time per effect at the end; a test reads the counts).
 */
#ifndef SL_EFFECTS_H
#define SL_EFFECTS_H

#include <stddef.h>

#include "dictionary/dict.h"
#include "kernel/kernel.h"
#include "neighbours/neighbours.h"
#include "particles/particles.h"

/* Where in the step (Algorithm 2) an effect acts. */
typedef enum {
    EFF_PRE_STEP,  /* before the neighbour search: the world at t + dt (moving bodies) */
    EFF_FORCES,    /* non-pressure accelerations, added to f->ax, ay, az */
    EFF_DENSITY,   /* a correction of every predicted density (in the density pass) */
    EFF_SHIFT,     /* after the pressure solve, before the integration: a change of the
                      positions x(t) (particle shifting), with the step's neighbour lists */
    EFF_POST_STEP, /* after an accepted step (emitters) */
    EFF_STAGES
} eff_stage;

/* What an effect sees of the state.  Effects of a stage change only what
 * their stage is for: forces f->ax..az, pre-step the boundary (and its
 * sort in grid), shift the fluid's positions f->x..z, post-step the fluid
 * set. */
typedef struct eff_view {
    sl_fluid *f;
    sl_boundary *b;
    nbr_grid *grid;
    const nbr_list *ff, *fb; /* fluid -> fluid and fluid -> boundary rows */
    krn_kernel k;
    double h, r0, mass, rho0;
    const double *gravity;
    double t, dt; /* the step goes from t to t + dt */
    /* EFF_DENSITY: the positions of this pass and the boundary method's
     * wall_density (whether the wall's share is part of the density) */
    const double *px, *py, *pz;
    int wall_density;
    /* EFF_FORCES and EFF_SHIFT: only rows [row0, row1) are acted on when
     * rows_only (-parallel's halo and domain modes: a rank's own rows,
     * the others' halo read as neighbours); else all */
    int rows_only;
    size_t row0, row1;
} eff_view;

/* The rows an EFF_FORCES or EFF_SHIFT effect acts on. */
static inline size_t eff_rows_from(const eff_view *v) { return v->rows_only ? v->row0 : 0; }
static inline size_t eff_rows_to(const eff_view *v) { return v->rows_only ? v->row1 : v->f->n; }

/* What an effect is read with. */
typedef struct eff_setup {
    double r0, h, rho0;
    const double *gravity;
} eff_setup;

typedef struct eff_type {
    const char *name;        /* its entry in constant/fluidProperties */
    const char *const *keys; /* the keys of that entry (NULL: a switch or none) */
    eff_stage stage;
    /* Read entry `name` of constant/fluidProperties d (present) into a new
     * state; NULL when the entry turns the effect off.  Bad values stop
     * with file, line and key (dict_fatal). */
    void *(*read)(const dict *d, const eff_setup *su);
    /* Act (pre-step, forces, post-step) or prepare the density pass. */
    void (*apply)(void *state, const eff_view *v);
    /* EFF_FORCES, instead of apply: a uniform acceleration, added to a[3];
     * the solver sets it where it resets the forces (no pass of its own). */
    void (*uniform)(const void *state, double a[3]);
    /* EFF_DENSITY: correct fluid particle i's density r (the solver's) and
     * rv (with the wall's share rb, the measure of every method);
     * thread-safe, called inside the density pass. */
    void (*correct)(const void *state, const eff_view *v, size_t i, double x, double y, double z,
                    double rb, double *r, double *rv);
    void (*free)(void *state);
    /* Plain data a step changes, saved with rollbacks and restart files. */
    size_t (*state_size)(const void *state);
    void (*save)(const void *state, void *buf);
    void (*load)(void *state, const void *buf);
} eff_type;

typedef struct eff_instance {
    const eff_type *type;
    void *state;
    long calls;
    double time; /* wall-clock seconds */
} eff_instance;

typedef struct eff_set {
    eff_instance *e;
    size_t n;
} eff_set;

void eff_set_init(eff_set *s);
void eff_set_free(eff_set *s);
/* Append an effect with its state (owned by the set from now on). */
eff_instance *eff_add(eff_set *s, const eff_type *t, void *state);
/* The instance of effect `name`, NULL if the case did not name it. */
eff_instance *eff_find(const eff_set *s, const char *name);
/* Run every effect of the set's stage st, counting and timing each. */
void eff_run(eff_set *s, eff_stage st, const eff_view *v);
/* The sum of the uniform accelerations of the forces stage (counted). */
void eff_uniform(eff_set *s, double a[3]);

/* The effects of constant/fluidProperties, in the order they act. */
extern const eff_type *const eff_fluid_effects[];
/* Read every effect of eff_fluid_effects that d names into s. */
void eff_read_fluid(eff_set *s, const dict *d, const eff_setup *su);

/* Bytes of the saved state of all effects, and its saving and loading. */
size_t eff_state_size(const eff_set *s);
void eff_save(const eff_set *s, void *buf);
void eff_load(eff_set *s, const void *buf);

#endif
