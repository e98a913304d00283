/*
 * sph_sums: the neighbour loops of the solver, written once.
 *
 * Each function sums a pair term over one compressed neighbour-list row
 * [q0, q1) of indices into the target arrays.  They are static inline and
 * take restrict pointers and the kernel by value, so that the compiler
 * vectorises the loop (indexed loads become gathers): these loops are
 * where a PCISPH step spends its time.
 */
#ifndef SL_SPH_SUMS_H
#define SL_SPH_SUMS_H

#include <math.h>
#include <stdint.h>

#include "kernel/kernel.h"

/* The loops are written once, for a kernel type given as a constant, and
 * each public sum picks the loop of its kernel's type: the cubic spline's
 * loop holds its formula alone, as before the type existed. */
#define SPH__INLINE static inline __attribute__((always_inline))

#if defined(__AVX512F__)
#include <immintrin.h>
/* AVX-512: eight neighbours a vector, the row's tail under a mask (no
 * scalar remainder: rows are ~30 long), indexed loads as gathers, and 1/r
 * from the approximate reciprocal square root refined by two Newton steps
 * (a few ulp; no sqrt or division per pair).  Each row is still summed in
 * one fixed order by one thread: the same bits for any thread count. */
#define SPH_SUMS_AVX512 1

/* The lanes [q, q1) of a row, at most eight. */
static inline __mmask8 sph__lanes(uint32_t q, uint32_t q1)
{
    const uint32_t left = q1 - q;
    return left >= 8 ? (__mmask8)0xff : (__mmask8)((1u << left) - 1u);
}

/* 1 / sqrt(r2), r2 > 0 (the caller keeps r2 away from zero). */
static inline __m512d sph__rsqrt(__m512d r2)
{
    const __m512d half = _mm512_set1_pd(0.5), three_halves = _mm512_set1_pd(1.5);
    const __m512d hr2 = _mm512_mul_pd(half, r2);
    __m512d y = _mm512_rsqrt14_pd(r2);
    y = _mm512_mul_pd(y, _mm512_fnmadd_pd(_mm512_mul_pd(hr2, y), y, three_halves));
    y = _mm512_mul_pd(y, _mm512_fnmadd_pd(_mm512_mul_pd(hr2, y), y, three_halves));
    return y;
}

/* Squared distances of (px, py, pz) to the gathered lanes; d[] gets the
 * differences p - x_j. */
static inline __m512d sph__dist2(__m256i j, __mmask8 m, __m512d px, __m512d py, __m512d pz,
                                 const double *x, const double *y, const double *z, __m512d d[3])
{
    d[0] = _mm512_sub_pd(px, _mm512_mask_i32gather_pd(px, m, j, x, 8));
    d[1] = _mm512_sub_pd(py, _mm512_mask_i32gather_pd(py, m, j, y, 8));
    d[2] = _mm512_sub_pd(pz, _mm512_mask_i32gather_pd(pz, m, j, z, 8));
    return _mm512_fmadd_pd(d[2], d[2], _mm512_fmadd_pd(d[1], d[1], _mm512_mul_pd(d[0], d[0])));
}

