/*
 * srf_contour: marching cubes (Lorensen & Cline 1987) with a generated case
 * table and shared vertices, threaded over grid planes (see surface.h).
 *
 * The table.  Corner c of a cube sits at offset (c & 1, c >> 1 & 1,
 * c >> 2 & 1); edge 4 d + m joins the m-th corner with bit d clear to the
 * corner one step along axis d.  For each of the 256 inside/outside
 * patterns, each face is walked counter-clockwise seen from outside the
 * cube; every run of inside corners gives one segment, from the edge where
 * the walk enters the run to the edge where it leaves it (so an ambiguous
 * face, inside corners diagonally apart, gets two segments: the inside
 * corners are cut off).  An edge of the cube lies on two faces walked in
 * opposite directions, so it is entered on one and left on the other: the
 * segments link into closed loops, each triangulated as a fan.  The fan of
 * the loop entered this way has its normal pointing out of the inside (for
 * the one-corner pattern: loop x-edge, y-edge, z-edge, normal (1, 1, 1)).
 *
 * The vertices.  One per crossed grid edge, numbered by plane k: the
 * x-edges of plane k (row by row), its y-edges, then the z-edges from k to
 * k + 1.  A first pass counts them (and the triangles of each slab of
 * cubes between planes k and k + 1), prefix sums give every plane's first
 * vertex and every slab's first triangle, and a second pass fills them:
 * the result does not depend on the thread count.
 */
#include "surface/surface.h"

#include "core/sl_mem.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define SRF_MAX_TRI 12 /* triangles of one pattern: at most 12 crossed edges, 2 per loop */

typedef struct srf_table {
    signed char edge[12][2]; /* corners of each cube edge */
    unsigned char ntri[256];
    signed char tri[256][3 * SRF_MAX_TRI]; /* cube edges, three per triangle */
} srf_table;

static int edge_of(const srf_table *t, int a, int b)
{
    for (int e = 0; e < 12; e++)
        if ((t->edge[e][0] == a && t->edge[e][1] == b) ||
            (t->edge[e][0] == b && t->edge[e][1] == a))
            return e;
    return -1;
}

/* The four corners of face (axis a, side s), counter-clockwise seen from
 * outside: (u, v, a) is right-handed, so the cycle (0,0) (1,0) (1,1) (0,1)
 * in (u, v) turns counter-clockwise about +a; side 0 reverses it. */
static void face_corners(int a, int s, int q[4])
{
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    const int cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
    for (int m = 0; m < 4; m++) {
        const int mm = s ? m : (4 - m) % 4;
        q[m] = (s << a) | (cu[mm] << u) | (cv[mm] << v);
    }
}

/* Whether cube edges e and f lie on a common face of the cube. */
static int share_face(const srf_table *t, int e, int f)
{
    const int de = e / 4, df = f / 4, ce = t->edge[e][0], cf = t->edge[f][0];
    for (int d = 0; d < 3; d++)
        if (d != de && d != df && (ce >> d & 1) == (cf >> d & 1)) return 1;
    return 0;
}

/* The fan's apex: a vertex of the loop whose diagonals (to the vertices
 * not next to it) each cross the cube's inside.  A diagonal lying on a
 * face would be the same vertex pair as a diagonal of the neighbouring
 * cube, and that edge would have four triangles.  The first such vertex;
 * every loop of the 256 patterns has one (tests/unit/test_surface meets
 * every pattern and checks that each edge has two triangles). */
static int fan_apex(const srf_table *t, const int *loop, int len)
{
    for (int a = 0; a < len; a++) {
        int ok = 1;
        for (int i = 2; ok && i + 1 < len; i++) ok = !share_face(t, loop[a], loop[(a + i) % len]);
        if (ok) return a;
    }
    return -1;
}

