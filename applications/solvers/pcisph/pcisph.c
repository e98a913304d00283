/*
 * pcisph: the Sluice solver.  Reads a case, builds the world, and advances
 * it with PCISPH and the boundary handling of Ihmsen et al. 2010
 * (Algorithm 2), with the paper's adaptive time stepping and shock
 * handling (Sec. 3.3), writing time directories of VTK files.
 *
 *   pcisph [-case <dir>] [-quiet] [-resume]
 *   mpirun -np N pcisph [-case <dir>] -parallel
 *
 * -parallel (doc/parallel.md): every rank reads the case and holds the
 * whole state; the pressure solve's passes are shared out by rows and
 * gathered (solver/pcisph.h, pcs_split), so every rank takes the same
 * steps and holds the same bits.  Rank 0 alone holds the lock and writes
 * time directories, the record, the function objects' files and the log;
 * the others compute what the writes need (the density at x(t) sorts the
 * fluid) and write nothing.  Requests to stop or write are made the
 * job's by a reduction each step.
 *
 * One solver per case: it holds a lock on <case>/.sluice.lock (case_lock).
 * Writes follow writeControl (adjustableRunTime: steps evened out to land
 * on each write time; runTime: the first step at or past it), and the
 * state at endTime is always written.  SIGINT/SIGTERM/SIGUSR2 or a file
 * named `stopNow` in the case: finish the step, write, exit (a second
 * signal stops at once); -resume (startFrom latestTime for this run)
 * continues.  SIGUSR1 or a file named `writeNow` in the case: write now
 * and go on.  Open MPI's mpirun forwards USR1 and USR2 to the ranks as
 * they are, but a TERM only after odls_base_sigkill_timeout and a KILL
 * one such timeout later, with the log's end lost: under mpirun stop
 * with USR2 or stopNow (doc/parallel.md, "Signals").  Progress with the
 * time left goes to stderr (sl_progress); the End summary reports this
 * session and, after a restart, the whole run.
 */
#include "app/app.h"
#include "case/case.h"
#include "case/case_lock.h"
#include "case/case_output.h"
#include "case/case_part.h"
#include "case/case_step.h"
#include "case/case_record.h"
#include "case/case_restart.h"
#include "solver/pcs_relax.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_progress.h"
#include "core/sl_threads.h"
#include "functionObjects/fo.h"
#include "io/time_dir.h"
#include "parallel/par.h"
#include "solver/pcisph.h"
#include "solver/pcs_domain.h"
#include "solver/pcs_history.h"
#include "timestep/timestep.h"

#include <math.h>
#include <omp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* What a run did, for the End summary: kept for this session and, in
 * the restart file, for the whole run. */
typedef struct run_totals {
    long steps; /* steps computed, those a shock discarded included */
    long shocks;
    double iterations; /* over the steps computed */
    long at_max_iter;  /* stopped at maxIterations with rho_err max above eta */
    long by_guard;     /* stopped by the divergence guard with rho_err max above eta */
    int guard_iter_min, guard_iter_max;
    double dt_min, dt_max; /* of the steps taken (after evening out for writes) */
    double max_err_avg, max_err_max;
    double active_ratio; /* sum over accepted steps of active boundary / fluid */
    long accepted;
    double wall;    /* seconds in the time loop */
    double t_first; /* time the run started from */
    long sessions;
} run_totals;

/* The run's state besides the particles, as plain data: the restart file
 * keeps it (with the effects' saved states after it), so that a restarted run
 * takes exactly the steps an uninterrupted one takes. */
typedef struct run_state {
    ts_state ctl;     /* the controller (its exact dt) */
    double origin;    /* write times are origin + k writeInterval */
    run_totals total; /* the whole run up to this state */
    int have_prev;    /* the state at the start of the step before is kept */
    ts_state ctl_prev;
} run_state;

typedef struct run {
    sl_case c;
    pcs_solver s;
    case_output out;
    case_record rec;
    case_lock lock;
    sl_progress prog;
    ts_state ctl;
    pcs_history hist;   /* the state at the start of the last two steps */
    pcs_snapshot wsnap; /* state written with each time directory (reused) */
    sl_boundary breal;  /* periodic: the real boundary's carried values (reused) */
    size_t eff_size;
    unsigned char *blob; /* run_state + the effects' states for restart files */
    size_t blob_size;
    double t, t_end, next_write, last_write, origin;
    long step;
    int quiet, resume, parallel;
    int root;                   /* rank 0 (or serial): writes and logs */
    run_totals session, before; /* this session; the run before it (restart) */
    double wall0;
    double write_wall;      /* seconds spent writing time directories */
    double cpu0, write_cpu; /* process CPU seconds: at the loop's start, in writing */
    char *restart_dir;      /* the time directory restarted from (NULL: none) */
    pcs_snapshot heads[2];  /* built in parts: its snapshots' headers (case_part.h) */
    int nheads;
} run;

static volatile sig_atomic_t stop_requested, write_requested;
static int stopped_by_file; /* the stop was asked for by the file stopNow */

static volatile sig_atomic_t stop_signals; /* stop signals received */

static void on_stop(int sig)
{
    if (stop_signals++) { /* second signal: stop at once */
        signal(sig, SIG_DFL);
        raise(sig);
    }
    stop_requested = 1;
}

static void on_write(int sig)
{
    (void)sig;
    write_requested = 1;
}

static const app_option options[] = {
    APP_CASE,
    {.name = "quiet", .help = "print no per-step line (summary and errors only)"},
    {.name = "resume",
     .help = "continue from the latest time directory (startFrom latestTime for\n"
             "this run)"},
    {.name = "parallel",
     .help = "run as one of the ranks of mpirun -np N (MPI; doc/parallel.md): one\n"
             "case, the same output as a serial run"},
    APP_END};

static const app_info info = {
    .name = "pcisph",
    .what = "Runs the PCISPH solver on a case.\n"
            "Signals: INT/TERM/USR2 (or a file <dir>/stopNow) write and stop; USR1 (or a\n"
            "file <dir>/writeNow) writes now.  Under mpirun stop with USR2 or stopNow.\n"
            "One solver per case (lock <dir>/.sluice.lock); progress and the time left go to\n"
            "stderr (SLUICE_PROGRESS=off|line|plain).",
    .options = options};

