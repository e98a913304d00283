/*
 * pcisph: one time step of PCISPH (Solenthaler & Pajarola 2009) with the
 * boundary handling of Ihmsen et al. 2010, as in the paper's Algorithm 2:
 *
 *   find neighbours (fluid and boundary)
 *   compute non-pressure forces; p = 0, F^p = 0 for fluid and boundary
 *   repeat (at least min_iter times, until max rho_err* <= eta or max_iter;
 *   with stop_max > 0: until avg rho_err* <= eta and max rho_err* <= stop_max):
 *       predict velocity and position; predict world collision (eq. 9-11)
 *       predict density of fluid and boundary particles (eq. 13),
 *       update their pressure p += delta rho_err* (eq. 3)
 *       compute the pressure force (eq. 6, boundary pressures included)
 *   integrate (Euler-Cromer); world collision (eq. 11, 12)
 *
 * Negative pressure: a particle at the free surface has a deficient
 * neighbourhood and a predicted density below rho0; its pressure would
 * pull the surface together (tensile instability).  We clamp pressures at
 * zero after each update, as SPlisHSPlasH and most PCISPH codes do, except
 * with meanPressure (a periodic box: no surface, and the clamp would leave
 * a background pressure that grows with the iterations).  The
 * density error statistics count compression only: max(rho - rho0, 0).
 */
#ifndef SL_PCISPH_H
#define SL_PCISPH_H

#include <math.h>
#include <stddef.h>

#include "boundary/bnd_method.h"
#include "boundary/boundary.h"
#include "domain/dom_periodic.h"
#include "effects/effects.h"
#include "kernel/kernel.h"
#include "neighbours/neighbours.h"
#include "particles/particles.h"

typedef struct pcs_params {
    double rho0;    /* rest density */
    double r0;      /* particle spacing */
    double support; /* the kernel's support radius over r0 (kernelSupport; the paper's 2) */
    int kernel;     /* KRN_CUBIC_SPLINE (the paper's) or KRN_WENDLAND_C2 (kernel) */
    double gravity[3];
    double eta; /* tolerated density error, fraction of rho0 (0.01 = 1 %) */
    int min_iter, max_iter;
    double stop_max;               /* > 0: the iterations stop when the average compression is at
                           * most eta and the largest at most stop_max (fractions of rho0;
                           * time-step controller cost); 0: when the largest is at most eta */
    double epsilon;                /* eq. (12): tangential velocity kept on contact */
    const bnd_method_type *method; /* boundary handling (constant/boundaryProperties) */
    double restitution;            /* becker2009: delta of eq. (7) */
    double mass_factor;            /* boundary masses times this (massFactor; 1: calibrated) */
    dom_periodic periodic;         /* periodic axes and their period (axes 0: none) */
    int one_rank;      /* 1: a solver of one rank's whole case even under -parallel (the relaxed
                   * packing, made alike on every rank before the split) */
    int point_queries; /* function objects query points (probes, waterGauges): under -parallel
                        * a periodic case keeps the halo mode (pcd_periodic_refusal) */
    /* pressureSource (constant/fluidProperties): what the pressure update of
     * eq. (3) corrects.  PCS_SOURCE_DENSITY (the paper's): the predicted
     * density error rho*_i - rho0.  PCS_SOURCE_DIVERGENCE: the predicted
     * density change over the step, dt sum_j m_j (v*_i - v*_j) . grad W_ij
     * at x(t) (DFSPH's divergence source, Bender & Koschier 2015), with the
     * wall's boundary particles as in eq. (13); no memory of the packing,
     * so the density drifts.  PCS_SOURCE_MIXED: (1 - source_mix) times the
     * divergence source plus source_mix times the density error (a
     * velocity-divergence source with a density-invariance correction, as
     * in Hu & Adams 2007, Asai et al. 2012). */
    int source;
    double source_mix;    /* mixed: the density error's weight, in (0, 1) */
    int warm_start;       /* divergence, mixed: each step starts from the last step's
                          * pressures (DFSPH's warm start; 0: from zero, as PCISPH) */
    int grad_correction;  /* divergence, mixed: the density change with the kernel gradient
                          * correction L_i of Bonet & Lok 1999 (exact for a linear
                          * velocity field on any packing) */
    int force_correction; /* pressureForce (PCS_FORCE_*).  corrected: the pressure force
                          * of eq. (6) times the same L_i (at x(t)) where the
                          * neighbourhood is isotropic (PCS_FORCE_ISOTROPY), so that
                          * there the force of a linear pressure field is its gradient
                          * on any packing and with any kernel's moment (Wendland C2's
                          * deficit at 2.2 r0); next to a free surface the paper's
                          * force.  Not conservative: the pairs' forces no longer
                          * cancel.  correctedConservative: each fluid pair's term
                          * times (L_i + L_j) / 2 (L the identity where it does not
                          * correct), the wall's term times L_i: the pairs' forces
                          * cancel again */
    int hold_mean;        /* divergence (meanPressure): pressures not clamped at zero and
                          * their mean over the fluid held at mean_pressure after every
                          * update; for a box without a free surface, where the
                          * projection fixes the pressure only up to a constant */
    double mean_pressure; /* Pa */
    double relaxation;    /* omega of p += omega delta rho_err* (pressureSource's relaxation,
                          * default 1: eq. 3).  delta is the prototype's; where a
                          * compressed or wide-support packing's largest mode has
                          * delta lambda > 2, the iteration grows that mode, which a
                          * warm start carries from step to step (relaxed Jacobi,
                          * IISPH's omega 0.5, damps it).  pcs_set_dt folds it into
                          * delta, so initialPacking relaxed's steps (pcs_relax) use
                          * it too */
} pcs_params;

