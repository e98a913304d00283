/* Unit tests: boundary calibration (fluid at rest against a flat wall sits
 * at rest density, and so do the wall's particles), geometry sampling
 * (spacing, normals into the fluid) and the world collision of eq. (9)-(12). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "assert_close.h"

#include <math.h>

#include "boundary/boundary.h"
#include "boundary/ihmsen2010.h"
#include "core/sl_log.h"
#include "geometry/geometry.h"
#include "solver/pcisph.h"
#include "solver/pcs_snapshot.h"

#define R0   0.02
#define RHO0 1000.0

typedef struct scene {
    geo_shape tank;
    sl_fluid f;
    sl_boundary b;
    pcs_solver s;
} scene;

/* A closed tank 0.4 x 0.4 x 0.4 half filled, no gravity. */
static void make_scene(scene *w)
{
    pcs_params p;
    pcs_params_default(&p);
    p.rho0 = RHO0;
    p.r0 = R0;
    p.gravity[2] = 0.0;
    p.max_iter = 3;
    double lo[3] = {0, 0, 0}, hi[3] = {0.4, 0.4, 0.4}, v[3] = {0, 0, 0};
    double flo[3] = {0, 0, 0}, fhi[3] = {0.4, 0.4, 0.2};
    double glo[3] = {-0.1, -0.1, -0.1}, ghi[3] = {0.5, 0.5, 0.5};
    w->tank = (geo_shape){.kind = GEO_CONTAINER, .lo = {0, 0, 0}, .hi = {0.4, 0.4, 0.4}};
    (void)lo;
    (void)hi;
    prt_fluid_init(&w->f);
    prt_boundary_init(&w->b);
    geo_sample(&w->tank, R0, 0, &w->b);
    geo_fill_box(flo, fhi, R0, v, &w->tank, 1, &w->f);
    pcs_init(&w->s, &p, &w->f, &w->b, glo, ghi, 1e-3, NULL);
}

static void free_scene(scene *w)
{
    pcs_free(&w->s);
    prt_fluid_free(&w->f);
    prt_boundary_free(&w->b);
}

static int far_from_side_walls(double x, double y)
{
    return x > 3 * R0 && x < 0.4 - 3 * R0 && y > 3 * R0 && y < 0.4 - 3 * R0;
}

static void test_rest_density_at_wall(void **state)
{
    (void)state;
    scene w;
    make_scene(&w);
    assert_int_equal(w.f.n, 20 * 20 * 10);
    pcs_compute_density(&w.s);
    size_t checked = 0;
    for (size_t i = 0; i < w.f.n; i++) {
        if (!far_from_side_walls(w.f.x[i], w.f.y[i]) || w.f.z[i] > 0.2 - 3 * R0) continue;
        assert_close(w.f.rho[i], RHO0, 1e-3 * RHO0); /* first layer included */
        checked++;
    }
    assert_true(checked > 500);
    free_scene(&w);
}

/* With no gravity the fluid at rest stays at rest, and the floor's
 * particles under it have rest density. */
static void test_rest_stays_at_rest(void **state)
{
    (void)state;
    scene w;
    pcs_stats st;
    make_scene(&w);
    for (int k = 0; k < 5; k++) pcs_step(&w.s, &st);
    assert_true(st.vmax < 1e-3);
    size_t floor = 0;
    for (size_t q = 0; q < w.s.nactive; q++) {
        uint32_t i = w.s.active[q];
        if (w.b.z[i] > 0 || !far_from_side_walls(w.b.x[i], w.b.y[i])) continue;
        assert_close(w.b.rho[i], RHO0, 2e-3 * RHO0);
        floor++;
    }
    assert_true(floor > 100);
    free_scene(&w);
}

/* Boundary particles: spacing r0, r0/2 behind the wall, unit normals
 * pointing into the tank. */
static void test_container_sampling(void **state)
{
    (void)state;
    scene w;
    make_scene(&w);
    for (size_t i = 0; i < w.b.n; i++) {
        double n = sqrt(w.b.nx[i] * w.b.nx[i] + w.b.ny[i] * w.b.ny[i] + w.b.nz[i] * w.b.nz[i]);
        assert_close(n, 1.0, 1e-12);
        /* a step along the normal goes towards the centre */
        double cx = 0.2 - w.b.x[i], cy = 0.2 - w.b.y[i], cz = 0.2 - w.b.z[i];
        assert_true(cx * w.b.nx[i] + cy * w.b.ny[i] + cz * w.b.nz[i] > 0);
        double d = -geo_solid_distance(&w.tank, (double[3]){w.b.x[i], w.b.y[i], w.b.z[i]});
        assert_true(d >= 0.5 * R0 - 1e-12);
    }
    /* walls 0.42 m apart (r0/2 behind each wall): 22 points per edge, the
     * surface of a 22^3 lattice */
    assert_int_equal(w.b.n, 22 * 22 * 22 - 20 * 20 * 20);
    free_scene(&w);
}

