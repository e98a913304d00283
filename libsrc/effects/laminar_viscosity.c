/* laminar_viscosity: Morris, Fox & Zhu 1997 viscosity (see laminar_viscosity.h). */
#include "effects/laminar_viscosity.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"
#include "kernel/sph_sums.h"

/* laminarViscosity normalized: particle i's second moment of the viscous
 * weights, tau_i = -1/3 sum_j V_j F_ij |r_ij|^2 (F = gradf r^2 / (r^2 +
 * eps), V_j = m_j / rho0, fluid and boundary neighbours in their lists'
 * order): the factor by which the sum misses nu Laplacian v on the packing
 * (0.9915 on the cubic lattice at h = 2 r0). */
static double second_moment(const krn_kernel *k, double vf, double irho0, const sl_fluid *f,
                            const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i,
                            double eps_h2)
{
    const double xi = f->x[i], yi = f->y[i], zi = f->z[i];
    double sf = 0.0, sb = 0.0;
    for (uint32_t q = ff->start[i]; q < ff->start[i + 1]; q++) {
        const uint32_t j = ff->idx[q];
        const double dx = xi - f->x[j], dy = yi - f->y[j], dz = zi - f->z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        sf += krn_gradf(k, sqrt(r2)) * r2 * r2 / (r2 + eps_h2);
    }
    for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
        const uint32_t j = fb->idx[q];
        const double dx = xi - b->x[j], dy = yi - b->y[j], dz = zi - b->z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        sb += b->mass[j] * krn_gradf(k, sqrt(r2)) * r2 * r2 / (r2 + eps_h2);
    }
    return -(vf * sf + irho0 * sb) / 3.0;
}

/* normalized tensor: the fourth moment of particle i's viscous weights,
 * Q_abcd = sum_j w_ij r_a r_b r_c r_d / |r|^2 (w_ij = -V_j gradf |r|^2 /
 * (|r|^2 + eps), fluid and boundary neighbours in their lists' order),
 * totally symmetric: its 15 components q[e], e the monomial x^nx y^ny
 * z^(4-nx-ny) at q4_index[nx][ny]. */
static const unsigned char q4_index[5][5] = {
    {0, 1, 2, 3, 4}, {5, 6, 7, 8, 0}, {9, 10, 11, 0, 0}, {12, 13, 0, 0, 0}, {14, 0, 0, 0, 0}};

static inline void q4_add(double q[15], double w, double dx, double dy, double dz)
{
    const double c = w / (dx * dx + dy * dy + dz * dz);
    const double x2 = dx * dx, y2 = dy * dy, z2 = dz * dz;
    const double cx = c * dx, cx2 = c * x2, cx3 = cx2 * dx, cy = c * dy, cy2 = c * y2;
    q[0] += c * z2 * z2;    /* z^4 */
    q[1] += cy * z2 * dz;   /* y z^3 */
    q[2] += cy2 * z2;       /* y^2 z^2 */
    q[3] += cy2 * dy * dz;  /* y^3 z */
    q[4] += cy2 * y2;       /* y^4 */
    q[5] += cx * z2 * dz;   /* x z^3 */
    q[6] += cx * dy * z2;   /* x y z^2 */
    q[7] += cx * y2 * dz;   /* x y^2 z */
    q[8] += cx * y2 * dy;   /* x y^3 */
    q[9] += cx2 * z2;       /* x^2 z^2 */
    q[10] += cx2 * dy * dz; /* x^2 y z */
    q[11] += cx2 * y2;      /* x^2 y^2 */
    q[12] += cx3 * dz;      /* x^3 z */
    q[13] += cx3 * dy;      /* x^3 y */
    q[14] += cx3 * dx;      /* x^4 */
}

static inline double q4_at(const double q[15], int a, int b, int c, int d)
{
    int n[3] = {0, 0, 0};
    n[a]++, n[b]++, n[c]++, n[d]++;
    return q[q4_index[n[0]][n[1]]];
}

