/* pcisph: the PCISPH step of Algorithm 2 (see pcisph.h). */
#include "solver/pcisph.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_reduce.h"
#include "solver/sph_sums.h"
#include "effects/surface_tension.h"

static const pcs_boundary_ops boundary_methods[3];

#include <math.h>
#include <omp.h>
#include <string.h>

double pcs_delta(const krn_kernel *k, double r0, double mass, double rho0, double dt)
{
    double gx = 0, gy = 0, gz = 0, gg = 0;
    int reach = (int)ceil(k->h / r0) + 1;
    for (int i = -reach; i <= reach; i++)
        for (int j = -reach; j <= reach; j++)
            for (int l = -reach; l <= reach; l++) {
                double x = i * r0, y = j * r0, z = l * r0;
                double r = sqrt(x * x + y * y + z * z);
                double f = krn_gradf(k, r);
                gx += f * x; gy += f * y; gz += f * z;
                gg += f * f * (x * x + y * y + z * z);
            }
    double beta = 2.0 * (mass * dt / rho0) * (mass * dt / rho0);        /* eq. (5) */
    return -1.0 / (beta * (-(gx * gx + gy * gy + gz * gz) - gg));        /* eq. (4) */
}

void pcs_set_dt(pcs_solver *s, double dt)
{
    s->dt = dt;
    s->beta = 2.0 * (s->mass * dt / s->prm.rho0) * (s->mass * dt / s->prm.rho0);
    s->delta = pcs_delta(&s->k, s->prm.r0, s->mass, s->prm.rho0, dt);
}

void pcs_init(pcs_solver *s, const pcs_params *p, sl_fluid *f, sl_boundary *b,
              const double lo[3], const double hi[3], double dt)
{
    memset(s, 0, sizeof *s);
    s->prm = *p;
    s->h = 2.0 * p->r0;
    s->mass = p->rho0 * p->r0 * p->r0 * p->r0;
    s->eta_abs = p->eta * p->rho0;
    s->f = f;
    s->b = b;
    krn_init(&s->k, s->h);
    size_t max_cells = 8 * (f->n + b->n) + ((size_t)1 << 20);
    nbr_grid_init(&s->grid, lo, hi, s->h, max_cells);
    nbr_list_init(&s->ff);
    nbr_list_init(&s->fb);
    nbr_list_init(&s->bf);
    nbr_sort_boundary(&s->grid, b);
    s->cal = bnd_calibrate(&s->k, p->r0, s->mass, p->rho0);
    bnd_set_mass(&s->grid, &s->k, &s->cal, p->rho0, b);
    s->active = sl_alloc_aligned((b->n + 1) * sizeof *s->active, "active boundary list");
    s->bops = &boundary_methods[p->method];
    s->eff.on[EFF_GRAVITY] = p->gravity[0] != 0.0 || p->gravity[1] != 0.0 || p->gravity[2] != 0.0;
    s->eff.on[EFF_VISCOSITY] = p->viscosity;
    s->eff.on[EFF_SURFACE_TENSION] = p->surface_tension;
    s->eff.on[EFF_SURFACE_DENSITY] = p->surface_density;
    for (size_t i = 0; i < f->n; i++) f->rho[i] = p->rho0; /* until the first pass */
    if (p->method == BND_HARADA2007) bnd_wall_table_build(&s->wall, &s->k, p->r0, s->mass, 256);
    pcs_set_dt(s, dt);
}

void pcs_free(pcs_solver *s)
{
    nbr_grid_free(&s->grid);
    nbr_list_free(&s->ff);
    nbr_list_free(&s->fb);
    nbr_list_free(&s->bf);
    sl_free_aligned(s->active);
    sl_free_aligned(s->err);
    sl_free_aligned(s->err_vol);
    sl_free_aligned(s->wall_d);
    sl_free_aligned(s->wall_b);
    sl_free_aligned(s->ap_best);
    if (s->wall.z) bnd_wall_table_free(&s->wall);
    memset(s, 0, sizeof *s);
}

