/*
 * pcisph: the Sluice solver.  Reads a case, builds the world, and advances
 * it with PCISPH and the boundary handling of Ihmsen et al. 2010
 * (Algorithm 2), writing time directories of VTK files.
 *
 *   pcisph [-case <dir>] [-quiet]
 */
#include "case/case.h"
#include "case/case_output.h"
#include "case/case_record.h"
#include "core/sl_log.h"
#include "solver/pcisph.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct run_totals {
    long steps;
    double iterations, max_err_avg, max_err_max, wall;
    int unconverged;
} run_totals;

static void usage(int status)
{
    fprintf(status ? stderr : stdout,
            "Usage: pcisph [-case <dir>] [-quiet] [-help]\n"
            "  Runs the PCISPH solver on the case in <dir> (default: the current directory).\n"
            "  -quiet  print no per-step line (summary and errors only)\n");
    exit(status);
}

static void print_world(const sl_case *c, const pcs_solver *s)
{
    sl_info("Case %s", c->dir);
    sl_info("  fluid particles     %zu", c->fluid.n);
    sl_info("  boundary particles  %zu (%zu shapes, method %s)", c->boundary.n, c->nshapes,
            c->method);
    sl_info("  particle spacing r0 %g m, support radius h %g m", c->prm.r0, s->h);
    sl_info("  particle mass       %g kg (rho0 r0^3), rho0 %g kg/m^3", s->mass, c->prm.rho0);
    sl_info("  boundary mass       gamma %.6f (Akinci volume x gamma), static density factor %.6f",
            s->cal.gamma, s->cal.c_static);
    sl_info("  deltaT              %g s (constant), delta %.6g (eq. 4)", s->dt, s->delta);
    sl_info("  eta                 %g %% of rho0, iterations %d..%d", 100 * c->prm.eta,
            c->prm.min_iter, c->prm.max_iter);
    sl_info("  gravity             (%g %g %g)", c->prm.gravity[0], c->prm.gravity[1],
            c->prm.gravity[2]);
    sl_info("  threads             %d", omp_get_max_threads());
}

static void progress(double t, double t0, double t1, double wall)
{
    if (!isatty(STDERR_FILENO)) return;
    double frac = (t - t0) / (t1 - t0);
    int w = 40, fill = (int)(frac * w);
    fprintf(stderr, "\r[");
    for (int i = 0; i < w; i++) fputc(i < fill ? '#' : '.', stderr);
    fprintf(stderr, "] %5.1f%%  t = %-10.5g  wall %6.1f s", 100 * frac, t, wall);
    if (frac >= 1.0) fputc('\n', stderr);
    fflush(stderr);
}

static void write_or_die(case_output *o, const pcs_solver *s, double t)
{
    sl_err err;
    pcs_compute_density((pcs_solver *)s);
    if (out_write(o, s, t, &err)) sl_fatal("%s", err.msg);
}

int main(int argc, char **argv)
{
    const char *dir = ".";
    int quiet = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-case") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "-quiet")) quiet = 1;
        else if (!strcmp(argv[i], "-help") || !strcmp(argv[i], "--help")) usage(0);
        else { fprintf(stderr, "pcisph: unknown option '%s'\n", argv[i]); usage(2); }
    }
    sl_case c;
    pcs_solver s;
    case_output out;
    case_record rec;
    run_totals tot = {0};
    case_read(&c, dir);
    if (c.ctl.nthreads > 0) omp_set_num_threads(c.ctl.nthreads);
    case_build(&c);
    pcs_init(&s, &c.prm, &c.fluid, &c.boundary, c.lo, c.hi, c.ts.dt);
    print_world(&c, &s);

    const double t0 = c.ctl.start_time, t_end = c.ctl.end_time, dt = c.ts.dt;
    const double tol = 1e-9 * dt;
    double t = t0, next_write = t0;
    double wall0 = omp_get_wtime();
    out_init(&out, &c, t0);
    rec_open(&rec, &c, t0);
    write_or_die(&out, &s, t);
    next_write = t0 + c.ctl.write_interval;
    while (t < t_end - tol) {
        double target = next_write < t_end ? next_write : t_end;
        double step = dt;
        if (t + step > target - tol) step = target - t; /* land on write times */
        if (step != s.dt) pcs_set_dt(&s, step);
        pcs_stats st;
        double ws = omp_get_wtime();
        pcs_step(&s, &st);
        t = (fabs(t + step - target) <= tol) ? target : t + step;
        rec_step(&rec, t, step, &st, 0, omp_get_wtime() - ws);
        tot.steps++;
        tot.iterations += st.iterations;
        if (st.err_avg > tot.max_err_avg) tot.max_err_avg = st.err_avg;
        if (st.err_max > tot.max_err_max) tot.max_err_max = st.err_max;
        tot.unconverged += !st.converged;
        if (!isfinite(st.vmax) || !isfinite(st.fmax))
            sl_fatal("the solution diverged at t = %.9g (non-finite velocity); "
                     "reduce deltaT in system/timeStepDict", t);
        if (!quiet)
            sl_info("Time = %-10.6g deltaT = %-9.4g iter %2d  rho_err avg %.3f%% max %.3f%% "
                    "(before %.3f%% / %.3f%%)  vmax %.3g  Fmax %.3g  active boundary %zu  %.3f s",
                    t, step, st.iterations, 100 * st.err_avg, 100 * st.err_max,
                    100 * st.err_avg_before, 100 * st.err_max_before, st.vmax, st.fmax,
                    st.nactive, omp_get_wtime() - ws);
        if (step != dt) pcs_set_dt(&s, dt);
        if (t >= next_write - tol) {
            write_or_die(&out, &s, t);
            next_write = t0 + (floor((t - t0) / c.ctl.write_interval + 0.5) + 1.0) * c.ctl.write_interval;
        }
        progress(t, t0, t_end, omp_get_wtime() - wall0);
    }
    tot.wall = omp_get_wtime() - wall0;
    const pcs_timers *tm = &s.time;
    double phases = tm->search + tm->forces + tm->predict + tm->density + tm->pressure + tm->integrate;
    sl_info("End: %ld steps, %.2f s wall, mean iterations %.2f, max rho_err avg %.3f%% max %.3f%%, "
            "%d steps stopped at maxIterations",
            tot.steps, tot.wall, tot.steps ? tot.iterations / (double)tot.steps : 0.0,
            100 * tot.max_err_avg, 100 * tot.max_err_max, tot.unconverged);
    sl_info("  phases: search %.2f s, forces %.2f s, predict+collision %.2f s, density %.2f s, "
            "pressure force %.2f s, integrate %.2f s, output+other %.2f s",
            tm->search, tm->forces, tm->predict, tm->density, tm->pressure, tm->integrate,
            tot.wall - phases);
    sl_info("  search: sort %.2f s, fluid lists %.2f s, boundary lists %.2f s",
            tm->sort, tm->list_ff, tm->list_bf);
    sl_info("  %.3g particle-steps/s (%d threads)",
            tot.wall > 0 ? (double)c.fluid.n * (double)tot.steps / tot.wall : 0.0,
            omp_get_max_threads());
    sl_info("Open %s/fluid.pvd in ParaView.", c.dir);
    rec_close(&rec);
    out_free(&out);
    pcs_free(&s);
    case_free(&c);
    return 0;
}
