/*
 * pcs_history: the state of a run that the next step depends on, kept at
 * the start of the last two steps, for the two-step rollback of the shock
 * handling (paper Sec. 3.3, eq. 24-27) and for restart files.
 *
 * A run state is the particles (pcs_snapshot: positions, velocities, ids
 * in memory order, t, dt, step), the time-step controller (ts_state) and
 * the effects' saved state (eff_save: emitters).  Restoring one and
 * stepping again gives bit-identical results.  Buffers grow on first use
 * and are reused: no allocation in the time loop afterwards.
 */
#ifndef SL_PCS_HISTORY_H
#define SL_PCS_HISTORY_H

#include "effects/effects.h"
#include "solver/pcs_snapshot.h"
#include "timestep/timestep.h"

typedef struct pcs_run_state {
    pcs_snapshot snap;
    ts_state ctl;
    unsigned char *eff; /* eff_state_size bytes */
} pcs_run_state;

typedef struct pcs_history {
    pcs_run_state ring[2];
    int n; /* states kept since the start or the last rollback */
    size_t eff_size;
} pcs_history;

void hist_init(pcs_history *h, const eff_set *e);
void hist_free(pcs_history *h);
/* Keep the state at the start of a step. */
void hist_remember(pcs_history *h, const sl_fluid *f, double t, double dt, long step,
                   const ts_state *ctl, const eff_set *e);
/* The state at the start of the step just taken; NULL if none is kept. */
pcs_run_state *hist_last(pcs_history *h);
/* A shock: back to the start of the step before the last one (or of the
 * last, when only one is kept): the fluid, the controller (ts_rollback:
 * the new, smaller step and the run's counts are kept) and the effects.
 * The history starts again from there; returns the state gone back to. */
const pcs_run_state *hist_roll_back(pcs_history *h, sl_fluid *f, ts_state *ctl, eff_set *e);
/* The run cannot go on: back to the start of the step just taken (the
 * last state, controller copied as it was), which leaves the history. */
const pcs_run_state *hist_restore_last(pcs_history *h, sl_fluid *f, ts_state *ctl, eff_set *e);
/* Restart: slot 0 holds the state at the start of the step before the
 * restart time (read into hist_slot(h, 0)); mark it kept (n = 1), or the
 * history empty (have == 0). */
pcs_run_state *hist_slot(pcs_history *h, int k);
void hist_seed(pcs_history *h, int have);

#endif