static void print_world(const run *r, const char *dt_rule)
{
    const sl_case *c = &r->c;
    const pcs_solver *s = &r->s;
    sl_info("Case %s", c->dir);
    sl_info("  fluid particles     %zu", pcs_fluid_total(s));
    sl_info("  boundary particles  %zu (%zu shapes, method %s)",
            pcs_boundary_total(s) - s->halo.nb_img, c->nshapes, c->prm.method->name);
    if (c->prm.periodic.axes) {
        char ax[8];
        dom_periodic_axes_text(c->prm.periodic.axes, ax, sizeof ax);
        sl_info("  periodic            %s (%zu boundary images; fluid images every step)", ax,
                s->halo.nb_img);
    }
    sl_info("  particle spacing r0 %g m, support radius h %g m (%g r0), kernel %s", c->prm.r0, s->h,
            c->prm.support, krn_type_name(c->prm.kernel));
    sl_info("  particle mass       %g kg (rho0 r0^3), rho0 %g kg/m^3", s->mass, c->prm.rho0);
    sl_info("  boundary mass       gamma %.6f (Akinci volume x gamma), static density factor %.6f",
            s->cal.gamma, s->cal.c_static);
    sl_info("  time step           %s%s: deltaT %g s (%s), delta %.6g (eq. 4)",
            ts_mode_name(c->ts.mode), ts_is_cost(&c->ts) ? ", controller cost" : "", s->dt, dt_rule,
            s->delta);
    sl_info("  eta                 %g %% of rho0 (eta_max %g %%), iterations %d..%d",
            100 * c->prm.eta, 100 * ts_eta_max(&c->ts, c->prm.eta), c->prm.min_iter,
            c->prm.max_iter);
    char list[512] = "";
    size_t off = 0;
    for (size_t k = 0; k < c->effects.n && off < sizeof list; k++)
        off += (size_t)snprintf(list + off, sizeof list - off, "%s%s", off ? ", " : "",
                                c->effects.e[k].type->name);
    sl_info("  effects             %s", off ? list : "none");
    sl_info("  threads             %d", omp_get_max_threads());
    char unit[32];
    sl_info("  grid                %d x %d x %d cells of %g m, units %s (SLUICE_GRID_UNIT: the "
            "particle order)",
            s->grid.nc[0], s->grid.nc[1], s->grid.nc[2], s->grid.cell,
            nbr_unit_name(&s->grid, unit, sizeof unit));
    if (r->parallel)
        sl_info("  ranks               %d (MPI; %s: doc/parallel.md)", par_size(),
                s->split.domain ? "domain mode, each rank stores its own particles and their halo"
                    : s->split.halo ? "halo mode, replicated state"
                                    : "gather mode, replicated state");
    if (r->parallel) /* mpirun's TERM reaches the ranks late and a KILL follows (header) */
        sl_info("  to stop             touch %s/stopNow, or send USR2 to mpirun: every rank "
                "finishes the step and the state is written",
                c->dir);
    const char *why =
        r->parallel && s->split.halo && !s->split.domain && !getenv("SLUICE_PARALLEL_EXCHANGE")
        ? pcd_periodic_refusal(s)
        : NULL;
    if (why)
        sl_info("  periodic, parallel  the halo mode, not the domain mode: the case has %s", why);
}

/* The status line: simulated time against endTime, steps per second. */
static void progress(run *r)
{
    char what[160];
    double el = sl_progress_elapsed(&r->prog);
    int k = snprintf(what, sizeof what, "t = %.6g of %g s  deltaT %.3g s  %.3g steps/s", r->t,
                     r->t_end, r->ctl.dt, el > 0 ? (double)r->session.steps / el : 0.0);
    if (r->parallel && k > 0 && (size_t)k < sizeof what) {
        const pcs_split *sp = &r->s.split;
        const double stepping = omp_get_wtime() - r->wall0 - r->write_wall;
        snprintf(what + k, sizeof what - (size_t)k, "  %d ranks, rows %zu-%zu, comm %.0f%%",
                 sp->size, sp->rows_min, sp->rows_max,
                 stepping > 0 ? 100 * r->s.time.comm / stepping : 0.0);
    }
    sl_progress_update(&r->prog, r->t, what);
}

/* The whole run so far: the run before this session and the session. */
static run_totals totals_add(const run_totals *a, const run_totals *b)
{
    run_totals t = *a;
    if (!a->steps) return *b;
    if (!b->steps) return *a;
    t.steps += b->steps;
    t.shocks += b->shocks;
    t.iterations += b->iterations;
    t.at_max_iter += b->at_max_iter;
    t.by_guard += b->by_guard;
    t.guard_iter_min = b->by_guard && (!a->by_guard || b->guard_iter_min < a->guard_iter_min)
        ? b->guard_iter_min
        : a->guard_iter_min;
    t.guard_iter_max =
        b->guard_iter_max > a->guard_iter_max ? b->guard_iter_max : a->guard_iter_max;
    t.dt_min = fmin(a->dt_min, b->dt_min);
    t.dt_max = fmax(a->dt_max, b->dt_max);
    t.max_err_avg = fmax(a->max_err_avg, b->max_err_avg);
    t.max_err_max = fmax(a->max_err_max, b->max_err_max);
    t.active_ratio += b->active_ratio;
    t.accepted += b->accepted;
    t.wall += b->wall;
    t.sessions = a->sessions + b->sessions;
    return t;
}

/* The run's state besides the particles, as one block for restart files:
 * run_state, then the effects' state now and at the start of the step
 * before (emitters). */
static void blob_pack(run *r)
{
    run_state st;
    const size_t ne = r->eff_size;
    const pcs_run_state *prev = hist_last(&r->hist);
    memset(&st, 0, sizeof st);
    st.ctl = r->ctl;
    st.origin = r->origin;
    r->session.wall = omp_get_wtime() - r->wall0;
    st.total = totals_add(&r->before, &r->session);
    st.have_prev = prev != NULL;
    if (prev) st.ctl_prev = prev->ctl;
    memcpy(r->blob, &st, sizeof st);
    eff_save(&r->c.effects, r->blob + sizeof st);
    if (prev) memcpy(r->blob + sizeof st + ne, prev->eff, ne);
}

/* Back from a restart file: the state, and the ring holding the start of
 * the step before (where a shock in the next step goes back to). */
static void blob_unpack(run *r, int nsnaps)
{
    run_state st;
    const size_t ne = r->eff_size;
    memcpy(&st, r->blob, sizeof st);
    r->ctl = st.ctl;
    r->origin = st.origin;
    r->before = st.total;
    eff_load(&r->c.effects, r->blob + sizeof st);
    pcs_run_state *prev = hist_slot(&r->hist, 0);
    hist_seed(&r->hist, st.have_prev && nsnaps > 1);
    if (hist_last(&r->hist)) {
        prev->ctl = st.ctl_prev;
        memcpy(prev->eff, r->blob + sizeof st + ne, ne);
    }
}

/* CPU seconds of the process (all its threads). */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* -parallel's domain mode (collective; nothing otherwise): on rank 0 what
 * the function objects due now read of rank 0's copy of the state: the
 * particles near their points when they make point queries only (probes,
 * gauges), nothing for those that read every particle through the view's
 * sums (densityError, energy: every rank sums its own rows, fo_serve),
 * else the whole state. */
static void gather_for(run *r, fo_list *fo)
{
    if (!r->s.split.domain) return;
    const double *boxes = NULL;
    size_t nboxes = 0;
    int want = FO_READS_NOTHING;
    if (r->root) want = fo_wants_region(fo, r->t, r->step, r->last_write == r->t, &boxes, &nboxes);
    want = par_max_int(want);
    if (want == FO_READS_ALL) pcs_gather(&r->s);
    else if (want == FO_READS_NEAR) pcs_gather_near(&r->s, boxes, nboxes);
}

/* The restart file's state of set `set` streamed from the ranks
 * (-parallel's domain mode, rank 0). */
static void streamed_state(pcs_solver *s, int set, double time, double dt, long step, rst_state *st)
{
    const int cols[RST_FIELDS] = {PCD_X,  PCD_Y,  PCD_Z, PCD_VX, PCD_VY,
                                  PCD_VZ, PCD_ID, PCD_P, PCD_RHO};
    st->n = pcd_output_count(s, set);
    st->time = time;
    st->dt = dt;
    st->step = step;
    for (int k = 0; k < RST_FIELDS; k++) st->col[k] = *pcd_output_source(s, set, 1, cols[k], 0, 0);
}

