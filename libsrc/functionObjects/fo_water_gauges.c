/*
 * fo_water_gauges: height of the free surface along vertical lines, like
 * the wave gauges of the SPHERIC dam-break benchmark, which record water
 * height.
 *
 * Method: the fluid colour c(z) = sum_j V_j W(x - x_j) (fo_query.h; about 1
 * in the fluid, 1/2 at a flat surface, 0 in air) is sampled on the line at
 * the multiples z_k = k r0/4 inside the scanned interval, from the top
 * down, until c(z_k) >= threshold (default 1/2).  The surface is the z
 * where c crosses the threshold, interpolated linearly between z_k and the
 * sample above it; that is the highest crossing, so spray above the surface
 * counts only if it is dense enough to reach the threshold.  A line that
 * never reaches the threshold (dry) reads nan; one already at the threshold
 * at the top of the interval reads that top.
 * Heights are z coordinates, in m.
 *
 *   type waterGauges; gaugeLocations ((0.5 0.3) (1.0 0.3));  // (x y)
 *   zRange (0 0.8);    // optional: scanned interval; default: the fluid's z
 *                      // extent widened by h
 *   threshold 0.5;     // optional
 */
#include "functionObjects/fo_type.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <math.h>
#include <stdlib.h>

static const char *const wg_keys[] = {"gaugeLocations", "zRange", "threshold", NULL};

typedef struct wg_state {
    double *xy; /* 2 per gauge */
    size_t n;
    int have_range;
    double z0, z1;
    double threshold;
} wg_state;

static void *wg_read(const dict *d)
{
    wg_state *st = sl_calloc(1, sizeof *st, "waterGauges");
    sl_err err;
    fo_get_points(d, "gaugeLocations", 2, &st->xy, &st->n);
    if (dict_has(d, "zRange")) {
        double *r;
        size_t n;
        fo_need(dict_get_scalar_list(d, "zRange", &r, &n, &err), &err);
        if (n != 2 || !(r[1] > r[0])) {
            free(r);
            fo_bad_key(d, "zRange", "must be (zMin zMax) with zMax > zMin");
        }
        st->have_range = 1;
        st->z0 = r[0];
        st->z1 = r[1];
        free(r);
    }
    fo_need(dict_get_scalar_or(d, "threshold", 0.5, &st->threshold, &err), &err);
    if (!(st->threshold > 0.0 && st->threshold < 1.0))
        fo_bad_key(d, "threshold", "must be between 0 and 1");
    return st;
}

/* The scanned interval: zRange, or the fluid's z extent widened by h (the
 * colour is zero outside it).  Returns 0 when there is nothing to scan. */
static int wg_range(const wg_state *st, const pcs_view *s, double *z0, double *z1)
{
    if (st->have_range) {
        *z0 = st->z0;
        *z1 = st->z1;
        return 1;
    }
    const sl_fluid *f = s->f;
    double lo = INFINITY, hi = -INFINITY;
    if (s->fluid_z) { /* f is the particles near the gauges (-parallel): the whole fluid's */
        lo = s->fluid_z[0];
        hi = s->fluid_z[1];
    }
    for (size_t i = 0; !s->fluid_z && i < f->n; i++) {
        if (f->z[i] < lo) lo = f->z[i];
        if (f->z[i] > hi) hi = f->z[i];
    }
    *z0 = lo - s->h;
    *z1 = hi + s->h;
    return hi >= lo;
}

static void wg_header(const void *vs, const pcs_view *s, FILE *f)
{
    const wg_state *st = vs;
    char range[128];
    if (st->have_range) snprintf(range, sizeof range, "in [%g, %g]", st->z0, st->z1);
    else snprintf(range, sizeof range, "below the highest fluid particle + h");
    fprintf(f,
            "# Free-surface height (z, m) on vertical lines: the highest z %s where the fluid "
            "colour sum_j V_j W reaches %g,\n"
            "# sampled at the multiples of r0/4 = %g m from the top down and interpolated "
            "linearly; nan: no fluid on the line\n",
            range, st->threshold, s->r0 / 4);
    for (size_t i = 0; i < st->n; i++)
        fprintf(f, "# Gauge %zu (%.10g %.10g)\n", i, st->xy[2 * i], st->xy[2 * i + 1]);
}

static void wg_columns(const void *vs, FILE *f)
{
    const wg_state *st = vs;
    for (size_t i = 0; i < st->n; i++) fprintf(f, "\theight_%zu", i);
}

/* Samples lie at the multiples of dz, whatever the range, so that a run and
 * a post-processing of its written times sample the same points. */
static double wg_height(const wg_state *st, const fo_index *ix, double x, double y)
{
    const pcs_view *s = ix->s;
    const double dz = s->r0 / 4, thr = st->threshold;
    double z0, z1;
    if (!wg_range(st, s, &z0, &z1)) return NAN;
    const double k0 = ceil(z0 / dz), k1 = floor(z1 / dz);
    if (k1 < k0) return NAN;
    double c_above = fo_query_colour(ix, x, y, k1 * dz);
    if (c_above >= thr) return k1 * dz;
    for (double k = k1 - 1; k >= k0; k--) {
        double c = fo_query_colour(ix, x, y, k * dz);
        if (c >= thr) return k * dz + dz * (c - thr) / (c - c_above);
        c_above = c;
    }
    return NAN;
}

static void wg_execute(void *vs, const fo_call *call)
{
    wg_state *st = vs;
    for (size_t i = 0; i < st->n; i++)
        fo_put(call->dat, wg_height(st, call->ix, st->xy[2 * i], st->xy[2 * i + 1]));
}

static void wg_free(void *vs)
{
    wg_state *st = vs;
    if (!st) return;
    free(st->xy);
    free(st);
}

/* Point queries on the gauges' vertical lines only (all of z: the range
 * may be the fluid's extent). */
static size_t wg_region(const void *vs, double *box, size_t max)
{
    const wg_state *st = vs;
    for (size_t i = 0; i < st->n && i < max; i++) {
        double *b = box + 6 * i;
        b[0] = b[3] = st->xy[2 * i];
        b[1] = b[4] = st->xy[2 * i + 1];
        b[2] = -INFINITY;
        b[5] = INFINITY;
    }
    return st->n;
}

const fo_type fo_type_water_gauges = {
    .name = "waterGauges",
    .keys = wg_keys,
    .needs = FO_NEED_GRID,
    .read = wg_read,
    .header = wg_header,
    .columns = wg_columns,
    .execute = wg_execute,
    .at_write = NULL,
    .free = wg_free,
    .region = wg_region,
};
