/* mesh_make: primitive meshes (box, icosphere, cylinder) for tests and
 * cases (see mesh.h).  Every primitive is closed, outward and indexed. */
#include "geometry/mesh.h"

#include "core/sl_mem.h"

#include <math.h>
#include <stdlib.h>

static int finite3(const double *x) { return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]); }

/* Reverse triangle j if its normal does not point along `out`. */
static void orient(mesh *m, size_t j, const double out[3])
{
    double n[3];
    mesh_triangle_normal(m, j, n);
    if (n[0] * out[0] + n[1] * out[1] + n[2] * out[2] < 0.0) {
        uint32_t s = m->t[3 * j + 1];
        m->t[3 * j + 1] = m->t[3 * j + 2];
        m->t[3 * j + 2] = s;
    }
}

int mesh_make_box(mesh *m, const double lo[3], const double hi[3], sl_err *err)
{
    mesh_init(m);
    if (!finite3(lo) || !finite3(hi) || !(lo[0] < hi[0] && lo[1] < hi[1] && lo[2] < hi[2])) {
        sl_err_set(err, "box (%g %g %g) (%g %g %g): expected finite corners with lo < hi", lo[0],
                   lo[1], lo[2], hi[0], hi[1], hi[2]);
        return 1;
    }
    for (int i = 0; i < 8; i++) /* vertex i = corner (i & 1, i & 2, i & 4) */
        mesh_add_vertex(m, i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]);
    for (int d = 0; d < 3; d++)
        for (int side = 0; side < 2; side++) {
            int a = (d + 1) % 3, b = (d + 2) % 3;
            uint32_t q[4];
            double out[3] = {0, 0, 0};
            out[d] = side ? 1.0 : -1.0;
            /* the face's corners in cyclic order over axes a, b */
            static const int cyc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; k++)
                q[k] = (uint32_t)(side << d | cyc[k][0] << a | cyc[k][1] << b);
            mesh_add_triangle(m, q[0], q[1], q[2]);
            orient(m, m->nt - 1, out);
            mesh_add_triangle(m, q[0], q[2], q[3]);
            orient(m, m->nt - 1, out);
        }
    mesh_index_build(m);
    return 0;
}

/* Split every triangle into four at its edge midpoints, projected on the
 * unit sphere. */