enum { PCS_SOURCE_DENSITY = 0, PCS_SOURCE_DIVERGENCE = 1, PCS_SOURCE_MIXED = 2 };
/* pressureForce: symmetric (eq. 6), corrected, correctedConservative */
enum { PCS_FORCE_SYMMETRIC = 0, PCS_FORCE_CORRECTED = 1, PCS_FORCE_CONSERVATIVE = 2 };

/* pressureForce corrected: L_i corrects particle i's pressure force where
 * its moment matrix A_i (kernel_correction.h) is isotropic, det A_i /
 * (tr A_i / 3)^3 >= this (1 for an isotropic A_i; on the cubic lattice
 * a free surface's particles, whose kernel lacks the fluid above, 0.922
 * with Wendland C2 at 2.2 r0, 0.917 and 0.935 with the cubic spline at 2
 * and 2.4 r0, the layer below 0.999-1).  Amplified
 * there, the surface layers' force held the column with a pressure too low
 * by about 0.7 r0 of water (hydrostaticTank: a threshold of 0.9 0.0163, 0.95
 * 0.0064, 0.98 0.0069 at r0 0.005; doc/verification.md, "The pressure
 * force corrected"). */
#define PCS_FORCE_ISOTROPY 0.95

/* The compiled defaults (equal to the annotated files of etc/caseDicts;
 * rho0 and r0, which a case must give, are 0). */
void pcs_params_default(pcs_params *p);

/* The support radius and the particle mass of a case: h = support r0
 * (2 r0 in the paper, Sec. 3.2) and m = rho0 r0^3 (a fluid particle fills
 * its cube of the lattice; there the lattice's summation density is
 * 0.99997 rho0).  A wider support's kernel sum over the cubic lattice is
 * up to 0.2 % above 1 / r0^3 (h = 3 r0: 1.0018), which a closed periodic
 * box could never relieve: there m = rho0 over that sum, so that the
 * lattice is at rest density (and so for the Wendland kernel at any
 * support: its lattice sum at 2 r0 is 2.6 % below 1 / r0^3). */
static inline double pcs_support(const pcs_params *p) { return p->support * p->r0; }
/* The case's kernel (type and support). */
static inline void pcs_kernel(const pcs_params *p, krn_kernel *k)
{
    krn_init_type(k, p->kernel, pcs_support(p));
}
double pcs_mass_lattice(const pcs_params *p);
/* r0^3 first, then rho0: the solver's order before kernelSupport, kept to
 * the last bit (volatile: -fassociative-math could reorder the product,
 * and a chaotic run follows the last bit of the mass) */
static inline double pcs_mass(const pcs_params *p)
{
    if (p->support != 2.0 || p->kernel != KRN_CUBIC_SPLINE) return pcs_mass_lattice(p);
    volatile double r3 = p->r0 * p->r0 * p->r0;
    return p->rho0 * r3;
}