/* The boundary's carried values streamed from their owners (rank 0). */
static void streamed_boundary(pcs_solver *s, rst_bstate *st)
{
    const int cols[RST_BFIELDS] = {PCD_ID, PCD_P, PCD_PT, PCD_RHO};
    st->n = pcd_output_count(s, PCD_SET_BOUNDARY);
    for (int k = 0; k < RST_BFIELDS; k++)
        st->col[k] = *pcd_output_source(s, PCD_SET_BOUNDARY, 1, cols[k], 0, 0);
}

/* The real boundary particles' carried values (periodic images left out,
 * as boundary.vtu and the domain mode's streamed write leave them: an
 * image's are its original's, copied before they are read), compacted in
 * b's order into out (reused). */
static void real_carried(const sl_boundary *b, sl_boundary *out)
{
    const uint32_t nreal = (uint32_t)(b->n - b->nimages);
    prt_boundary_reserve(out, b->n + 1);
    out->n = 0;
    for (size_t j = 0; j < b->n; j++)
        if (b->id[j] < nreal) {
            const size_t q = out->n++;
            out->id[q] = b->id[j];
            out->p[q] = b->p[j];
            out->pt[q] = b->pt[j];
            out->rho[q] = b->rho[j];
        }
}

/* Write time directory r->t (density recomputed from x(t), restart file
 * included); the record is flushed with it.  -parallel's domain mode:
 * rank 0 writes the files from every rank's part, streamed in the serial
 * order (pcd_output_begin), and holds none of the others' state whole. */
static void write_time(run *r)
{
    sl_err err;
    const double w0 = omp_get_wtime(), c0 = cpu_seconds();
    const pcs_run_state *prev = hist_last(&r->hist);
    rst_state st[2];
    rst_bstate bst;
    const int nst = prev ? 2 : 1;
    pcs_compute_density(&r->s); /* sorts: the snapshot is taken after it */
    blob_pack(r);
    int writer = r->root;
    if (r->s.split.domain) {
        writer = pcd_output_begin(&r->s, prev ? &prev->snap : NULL);
        if (writer) {
            streamed_state(&r->s, PCD_SET_FLUID, r->t, r->s.dt, r->step, &st[0]);
            if (prev)
                streamed_state(&r->s, PCD_SET_PREV, prev->snap.time, prev->snap.dt, prev->snap.step,
                               &st[1]);
            streamed_boundary(&r->s, &bst);
        }
    } else {
        snap_take(&r->wsnap, pcs_view_of(&r->s).f, r->t, r->s.dt, r->step);
        rst_state_of(&st[0], &r->wsnap);
        if (prev) rst_state_of(&st[1], &prev->snap);
        const sl_boundary *b = pcs_view_of(&r->s).b;
        if (b->nimages) real_carried(b, &r->breal);
        rst_bstate_of(&bst, b->nimages ? &r->breal : b);
    }
    if (writer) {
        rec_flush(&r->rec);
        if (out_write(&r->out, &r->s, r->t, st, nst, &bst, r->blob, r->blob_size, &err))
            sl_fatal("%s", err.msg);
        if (r->s.split.domain) pcd_output_end(&r->s);
    }
    r->last_write = r->t;
    r->write_wall += omp_get_wtime() - w0;
    r->write_cpu += cpu_seconds() - c0;
}

/* The next write time after t: multiples of writeInterval from the run's
 * origin (its first startTime, kept across restarts, so that a restarted
 * run aims at the very same times). */
static double next_write_after(const run *r, double t)
{
    const double t0 = r->origin, dw = r->c.ctl.write_interval;
    double k = floor((t - t0) / dw + 1e-9) + 1.0;
    return t0 + k * dw;
}


/* A restart file that cannot be used: say which time directory, why, and
 * what to do about it. */
static void restart_refused(const run *r, const tdir_list *l, rst_status st, const sl_err *err)
{
    const char *name = l->name[l->n - 1];
    char advice[1024];
    if (st == RST_DAMAGED && l->n > 1)
        snprintf(advice, sizeof advice,
                 "the time directory %s cannot be continued: remove it "
                 "(listTimes -case %s -time %s -rm) to restart from %s, the one before it, or "
                 "set startFrom startTime to start again",
                 name, r->c.dir, name, l->name[l->n - 2]);
    else if (st == RST_DAMAGED)
        snprintf(advice, sizeof advice,
                 "the time directory %s cannot be continued: set "
                 "startFrom startTime to start again",
                 name);
    else
        snprintf(advice, sizeof advice,
                 "to continue from %s, use the Sluice that wrote it "
                 "with the same case; or set startFrom startTime to start again",
                 name);
    sl_fatal("%s: %s", err->msg, advice);
}

/* The precision that gives the restart folder's own name (it was raised
 * in the run that wrote it), so that records continue under that name. */
static void precision_of(sl_case *c, double t, const char *name)
{
    char buf[64];
    for (int p = c->ctl.time_precision; p <= 17; p++) {
        tdir_name(t, p, buf, sizeof buf);
        if (!strcmp(buf, name)) {
            c->ctl.time_precision = p;
            return;
        }
    }
}

/* What reading the restart file cost each rank (collective): bytes
 * decompressed and read, seconds (case_restart.h's counters). */
static void log_restart_read(const run *r)
{
    const rst_counts c = rst_counters();
    char path[4096];
    struct stat sb;
    snprintf(path, sizeof path, "%s/uniform/restart", r->restart_dir);
    const double size = stat(path, &sb) ? 0.0 : (double)sb.st_size;
    double v[8] = {c.inflated, -c.inflated, c.read, -c.read, c.wall, -c.wall, c.cpu, -c.cpu};
    for (int k = 0; k < 8; k++) v[k] = par_max_double(v[k]);
    sl_info("Restart file read: bytes decompressed per rank %.4g-%.4g, compressed bytes read "
            "%.4g-%.4g (the file %.4g bytes), %.3f-%.3f s wall, %.3f-%.3f s CPU per rank%s",
            -v[1], v[0], -v[3], v[2], size, -v[5], v[4], -v[7], v[6],
            r->c.part ? " (in parts)" : "");
}

/* startFrom latestTime: continue from the newest complete time directory. */
static int restart_from_latest(run *r)
{
    tdir_list l;
    sl_err err;
    int nsnaps = 0;
    if (tdir_list_read(r->c.dir, "fluid.vtu", &l, &err)) sl_fatal("%s", err.msg);
    if (l.n == 0) {
        tdir_list_free(&l);
        sl_warning("startFrom latestTime: no time directory in %s; starting from startTime",
                   r->c.dir);
        return 0;
    }
    size_t len = strlen(r->c.dir) + strlen(l.name[l.n - 1]) + 2;
    char *dir = malloc(len);
    snprintf(dir, len, "%s/%s", r->c.dir, l.name[l.n - 1]);
    pcs_snapshot got[2] = {r->wsnap, hist_slot(&r->hist, 0)->snap};
    rst_status st;
    if (r->c.part) { /* built in parts: the headers now, each rank's records later */
        snap_init(&r->heads[0]), snap_init(&r->heads[1]);
        st = rst_probe(dir, r->heads, 2, &nsnaps, r->blob, r->blob_size, &err);
        r->nheads = nsnaps;
    } else {
        st = rst_read(dir, got, 2, &nsnaps, r->blob, r->blob_size, &err);
        r->wsnap = got[0];
        hist_slot(&r->hist, 0)->snap = got[1];
    }
    if (st != RST_OK) restart_refused(r, &l, st, &err);
    blob_unpack(r, nsnaps);
    const pcs_snapshot *now = r->c.part ? &r->heads[0] : &r->wsnap;
    if (!r->c.part) snap_restore(&r->wsnap, &r->c.fluid);
    r->t = now->time;
    r->step = now->step;
    r->c.ctl.start_time = r->t;
    precision_of(&r->c, r->t, l.name[l.n - 1]);
    sl_info("Restarting from %s (t = %.17g, step %ld)", dir, r->t, r->step);
    r->restart_dir = dir;
    tdir_list_free(&l);
    return 1;
}

