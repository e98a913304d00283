/*
 * srf_surface: the reconstruction's entry point, its parameters
 * (system/surfaceDict) and the measurements of a mesh (see surface.h).
 */
#include "surface/surface.h"

#include "core/sl_mem.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Grid points beyond which srf_reconstruct refuses (4 bytes each). */
#define SRF_MAX_POINTS    ((size_t)1 << 31)
#define SRF_MAX_SMOOTHING 20

const char *const srf_keys[] = {"gridSpacing",   "isoValue", "kernelRadius",     "smoothing",
                                "dropletRadius", "kernel",   "anisotropyRadius", "maxStretch",
                                "minNeighbours", NULL};

void srf_params_default(srf_params *p)
{
    p->grid_spacing = 0.5;
    p->iso_value = 0.5;
    p->kernel_radius = 2.0;
    p->smoothing = 0;
    p->droplet_radius = 0.5;
    p->anisotropic = 0;
    p->anisotropy_radius = 2.0;
    p->max_stretch = 4.0;
    p->min_neighbours = 25;
}

void srf_params_read(const dict *d, srf_params *p)
{
    sl_err err;
    long sm;
    srf_params_default(p);
    if (!d) return;
    dict_warn_unknown(d, srf_keys);
    dict_need(dict_get_scalar_or(d, "gridSpacing", p->grid_spacing, &p->grid_spacing, &err), &err);
    dict_need(dict_get_scalar_or(d, "isoValue", p->iso_value, &p->iso_value, &err), &err);
    dict_need(dict_get_scalar_or(d, "kernelRadius", p->kernel_radius, &p->kernel_radius, &err),
              &err);
    dict_need(dict_get_int_or(d, "smoothing", p->smoothing, &sm, &err), &err);
    dict_need(dict_get_scalar_or(d, "dropletRadius", p->droplet_radius, &p->droplet_radius, &err),
              &err);
    dict_need_positive(d, "gridSpacing", p->grid_spacing);
    if (p->grid_spacing < 0.05 || p->grid_spacing > 4)
        dict_fatal(d, "gridSpacing", "%g must be between 0.05 and 4 (times particleSpacing)",
                   p->grid_spacing);
    if (!(p->iso_value > 0 && p->iso_value < 1))
        dict_fatal(d, "isoValue", "%g must be between 0 and 1 (the fluid's volume fraction)",
                   p->iso_value);
    if (p->kernel_radius < 1 || p->kernel_radius > 6)
        dict_fatal(d, "kernelRadius", "%g must be between 1 and 6 (times particleSpacing)",
                   p->kernel_radius);
    if (sm < 0 || sm > SRF_MAX_SMOOTHING)
        dict_fatal(d, "smoothing", "%ld must be between 0 and %d (filter passes)", sm,
                   SRF_MAX_SMOOTHING);
    p->smoothing = (int)sm;
    const char *kern;
    dict_need(
        dict_get_word_or(d, "kernel", p->anisotropic ? "anisotropic" : "isotropic", &kern, &err),
        &err);
    if (strcmp(kern, "isotropic") && strcmp(kern, "anisotropic"))
        dict_fatal(d, "kernel", "'%s' is not one of: isotropic anisotropic", kern);
    p->anisotropic = !strcmp(kern, "anisotropic");
    dict_need(dict_get_scalar_or(d, "anisotropyRadius", p->anisotropy_radius, &p->anisotropy_radius,
                                 &err),
              &err);
    dict_need(dict_get_scalar_or(d, "maxStretch", p->max_stretch, &p->max_stretch, &err), &err);
    dict_need(dict_get_int_or(d, "minNeighbours", p->min_neighbours, &p->min_neighbours, &err),
              &err);
    if (p->anisotropy_radius < 1 || p->anisotropy_radius > 3)
        dict_fatal(d, "anisotropyRadius", "%g must be between 1 and 3 (times the kernel radius)",
                   p->anisotropy_radius);
    if (p->max_stretch < 1 || p->max_stretch > 16)
        dict_fatal(d, "maxStretch", "%g must be between 1 and 16", p->max_stretch);
    if (p->min_neighbours < 3 || p->min_neighbours > 1000)
        dict_fatal(d, "minNeighbours", "%ld must be between 3 and 1000", p->min_neighbours);
    if (p->droplet_radius < 0 || 2 * p->droplet_radius > p->kernel_radius)
        dict_fatal(d, "dropletRadius", "%g must be between 0 and kernelRadius / 2 = %g",
                   p->droplet_radius, p->kernel_radius / 2);
}

