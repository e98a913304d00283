/* kernel: set-up of the kernels' constants (see kernel.h). */
#include "kernel/kernel.h"

#include <string.h>

void krn_init_type(krn_kernel *k, int type, double h)
{
    k->h = h;
    k->inv_h = 1.0 / h;
    k->type = type == KRN_WENDLAND_C2 ? KRN_WENDLAND_C2 : KRN_CUBIC_SPLINE;
    k->sigma =
        k->type == KRN_WENDLAND_C2 ? 21.0 / (2.0 * M_PI * h * h * h) : 8.0 / (M_PI * h * h * h);
    k->gsigma = k->sigma / (h * h);
}

void krn_init(krn_kernel *k, double h) { krn_init_type(k, KRN_CUBIC_SPLINE, h); }

const char *krn_type_name(int type)
{
    return type == KRN_WENDLAND_C2 ? "wendlandC2" : "cubicSpline";
}

int krn_type_of(const char *name)
{
    if (!strcmp(name, "cubicSpline")) return KRN_CUBIC_SPLINE;
    if (!strcmp(name, "wendlandC2")) return KRN_WENDLAND_C2;
    return -1;
}