static void ensure_scratch(pcs_solver *s)
{
    if (s->err_cap < s->f->cap) {
        sl_free_aligned(s->err);
        s->err = sl_alloc_aligned(s->f->cap * sizeof *s->err, "density error");
        if (s->prm.max_iter > s->prm.min_iter) {
            sl_free_aligned(s->ap_best);
            s->ap_best = sl_alloc_aligned(3 * s->f->cap * sizeof *s->ap_best, "pressure force");
        }
        if (s->prm.method != BND_IHMSEN2010) {
            sl_free_aligned(s->err_vol);
            s->err_vol = sl_alloc_aligned(s->f->cap * sizeof *s->err_vol, "density error");
        }
        if (s->prm.method == BND_HARADA2007) {
            sl_free_aligned(s->wall_d);
            sl_free_aligned(s->wall_b);
            s->wall_d = sl_alloc_aligned(s->f->cap * sizeof *s->wall_d, "wall distances");
            s->wall_b = sl_alloc_aligned(s->f->cap * sizeof *s->wall_b, "wall neighbours");
        }
        s->err_cap = s->f->cap;
    }
}

/* ---- the phases of Algorithm 2 ---- */

void pcs_find_neighbours(pcs_solver *s)
{
    double t0 = omp_get_wtime(), t1;
    nbr_sort_fluid(&s->grid, s->f);
    t1 = omp_get_wtime(); s->time.sort += t1 - t0; t0 = t1;
    nbr_build_fluid(&s->grid, s->f, s->b, &s->ff, &s->fb);
    t1 = omp_get_wtime(); s->time.list_ff += t1 - t0; t0 = t1;
    nbr_transpose(&s->fb, s->b->n, &s->bf, s->active, &s->nactive);
    t1 = omp_get_wtime(); s->time.list_bf += t1 - t0;
}

/* Run effect k's body, counting and timing it. */
#define EFFECT(s, k, body)                                                     \
    do {                                                                       \
        double t0_ = omp_get_wtime();                                          \
        body;                                                                  \
        (s)->eff.calls[k]++;                                                   \
        (s)->eff.time[k] += omp_get_wtime() - t0_;                             \
    } while (0)

/* Non-pressure forces per unit mass (the effects the case named); zero
 * pressure and pressure force. */
static void compute_forces(pcs_solver *s)
{
    sl_fluid *f = s->f;
    const double gx = s->prm.gravity[0], gy = s->prm.gravity[1], gz = s->prm.gravity[2];
    const int g = s->eff.on[EFF_GRAVITY];
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < f->n; i++) {
        f->ax[i] = g ? gx : 0.0;
        f->ay[i] = g ? gy : 0.0;
        f->az[i] = g ? gz : 0.0;
        f->apx[i] = f->apy[i] = f->apz[i] = 0.0;
        f->p[i] = 0.0;
    }
    if (g) s->eff.calls[EFF_GRAVITY]++;
    if (s->eff.on[EFF_VISCOSITY])
        EFFECT(s, EFF_VISCOSITY,
               visc_apply(&s->prm.visc, &s->k, s->mass, s->prm.rho0, f, s->b, &s->ff, &s->fb));
    if (s->eff.on[EFF_SURFACE_TENSION])
        EFFECT(s, EFF_SURFACE_TENSION, st_apply(s->prm.kappa, &s->k, f, &s->ff));
    const uint32_t *act = s->active;
    double *pb = s->b->p;
#pragma omp parallel for schedule(static)
    for (size_t q = 0; q < s->nactive; q++) pb[act[q]] = 0.0;
}

static void predict_positions(pcs_solver *s)
{
    sl_fluid *f = s->f;
    const double dt = s->dt;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < f->n; i++) {
        double vx = f->vx[i] + dt * (f->ax[i] + f->apx[i]);
        double vy = f->vy[i] + dt * (f->ay[i] + f->apy[i]);
        double vz = f->vz[i] + dt * (f->az[i] + f->apz[i]);
        f->xs[i] = f->x[i] + dt * vx;
        f->ys[i] = f->y[i] + dt * vy;
        f->zs[i] = f->z[i] + dt * vz;
    }
    s->bops->collide(s, f->xs, f->ys, f->zs, NULL, NULL, NULL);
}

