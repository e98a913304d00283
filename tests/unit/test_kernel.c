/* Unit tests: the cubic spline and Wendland C2 kernels (normalisation,
 * support, gradient, consistency), the neighbour sums of sph_sums.h
 * against the kernels pair by pair, and the PCISPH delta of eq. (4)-(5)
 * against a hand-checked value. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "assert_close.h"

#include <math.h>

#include "kernel/kernel.h"
#include "kernel/sph_sums.h"
#include "solver/pcisph.h"

/* Sum of W over a fine cubic lattice (25 cells per support radius h)
 * times the cell volume: the kernel's integral. */
static double lattice_integral(const krn_kernel *k)
{
    const double dx = k->h / 25.0;
    double s = 0.0;
    for (int i = -26; i <= 26; i++)
        for (int j = -26; j <= 26; j++)
            for (int l = -26; l <= 26; l++)
                s += krn_w(k, dx * sqrt((double)(i * i + j * j + l * l)));
    return s * dx * dx * dx;
}

static void test_normalisation(void **state)
{
    (void)state;
    krn_kernel k;
    krn_init(&k, 0.1);
    assert_close(lattice_integral(&k), 1.0, 1e-3);
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

/* Why the warm-started pressure sources need pressureSource's relaxation
 * at 2.4 r0 (doc/verification.md, "The mixed source: a period that
 * does not move with the step"): on the cubic lattice delta lambda_max is 1.41 at 2 r0, 1.65
 * at 2.2 r0 and 1.97 at 2.4 r0 (at k r0 about 0.9 along the diagonal); 2 %
 * closer, 1.61 at 2 r0 and 2.22 at 2.4 r0, where the update grows its
 * largest modes (by 1.22 an iteration); Wendland C2 at 2.2 r0 1.52, 1.72.
 * Measured by a python sum; tolerances 0.03. */
static void test_delta_largest_mode(void **state)
{
    (void)state;
    const double c20 = pcs_delta_lambda_max(KRN_CUBIC_SPLINE, 2.0, 1.0),
                 c24 = pcs_delta_lambda_max(KRN_CUBIC_SPLINE, 2.4, 1.0),
                 c20c = pcs_delta_lambda_max(KRN_CUBIC_SPLINE, 2.0, 0.98),
                 c24c = pcs_delta_lambda_max(KRN_CUBIC_SPLINE, 2.4, 0.98),
                 w22 = pcs_delta_lambda_max(KRN_WENDLAND_C2, 2.2, 1.0),
                 w22c = pcs_delta_lambda_max(KRN_WENDLAND_C2, 2.2, 0.98);
    print_message("delta lambda_max: cubic 2 r0 %.3f (2 %% closer %.3f), 2.4 r0 %.3f (%.3f); "
                  "Wendland C2 2.2 r0 %.3f (%.3f)\n",
                  c20, c20c, c24, c24c, w22, w22c);
    assert_close(c20, 1.41, 0.03);
    assert_close(c24, 1.97, 0.03);
    assert_close(c20c, 1.61, 0.03);
    assert_close(c24c, 2.22, 0.03);
    assert_close(w22, 1.52, 0.03);
    assert_true(c24c > 2.0 && c20c < 2.0 && w22c < 2.0);
    /* relaxation 0.5 brings every one of them below 2 */
    assert_true(0.5 * c24c < 2.0);
}

/* The pressure gradient's zeroth moment on the cubic lattice, sum_j V_j
 * x_ij . grad W_ij / 3 with V_j = m / rho0 = 1 / sum_j W_ij (the solver's
 * mass: the lattice's summation density is rho0), exact -1: the share of
 * gravity that the symmetric pressure force of a linear pressure field
 * holds.  Its deficit is a support-sized error that does not fall with r0
 * (doc/verification.md, "Wendland C2 on the hydrostatic tank"): the
 * hydrostatic pressure is 1 / |moment| too steep.  Measured by a python
 * sum: cubic spline -1.0201 (2 r0), -1.0016 (2.2 r0), -0.9809 (2.4 r0);
 * Wendland C2 -0.9774 (2.2 r0), -0.9975 (3 r0).  Tolerance 2e-4. */
static double lattice_gradient_moment(int type, double support)
{
    krn_kernel k;
    krn_init_type(&k, type, support);
    const int reach = (int)ceil(support) + 1;
    double sw = 0.0, sm = 0.0;
    for (int i = -reach; i <= reach; i++)
        for (int j = -reach; j <= reach; j++)
            for (int l = -reach; l <= reach; l++) {
                const double r2 = (double)(i * i + j * j + l * l), r = sqrt(r2);
                sw += krn_w(&k, r);
                sm += krn_gradf(&k, r) * r2; /* x . grad W = (dW/dr / r) r^2 */
            }
    return sm / 3.0 / sw;
}

static void test_lattice_gradient_moment(void **state)
{
    (void)state;
    const double c20 = lattice_gradient_moment(KRN_CUBIC_SPLINE, 2.0),
                 c22 = lattice_gradient_moment(KRN_CUBIC_SPLINE, 2.2),
                 c24 = lattice_gradient_moment(KRN_CUBIC_SPLINE, 2.4),
                 w22 = lattice_gradient_moment(KRN_WENDLAND_C2, 2.2),
                 w30 = lattice_gradient_moment(KRN_WENDLAND_C2, 3.0);
    print_message("gradient moment: cubic %.4f %.4f %.4f (2, 2.2, 2.4 r0), Wendland C2 %.4f %.4f "
                  "(2.2, 3 r0)\n",
                  c20, c22, c24, w22, w30);
    assert_close(c20, -1.0201, 2e-4);
    assert_close(c22, -1.0016, 2e-4);
    assert_close(c24, -0.9809, 2e-4);
    assert_close(w22, -0.9774, 2e-4);
    assert_close(w30, -0.9975, 2e-4);
}

/* Wendland C2: unit integral (a fine lattice), zero at and beyond the
 * support, W(0) = 21 / (2 pi h^3), monotone, smooth at the support. */
static void test_wendland_normalisation_and_support(void **state)
{
    (void)state;
    krn_kernel k;
    krn_init_type(&k, KRN_WENDLAND_C2, 0.1);
    assert_int_equal(k.type, KRN_WENDLAND_C2);
    assert_close(lattice_integral(&k), 1.0, 1e-3);
    krn_init_type(&k, KRN_WENDLAND_C2, 2.0);
    assert_true(krn_w(&k, 2.0) == 0.0);
    assert_true(krn_w(&k, 2.5) == 0.0);
    assert_true(krn_gradf(&k, 2.0) == 0.0);
    assert_true(krn_gradf(&k, 3.0) == 0.0);
    assert_close(krn_w(&k, 0.0), 21.0 / (2.0 * M_PI * 8.0), 1e-15);
    for (double r = 0.0; r < 2.0; r += 0.01) assert_true(krn_w(&k, r + 0.01) <= krn_w(&k, r));
    /* C2 at the support: W ~ (1 - q)^4 */
    assert_true(krn_w(&k, 2.0 - 1e-3) < 1e-12);
    assert_string_equal(krn_type_name(KRN_WENDLAND_C2), "wendlandC2");
    assert_int_equal(krn_type_of("wendlandC2"), KRN_WENDLAND_C2);
    assert_int_equal(krn_type_of("cubicSpline"), KRN_CUBIC_SPLINE);
    assert_int_equal(krn_type_of("gaussian"), -1);
}

/* Wendland C2: gradf(r) r = dW/dr by central differences, and the
 * lattice's first-order consistency. */
static void test_wendland_gradient(void **state)
{
    (void)state;
    krn_kernel k;
    krn_init_type(&k, KRN_WENDLAND_C2, 1.0);
    for (double r = 0.013; r < 1.0; r += 0.0371) {
        const double e = 1e-6;
        double fd = (krn_w(&k, r + e) - krn_w(&k, r - e)) / (2 * e);
        double an = krn_gradf(&k, r) * r;
        assert_close(fd, an, 1e-6 * (1.0 + fabs(an)));
    }
    const double dx = 1.0 / 12.0, v = dx * dx * dx;
    double m[3][3] = {{0}};
    for (int i = -13; i <= 13; i++)
        for (int j = -13; j <= 13; j++)
            for (int l = -13; l <= 13; l++) {
                double x[3] = {i * dx, j * dx, l * dx};
                double f = krn_gradf(&k, sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]));
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++) m[a][b] += v * x[a] * f * x[b];
            }
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) assert_close(m[a][b], (a == b ? -1.0 : 0.0), 1e-2);
}