/* A boundary particle of this rank by creation index (restore_boundary). */
typedef struct bnd_key {
    uint32_t id, j;
} bnd_key;

static int cmp_bnd_key(const void *a, const void *b)
{
    const uint32_t x = ((const bnd_key *)a)->id, y = ((const bnd_key *)b)->id;
    return (x > y) - (x < y);
}

typedef struct bnd_restore {
    sl_boundary *b;
    const bnd_key *keys;
    size_t matched;
    const size_t *infile; /* the file's count (rst_scan_boundary's *n) */
    size_t total;         /* the case's */
} bnd_restore;

static void restore_bchunk(void *ctx, size_t n, const uint32_t *id, const double *p,
                           const double *pt, const double *rho)
{
    bnd_restore *k = ctx;
    if (*k->infile != k->total) return; /* other walls: not restored (restore_boundary) */
    for (size_t i = 0; i < n; i++) {
        if (id[i] >= k->total) continue; /* damaged (an image's id: never written) */
        const bnd_key want = {id[i], 0};
        const bnd_key *at = bsearch(&want, k->keys, k->b->n, sizeof *k->keys, cmp_bnd_key);
        if (!at) continue; /* another rank's (domain mode) */
        k->b->p[at->j] = p[i];
        k->b->pt[at->j] = pt[i];
        k->b->rho[at->j] = rho[i];
        k->matched++;
    }
}

/* The boundary particles' pressure, p / rho^2 and density from the
 * restart file (each rank the real ones it stores, matched by creation
 * index; periodic images get their originals' before they are read);
 * returns 0 when the file has none (formats 2 and 3), or holds another
 * number of boundary particles than the case (its walls were edited
 * before the restart: a gate removed), which then start from 0. */
static int restore_boundary(run *r)
{
    sl_boundary *b = r->s.b;
    sl_err err;
    bnd_key *keys = sl_malloc((b->n + 1) * sizeof *keys, "boundary ids");
    for (size_t j = 0; j < b->n; j++) keys[j] = (bnd_key){b->id[j], (uint32_t)j};
    qsort(keys, b->n, sizeof *keys, cmp_bnd_key);
    size_t n = 0, real = 0;
    const size_t total = r->s.halo.nb_img ? r->s.halo.nb_real : pcs_boundary_total(&r->s);
    for (size_t j = 0; j < b->n; j++) real += b->id[j] < total;
    bnd_restore k = {b, keys, 0, &n, total};
    if (rst_scan_boundary(r->restart_dir, restore_bchunk, &k, &n, &err))
        sl_fatal("%s: this time directory cannot be continued (listTimes -check marks the damaged "
                 "ones; remove it to restart from the one before, or set startFrom startTime)",
                 err.msg);
    rst_scan_end();
    free(keys);
    if (n && n != k.total) {
        sl_info("Restart file '%s/uniform/restart' holds %zu boundary particles, the case %zu (its "
                "walls changed): the boundary particles' pressures and densities start from 0",
                r->restart_dir, n, k.total);
        return 1;
    }
    if (n && k.matched != real)
        sl_fatal("restart: %zu of this rank's %zu boundary particles found in '%s/uniform/restart' "
                 "(internal error)",
                 k.matched, real, r->restart_dir);
    return n > 0;
}

/* After the solver's set-up on a restart: the pressure and density each
 * fluid particle carries to the next step (now: the file's first state,
 * this rank's part; in the order of the solver's fluid), and the boundary
 * particles' (the warm start of pressureSource divergence and mixed starts
 * from them; boundary.vtu shows the last values of every boundary
 * particle).  A file without them (formats 2 and 3) leaves p = 0 and rho =
 * rho0, as a new run starts: said in the log. */
static void restore_carried(run *r, pcs_snapshot *now)
{
    sl_fluid *f = r->s.f;
    pcs_own_snapshot(&r->s, now); /* domain mode (set-up whole): this rank's, in its order */
    /* a case without boundary particles has none to restore (a fully
     * periodic box): not a file of an older format */
    const int fluid = now->carried, walls = restore_boundary(r) || pcs_boundary_total(&r->s) == 0;
    if (fluid) {
        if (now->n != f->n)
            sl_fatal("restart: %zu fluid particles in the solver, %zu in the state read "
                     "(internal error)",
                     f->n, now->n);
        for (size_t i = 0; i < f->n; i++) {
            if (f->id[i] != now->id[i])
                sl_fatal("restart: the solver's fluid is not in the order of the state read "
                         "(internal error)");
            f->p[i] = now->p[i];
            f->rho[i] = now->rho[i];
        }
    }
    if (fluid && walls) return;
    const int warm = r->c.prm.source != PCS_SOURCE_DENSITY && r->c.prm.warm_start;
    if (warm)
        sl_warning("restart file '%s/uniform/restart' (an older format) holds no pressures: the "
                   "warm start (pressureSource %s, warmStart on) starts from p = 0 and the "
                   "boundary particles' pressures from 0, so this run continues but not as the "
                   "uninterrupted run would (write it again with this Sluice to restart exactly)",
                   r->restart_dir,
                   r->c.prm.source == PCS_SOURCE_DIVERGENCE ? "divergence" : "mixed");
    else
        sl_info("Restart file of an older format: no boundary pressures in it; boundary.vtu "
                "shows 0 for the boundary particles not active since the restart (the fluid "
                "continues exactly)");
}

/* startFrom latestTime and a time directory to continue from (the
 * restart itself may still be refused). */
static int will_restart(const run *r)
{
    tdir_list l;
    sl_err err;
    if (r->c.ctl.start_from != CASE_LATEST_TIME) return 0;
    if (tdir_list_read(r->c.dir, "fluid.vtu", &l, &err)) sl_fatal("%s", err.msg);
    const int any = l.n > 0;
    tdir_list_free(&l);
    return any;
}

/* The run cannot go on: write the last good state (the start of the step
 * that failed) and stop with a non-zero exit. */
static void fail_with_last_good(run *r, const char *why)
{
    char name[64];
    const pcs_run_state *good = hist_restore_last(&r->hist, r->s.f, &r->ctl, &r->c.effects);
    if (good) {
        r->t = good->snap.time;
        r->step = good->snap.step;
        write_time(r);
    }
    out_name(&r->out, r->t, name, sizeof name);
    if (r->root) rec_close(&r->rec);
    par_barrier(); /* the state is written before any rank exits */
    sl_fatal("%s at t = %.9g; last good state written to %s/%s", why, r->t, r->c.dir, name);
}

