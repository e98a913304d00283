/*
 * benchPcisph: one benchmark run of the PCISPH step on a dam-break scene of
 * a given size (a fluid block of proportions 0.4 x 0.6 x 0.6 in the corner
 * of a closed tank four block-lengths long, full boundary), with a constant
 * time step and a fixed number of PCISPH iterations.  Prints key=value
 * lines that tests/bench/run_bench turns into the Markdown report.
 *
 *   benchPcisph -particles N [-steps S] [-iterations K] [-micro R]
 *
 * -micro R also times R repetitions of the neighbour passes alone (density
 * and pressure force over the stored lists), to compare with the hardware
 * ceiling.  Threads: OMP_NUM_THREADS.
 */
#include "app/app.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_threads.h"
#include "geometry/geometry.h"
#include "effects/gravity.h"
#include "solver/pcisph.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct bench_args {
    long particles, steps, micro;
    int iterations;
} bench_args;

static const app_option options[] = {
    {.name = "particles",
     .kind = APP_INT,
     .help = "fluid particles of the scene",
     .def = "100000",
     .min = 1000,
     .max = 1e9},
    {.name = "steps", .kind = APP_INT, .help = "steps timed", .def = "20", .min = 1, .max = 1e9},
    {.name = "iterations",
     .kind = APP_INT,
     .help = "PCISPH iterations per step (min and max)",
     .def = "3",
     .min = 1,
     .max = 1000},
    {.name = "micro",
     .kind = APP_INT,
     .arg = "<R>",
     .help = "also time R repetitions of the neighbour passes alone",
     .def = "0",
     .min = 0,
     .max = 1e9},
    APP_END};

static const app_info info = {
    .name = "benchPcisph",
    .what = "One benchmark run of the PCISPH step on a dam-break scene of the given\n"
            "size (a fluid block 0.4 x 0.6 x 0.6 in the corner of a closed tank four\n"
            "block-lengths long, full boundary), with a constant time step and a fixed\n"
            "number of PCISPH iterations.  Prints key=value lines (tests/bench/run_bench\n"
            "turns them into the report).  Threads: OMP_NUM_THREADS.",
    .options = options};

static bench_args parse(int argc, char **argv)
{
    app a;
    bench_args b;
    app_parse(&a, &info, argc, argv);
    b.particles = app_int(&a, "particles", 100000);
    b.steps = app_int(&a, "steps", 20);
    b.iterations = (int)app_int(&a, "iterations", 3);
    b.micro = app_int(&a, "micro", 0);
    app_free(&a);
    return b;
}

/* The scene: block 0.4 s x 0.6 s x 0.6 s with s chosen for N particles at
 * r0 = 0.01 m, tank 1.6 s x 0.6 s x 0.8 s. */
static void build_scene(long n, double r0, sl_fluid *f, sl_boundary *b, double lo[3], double hi[3])
{
    double s = cbrt((double)n * r0 * r0 * r0 / (0.4 * 0.6 * 0.6));
    geo_shape tank = {.kind = GEO_CONTAINER, .lo = {0, 0, 0}, .hi = {1.6 * s, 0.6 * s, 0.8 * s}};
    double flo[3] = {0, 0, 0}, fhi[3] = {0.4 * s, 0.6 * s, 0.6 * s}, v[3] = {0, 0, 0};
    geo_sample(&tank, r0, 0, b);
    geo_fill_box(flo, fhi, r0, v, &tank, 1, f);
    for (int d = 0; d < 3; d++) {
        lo[d] = tank.lo[d] - 2 * r0;
        hi[d] = tank.hi[d] + 2 * r0;
    }
}

/* CPU seconds of the process (all its threads): the per-core rate that
 * other work on a shared machine does not dilute. */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    sl_threads_passive(argv); /* before any parallel region */
    bench_args a = parse(argc, argv);
    const double r0 = 0.01, dt = 0.5e-3;
    sl_fluid f;
    sl_boundary b;
    pcs_solver s;
    pcs_stats st;
    double lo[3], hi[3];
    pcs_params p;
    pcs_params_default(&p);
    p.rho0 = 1000;
    p.r0 = r0;
    p.min_iter = p.max_iter = a.iterations;
    eff_set effects;
    eff_set_init(&effects);
    eff_add(&effects, &eff_gravity, eff_gravity_new(p.gravity));
    sl_log_set_quiet(1);
    prt_fluid_init(&f);
    prt_boundary_init(&b);
    build_scene(a.particles, r0, &f, &b, lo, hi);
    pcs_init(&s, &p, &f, &b, lo, hi, dt, &effects);
    /* let the block start to collapse so the benchmark sees moving fluid */
    for (int k = 0; k < 20; k++) pcs_step(&s, &st);
    memset(&s.time, 0, sizeof s.time);
    double t0 = omp_get_wtime(), c0 = cpu_seconds(), iters = 0;
    for (long k = 0; k < a.steps; k++) {
        pcs_step(&s, &st);
        iters += st.iterations;
    }
    double wall = omp_get_wtime() - t0, cpu = cpu_seconds() - c0;
    const pcs_timers *tm = &s.time;
    int threads = omp_get_max_threads();
    printf("particles=%zu\nboundary=%zu\nactive=%zu\nthreads=%d\nsteps=%ld\niterations=%.3f\n", f.n,
           b.n, st.nactive, threads, a.steps, iters / (double)a.steps);
    printf("neighbours_fluid=%.2f\nneighbours_boundary=%.2f\n",
           (double)nbr_list_size(&s.ff) / (double)f.n, (double)nbr_list_size(&s.fb) / (double)f.n);
    printf("wall=%.6f\ncpu=%.6f\n", wall, cpu);
    printf("t_search=%.6f\nt_sort=%.6f\nt_forces=%.6f\nt_predict=%.6f\nt_density=%.6f\n"
           "t_pressure=%.6f\nt_integrate=%.6f\n",
           tm->search, tm->sort, tm->forces, tm->predict, tm->density, tm->pressure, tm->integrate);
    if (a.micro > 0) {
        size_t inter = nbr_list_size(&s.ff) + nbr_list_size(&s.fb) + nbr_list_size(&s.bf);
        double m0 = omp_get_wtime();
        for (long r = 0; r < a.micro; r++) pcs_pass_density(&s);
        double m1 = omp_get_wtime();
        for (long r = 0; r < a.micro; r++) pcs_pass_pressure(&s);
        double m2 = omp_get_wtime();
        printf("micro_density_interactions_per_s=%.6g\nmicro_pressure_interactions_per_s=%.6g\n",
               (double)inter * (double)a.micro / (m1 - m0),
               (double)(nbr_list_size(&s.ff) + nbr_list_size(&s.fb)) * (double)a.micro / (m2 - m1));
        double n0 = omp_get_wtime();
        for (long r = 0; r < a.micro; r++) pcs_find_neighbours(&s);
        printf("micro_search_s_per_build=%.6g\n", (omp_get_wtime() - n0) / (double)a.micro);
    }
    printf("peak_rss=%zu\n", sl_mem_peak_rss());
    pcs_free(&s);
    eff_set_free(&effects);
    prt_fluid_free(&f);
    prt_boundary_free(&b);
    return 0;
}