/* W(r) of the lanes (q = r / h); zero at q >= 1. */
SPH__INLINE __m512d sph__w(const krn_kernel *k, __m512d r2, int type)
{
    const __m512d one = _mm512_set1_pd(1.0);
    const __m512d r2s = _mm512_max_pd(r2, _mm512_set1_pd(1e-300));
    const __m512d q = _mm512_mul_pd(_mm512_mul_pd(r2s, sph__rsqrt(r2s)), _mm512_set1_pd(k->inv_h));
    const __mmask8 inside = _mm512_cmp_pd_mask(q, one, _CMP_LT_OQ);
    const __m512d om = _mm512_sub_pd(one, q);
    if (type == KRN_WENDLAND_C2) { /* (1 - q)^4 (1 + 4 q) */
        const __m512d om2 = _mm512_mul_pd(om, om);
        const __m512d w =
            _mm512_mul_pd(_mm512_mul_pd(om2, om2), _mm512_fmadd_pd(_mm512_set1_pd(4.0), q, one));
        return _mm512_maskz_mul_pd(inside, w, _mm512_set1_pd(k->sigma));
    }
    const __m512d q2 = _mm512_mul_pd(q, q);
    const __m512d a = _mm512_fmadd_pd(_mm512_set1_pd(6.0), _mm512_fmsub_pd(q2, q, q2), one);
    const __m512d b = _mm512_mul_pd(_mm512_set1_pd(2.0), _mm512_mul_pd(_mm512_mul_pd(om, om), om));
    const __mmask8 inner = _mm512_cmp_pd_mask(q, _mm512_set1_pd(0.5), _CMP_LE_OQ);
    const __m512d w = _mm512_mask_blend_pd(inner, b, a);
    return _mm512_maskz_mul_pd(inside, w, _mm512_set1_pd(k->sigma));
}

/* (dW/dr) / r of the lanes; zero at q >= 1. */
SPH__INLINE __m512d sph__gradf(const krn_kernel *k, __m512d r2, int type)
{
    const __m512d one = _mm512_set1_pd(1.0);
    const __m512d r2s = _mm512_max_pd(r2, _mm512_set1_pd(1e-300));
    const __m512d rinv = sph__rsqrt(r2s);
    const __m512d q = _mm512_mul_pd(_mm512_mul_pd(r2s, rinv), _mm512_set1_pd(k->inv_h));
    const __m512d gs = _mm512_set1_pd(k->gsigma);
    if (type == KRN_WENDLAND_C2) { /* -20 gsigma (1 - q)^3 */
        const __m512d om = _mm512_sub_pd(one, q);
        const __m512d g = _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(-20.0), gs),
                                        _mm512_mul_pd(_mm512_mul_pd(om, om), om));
        return _mm512_maskz_mov_pd(_mm512_cmp_pd_mask(q, one, _CMP_LT_OQ), g);
    }
    const __m512d a =
        _mm512_mul_pd(gs, _mm512_fmsub_pd(_mm512_set1_pd(18.0), q, _mm512_set1_pd(12.0)));
    const __m512d om = _mm512_sub_pd(one, q);
    /* -6 gsigma (1 - q)^2 / q, 1 / q = h / r */
    const __m512d b = _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(-6.0 * k->gsigma * k->h), rinv),
                                    _mm512_mul_pd(om, om));
    const __mmask8 inner = _mm512_cmp_pd_mask(q, _mm512_set1_pd(0.5), _CMP_LE_OQ);
    const __mmask8 inside = _mm512_cmp_pd_mask(q, one, _CMP_LT_OQ);
    return _mm512_maskz_mov_pd(inside, _mm512_mask_blend_pd(inner, b, a));
}

static inline __m256i sph__idx(const uint32_t *idx, uint32_t q, __mmask8 m)
{
    return _mm256_maskz_loadu_epi32(m, idx + q);
}
#else
#define SPH_SUMS_AVX512 0 /* the scalar loops */
#endif

