/* pcisph: the PCISPH step of Algorithm 2 (see pcisph.h). */
#include "solver/pcisph.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "boundary/bnd_methods.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_reduce.h"
#include "kernel/kernel_correction.h"
#include "kernel/sph_sums.h"
#include "parallel/par.h"
#include "solver/pcs_domain.h"
#include "solver/pcs_parallel.h"

/* Accumulate the wall-clock time of `body` in s->time.<phase>. */
#define PHASE(s, phase, body)                     \
    do {                                          \
        const double t0_ = omp_get_wtime();       \
        body;                                     \
        (s)->time.phase += omp_get_wtime() - t0_; \
    } while (0)

void pcs_params_default(pcs_params *p)
{
    memset(p, 0, sizeof *p);
    p->gravity[2] = -9.81;
    p->eta = 0.01;
    p->min_iter = 3;
    p->max_iter = 100;
    p->epsilon = 1.0;
    p->method = &ihmsen2010_method;
    p->restitution = 0.0;
    p->mass_factor = 1.0;
    p->support = 2.0;
    p->relaxation = 1.0;
}

double pcs_mass_lattice(const pcs_params *p)
{
    const double r0 = p->r0;
    krn_kernel k;
    pcs_kernel(p, &k);
    const int reach = (int)ceil(p->support) + 1;
    double sum = 0.0;
    for (int i = -reach; i <= reach; i++)
        for (int j = -reach; j <= reach; j++)
            for (int l = -reach; l <= reach; l++)
                sum += krn_w(&k, r0 * sqrt((double)(i * i + j * j + l * l)));
    return p->rho0 / sum;
}

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
                gx += f * x;
                gy += f * y;
                gz += f * z;
                gg += f * f * (x * x + y * y + z * z);
            }
    double beta = 2.0 * (mass * dt / rho0) * (mass * dt / rho0);  /* eq. (5) */
    return -1.0 / (beta * (-(gx * gx + gy * gy + gz * gz) - gg)); /* eq. (4) */
}

/* delta times the largest eigenvalue of eq. (3)'s update on a cubic
 * lattice of spacing scale * r0 (kernel of support `support` r0; delta of
 * the lattice of spacing r0, as the solver's).  A pressure mode p_j =
 * P exp(i k . x_j) changes the predicted density by -beta / 2 |H(k)|^2 P,
 * H(k) = sum_j sin(k . x_ij) grad W_ij, so one update p += delta rho_err
 * multiplies the mode's residual by 1 - |H|^2 / (2 sum_j |grad W_ij|^2):
 * it grows where that exceeds 2.  The largest over k (a grid of 25 per
 * axis on [0, pi / (scale r0)], k_x >= k_y >= k_z). */
double pcs_delta_lambda_max(int type, double support, double scale)
{
    const double r0 = 1.0;
    krn_kernel k;
    krn_init_type(&k, type, support * r0);
    const double m = 1.0, rho0 = 1.0, dt = 1.0;
    const double beta = 2.0 * (m * dt / rho0) * (m * dt / rho0);
    const double delta = pcs_delta(&k, r0, m, rho0, dt); /* 1 / (beta sum |g|^2) at scale 1 */
    const int reach = (int)ceil(support) + 1;
    double best = 0.0;
    const int n = 25;
    for (int a = 0; a < n; a++)
        for (int b = 0; b <= a; b++)
            for (int c = 0; c <= b; c++) {
                const double kx = M_PI * a / (n - 1) / scale, ky = M_PI * b / (n - 1) / scale,
                             kz = M_PI * c / (n - 1) / scale;
                double h[3] = {0.0, 0.0, 0.0};
                for (int i = -reach; i <= reach; i++)
                    for (int j = -reach; j <= reach; j++)
                        for (int l = -reach; l <= reach; l++) {
                            const double x = i * scale, y = j * scale, z = l * scale;
                            const double f = krn_gradf(&k, sqrt(x * x + y * y + z * z));
                            const double s = sin(kx * x + ky * y + kz * z);
                            h[0] += s * f * x;
                            h[1] += s * f * y;
                            h[2] += s * f * z;
                        }
                const double v = delta * beta / 2.0 * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
                best = v > best ? v : best;
            }
    return best;
}

void pcs_set_dt(pcs_solver *s, double dt)
{
    s->dt = dt;
    s->beta = 2.0 * (s->mass * dt / s->prm.rho0) * (s->mass * dt / s->prm.rho0);
    s->delta = s->prm.relaxation * pcs_delta(&s->k, s->prm.r0, s->mass, s->prm.rho0, dt);
}

/* ---- the passes of a boundary method, compiled once per method ---- */

typedef double (*wall_density_fn)(const bnd_pass *c, size_t i, double x, double y, double z,
                                  double rb);
typedef void (*wall_pressure_fn)(const bnd_pass *c, size_t i, double x, double y, double z,
                                 double pti, double a[3]);

struct pcs_method_passes {
    const bnd_method_type *type;
    double (*predict)(pcs_solver *s); /* eq. (13) and (3); returns the largest compression */
    void (*pressure)(pcs_solver *s);  /* eq. (6) */
    void (*density)(pcs_solver *s);   /* density at x(t), for output */
};

static bnd_pass boundary_pass(const pcs_solver *s)
{
    return (bnd_pass){s->k, s->fb.start, s->fb.idx, s->b, s->bstate};
}

static eff_view effect_view(pcs_solver *s, double t, double dt, const double *px, const double *py,
                            const double *pz)
{
    return (eff_view){.f = s->f,
                      .b = s->b,
                      .grid = &s->grid,
                      .ff = &s->ff,
                      .fb = &s->fb,
                      .k = s->k,
                      .h = s->h,
                      .r0 = s->prm.r0,
                      .mass = s->mass,
                      .rho0 = s->prm.rho0,
                      .gravity = s->prm.gravity,
                      .t = t,
                      .dt = dt,
                      .px = px,
                      .py = py,
                      .pz = pz,
                      .wall_density = s->prm.method->wall_density};
}

/* -parallel's halo and domain modes: a rank predicts and integrates its
 * own rows only, so its EFF_FORCES and EFF_SHIFT effects act on those. */
static void own_rows_only(const pcs_solver *s, eff_view *v)
{
    if (!s->split.halo) return;
    v->rows_only = 1;
    v->row0 = s->split.row[s->split.rank];
    v->row1 = s->split.row[s->split.rank + 1];
}

/* Before a density pass at positions (px, py, pz): prepare the EFF_DENSITY
 * effects (counted and timed as every effect). */
static eff_view density_effects(pcs_solver *s, const double *px, const double *py, const double *pz)
{
    eff_view v = effect_view(s, s->t, s->dt, px, py, pz);
    eff_run(s->eff, EFF_DENSITY, &v);
    return v;
}

/* The EFF_DENSITY corrections of fluid particle i's density. */
static inline void correct_density(const pcs_solver *s, const eff_view *v, size_t i, double x,
                                   double y, double z, double rb, double *r, double *rv)
{
    for (size_t q = 0; q < s->ndens; q++)
        s->dens[q]->type->correct(s->dens[q]->state, v, i, x, y, z, rb, r, rv);
}

/* pressureSource divergence and mixed: the predicted density change of
 * active boundary particle i over the step, from the fluid's
 * displacements d_f = x*_f - x_f(t) and the wall's dt v_b:
 * sum_f m grad W(x_b - x_f(t)) . (dt v_b - d_f), its fluid neighbours in
 * the order of its list. */
static double boundary_change(const pcs_solver *s, uint32_t i)
{
    const sl_boundary *b = s->b;
    const sl_fluid *f = s->f;
    const krn_kernel k = s->k;
    const double dt = s->dt, xb = b->x[i], yb = b->y[i], zb = b->z[i];
    const double ux = dt * b->vx[i], uy = dt * b->vy[i], uz = dt * b->vz[i];
    double sum = 0.0;
    for (uint32_t q = s->bf.start[i]; q < s->bf.start[i + 1]; q++) {
        const uint32_t j = s->bf.idx[q];
        const double rx = xb - f->x[j], ry = yb - f->y[j], rz = zb - f->z[j];
        const double g = krn_gradf(&k, sqrt(rx * rx + ry * ry + rz * rz));
        sum += g *
            (rx * (ux - (f->xs[j] - f->x[j])) + ry * (uy - (f->ys[j] - f->y[j])) +
             rz * (uz - (f->zs[j] - f->z[j])));
    }
    return s->mass * sum;
}

/* Predicted density and pressure of the active boundary particles (eq. 13
 * and eq. 3), for the methods whose walls take part in the solve.  Called
 * inside the fluid's density pass's parallel region (its loop is shared
 * by the team, without a barrier of its own).  part: -1 all; with the
 * domain mode's overlap 0 the set's particles that read no halo x*, 1 the
 * others. */