static void table_pattern(srf_table *t, int pat)
{
    int next[12];
    for (int e = 0; e < 12; e++) next[e] = -1;
    for (int a = 0; a < 3; a++)
        for (int s = 0; s < 2; s++) {
            int q[4], in[4];
            face_corners(a, s, q);
            for (int m = 0; m < 4; m++) in[m] = pat >> q[m] & 1;
            for (int m = 0; m < 4; m++) {
                const int prev = (m + 3) % 4;
                if (!in[m] || in[prev]) continue;
                int last = m;
                while (in[(last + 1) % 4]) last = (last + 1) % 4;
                const int entry = edge_of(t, q[prev], q[m]);
                next[entry] = edge_of(t, q[last], q[(last + 1) % 4]);
            }
        }
    int seen[12] = {0}, n = 0;
    for (int e0 = 0; e0 < 12; e0++) {
        if (next[e0] < 0 || seen[e0]) continue;
        int loop[12], len = 0;
        for (int e = e0; !seen[e]; e = next[e]) {
            seen[e] = 1;
            loop[len++] = e;
        }
        const int a = fan_apex(t, loop, len) < 0 ? 0 : fan_apex(t, loop, len);
        for (int i = 1; i + 1 < len; i++) {
            t->tri[pat][3 * n] = (signed char)loop[a];
            t->tri[pat][3 * n + 1] = (signed char)loop[(a + i) % len];
            t->tri[pat][3 * n + 2] = (signed char)loop[(a + i + 1) % len];
            n++;
        }
    }
    t->ntri[pat] = (unsigned char)n;
}

static void table_build(srf_table *t)
{
    memset(t, 0, sizeof *t);
    for (int d = 0, e = 0; d < 3; d++)
        for (int c = 0; c < 8; c++)
            if (!(c >> d & 1)) {
                t->edge[e][0] = (signed char)c;
                t->edge[e][1] = (signed char)(c | 1 << d);
                e++;
            }
    for (int pat = 0; pat < 256; pat++) table_pattern(t, pat);
}

/* ---- the grid ---------------------------------------------------------- */

typedef struct srf_scan {
    const srf_grid *g;
    float iso;
    size_t nx, ny, nxy;
} srf_scan;

static int above(const srf_scan *s, size_t at) { return s->g->f[at] > s->iso; }

static int crossed(const srf_scan *s, size_t a, size_t b) { return above(s, a) != above(s, b); }

/* The pattern of the cube whose lowest corner is grid point `at`. */
static int pattern(const srf_scan *s, size_t at)
{
    int pat = 0;
    for (int c = 0; c < 8; c++) {
        size_t p =
            at + (size_t)(c & 1) + (size_t)(c >> 1 & 1) * s->nx + (size_t)(c >> 2 & 1) * s->nxy;
        pat |= above(s, p) << c;
    }
    return pat;
}

/* Crossed x-edges, y-edges of plane k; z-edges from k to k + 1. */
static void count_plane(const srf_scan *s, int k, size_t *cx, size_t *cy, size_t *cz)
{
    const size_t base = (size_t)k * s->nxy;
    const int top = k + 1 < s->g->nc[2];
    *cx = *cy = *cz = 0;
    for (size_t j = 0; j < s->ny; j++)
        for (size_t i = 0; i < s->nx; i++) {
            const size_t at = base + j * s->nx + i;
            if (i + 1 < s->nx) *cx += (size_t)crossed(s, at, at + 1);
            if (j + 1 < s->ny) *cy += (size_t)crossed(s, at, at + s->nx);
            if (top) *cz += (size_t)crossed(s, at, at + s->nxy);
        }
}

/* Vertex numbers of the crossed edges of plane k, from `first`: x-edges
 * into ix, y-edges into iy, and (ix, iy, iz non-NULL) z-edges into iz;
 * with m non-NULL also the vertices' positions. */
static void number_plane(const srf_scan *s, int k, int64_t first, int64_t *ix, int64_t *iy,
                         int64_t *iz, srf_mesh *m)
{
    const srf_grid *g = s->g;
    const size_t base = (size_t)k * s->nxy;
    int64_t id = first;
    for (int d = 0; d < 3; d++) {
        int64_t *out = d == 0 ? ix : d == 1 ? iy : iz;
        if (!out) continue;
        const size_t step = d == 0 ? 1 : d == 1 ? s->nx : s->nxy;
        for (size_t j = 0; j < s->ny; j++)
            for (size_t i = 0; i < s->nx; i++) {
                const size_t at = base + j * s->nx + i;
                const int inside = d == 0 ? i + 1 < s->nx : d == 1 ? j + 1 < s->ny : 1;
                if (!inside || !crossed(s, at, at + step)) continue;
                out[j * s->nx + i] = id;
                if (m) {
                    const double fa = g->f[at], fb = g->f[at + step];
                    const double t = ((double)s->iso - fa) / (fb - fa);
                    double p[3] = {(double)i, (double)j, (double)k};
                    p[d] += t;
                    m->x[id] = g->lo[0] + p[0] * g->dx;
                    m->y[id] = g->lo[1] + p[1] * g->dx;
                    m->z[id] = g->lo[2] + p[2] * g->dx;
                }
                id++;
            }
    }
}