/* Predicted density of fluid and active boundary particles (eq. 13) and
 * pressure update (eq. 3), for boundary method M (a constant: each method
 * gets its own compiled copy).  Fills s->err with each fluid particle's
 * compression and returns the largest one (absolute units). */
static inline __attribute__((always_inline)) double density_pass(pcs_solver *s, const bnd_method M,
                                                                  const int predict)
{
    sl_fluid *f = s->f;
    sl_boundary *b = s->b;
    const krn_kernel k = s->k;
    const double m = s->mass, rho0 = s->prm.rho0, delta = s->delta;
    const double self = m * krn_w(&k, 0.0);
    const size_t n = f->n;
    const uint32_t *restrict ffs = s->ff.start, *restrict ffi = s->ff.idx;
    const uint32_t *restrict fbs = s->fb.start, *restrict fbi = s->fb.idx;
    /* predict: x*(t + dt) and the pressure update; else x(t), density only */
    const double *restrict xs = predict ? f->xs : f->x, *restrict ys = predict ? f->ys : f->y,
                           *restrict zs = predict ? f->zs : f->z;
    const double *restrict bx = b->x, *restrict by = b->y, *restrict bz = b->z;
    const double *restrict bm = b->mass;
    double *restrict rho = f->rho, *restrict p = f->p, *restrict pt = f->pt;
    double *restrict err = s->err, *restrict err_vol = s->err_vol;
    double emax = 0.0;
    /* the correction reads the densities of the previous pass (a copy, so
     * that every thread reads the same values) */
    const int bk = s->eff.on[EFF_SURFACE_DENSITY];
    double *restrict rho_prev = f->scratch; /* free outside the sort */
    if (bk) {
        if (n) memcpy(rho_prev, rho, n * sizeof *rho);
        s->eff.calls[EFF_SURFACE_DENSITY]++;
    }
#pragma omp parallel for schedule(static) reduction(max : emax)
    for (size_t i = 0; i < n; i++) {
        const double xi = xs[i], yi = ys[i], zi = zs[i];
        const double rf = self + m * sph_sum_w(k, ffi, ffs[i], ffs[i + 1], xi, yi, zi, xs, ys, zs);
        /* eq. (13); for the other methods only measured (vol_avg) */
        const double rb = (M == BND_IHMSEN2010 || predict)
                              ? sph_sum_mw(k, fbi, fbs[i], fbs[i + 1], xi, yi, zi, bx, by, bz, bm)
                              : 0.0;
        double r = rf;
        if (M == BND_IHMSEN2010) r += rb;
        if (M == BND_HARADA2007) { /* wall weight Z(d) [HKK07] */
            double d = 0.0, z = 0.0, dz = 0.0;
            uint32_t j = bnd_nearest(&s->fb, b, i, xi, yi, zi, &d);
            if (j != UINT32_MAX) bnd_wall_lookup(&s->wall, d, &z, &dz);
            s->wall_b[i] = j;
            s->wall_d[i] = dz;
            r += z;
        }
        double rv = rf + rb; /* the density with the wall's share, for every method */
        if (bk) { /* Bonet & Kulasegaram 2002: r / sum_j V_j W_ij where it is < 1 */
            const double shf = m * (krn_w(&k, 0.0) / rho_prev[i] +
                                    sph_sum_w_over(k, ffi, ffs[i], ffs[i + 1], xi, yi, zi, xs, ys,
                                                   zs, rho_prev));
            const double shv = shf + rb / rho0;
            const double sh = M == BND_IHMSEN2010 ? shv : shf;
            if (sh < 1.0 && sh > 0.0) r /= sh;
            if (shv < 1.0 && shv > 0.0) rv /= shv;
        }
        rho[i] = r;
        if (!predict) continue;
        if (M != BND_IHMSEN2010) err_vol[i] = rv > rho0 ? rv - rho0 : 0.0;
        const double e = r - rho0;
        const double pn = p[i] + delta * e; /* eq. (3) */
        const double pc = pn > 0.0 ? pn : 0.0;
        p[i] = pc;
        pt[i] = pc / (r * r);
        const double c = e > 0.0 ? e : 0.0;
        err[i] = c;
        emax = c > emax ? c : emax;
    }
    if (M != BND_IHMSEN2010 || !predict) return emax;
    const uint32_t *restrict act = s->active;
    const uint32_t *restrict bfs = s->bf.start, *restrict bfi = s->bf.idx;
    const double *restrict brs = b->rho_static;
    double *restrict brho = b->rho, *restrict bp = b->p, *restrict bpt = b->pt;
#pragma omp parallel for schedule(static)
    for (size_t q = 0; q < s->nactive; q++) {
        const uint32_t i = act[q];
        const double r = brs[i] + m * sph_sum_w(k, bfi, bfs[i], bfs[i + 1], bx[i], by[i], bz[i],
                                                 xs, ys, zs); /* eq. (13) */
        const double pn = bp[i] + delta * (r - rho0);
        const double pc = pn > 0.0 ? pn : 0.0;
        brho[i] = r;
        bp[i] = pc;
        bpt[i] = pc / (r * r);
    }
    return emax;
}

