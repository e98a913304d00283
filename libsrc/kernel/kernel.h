/*
 * kernel: the smoothing kernels in 3D, written with a compact support
 * radius h (W = 0 for r >= h), q = r / h.
 *
 * KRN_CUBIC_SPLINE, Monaghan 1992 (the paper's, Sec. 3.4):
 *   sigma = 8 / (pi h^3)
 *   W(q) = sigma * (6 (q^3 - q^2) + 1)   for 0 <= q <= 1/2
 *        = sigma * 2 (1 - q)^3           for 1/2 < q <= 1
 *
 * KRN_WENDLAND_C2, Wendland 1995 (DualSPHysics' default; Dehnen & Aly
 * 2012: no pairing instability at any support, so wide supports stay
 * ordered where the cubic spline's particles pair up beyond ~2.4 r0):
 *   sigma = 21 / (2 pi h^3)
 *   W(q) = sigma * (1 - q)^4 (1 + 4 q)   for 0 <= q <= 1
 *   (dW/dr) / r = -20 sigma / h^2 (1 - q)^3
 *
 * The functions are static inline and branch-free (selects, no early
 * return) so that neighbour loops vectorise; the kernel's type is a
 * select too, on a value the loops do not change (the compiler unswitches
 * the loop on it).  krn_gradf returns (dW/dr) / r, so that grad W(x_ij) =
 * krn_gradf(r) * x_ij; it is finite at r = 0 and the gradient there is the
 * zero vector.
 */
#ifndef SL_KERNEL_H
#define SL_KERNEL_H

#include <math.h>

enum { KRN_CUBIC_SPLINE = 0, KRN_WENDLAND_C2 = 1 };

typedef struct krn_kernel {
    double h; /* support radius */
    double inv_h;
    double sigma;  /* 8 / (pi h^3); Wendland C2: 21 / (2 pi h^3) */
    double gsigma; /* sigma / h^2, for the gradient */
    int type;      /* KRN_CUBIC_SPLINE or KRN_WENDLAND_C2 */
} krn_kernel;

/* The cubic spline of support h. */
void krn_init(krn_kernel *k, double h);
/* A kernel of the given type and support h. */
void krn_init_type(krn_kernel *k, int type, double h);
/* The case file's name of a type ("cubicSpline", "wendlandC2"), and the
 * type of a name (-1: none). */
const char *krn_type_name(int type);
int krn_type_of(const char *name);

/* W(r) of a kernel of the given type: always inlined, so that a loop
 * written for a constant type holds that type's formula alone (the hot
 * loops of sph_sums.h are written once and instantiated per type). */
static inline __attribute__((always_inline)) double krn_w_t(const krn_kernel *k, int type, double r)
{
    const double q = r * k->inv_h;
    if (type == KRN_WENDLAND_C2) {
        const double om = 1.0 - q, om2 = om * om;
        return q < 1.0 ? k->sigma * (om2 * om2 * (1.0 + 4.0 * q)) : 0.0;
    }
    const double a = 6.0 * (q * q * q - q * q) + 1.0;
    const double om = 1.0 - q;
    const double b = 2.0 * om * om * om;
    const double w = q <= 0.5 ? a : b;
    return q < 1.0 ? k->sigma * w : 0.0;
}

/* (dW/dr) / r.  Cubic spline: for q <= 1/2: sigma/h^2 (18 q - 12); for
 * 1/2 < q < 1: -6 sigma (1 - q)^2 / (h r).  Wendland C2: -20 sigma/h^2
 * (1 - q)^3. */
static inline __attribute__((always_inline)) double krn_gradf_t(const krn_kernel *k, int type,
                                                                double r)
{
    const double q = r * k->inv_h;
    const double om = 1.0 - q;
    if (type == KRN_WENDLAND_C2) return q < 1.0 ? -20.0 * k->gsigma * (om * om * om) : 0.0;
    const double a = k->gsigma * (18.0 * q - 12.0);
    const double qs = q > 0.5 ? q : 0.5; /* keeps the unused branch finite */
    const double b = -6.0 * k->gsigma * om * om / qs;
    const double g = q <= 0.5 ? a : b;
    return q < 1.0 ? g : 0.0;
}

static inline double krn_w(const krn_kernel *k, double r) { return krn_w_t(k, k->type, r); }
static inline double krn_gradf(const krn_kernel *k, double r) { return krn_gradf_t(k, k->type, r); }

#endif
