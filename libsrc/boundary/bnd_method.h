/*
 * bnd_method: the contract of a boundary method, the choice `method` of
 * constant/boundaryProperties (paper Sec. 3.2 and the references of its
 * Sec. 4.1).  One method per file pair boundary/<name>.{h,c}; the list of
 * methods is BND_METHODS in boundary/bnd_methods.h, the one table.
 *
 * A method is two things:
 *  - a bnd_method_type (its .c file): the name, whether boundary particles
 *    carry a density and pressure of their own in the pressure solve
 *    (eq. 13), its own state (init / reserve / free) and the world
 *    collision that keeps fluid out of the walls;
 *  - two static inline per-particle terms (its .h file), which the
 *    solver's density and pressure passes instantiate once per method (the
 *    include-template idiom of SWIFT's hydro schemes), so that every pass
 *    is compiled for its method and stays vectorised:
 *      <name>_density(c, i, x, y, z, rb):  the wall's share of fluid
 *          particle i's density, given rb = sum_b m_b W_ib over its
 *          boundary neighbours (computed by the pass for every method);
 *      <name>_pressure(c, i, x, y, z, pt_i, a):  add the wall's pressure
 *          acceleration on fluid particle i to a[3];
 *    and one constant, <name>_wall_density (1: the boundary particles'
 *    predicted density and pressure enter the solve, eq. 13).
 */
#ifndef SL_BND_METHOD_H
#define SL_BND_METHOD_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/kernel.h"
#include "neighbours/neighbours.h"
#include "particles/particles.h"

/* What a method is set up with (constant/boundaryProperties and the fluid). */
typedef struct bnd_setup {
    krn_kernel k;
    double r0, mass, rho0;
    double epsilon;     /* eq. (12): tangential velocity kept on contact */
    double restitution; /* becker2009: delta of eq. (7) */
} bnd_setup;

/* What a method's per-particle terms read during one pass. */
typedef struct bnd_pass {
    krn_kernel k;
    const uint32_t *restrict fbs, *restrict fbi; /* fluid -> boundary rows */
    const sl_boundary *b;
    void *state; /* the method's own state */
} bnd_pass;

typedef struct bnd_method_type {
    const char *name; /* as in constant/boundaryProperties */
    const char *what; /* one line for the log and -help */
    int wall_density; /* boundary density and pressure in the solve (eq. 13) */
    /* The method's own state (NULL: none); per-fluid-particle arrays sized
     * for fluid capacity cap by reserve (called before every step, cheap
     * when nothing grew). */
    void *(*init)(const bnd_setup *su);
    void (*reserve)(void *state, size_t cap);
    void (*free)(void *state);
    /* World collision of n fluid positions (and of their velocities when
     * vx != NULL) against the boundary b through the fluid -> boundary
     * lists fb; returns the number of corrected particles. */
    size_t (*collide)(void *state, const bnd_setup *su, const nbr_list *fb, const sl_boundary *b,
                      size_t n, double *x, double *y, double *z, double *vx, double *vy,
                      double *vz);
} bnd_method_type;

/* The method called `name`, NULL if there is none. */
const bnd_method_type *bnd_method_find(const char *name);
/* The names of all methods, NULL-terminated (for messages and checks). */
const char *const *bnd_method_names(void);

#endif