int srf_reconstruct(const srf_particles *in, const srf_params *prm, srf_mesh *m, sl_err *err)
{
    const double h = prm->kernel_radius * in->r0, dx = prm->grid_spacing * in->r0;
    const double *p[3] = {in->x, in->y, in->z};
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    srf_grid g;
    memset(m, 0, sizeof *m);
    if (!(in->r0 > 0)) {
        sl_err_set(err, "surface: particle spacing %g is not positive", in->r0);
        return 1;
    }
    for (size_t i = 0; i < in->n; i++)
        for (int d = 0; d < 3; d++) {
            if (!isfinite(p[d][i])) {
                sl_err_set(err, "surface: particle %zu has a position that is not finite", i);
                return 1;
            }
            if (p[d][i] < lo[d]) lo[d] = p[d][i];
            if (p[d][i] > hi[d]) hi[d] = p[d][i];
        }
    if (in->n == 0) { /* no fluid: an empty surface */
        m->x = sl_malloc(sizeof(double), "surface");
        m->y = sl_malloc(sizeof(double), "surface");
        m->z = sl_malloc(sizeof(double), "surface");
        m->tri = sl_malloc(sizeof *m->tri, "surface");
        return 0;
    }
    /* a margin of h plus the smoothing's reach plus two cells: the field
     * is zero on the grid's faces, so the surface is closed inside it */
    const double reach = prm->anisotropic ? h * cbrt(prm->max_stretch * prm->max_stretch) : h;
    const double margin = reach + (prm->smoothing + 2) * dx;
    double total = 1;
    g.dx = dx;
    for (int d = 0; d < 3; d++) {
        g.lo[d] = lo[d] - margin;
        const double n = ceil((hi[d] - lo[d] + 2 * margin) / dx) + 1;
        total *= n;
        g.nc[d] = n < (double)SRF_MAX_POINTS ? (int)n : 0;
    }
    const size_t npts = (size_t)g.nc[0] * (size_t)g.nc[1] * (size_t)g.nc[2];
    if (total > (double)SRF_MAX_POINTS) {
        sl_err_set(err,
                   "surface: a grid of spacing %g over the fluid's extent (%g x %g x %g) needs "
                   "more than %zu points; raise gridSpacing",
                   dx, hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], SRF_MAX_POINTS);
        return 1;
    }
    g.f = sl_malloc(npts * sizeof *g.f, "surface grid");
    srf_colour_field(in, prm, &g);
    srf_smooth(&g, prm->smoothing);
    srf_contour(&g, prm->iso_value, m);
    free(g.f);
    srf_interpolate(in, h, m);
    return 0;
}

void srf_mesh_free(srf_mesh *m)
{
    free(m->x);
    free(m->y);
    free(m->z);
    free(m->vx);
    free(m->vy);
    free(m->vz);
    free(m->p);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

/* ---- measurements ---- */

static void corner(const srf_mesh *m, size_t t, int k, double v[3])
{
    const int64_t i = m->tri[3 * t + (size_t)k];
    v[0] = m->x[i];
    v[1] = m->y[i];
    v[2] = m->z[i];
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

double srf_area(const srf_mesh *m)
{
    double s = 0;
    for (size_t t = 0; t < m->nt; t++) {
        double a[3], b[3], c[3], u[3], v[3], n[3];
        corner(m, t, 0, a);
        corner(m, t, 1, b);
        corner(m, t, 2, c);
        for (int d = 0; d < 3; d++) {
            u[d] = b[d] - a[d];
            v[d] = c[d] - a[d];
        }
        cross(u, v, n);
        s += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return s;
}

double srf_volume(const srf_mesh *m)
{
    double s = 0;
    for (size_t t = 0; t < m->nt; t++) {
        double a[3], b[3], c[3], n[3];
        corner(m, t, 0, a);
        corner(m, t, 1, b);
        corner(m, t, 2, c);
        cross(b, c, n);
        s += (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 6.0;
    }
    return s;
}

double srf_height_at(const srf_mesh *m, double x, double y)
{
    double best = NAN;
    for (size_t t = 0; t < m->nt; t++) {
        double a[3], b[3], c[3];
        corner(m, t, 0, a);
        corner(m, t, 1, b);
        corner(m, t, 2, c);
        /* barycentric coordinates of (x, y) in the projected triangle */
        const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if (det == 0) continue; /* seen edge-on from above */
        const double u = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
        const double v = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
        if (u < 0 || v < 0 || u + v > 1) continue;
        const double z = a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]);
        if (isnan(best) || z > best) best = z;
    }
    return best;
}

static int cmp_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

size_t srf_open_edges(const srf_mesh *m, size_t *nedges)
{
    const size_t ne = 3 * m->nt;
    uint64_t *e = sl_malloc((ne ? ne : 1) * sizeof *e, "surface edges");
    for (size_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            const uint64_t a = (uint64_t)m->tri[3 * t + (size_t)k];
            const uint64_t b = (uint64_t)m->tri[3 * t + (size_t)(k + 1) % 3];
            e[3 * t + (size_t)k] = a < b ? a << 32 | b : b << 32 | a;
        }
    qsort(e, ne, sizeof *e, cmp_u64);
    size_t open = 0, distinct = 0;
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && e[j] == e[i]) j++;
        distinct++;
        if (j - i != 2) open++;
        i = j;
    }
    free(e);
    if (nedges) *nedges = distinct;
    return open;
}