/* sum_j W(|p - x_j|) */
SPH__INLINE double sph__sum_w(int type, const krn_kernel k, const uint32_t *restrict idx,
                              uint32_t q0, uint32_t q1, double px, double py, double pz,
                              const double *restrict x, const double *restrict y,
                              const double *restrict z)
{
#if SPH_SUMS_AVX512
    const __m512d vx = _mm512_set1_pd(px), vy = _mm512_set1_pd(py), vz = _mm512_set1_pd(pz);
    __m512d acc = _mm512_setzero_pd(), d[3];
    for (uint32_t q = q0; q < q1; q += 8) {
        const __mmask8 m = sph__lanes(q, q1);
        const __m512d r2 = sph__dist2(sph__idx(idx, q, m), m, vx, vy, vz, x, y, z, d);
        acc = _mm512_mask_add_pd(acc, m, acc, sph__w(&k, r2, type));
    }
    return _mm512_reduce_add_pd(acc);
#else
    double s = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        s += krn_w_t(&k, type, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return s;
#endif
}

static inline double sph_sum_w(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                               uint32_t q1, double px, double py, double pz,
                               const double *restrict x, const double *restrict y,
                               const double *restrict z)
{
    return k.type == KRN_WENDLAND_C2
        ? sph__sum_w(KRN_WENDLAND_C2, k, idx, q0, q1, px, py, pz, x, y, z)
        : sph__sum_w(KRN_CUBIC_SPLINE, k, idx, q0, q1, px, py, pz, x, y, z);
}

/* sum_j m_j W(|p - x_j|) */
SPH__INLINE double sph__sum_mw(int type, const krn_kernel k, const uint32_t *restrict idx,
                               uint32_t q0, uint32_t q1, double px, double py, double pz,
                               const double *restrict x, const double *restrict y,
                               const double *restrict z, const double *restrict m)
{
#if SPH_SUMS_AVX512
    const __m512d vx = _mm512_set1_pd(px), vy = _mm512_set1_pd(py), vz = _mm512_set1_pd(pz);
    __m512d acc = _mm512_setzero_pd(), d[3];
    for (uint32_t q = q0; q < q1; q += 8) {
        const __mmask8 l = sph__lanes(q, q1);
        const __m256i j = sph__idx(idx, q, l);
        const __m512d r2 = sph__dist2(j, l, vx, vy, vz, x, y, z, d);
        const __m512d mj = _mm512_mask_i32gather_pd(_mm512_setzero_pd(), l, j, m, 8);
        acc = _mm512_fmadd_pd(mj, sph__w(&k, r2, type), acc); /* mj = 0 off the row */
    }
    return _mm512_reduce_add_pd(acc);
#else
    double s = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        s += m[j] * krn_w_t(&k, type, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return s;
#endif
}

static inline double sph_sum_mw(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                uint32_t q1, double px, double py, double pz,
                                const double *restrict x, const double *restrict y,
                                const double *restrict z, const double *restrict m)
{
    return k.type == KRN_WENDLAND_C2
        ? sph__sum_mw(KRN_WENDLAND_C2, k, idx, q0, q1, px, py, pz, x, y, z, m)
        : sph__sum_mw(KRN_CUBIC_SPLINE, k, idx, q0, q1, px, py, pz, x, y, z, m);
}

/* sum_j W(|p - x_j|) / rho_j: with the mass, the Shepard sum of volumes */
SPH__INLINE double sph__sum_w_over(int type, const krn_kernel k, const uint32_t *restrict idx,
                                   uint32_t q0, uint32_t q1, double px, double py, double pz,
                                   const double *restrict x, const double *restrict y,
                                   const double *restrict z, const double *restrict rho)
{
    double s = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        s += krn_w_t(&k, type, sqrt(dx * dx + dy * dy + dz * dz)) / rho[j];
    }
    return s;
}

static inline double sph_sum_w_over(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                    uint32_t q1, double px, double py, double pz,
                                    const double *restrict x, const double *restrict y,
                                    const double *restrict z, const double *restrict rho)
{
    return k.type == KRN_WENDLAND_C2
        ? sph__sum_w_over(KRN_WENDLAND_C2, k, idx, q0, q1, px, py, pz, x, y, z, rho)
        : sph__sum_w_over(KRN_CUBIC_SPLINE, k, idx, q0, q1, px, py, pz, x, y, z, rho);
}

/* a += -sum_j m_j (pi + pt_j) grad W(p - x_j): the symmetric pressure
 * force of eq. (6) per unit mass, with pt = p / rho^2.  mj == NULL means
 * every m_j = mconst. */
SPH__INLINE void sph__sum_pressure(int type, const krn_kernel k, const uint32_t *restrict idx,
                                   uint32_t q0, uint32_t q1, double px, double py, double pz,
                                   double pi, const double *restrict x, const double *restrict y,
                                   const double *restrict z, const double *restrict pt,
                                   const double *restrict mj, double mconst, double a[3])
{
#if SPH_SUMS_AVX512
    const __m512d vx = _mm512_set1_pd(px), vy = _mm512_set1_pd(py), vz = _mm512_set1_pd(pz);
    const __m512d vpi = _mm512_set1_pd(pi);
    __m512d sx = _mm512_setzero_pd(), sy = sx, sz = sx, d[3];
    for (uint32_t q = q0; q < q1; q += 8) {
        const __mmask8 l = sph__lanes(q, q1);
        const __m256i j = sph__idx(idx, q, l);
        const __m512d r2 = sph__dist2(j, l, vx, vy, vz, x, y, z, d);
        __m512d c = _mm512_mul_pd(_mm512_add_pd(vpi, _mm512_mask_i32gather_pd(vpi, l, j, pt, 8)),
                                  sph__gradf(&k, r2, type));
        if (mj) c = _mm512_mul_pd(c, _mm512_mask_i32gather_pd(_mm512_setzero_pd(), l, j, mj, 8));
        sx = _mm512_mask3_fmadd_pd(c, d[0], sx, l);
        sy = _mm512_mask3_fmadd_pd(c, d[1], sy, l);
        sz = _mm512_mask3_fmadd_pd(c, d[2], sz, l);
    }
    const double scale = mj ? 1.0 : mconst;
    a[0] -= scale * _mm512_reduce_add_pd(sx);
    a[1] -= scale * _mm512_reduce_add_pd(sy);
    a[2] -= scale * _mm512_reduce_add_pd(sz);
#else
    double ax = 0.0, ay = 0.0, az = 0.0;
    if (mj) {
        for (uint32_t q = q0; q < q1; q++) {
            const uint32_t j = idx[q];
            const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
            const double c =
                mj[j] * (pi + pt[j]) * krn_gradf_t(&k, type, sqrt(dx * dx + dy * dy + dz * dz));
            ax -= c * dx;
            ay -= c * dy;
            az -= c * dz;
        }
    } else {
        for (uint32_t q = q0; q < q1; q++) {
            const uint32_t j = idx[q];
            const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
            const double c =
                (pi + pt[j]) * krn_gradf_t(&k, type, sqrt(dx * dx + dy * dy + dz * dz));
            ax -= c * dx;
            ay -= c * dy;
            az -= c * dz;
        }
        ax *= mconst;
        ay *= mconst;
        az *= mconst;
    }
    a[0] += ax;
    a[1] += ay;
    a[2] += az;
#endif
}

static inline void sph_sum_pressure(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                    uint32_t q1, double px, double py, double pz, double pi,
                                    const double *restrict x, const double *restrict y,
                                    const double *restrict z, const double *restrict pt,
                                    const double *restrict mj, double mconst, double a[3])
{
    if (k.type == KRN_WENDLAND_C2)
        sph__sum_pressure(KRN_WENDLAND_C2, k, idx, q0, q1, px, py, pz, pi, x, y, z, pt, mj, mconst,
                          a);
    else
        sph__sum_pressure(KRN_CUBIC_SPLINE, k, idx, q0, q1, px, py, pz, pi, x, y, z, pt, mj, mconst,
                          a);
}

/* The pairs' terms f_j = -(pi + pt_j) grad W(p - x_j) of eq. (6) (per unit
 * mass of the neighbours): s += sum_j f_j and t += sum_j L_j f_j, L_j the
 * 3 x 3 matrix at L + 9 j, row-major (pressureForce correctedConservative,
 * solver/pcisph.c: each pair's term times (L_i + L_j) / 2). */
SPH__INLINE void sph__sum_pressure_pairs(int type, const krn_kernel k, const uint32_t *restrict idx,
                                         uint32_t q0, uint32_t q1, double px, double py, double pz,
                                         double pi, const double *restrict x,
                                         const double *restrict y, const double *restrict z,
                                         const double *restrict pt, const double *restrict L,
                                         double s[3], double t[3])
{
#if SPH_SUMS_AVX512
    const __m512d vx = _mm512_set1_pd(px), vy = _mm512_set1_pd(py), vz = _mm512_set1_pd(pz);
    const __m512d vpi = _mm512_set1_pd(pi), zero = _mm512_setzero_pd();
    const __m256i nine = _mm256_set1_epi32(9);
    __m512d sx = zero, sy = zero, sz = zero, tx = zero, ty = zero, tz = zero, d[3];
    for (uint32_t q = q0; q < q1; q += 8) {
        const __mmask8 l = sph__lanes(q, q1);
        const __m256i j = sph__idx(idx, q, l);
        const __m512d r2 = sph__dist2(j, l, vx, vy, vz, x, y, z, d);
        const __m512d c =
            _mm512_mul_pd(_mm512_add_pd(vpi, _mm512_mask_i32gather_pd(vpi, l, j, pt, 8)),
                          sph__gradf(&k, r2, type));
        const __m512d fx = _mm512_maskz_mul_pd(l, c, d[0]), fy = _mm512_maskz_mul_pd(l, c, d[1]);
        const __m512d fz = _mm512_maskz_mul_pd(l, c, d[2]);
        sx = _mm512_add_pd(sx, fx);
        sy = _mm512_add_pd(sy, fy);
        sz = _mm512_add_pd(sz, fz);
        const __m256i j9 = _mm256_mullo_epi32(j, nine);
        __m512d m[9];
        for (int e = 0; e < 9; e++)
            m[e] =
                _mm512_mask_i32gather_pd(zero, l, _mm256_add_epi32(j9, _mm256_set1_epi32(e)), L, 8);
        tx = _mm512_fmadd_pd(m[0], fx, _mm512_fmadd_pd(m[1], fy, _mm512_fmadd_pd(m[2], fz, tx)));
        ty = _mm512_fmadd_pd(m[3], fx, _mm512_fmadd_pd(m[4], fy, _mm512_fmadd_pd(m[5], fz, ty)));
        tz = _mm512_fmadd_pd(m[6], fx, _mm512_fmadd_pd(m[7], fy, _mm512_fmadd_pd(m[8], fz, tz)));
    }
    s[0] -= _mm512_reduce_add_pd(sx);
    s[1] -= _mm512_reduce_add_pd(sy);
    s[2] -= _mm512_reduce_add_pd(sz);
    t[0] -= _mm512_reduce_add_pd(tx);
    t[1] -= _mm512_reduce_add_pd(ty);
    t[2] -= _mm512_reduce_add_pd(tz);
#else
    double sx = 0.0, sy = 0.0, sz = 0.0, tx = 0.0, ty = 0.0, tz = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = px - x[j], dy = py - y[j], dz = pz - z[j];
        const double c = (pi + pt[j]) * krn_gradf_t(&k, type, sqrt(dx * dx + dy * dy + dz * dz));
        const double fx = c * dx, fy = c * dy, fz = c * dz;
        const double *Lj = L + 9 * (size_t)j;
        sx += fx, sy += fy, sz += fz;
        tx += Lj[0] * fx + Lj[1] * fy + Lj[2] * fz;
        ty += Lj[3] * fx + Lj[4] * fy + Lj[5] * fz;
        tz += Lj[6] * fx + Lj[7] * fy + Lj[8] * fz;
    }
    s[0] -= sx, s[1] -= sy, s[2] -= sz;
    t[0] -= tx, t[1] -= ty, t[2] -= tz;
#endif
}