static void boundary_density(const pcs_solver *s, int part)
{
    const sl_boundary *b = s->b;
    const krn_kernel k = s->k;
    const double m = s->mass, rho0 = s->prm.rho0, delta = s->delta;
    const double *restrict xs = s->f->xs, *restrict ys = s->f->ys, *restrict zs = s->f->zs;
    const double *restrict bx = b->x, *restrict by = b->y, *restrict bz = b->z;
    const uint32_t *restrict act = s->active;
    const uint32_t *restrict bfs = s->bf.start, *restrict bfi = s->bf.idx;
    const double *restrict brs = b->rho_static;
    double *restrict brho = b->rho, *restrict bp = b->p, *restrict bpt = b->pt;
    double *restrict buf = s->split.bbuf;
    /* -parallel: this rank's share of the active ones (gathered after the
     * pass), or in halo mode the ones its rows see (pcs_parallel.h) */
    const int halo = s->split.halo;
    const size_t q0 = halo ? (part == 1 ? s->split.nbset_inner : 0) : s->split.act[s->split.rank];
    const size_t q1 = halo ? (part == 0 ? s->split.nbset_inner : s->split.nbset)
                           : s->split.act[s->split.rank + 1];
    const uint32_t *restrict set = halo ? s->split.bset : act;
    const int packed = s->split.size > 1 && !halo;
#pragma omp for schedule(dynamic, 256) nowait
    for (size_t q = q0; q < q1; q++) {
        const uint32_t i = set[q];
        const double r = brs[i] +
            m *
                sph_sum_w(k, bfi, bfs[i], bfs[i + 1], bx[i], by[i], bz[i], xs, ys,
                          zs); /* eq. (13) */
        double e = r - rho0;
        if (s->prm.source != PCS_SOURCE_DENSITY) {
            const double d = boundary_change(s, i);
            e = s->prm.source == PCS_SOURCE_DIVERGENCE
                ? d
                : (1.0 - s->prm.source_mix) * d + s->prm.source_mix * e;
        }
        const double pn = bp[i] + delta * e;
        const double pc = pn > 0.0 || s->prm.hold_mean ? pn : 0.0; /* meanPressure */
        brho[i] = r;
        bp[i] = pc;
        bpt[i] = pc / (r * r);
        if (packed) {
            buf[3 * q] = r;
            buf[3 * q + 1] = pc;
            buf[3 * q + 2] = bpt[i];
        }
    }
}

/* ---- -parallel: what a pass computed on each rank, made whole ---- */

/* Particles that changed rank since the last search (the rows move
 * with the fluid: a dam break carries them from rank to rank). */
static void count_moves(pcs_split *sp, const sl_fluid *f)
{
    uint32_t idmax = 0;
    for (size_t i = 0; i < f->n; i++) idmax = f->id[i] > idmax ? f->id[i] : idmax;
    if (sp->owner_cap < (size_t)idmax + 1) {
        size_t cap = sp->owner_cap ? sp->owner_cap : 1024;
        while (cap < (size_t)idmax + 1) cap *= 2;
        int32_t *o = sl_malloc(cap * sizeof *o, "particle ranks");
        for (size_t k = 0; k < cap; k++) o[k] = k < sp->owner_cap ? sp->owner[k] : -1;
        free(sp->owner);
        sp->owner = o;
        sp->owner_cap = cap;
    }
    for (int r = 0; r < sp->size; r++)
        for (size_t i = sp->row[r]; i < sp->row[r + 1]; i++) {
            int32_t *o = &sp->owner[f->id[i]];
            if (*o >= 0 && *o != r) {
                if (r > *o) sp->moved_up++;
                else sp->moved_down++;
            }
            *o = r;
        }
}

/* Rows and active boundary particles of each rank for this search: the
 * fluid rows by count, the active boundary particles by count. */
static void split_rows(pcs_solver *s)
{
    pcs_split *sp = &s->split;
    const size_t n = s->f->n, p = (size_t)sp->size;
    for (size_t r = 0; r <= p; r++) {
        sp->row[r] = n * r / p;
        sp->act[r] = s->nactive * r / p;
    }
    sp->rows_min = n;
    sp->rows_max = 0;
    for (size_t r = 0; r < p; r++) {
        const size_t k = sp->row[r + 1] - sp->row[r];
        sp->rows_min = k < sp->rows_min ? k : sp->rows_min;
        sp->rows_max = k > sp->rows_max ? k : sp->rows_max;
    }
    if (p > 1) count_moves(sp, s->f);
    sp->steps++;
    sp->empty += sp->rows_min == 0;
    sp->rows_min_sum += (double)sp->rows_min;
    sp->rows_max_sum += (double)sp->rows_max;
}

/* The block sums of the density error, from every rank's rows: each block
 * summed in order, as the density pass sums its rows one at a time (the
 * empty asm keeps the compiler from reassociating this loop, which
 * -fassociative-math would vectorise: the serial code's bits). */
static void block_sums(const double *err, size_t n, double *part)
{
    const size_t nb = (n + SL_REDUCE_BLOCK - 1) / SL_REDUCE_BLOCK;
#pragma omp parallel for schedule(static)
    for (size_t blk = 0; blk < nb; blk++) {
        const size_t lo = blk * SL_REDUCE_BLOCK;
        const size_t hi = lo + SL_REDUCE_BLOCK < n ? lo + SL_REDUCE_BLOCK : n;
        double sum = 0.0;
        for (size_t i = lo; i < hi; i++) {
            sum += err[i];
            __asm__("" : "+m"(sum));
        }
        part[blk] = sum;
    }
}

/* The block sums added in block order, one at a time (the same bits on
 * every rank and in every mode: the loop is kept from reassociating). */
static double sum_in_order(const double *part, size_t nb)
{
    double total = 0.0;
    for (size_t b = 0; b < nb; b++) {
        total += part[b];
        __asm__("" : "+m"(total));
    }
    return total;
}

/* Offsets of a per-row array of `w` doubles per row (scratch in off). */
static const size_t *scaled(const size_t *in, size_t w, size_t *off, int size)
{
    for (int r = 0; r <= size; r++) off[r] = w * in[r];
    return off;
}

/* After a density pass: every rank's fluid rows (density, pressure,
 * p/rho^2, compression, and the measured compression of the methods
 * without wall density), its block sums and its active boundary
 * particles' density and pressure; the largest compression of all. */
static double gather_predicted(pcs_solver *s, int wall, double emax)
{
    pcs_split *sp = &s->split;
    const double t0 = omp_get_wtime();
    sl_fluid *f = s->f;
    sl_boundary *b = s->b;
    par_gather_rows(f->rho, sp->row);
    par_gather_rows(f->p, sp->row);
    par_gather_rows(f->pt, sp->row);
    par_gather_rows(s->err, sp->row);
    if (!wall) par_gather_rows(s->err_vol, sp->row);
    block_sums(s->err, f->n, s->err_block);
    if (wall && s->nactive) {
        size_t off[sp->size + 1];
        par_gather_rows(sp->bbuf, scaled(sp->act, 3, off, sp->size));
        const uint32_t *act = s->active;
        const double *buf = sp->bbuf;
        const size_t q0 = sp->act[sp->rank], q1 = sp->act[sp->rank + 1];
        for (size_t q = 0; q < s->nactive; q++) {
            if (q == q0) q = q1; /* own values are in place */
            if (q >= s->nactive) break;
            const uint32_t i = act[q];
            b->rho[i] = buf[3 * q];
            b->p[i] = buf[3 * q + 1];
            b->pt[i] = buf[3 * q + 2];
        }
    }
    emax = par_max_double(emax); /* a maximum: exact in any order */
    s->time.comm += omp_get_wtime() - t0;
    return emax;
}

/* After a pressure-force pass: every rank's rows of the force. */
static void gather_force(pcs_solver *s)
{
    const double t0 = omp_get_wtime();
    par_gather_rows(s->f->apx, s->split.row);
    par_gather_rows(s->f->apy, s->split.row);
    par_gather_rows(s->f->apz, s->split.row);
    s->time.comm += omp_get_wtime() - t0;
}

/* What the per-particle work of a density or pressure pass reads. */
typedef struct pass_ctx {
    krn_kernel k;
    double m, rho0, delta, self;
    const uint32_t *ffs, *ffi, *fbs, *fbi;
    const double *x, *y, *z;    /* positions of the pass: x* or x(t) */
    const double *x0, *y0, *z0; /* x(t): the displacements x* - x(t) of pressureSource */
    const double *bvx, *bvy, *bvz;
    double dt, mix;
    int source;       /* pressureSource (PCS_SOURCE_*) */
    double pmin;      /* the clamp of eq. (3)'s update: 0, or -HUGE_VAL with meanPressure */
    const double *lc; /* the gradient correction of each fluid particle (9 per particle) */
    const double *lf; /* the same for the pressure force (pressureForce corrected), or NULL */
    const unsigned char *lin; /* with lf: 1 where it corrects (an isotropic neighbourhood) */
    const double *lfc;        /* correctedConservative: L_i or the identity, every row, or NULL */
    const double *bx, *by, *bz, *bm;
    double *rho, *p, *pt, *err, *err_vol;
    double *apx, *apy, *apz;
    bnd_pass bp; /* what the method's terms read */
    eff_view dv; /* what the EFF_DENSITY effects read */
    const pcs_solver *s;
    int corrected; /* EFF_DENSITY effects in the set */
} pass_ctx;

