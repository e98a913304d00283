/*
 * pcisph: the Sluice solver.  Reads a case, builds the world, and advances
 * it with PCISPH and the boundary handling of Ihmsen et al. 2010
 * (Algorithm 2), with the paper's adaptive time stepping and shock
 * handling (Sec. 3.3), writing time directories of VTK files.
 *
 *   pcisph [-case <dir>] [-quiet]
 *
 * SIGINT/SIGTERM: finish the step, write, exit (a second one stops at
 * once).  SIGUSR1 or a file named `writeNow` in the case: write now and go on.
 */
#include "case/case.h"
#include "case/case_output.h"
#include "case/case_record.h"
#include "case/case_restart.h"
#include "core/sl_log.h"
#include "functionObjects/fo.h"
#include "io/time_dir.h"
#include "solver/pcisph.h"
#include "solver/pcs_snapshot.h"
#include "timestep/timestep.h"

#include <math.h>
#include <omp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct run {
    sl_case c;
    pcs_solver s;
    case_output out;
    case_record rec;
    ts_state ctl;
    pcs_snapshot back[2];      /* state at the start of the last two steps */
    pcs_snapshot wsnap;        /* state written with each time directory (reused) */
    ts_state ctl_back[2];
    unsigned char *eff_back[2]; /* the effects' saved state, likewise */
    size_t eff_size;
    unsigned char *blob;       /* controller + effects' state for restart files */
    size_t blob_size;
    int nback;                 /* how many of back[] are valid */
    double t, t_end, next_write, last_write;
    long step;
    int quiet;
    /* totals */
    double iterations, max_err_avg, max_err_max, wall0;
    double active_ratio;       /* sum over accepted steps of active boundary / fluid */
    long unconverged;
} run;

static volatile sig_atomic_t stop_requested, write_requested;