/* What one step did (logged every step). Errors are fractions of rho0. */
typedef struct pcs_stats {
    int iterations;
    int converged;                         /* max error <= eta at exit */
    double err_avg_before, err_max_before; /* first prediction (p = 0) */
    double err_avg, err_max;               /* last prediction */
    /* The same compression measured alike for every boundary method: the
     * density with the wall's share from the boundary particles of eq. (13)
     * (ihmsen2010: err_avg, err_max; becker2009 and harada2007 solve
     * without it, so their own err_* cannot see fluid pressed into a wall). */
    double vol_avg, vol_max;
    double vmax;     /* max |v(t + dt)| */
    double fmax;     /* max |F/m| (all forces) */
    size_t nactive;  /* active boundary particles */
    size_t ncollide; /* fluid particles corrected by the final collision */
    int diverging;   /* the iterations stopped because the error grew */
} pcs_stats;

/* Wall-clock seconds spent in each phase (accumulated). */
typedef struct pcs_timers {
    double world, search, forces, predict, density, pressure, integrate;
    double sort, list_ff, list_bf; /* parts of search: sorting, fluid rows, boundary rows */
    double halo;                   /* halo copies: building (search) and refreshing */
    double comm;                   /* MPI exchanges (-parallel), inside density and pressure */
} pcs_timers;

/* -parallel, phase 1 (replicated state, doc/parallel.md): every rank holds
 * every particle; the density and pressure-force passes compute rank r's
 * fluid rows [row[r], row[r+1]) and active boundary particles
 * [act[r], act[r+1]) (split by count at each search); the pass's outputs
 * are then gathered on every rank, and every rank sums the density error
 * by blocks of SL_REDUCE_BLOCK in the serial code's order.  One rank: the
 * serial code, nothing exchanged. */
typedef struct pcs_split {
    int rank, size;
    size_t *row, *act;         /* size + 1 entries each, set by each search */
    double *bbuf;              /* active boundary rho, p, p/rho^2 packed by rank (3 x nb) */
    size_t rows_min, rows_max; /* fluid rows per rank of the last search */
    long steps;                /* searches split */
    long empty;                /* of them, with a rank holding no fluid row */
    int halo;                  /* halo mode (solver/pcs_parallel.h) */
    struct pcs_halo_x *hx;     /* its lists and buffers */
    uint32_t *bset;            /* halo mode: the boundary particles this rank computes */
    size_t nbset, bset_cap;
    size_t halo_rows, halo_max; /* halo rows received, last search and largest */
    double halo_sum;            /* summed over the searches */
    int32_t *owner;             /* rank of particle id at the last search (-1: none) */
    size_t owner_cap;
    long moved_up, moved_down;         /* particles whose rank rose / fell between searches */
    double rows_min_sum, rows_max_sum; /* their sums over those searches (balance) */
    /* domain mode (phase 2, solver/pcs_domain.h; with halo set too): a rank
     * stores its own particles and their halo only */
    int domain;
    struct pcs_domain *dd;
    ptrdiff_t gshift; /* own row i is row i + gshift of the serial order */
    size_t nglobal;   /* fluid particles of all ranks */
    size_t nbglobal;  /* boundary particles of all ranks (each rank stores some) */
    /* domain mode's overlap (SLUICE_PARALLEL_OVERLAP): the own rows whose
     * lists hold no halo particle, order[0..ninner), computed while the
     * halo's values travel, then the others, order[ninner..norder); the
     * boundary set likewise, bset[0..nbset_inner) first */
    int overlap;
    uint32_t *order;
    size_t ninner, norder, order_cap, nbset_inner;
    size_t nactive_all; /* active boundary particles of all ranks */
} pcs_split;

typedef struct pcs_solver pcs_solver;
/* A boundary method's passes, compiled for it (pcisph.c). */
typedef struct pcs_method_passes pcs_method_passes;

