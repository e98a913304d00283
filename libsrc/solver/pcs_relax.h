/*
 * pcs_relax: a relaxed initial packing (constant/fluidProperties:
 * initialPacking relaxed), before t = 0.
 *
 * The fluid is built on a cubic lattice.  Under the SPH pressure force a
 * cubic lattice is an equilibrium but perhaps not a stable one
 * (doc/verification.md, "Bursts"): the hypothesis is that it rearranges
 * after a delay, and that a packing relaxed beforehand does not.  The
 * relaxation: every particle displaced by up to jitter r0 along each axis
 * (a hash of its id, so the same on every thread count and every run),
 * then `steps` pseudo-time steps of the case's own step (forces, pressure
 * solve to eta, walls) with the world held still, damped by FIRE (Bitzek,
 * Koskinen, Gahler, Moseler & Gumbsch 2006, PRL 97 170201: the velocity
 * turned towards the force while the power F.v is positive, zeroed when it
 * turns negative; the step fixed at the case's): a damped descent to the
 * discrete equilibrium of the case's forces (gravity included: a column settles to its
 * hydrostatic compression, the "settling phase" of DualSPHysics users;
 * PCISPH rebuilds the pressure from zero every step, so an initial
 * pressure field would not survive the first step, and the compression
 * that holds a column up is what the settling gives).  The moving walls'
 * velocities are zero during it and restored after.
 *
 * On a solver of the whole case (pcs_params.one_rank: under -parallel
 * every rank relaxes the whole case alike before the split).  The
 * velocities are zero at the end: the caller sets the initial ones at the
 * relaxed positions (case_initial_velocity).
 */
#ifndef SL_PCS_RELAX_H
#define SL_PCS_RELAX_H

#include "solver/pcisph.h"

typedef struct pcs_relax_stats {
    long steps;    /* steps taken */
    int converged; /* tolerance > 0: met (the last PCS_RELAX_WINDOW steps below it) */
    double move_first, move_last; /* largest displacement of a step / r0: first, last */
    double move_max;              /* largest of any step */
    double err_avg, err_max;      /* compression after the last step (fraction of rho0) */
    long restarts;                /* FIRE restarts from rest */
    double wall;                  /* seconds */
} pcs_relax_stats;

/* Displace fluid particle i by up to jitter r0 per axis (deterministic in
 * its id), wrap periodic axes. */
void pcs_jitter(pcs_solver *s, double jitter);
/* The residual stop: with tolerance > 0 the relaxation ends once the
 * largest displacement of a step, dt max|v| / r0, has stayed below
 * tolerance for PCS_RELAX_WINDOW consecutive steps.  dt max|v| / r0 is the
 * largest speed over the solver's own speed r0 / dt, which sets PCISPH's
 * stiffness (doc/verification.md, Taylor-Green): case-independent (no
 * height or gravity needed, unlike a speed over sqrt(g H)) and, at dt
 * proportional to r0, the same bound on the speed at every level of a
 * sweep.  The window: FIRE's restarts zero the velocity, so single steps
 * are small after one; over 100 steps from rest a particle reaches the
 * tolerance unless its acceleration is below tolerance r0 / (100 dt^2).
 * (The largest force is no residual: a particle held by a wall keeps
 * tens of m/s^2 at rest.)  A maximum: the same on every thread count,
 * so the stopping step is too. */
#define PCS_RELAX_WINDOW 100
/* The relaxation above, at the solver's dt: at most `steps` steps (all of
 * them with tolerance 0); logs every `every` steps (0: the first and last
 * only). */
void pcs_relax(pcs_solver *s, long steps, double tolerance, double jitter, long every,
               pcs_relax_stats *out);

#endif