static void on_stop(int sig)
{
    if (stop_requested) { /* second signal: stop at once */
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

static void usage(int status)
{
    fprintf(status ? stderr : stdout,
            "Usage: pcisph [-case <dir>] [-quiet] [-help]\n"
            "  Runs the PCISPH solver on the case in <dir> (default: the current directory).\n"
            "  -quiet  print no per-step line (summary and errors only)\n"
            "  Signals: INT/TERM write and stop; USR1 (or a file <dir>/writeNow) writes now.\n");
    exit(status);
}

static void print_world(const run *r, const char *dt_rule)
{
    const sl_case *c = &r->c;
    const pcs_solver *s = &r->s;
    sl_info("Case %s", c->dir);
    sl_info("  fluid particles     %zu", c->fluid.n);
    sl_info("  boundary particles  %zu (%zu shapes, method %s)", c->boundary.n, c->nshapes,
            c->prm.method->name);
    sl_info("  particle spacing r0 %g m, support radius h %g m", c->prm.r0, s->h);
    sl_info("  particle mass       %g kg (rho0 r0^3), rho0 %g kg/m^3", s->mass, c->prm.rho0);
    sl_info("  boundary mass       gamma %.6f (Akinci volume x gamma), static density factor %.6f",
            s->cal.gamma, s->cal.c_static);
    sl_info("  time step           %s: deltaT %g s (%s), delta %.6g (eq. 4)",
            ts_mode_name(c->ts.mode), s->dt, dt_rule, s->delta);
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
}

static void progress(const run *r)
{
    if (!isatty(STDERR_FILENO)) return;
    double t0 = r->c.ctl.start_time, frac = (r->t - t0) / (r->t_end - t0);
    int w = 40, fill = (int)(frac * w);
    fprintf(stderr, "\r[");
    for (int i = 0; i < w; i++) fputc(i < fill ? '#' : '.', stderr);
    fprintf(stderr, "] %5.1f%%  t = %-10.5g dt = %-9.3g wall %6.1f s", 100 * frac, r->t, r->s.dt,
            omp_get_wtime() - r->wall0);
    if (frac >= 1.0) fputc('\n', stderr);
    fflush(stderr);
}

/* The run's state besides the particles, as one block for restart files:
 * the controller, then the effects' saved state (emitters). */
static void blob_pack(run *r)
{
    memcpy(r->blob, &r->ctl, sizeof r->ctl);
    eff_save(&r->c.effects, r->blob + sizeof r->ctl);
}

static void blob_unpack(run *r)
{
    memcpy(&r->ctl, r->blob, sizeof r->ctl);
    eff_load(&r->c.effects, r->blob + sizeof r->ctl);
}

/* Write time directory r->t (density recomputed from x(t), restart file
 * included). */
static void write_time(run *r)
{
    sl_err err;
    pcs_compute_density(&r->s); /* sorts: the snapshot is taken after it */
    snap_take(&r->wsnap, r->s.f, r->t, r->s.dt, r->step);
    blob_pack(r);
    if (out_write(&r->out, &r->s, r->t, &r->wsnap, r->blob, r->blob_size, &err))
        sl_fatal("%s", err.msg);
    r->last_write = r->t;
}

/* The next write time after t (multiples of writeInterval from startTime). */
static double next_write_after(const run *r, double t)
{
    const double t0 = r->c.ctl.start_time, dw = r->c.ctl.write_interval;
    double k = floor((t - t0) / dw + 1e-9) + 1.0;
    return t0 + k * dw;
}

/* Height of the fluid's top above the lowest boundary particle, along g. */
static double fluid_height(const sl_case *c)
{
    const double *g = c->prm.gravity;
    double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), top = -INFINITY, low = INFINITY;
    if (gn == 0.0) return 0.0;
    for (size_t i = 0; i < c->fluid.n; i++) {
        double u = -(g[0] * c->fluid.x[i] + g[1] * c->fluid.y[i] + g[2] * c->fluid.z[i]) / gn;
        if (u > top) top = u;
        if (u < low) low = u;
    }
    for (size_t i = 0; i < c->boundary.n; i++) {
        double u = -(g[0] * c->boundary.x[i] + g[1] * c->boundary.y[i] + g[2] * c->boundary.z[i]) / gn;
        if (u < low) low = u;
    }
    return top > low ? top - low : 0.0;
}

static double initial_step(run *r, char *rule, size_t len)
{
    const sl_case *c = &r->c;
    double v2 = 0.0;
    for (size_t i = 0; i < c->fluid.n; i++) {
        double a = c->fluid.vx[i] * c->fluid.vx[i] + c->fluid.vy[i] * c->fluid.vy[i] +
                   c->fluid.vz[i] * c->fluid.vz[i];
        if (a > v2) v2 = a;
    }
    for (size_t e = 0; e < c->nemitters; e++)
        if (c->emitters[e].speed * c->emitters[e].speed > v2) v2 = c->emitters[e].speed * c->emitters[e].speed;
    const double *g = c->prm.gravity;
    double dt = ts_initial(&c->ts, 2.0 * c->prm.r0, sqrt(v2),
                           sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), fluid_height(c), rule, len);
    if (c->ts.mode == TS_ADAPTIVE && !(c->ts.delta_t > 0.0)) {
        krn_kernel k;
        const double m = c->prm.rho0 * c->prm.r0 * c->prm.r0 * c->prm.r0, H = fluid_height(c);
        const double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        krn_init(&k, 2.0 * c->prm.r0);
        double dtp = ts_initial_pressure(c->prm.eta, c->ts.iterations,
                                         pcs_delta(&k, c->prm.r0, m, c->prm.rho0, 1.0), gn, H);
        if (dtp < dt && dtp >= c->ts.delta_t_min) {
            dt = dtp;
            snprintf(rule, len, "hydrostatic pressure: a %g m column held with %d iterations at "
                                "an average compression of eta/2", H, c->ts.iterations);
        }
    }
    if (!(dt > 0.0))
        sl_fatal("%s/system/timeStepDict: no initial time step can be estimated (fluid at rest, no "
                 "gravity): give deltaT", c->dir);
    return dt;
}