struct pcs_solver {
    pcs_params prm;
    double h, mass, dt, beta, delta, eta_abs;
    krn_kernel k;
    bnd_calibration cal;
    bnd_setup bsu; /* what the boundary method was set up with */
    void *bstate;  /* the boundary method's own state */
    const pcs_method_passes *passes;
    sl_fluid *f;
    sl_boundary *b;
    nbr_grid grid;
    nbr_list ff, fb, bf;
    uint32_t *active;
    size_t nactive, active_cap;
    double *err;       /* per-fluid-particle compression (scratch) */
    double *err_block; /* its sums by blocks of SL_REDUCE_BLOCK (last prediction) */
    double err_sum;    /* their sum in block order */
    size_t block_cap;  /* entries of err_block */
    double *err_vol;   /* methods without wall density: the same with the wall's share */
    double *vol_block; /* its sums by blocks of SL_REDUCE_BLOCK (the last prediction) */
    double *p_block;   /* meanPressure: the pressure's sums by blocks (scratch) */
    /* pcs_want_power: the power of the forces on the fluid over the last
     * step, [0] the pressure force's, [1] the others', W (NaN before the
     * first step); pw a row's share (cap), pw_block its block sums */
    int power_on;
    double power[2];
    double *pw, *pw_block;
    size_t pw_cap, pw_blocks;
    size_t err_cap;
    double *ap_best;          /* pressure force of the best iteration (3 x cap) */
    double *lcorr;            /* gradientCorrection, pressureForce corrected: L_i (9 x cap) */
    unsigned char *linterior; /* pressureForce corrected: 1 where L_i corrects the force
                               * (an isotropic neighbourhood, PCS_FORCE_ISOTROPY) */
    double *lforce;           /* correctedConservative: L_i where it corrects the force,
                               * else the identity (9 x cap), on every row the pressure
                               * force reads: own, halo (exchanged) and images */
    pcs_timers time;
    eff_set *eff;        /* the case's effects (not owned; may be NULL) */
    eff_instance **dens; /* its EFF_DENSITY effects */
    size_t ndens;
    double t;        /* time of the state (set by the caller before a step) */
    dom_halo halo;   /* periodic images (domain/dom_periodic.h) */
    pcs_split split; /* rows of each rank (-parallel) */
};

/* What function objects and post-processing read of the state (a view:
 * nothing is copied, nothing may be changed through it). */
typedef struct pcs_view {
    const sl_fluid *f;
    const sl_boundary *b;
    const nbr_grid *grid; /* f and b as sorted at the last neighbour search */
    const nbr_list *bf;   /* boundary -> fluid rows of that search (active boundary) */
    krn_kernel k;
    double h, r0, mass, rho0;
    const double *gravity;
    /* periodic axes (NULL or axes 0: none); boundary_images: b holds the
     * boundary images (a running solver) rather than only the real
     * particles (a snapshot read back from boundary.vtu) */
    const dom_periodic *periodic;
    int boundary_images;
    /* [lo, hi] of the whole fluid's z where f may hold only the particles
     * near the points queried (-parallel's domain mode, pcs_gather_near);
     * NULL: f is the whole fluid */
    const double *fluid_z;
    /* the fluid rows that sums and statistics over every particle read
     * (solver/pcs_sums.h; NULL: f): -parallel's domain mode, this rank's
     * own rows, and dom the solver whose ranks those functions combine
     * (collective); NULL: the view holds every particle */
    const sl_fluid *own;
    const struct pcs_solver *dom;
    /* a running solver asked for it (pcs_want_power): the power of the
     * forces on the fluid over its last step, m sum_i a_i . v_i(t + dt),
     * [0] the pressure force's (eq. 6), [1] the other forces' (body forces,
     * viscosity, the effects' forces), W, on rank 0; NaN before the first
     * step.  NULL otherwise (a snapshot read back: postProcess) */
    const double *power;
} pcs_view;

/* The view of s's state. */
pcs_view pcs_view_of(const pcs_solver *s);

/* delta of eq. (4) for a prototype particle with a filled neighbourhood
 * on a cubic lattice of spacing r0, with beta of eq. (5). */
double pcs_delta(const krn_kernel *k, double r0, double mass, double rho0, double dt);

/* delta lambda_max of eq. (3)'s update p += delta rho_err on a cubic
 * lattice of spacing scale r0 (kernel `type` of support `support` r0,
 * delta of the lattice of spacing r0): above 2 one update grows that
 * lattice's largest pressure mode (pcs_params' relaxation). */
double pcs_delta_lambda_max(int type, double support, double scale);

/* Set up: grid over [lo, hi], boundary sorted and its masses set,
 * fluid sorted, delta for dt.  The solver keeps pointers to f, b and the
 * effects (NULL: none, not even gravity; see effects/gravity.h). */
