/* Unit tests: grid neighbour search against brute force, Z-order sorting,
 * clamping of particles outside the grid, identical lists for any
 * thread count and an order that does not depend on the input order; the
 * same lists with the grid's block units (SLUICE_GRID_UNIT), whose cell
 * numbering is a permutation with each block one run of it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <gsl/gsl_rng.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "neighbours/neighbours.h"

#define NF 3000
#define NB 1500

typedef struct world {
    sl_fluid f;
    sl_boundary b;
    nbr_grid g;
    double h;
} world;

/* Random fluid in [0,1]^3 plus 5 % outside the grid box; boundary on the
 * faces of the unit cube. */
static void make_world(world *w)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 42);
    prt_fluid_init(&w->f);
    prt_boundary_init(&w->b);
    for (int i = 0; i < NF; i++) {
        double s = i % 20 == 0 ? 3.0 : 1.0; /* some far outside */
        prt_fluid_push(&w->f, s * gsl_rng_uniform(r) - (s - 1) / 2, s * gsl_rng_uniform(r),
                       gsl_rng_uniform(r), 0, 0, 0);
    }
    for (int i = 0; i < NB; i++) {
        double x = gsl_rng_uniform(r), y = gsl_rng_uniform(r);
        prt_boundary_push(&w->b, x, y, i % 2 ? 0.0 : 1.0, 0, 0, i % 2 ? 1.0 : -1.0, 0);
    }
    gsl_rng_free(r);
    w->h = 0.07;
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    nbr_grid_init(&w->g, lo, hi, w->h, 1u << 20);
    nbr_sort_boundary(&w->g, &w->b);
    nbr_sort_fluid(&w->g, &w->f);
}