/* startFrom latestTime: continue from the newest complete time directory. */
static int restart_from_latest(run *r)
{
    tdir_list l;
    sl_err err;
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
    if (rst_read(dir, &r->back[0], r->blob, r->blob_size, &err)) sl_fatal("%s", err.msg);
    blob_unpack(r);
    snap_restore(&r->back[0], &r->c.fluid);
    r->t = r->back[0].time;
    r->step = r->back[0].step;
    r->c.ctl.start_time = r->t;
    sl_info("Restarting from %s (t = %.9g, step %ld)", dir, r->t, r->step);
    free(dir);
    tdir_list_free(&l);
    return 1;
}

/* The run cannot go on: write the last good state (the start of the step
 * that failed) and stop with a non-zero exit. */
static void fail_with_last_good(run *r, const char *why)
{
    char name[64];
    const pcs_snapshot *good = &r->back[(r->nback - 1) % 2];
    if (r->nback > 0) {
        snap_restore(good, r->s.f);
        r->t = good->time;
        r->step = good->step;
        write_time(r);
    }
    tdir_name(r->t, r->c.ctl.time_precision, name, sizeof name);
    rec_close(&r->rec);
    sl_fatal("%s at t = %.9g; last good state written to %s/%s", why, r->t, r->c.dir, name);
}

static void log_step(const run *r, const pcs_stats *st, double step, ts_action a,
                     unsigned crit, double wall)
{
    if (r->quiet) return;
    char why[256] = "";
    if (a == TS_SHOCK) ts_criteria_text(&r->c.ts, crit, why, sizeof why);
    sl_info("Time = %-10.6g deltaT = %-9.4g iter %2d  rho_err avg %.3f%% max %.3f%% "
            "(before %.3f%% / %.3f%%)  vmax %.3g  Fmax %.3g  boundary %zu  %.3f s%s%s%s",
            r->t, step, st->iterations, 100 * st->err_avg, 100 * st->err_max,
            100 * st->err_avg_before, 100 * st->err_max_before, st->vmax, st->fmax,
            st->nactive, wall, a == TS_SHOCK ? "  SHOCK " : "", why,
            a == TS_SHOCK ? ": back two steps" : "");
}

/* Keep the state at the start of this step (ring of two). */
static void remember(run *r)
{
    const int k = r->nback % 2;
    snap_take(&r->back[k], r->s.f, r->t, r->s.dt, r->step);
    r->ctl_back[k] = r->ctl;
    eff_save(&r->c.effects, r->eff_back[k]);
    r->nback++;
}

/* Shock: restore the state of two steps back and resume with the new dt. */
static void roll_back(run *r)
{
    int k = r->nback >= 2 ? (r->nback - 2) % 2 : 0;
    snap_restore(&r->back[k], r->s.f);
    ts_rollback(&r->ctl, &r->ctl_back[k]);
    eff_load(&r->c.effects, r->eff_back[k]);
    r->t = r->back[k].time;
    r->step = r->back[k].step;
    r->nback = 0; /* the history restarts from here */
    r->next_write = next_write_after(r, r->t); /* a write passed over is written again */
}

/* The step to take: the controller's dt, adjusted so that a whole number
 * k of equal steps lands exactly on the next write (or end) time.  A step
 * cut short just before a write time would be a sudden change of dt, and
 * PCISPH resolves the same density error in any dt, so a tiny step gives a
 * velocity kick of order 1/dt; spreading the remainder keeps every step
 * within 1 +- 0.5/k of dt (0.5-1.5 dt at worst, for k = 1). */
static double next_step(const run *r, double target, int *last)
{
    const double remaining = target - r->t;
    double k = floor(remaining / r->ctl.dt + 0.5);
    if (k < 1.0) k = 1.0;
    *last = k == 1.0;
    return remaining / k;
}