/* The symmetric A with sum_j w_ij (r^T A r / |r|^2) r r^T = I, i.e.
 * Q : A = I (six equations, Gaussian elimination with partial pivoting),
 * into A[9]; 0 when the system is singular or A is not positive definite
 * (a pair weight could turn negative): the caller falls back to 1 / tau. */
static int tensor_normalization(const double q[15], double A[9])
{
    static const int pa[6] = {0, 1, 2, 0, 0, 1}, pb[6] = {0, 1, 2, 1, 2, 2};
    double K[6][7];
    double big = 0.0;
    for (int r = 0; r < 6; r++) {
        for (int c = 0; c < 6; c++) {
            K[r][c] = q4_at(q, pa[r], pb[r], pa[c], pb[c]) * (c < 3 ? 1.0 : 2.0);
            big = fabs(K[r][c]) > big ? fabs(K[r][c]) : big;
        }
        K[r][6] = r < 3 ? 1.0 : 0.0;
    }
    for (int c = 0; c < 6; c++) {
        int piv = c;
        for (int r = c + 1; r < 6; r++)
            if (fabs(K[r][c]) > fabs(K[piv][c])) piv = r;
        if (!(fabs(K[piv][c]) > 1e-10 * big)) return 0;
        if (piv != c)
            for (int e = 0; e < 7; e++) {
                const double t = K[c][e];
                K[c][e] = K[piv][e], K[piv][e] = t;
            }
        for (int r = c + 1; r < 6; r++) {
            const double m = K[r][c] / K[c][c];
            for (int e = c; e < 7; e++) K[r][e] -= m * K[c][e];
        }
    }
    double x[6];
    for (int r = 5; r >= 0; r--) {
        double t = K[r][6];
        for (int e = r + 1; e < 6; e++) t -= K[r][e] * x[e];
        x[r] = t / K[r][r];
    }
    A[0] = x[0], A[4] = x[1], A[8] = x[2];
    A[1] = A[3] = x[3], A[2] = A[6] = x[4], A[5] = A[7] = x[5];
    const double m2 = A[0] * A[4] - A[1] * A[1];
    const double det = A[0] * (A[4] * A[8] - A[5] * A[5]) - A[1] * (A[1] * A[8] - A[5] * A[2]) +
        A[2] * (A[1] * A[5] - A[4] * A[2]);
    return A[0] > 0.0 && m2 > 0.0 && det > 0.0;
}

/* a += scale sum_j m_j gradf r^2 / (r^2 + eps) (r^T A r / r^2) (v_i - v_j):
 * the laminar sum with each pair's weight corrected by A (normalized
 * tensor).  mj == NULL: every m_j = 1. */
static void sum_tensor(const krn_kernel *k, const uint32_t *idx, uint32_t q0, uint32_t q1,
                       const double p[3], const double v[3], const double *x, const double *y,
                       const double *z, const double *vx, const double *vy, const double *vz,
                       const double *mj, double eps_h2, double scale, const double A[9],
                       double a[3])
{
    double s[3] = {0.0, 0.0, 0.0};
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double r[3] = {p[0] - x[j], p[1] - y[j], p[2] - z[j]};
        const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        double rar = 0.0;
        for (int e = 0; e < 3; e++)
            rar += r[e] * (A[3 * e] * r[0] + A[3 * e + 1] * r[1] + A[3 * e + 2] * r[2]);
        const double c = (mj ? mj[j] : 1.0) * krn_gradf(k, sqrt(r2)) * rar / (r2 + eps_h2);
        s[0] += c * (v[0] - vx[j]);
        s[1] += c * (v[1] - vy[j]);
        s[2] += c * (v[2] - vz[j]);
    }
    for (int e = 0; e < 3; e++) a[e] += scale * s[e];
}

/* tensorLimit: the departure of tau A from I (the scalar normalization's
 * tau A) shrunk to Frobenius norm `limit` where it is larger, in place:
 * A = (I + s (tau A - I)) / tau, s = limit / |tau A - I|; 0 gives I / tau
 * (the scalar normalization), HUGE_VAL leaves A as it is. */