static void free_world(world *w)
{
    prt_fluid_free(&w->f);
    prt_boundary_free(&w->b);
    nbr_grid_free(&w->g);
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Compare row i of l (as a set) with the brute-force neighbours. */
static void check_row(const nbr_list *l, size_t i, const double p[3], const double *x,
                      const double *y, const double *z, size_t n, double h, size_t self)
{
    uint32_t *want = malloc(n * sizeof *want), cnt = 0;
    for (size_t j = 0; j < n; j++) {
        double dx = p[0] - x[j], dy = p[1] - y[j], dz = p[2] - z[j];
        if (j != self && dx * dx + dy * dy + dz * dz < h * h) want[cnt++] = (uint32_t)j;
    }
    uint32_t got_n = l->start[i + 1] - l->start[i];
    assert_int_equal(got_n, cnt);
    uint32_t *got = malloc((got_n + 1) * sizeof *got);
    memcpy(got, l->idx + l->start[i], got_n * sizeof *got);
    qsort(got, got_n, sizeof *got, cmp_u32);
    for (uint32_t q = 0; q < cnt; q++) assert_int_equal(got[q], want[q]);
    free(got);
    free(want);
}

static void test_fluid_fluid_brute_force(void **state)
{
    (void)state;
    world w;
    make_world(&w);
    nbr_list l;
    nbr_list_init(&l);
    nbr_build_ff(&w.g, &w.f, &l);
    size_t total = 0;
    for (size_t i = 0; i < w.f.n; i++) {
        double p[3] = {w.f.x[i], w.f.y[i], w.f.z[i]};
        check_row(&l, i, p, w.f.x, w.f.y, w.f.z, w.f.n, w.h, i);
        total += l.start[i + 1] - l.start[i];
    }
    assert_true(total > 3 * NF); /* the test has neighbours to find (~4 each) */
    nbr_list_free(&l);
    free_world(&w);
}

static void test_fluid_boundary_brute_force(void **state)
{
    (void)state;
    world w;
    make_world(&w);
    nbr_list fb, bf;
    nbr_list_init(&fb);
    nbr_list_init(&bf);
    uint32_t *active = malloc(w.b.n * sizeof *active);
    size_t nact = 0, with = 0;
    nbr_build_fb(&w.g, &w.f, &w.b, &fb);
    nbr_build_bf(&w.g, &w.f, &w.b, &bf, active, &nact);
    for (size_t i = 0; i < w.f.n; i++) {
        double p[3] = {w.f.x[i], w.f.y[i], w.f.z[i]};
        check_row(&fb, i, p, w.b.x, w.b.y, w.b.z, w.b.n, w.h, SIZE_MAX);
    }
    for (size_t i = 0; i < w.b.n; i++) {
        double p[3] = {w.b.x[i], w.b.y[i], w.b.z[i]};
        check_row(&bf, i, p, w.f.x, w.f.y, w.f.z, w.f.n, w.h, SIZE_MAX);
        with += bf.start[i + 1] > bf.start[i];
    }
    assert_int_equal(nact, with);
    assert_true(nact > 0 && nact < w.b.n);
    for (size_t q = 1; q < nact; q++) assert_true(active[q] > active[q - 1]);
    free(active);
    nbr_list_free(&fb);
    nbr_list_free(&bf);
    free_world(&w);
}

/* After sorting, particles are in non-decreasing cell rank order. */
static void test_sorted_by_cell(void **state)
{
    (void)state;
    world w;
    make_world(&w);
    for (size_t i = 1; i < w.f.n; i++) assert_true(w.f.cell[i] >= w.f.cell[i - 1]);
    free_world(&w);
}

static void test_same_lists_any_thread_count(void **state)
{
    (void)state;
    world w;
    make_world(&w);
    nbr_list a, b;
    nbr_list_init(&a);
    nbr_list_init(&b);
    omp_set_num_threads(1);
    nbr_build_ff(&w.g, &w.f, &a);
    omp_set_num_threads(3);
    nbr_build_ff(&w.g, &w.f, &b);
    omp_set_num_threads(omp_get_num_procs());
    assert_memory_equal(a.start, b.start, (w.f.n + 1) * sizeof *a.start);
    assert_memory_equal(a.idx, b.idx, a.start[w.f.n] * sizeof *a.idx);
    nbr_list_free(&a);
    nbr_list_free(&b);
    free_world(&w);
}

/* Transposing fluid -> boundary gives the boundary -> fluid lists (as
 * sets per row) and the same active set. */
static void test_transpose(void **state)
{
    (void)state;
    world w;
    make_world(&w);
    nbr_list fb, bf, tr;
    nbr_list_init(&fb);
    nbr_list_init(&bf);
    nbr_list_init(&tr);
    uint32_t *a1 = malloc(w.b.n * sizeof *a1), *a2 = malloc(w.b.n * sizeof *a2);
    size_t n1, n2;
    nbr_build_fb(&w.g, &w.f, &w.b, &fb);
    nbr_build_bf(&w.g, &w.f, &w.b, &bf, a1, &n1);
    nbr_transpose(&fb, w.b.n, &tr, a2, &n2);
    assert_int_equal(n1, n2);
    assert_memory_equal(a1, a2, n1 * sizeof *a1);
    assert_memory_equal(bf.start, tr.start, (w.b.n + 1) * sizeof *bf.start);
    for (size_t i = 0; i < w.b.n; i++) {
        uint32_t k = bf.start[i], m = bf.start[i + 1] - k;
        qsort(bf.idx + k, m, sizeof *bf.idx, cmp_u32);
        for (uint32_t q = 1; q < m; q++) assert_true(tr.idx[k + q] > tr.idx[k + q - 1]);
        assert_memory_equal(bf.idx + k, tr.idx + k, m * sizeof *bf.idx);
    }
    free(a1);
    free(a2);
    nbr_list_free(&fb);
    nbr_list_free(&bf);
    nbr_list_free(&tr);
    free_world(&w);
}

/* The one-sweep build gives the same lists as the separate builds. */
static void test_combined_build(void **state)
{
    (void)state;
    world w;
    make_world(&w);
    nbr_list a, b, c, d;
    nbr_list_init(&a);
    nbr_list_init(&b);
    nbr_list_init(&c);
    nbr_list_init(&d);
    nbr_build_ff(&w.g, &w.f, &a);
    nbr_build_fb(&w.g, &w.f, &w.b, &b);
    nbr_build_fluid(&w.g, &w.f, &w.b, &c, &d);
    assert_memory_equal(a.start, c.start, (w.f.n + 1) * sizeof *a.start);
    assert_memory_equal(a.idx, c.idx, a.start[w.f.n] * sizeof *a.idx);
    assert_memory_equal(b.start, d.start, (w.f.n + 1) * sizeof *b.start);
    assert_memory_equal(b.idx, d.idx, b.start[w.f.n] * sizeof *b.idx);
    nbr_list_free(&a);
    nbr_list_free(&b);
    nbr_list_free(&c);
    nbr_list_free(&d);
    free_world(&w);
}

/* The sort key is (cell, id): a fluid given in another order (reversed,
 * as another rank or a restart could hold it) sorts to the same order,
 * ids and positions alike. */
static void test_order_independent_of_input_order(void **state)
{
    (void)state;
    world w;
    make_world(&w);
    const size_t n = w.f.n;
    uint32_t *rev = malloc(n * sizeof *rev), *id0 = malloc(n * sizeof *id0);
    double *x0 = malloc(n * sizeof *x0);
    memcpy(id0, w.f.id, n * sizeof *id0);
    memcpy(x0, w.f.x, n * sizeof *x0);
    for (size_t i = 0; i < n; i++) rev[i] = (uint32_t)(n - 1 - i);
    prt_fluid_permute(&w.f, rev);
    nbr_sort_fluid(&w.g, &w.f);
    assert_memory_equal(id0, w.f.id, n * sizeof *id0);
    assert_memory_equal(x0, w.f.x, n * sizeof *x0);
    for (size_t i = 1; i < n; i++)
        if (w.f.cell[i] == w.f.cell[i - 1]) assert_true(w.f.id[i] > w.f.id[i - 1]);
    free(rev);
    free(id0);
    free(x0);
    free_world(&w);
}

/* Blocks of 4, 2 and 3 cells a side (odd: the curve's diagonal steps):
 * the cell ranks a permutation, a block's cells one run of ucells ranks,
 * the grid whole blocks, and the lists the brute force's. */
static void test_block_units(void **state)
{
    (void)state;
    const char *units[] = {"block", "block:2", "block:3"};
    const int edge[] = {4, 2, 3};
    for (int u = 0; u < 3; u++) {
        setenv("SLUICE_GRID_UNIT", units[u], 1);
        world w;
        make_world(&w);
        unsetenv("SLUICE_GRID_UNIT");
        const nbr_grid *g = &w.g;
        const int B = edge[u];
        assert_int_equal(g->unit[0], B);
        assert_int_equal(g->ucells, (size_t)(B * B * B));
        for (int d = 0; d < 3; d++) assert_int_equal(g->nc[d] % B, 0);
        assert_int_equal(g->nunits * g->ucells, g->ncells);
        unsigned char *seen = calloc(g->ncells, 1);
        uint32_t *first = malloc(g->nunits * sizeof *first);
        for (size_t k = 0; k < g->nunits; k++) first[k] = UINT32_MAX;
        for (int cz = 0; cz < g->nc[2]; cz++)
            for (int cy = 0; cy < g->nc[1]; cy++)
                for (int cx = 0; cx < g->nc[0]; cx++) {
                    const uint32_t r =
                        g->rank[cx + g->nc[0] * (cy + (size_t)g->nc[1] * (size_t)cz)];
                    assert_true(r < g->ncells && !seen[r]);
                    seen[r] = 1;
                    /* the cell's place in its block, x fastest */
                    assert_int_equal(r % g->ucells, cx % B + B * (cy % B + B * (cz % B)));
                    /* the same block for every cell of the block */
                    const size_t k = r / g->ucells;
                    const uint32_t corner =
                        (uint32_t)(cx / B + g->nc[0] / B * (cy / B + g->nc[1] / B * (cz / B)));
                    if (first[k] == UINT32_MAX) first[k] = corner;
                    assert_int_equal(first[k], corner);
                }
        free(seen);
        free(first);
        nbr_list ff, fb;
        nbr_list_init(&ff);
        nbr_list_init(&fb);
        nbr_build_ff(g, &w.f, &ff);
        nbr_build_fb(g, &w.f, &w.b, &fb);
        for (size_t i = 1; i < w.f.n; i++) assert_true(w.f.cell[i] >= w.f.cell[i - 1]);
        for (size_t i = 0; i < w.f.n; i++) {
            double p[3] = {w.f.x[i], w.f.y[i], w.f.z[i]};
            check_row(&ff, i, p, w.f.x, w.f.y, w.f.z, w.f.n, w.h, i);
            check_row(&fb, i, p, w.b.x, w.b.y, w.b.z, w.b.n, w.h, SIZE_MAX);
        }
        nbr_list_free(&ff);
        nbr_list_free(&fb);
        free_world(&w);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fluid_fluid_brute_force),
        cmocka_unit_test(test_fluid_boundary_brute_force),
        cmocka_unit_test(test_sorted_by_cell),
        cmocka_unit_test(test_same_lists_any_thread_count),
        cmocka_unit_test(test_combined_build),
        cmocka_unit_test(test_transpose),
        cmocka_unit_test(test_order_independent_of_input_order),
        cmocka_unit_test(test_block_units),
    };
    return cmocka_run_group_tests_name("neighbours", tests, NULL, NULL);
}
