/*
 * pcisph: one time step of PCISPH (Solenthaler & Pajarola 2009) with the
 * boundary handling of Ihmsen et al. 2010, as in the paper's Algorithm 2:
 *
 *   find neighbours (fluid and boundary)
 *   compute non-pressure forces; p = 0, F^p = 0 for fluid and boundary
 *   repeat (at least min_iter times, until max rho_err* <= eta or max_iter):
 *       predict velocity and position; predict world collision (eq. 9-11)
 *       predict density of fluid and boundary particles (eq. 13),
 *       update their pressure p += delta rho_err* (eq. 3)
 *       compute the pressure force (eq. 6, boundary pressures included)
 *   integrate (Euler-Cromer); world collision (eq. 11, 12)
 *
 * Negative pressure: a particle at the free surface has a deficient
 * neighbourhood and a predicted density below rho0; its pressure would
 * pull the surface together (tensile instability).  We clamp pressures at
 * zero after each update, as SPlisHSPlasH and most PCISPH codes do.  The
 * density error statistics count compression only: max(rho - rho0, 0).
 */
#ifndef SL_PCISPH_H
#define SL_PCISPH_H

#include <stddef.h>

#include "boundary/boundary.h"
#include "effects/effects.h"
#include "effects/viscosity.h"
#include "kernel/kernel.h"
#include "motion/motion.h"
#include "neighbours/neighbours.h"
#include "particles/particles.h"

typedef struct pcs_params {
    double rho0;          /* rest density */
    double r0;            /* particle spacing; h = 2 r0 */
    double gravity[3];
    double eta;           /* tolerated density error, fraction of rho0 (0.01 = 1 %) */
    int min_iter, max_iter;
    double epsilon;       /* eq. (12): tangential velocity kept on contact */
    bnd_method method;    /* boundary handling (constant/boundaryProperties) */
    double restitution;   /* becker2009: delta of eq. (7) */
    int viscosity;        /* effect named by the case */
    visc_params visc;
    int surface_tension;  /* effect: Becker & Teschner 2007 cohesion */
    double kappa;
    int surface_density;  /* effect: Bonet & Kulasegaram 2002 correction */
} pcs_params;

/* What one step did (logged every step). Errors are fractions of rho0. */
typedef struct pcs_stats {
    int iterations;
    int converged;           /* max error <= eta at exit */
    double err_avg_before, err_max_before;  /* first prediction (p = 0) */
    double err_avg, err_max;                /* last prediction */
    /* The same compression measured alike for every boundary method: the
     * density with the wall's share from the boundary particles of eq. (13)
     * (ihmsen2010: err_avg, err_max; becker2009 and harada2007 solve
     * without it, so their own err_* cannot see fluid pressed into a wall). */
    double vol_avg, vol_max;
    double vmax;             /* max |v(t + dt)| */
    double fmax;             /* max |F/m| (all forces) */
    size_t nactive;          /* active boundary particles */
    size_t ncollide;         /* fluid particles corrected by the final collision */
    int diverging;           /* the iterations stopped because the error grew */
} pcs_stats;

/* Wall-clock seconds spent in each phase (accumulated). */
typedef struct pcs_timers {
    double search, forces, predict, density, pressure, integrate;
    double sort, list_ff, list_bf;   /* parts of search: sorting, fluid rows, boundary rows */
} pcs_timers;

typedef struct pcs_solver pcs_solver;

/* A boundary method's passes (boundary_methods in pcisph.c, the one place
 * that chooses by method): predicted density with the pressure update,
 * pressure force, and world collision of positions (and velocities when
 * vx != NULL). */
typedef struct pcs_boundary_ops {
    bnd_method method;
    double (*density)(pcs_solver *s, int predict); /* predict 0: rho from x(t) only */
    void (*pressure)(pcs_solver *s);
    size_t (*collide)(pcs_solver *s, double *x, double *y, double *z, double *vx, double *vy,
                      double *vz);
} pcs_boundary_ops;

struct pcs_solver {
    pcs_params prm;
    double h, mass, dt, beta, delta, eta_abs;
    krn_kernel k;
    bnd_calibration cal;
    sl_fluid *f;
    sl_boundary *b;
    nbr_grid grid;
    nbr_list ff, fb, bf;
    uint32_t *active;
    size_t nactive;
    double *err;           /* per-fluid-particle compression (scratch) */
    double *err_vol;       /* becker2009, harada2007: the same with the wall's density */
    size_t err_cap;
    const pcs_boundary_ops *bops;
    bnd_wall_table wall;   /* harada2007 */
    double *wall_d;        /* harada2007: distance to the nearest boundary plane */
    uint32_t *wall_b;      /* harada2007: nearest boundary particle */
    double *ap_best;       /* pressure force of the best iteration (3 x cap) */
    pcs_timers time;
    eff_list eff;          /* the effects in use, their calls and times */
    const mot_motion *motions; /* per body (pcs_set_motions) */
    size_t nbodies;
    double t;              /* time of the state (set by the caller before a step) */
};

/* delta of eq. (4) for a prototype particle with a filled neighbourhood
 * on a cubic lattice of spacing r0, with beta of eq. (5). */
double pcs_delta(const krn_kernel *k, double r0, double mass, double rho0, double dt);

/* Set up: grid over [lo, hi], boundary sorted and its masses set,
 * fluid sorted, delta for dt.  The solver keeps pointers to f and b. */
void pcs_init(pcs_solver *s, const pcs_params *p, sl_fluid *f, sl_boundary *b,
              const double lo[3], const double hi[3], double dt);
void pcs_free(pcs_solver *s);
/* Change the time step; recomputes beta and delta (eq. 4, 5). */
void pcs_set_dt(pcs_solver *s, double dt);
/* Bodies with a prescribed motion (motions[body], MOT_NONE for static
 * ones); turns the movingBoundary effect on when any body moves. */
void pcs_set_motions(pcs_solver *s, const mot_motion *motions, size_t nbodies);
/* Put the moving bodies where they are at time t (and re-sort them). */
void pcs_move_boundaries(pcs_solver *s, double t);
/* Advance by s->dt from time s->t (s->t is advanced too). */
void pcs_step(pcs_solver *s, pcs_stats *st);
/* The phases of a step, public for benchmarks: sort and build the
 * neighbour lists; one predicted-density + pressure-update pass (returns
 * the largest compression); one pressure-force pass. */
void pcs_find_neighbours(pcs_solver *s);
double pcs_pass_density(pcs_solver *s);
void pcs_pass_pressure(pcs_solver *s);

/* Density of every fluid particle from the current positions x(t) (for
 * output; uses the lists of the last step or rebuilds them). */
void pcs_compute_density(pcs_solver *s);

#endif