static void log_step(const run *r, const pcs_stats *st, double step, ts_action a, unsigned crit,
                     double wall)
{
    if (r->quiet) return;
    char why[256] = "";
    const int shock = a == TS_SHOCK || a == TS_SHOCK_STORM;
    if (shock) ts_criteria_text(&r->c.ts, crit, why, sizeof why);
    sl_info("Time = %-10.6g deltaT = %-9.4g iter %2d  rho_err avg %.3f%% max %.3f%% "
            "(before %.3f%% / %.3f%%)  vmax %.3g  Fmax %.3g  boundary %zu  %.3f s%s%s%s",
            r->t, step, st->iterations, 100 * st->err_avg, 100 * st->err_max,
            100 * st->err_avg_before, 100 * st->err_max_before, st->vmax, st->fmax, st->nactive,
            wall, shock ? "  SHOCK " : "", why, shock ? ": back two steps" : "");
}


/* Shock: restore the state of two steps back and resume with the new dt;
 * time directories written after it hold discarded states and go. */
static void roll_back(run *r)
{
    sl_err err;
    const pcs_run_state *back = hist_roll_back(&r->hist, r->s.f, &r->ctl, &r->c.effects);
    r->t = back->snap.time;
    r->step = back->snap.step;
    r->next_write = next_write_after(r, r->t); /* a write passed over is written again */
    if (r->last_write > r->t) r->last_write = -INFINITY;
    if (r->root && out_discard_after(&r->out, r->t, &err)) sl_fatal("%s", err.msg);
}

/* writeControl adjustableRunTime: the controller's dt, adjusted so that a
 * whole number k of equal steps lands exactly on the next write (or end)
 * time.  A step cut short just before a write time would be a sudden
 * change of dt, and PCISPH resolves the same density error in any dt, so a
 * tiny step gives a velocity kick of order 1/dt; spreading the remainder
 * keeps every step within 1 +- 0.5/k of dt (0.5-1.5 dt at worst, for k = 1). */
static double step_adjustable(const run *r, double target, int *last)
{
    const double remaining = target - r->t;
    double k = floor(remaining / r->ctl.dt + 0.5);
    if (k < 1.0) k = 1.0;
    *last = k == 1.0;
    return remaining / k;
}

/* writeControl runTime: the controller's dt as it is, so that the steps do
 * not depend on the write schedule; only the last two steps before endTime
 * share what is left (each 0.5-1 dt, never a sliver). */
static double step_run_time(const run *r, int *last)
{
    const double remaining = r->t_end - r->t, dt = r->ctl.dt;
    *last = remaining <= dt * (1.0 + 1e-9);
    if (*last) return remaining;
    return remaining < 2.0 * dt ? 0.5 * remaining : dt;
}

/* The step to take now and the time it ends at (exactly the target when
 * it is the last one before it). */
static double next_step(const run *r, double *t_after)
{
    int last;
    double step, target;
    if (r->c.ctl.write_control == CASE_RUN_TIME) {
        target = r->t_end;
        step = step_run_time(r, &last);
    } else {
        /* endTime on a write time (to rounding) is that write time, so
         * that a run ending there ends where a longer run writes */
        const double tol = 1e-9 * r->c.ctl.write_interval;
        target = r->next_write <= r->t_end + tol ? r->next_write : r->t_end;
        step = step_adjustable(r, target, &last);
    }
    *t_after = last ? target : r->t + step;
    return step;
}

/* This session's counts of a step computed (a shock's included). */
static void count_step(run *r, const pcs_stats *st, double step)
{
    run_totals *n = &r->session;
    const double eta = r->c.prm.eta;
    if (!n->steps) n->dt_min = n->dt_max = step;
    n->steps++;
    n->iterations += st->iterations;
    n->dt_min = fmin(n->dt_min, step);
    n->dt_max = fmax(n->dt_max, step);
    if (st->err_max > eta && st->iterations >= r->c.prm.max_iter) n->at_max_iter++;
    else if (st->err_max > eta && st->diverging) {
        if (!n->by_guard || st->iterations < n->guard_iter_min) n->guard_iter_min = st->iterations;
        if (st->iterations > n->guard_iter_max) n->guard_iter_max = st->iterations;
        n->by_guard++;
    }
}

/* ... and of a step kept. */
static void count_accepted(run *r, const pcs_stats *st)
{
    run_totals *n = &r->session;
    n->accepted++;
    const size_t nf = pcs_fluid_total(&r->s);
    if (nf) n->active_ratio += (double)st->nactive / (double)nf;
    if (st->err_avg > n->max_err_avg) n->max_err_avg = st->err_avg;
    if (st->err_max > n->max_err_max) n->max_err_max = st->err_max;
}

/* Write after a step: at each write time, and at endTime whatever
 * writeInterval says. */
static void write_if_due(run *r)
{
    const double tol = 1e-9 * r->ctl.dt;
    if (r->t >= r->next_write - tol || r->t >= r->t_end - tol) {
        write_time(r);
        r->next_write = next_write_after(r, r->t);
    }
}

static void advance(run *r)
{
    double t_after, step = next_step(r, &t_after);
    if (step != r->s.dt) pcs_set_dt(&r->s, step);
    hist_remember(&r->hist, r->s.f, r->t, r->s.dt, r->step, &r->ctl, &r->c.effects);
    pcs_stats st;
    double ws = omp_get_wtime();
    r->s.t = r->t;
    pcs_step(&r->s, &st);
    double wall = omp_get_wtime() - ws;
    r->t = t_after;
    r->step++;
    ts_obs o = {st.err_avg,   st.err_max,   st.vmax,
                st.fmax,      st.converged, r->c.prm.max_iter > r->c.prm.min_iter,
                st.iterations};
    unsigned crit = 0;
    ts_action a = ts_update(&r->c.ts, &r->ctl, r->c.prm.eta, r->s.h, &o, &crit);
    const int shock = a == TS_SHOCK || a == TS_SHOCK_STORM;
    if (r->root) rec_step(&r->rec, r->t, step, &st, shock, wall, r->ctl.dt);
    log_step(r, &st, step, a, crit, wall);
    count_step(r, &st, step);
    const char *why = ts_failure(a);
    if (why) fail_with_last_good(r, why);
    if (a == TS_SHOCK) {
        r->session.shocks++;
        roll_back(r);
        pcs_set_dt(&r->s, r->ctl.dt);
        return;
    }
    pcs_post_step(&r->s, r->t - step, step);
    count_accepted(r, &st);
    if (r->s.dt != r->ctl.dt) pcs_set_dt(&r->s, r->ctl.dt);
    write_if_due(r);
}

/* A request file <case>/<name> (rank 0 looks): found and used up. */
static int take_request_file(const run *r, const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", r->c.dir, name);
    if (!r->root || access(path, F_OK) != 0) return 0;
    unlink(path);
    return 1;
}

/* Requests to write (a signal, the file writeNow) and to stop (a signal,
 * the file stopNow): the job's when any rank got one (-parallel: one
 * reduction per step, so that every rank writes and stops at the same
 * step).  Returns whether the job stops after this step: the value the
 * ranks agreed on here, never the flag itself, which a signal may set on
 * one rank after the reduction (that rank would stop a step before the
 * others, whose next collective then finds it gone: MPI_ERR_TRUNCATE in
 * the End summary, seen once under load); such a late request is the
 * next step's. */
static int poll_write_requests(run *r)
{
    if (take_request_file(r, "writeNow")) write_requested = 1;
    if (take_request_file(r, "stopNow")) stop_requested = stopped_by_file = 1;
    int want = (write_requested ? 1 : 0) | (stop_requested ? 2 : 0);
    if (want & 1) write_requested = 0; /* taken: a later signal asks again */
    if (r->parallel) want = par_max_int(want);
    if ((want & 1) && r->last_write != r->t) {
        sl_info("Writing at t = %.9g on request", r->t);
        write_time(r);
    }
    return (want & 2) != 0;
}