static void advance(run *r)
{
    const double tol = 1e-9 * r->ctl.dt;
    const double target = r->next_write < r->t_end ? r->next_write : r->t_end;
    int last;
    double step = next_step(r, target, &last);
    if (step != r->s.dt) pcs_set_dt(&r->s, step);
    remember(r);
    pcs_stats st;
    double ws = omp_get_wtime();
    r->s.t = r->t;
    pcs_step(&r->s, &st);
    double wall = omp_get_wtime() - ws;
    r->t = last ? target : r->t + step;
    r->step++;
    ts_obs o = {st.err_avg, st.err_max, st.vmax, st.fmax};
    unsigned crit = 0;
    double dt_used = r->ctl.dt;
    ts_action a = ts_update(&r->c.ts, &r->ctl, r->c.prm.eta, r->s.h, &o, &crit);
    rec_step(&r->rec, r->t, step, &st, a == TS_SHOCK, wall, r->ctl.dt);
    log_step(r, &st, step, a, crit, wall);
    r->iterations += st.iterations;
    r->unconverged += !st.converged;
    if (!isfinite(st.vmax) || !isfinite(st.fmax) || !isfinite(st.err_max)) {
        if (a != TS_SHOCK)
            fail_with_last_good(r, "the solution diverged (non-finite velocity or density); "
                                   "reduce deltaT in system/timeStepDict or use mode adaptive");
    }
    /* constant mode: the step must let PCISPH reach eta; when iterating to
     * convergence cannot bring the error down (the average above eta, or
     * the maximum above eta_max), the step is too large for this case */
    if (r->c.ts.mode == TS_CONSTANT &&
        (st.err_avg > ts_eta_max(&r->c.ts, r->c.prm.eta) ||
         (!st.converged && r->c.prm.max_iter > r->c.prm.min_iter &&
          (st.err_max > ts_eta_max(&r->c.ts, r->c.prm.eta) || st.err_avg > r->c.prm.eta))))
        fail_with_last_good(r, "not converging: PCISPH cannot bring the density error below "
                               "eta at this deltaT; reduce deltaT in system/timeStepDict or use "
                               "mode adaptive");
    if (a == TS_TOO_SMALL)
        fail_with_last_good(r, "not stable: the time step fell below deltaTMin");
    if (a == TS_SHOCK) {
        if (!(r->ctl.dt > 1e-9 * dt_used) || !(r->ctl.dt > 1e-14))
            fail_with_last_good(r, "not converging: shocks keep shrinking the time step");
        roll_back(r);
        pcs_set_dt(&r->s, r->ctl.dt);
        return;
    }
    pcs_post_step(&r->s, r->t - step, step);
    if (r->s.f->n) r->active_ratio += (double)st.nactive / (double)r->s.f->n;
    if (st.err_avg > r->max_err_avg) r->max_err_avg = st.err_avg;
    if (st.err_max > r->max_err_max) r->max_err_max = st.err_max;
    if (r->s.dt != r->ctl.dt) pcs_set_dt(&r->s, r->ctl.dt);
    if (r->t >= r->next_write - tol) {
        write_time(r);
        r->next_write = next_write_after(r, r->t);
    }
}

static void poll_write_requests(run *r)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/writeNow", r->c.dir);
    if (access(path, F_OK) == 0) {
        unlink(path);
        write_requested = 1;
    }
    if (write_requested && r->last_write != r->t) {
        sl_info("Writing at t = %.9g on request", r->t);
        write_time(r);
    }
    write_requested = 0;
}

static void summary(const run *r)
{
    const pcs_timers *tm = &r->s.time;
    const ts_counts *n = &r->ctl.count;
    double wall = omp_get_wtime() - r->wall0;
    double phases = tm->world + tm->search + tm->forces + tm->predict + tm->density + tm->pressure +
                    tm->integrate;
    long steps = n->steps;
    sl_info("End: %ld steps (%ld shocks, %ld increases, %ld decreases), %.2f s wall, "
            "mean iterations %.2f, max rho_err avg %.3f%% max %.3f%%",
            steps, n->shock, n->increase, n->decrease, wall,
            steps ? r->iterations / (double)steps : 0.0, 100 * r->max_err_avg,
            100 * r->max_err_max);
    if (r->c.ts.mode == TS_CONSTANT)
        sl_info("  %ld steps stopped at maxIterations with rho_err max above eta", r->unconverged);
    sl_info("  deltaT min %.4g s, max %.4g s; active boundary particles per fluid particle %.1f %%",
            n->dt_min, n->dt_max, steps ? 100 * r->active_ratio / (double)(steps - n->shock) : 0.0);
    sl_info("  phases: moving world %.2f s, search %.2f s, forces %.2f s, predict+collision %.2f s, "
            "density %.2f s, pressure force %.2f s, integrate %.2f s, output+other %.2f s",
            tm->world, tm->search, tm->forces, tm->predict, tm->density, tm->pressure,
            tm->integrate, wall - phases);
    sl_info("  search: sort %.2f s, fluid lists %.2f s, boundary lists %.2f s", tm->sort,
            tm->list_ff, tm->list_bf);
    for (size_t k = 0; k < r->c.effects.n; k++) {
        const eff_instance *e = &r->c.effects.e[k];
        sl_info("  effect %-24s %8ld calls %8.2f s", e->type->name, e->calls, e->time);
    }
    sl_info("  %.3g particle-steps/s (%d threads)",
            wall > 0 ? (double)r->c.fluid.n * (double)steps / wall : 0.0, omp_get_max_threads());
}