/* The neighbour sums (vectorised where the machine has AVX-512, a few ulp
 * from the approximate reciprocal square root) equal the kernels' pair
 * terms summed one by one, for both kernel types. */
static void test_sums_follow_the_kernel(void **state)
{
    (void)state;
    enum { N = 37 };
    double x[N], y[N], z[N], m[N], pt[N], vx[N], vy[N], vz[N];
    uint32_t idx[N];
    for (int j = 0; j < N; j++) {
        idx[j] = (uint32_t)(N - 1 - j);
        x[j] = 0.31 * sin(1.7 * j);
        y[j] = 0.29 * cos(2.3 * j);
        z[j] = 0.27 * sin(0.9 * j + 1.0);
        m[j] = 1.0 + 0.01 * j;
        pt[j] = 0.5 + 0.02 * j;
        vx[j] = sin(0.3 * j);
        vy[j] = cos(0.7 * j);
        vz[j] = sin(1.1 * j);
    }
    const double p[3] = {0.02, -0.01, 0.03}, v[3] = {0.1, 0.2, -0.3};
    for (int type = KRN_CUBIC_SPLINE; type <= KRN_WENDLAND_C2; type++) {
        krn_kernel k;
        krn_init_type(&k, type, 0.4);
        double w = 0, mw = 0, a[3] = {0}, av[3] = {0};
        for (int q = 0; q < N; q++) {
            const uint32_t j = idx[q];
            const double dx = p[0] - x[j], dy = p[1] - y[j], dz = p[2] - z[j];
            const double r2 = dx * dx + dy * dy + dz * dz, r = sqrt(r2);
            w += krn_w(&k, r);
            mw += m[j] * krn_w(&k, r);
            const double c = m[j] * (0.7 + pt[j]) * krn_gradf(&k, r);
            a[0] -= c * dx, a[1] -= c * dy, a[2] -= c * dz;
            const double vr = (v[0] - vx[j]) * dx + (v[1] - vy[j]) * dy + (v[2] - vz[j]) * dz;
            const double cv = vr < 0 ? m[j] * vr / (r2 + 1e-4) * krn_gradf(&k, r) : 0.0;
            av[0] += cv * dx, av[1] += cv * dy, av[2] += cv * dz;
        }
        assert_true(w > 0.0);
        assert_close(sph_sum_w(k, idx, 0, N, p[0], p[1], p[2], x, y, z), w, 1e-12 * w);
        assert_close(sph_sum_mw(k, idx, 0, N, p[0], p[1], p[2], x, y, z, m), mw, 1e-12 * mw);
        double b[3] = {0}, bv[3] = {0};
        sph_sum_pressure(k, idx, 0, N, p[0], p[1], p[2], 0.7, x, y, z, pt, m, 1.0, b);
        sph_sum_viscosity(k, idx, 0, N, p, v, x, y, z, vx, vy, vz, m, 1e-4, 1.0, bv);
        for (int d = 0; d < 3; d++) {
            assert_close(b[d], a[d], 1e-10 * (fabs(a[0]) + fabs(a[1]) + fabs(a[2])));
            assert_close(bv[d], av[d], 1e-10 * (fabs(av[0]) + fabs(av[1]) + fabs(av[2])));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normalisation),
        cmocka_unit_test(test_support_and_continuity),
        cmocka_unit_test(test_gradient),
        cmocka_unit_test(test_gradient_consistency),
        cmocka_unit_test(test_delta),
        cmocka_unit_test(test_delta_largest_mode),
        cmocka_unit_test(test_lattice_gradient_moment),
        cmocka_unit_test(test_wendland_normalisation_and_support),
        cmocka_unit_test(test_wendland_gradient),
        cmocka_unit_test(test_sums_follow_the_kernel),
    };
    return cmocka_run_group_tests_name("kernel", tests, NULL, NULL);
}