static void limit_tensor(double A[9], double tau, double limit)
{
    double d2 = 0.0;
    for (int e = 0; e < 9; e++) {
        const double dev = A[e] * tau - (e % 4 == 0 ? 1.0 : 0.0);
        d2 += dev * dev;
    }
    if (!(d2 > limit * limit)) return;
    const double s = limit / sqrt(d2);
    for (int e = 0; e < 9; e++) {
        const double id = e % 4 == 0 ? 1.0 : 0.0;
        A[e] = (id + s * (A[e] * tau - id)) / tau;
    }
}

/* Particle i's acceleration with normalized tensor: Q from its fluid and
 * boundary neighbours, A from Q : A = I (its departure from the scalar
 * normalization capped at `limit`, HUGE_VAL for none), the sums with the corrected
 * weights; where A is not found (or the sum is deficient, tau <= 1/2) the
 * scalar normalization's a / tau, or the plain sum. */
static void tensor_one(const krn_kernel *k, double mass, double rho0, double c, double cb,
                       const sl_fluid *f, const sl_boundary *b, const nbr_list *ff,
                       const nbr_list *fb, size_t i, double eps_h2, double limit, double a[3])
{
    const double pi[3] = {f->x[i], f->y[i], f->z[i]}, vi[3] = {f->vx[i], f->vy[i], f->vz[i]};
    const double vf = mass / rho0, irho0 = 1.0 / rho0;
    double q[15] = {0};
    for (uint32_t e = ff->start[i]; e < ff->start[i + 1]; e++) {
        const uint32_t j = ff->idx[e];
        const double dx = pi[0] - f->x[j], dy = pi[1] - f->y[j], dz = pi[2] - f->z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        q4_add(q, -vf * krn_gradf(k, sqrt(r2)) * r2 / (r2 + eps_h2), dx, dy, dz);
    }
    for (uint32_t e = fb->start[i]; e < fb->start[i + 1]; e++) {
        const uint32_t j = fb->idx[e];
        const double dx = pi[0] - b->x[j], dy = pi[1] - b->y[j], dz = pi[2] - b->z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        q4_add(q, -b->mass[j] * irho0 * krn_gradf(k, sqrt(r2)) * r2 / (r2 + eps_h2), dx, dy, dz);
    }
    /* tau = tr(M) / 3, M_ab = sum_c Q_abcc */
    double tau = 0.0;
    for (int d = 0; d < 3; d++)
        for (int e = 0; e < 3; e++) tau += q4_at(q, d, d, e, e);
    tau /= 3.0;
    double A[9];
    if (!(tau > 0.5) || !tensor_normalization(q, A)) {
        const double g = tau > 0.5 ? 1.0 / tau : 1.0;
        A[0] = A[4] = A[8] = g;
        A[1] = A[2] = A[3] = A[5] = A[6] = A[7] = 0.0;
    } else {
        limit_tensor(A, tau, limit);
    }
    sum_tensor(k, ff->idx, ff->start[i], ff->start[i + 1], pi, vi, f->x, f->y, f->z, f->vx, f->vy,
               f->vz, NULL, eps_h2, mass * c, A, a);
    if (cb > 0.0)
        sum_tensor(k, fb->idx, fb->start[i], fb->start[i + 1], pi, vi, b->x, b->y, b->z, b->vx,
                   b->vy, b->vz, b->mass, eps_h2, cb, A, a);
}

