/*
 * assert_close: a cmocka check of |a - b| <= tol that prints both values
 * (and the tolerance) when it fails; NaN on either side fails.
 */
#ifndef SL_ASSERT_CLOSE_H
#define SL_ASSERT_CLOSE_H

#include <math.h>

#define assert_close(a, b, tol) \
    assert_close_at((double)(a), (double)(b), (double)(tol), #a, #b, __FILE__, __LINE__)

static inline void assert_close_at(double a, double b, double tol, const char *ea, const char *eb,
                                   const char *file, int line)
{
    if (fabs(a - b) <= tol) return;
    print_error("%s = %.17g\n%s = %.17g\ndiffer by %.6g, more than %.6g\n", ea, a, eb, b,
                fabs(a - b), tol);
    _fail(file, line);
}

#endif