/* A particle pushed into the floor is put back to r0 from it and keeps
 * its tangential velocity (epsilon = 1) but loses the normal one. */
static void test_collision(void **state)
{
    (void)state;
    scene w;
    make_scene(&w);
    pcs_compute_density(&w.s); /* builds the lists */
    size_t i = 0;
    for (size_t k = 0; k < w.f.n; k++)
        if (w.f.z[k] < R0 && far_from_side_walls(w.f.x[k], w.f.y[k])) {
            i = k;
            break;
        }
    w.f.z[i] -= 0.3 * R0;
    w.f.vx[i] = 1.0;
    w.f.vz[i] = -2.0;
    double x = w.f.x[i];
    bnd_collide(&w.s.fb, &w.b, R0, 1.0, w.f.n, w.f.x, w.f.y, w.f.z, w.f.vx, w.f.vy, w.f.vz);
    assert_close(w.f.z[i], 0.5 * R0, 0.05 * R0);
    assert_close(w.f.x[i], x, 1e-3 * R0);
    assert_true(fabs(w.f.vz[i]) < 1e-12);
    assert_close(w.f.vx[i], 1.0, 1e-12);
    free_scene(&w);
}

static void test_sphere_sampling(void **state)
{
    (void)state;
    sl_boundary b;
    geo_shape s = {.kind = GEO_SPHERE, .centre = {1, 2, 3}, .radius = 0.2};
    prt_boundary_init(&b);
    size_t n = geo_sample(&s, R0, 0, &b);
    assert_true(n > 300);
    double dmin = 1e9, dmax = 0;
    for (size_t i = 0; i < n; i++) {
        double dx = b.x[i] - 1, dy = b.y[i] - 2, dz = b.z[i] - 3;
        double r = sqrt(dx * dx + dy * dy + dz * dz);
        assert_close(r, (0.2 - 0.5 * R0), 1e-12);
        assert_true(dx * b.nx[i] + dy * b.ny[i] + dz * b.nz[i] > 0); /* outward */
        double nn = 1e9;
        for (size_t j = 0; j < n; j++) {
            if (j == i) continue;
            double ex = b.x[i] - b.x[j], ey = b.y[i] - b.y[j], ez = b.z[i] - b.z[j];
            double d = sqrt(ex * ex + ey * ey + ez * ez);
            if (d < nn) nn = d;
        }
        if (nn < dmin) dmin = nn;
        if (nn > dmax) dmax = nn;
    }
    assert_true(dmin > 0.6 * R0 && dmax < 1.3 * R0);
    prt_boundary_free(&b);
}

/* Rollback (paper Sec. 3.3): step, step, go back, step, step again gives
 * the same bits; a dam break with gravity so that the state changes. */
static void test_rollback_restores_exactly(void **state)
{
    (void)state;
    scene w;
    pcs_stats st;
    pcs_snapshot s0, a, b;
    make_scene(&w);
    w.s.prm.gravity[2] = -9.81;
    w.f.vx[0] = 0.3; /* something asymmetric */
    for (int k = 0; k < 3; k++) pcs_step(&w.s, &st);
    snap_init(&s0);
    snap_init(&a);
    snap_init(&b);
    snap_take(&s0, &w.f, 0.0, w.s.dt, 0);
    pcs_step(&w.s, &st);
    pcs_step(&w.s, &st);
    snap_take(&a, &w.f, 0.0, w.s.dt, 0);
    assert_false(snap_equal(&a, &s0));
    snap_restore(&s0, &w.f);
    pcs_step(&w.s, &st);
    pcs_step(&w.s, &st);
    snap_take(&b, &w.f, 0.0, w.s.dt, 0);
    assert_true(snap_equal(&a, &b));
    snap_free(&s0);
    snap_free(&a);
    snap_free(&b);
    free_scene(&w);
}

int main(void)
{
    sl_log_set_quiet(1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rest_density_at_wall),
        cmocka_unit_test(test_rest_stays_at_rest),
        cmocka_unit_test(test_container_sampling),
        cmocka_unit_test(test_collision),
        cmocka_unit_test(test_sphere_sampling),
        cmocka_unit_test(test_rollback_restores_exactly),
    };
    return cmocka_run_group_tests_name("boundary", tests, NULL, NULL);
}
