/* Unit tests: cubic spline kernel (normalisation, gradient, consistency)
 * and the PCISPH delta of eq. (4)-(5) against a hand-checked value. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "assert_close.h"

#include <math.h>

#include "kernel/kernel.h"
#include "solver/pcisph.h"

/* Sum of W over a fine cubic lattice times the cell volume: ~ 1. */
static void test_normalisation(void **state)
{
    (void)state;
    krn_kernel k;
    krn_init(&k, 0.1);
    const double dx = 0.1 / 25.0;
    double s = 0.0;
    for (int i = -26; i <= 26; i++)
        for (int j = -26; j <= 26; j++)
            for (int l = -26; l <= 26; l++)
                s += krn_w(&k, dx * sqrt((double)(i * i + j * j + l * l)));
    assert_close(s * dx * dx * dx, 1.0, 1e-3);
}

static void test_support_and_continuity(void **state)
{
    (void)state;
    krn_kernel k;
    krn_init(&k, 2.0);
    assert_true(krn_w(&k, 2.0) == 0.0);
    assert_true(krn_w(&k, 2.5) == 0.0);
    assert_true(krn_gradf(&k, 2.0) == 0.0);
    assert_close(krn_w(&k, 1.0 - 1e-12), krn_w(&k, 1.0 + 1e-12), 1e-9);
    assert_close(krn_w(&k, 0.0), 8.0 / (M_PI * 8.0), 1e-15);
    /* monotone decreasing */
    for (double r = 0.0; r < 2.0; r += 0.01) assert_true(krn_w(&k, r + 0.01) <= krn_w(&k, r));
}

/* gradf(r) * r equals dW/dr by central differences. */
static void test_gradient(void **state)
{
    (void)state;
    krn_kernel k;
    krn_init(&k, 1.0);
    for (double r = 0.013; r < 1.0; r += 0.0371) {
        const double e = 1e-6;
        double fd = (krn_w(&k, r + e) - krn_w(&k, r - e)) / (2 * e);
        double an = krn_gradf(&k, r) * r;
        assert_close(fd, an, 1e-6 * (1.0 + fabs(an)));
    }
}

/* First-order consistency on a lattice: sum_j V x_ij (x) grad W_ij = -I,
 * and sum_j grad W_ij = 0. */
static void test_gradient_consistency(void **state)
{
    (void)state;
    krn_kernel k;
    krn_init(&k, 1.0);
    const double dx = 1.0 / 12.0, v = dx * dx * dx;
    double m[3][3] = {{0}}, g[3] = {0};
    for (int i = -13; i <= 13; i++)
        for (int j = -13; j <= 13; j++)
            for (int l = -13; l <= 13; l++) {
                double x[3] = {i * dx, j * dx, l * dx};
                double f = krn_gradf(&k, sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]));
                for (int a = 0; a < 3; a++) {
                    g[a] += f * x[a];
                    for (int b = 0; b < 3; b++) m[a][b] += v * x[a] * f * x[b];
                }
            }
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(g[a]) < 1e-9);
        for (int b = 0; b < 3; b++) assert_close(m[a][b], (a == b ? -1.0 : 0.0), 1e-2);
    }
}

/* delta for r0 = 0.02, rho0 = 1000, dt = 1 ms: by hand, the filled lattice
 * has 6 neighbours at r0 (|grad W| = 1.4921e6), 12 at sqrt(2) r0 (5.1202e5)
 * and 8 at sqrt(3) r0 (1.0713e5): sum |grad W|^2 = 1.65953e13, beta =
 * 2 (m dt / rho0)^2 = 1.28e-16, delta = 1 / (beta sum) = 470.77. */
static void test_delta(void **state)
{
    (void)state;
    krn_kernel k;
    const double r0 = 0.02, rho0 = 1000.0, m = rho0 * r0 * r0 * r0;
    krn_init(&k, 2 * r0);
    double d = pcs_delta(&k, r0, m, rho0, 1e-3);
    assert_close(d, 470.7655, 0.01);
    /* delta scales as 1 / dt^2 */
    double d2 = pcs_delta(&k, r0, m, rho0, 2e-3);
    assert_close(d2 * 4.0, d, 1e-9 * d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normalisation), cmocka_unit_test(test_support_and_continuity),
        cmocka_unit_test(test_gradient),      cmocka_unit_test(test_gradient_consistency),
        cmocka_unit_test(test_delta),
    };
    return cmocka_run_group_tests_name("kernel", tests, NULL, NULL);
}