static pass_ctx pass_begin(pcs_solver *s, const double *x, const double *y, const double *z)
{
    const sl_fluid *f = s->f;
    const sl_boundary *b = s->b;
    pass_ctx c = {.k = s->k,
                  .m = s->mass,
                  .rho0 = s->prm.rho0,
                  .delta = s->delta,
                  .self = s->mass * krn_w(&s->k, 0.0),
                  .ffs = s->ff.start,
                  .ffi = s->ff.idx,
                  .fbs = s->fb.start,
                  .fbi = s->fb.idx,
                  .x = x,
                  .y = y,
                  .z = z,
                  .x0 = f->x,
                  .y0 = f->y,
                  .z0 = f->z,
                  .bvx = b->vx,
                  .bvy = b->vy,
                  .bvz = b->vz,
                  .dt = s->dt,
                  .mix = s->prm.source_mix,
                  .source = s->prm.source,
                  .pmin = s->prm.hold_mean ? -HUGE_VAL : 0.0,
                  .lc = s->prm.grad_correction ? s->lcorr : NULL,
                  .lf = s->prm.force_correction == PCS_FORCE_CORRECTED ? s->lcorr : NULL,
                  .lfc = s->prm.force_correction == PCS_FORCE_CONSERVATIVE ? s->lforce : NULL,
                  .lin = s->linterior,
                  .bx = b->x,
                  .by = b->y,
                  .bz = b->z,
                  .bm = b->mass,
                  .rho = f->rho,
                  .p = f->p,
                  .pt = f->pt,
                  .err = s->err,
                  .err_vol = s->err_vol,
                  .apx = f->apx,
                  .apy = f->apy,
                  .apz = f->apz,
                  .bp = boundary_pass(s),
                  .s = s,
                  .corrected = s->ndens > 0};
    return c;
}

/* The same before a density pass: the EFF_DENSITY effects are prepared. */
static pass_ctx density_pass_begin(pcs_solver *s, const double *x, const double *y, const double *z)
{
    pass_ctx c = pass_begin(s, x, y, z);
    c.dv = density_effects(s, x, y, z);
    return c;
}

/* Density of fluid particle i at the pass's positions: its fluid
 * neighbours (and itself), the wall's share as the method takes it
 * (eq. 13 for ihmsen2010), and the EFF_DENSITY corrections; *rv is the
 * density with the boundary particles' share, the measure of every method. */
static inline __attribute__((always_inline)) double fluid_density(const pass_ctx *c, size_t i,
                                                                  const int wall_measured,
                                                                  const wall_density_fn wall_term,
                                                                  double *rv)
{
    const double xi = c->x[i], yi = c->y[i], zi = c->z[i];
    const double rf = c->self +
        c->m * sph_sum_w(c->k, c->ffi, c->ffs[i], c->ffs[i + 1], xi, yi, zi, c->x, c->y, c->z);
    /* the wall's share: part of the density (eq. 13) or only measured */
    const double rb = wall_measured
        ? sph_sum_mw(c->k, c->fbi, c->fbs[i], c->fbs[i + 1], xi, yi, zi, c->bx, c->by, c->bz, c->bm)
        : 0.0;
    double r = rf + wall_term(&c->bp, i, xi, yi, zi, rb);
    *rv = rf + rb;
    if (c->corrected) correct_density(c->s, &c->dv, i, xi, yi, zi, rb, &r, rv);
    return r;
}

/* pressureSource divergence and mixed: the predicted density change of
 * fluid particle i over the step from the displacements d = x* - x(t)
 * (dt v* where no collision moved it), at x(t): sum_j m (d_i - d_j) .
 * L_i grad W(x_i - x_j) over its fluid neighbours and, with walls in the
 * solve (eq. 13), sum_b m_b (d_i - dt v_b) . L_i grad W(x_i - x_b) over
 * its boundary neighbours, each in the order of its list; L_i the
 * gradient correction (gradientCorrection on), else the identity. */