/* One line of totals: steps, shocks, iterations, errors, wall time. */
static void summary_totals(const char *label, const run_totals *n, double t_from, double t_to)
{
    sl_info("%s%ld steps (%ld shocks), t = %.6g to %.6g s, %.2f s wall, mean iterations %.2f, "
            "max rho_err avg %.3f%% max %.3f%%",
            label, n->steps, n->shocks, t_from, t_to, n->wall,
            n->steps ? n->iterations / (double)n->steps : 0.0, 100 * n->max_err_avg,
            100 * n->max_err_max);
}

/* Steps whose iterations ended with rho_err max above eta, and why. */
static void summary_unconverged(const run *r, const run_totals *n)
{
    if (n->at_max_iter)
        sl_info("  %ld steps stopped at maxIterations %d with rho_err max above eta",
                n->at_max_iter, r->c.prm.max_iter);
    if (n->by_guard)
        sl_info("  %ld steps stopped by the divergence guard (the error grew; the best "
                "iteration kept) after %d-%d of %d iterations, rho_err max above eta",
                n->by_guard, n->guard_iter_min, n->guard_iter_max, r->c.prm.max_iter);
    if (!n->at_max_iter && !n->by_guard && r->c.ts.mode == TS_CONSTANT)
        sl_info("  every step ended with rho_err max at or below eta");
}

/* -parallel: the balance (fluid rows per rank) and the communication
 * (the largest share of a rank's time loop spent in MPI exchanges, which
 * includes waiting for a slower rank, and for rank 0's writes; messages
 * and bytes received per step by rank 0).  Collective: every rank calls
 * it. */
static void summary_parallel(const run *r, double wall)
{
    const pcs_split *sp = &r->s.split;
    const par_counts pc = par_counters();
    const double comm_max = par_max_double(r->s.time.comm);
    const double comm_min = par_min_double(r->s.time.comm);
    const double steps = r->session.steps > 0 ? (double)r->session.steps : 1.0;
    const double searches = sp->steps > 0 ? (double)sp->steps : 1.0;
    sl_info("  parallel: %d ranks x %d threads; fluid rows per rank min %zu, max %zu (mean over "
            "searches %.0f / %.0f; %ld of %ld searches left a rank without fluid)",
            sp->size, omp_get_max_threads(), sp->rows_min, sp->rows_max,
            sp->rows_min_sum / searches, sp->rows_max_sum / searches, sp->empty, sp->steps);
    if (sp->size > 1 && !sp->domain)
        sl_info("  parallel: particles that changed rank between searches: %ld to a higher rank, "
                "%ld to a lower one (%.1f per search)",
                sp->moved_up, sp->moved_down, (double)(sp->moved_up + sp->moved_down) / searches);
    if (sp->domain) {
        const pcd_counts dc = pcd_counters(&r->s);
        sl_info("  parallel: particles that changed rank between searches: %ld to a higher rank, "
                "%ld to a lower one (%.1f per search; migrated)",
                dc.migrated_up, dc.migrated_down,
                (double)(dc.migrated_up + dc.migrated_down) / searches);
        sl_info("  parallel: domain mode: each rank stores its own particles and their halo only "
                "(particles stored per rank at the last search: min %zu, max %zu of %zu; this "
                "rank's mean %.0f, capacity %zu); halo received per rank min %zu, max %zu (this "
                "rank's mean %.0f)",
                dc.stored_min, dc.stored_max, pcs_fluid_total(&r->s), dc.stored_mean, dc.cap,
                dc.halo_min, dc.halo_max, dc.halo_mean);
        sl_info("  parallel: boundary particles stored per rank (own and halo rows) min %zu, max "
                "%zu of %zu (this rank's mean %.0f); distributed %ld times, %ld changed owner",
                dc.bstored_min, dc.bstored_max, dc.nb_global, dc.bstored_mean, dc.bdistributions,
                dc.bmigrated);
        if (dc.overlap)
            sl_info("  parallel: overlap: %.0f %% of the own rows (the smallest share of a rank, "
                    "mean over searches) read no halo value and are computed while x* and "
                    "p/rho^2 travel",
                    100 * dc.inner_share);
        else
            sl_info("  parallel: no overlap (SLUICE_PARALLEL_OVERLAP=0, or EFF_DENSITY effects): "
                    "the halo exchanges block");
        sl_info("  parallel: %ld rebalances (largest imbalance max/mean %.3f); %ld gathers of the "
                "whole state on rank 0 for function objects, %.2f s; resident memory per "
                "rank at the end %.1f-%.1f MB (particle arrays and neighbour lists %.1f-%.1f MB)",
                dc.rebalances, dc.imbalance_max, dc.gathers, dc.gather_seconds, 1e-6 * dc.mem_min,
                1e-6 * dc.mem_max, 1e-6 * dc.arrays_min, 1e-6 * dc.arrays_max);
        sl_info("  parallel: set-up %s: particles made or read and kept per rank: fluid min %zu, "
                "max %zu of %zu, boundary min %zu, max %zu of %zu; peak resident memory per rank "
                "%.1f-%.1f MB at the end of the set-up (VmHWM)",
                dc.parts ? "in parts (no rank built the whole case)"
                         : "whole (every rank built the whole case)",
                dc.setup_fluid_min, dc.setup_fluid_max, pcs_fluid_total(&r->s),
                dc.setup_boundary_min, dc.setup_boundary_max, dc.nb_global,
                1e-6 * dc.peak_setup_min, 1e-6 * dc.peak_setup_max);
        sl_info("  parallel: output streamed to rank 0: %ld writes, %.3g bytes received per "
                "write, %.2f s (%ld windows asked for while the one before was written, %ld "
                "dropped unread; zlib blocks compressed by the ranks holding them %ld, by rank 0 "
                "%ld); rank 0's largest output buffer %zu particles (of %zu fluid, %zu "
                "boundary), %.3g bytes held; function objects: %ld gathers of the whole state, "
                "%ld of the particles near their points only (%zu cells at the last), %.3g bytes "
                "received per step; %ld reductions over every particle (densityError, energy; "
                "no gather), %.3g bytes received per step, %.2f s; peak resident memory rank 0 "
                "%.1f MB, the others %.1f-%.1f MB",
                dc.out_writes, dc.out_writes ? dc.out_bytes / (double)dc.out_writes : 0.0,
                dc.out_seconds, dc.out_prefetched, dc.out_discarded, dc.out_zblocks_ranks,
                dc.out_zblocks_root, dc.out_window, pcs_fluid_total(&r->s),
                pcs_boundary_total(&r->s), dc.out_held, dc.gathers, dc.near_gathers, dc.near_cells,
                dc.gather_bytes / steps, dc.fo_reductions, dc.fo_bytes / steps, dc.fo_seconds,
                1e-6 * dc.peak_root, 1e-6 * dc.peak_others_min, 1e-6 * dc.peak_others_max);
    }
    if (sp->size == 1) sl_info("  parallel: one rank, nothing exchanged");
    else if (sp->domain)
        ; /* above */
    else if (sp->halo)
        sl_info("  parallel: halo mode: each PCISPH iteration exchanges x*, p/rho^2 and rho of the "
                "halo only (rows received per rank: %zu at the last search, mean %.0f, largest "
                "%zu); the state is gathered once per step",
                sp->halo_rows, sp->halo_sum / searches, sp->halo_max);
    else
        sl_info("  parallel: gather mode: each PCISPH iteration gathers every rank's rows on "
                "every rank (SLUICE_PARALLEL_EXCHANGE=gather)");
    sl_info("  parallel: exchanges %.2f-%.2f s of the %.2f s time loop (%.1f %% at most, waiting "
            "included); per step %.1f collectives, %.1f messages and %.3g bytes received by "
            "rank 0",
            comm_min, comm_max, wall, wall > 0 ? 100 * comm_max / wall : 0.0,
            (double)pc.calls / steps, (double)pc.messages / steps, pc.bytes / steps);
}

