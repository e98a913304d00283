/*
 * pcs_snapshot: everything a PCISPH step depends on, copied out and back.
 *
 * A step reads the fluid positions, velocities and ids (in memory order:
 * the stable cell sort keeps ties in that order), the time step and the
 * time, and the pressure and density each particle carries from the step
 * before: pressureSource divergence and mixed start each step from the
 * last step's pressures (the warm start, pcisph.c: its force at x(t) is p
 * / rho^2 with the density in memory, the last prediction's or, after a
 * write, the density at x(t)); the density source rebuilds them from zero
 * (Alg. 2).  The snapshot keeps these, so restoring it and stepping again
 * gives bit-identical results.  Used for the two-step rollback of the
 * shock handling (paper Sec. 3.3) and for restart files (which also keep
 * the boundary particles' pressures: case_restart.h).  Buffers grow on
 * first use and are reused: no allocation in the time loop afterwards.
 */
#ifndef SL_PCS_SNAPSHOT_H
#define SL_PCS_SNAPSHOT_H

#include <stddef.h>
#include <stdint.h>

#include "solver/pcisph.h"

typedef struct pcs_snapshot {
    size_t n, cap;
    double *x, *y, *z, *vx, *vy, *vz;
    uint32_t *id;
    double *p, *rho; /* carried between steps (see above) */
    int carried;     /* p and rho hold them (0: read from a restart file without them) */
    double time, dt;
    long step;
} pcs_snapshot;

void snap_init(pcs_snapshot *s);
void snap_free(pcs_snapshot *s);
void snap_take(pcs_snapshot *s, const sl_fluid *f, double time, double dt, long step);
/* Room for n particles (contents lost when it grows); s->n = n. */
void snap_resize(pcs_snapshot *s, size_t n);
/* One particle appended (the buffers grow, keeping their contents; its p
 * and rho 0: the caller sets them). */
void snap_push(pcs_snapshot *s, double x, double y, double z, double vx, double vy, double vz,
               uint32_t id);
/* Copy back into f (grown to hold s->n particles); without carried
 * values (s->carried 0) p is set to 0 and rho left as it is. */
void snap_restore(const pcs_snapshot *s, sl_fluid *f);
/* -parallel's domain mode (solver/pcs_domain.h), where each rank holds
 * its own particles: a snapshot of every particle cut down to this
 * rank's (restart files are written streamed, never gathered whole).
 * Otherwise nothing. */
void pcs_own_snapshot(const pcs_solver *s, pcs_snapshot *snap);
/* Bitwise equality of two snapshots, p and rho included (for tests). */
int snap_equal(const pcs_snapshot *a, const pcs_snapshot *b);

#endif