/* Pressure force per unit mass, eq. (6), for boundary method M. */
static inline __attribute__((always_inline)) void pressure_pass(pcs_solver *s, const bnd_method M)
{
    sl_fluid *f = s->f;
    const sl_boundary *b = s->b;
    const krn_kernel k = s->k;
    const double m = s->mass;
    const size_t n = f->n;
    const uint32_t *restrict ffs = s->ff.start, *restrict ffi = s->ff.idx;
    const uint32_t *restrict fbs = s->fb.start, *restrict fbi = s->fb.idx;
    const double *restrict xs = f->xs, *restrict ys = f->ys, *restrict zs = f->zs;
    const double *restrict pt = f->pt, *restrict bpt = b->pt, *restrict bm = b->mass;
    double *restrict apx = f->apx, *restrict apy = f->apy, *restrict apz = f->apz;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        const double xi = xs[i], yi = ys[i], zi = zs[i];
        double a[3] = {0.0, 0.0, 0.0};
        sph_sum_pressure(k, ffi, ffs[i], ffs[i + 1], xi, yi, zi, pt[i], xs, ys, zs, pt, NULL, m, a);
        if (M == BND_IHMSEN2010) /* boundary pressures, eq. (6) with eq. (13)'s particles */
            sph_sum_pressure(k, fbi, fbs[i], fbs[i + 1], xi, yi, zi, pt[i], b->x, b->y, b->z, bpt,
                             bm, 0.0, a);
        if (M == BND_HARADA2007 && s->wall_b[i] != UINT32_MAX) {
            /* wall particles carry the fluid particle's own pressure [HKK07]:
             * -sum_w m_w 2 p_i / rho_i^2 grad W = -2 p_i / rho_i^2 dZ/dd n */
            const uint32_t j = s->wall_b[i];
            const double c = -2.0 * pt[i] * s->wall_d[i];
            a[0] += c * b->nx[j];
            a[1] += c * b->ny[j];
            a[2] += c * b->nz[j];
        }
        apx[i] = a[0];
        apy[i] = a[1];
        apz[i] = a[2];
    }
}

