/* sl_reduce: deterministic parallel sums (see sl_reduce.h). */
#include "core/sl_reduce.h"

#include <math.h>

double sl_sum(const double *a, size_t n)
{
    size_t nb = (n + SL_REDUCE_BLOCK - 1) / SL_REDUCE_BLOCK;
    double total = 0.0;
    /* Block sums live on the stack in chunks to avoid allocation. */
    enum { CHUNK = 256 };
    double part[CHUNK];
    for (size_t b0 = 0; b0 < nb; b0 += CHUNK) {
        size_t b1 = b0 + CHUNK < nb ? b0 + CHUNK : nb;
#pragma omp parallel for schedule(static)
        for (size_t b = b0; b < b1; b++) {
            size_t lo = b * SL_REDUCE_BLOCK,
                   hi = lo + SL_REDUCE_BLOCK < n ? lo + SL_REDUCE_BLOCK : n;
            double s = 0.0;
            for (size_t i = lo; i < hi; i++) s += a[i];
            part[b - b0] = s;
        }
        for (size_t b = b0; b < b1; b++) total += part[b - b0];
    }
    return total;
}

double sl_max(const double *a, size_t n)
{
    double m = -INFINITY;
#pragma omp parallel for schedule(static) reduction(max : m)
    for (size_t i = 0; i < n; i++)
        if (a[i] > m) m = a[i];
    return m;
}
