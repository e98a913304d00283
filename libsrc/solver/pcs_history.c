/* pcs_history: the run states of the last two steps (see pcs_history.h). */
#include "solver/pcs_history.h"

#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

void hist_init(pcs_history *h, const eff_set *e)
{
    memset(h, 0, sizeof *h);
    h->eff_size = eff_state_size(e);
    for (int k = 0; k < 2; k++) {
        snap_init(&h->ring[k].snap);
        h->ring[k].eff = sl_malloc(h->eff_size + 1, "effects' saved state");
        memset(h->ring[k].eff, 0, h->eff_size + 1);
    }
}

void hist_free(pcs_history *h)
{
    for (int k = 0; k < 2; k++) {
        snap_free(&h->ring[k].snap);
        free(h->ring[k].eff);
    }
    memset(h, 0, sizeof *h);
}

void hist_remember(pcs_history *h, const sl_fluid *f, double t, double dt, long step,
                   const ts_state *ctl, const eff_set *e)
{
    pcs_run_state *s = &h->ring[h->n % 2];
    snap_take(&s->snap, f, t, dt, step);
    s->ctl = *ctl;
    eff_save(e, s->eff);
    h->n++;
}

pcs_run_state *hist_last(pcs_history *h) { return h->n > 0 ? &h->ring[(h->n - 1) % 2] : NULL; }

const pcs_run_state *hist_roll_back(pcs_history *h, sl_fluid *f, ts_state *ctl, eff_set *e)
{
    const pcs_run_state *s = &h->ring[h->n >= 2 ? (h->n - 2) % 2 : 0];
    snap_restore(&s->snap, f);
    ts_rollback(ctl, &s->ctl);
    eff_load(e, s->eff);
    h->n = 0;
    return s;
}

const pcs_run_state *hist_restore_last(pcs_history *h, sl_fluid *f, ts_state *ctl, eff_set *e)
{
    const pcs_run_state *s = hist_last(h);
    if (!s) return NULL;
    snap_restore(&s->snap, f);
    *ctl = s->ctl;
    eff_load(e, s->eff);
    h->n--;
    return s;
}

pcs_run_state *hist_slot(pcs_history *h, int k) { return &h->ring[k]; }

void hist_seed(pcs_history *h, int have) { h->n = have ? 1 : 0; }