static void subdivide_unit(mesh *m)
{
    mesh_topology tp;
    mesh old;
    uint32_t *mid;
    mesh_topology_build(m, &tp);
    mid = sl_malloc((tp.ne ? tp.ne : 1) * sizeof *mid, "icosphere midpoints");
    for (size_t e = 0; e < tp.ne; e++) {
        const double *a = m->v + 3 * tp.ev[2 * e], *b = m->v + 3 * tp.ev[2 * e + 1];
        double p[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
        double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        mid[e] = mesh_add_vertex(m, p[0] / len, p[1] / len, p[2] / len);
    }
    old = *m;
    old.t = sl_malloc(3 * m->nt * sizeof *old.t, "icosphere triangles");
    for (size_t i = 0; i < 3 * m->nt; i++) old.t[i] = m->t[i];
    m->nt = 0;
    for (size_t j = 0; j < old.nt; j++) {
        const uint32_t *t = old.t + 3 * j;
        uint32_t ab = mid[tp.tedge[3 * j]], bc = mid[tp.tedge[3 * j + 1]],
                 ca = mid[tp.tedge[3 * j + 2]];
        mesh_add_triangle(m, t[0], ab, ca);
        mesh_add_triangle(m, t[1], bc, ab);
        mesh_add_triangle(m, t[2], ca, bc);
        mesh_add_triangle(m, ab, bc, ca);
    }
    free(old.t);
    free(mid);
    mesh_topology_free(&tp);
}

int mesh_make_sphere(mesh *m, const double centre[3], double radius, int level, sl_err *err)
{
    static const int face[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    const double g = 0.5 * (1.0 + sqrt(5.0)), s = 1.0 / sqrt(1.0 + g * g);
    const double v[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                             {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                             {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    mesh_init(m);
    if (!finite3(centre) || !(radius > 0.0) || !isfinite(radius) || level < 0 || level > 9) {
        sl_err_set(err,
                   "sphere: expected a finite centre, radius > 0 and level 0..9, "
                   "found radius %g, level %d",
                   radius, level);
        return 1;
    }
    for (int i = 0; i < 12; i++) mesh_add_vertex(m, s * v[i][0], s * v[i][1], s * v[i][2]);
    for (int j = 0; j < 20; j++) {
        const double *a = v[face[j][0]], *b = v[face[j][1]], *c = v[face[j][2]];
        double out[3] = {a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
        mesh_add_triangle(m, (uint32_t)face[j][0], (uint32_t)face[j][1], (uint32_t)face[j][2]);
        orient(m, (size_t)j, out);
    }
    for (int l = 0; l < level; l++) subdivide_unit(m);
    for (size_t i = 0; i < m->nv; i++)
        for (int d = 0; d < 3; d++) m->v[3 * i + d] = centre[d] + radius * m->v[3 * i + d];
    mesh_index_build(m);
    return 0;
}

int mesh_make_cylinder(mesh *m, const double a[3], const double b[3], double radius, int nseg,
                       sl_err *err)
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e1[3], e2[3], len, dot;
    uint32_t ca, cb, n;
    mesh_init(m);
    len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (!finite3(a) || !finite3(b) || !(len > 0.0) || !isfinite(len) || !(radius > 0.0) ||
        !isfinite(radius) || nseg < 3 || nseg > 1000000) {
        sl_err_set(err,
                   "cylinder: expected finite, distinct cap centres, radius > 0 and "
                   "3..1000000 segments, found length %g, radius %g, %d segments",
                   len, radius, nseg);
        return 1;
    }
    for (int d = 0; d < 3; d++) u[d] /= len;
    /* e1, e2, u right-handed */
    e1[0] = fabs(u[0]) < 0.9 ? 1.0 : 0.0;
    e1[1] = 1.0 - e1[0];
    e1[2] = 0.0;
    dot = e1[0] * u[0] + e1[1] * u[1];
    for (int d = 0; d < 3; d++) e1[d] -= dot * u[d];
    len = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int d = 0; d < 3; d++) e1[d] /= len;
    e2[0] = u[1] * e1[2] - u[2] * e1[1];
    e2[1] = u[2] * e1[0] - u[0] * e1[2];
    e2[2] = u[0] * e1[1] - u[1] * e1[0];
    n = (uint32_t)nseg;
    for (uint32_t i = 0; i < n; i++) { /* vertex 2i: bottom ring, 2i + 1: top ring */
        double th = 2.0 * M_PI * i / n, c = radius * cos(th), s = radius * sin(th);
        for (int k = 0; k < 2; k++) {
            const double *o = k ? b : a;
            (void)mesh_add_vertex(m, o[0] + c * e1[0] + s * e2[0], o[1] + c * e1[1] + s * e2[1],
                                  o[2] + c * e1[2] + s * e2[2]);
        }
    }
    ca = mesh_add_vertex(m, a[0], a[1], a[2]);
    cb = mesh_add_vertex(m, b[0], b[1], b[2]);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = (i + 1) % n;
        uint32_t b0 = 2 * i, b1 = 2 * j, t0 = 2 * i + 1, t1 = 2 * j + 1;
        mesh_add_triangle(m, b0, b1, t1); /* side: (e_theta x u) = outward */
        mesh_add_triangle(m, b0, t1, t0);
        mesh_add_triangle(m, ca, b1, b0); /* bottom cap: -u */
        mesh_add_triangle(m, cb, t0, t1); /* top cap: +u */
    }
    mesh_index_build(m);
    return 0;
}