static void summary(run *r)
{
    const pcs_timers *tm = &r->s.time;
    const ts_counts *c = &r->ctl.count;
    run_totals *n = &r->session;
    double wall = omp_get_wtime() - r->wall0;
    double phases = tm->world + tm->search + tm->forces + tm->predict + tm->density + tm->pressure +
        tm->integrate;
    n->wall = wall;
    const int restarted = r->before.steps > 0;
    summary_totals(restarted ? "End: this session: " : "End: ", n, r->c.ctl.start_time, r->t);
    if (restarted) {
        run_totals all = totals_add(&r->before, n);
        summary_totals("  whole run: ", &all, r->before.t_first, r->t);
        sl_info("  (the whole run: %ld sessions; below, this session)", all.sessions);
    }
    summary_unconverged(r, n);
    sl_info("  deltaT min %.6g s, max %.6g s (steps taken; the controller's: %.6g to %.6g s, "
            "%ld increases, %ld decreases); active boundary particles per fluid particle %.1f %%",
            n->dt_min, n->dt_max, c->dt_min, c->dt_max, c->increase, c->decrease,
            n->accepted ? 100 * n->active_ratio / (double)n->accepted : 0.0);
    sl_info(
        "  phases: moving world %.2f s, search %.2f s, forces %.2f s, predict+collision %.2f s, "
        "density %.2f s, pressure force %.2f s, integrate %.2f s, output+other %.2f s",
        tm->world, tm->search, tm->forces, tm->predict, tm->density, tm->pressure, tm->integrate,
        wall - phases);
    sl_info("  search: sort %.2f s, fluid lists %.2f s, boundary lists %.2f s", tm->sort,
            tm->list_ff, tm->list_bf);
    for (size_t k = 0; k < r->c.effects.n; k++) {
        const eff_instance *e = &r->c.effects.e[k];
        sl_info("  effect %-24s %8ld calls %8.2f s", e->type->name, e->calls, e->time);
    }
    const double stepping = wall - r->write_wall;
    if (r->parallel) summary_parallel(r, wall);
    const double nf = (double)pcs_fluid_total(&r->s);
    sl_info("  %.3g particle-steps/s (%d threads)", wall > 0 ? nf * (double)n->steps / wall : 0.0,
            omp_get_max_threads());
    const double work = nf * (double)n->steps;
    const double cpu = cpu_seconds() - r->cpu0 - r->write_cpu;
    sl_info("  without output (%.2f s writing): %.2f s, %.3g particle-steps/s, %.3g per thread; "
            "%.2f CPU s, %.3g particle-steps per CPU second",
            r->write_wall, stepping, stepping > 0 ? work / stepping : 0.0,
            stepping > 0 ? work / stepping / omp_get_max_threads() : 0.0, cpu,
            cpu > 0 ? work / cpu : 0.0);
}

/* initialPacking relaxed: the particles relaxed before t = 0
 * (solver/pcs_relax.h), then the initial velocities at their new places.
 * The relaxation runs before the run's solver exists, on a solver of the
 * whole case (one rank's, with a copy of the boundary), so that under
 * -parallel every rank makes the serial run's packing (each holds the
 * whole case until its solver keeps its part) and the run then starts from
 * it as the serial run does. */
static void relax(run *r)
{
    pcs_relax_stats rs;
    const case_packing *k = &r->c.packing;
    if (k->tolerance > 0.0)
        sl_info("%s: initialPacking relaxed: lattice displaced by up to %g r0, then damped steps "
                "of %g s (FIRE) before t = %g until the largest displacement per step stays below "
                "%g r0 for %d steps (at most %ld steps)",
                k->where.text, k->jitter, r->ctl.dt, r->t, k->tolerance, PCS_RELAX_WINDOW,
                k->steps);
    else
        sl_info("%s: initialPacking relaxed: lattice displaced by up to %g r0, then %ld damped "
                "steps of %g s (FIRE) before t = %g",
                k->where.text, k->jitter, k->steps, r->ctl.dt, r->t);
    pcs_params prm = r->c.prm;
    prm.one_rank = 1;
    prm.source = PCS_SOURCE_DENSITY; /* packed to rest density, whatever the run solves */
    prm.hold_mean = 0;               /* the density source's clamp (meanPressure is the run's) */
    sl_boundary walls;
    prt_boundary_copy(&walls, &r->c.boundary);
    pcs_solver s;
    pcs_init(&s, &prm, &r->c.fluid, &walls, r->c.lo, r->c.hi, r->ctl.dt, &r->c.effects);
    pcs_place_world(&s, r->t);
    pcs_relax(&s, k->steps, k->tolerance, k->jitter, r->quiet ? 0 : 50, &rs);
    pcs_free(&s);
    prt_boundary_free(&walls);
    case_initial_velocity(&r->c, &r->c.fluid);
    /* the run's effect counts start after it (its own cost is the line
     * below) */
    for (size_t q = 0; q < r->c.effects.n; q++) {
        r->c.effects.e[q].calls = 0;
        r->c.effects.e[q].time = 0.0;
    }
    sl_info("Relaxed: %ld steps; largest displacement per step %.3g r0 (first), %.3g r0 (last); "
            "rho_err avg %.3f%% max %.3f%%; %ld restarts from rest; %.2f s wall",
            rs.steps, rs.move_first, rs.move_last, 100 * rs.err_avg, 100 * rs.err_max, rs.restarts,
            rs.wall);
    if (k->tolerance > 0.0 && !rs.converged)
        sl_warning("%s: initialPacking relaxed: the largest displacement per step did not stay "
                   "below tolerance %g r0 for %d steps within steps %ld (last %.3g r0): the "
                   "packing is not relaxed to the tolerance; raise steps or tolerance",
                   k->where.text, k->tolerance, PCS_RELAX_WINDOW, k->steps, rs.move_last);
}

static run *the_run; /* for the exit handler */

static void release_lock(void)
{
    if (the_run && the_run->root) case_lock_release(&the_run->lock);
}

/* Before anything is written: hold the case, and clear what runs that
 * died left behind. */
static void claim_case(run *r)
{
    sl_err err;
    char names[512];
    if (r->root) {
        if (case_lock_take(&r->lock, r->c.dir, &err)) sl_fatal("%s", err.msg);
        the_run = r;
        atexit(release_lock);
        size_t n = tdir_remove_stale(r->c.dir, names, sizeof names);
        if (n)
            sl_warning("removed %zu temporaries left in %s by runs that died: %s", n, r->c.dir,
                       names);
        static const char *const requests[] = {"writeNow", "stopNow"};
        for (int q = 0; q < 2; q++) /* made before this run: not for it */
            if (take_request_file(r, requests[q]))
                sl_warning("removed %s/%s, left from before this run (a request to the run "
                           "that holds the case)",
                           r->c.dir, requests[q]);
    }
    par_barrier(); /* the others read the case after rank 0 holds and cleaned it */
}