int main(int argc, char **argv)
{
    const char *dir = ".";
    static run r;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-case") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "-quiet")) r.quiet = 1;
        else if (!strcmp(argv[i], "-help") || !strcmp(argv[i], "--help")) usage(0);
        else { fprintf(stderr, "pcisph: unknown option '%s'\n", argv[i]); usage(2); }
    }
    signal(SIGINT, on_stop);
    signal(SIGTERM, on_stop);
    signal(SIGUSR1, on_write);
    case_read(&r.c, dir);
    if (r.c.ctl.nthreads > 0) omp_set_num_threads(r.c.ctl.nthreads);
    case_build(&r.c);
    fo_list *fo = fo_read(&r.c);
    snap_init(&r.back[0]);
    snap_init(&r.back[1]);
    snap_init(&r.wsnap);
    r.eff_size = eff_state_size(&r.c.effects);
    r.eff_back[0] = calloc(1, r.eff_size + 1);
    r.eff_back[1] = calloc(1, r.eff_size + 1);
    r.blob_size = sizeof r.ctl + r.eff_size;
    r.blob = calloc(1, r.blob_size);
    if (!r.eff_back[0] || !r.eff_back[1] || !r.blob) sl_fatal("out of memory");
    char rule[256] = "restart";
    r.t = r.c.ctl.start_time;
    int restarted = r.c.ctl.start_from == CASE_LATEST_TIME && restart_from_latest(&r);
    if (!restarted) ts_init(&r.ctl, initial_step(&r, rule, sizeof rule));
    pcs_init(&r.s, &r.c.prm, &r.c.fluid, &r.c.boundary, r.c.lo, r.c.hi, r.ctl.dt, &r.c.effects);
    pcs_place_world(&r.s, r.t);
    print_world(&r, rule);
    r.t_end = r.c.ctl.end_time;
    r.wall0 = omp_get_wtime();
    out_init(&r.out, &r.c, r.t);
    rec_open(&r.rec, &r.c, r.t);
    if (!restarted) write_time(&r);
    const pcs_view view = pcs_view_of(&r.s); /* what the function objects read */
    if (restarted) fo_start(fo, &view, r.t); /* its state was recorded by the last run */
    else fo_execute(fo, &view, r.t, r.step, 1);
    r.last_write = r.t;
    r.next_write = next_write_after(&r, r.t);
    while (r.t < r.t_end - 1e-9 * r.ctl.dt) {
        advance(&r);
        poll_write_requests(&r);
        fo_execute(fo, &view, r.t, r.step, r.last_write == r.t);
        progress(&r);
        if (stop_requested) {
            if (r.last_write != r.t) write_time(&r);
            sl_info("Stopped by a signal at t = %.9g; continue with 'startFrom latestTime;'", r.t);
            break;
        }
    }
    summary(&r);
    sl_info("Open %s/fluid.pvd in ParaView.", r.c.dir);
    rec_close(&r.rec);
    out_free(&r.out);
    snap_free(&r.back[0]);
    snap_free(&r.back[1]);
    snap_free(&r.wsnap);
    free(r.eff_back[0]);
    free(r.eff_back[1]);
    free(r.blob);
    fo_free(fo);
    pcs_free(&r.s);
    case_free(&r.c);
    return 0;
}