static inline void sph_sum_pressure_pairs(const krn_kernel k, const uint32_t *restrict idx,
                                          uint32_t q0, uint32_t q1, double px, double py, double pz,
                                          double pi, const double *restrict x,
                                          const double *restrict y, const double *restrict z,
                                          const double *restrict pt, const double *restrict L,
                                          double s[3], double t[3])
{
    if (k.type == KRN_WENDLAND_C2)
        sph__sum_pressure_pairs(KRN_WENDLAND_C2, k, idx, q0, q1, px, py, pz, pi, x, y, z, pt, L, s,
                                t);
    else
        sph__sum_pressure_pairs(KRN_CUBIC_SPLINE, k, idx, q0, q1, px, py, pz, pi, x, y, z, pt, L, s,
                                t);
}

/* a += scale sum_j m_j Pi'_ij gradf(r_ij) x_ij, Pi'_ij = (v_ij . x_ij) /
 * (r_ij^2 + eps_h2) for approaching pairs (v_ij . x_ij < 0), else 0: the
 * artificial viscosity's sum (effects/viscosity.h), v_ij = v - v_j.
 * mj == NULL means every m_j = 1. */
SPH__INLINE void sph__sum_viscosity(int type, const krn_kernel k, const uint32_t *restrict idx,
                                    uint32_t q0, uint32_t q1, const double p[3], const double v[3],
                                    const double *restrict x, const double *restrict y,
                                    const double *restrict z, const double *restrict vx,
                                    const double *restrict vy, const double *restrict vz,
                                    const double *restrict mj, double eps_h2, double scale,
                                    double a[3])
{
#if SPH_SUMS_AVX512
    const __m512d px = _mm512_set1_pd(p[0]), py = _mm512_set1_pd(p[1]), pz = _mm512_set1_pd(p[2]);
    const __m512d ux = _mm512_set1_pd(v[0]), uy = _mm512_set1_pd(v[1]), uz = _mm512_set1_pd(v[2]);
    const __m512d eps = _mm512_set1_pd(eps_h2), zero = _mm512_setzero_pd();
    __m512d sx = zero, sy = zero, sz = zero, d[3];
    for (uint32_t q = q0; q < q1; q += 8) {
        const __mmask8 l = sph__lanes(q, q1);
        const __m256i j = sph__idx(idx, q, l);
        const __m512d r2 = sph__dist2(j, l, px, py, pz, x, y, z, d);
        const __m512d wx = _mm512_sub_pd(ux, _mm512_mask_i32gather_pd(ux, l, j, vx, 8));
        const __m512d wy = _mm512_sub_pd(uy, _mm512_mask_i32gather_pd(uy, l, j, vy, 8));
        const __m512d wz = _mm512_sub_pd(uz, _mm512_mask_i32gather_pd(uz, l, j, vz, 8));
        const __m512d vr =
            _mm512_fmadd_pd(wz, d[2], _mm512_fmadd_pd(wy, d[1], _mm512_mul_pd(wx, d[0])));
        const __mmask8 on = _mm512_mask_cmp_pd_mask(l, vr, zero, _CMP_LT_OQ);
        __m512d c =
            _mm512_mul_pd(_mm512_div_pd(vr, _mm512_add_pd(r2, eps)), sph__gradf(&k, r2, type));
        if (mj) c = _mm512_mul_pd(c, _mm512_mask_i32gather_pd(zero, l, j, mj, 8));
        sx = _mm512_mask3_fmadd_pd(c, d[0], sx, on);
        sy = _mm512_mask3_fmadd_pd(c, d[1], sy, on);
        sz = _mm512_mask3_fmadd_pd(c, d[2], sz, on);
    }
    a[0] += scale * _mm512_reduce_add_pd(sx);
    a[1] += scale * _mm512_reduce_add_pd(sy);
    a[2] += scale * _mm512_reduce_add_pd(sz);
#else
    double ax = 0.0, ay = 0.0, az = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = p[0] - x[j], dy = p[1] - y[j], dz = p[2] - z[j];
        const double vr = (v[0] - vx[j]) * dx + (v[1] - vy[j]) * dy + (v[2] - vz[j]) * dz;
        const double r2 = dx * dx + dy * dy + dz * dz;
        const double pr = vr < 0.0 ? vr / (r2 + eps_h2) : 0.0;
        const double c = (mj ? mj[j] : 1.0) * pr * krn_gradf_t(&k, type, sqrt(r2));
        ax += c * dx;
        ay += c * dy;
        az += c * dz;
    }
    a[0] += scale * ax;
    a[1] += scale * ay;
    a[2] += scale * az;