static double density_ihmsen(pcs_solver *s, int predict)
{
    return predict ? density_pass(s, BND_IHMSEN2010, 1) : density_pass(s, BND_IHMSEN2010, 0);
}
static double density_becker(pcs_solver *s, int predict)
{
    return predict ? density_pass(s, BND_BECKER2009, 1) : density_pass(s, BND_BECKER2009, 0);
}
static double density_harada(pcs_solver *s, int predict)
{
    return predict ? density_pass(s, BND_HARADA2007, 1) : density_pass(s, BND_HARADA2007, 0);
}
static void pressure_ihmsen(pcs_solver *s) { pressure_pass(s, BND_IHMSEN2010); }
static void pressure_becker(pcs_solver *s) { pressure_pass(s, BND_BECKER2009); }
static void pressure_harada(pcs_solver *s) { pressure_pass(s, BND_HARADA2007); }

static size_t collide_ihmsen(pcs_solver *s, double *x, double *y, double *z, double *vx,
                             double *vy, double *vz)
{
    return bnd_collide(&s->fb, s->b, s->prm.r0, s->prm.epsilon, s->f->n, x, y, z, vx, vy, vz);
}
static size_t collide_becker(pcs_solver *s, double *x, double *y, double *z, double *vx,
                             double *vy, double *vz)
{
    return bnd_collide_becker(&s->fb, s->b, s->prm.r0, s->prm.epsilon, s->prm.restitution,
                              s->f->n, x, y, z, vx, vy, vz);
}
static size_t collide_harada(pcs_solver *s, double *x, double *y, double *z, double *vx,
                             double *vy, double *vz)
{
    return bnd_collide_harada(&s->fb, s->b, s->prm.r0, s->prm.epsilon, s->f->n, x, y, z, vx,
                              vy, vz);
}

/* The one place that chooses by boundary method. */
static const pcs_boundary_ops boundary_methods[3] = {
    {BND_IHMSEN2010, density_ihmsen, pressure_ihmsen, collide_ihmsen},
    {BND_BECKER2009, density_becker, pressure_becker, collide_becker},
    {BND_HARADA2007, density_harada, pressure_harada, collide_harada},
};

double pcs_pass_density(pcs_solver *s) { return s->bops->density(s, 1); }

void pcs_pass_pressure(pcs_solver *s) { s->bops->pressure(s); }

/* Euler-Cromer, then the world collision (eq. 11, 12); vmax and fmax. */
static void integrate(pcs_solver *s, pcs_stats *st)
{
    sl_fluid *f = s->f;
    const double dt = s->dt;
    double v2max = 0.0, f2max = 0.0;
#pragma omp parallel for schedule(static) reduction(max : f2max)
    for (size_t i = 0; i < f->n; i++) {
        double ax = f->ax[i] + f->apx[i], ay = f->ay[i] + f->apy[i], az = f->az[i] + f->apz[i];
        double a2 = ax * ax + ay * ay + az * az;
        if (!(a2 <= f2max)) f2max = isnan(a2) ? HUGE_VAL : a2; /* NaN is reported, not skipped */
        f->vx[i] += dt * ax;
        f->vy[i] += dt * ay;
        f->vz[i] += dt * az;
        f->x[i] += dt * f->vx[i];
        f->y[i] += dt * f->vy[i];
        f->z[i] += dt * f->vz[i];
    }
    st->ncollide = s->bops->collide(s, f->x, f->y, f->z, f->vx, f->vy, f->vz);
#pragma omp parallel for schedule(static) reduction(max : v2max)
    for (size_t i = 0; i < f->n; i++) {
        double v2 = f->vx[i] * f->vx[i] + f->vy[i] * f->vy[i] + f->vz[i] * f->vz[i];
        if (!(v2 <= v2max)) v2max = isnan(v2) ? HUGE_VAL : v2;
    }
    st->vmax = sqrt(v2max);
    st->fmax = sqrt(f2max);
}

void pcs_set_motions(pcs_solver *s, const mot_motion *motions, size_t nbodies)
{
    s->motions = motions;
    s->nbodies = nbodies;
    s->eff.on[EFF_MOVING_BOUNDARY] = 0;
    for (size_t k = 0; k < nbodies; k++)
        if (motions[k].type != MOT_NONE) s->eff.on[EFF_MOVING_BOUNDARY] = 1;
}