static void stopped_by_signal(run *r)
{
    if (r->last_write != r->t) write_time(r);
    if (r->root) rec_flush(&r->rec);
    sl_progress_end(&r->prog);
    sl_info("Stopped by %s at t = %.9g (written to %s/%s); resume with ./Allrun -resume, "
            "or pcisph -case %s -resume (startFrom latestTime for one run)",
            stopped_by_file ? "the file stopNow" : "a signal", r->t, r->c.dir, r->out.last_name,
            r->c.dir);
}

static void parse_args(run *r, int argc, char **argv, const char **dir)
{
    app a;
    app_parse(&a, &info, argc, argv);
    *dir = app_case(&a);
    r->quiet = app_found(&a, "quiet");
    r->resume = app_found(&a, "resume");
    r->parallel = app_found(&a, "parallel");
    app_free(&a);
    const int launched = par_launcher_size();
    if (launched > 1 && !r->parallel)
        sl_fatal("started by mpirun with %d ranks but without -parallel: each rank would run "
                 "the whole case alone; add -parallel (mpirun -np %d pcisph -case %s -parallel)",
                 launched, launched, *dir);
    par_init(&argc, &argv, r->parallel);
    r->root = par_root();
    if (!r->root) sl_log_set_secondary(par_rank());
}

static void alloc_state(run *r)
{
    hist_init(&r->hist, &r->c.effects);
    snap_init(&r->wsnap);
    prt_boundary_init(&r->breal);
    r->eff_size = r->hist.eff_size;
    r->blob_size = sizeof(run_state) + 2 * r->eff_size;
    r->blob = calloc(1, r->blob_size);
    if (!r->blob) sl_fatal("out of memory");
}

static void free_state(run *r)
{
    hist_free(&r->hist);
    snap_free(&r->wsnap);
    prt_boundary_free(&r->breal);
    free(r->blob);
    free(r->restart_dir);
}

int main(int argc, char **argv)
{
    const char *dir = ".";
    static run r;
    sl_threads_passive(argv); /* before any parallel region */
    parse_args(&r, argc, argv, &dir);
    signal(SIGINT, on_stop);
    signal(SIGTERM, on_stop);
    signal(SIGUSR2, on_stop); /* mpirun forwards it at once, and sends no KILL after it */
    signal(SIGUSR1, on_write);
    case_read(&r.c, dir);
    if (r.resume) r.c.ctl.start_from = CASE_LATEST_TIME;
    if (r.c.ctl.nthreads > 0) omp_set_num_threads(r.c.ctl.nthreads);
    claim_case(&r);
    /* -parallel's domain mode: no rank makes or reads the whole case (case_part.h) */
    const int parts = r.parallel && case_part_applies(&r.c, will_restart(&r));
    if (parts) case_part_census(&r.c);
    else case_build(&r.c);
    alloc_state(&r);
    char rule[256] = "restart";
    r.t = r.origin = r.c.ctl.start_time;
    int restarted = r.c.ctl.start_from == CASE_LATEST_TIME && restart_from_latest(&r);
    pcd_plan *plan = NULL;
    if (parts)
        plan =
            case_part_build(&r.c, restarted ? r.restart_dir : NULL, r.heads, r.nheads,
                            restarted && hist_last(&r.hist) ? &hist_slot(&r.hist, 0)->snap : NULL);
    if (parts && restarted) { /* this rank's records, their carried values (restore_carried) */
        snap_take(&r.wsnap, &r.c.fluid, r.t, r.ctl.dt, r.step);
        r.wsnap.carried = r.heads[0].carried;
    }
    if (restarted) log_restart_read(&r);
    if (!restarted) {
        ts_init(&r.ctl, case_initial_step(&r.c, rule, sizeof rule));
        r.before.t_first = r.t;
    }
    r.session.t_first = r.t;
    r.session.sessions = 1;
    fo_list *fo = fo_read(&r.c);
    for (size_t q = 0; q < fo_count(fo); q++) /* their copy on rank 0 has no periodic image */
        if (!strcmp(fo_type_name(fo, q), "probes") || !strcmp(fo_type_name(fo, q), "waterGauges"))
            r.c.prm.point_queries = 1;
    if (!restarted && r.c.packing.relaxed) relax(&r);
    pcs_init_part(&r.s, &r.c.prm, &r.c.fluid, &r.c.boundary, r.c.lo, r.c.hi, r.ctl.dt, &r.c.effects,
                  plan);
    pcd_plan_free(plan);
    if (fo_needs(fo) & FO_NEED_POWER) pcs_want_power(&r.s);
    pcs_place_world(&r.s, r.t);
    if (restarted && hist_last(&r.hist)) /* domain mode: this rank's part of it */
        pcs_own_snapshot(&r.s, &hist_slot(&r.hist, 0)->snap);
    if (restarted) restore_carried(&r, &r.wsnap);
    print_world(&r, rule);
    r.t_end = r.c.ctl.end_time;
    r.wall0 = omp_get_wtime();
    r.cpu0 = cpu_seconds();
    out_init(&r.out, &r.c, r.t);
    char start_name[64];
    out_name(&r.out, r.t, start_name, sizeof start_name);
    if (r.root) rec_open(&r.rec, &r.c, start_name);
    if (!restarted) write_time(&r);
    const int fo_on = fo != NULL; /* the same on every rank: they gather for rank 0 */
    if (fo_on) gather_for(&r, fo);
    const pcs_view view = pcs_view_of(&r.s); /* what the function objects read */
    if (!r.root && r.s.split.domain)         /* the files are rank 0's; the sums are every rank's */
        fo_serve(fo);
    else if (!r.root) { /* the other modes: every rank holds every particle; rank 0 writes */
        fo_free(fo);
        fo = NULL;
    }
    if (restarted) fo_start(fo, &view, r.t); /* its state was recorded by the last run */
    else fo_execute(fo, &view, r.t, r.step, 1);
    r.last_write = r.t;
    r.next_write = next_write_after(&r, r.t);
    sl_progress_start(&r.prog, stderr, r.t, r.t_end, 10.0);
    if (!r.root) r.prog.mode = SL_PROGRESS_OFF;
    if (!r.quiet && isatty(STDOUT_FILENO) && r.prog.mode == SL_PROGRESS_LINE)
        r.prog.mode = SL_PROGRESS_PLAIN; /* step lines scroll on the same terminal */
    int stopped = 0;                     /* agreed by every rank (poll_write_requests) */
    while (r.t < r.t_end - 1e-9 * r.ctl.dt) {
        advance(&r);
        stopped = poll_write_requests(&r);
        if (fo_on) gather_for(&r, fo);
        fo_execute(fo, &view, r.t, r.step, r.last_write == r.t);
        progress(&r);
        if (stopped) {
            stopped_by_signal(&r);
            break;
        }
    }
    if (!stopped && r.last_write != r.t) write_time(&r); /* endTime, whatever happened */
    sl_progress_end(&r.prog);
    summary(&r);
    sl_info("Open %s/fluid.pvd in ParaView.", r.c.dir);
    if (r.root) rec_close(&r.rec);
    out_free(&r.out);
    free_state(&r);
    fo_free(fo);
    pcs_free(&r.s);
    case_free(&r.c);
    par_finalize();
    return 0;
}