void pcs_init(pcs_solver *s, const pcs_params *p, sl_fluid *f, sl_boundary *b, const double lo[3],
              const double hi[3], double dt, eff_set *effects);
/* pcs_init for a case built in parts (-parallel's domain mode,
 * solver/pcs_domain.h pcd_plan; NULL: pcs_init): f and b hold this rank's
 * share, the plan the cuts and the counts of the whole case. */
struct pcd_plan;
void pcs_init_part(pcs_solver *s, const pcs_params *p, sl_fluid *f, sl_boundary *b,
                   const double lo[3], const double hi[3], double dt, eff_set *effects,
                   struct pcd_plan *plan);
/* The neighbour grid's largest cell count for a case of nfluid and
 * nboundary particles (the whole case's, on every rank alike). */
size_t pcs_grid_cells(size_t nfluid, size_t nboundary);
void pcs_free(pcs_solver *s);
/* Change the time step; recomputes beta and delta (eq. 4, 5). */
void pcs_set_dt(pcs_solver *s, double dt);
/* The world at time t: run the pre-step effects (moving bodies) for t. */
void pcs_place_world(pcs_solver *s, double t);
/* Advance by s->dt from time s->t (s->t is advanced too). */
void pcs_step(pcs_solver *s, pcs_stats *st);
/* pcs_step with the world held where pcs_place_world put it (no moving
 * body moves) and s->t kept: the pseudo-time step of solver/pcs_relax.h. */
void pcs_step_in_place(pcs_solver *s, pcs_stats *st);
/* After a step from t to t + dt was accepted: the post-step effects
 * (emitters). */
void pcs_post_step(pcs_solver *s, double t, double dt);
/* The phases of a step, public for benchmarks: sort and build the
 * neighbour lists; one predicted-density + pressure-update pass (returns
 * the largest compression); one pressure-force pass. */
void pcs_find_neighbours(pcs_solver *s);
double pcs_pass_density(pcs_solver *s);
void pcs_pass_pressure(pcs_solver *s);

/* Density of every fluid particle from the current positions x(t) (for
 * output; uses the lists of the last step or rebuilds them).  -parallel's
 * domain mode: each rank's own particles (output streams them to rank 0,
 * pcd_output_begin). */
void pcs_compute_density(pcs_solver *s);

/* fluid.vtu's derived fields, per particle (the same expressions for the
 * serial and the streamed -parallel output): densityError in percent of
 * rho0, and the paper's Fig. 2 colouring sqrt(p / p_max(t)). */
static inline double pcs_density_error_percent(double rho, double rho0)
{
    return 100.0 * (rho - rho0) / rho0;
}
static inline double pcs_pressure_ratio(double p, double pmax)
{
    return pmax > 0.0 ? sqrt(p / pmax) : 0.0;
}

/* The fluid particles of the case (all ranks'; s->f->n is this rank's in
 * -parallel's domain mode). */
size_t pcs_fluid_total(const pcs_solver *s);
/* The boundary particles of the case (images included; s->b->n is those
 * this rank stores in -parallel's domain mode). */
size_t pcs_boundary_total(const pcs_solver *s);
/* -parallel's domain mode (collective; nothing otherwise): the state of
 * every rank gathered on rank 0 in the serial order, where pcs_view_of
 * shows it to function objects (nothing when already gathered since the
 * last step; output does not gather, it streams: pcd_output_begin). */
/* From the next step on, the power of the forces on the fluid over each
 * step (pcs_view.power): m sum_i a_i . v_i(t + dt) with the velocity
 * before the world's collision, the sum in the density error's
 * association (the same bits on any ranks x threads; collective).  With
 * Euler-Cromer, dt times the two powers is the kinetic energy's change
 * plus dt^2 m sum |a|^2 / 2, less what collisions and particleShifting's
 * velocity correction change.  Costs two passes over the rows a step. */
void pcs_want_power(pcs_solver *s);

void pcs_gather(pcs_solver *s);
/* The same for point queries inside nboxes boxes (6 doubles each: lo x y
 * z, hi x y z; rank 0's, sent to all) only: rank 0 receives the particles
 * of the cells a query there can read (fo_query), in the serial order, and
 * the whole fluid's z extent (pcs_view.fluid_z); the queries then give the
 * serial values.  Collective; nothing outside the domain mode. */
void pcs_gather_near(pcs_solver *s, const double *boxes, size_t nboxes);

#endif