void pcs_move_boundaries(pcs_solver *s, double t)
{
    if (!s->eff.on[EFF_MOVING_BOUNDARY]) return;
    EFFECT(s, EFF_MOVING_BOUNDARY, {
        for (size_t k = 0; k < s->nbodies; k++)
            if (s->motions[k].type != MOT_NONE) mot_apply(&s->motions[k], (uint32_t)k, t, s->b);
        nbr_sort_boundary(&s->grid, s->b);
    });
}

void pcs_step(pcs_solver *s, pcs_stats *st)
{
    sl_fluid *f = s->f;
    const double rho0 = s->prm.rho0;
    const double inv_n = f->n ? 1.0 / (double)f->n : 0.0;
    double t0 = omp_get_wtime(), t1;
    memset(st, 0, sizeof *st);
    ensure_scratch(s);
    pcs_move_boundaries(s, s->t + s->dt); /* walls where they are at the end of the step */

    pcs_find_neighbours(s);
    t1 = omp_get_wtime(); s->time.search += t1 - t0; t0 = t1;
    compute_forces(s);
    t1 = omp_get_wtime(); s->time.forces += t1 - t0; t0 = t1;

    int k = 0;
    double emax;
    /* Iterating to convergence (maxIterations > minIterations), the
     * correction can overshoot near walls, where the collision keeps the
     * predicted positions from moving, and the error then grows with every
     * further iteration.  The pressure force that gave the smallest error
     * is kept, and a growing error ends the iterations with it. */
    const int guard = s->prm.max_iter > s->prm.min_iter && f->n > 0;
    double best = HUGE_VAL;
    for (;;) {
        predict_positions(s);
        t1 = omp_get_wtime(); s->time.predict += t1 - t0; t0 = t1;
        emax = pcs_pass_density(s);
        if (k == 0) {
            st->err_max_before = emax / rho0;
            st->err_avg_before = sl_sum(s->err, f->n) * inv_n / rho0;
        }
        t1 = omp_get_wtime(); s->time.density += t1 - t0; t0 = t1;
        if (guard) {
            const size_t bytes = f->n * sizeof(double);
            if (emax < best) { /* the force in use gave the best prediction so far */
                best = emax;
                memcpy(s->ap_best, f->apx, bytes);
                memcpy(s->ap_best + f->cap, f->apy, bytes);
                memcpy(s->ap_best + 2 * f->cap, f->apz, bytes);
            } else if (k >= s->prm.min_iter) {
                memcpy(f->apx, s->ap_best, bytes);
                memcpy(f->apy, s->ap_best + f->cap, bytes);
                memcpy(f->apz, s->ap_best + 2 * f->cap, bytes);
                emax = best;
                st->diverging = 1;
                break;
            }
        }
        pcs_pass_pressure(s);
        t1 = omp_get_wtime(); s->time.pressure += t1 - t0; t0 = t1;
        k++;
        if (k >= s->prm.max_iter) break;
        if (k >= s->prm.min_iter && emax <= s->eta_abs) break;
    }
    st->iterations = k;
    st->converged = emax <= s->eta_abs;
    st->err_max = emax / rho0;
    st->err_avg = sl_sum(s->err, f->n) * inv_n / rho0;
    if (s->prm.method == BND_IHMSEN2010) {
        st->vol_avg = st->err_avg;
        st->vol_max = st->err_max;
    } else {
        st->vol_avg = sl_sum(s->err_vol, f->n) * inv_n / rho0;
        st->vol_max = f->n ? sl_max(s->err_vol, f->n) / rho0 : 0.0;
    }
    st->nactive = s->nactive;

    integrate(s, st);
    t1 = omp_get_wtime(); s->time.integrate += t1 - t0;
    s->t += s->dt;
}

void pcs_compute_density(pcs_solver *s)
{
    ensure_scratch(s);
    pcs_find_neighbours(s);
    s->bops->density(s, 0);
}
