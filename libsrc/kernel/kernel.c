/* kernel: set-up of the cubic spline constants (see kernel.h). */
#include "kernel/kernel.h"

void krn_init(krn_kernel *k, double h)
{
    k->h = h;
    k->inv_h = 1.0 / h;
    k->sigma = 8.0 / (M_PI * h * h * h);
    k->gsigma = k->sigma / (h * h);
}