void lvisc_apply(const lvisc_params *p, const krn_kernel *k, double mass, double rho0, sl_fluid *f,
                 const sl_boundary *b, const nbr_list *ff, const nbr_list *fb, size_t i0, size_t i1)
{
    const double c = 2.0 * p->nu / rho0, cb = 2.0 * p->nu_boundary / rho0;
    const double eps_h2 = 0.01 * k->h * k->h;
    const krn_kernel kk = *k;
    if (p->normalized == LVISC_TENSOR) {
#pragma omp parallel for schedule(dynamic, 512)
        for (size_t i = i0; i < i1; i++) {
            double a[3] = {0.0, 0.0, 0.0};
            tensor_one(&kk, mass, rho0, c, cb, f, b, ff, fb, i, eps_h2, p->tensor_limit, a);
            f->ax[i] += a[0];
            f->ay[i] += a[1];
            f->az[i] += a[2];
        }
        return;
    }
#pragma omp parallel for schedule(dynamic, 512)
    for (size_t i = i0; i < i1; i++) {
        const double pi[3] = {f->x[i], f->y[i], f->z[i]}, vi[3] = {f->vx[i], f->vy[i], f->vz[i]};
        double a[3] = {0.0, 0.0, 0.0};
        sph_sum_laminar(kk, ff->idx, ff->start[i], ff->start[i + 1], pi, vi, f->x, f->y, f->z,
                        f->vx, f->vy, f->vz, NULL, eps_h2, mass * c, a);
        if (cb > 0.0)
            sph_sum_laminar(kk, fb->idx, fb->start[i], fb->start[i + 1], pi, vi, b->x, b->y, b->z,
                            b->vx, b->vy, b->vz, b->mass, eps_h2, cb, a);
        if (p->normalized) { /* a deficient sum (tau <= 1/2) is left as it is */
            const double tau = second_moment(&kk, mass / rho0, 1.0 / rho0, f, b, ff, fb, i, eps_h2);
            if (tau > 0.5)
                for (int e = 0; e < 3; e++) a[e] /= tau;
        }
        f->ax[i] += a[0];
        f->ay[i] += a[1];
        f->az[i] += a[2];
    }
}

static const char *const keys[] = {"nu", "boundaryNu", "normalized", "tensorLimit", NULL};

static void *read(const dict *d, const eff_setup *su)
{
    (void)su;
    sl_err err;
    const dict *v = dict_sub(d, "laminarViscosity");
    if (!v)
        dict_fatal(d, "laminarViscosity",
                   "must be a dictionary { nu ..; [boundaryNu ..;] [normalized on | tensor;] }");
    dict_warn_unknown(v, keys);
    lvisc_params q; /* read and checked before it is allocated: a refusal leaks nothing */
    dict_need(dict_get_scalar(v, "nu", &q.nu, &err), &err);
    if (!(q.nu >= 0.0)) dict_fatal(v, "nu", "must be zero or positive");
    dict_need(dict_get_scalar_or(v, "boundaryNu", q.nu, &q.nu_boundary, &err), &err);
    if (!(q.nu_boundary >= 0.0)) dict_fatal(v, "boundaryNu", "must be zero or positive");
    const char *w;
    dict_need(dict_get_word_or(v, "normalized", "off", &w, &err), &err);
    if (!strcmp(w, "tensor")) q.normalized = LVISC_TENSOR;
    else if (dict_get_bool_or(v, "normalized", 0, &q.normalized, &err))
        dict_fatal(v, "normalized",
                   "must be off, on (the sum over the scalar second moment) or tensor (each "
                   "pair's weight corrected by the fourth moment), not '%s'",
                   w);
    q.tensor_limit = HUGE_VAL;
    const char *lim;
    if (dict_has(v, "tensorLimit") &&
        (dict_get_word(v, "tensorLimit", &lim, &err) ||
         strcmp(lim, "none"))) { /* none: the default */
        if (q.normalized != LVISC_TENSOR)
            dict_fatal(v, "tensorLimit", "applies to normalized tensor only (normalized is '%s')",
                       w);
        dict_need(dict_get_scalar(v, "tensorLimit", &q.tensor_limit, &err), &err);
        if (!(q.tensor_limit >= 0.0))
            dict_fatal(v, "tensorLimit",
                       "must be none, zero (the scalar normalization) or positive (the "
                       "largest departure |tau A - I| of the tensor from the scalar "
                       "normalization)");
    }
    lvisc_params *p = sl_malloc(sizeof *p, "laminarViscosity");
    *p = q;
    return p;
}

static void apply(void *state, const eff_view *v)
{
    lvisc_apply(state, &v->k, v->mass, v->rho0, v->f, v->b, v->ff, v->fb, eff_rows_from(v),
                eff_rows_to(v));
}

const eff_type eff_laminar_viscosity = {
    .name = "laminarViscosity",
    .keys = keys,
    .stage = EFF_FORCES,
    .read = read,
    .apply = apply,
    .free = free,
};