void srf_contour(const srf_grid *g, double iso, srf_mesh *m)
{
    srf_table *t = sl_malloc(sizeof *t, "marching cubes table");
    srf_scan s = {g, (float)iso, (size_t)g->nc[0], (size_t)g->nc[1], 0};
    s.nxy = s.nx * s.ny;
    const int nz = g->nc[2];
    table_build(t);
    size_t *cnt = sl_calloc(4 * (size_t)nz, sizeof *cnt, "surface counts"); /* x y z tri */
    int64_t *voff = sl_calloc((size_t)nz + 1, sizeof *voff, "surface offsets");
    int64_t *toff = sl_calloc((size_t)nz + 1, sizeof *toff, "surface offsets");
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < nz; k++) {
        size_t *c = cnt + 4 * (size_t)k;
        count_plane(&s, k, &c[0], &c[1], &c[2]);
        if (k + 1 < nz)
            for (size_t j = 0; j + 1 < s.ny; j++)
                for (size_t i = 0; i + 1 < s.nx; i++)
                    c[3] += t->ntri[pattern(&s, (size_t)k * s.nxy + j * s.nx + i)];
    }
    for (int k = 0; k < nz; k++) {
        const size_t *c = cnt + 4 * (size_t)k;
        voff[k + 1] = voff[k] + (int64_t)(c[0] + c[1] + c[2]);
        toff[k + 1] = toff[k] + (int64_t)c[3];
    }
    memset(m, 0, sizeof *m);
    m->nv = (size_t)voff[nz];
    m->nt = (size_t)toff[nz];
    m->dx = g->dx;
    memcpy(m->nc, g->nc, sizeof m->nc);
    const size_t nv = m->nv ? m->nv : 1;
    m->x = sl_malloc(nv * sizeof(double), "surface vertices");
    m->y = sl_malloc(nv * sizeof(double), "surface vertices");
    m->z = sl_malloc(nv * sizeof(double), "surface vertices");
    m->tri = sl_malloc((m->nt ? 3 * m->nt : 1) * sizeof *m->tri, "surface triangles");
#pragma omp parallel
    {
        /* ids of plane k's x, y edges, the z edges, plane k + 1's x, y edges */
        int64_t *ids = sl_malloc(5 * s.nxy * sizeof *ids, "surface edge numbers");
        int64_t *ix0 = ids, *iy0 = ids + s.nxy, *iz = ids + 2 * s.nxy, *ix1 = ids + 3 * s.nxy,
                *iy1 = ids + 4 * s.nxy;
#pragma omp for schedule(dynamic, 1)
        for (int k = 0; k < nz; k++) {
            const size_t *c = cnt + 4 * (size_t)k;
            if (k + 1 == nz) { /* the last plane: its vertices only */
                if (c[0] + c[1]) number_plane(&s, k, voff[k], ix0, iy0, NULL, m);
                continue;
            }
            if (c[0] + c[1] + c[2] == 0 && c[3] == 0) continue;
            number_plane(&s, k, voff[k], ix0, iy0, iz, m);
            number_plane(&s, k + 1, voff[k + 1], ix1, iy1, NULL, NULL);
            int64_t *tri = m->tri + 3 * toff[k];
            for (size_t j = 0; j + 1 < s.ny; j++)
                for (size_t i = 0; i + 1 < s.nx; i++) {
                    const int pat = pattern(&s, (size_t)k * s.nxy + j * s.nx + i);
                    for (int e3 = 0; e3 < 3 * t->ntri[pat]; e3++) {
                        const int e = t->tri[pat][e3], c0 = t->edge[e][0], d = e / 4;
                        const size_t ci = i + (size_t)(c0 & 1), cj = j + (size_t)(c0 >> 1 & 1);
                        const size_t at = cj * s.nx + ci;
                        const int up = c0 >> 2 & 1;
                        *tri++ = d == 2 ? iz[at]
                            : d == 0    ? (up ? ix1 : ix0)[at]
                                        : (up ? iy1 : iy0)[at];
                    }
                }
        }
        free(ids);
    }
    free(cnt);
    free(voff);
    free(toff);
    free(t);
}