static inline double fluid_change(const pass_ctx *c, size_t i, const int wall)
{
    const double xi = c->x0[i], yi = c->y0[i], zi = c->z0[i];
    const double dx = c->x[i] - xi, dy = c->y[i] - yi, dz = c->z[i] - zi;
    static const double unit[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double *L = c->lc ? c->lc + 9 * i : unit;
    double sf = 0.0;
    for (uint32_t q = c->ffs[i]; q < c->ffs[i + 1]; q++) {
        const uint32_t j = c->ffi[q];
        const double rx = xi - c->x0[j], ry = yi - c->y0[j], rz = zi - c->z0[j];
        const double g = krn_gradf(&c->k, sqrt(rx * rx + ry * ry + rz * rz));
        sf += g *
            ((L[0] * rx + L[1] * ry + L[2] * rz) * (dx - (c->x[j] - c->x0[j])) +
             (L[3] * rx + L[4] * ry + L[5] * rz) * (dy - (c->y[j] - c->y0[j])) +
             (L[6] * rx + L[7] * ry + L[8] * rz) * (dz - (c->z[j] - c->z0[j])));
    }
    double sb = 0.0;
    if (wall)
        for (uint32_t q = c->fbs[i]; q < c->fbs[i + 1]; q++) {
            const uint32_t j = c->fbi[q];
            const double rx = xi - c->bx[j], ry = yi - c->by[j], rz = zi - c->bz[j];
            const double g = krn_gradf(&c->k, sqrt(rx * rx + ry * ry + rz * rz));
            sb += c->bm[j] * g *
                ((L[0] * rx + L[1] * ry + L[2] * rz) * (dx - c->dt * c->bvx[j]) +
                 (L[3] * rx + L[4] * ry + L[5] * rz) * (dy - c->dt * c->bvy[j]) +
                 (L[6] * rx + L[7] * ry + L[8] * rz) * (dz - c->dt * c->bvz[j]));
        }
    return c->m * sf + sb;
}

/* Predicted density of fluid particle i at x* and its pressure update
 * p += delta rho_err* (eq. 3), clamped at zero; returns its compression
 * (pressureSource divergence and mixed: rho_err* is their source). */
static inline __attribute__((always_inline)) double
predict_one(const pass_ctx *c, size_t i, const int wall, const wall_density_fn wall_term)
{
    double rv;
    const double r = fluid_density(c, i, 1, wall_term, &rv);
    c->rho[i] = r;
    if (!wall) c->err_vol[i] = rv > c->rho0 ? rv - c->rho0 : 0.0;
    double e = r - c->rho0;
    if (c->source != PCS_SOURCE_DENSITY) {
        const double d = fluid_change(c, i, wall);
        e = c->source == PCS_SOURCE_DIVERGENCE ? d : (1.0 - c->mix) * d + c->mix * e;
    }
    const double pn = c->p[i] + c->delta * e; /* eq. (3) */
    const double pc = pn > c->pmin ? pn : c->pmin;
    c->p[i] = pc;
    c->pt[i] = pc / (r * r);
    const double cmp = e > 0.0 ? e : 0.0;
    c->err[i] = cmp;
    return cmp;
}

/* pressureForce correctedConservative: particle i's force, each fluid
 * pair's term of eq. (6) times (L_i + L_j) / 2 (lfc: L or the identity),
 * the wall's term times L_i: L_i (s / 2 + wall) + (sum_j L_j f_ij) / 2
 * with s = sum_j f_ij.  The pair's terms are opposite on i and j, as the
 * symmetric force's. */
static inline __attribute__((always_inline)) void
pressure_conservative(const pass_ctx *c, size_t i, const wall_pressure_fn wall_term)
{
    const double xi = c->x[i], yi = c->y[i], zi = c->z[i], pti = c->pt[i];
    double sm[3] = {0.0, 0.0, 0.0}, t[3] = {0.0, 0.0, 0.0};
    sph_sum_pressure_pairs(c->k, c->ffi, c->ffs[i], c->ffs[i + 1], xi, yi, zi, pti, c->x, c->y,
                           c->z, c->pt, c->lfc, sm, t);
    const double hm = 0.5 * c->m;
    double a[3] = {hm * sm[0], hm * sm[1], hm * sm[2]};
    wall_term(&c->bp, i, xi, yi, zi, pti, a);
    const double *L = c->lfc + 9 * i;
    c->apx[i] = L[0] * a[0] + L[1] * a[1] + L[2] * a[2] + hm * t[0];
    c->apy[i] = L[3] * a[0] + L[4] * a[1] + L[5] * a[2] + hm * t[1];
    c->apz[i] = L[6] * a[0] + L[7] * a[1] + L[8] * a[2] + hm * t[2];
}

/* Pressure force per unit mass on fluid particle i, eq. (6): its fluid
 * neighbours, then the wall's term of the method; with pressureForce
 * corrected the sum times L_i where its neighbourhood is isotropic (every
 * term is a multiple of grad W_ij).  correctedConservative:
 * pressure_conservative, in loops of its own (PCS_FORCE_ROWS), so that
 * the other forces' compiled loops, and their bits, are as before. */
static inline __attribute__((always_inline)) void pressure_one(const pass_ctx *c, size_t i,
                                                               const wall_pressure_fn wall_term)
{
    const double xi = c->x[i], yi = c->y[i], zi = c->z[i];
    double a[3] = {0.0, 0.0, 0.0};
    sph_sum_pressure(c->k, c->ffi, c->ffs[i], c->ffs[i + 1], xi, yi, zi, c->pt[i], c->x, c->y, c->z,
                     c->pt, NULL, c->m, a);
    wall_term(&c->bp, i, xi, yi, zi, c->pt[i], a);
    if (c->lf && c->lin[i]) {
        const double *L = c->lf + 9 * i;
        c->apx[i] = L[0] * a[0] + L[1] * a[1] + L[2] * a[2];
        c->apy[i] = L[3] * a[0] + L[4] * a[1] + L[5] * a[2];
        c->apz[i] = L[6] * a[0] + L[7] * a[1] + L[8] * a[2];
        return;
    }
    c->apx[i] = a[0];
    c->apy[i] = a[1];
    c->apz[i] = a[2];
}

/* The sums of rows (s->err for the density error) over this rank's rows
 * of blocks [b0, b1) of the serial order (rows [g0, g1) of it; own row i
 * is row i + gshift), into part: each block summed one row at a time, as
 * the serial pass sums its rows (the empty asm keeps the compiler from
 * reassociating). */
static void own_block_sums(const pcs_solver *s, const double *err, double *part, size_t b0,
                           size_t b1, size_t g0, size_t g1)
{
    const ptrdiff_t gs = s->split.gshift;
#pragma omp parallel for schedule(static)
    for (size_t blk = b0; blk < b1; blk++) {
        const size_t bl = blk * SL_REDUCE_BLOCK, lo = bl > g0 ? bl : g0;
        const size_t hi = bl + SL_REDUCE_BLOCK < g1 ? bl + SL_REDUCE_BLOCK : g1;
        double sum = 0.0;
        for (size_t gi = lo; gi < hi; gi++) {
            sum += err[(size_t)((ptrdiff_t)gi - gs)];
            __asm__("" : "+m"(sum));
        }
        part[blk] = sum;
    }
}

/* The sum of a per-row array over every fluid particle of the case, in
 * the density error's association (blocks of SL_REDUCE_BLOCK rows, each
 * summed from 0 one row at a time, the block sums in order): the same
 * bits on any ranks x threads.  Serial and the gather mode (after the
 * gather) hold every row; in the halo and domain modes each rank holds its
 * own rows of a, and the block sums (part: scratch of the blocks) are
 * continued across the ranks in the serial order (collective). */
static double fluid_sum(pcs_solver *s, const double *a, double *part)
{
    const size_t B = SL_REDUCE_BLOCK, nb = (pcs_fluid_total(s) + B - 1) / B;
    if (!s->split.halo) {
        block_sums(a, pcs_fluid_total(s), part);
        return sum_in_order(part, nb);
    }
    const size_t i0 = s->split.row[s->split.rank], i1 = s->split.row[s->split.rank + 1];
    const ptrdiff_t gs = s->split.gshift;
    const size_t g0 = (size_t)((ptrdiff_t)i0 + gs), g1 = (size_t)((ptrdiff_t)i1 + gs);
    own_block_sums(s, a, part, g0 / B, g1 > g0 ? (g1 + B - 1) / B : g0 / B, g0, g1);
    pcx_block_sums(s, a, part);
    return sum_in_order(part, nb);
}

/* meanPressure: the pressures of fluid and active boundary particles
 * shifted by one constant so that the fluid's mean is mean_pressure (in a
 * box without a free surface the projection's operator has the constant
 * in its null space: each update's mean source would otherwise move the
 * level, and on a disordered packing a level is a force of the symmetric
 * form, eq. (6)).  The mean is fluid_sum's: the same bits on any ranks x
 * threads.  In the halo and domain modes every rank shifts the rows it
 * computed (its own fluid rows, the boundary particles its rows see) by
 * the same constant, before their p/rho^2 travel to the neighbours; in
 * the gather mode and serially every row. */
static void hold_mean_pressure(pcs_solver *s)
{
    sl_fluid *f = s->f;
    sl_boundary *b = s->b;
    const size_t n = pcs_fluid_total(s);
    if (!n) return;
    const double shift = s->prm.mean_pressure - fluid_sum(s, f->p, s->p_block) / (double)n;
    const int own = s->split.halo;
    const size_t i0 = own ? s->split.row[s->split.rank] : 0;
    const size_t i1 = own ? s->split.row[s->split.rank + 1] : f->n;
    const uint32_t *set = own ? s->split.bset : s->active;
    const size_t nb = !s->prm.method->wall_density ? 0 /* eq. (13) */
        : own                                      ? s->split.nbset
                                                   : s->nactive;
#pragma omp parallel
    {
#pragma omp for schedule(static) nowait
        for (size_t i = i0; i < i1; i++) {
            f->p[i] += shift;
            f->pt[i] = f->p[i] / (f->rho[i] * f->rho[i]);
        }
#pragma omp for schedule(static) nowait
        for (size_t q = 0; q < nb; q++) {
            const uint32_t i = set[q];
            b->p[i] += shift;
            b->pt[i] = b->p[i] / (b->rho[i] * b->rho[i]);
        }
    }
}

/* After a density pass: meanPressure's shift, and under -parallel what
 * the pass computed made whole.  The gather mode shifts after the gather
 * (every rank then holds every row); the halo and domain modes before the
 * halo's p/rho^2 are sent. */
static double after_density(pcs_solver *s, int wall, double emax)
{
    if (s->split.size > 1 && !s->split.halo) {
        emax = gather_predicted(s, wall, emax);
        if (s->prm.hold_mean) hold_mean_pressure(s);
        return emax;
    }
    if (s->prm.hold_mean) hold_mean_pressure(s);
    return s->split.size > 1 ? pcx_after_density(s, emax) : emax;
}

/* The pressure force's rows of this rank (ROW: pressure_one or
 * pressure_conservative, WALL the method's wall term; c the pass): with
 * the domain mode's overlap first the rows that read no halo p/rho^2
 * while it travels, then the others; the gather mode gathers them. */
#define PCS_FORCE_ROWS(ROW, WALL)                                                                \
    do {                                                                                         \
        const size_t i0 = s->split.row[s->split.rank], i1 = s->split.row[s->split.rank + 1];     \
        if (s->split.overlap) {                                                                  \
            const uint32_t *ord = s->split.order;                                                \
            const size_t nin = s->split.ninner, nall = s->split.norder;                          \
            _Pragma("omp parallel for schedule(dynamic, 1024)") for (size_t q = 0; q < nin; q++) \
                ROW(&c, ord[q], WALL);                                                           \
            pcd_wait(s);                                                                         \
            _Pragma("omp parallel for schedule(dynamic, 1024)") for (size_t q = nin; q < nall;   \
                                                                     q++) ROW(&c, ord[q], WALL); \
            break;                                                                               \
        }                                                                                        \
        _Pragma("omp parallel for schedule(dynamic, 1024)") for (size_t i = i0; i < i1; i++)     \
            ROW(&c, i, WALL);                                                                    \
        if (s->split.size > 1 && !s->split.halo) gather_force(s);                                \
    } while (0)

/* The three passes of method M, each with its own parallel loop so that
 * the method's terms are inlined into it (the parallel region is outlined
 * per function, before inlining):
 *   M_predict  predicted density and pressure of the fluid at x* and of
 *              the active boundary particles (eq. 13, eq. 3), in one
 *              parallel region; fills s->err and its sum s->err_sum (in
 *              blocks of SL_REDUCE_BLOCK, each summed in order, the block
 *              sums in order: the same bits for any thread count) and
 *              returns the largest compression (absolute);
 *   M_force    the pressure force (eq. 6); correctedConservative's in
 *              M_force_conservative's loops;
 *   M_current  the density at x(t), for output (no pressure update). */
#define PCS_METHOD_PASSES(M)                                                                      \
    static double M##_predict_overlap(pcs_solver *s, const pass_ctx *c, size_t b0, size_t b1,     \
                                      size_t g0, size_t g1)                                       \
    {                                                                                             \
        const uint32_t *ord = s->split.order;                                                     \
        const size_t nin = s->split.ninner, nall = s->split.norder;                               \
        double emax = 0.0;                                                                        \
        _Pragma("omp parallel reduction(max : emax)")                                             \
        {                                                                                         \
            _Pragma("omp for schedule(dynamic, 256) nowait") for (size_t q = 0; q < nin; q++)     \
            {                                                                                     \
                const double e = predict_one(c, ord[q], M##_wall_density, M##_density);           \
                emax = e > emax ? e : emax;                                                       \
            }                                                                                     \
            if (M##_wall_density) boundary_density(s, 0);                                         \
        }                                                                                         \
        pcd_wait(s); /* the halo's x* */                                                          \
        _Pragma("omp parallel reduction(max : emax)")                                             \
        {                                                                                         \
            _Pragma("omp for schedule(dynamic, 256) nowait") for (size_t q = nin; q < nall; q++)  \
            {                                                                                     \
                const double e = predict_one(c, ord[q], M##_wall_density, M##_density);           \
                emax = e > emax ? e : emax;                                                       \
            }                                                                                     \
            if (M##_wall_density) boundary_density(s, 1);                                         \
        }                                                                                         \
        own_block_sums(s, s->err, s->err_block, b0, b1, g0, g1);                                  \
        return emax;                                                                              \
    }                                                                                             \
    static double M##_predict(pcs_solver *s)                                                      \
    {                                                                                             \
        const sl_fluid *f = s->f;                                                                 \
        const pass_ctx c = density_pass_begin(s, f->xs, f->ys, f->zs);                            \
        const size_t nb = (pcs_fluid_total(s) + SL_REDUCE_BLOCK - 1) / SL_REDUCE_BLOCK;           \
        const size_t i0 = s->split.row[s->split.rank], i1 = s->split.row[s->split.rank + 1];      \
        /* blocks of the serial order: own row i is row i + gs of it */                           \
        const ptrdiff_t gs = s->split.gshift;                                                     \
        const size_t g0 = (size_t)((ptrdiff_t)i0 + gs), g1 = (size_t)((ptrdiff_t)i1 + gs);        \
        const size_t b0 = g0 / SL_REDUCE_BLOCK;                                                   \
        const size_t b1 = g1 > g0 ? (g1 + SL_REDUCE_BLOCK - 1) / SL_REDUCE_BLOCK : b0;            \
        double *restrict part = s->err_block;                                                     \
        double emax = 0.0;                                                                        \
        if (s->split.overlap) /* the rows that read no halo x* while it travels */                \
            emax = M##_predict_overlap(s, &c, b0, b1, g0, g1);                                    \
        else _Pragma("omp parallel reduction(max : emax)")                                        \
            {                                                                                     \
                _Pragma("omp for schedule(dynamic, 1) nowait") for (size_t blk = b0; blk < b1;    \
                                                                    blk++)                        \
                {                                                                                 \
                    const size_t bl = blk * SL_REDUCE_BLOCK, lo = bl > g0 ? bl : g0;              \
                    const size_t hi = bl + SL_REDUCE_BLOCK < g1 ? bl + SL_REDUCE_BLOCK : g1;      \
                    double sum = 0.0;                                                             \
                    for (size_t gi = lo; gi < hi; gi++) {                                         \
                        const size_t i = (size_t)((ptrdiff_t)gi - gs);                            \
                        const double e = predict_one(&c, i, M##_wall_density, M##_density);       \
                        emax = e > emax ? e : emax;                                               \
                        sum += e;                                                                 \
                    }                                                                             \
                    part[blk] = sum;                                                              \
                }                                                                                 \
                if (M##_wall_density) boundary_density(s, -1);                                    \
            }                                                                                     \
        emax = after_density(s, M##_wall_density, emax);                                          \
        double total = 0.0;                                                                       \
        for (size_t blk = 0; blk < nb; blk++) total += part[blk];                                 \
        s->err_sum = total;                                                                       \
        return emax;                                                                              \
    }                                                                                             \
    static void M##_force_conservative(pcs_solver *s)                                             \
    {                                                                                             \
        const sl_fluid *f = s->f;                                                                 \
        const pass_ctx c = pass_begin(s, f->xs, f->ys, f->zs);                                    \
        PCS_FORCE_ROWS(pressure_conservative, M##_pressure);                                      \
    }                                                                                             \
    static void M##_force(pcs_solver *s)                                                          \
    {                                                                                             \
        if (s->prm.force_correction == PCS_FORCE_CONSERVATIVE) {                                  \
            M##_force_conservative(s);                                                            \
            return;                                                                               \
        }                                                                                         \
        const sl_fluid *f = s->f;                                                                 \
        const pass_ctx c = pass_begin(s, f->xs, f->ys, f->zs);                                    \
        PCS_FORCE_ROWS(pressure_one, M##_pressure);                                               \
    }                                                                                             \
    static void M##_current(pcs_solver *s)                                                        \
    {                                                                                             \
        const sl_fluid *f = s->f;                                                                 \
        const pass_ctx c = density_pass_begin(s, f->x, f->y, f->z);                               \
        const size_t n = f->n;                                                                    \
        double rv;                                                                                \
        _Pragma("omp parallel for schedule(dynamic, 1024) private(rv)") for (size_t i = 0; i < n; \
                                                                             i++) c.rho[i] =      \
            fluid_density(&c, i, M##_wall_density, M##_density, &rv);                             \
    }
BND_METHODS(PCS_METHOD_PASSES)
#define PCS_METHOD_ENTRY(M) {&M##_method, M##_predict, M##_force, M##_current},
static const pcs_method_passes method_passes[] = {BND_METHODS(PCS_METHOD_ENTRY)};

double pcs_pass_density(pcs_solver *s) { return s->passes->predict(s); }

void pcs_pass_pressure(pcs_solver *s) { s->passes->pressure(s); }

/* ---- set-up ---- */

/* The ranks of the job (one without -parallel) and room for the split;
 * the boundary's count does not change after set-up. */
static void split_init(pcs_split *sp, size_t nb, int one_rank)
{
    memset(sp, 0, sizeof *sp);
    sp->rank = one_rank ? 0 : par_rank();
    sp->size = one_rank ? 1 : par_size();
    const size_t p = (size_t)sp->size + 1;
    sp->row = sl_malloc(p * sizeof *sp->row, "rank rows");
    sp->act = sl_malloc(p * sizeof *sp->act, "rank rows");
    memset(sp->row, 0, p * sizeof *sp->row);
    memset(sp->act, 0, p * sizeof *sp->act);
    if (sp->size > 1) sp->bbuf = sl_alloc_aligned((3 * nb + 1) * sizeof *sp->bbuf, "boundary rows");
}

size_t pcs_grid_cells(size_t nfluid, size_t nboundary)
{
    return 8 * (nfluid + nboundary) + ((size_t)1 << 20);
}

void pcs_init(pcs_solver *s, const pcs_params *p, sl_fluid *f, sl_boundary *b, const double lo[3],
              const double hi[3], double dt, eff_set *effects)
{
    pcs_init_part(s, p, f, b, lo, hi, dt, effects, NULL);
}

void pcs_init_part(pcs_solver *s, const pcs_params *p, sl_fluid *f, sl_boundary *b,
                   const double lo[3], const double hi[3], double dt, eff_set *effects,
                   struct pcd_plan *plan)
{
    memset(s, 0, sizeof *s);
    s->prm = *p;
    s->h = pcs_support(p);
    s->mass = pcs_mass(p);
    s->eta_abs = p->eta * p->rho0;
    s->f = f;
    s->b = b;
    s->eff = effects;
    pcs_kernel(p, &s->k);
    const size_t max_cells = plan
        ? pcs_grid_cells(pcd_plan_fluid_total(plan), pcd_plan_boundary_total(plan))
        : pcs_grid_cells(f->n, b->n);
    nbr_grid_init(&s->grid, lo, hi, s->h, max_cells);
    nbr_list_init(&s->ff);
    nbr_list_init(&s->fb);
    nbr_list_init(&s->bf);
    dom_halo_init(&s->halo, &p->periodic, s->h);
    dom_boundary_images(&s->halo, b);
    dom_periodic_wrap(&p->periodic, f->n, f->x, f->y, f->z);
    nbr_sort_boundary(&s->grid, b);
    s->cal = bnd_calibrate(&s->k, p->r0, s->mass, p->rho0);
    /* massFactor: heavier (or lighter) walls, the boundary particles' own
     * rest density kept at rho0 */
    s->cal.gamma *= p->mass_factor;
    s->cal.c_static /= p->mass_factor;
    bnd_set_mass(&s->grid, &s->k, &s->cal, p->rho0, b);
    dom_boundary_images_mass(&s->halo, &s->grid, &s->k, s->cal.c_static, b);
    s->active_cap = b->n + 1;
    s->active = sl_alloc_aligned(s->active_cap * sizeof *s->active, "active boundary list");
    for (size_t m = 0; m < sizeof method_passes / sizeof *method_passes; m++)
        if (method_passes[m].type == p->method) s->passes = &method_passes[m];
    if (!s->passes) sl_fatal("pcs_init: boundary method not in BND_METHODS");
    s->bsu = (bnd_setup){s->k, p->r0, s->mass, p->rho0, p->epsilon, p->restitution};
    s->bstate = p->method->init ? p->method->init(&s->bsu) : NULL;
    if (effects && effects->n) {
        s->dens = sl_malloc(effects->n * sizeof *s->dens, "density effects");
        for (size_t q = 0; q < effects->n; q++)
            if (effects->e[q].type->stage == EFF_DENSITY) s->dens[s->ndens++] = &effects->e[q];
    }
    for (size_t i = 0; i < f->n; i++) f->rho[i] = p->rho0; /* until the first pass */
    split_init(&s->split, b->n, p->one_rank);
    s->split.halo = pcx_usable(s);
    if (s->split.halo && pcd_usable(s)) { /* every rank keeps its own particles only */
        s->split.domain = 1;
        pcd_init(s, plan);
    } else if (plan)
        sl_fatal("pcs_init_part: a case built in parts needs the domain mode (internal error)");
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
    sl_free_aligned(s->err_block);
    sl_free_aligned(s->vol_block);
    sl_free_aligned(s->p_block);
    sl_free_aligned(s->err_vol);
    sl_free_aligned(s->ap_best);
    sl_free_aligned(s->lcorr);
    sl_free_aligned(s->linterior);
    sl_free_aligned(s->lforce);
    sl_free_aligned(s->pw);
    sl_free_aligned(s->pw_block);
    if (s->prm.method && s->prm.method->free) s->prm.method->free(s->bstate);
    free(s->dens);
    dom_halo_free(&s->halo);
    pcx_free(s);
    pcd_free(s);
    free(s->split.owner);
    sl_free_aligned(s->split.order);
    free(s->split.row);
    free(s->split.act);
    sl_free_aligned(s->split.bbuf);
    memset(s, 0, sizeof *s);
}

/* Scratch sized for the fluid's capacity (which an emitter grows). */
static void ensure_scratch(pcs_solver *s)
{
    /* the blocks of the serial order (domain mode: of every rank's rows) */
    const size_t rows = s->f->cap > s->split.nglobal ? s->f->cap : s->split.nglobal;
    if (s->block_cap < rows / SL_REDUCE_BLOCK + 1) {
        s->block_cap = rows / SL_REDUCE_BLOCK + 1;
        sl_free_aligned(s->err_block);
        s->err_block = sl_alloc_aligned(s->block_cap * sizeof *s->err_block, "density error sums");
        if (s->prm.hold_mean) {
            sl_free_aligned(s->p_block);
            s->p_block = sl_alloc_aligned(s->block_cap * sizeof *s->p_block, "pressure sums");
        }
        if (!s->prm.method->wall_density) {
            sl_free_aligned(s->vol_block);
            s->vol_block =
                sl_alloc_aligned(s->block_cap * sizeof *s->vol_block, "density error sums");
        }
    }
    if (s->power_on && (s->pw_cap < s->f->cap || s->pw_blocks < s->block_cap)) {
        s->pw_cap = s->f->cap;
        s->pw_blocks = s->block_cap;
        sl_free_aligned(s->pw);
        sl_free_aligned(s->pw_block);
        s->pw = sl_alloc_aligned(s->pw_cap * sizeof *s->pw, "power");
        s->pw_block = sl_alloc_aligned(s->pw_blocks * sizeof *s->pw_block, "power sums");
    }
    if (s->err_cap < s->f->cap) {
        sl_free_aligned(s->err);
        s->err = sl_alloc_aligned(s->f->cap * sizeof *s->err, "density error");
        if (s->prm.max_iter > s->prm.min_iter) {
            sl_free_aligned(s->ap_best);
            s->ap_best = sl_alloc_aligned(3 * s->f->cap * sizeof *s->ap_best, "pressure force");
        }
        if (s->prm.grad_correction || s->prm.force_correction) {
            sl_free_aligned(s->lcorr);
            s->lcorr = sl_alloc_aligned(9 * s->f->cap * sizeof *s->lcorr, "gradient correction");
        }
        if (s->prm.force_correction) {
            sl_free_aligned(s->linterior);
            s->linterior =
                sl_alloc_aligned(s->f->cap * sizeof *s->linterior, "gradient correction");
        }
        if (s->prm.force_correction == PCS_FORCE_CONSERVATIVE) {
            sl_free_aligned(s->lforce);
            s->lforce = sl_alloc_aligned(9 * s->f->cap * sizeof *s->lforce, "gradient correction");
        }
        if (!s->prm.method->wall_density) {
            sl_free_aligned(s->err_vol);
            s->err_vol = sl_alloc_aligned(s->f->cap * sizeof *s->err_vol, "density error");
        }
        s->err_cap = s->f->cap;
    }
    if (s->prm.method->reserve) s->prm.method->reserve(s->bstate, s->f->cap);
}

/* ---- the phases of Algorithm 2 ---- */

void pcs_place_world(pcs_solver *s, double t)
{
    eff_view v = effect_view(s, t, 0.0, NULL, NULL, NULL);
    eff_run(s->eff, EFF_PRE_STEP, &v);
}

/* The world at the end of the step (moving bodies at t + dt). */
static void move_world(pcs_solver *s)
{
    eff_view v = effect_view(s, s->t, s->dt, NULL, NULL, NULL);
    eff_run(s->eff, EFF_PRE_STEP, &v);
}

void pcs_find_neighbours(pcs_solver *s)
{
    if (s->split.domain) { /* migration, rebalancing, the halo from its owners */
        pcd_distribute(s);
        ensure_scratch(s);
        if (s->active_cap < s->b->n + 1) { /* moving walls brought more boundary particles */
            sl_free_aligned(s->active);
            s->active_cap = s->b->cap + 1;
            s->active = sl_alloc_aligned(s->active_cap * sizeof *s->active, "active boundary list");
        }
    }
    PHASE(s, sort, nbr_sort_fluid(&s->grid, s->f));
    if (dom_halo_on(&s->halo)) { /* periodic images after the owned particles */
        PHASE(s, halo, dom_fluid_images(&s->halo, &s->grid, s->f, s->b));
        ensure_scratch(s);
    }
    PHASE(s, list_ff, nbr_build_fluid(&s->grid, s->f, s->b, &s->ff, &s->fb));
    PHASE(s, list_bf, nbr_transpose(&s->fb, s->b->n, &s->bf, s->active, &s->nactive));
    if (s->split.domain) {
        pcd_after_search(s);
        return;
    }
    split_rows(s);
    if (s->split.halo) pcx_build(s);
}

/* Non-pressure forces per unit mass (the forces-stage effects the case
 * named: the uniform ones set with the reset, the others each a pass);
 * zero pressure and pressure force of fluid and active boundary (with
 * pressureSource divergence or mixed the pressures are kept: the warm
 * start, warm_start below). */
static void compute_forces(pcs_solver *s)
{
    sl_fluid *f = s->f;
    const int keep = s->prm.source != PCS_SOURCE_DENSITY && s->prm.warm_start;
    double g[3];
    eff_uniform(s->eff, g); /* gravity */
    const double gx = g[0], gy = g[1], gz = g[2];
    const uint32_t *act = s->active;
    double *pb = s->b->p;
#pragma omp parallel
    {
#pragma omp for schedule(dynamic, 1024) nowait
        for (size_t i = 0; i < f->n; i++) {
            f->ax[i] = gx;
            f->ay[i] = gy;
            f->az[i] = gz;
            f->apx[i] = f->apy[i] = f->apz[i] = 0.0;
            if (!keep) f->p[i] = 0.0;
        }
        if (!keep) {
#pragma omp for schedule(static) nowait
            for (size_t q = 0; q < s->nactive; q++) pb[act[q]] = 0.0;
        }
    }
    eff_view v = effect_view(s, s->t, s->dt, f->x, f->y, f->z);
    own_rows_only(s, &v);
    eff_run(s->eff, EFF_FORCES, &v);
}

/* World collision of positions (and velocities when vx != NULL). */
static size_t collide(pcs_solver *s, double *x, double *y, double *z, double *vx, double *vy,
                      double *vz)
{
    return s->prm.method->collide(s->bstate, &s->bsu, &s->fb, s->b, s->f->n, x, y, z, vx, vy, vz);
}

/* The rows a rank integrates: its own in halo mode, else all. */
static void own_rows(const pcs_solver *s, size_t *i0, size_t *i1)
{
    *i0 = s->split.halo ? s->split.row[s->split.rank] : 0;
    *i1 = s->split.halo ? s->split.row[s->split.rank + 1] : s->f->n;
}

/* World collision of rows [i0, i1) (the lists seen from row i0). */
static size_t collide_rows(pcs_solver *s, size_t i0, size_t i1, double *x, double *y, double *z,
                           double *vx, double *vy, double *vz)
{
    if (i0 == 0 && i1 == s->f->n) return collide(s, x, y, z, vx, vy, vz);
    nbr_list v = s->fb;
    v.start = s->fb.start + i0;
    v.n = i1 - i0;
    return s->prm.method->collide(s->bstate, &s->bsu, &v, s->b, i1 - i0, x + i0, y + i0, z + i0,
                                  vx ? vx + i0 : NULL, vy ? vy + i0 : NULL, vz ? vz + i0 : NULL);
}

/* v* = v + dt (F^{v,g,ext} + F^p) / m, x* = x + dt v*; collision (eq. 9-11). */
static void predict_positions(pcs_solver *s)
{
    sl_fluid *f = s->f;
    const double dt = s->dt;
    size_t i0, i1;
    own_rows(s, &i0, &i1);
#pragma omp parallel for schedule(dynamic, 1024)
    for (size_t i = i0; i < i1; i++) {
        double vx = f->vx[i] + dt * (f->ax[i] + f->apx[i]);
        double vy = f->vy[i] + dt * (f->ay[i] + f->apy[i]);
        double vz = f->vz[i] + dt * (f->az[i] + f->apz[i]);
        f->xs[i] = f->x[i] + dt * vx;
        f->ys[i] = f->y[i] + dt * vy;
        f->zs[i] = f->z[i] + dt * vz;
    }
    collide_rows(s, i0, i1, f->xs, f->ys, f->zs, NULL, NULL, NULL);
    if (s->split.halo) pcx_exchange_predicted(s); /* the halo's x* */
}

/* Iterating to convergence (maxIterations > minIterations), the
 * correction can overshoot near walls, where the collision keeps the
 * predicted positions from moving, and the error then grows with every
 * further iteration.  The guard keeps the pressure force that gave the
 * smallest error, and a growing error ends the iterations with it. */
typedef struct pcs_guard {
    int on;
    double best;
} pcs_guard;

/* 1 when this prediction (error emax after k force updates) is worse than
 * the best so far and the minimum iterations are done: the best force is
 * back in place and the iterations end. */
static int guard_stops(pcs_solver *s, pcs_guard *g, double emax, int k)
{
    if (!g->on) return 0;
    sl_fluid *f = s->f;
    const size_t bytes = f->n * sizeof(double);
    if (emax < g->best) { /* the force in use gave the best prediction so far */
        g->best = emax;
        memcpy(s->ap_best, f->apx, bytes);
        memcpy(s->ap_best + f->cap, f->apy, bytes);
        memcpy(s->ap_best + 2 * f->cap, f->apz, bytes);
        return 0;
    }
    if (k < s->prm.min_iter) return 0;
    memcpy(f->apx, s->ap_best, bytes);
    memcpy(f->apy, s->ap_best + f->cap, bytes);
    memcpy(f->apz, s->ap_best + 2 * f->cap, bytes);
    return 1;
}

/* Average compression of the fluid (fraction of rho0) from the sum of its
 * compressions. */
static double average_of(const pcs_solver *s, double sum)
{
    const size_t n = pcs_fluid_total(s);
    const double inv_n = n ? 1.0 / (double)n : 0.0;
    return sum * inv_n / s->prm.rho0;
}

/* Whether a prediction with largest error emax (and average from
 * s->err_sum) ends the iterations (after minIterations). */
static int reached_eta(const pcs_solver *s, double emax)
{
    if (s->prm.stop_max > 0.0)
        return emax <= s->prm.stop_max * s->prm.rho0 && average_of(s, s->err_sum) <= s->prm.eta;
    return emax <= s->eta_abs;
}

/* The statistics of the last prediction (err_max: emax). */
static void solve_stats(pcs_solver *s, pcs_stats *st, int k, double emax)
{
    const size_t n = pcs_fluid_total(s);
    const double rho0 = s->prm.rho0;
    st->iterations = k;
    st->converged = reached_eta(s, emax);
    st->err_max = emax / rho0;
    st->err_avg = average_of(s, s->err_sum); /* the last prediction's */
    if (s->prm.method->wall_density) {
        st->vol_avg = st->err_avg;
        st->vol_max = st->err_max;
    } else { /* by blocks in the serial order, as the density error (domain mode: no row
              * travels; the other modes hold every row) */
        const size_t nb = (n + SL_REDUCE_BLOCK - 1) / SL_REDUCE_BLOCK;
        double vmax;
        if (s->split.domain) vmax = pcd_vol_blocks(s);
        else {
            block_sums(s->err_vol, n, s->vol_block);
            vmax = sl_max(s->err_vol, n);
        }
        st->vol_avg = n ? average_of(s, sum_in_order(s->vol_block, nb)) : 0.0;
        st->vol_max = n ? vmax / rho0 : 0.0;
    }
    st->nactive = s->split.domain ? s->split.nactive_all : s->nactive;
}

/* What the next pass reads of the halo copies, from their originals:
 * after the prediction (what = 0) the predicted positions, after the
 * density pass (what = 1) density, pressure and p / rho^2. */
static void halo_refresh(pcs_solver *s, int what)
{
    if (!dom_halo_on(&s->halo)) return;
    const double t0 = omp_get_wtime();
    if (what == 0) dom_refresh_predicted(&s->halo, s->f);
    else dom_refresh_pressure(&s->halo, s->f, s->b);
    s->time.halo += omp_get_wtime() - t0;
}

/* pressureSource divergence and mixed: the step starts from the last
 * step's pressures (as DFSPH's solvers do), since the divergence source
 * only corrects what the step would change: their force at x(t) (p /
 * rho^2 with the density of the last prediction) is the first iteration's
 * F^p.  Every mode: a halo particle carries its owner's p and rho (the
 * domain mode's halo, the replicated state of the halo and gather modes),
 * so every rank starts from the serial values. */
static void warm_start(pcs_solver *s)
{
    sl_fluid *f = s->f;
    const size_t n = f->n;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        f->xs[i] = f->x[i];
        f->ys[i] = f->y[i];
        f->zs[i] = f->z[i];
        f->pt[i] = f->p[i] / (f->rho[i] * f->rho[i]);
    }
    halo_refresh(s, 0);
    halo_refresh(s, 1);
    PHASE(s, pressure, s->passes->pressure(s));
}

/* pressureSource gradientCorrection, pressureForce corrected: the kernel
 * gradient correction of each fluid particle at x(t),
 * L_i = (sum_j V_j grad W_ij (x_j - x_i)^T)^-1 over its fluid and
 * boundary neighbours (V_j = m_j / rho0; Bonet & Lok 1999), the identity
 * where the sum is near singular (a deficient neighbourhood);
 * with pressureForce corrected and correctedConservative also whether the
 * force takes it (an isotropic A_i, PCS_FORCE_ISOTROPY); with
 * correctedConservative lforce, L_i or the identity, on every row the
 * force reads (own, halo, images). */
static void gradient_correction(pcs_solver *s)
{
    const sl_fluid *f = s->f;
    const sl_boundary *b = s->b;
    const krn_kernel k = s->k;
    const double vf = s->mass / s->prm.rho0, irho0 = 1.0 / s->prm.rho0;
    const size_t n = f->n;
    double *lc = s->lcorr;
#pragma omp parallel for schedule(dynamic, 1024)
    for (size_t i = 0; i < n; i++) {
        double A[9] = {0};
        const double xi = f->x[i], yi = f->y[i], zi = f->z[i];
        for (uint32_t q = s->ff.start[i]; q < s->ff.start[i + 1]; q++) {
            const uint32_t j = s->ff.idx[q];
            const double r[3] = {xi - f->x[j], yi - f->y[j], zi - f->z[j]};
            krn_correction_add(A, vf * krn_gradf(&k, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])),
                               r);
        }
        for (uint32_t q = s->fb.start[i]; q < s->fb.start[i + 1]; q++) {
            const uint32_t j = s->fb.idx[q];
            const double r[3] = {xi - b->x[j], yi - b->y[j], zi - b->z[j]};
            krn_correction_add(A,
                               b->mass[j] * irho0 *
                                   krn_gradf(&k, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])),
                               r);
        }
        const int corrects = krn_correction_invert(A, lc + 9 * i);
        if (s->linterior)
            s->linterior[i] =
                (unsigned char)(corrects && krn_correction_isotropy(A) >= PCS_FORCE_ISOTROPY);
        if (s->lforce) {
            static const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            memcpy(s->lforce + 9 * i, s->linterior[i] ? lc + 9 * i : id, sizeof id);
        }
    }
    if (s->prm.force_correction != PCS_FORCE_CONSERVATIVE) return;
    /* correctedConservative reads its neighbours' L_j: the domain mode's
     * halo rows from their owners (their lists here are not whole), then
     * the periodic images from their originals */
    if (s->split.domain) pcd_exchange_rows(s, s->lforce, 9);
    if (dom_halo_on(&s->halo)) dom_refresh_rows(&s->halo, n, s->lforce, 9);
}

/* The loop of Algorithm 2: predict, correct the pressure, until the
 * largest predicted compression is at most eta (after minIterations, at
 * most maxIterations). */
static void pressure_solve(pcs_solver *s, pcs_stats *st)
{
    if ((s->prm.source != PCS_SOURCE_DENSITY && s->prm.grad_correction) || s->prm.force_correction)
        gradient_correction(s);
    if (s->prm.source != PCS_SOURCE_DENSITY && s->prm.warm_start) warm_start(s);
    pcs_guard g = {s->prm.max_iter > s->prm.min_iter && pcs_fluid_total(s) > 0, HUGE_VAL};
    double emax;
    int k = 0;
    for (;;) {
        PHASE(s, predict, predict_positions(s));         /* v*, x*; eq. (9)-(11) */
        halo_refresh(s, 0);                              /* images' x* */
        PHASE(s, density, emax = s->passes->predict(s)); /* rho*, eq. (13); p, eq. (3) */
        halo_refresh(s, 1);                              /* images' rho, p, p/rho^2 */
        if (k == 0) {
            st->err_max_before = emax / s->prm.rho0;
            st->err_avg_before = average_of(s, s->err_sum);
        }
        if (guard_stops(s, &g, emax, k)) {
            emax = g.best;
            st->diverging = 1;
            break;
        }
        PHASE(s, pressure, s->passes->pressure(s)); /* F^p, eq. (6) */
        k++;
        if (k >= s->prm.max_iter || (k >= s->prm.min_iter && reached_eta(s, emax))) break;
    }
    pcd_wait(s); /* domain mode: what the guard left in flight */
    solve_stats(s, st, k, emax);
}

/* pcs_want_power: the step's powers m sum a . v(t + dt) of the pressure
 * force and of the others, over rows [i0, i1) (own), summed as the
 * density error (fluid_sum: collective in the halo and domain modes). */
static void step_power(pcs_solver *s, size_t i0, size_t i1)
{
    const sl_fluid *f = s->f;
    double *pw = s->pw;
    for (int q = 0; q < 2; q++) {
        const double *ax = q ? f->ax : f->apx, *ay = q ? f->ay : f->apy, *az = q ? f->az : f->apz;
#pragma omp parallel for schedule(static)
        for (size_t i = i0; i < i1; i++)
            pw[i] = ax[i] * f->vx[i] + ay[i] * f->vy[i] + az[i] * f->vz[i];
        s->power[q] = s->mass * fluid_sum(s, pw, s->pw_block);
    }
}

void pcs_want_power(pcs_solver *s)
{
    s->power_on = 1;
    s->power[0] = s->power[1] = (double)NAN; /* pw: ensure_scratch */
}

/* Euler-Cromer, then the world collision (eq. 11, 12); vmax and fmax. */
static void integrate(pcs_solver *s, pcs_stats *st)
{
    sl_fluid *f = s->f;
    const double dt = s->dt;
    double v2max = 0.0, f2max = 0.0;
    size_t i0, i1;
    own_rows(s, &i0, &i1);
#pragma omp parallel for schedule(dynamic, 1024) reduction(max : f2max)
    for (size_t i = i0; i < i1; i++) {
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
    if (s->power_on) step_power(s, i0, i1);
    st->ncollide = collide_rows(s, i0, i1, f->x, f->y, f->z, f->vx, f->vy, f->vz);
#pragma omp parallel for schedule(dynamic, 1024) reduction(max : v2max)
    for (size_t i = i0; i < i1; i++) {
        double v2 = f->vx[i] * f->vx[i] + f->vy[i] * f->vy[i] + f->vz[i] * f->vz[i];
        if (!(v2 <= v2max)) v2max = isnan(v2) ? HUGE_VAL : v2;
    }
    if (s->split.halo) { /* maxima and a count: exact in any order */
        const double t0 = omp_get_wtime();
        v2max = par_max_double(v2max);
        f2max = par_max_double(f2max);
        st->ncollide = (size_t)par_sum_long((long)st->ncollide);
        s->time.comm += omp_get_wtime() - t0;
        pcx_after_integrate(s); /* the state whole again on every rank */
    }
    st->vmax = sqrt(v2max);
    st->fmax = sqrt(f2max);
}

/* The EFF_SHIFT effects (particleShifting): x(t) moved with the step's
 * lists, before the integration adds dt v; not in the relaxation. */
static void shift_positions(pcs_solver *s)
{
    eff_view v = effect_view(s, s->t, s->dt, s->f->x, s->f->y, s->f->z);
    own_rows_only(s, &v);
    eff_run(s->eff, EFF_SHIFT, &v);
}

/* One step of Algorithm 2 from t to t + dt. */
void pcs_step(pcs_solver *s, pcs_stats *st)
{
    memset(st, 0, sizeof *st);
    ensure_scratch(s);
    PHASE(s, world, move_world(s));           /* moving bodies at t + dt */
    PHASE(s, search, pcs_find_neighbours(s)); /* neighbours N_i(t), fluid and boundary */
    PHASE(s, forces, compute_forces(s));      /* F^{v,g,ext}; p = 0, F^p = 0 */
    pressure_solve(s, st);                    /* until rho_err* <= eta: eq. (3)-(13) */
    shift_positions(s);                       /* particleShifting: x(t) moved (effects) */
    PHASE(s, integrate, integrate(s, st));    /* v, x (Euler-Cromer); eq. (9)-(12) */
    dom_after_integrate(&s->halo, s->f);      /* periodic: x wrapped, images dropped */
    s->t += s->dt;
}

void pcs_step_in_place(pcs_solver *s, pcs_stats *st)
{
    memset(st, 0, sizeof *st);
    ensure_scratch(s);
    PHASE(s, search, pcs_find_neighbours(s));
    PHASE(s, forces, compute_forces(s));
    pressure_solve(s, st);
    PHASE(s, integrate, integrate(s, st));
    dom_after_integrate(&s->halo, s->f);
}

void pcs_post_step(pcs_solver *s, double t, double dt)
{
    const size_t n0 = s->f->n;
    eff_view v = effect_view(s, t, dt, NULL, NULL, NULL);
    eff_run(s->eff, EFF_POST_STEP, &v);
    if (s->split.domain) pcd_keep_emitted(s, n0); /* emitted alike on every rank */
}

pcs_view pcs_view_of(const pcs_solver *s)
{
    /* domain mode: rank 0 shows the state gathered (pcs_gather) */
    const sl_fluid *mf = pcd_mirror(s);
    const nbr_list *mbf = pcd_mirror_bf(s);
    const sl_boundary *mb = pcd_mirror_boundary(s);
    return (pcs_view){.f = mf ? mf : s->f,
                      .b = mb ? mb : s->b,
                      .grid = mf ? pcd_mirror_grid(s) : &s->grid,
                      .bf = mbf ? mbf : &s->bf,
                      .k = s->k,
                      .h = s->h,
                      .r0 = s->prm.r0,
                      .mass = s->mass,
                      .rho0 = s->prm.rho0,
                      .gravity = s->prm.gravity,
                      .periodic = s->prm.periodic.axes ? &s->prm.periodic : NULL,
                      .boundary_images = s->halo.nb_img > 0,
                      .fluid_z = mf ? pcd_mirror_zext(s) : NULL,
                      .own = s->f,
                      .dom = s->split.domain ? s : NULL,
                      .power = s->power_on ? s->power : NULL};
}

void pcs_compute_density(pcs_solver *s)
{
    ensure_scratch(s);
    pcs_find_neighbours(s);
    s->passes->density(s);
    if (s->split.domain) pcd_keep_own(s); /* the own rows (output streams them: pcd_output_begin) */
}

size_t pcs_fluid_total(const pcs_solver *s) { return s->split.domain ? s->split.nglobal : s->f->n; }

size_t pcs_boundary_total(const pcs_solver *s)
{
    return s->split.domain ? s->split.nbglobal : s->b->n;
}

void pcs_gather(pcs_solver *s)
{
    if (s->split.domain) pcd_gather(s);
}

void pcs_gather_near(pcs_solver *s, const double *boxes, size_t nboxes)
{
    if (s->split.domain) pcd_gather_near(s, boxes, nboxes);
}