#endif
}

static inline void sph_sum_viscosity(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                     uint32_t q1, const double p[3], const double v[3],
                                     const double *restrict x, const double *restrict y,
                                     const double *restrict z, const double *restrict vx,
                                     const double *restrict vy, const double *restrict vz,
                                     const double *restrict mj, double eps_h2, double scale,
                                     double a[3])
{
    if (k.type == KRN_WENDLAND_C2)
        sph__sum_viscosity(KRN_WENDLAND_C2, k, idx, q0, q1, p, v, x, y, z, vx, vy, vz, mj, eps_h2,
                           scale, a);
    else
        sph__sum_viscosity(KRN_CUBIC_SPLINE, k, idx, q0, q1, p, v, x, y, z, vx, vy, vz, mj, eps_h2,
                           scale, a);
}

/* a += scale sum_j m_j gradf(r_ij) r_ij^2 / (r_ij^2 + eps_h2) (v - v_j): the
 * laminar viscosity's sum (Morris et al. 1997, effects/laminar_viscosity.h),
 * every pair.  mj == NULL means every m_j = 1. */
SPH__INLINE void sph__sum_laminar(int type, const krn_kernel k, const uint32_t *restrict idx,
                                  uint32_t q0, uint32_t q1, const double p[3], const double v[3],
                                  const double *restrict x, const double *restrict y,
                                  const double *restrict z, const double *restrict vx,
                                  const double *restrict vy, const double *restrict vz,
                                  const double *restrict mj, double eps_h2, double scale,
                                  double a[3])
{
    double ax = 0.0, ay = 0.0, az = 0.0;
    for (uint32_t q = q0; q < q1; q++) {
        const uint32_t j = idx[q];
        const double dx = p[0] - x[j], dy = p[1] - y[j], dz = p[2] - z[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        const double c = (mj ? mj[j] : 1.0) * krn_gradf_t(&k, type, sqrt(r2)) * r2 / (r2 + eps_h2);
        ax += c * (v[0] - vx[j]);
        ay += c * (v[1] - vy[j]);
        az += c * (v[2] - vz[j]);
    }
    a[0] += scale * ax;
    a[1] += scale * ay;
    a[2] += scale * az;
}

static inline void sph_sum_laminar(const krn_kernel k, const uint32_t *restrict idx, uint32_t q0,
                                   uint32_t q1, const double p[3], const double v[3],
                                   const double *restrict x, const double *restrict y,
                                   const double *restrict z, const double *restrict vx,
                                   const double *restrict vy, const double *restrict vz,
                                   const double *restrict mj, double eps_h2, double scale,
                                   double a[3])
{
    if (k.type == KRN_WENDLAND_C2)
        sph__sum_laminar(KRN_WENDLAND_C2, k, idx, q0, q1, p, v, x, y, z, vx, vy, vz, mj, eps_h2,
                         scale, a);
    else
        sph__sum_laminar(KRN_CUBIC_SPLINE, k, idx, q0, q1, p, v, x, y, z, vx, vy, vz, mj, eps_h2,
                         scale, a);
}

#endif
