/*
 * kernel: the cubic spline kernel of Monaghan 1992 (paper Sec. 3.4) in 3D,
 * written with a compact support radius h (W = 0 for r >= h):
 *
 *   q = r / h,  sigma = 8 / (pi h^3)
 *   W(q) = sigma * (6 (q^3 - q^2) + 1)   for 0 <= q <= 1/2
 *        = sigma * 2 (1 - q)^3           for 1/2 < q <= 1
 *
 * The functions are static inline and branch-free (selects, no early
 * return) so that neighbour loops vectorise.  krn_gradf returns
 * (dW/dr) / r, so that grad W(x_ij) = krn_gradf(r) * x_ij; it is finite at
 * r = 0 and the gradient there is the zero vector.
 */
#ifndef SL_KERNEL_H
#define SL_KERNEL_H

#include <math.h>

typedef struct krn_kernel {
    double h; /* support radius */
    double inv_h;
    double sigma;  /* 8 / (pi h^3) */
    double gsigma; /* sigma / h^2, for the gradient */
} krn_kernel;

void krn_init(krn_kernel *k, double h);

static inline double krn_w(const krn_kernel *k, double r)
{
    const double q = r * k->inv_h;
    const double a = 6.0 * (q * q * q - q * q) + 1.0;
    const double om = 1.0 - q;
    const double b = 2.0 * om * om * om;
    const double w = q <= 0.5 ? a : b;
    return q < 1.0 ? k->sigma * w : 0.0;
}

/* (dW/dr) / r.  For q <= 1/2: sigma/h^2 (18 q - 12); for 1/2 < q < 1:
 * -6 sigma (1 - q)^2 / (h r). */
static inline double krn_gradf(const krn_kernel *k, double r)
{
    const double q = r * k->inv_h;
    const double om = 1.0 - q;
    const double a = k->gsigma * (18.0 * q - 12.0);
    const double qs = q > 0.5 ? q : 0.5; /* keeps the unused branch finite */
    const double b = -6.0 * k->gsigma * om * om / qs;
    const double g = q <= 0.5 ? a : b;
    return q < 1.0 ? g : 0.0;
}

#endif
