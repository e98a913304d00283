/* mesh_distance: exact point-mesh distance with a bounding-volume hierarchy,
 * signed by angle-weighted pseudo-normals (J. A. Baerentzen and H. Aanaes,
 * "Signed distance computation using the angle weighted pseudonormal",
 * IEEE TVCG 11(3), 2005).  See mesh.h.
 *
 * The closest point c on the mesh lies in the interior of a face, on an
 * edge or at a vertex; sign(d) = sign((p - c) . n) with n the face normal,
 * the sum of the two face normals of the edge, or the angle-weighted sum of
 * the face normals around the vertex.  A closest point within 1e-9 (in
 * barycentric terms) of an edge or a vertex is snapped to it, so that the
 * triangles sharing that feature agree on its normal.
 *
 * The hierarchy splits the triangles at the median of their centroids along
 * the longest axis, so its depth is at most log2(nt) + 1 and the traversal
 * stack below has a proven bound, not a capacity limit.
 *
 * Deep inside (or far outside) a body every triangle is nearly equally far,
 * so exact queries there are slow.  mesh_signed_distance_bounded avoids
 * them with a coarse grid: cells no triangle touches form connected
 * regions of one sign each, found by one exact query per region. */
#include "geometry/mesh.h"

#include "core/sl_mem.h"
#include "geometry/mesh_progress.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#define LEAF_SIZE 4
#define MAX_DEPTH 96 /* > log2(2^32) + 1 with margin */
#define SNAP      1e-9

typedef struct bvh_node {
    double lo[3], hi[3];
    uint32_t first; /* leaf: first slot; inner: right child (left child is next) */
    uint32_t count; /* triangles in a leaf, 0 for inner nodes */
} bvh_node;

struct mesh_index {
    size_t nt, nnode;
    double *tri;      /* 9 per slot: corners a, b, c in hierarchy order */
    double *fn;       /* 3 per slot: unit face normal */
    uint32_t *id;     /* slot -> triangle */
    uint32_t *corner; /* 3 per slot: vertex ids */
    uint32_t *edge;   /* 3 per slot: edge ids (ab, bc, ca) */
    double *vn;       /* 3 per vertex: angle-weighted pseudo-normal */
    double *en;       /* 3 per edge: sum of the face normals */
    bvh_node *node;
    /* sign grid for mesh_signed_distance_bounded: 0 for cells the surface
     * may touch, else the sign shared by every point of the cell */
    double glo[3], gcell;
    size_t gn[3];
    int8_t *gsign;
};

void mesh_index_free(mesh_index *ix)
{
    if (!ix) return;
    free(ix->tri);
    free(ix->fn);
    free(ix->id);
    free(ix->corner);
    free(ix->edge);
    free(ix->vn);
    free(ix->en);
    free(ix->node);
    free(ix->gsign);
    free(ix);
}

/* ---- building ----------------------------------------------------------- */

static double angle_at(const double *a, const double *b, const double *c)
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double x[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    return atan2(sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]),
                 u[0] * w[0] + u[1] * w[1] + u[2] * w[2]);
}

static void pseudo_normals(const mesh *m, const mesh_topology *tp, mesh_index *ix)
{
    ix->vn = sl_calloc(3 * (m->nv ? m->nv : 1), sizeof *ix->vn, "vertex pseudo-normals");
    ix->en = sl_calloc(3 * (tp->ne ? tp->ne : 1), sizeof *ix->en, "edge pseudo-normals");
    for (size_t j = 0; j < m->nt; j++) {
        double n[3];
        mesh_triangle_normal(m, j, n);
        for (int k = 0; k < 3; k++) {
            const double *p = m->v + 3 * m->t[3 * j + k];
            const double *q = m->v + 3 * m->t[3 * j + (k + 1) % 3];
            const double *r = m->v + 3 * m->t[3 * j + (k + 2) % 3];
            double w = angle_at(p, q, r);
            for (int d = 0; d < 3; d++) {
                ix->vn[3 * m->t[3 * j + k] + d] += w * n[d];
                ix->en[3 * tp->tedge[3 * j + k] + d] += n[d];
            }
        }
    }
}

typedef struct build_ctx {
    const mesh *m;
    double *cen;    /* 3 per triangle: centroid */
    uint32_t *perm; /* slot -> triangle while building */
    bvh_node *node;
    size_t nnode;
    size_t work; /* triangles scanned so far: the build's cost (progress) */
    mesh_progress *mp;
} build_ctx;

/* Partially sort perm[lo, hi) so that perm[k] has the k-th centroid along
 * axis d, smaller or equal ones before it and larger or equal ones after
 * (N. Wirth's FIND). */
static void select_kth(build_ctx *b, size_t lo, size_t hi, size_t k, int d)
{
    uint32_t *p = b->perm;
    const double *c = b->cen;
    ptrdiff_t l = (ptrdiff_t)lo, r = (ptrdiff_t)hi - 1, kk = (ptrdiff_t)k;
    while (l < r) {
        double x = c[3 * p[kk] + d];
        ptrdiff_t i = l, j = r;
        do {
            while (c[3 * p[i] + d] < x) i++;
            while (x < c[3 * p[j] + d]) j--;
            if (i <= j) {
                uint32_t s = p[i];
                p[i] = p[j];
                p[j] = s;
                i++;
                j--;
            }
        } while (i <= j);
        if (j < kk) l = i;
        if (kk < i) r = j;
    }
}

static size_t build_node(build_ctx *b, size_t lo, size_t hi, int depth)
{
    size_t me = b->nnode++;
    bvh_node *n = &b->node[me];
    double clo[3], chi[3];
    int axis = 0;
    if (depth >= MAX_DEPTH) sl_fatal("mesh index: hierarchy deeper than %d", MAX_DEPTH);
    b->work += hi - lo; /* each level scans (and splits) every triangle once */
    mesh_progress_at(b->mp, b->work);
    for (int d = 0; d < 3; d++) {
        n->lo[d] = clo[d] = INFINITY;
        n->hi[d] = chi[d] = -INFINITY;
    }
    for (size_t s = lo; s < hi; s++) {
        uint32_t j = b->perm[s];
        for (int k = 0; k < 3; k++) {
            const double *v = b->m->v + 3 * b->m->t[3 * j + k];
            for (int d = 0; d < 3; d++) {
                n->lo[d] = fmin(n->lo[d], v[d]);
                n->hi[d] = fmax(n->hi[d], v[d]);
            }
        }
        for (int d = 0; d < 3; d++) {
            clo[d] = fmin(clo[d], b->cen[3 * j + d]);
            chi[d] = fmax(chi[d], b->cen[3 * j + d]);
        }
    }
    if (hi - lo <= LEAF_SIZE) {
        n->first = (uint32_t)lo;
        n->count = (uint32_t)(hi - lo);
        return me;
    }
    for (int d = 1; d < 3; d++)
        if (chi[d] - clo[d] > chi[axis] - clo[axis]) axis = d;
    select_kth(b, lo, hi, lo + (hi - lo) / 2, axis);
    build_node(b, lo, lo + (hi - lo) / 2, depth + 1);
    {
        size_t right = build_node(b, lo + (hi - lo) / 2, hi, depth + 1);
        b->node[me].first = (uint32_t)right;
        b->node[me].count = 0;
    }
    return me;
}

static void build_sign_grid(mesh_index *ix, const mesh *m);

void mesh_index_build(mesh *m)
{
    mesh_index *ix = sl_calloc(1, sizeof *ix, "a mesh index");
    mesh_topology tp;
    mesh_progress mp;
    build_ctx b = {.m = m, .mp = &mp};
    size_t nt = m->nt;
    mesh_touch(m);
    if (nt > UINT32_MAX / 2) sl_fatal("mesh index: %zu triangles are too many", nt);
    mesh_topology_build(m, &tp);
    pseudo_normals(m, &tp, ix);
    b.cen = sl_malloc(3 * (nt ? nt : 1) * sizeof *b.cen, "triangle centroids");
    b.perm = sl_malloc((nt ? nt : 1) * sizeof *b.perm, "a mesh index");
    b.node = sl_malloc((2 * nt + 1) * sizeof *b.node, "a mesh index");
    for (size_t j = 0; j < nt; j++) {
        b.perm[j] = (uint32_t)j;
        for (int d = 0; d < 3; d++)
            b.cen[3 * j + d] = (m->v[3 * m->t[3 * j] + d] + m->v[3 * m->t[3 * j + 1] + d] +
                                m->v[3 * m->t[3 * j + 2] + d]) /
                3.0;
    }
    size_t levels = 1;
    while ((nt >> levels) > LEAF_SIZE) levels++;
    mesh_progress_start(&mp, nt * (levels + 1), "indexing a mesh of %zu triangles", nt);
    if (nt) build_node(&b, 0, nt, 0);
    mesh_progress_end(&mp);
    ix->nt = nt;
    ix->nnode = b.nnode;
    ix->node = b.node;
    ix->id = b.perm;
    ix->tri = sl_malloc(9 * (nt ? nt : 1) * sizeof *ix->tri, "a mesh index");
    ix->fn = sl_malloc(3 * (nt ? nt : 1) * sizeof *ix->fn, "a mesh index");
    ix->corner = sl_malloc(3 * (nt ? nt : 1) * sizeof *ix->corner, "a mesh index");
    ix->edge = sl_malloc(3 * (nt ? nt : 1) * sizeof *ix->edge, "a mesh index");
    for (size_t s = 0; s < nt; s++) {
        uint32_t j = ix->id[s];
        mesh_triangle_normal(m, j, ix->fn + 3 * s);
        for (int k = 0; k < 3; k++) {
            ix->corner[3 * s + k] = m->t[3 * j + k];
            ix->edge[3 * s + k] = tp.tedge[3 * j + k];
            memcpy(ix->tri + 9 * s + 3 * k, m->v + 3 * m->t[3 * j + k], 3 * sizeof(double));
        }
    }
    free(b.cen);
    mesh_topology_free(&tp);
    build_sign_grid(ix, m);
    m->index = ix;
}

/* ---- queries ------------------------------------------------------------- */

enum { R_FACE, R_VA, R_VB, R_VC, R_AB, R_BC, R_CA };

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Closest point on segment [a, b] to p: parameter t in [0, 1]. */
static double segment_t(const double *p, const double *a, const double *b)
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double l2 = dot3(ab, ab), t = l2 > 0.0 ? dot3(ap, ab) / l2 : 0.0;
    return t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
}

/* Region code of a point on edge k (0: ab, 1: bc, 2: ca) at parameter t. */
static int edge_region(int k, double t)
{
    if (t <= SNAP) return R_VA + k;
    if (t >= 1.0 - SNAP) return R_VA + (k + 1) % 3;
    return R_AB + k;
}

/* Closest point c on triangle (a, b, c) to p (C. Ericson, Real-Time
 * Collision Detection, 5.1.5), returning its region code. */
static int closest_on_triangle(const double *p, const double *tri, double c[3])
{
    const double *a = tri, *b = tri + 3, *cc = tri + 6;
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    double d1, d2, d3, d4, d5, d6, va, vb, vc, denom, v, w;
    for (int d = 0; d < 3; d++) {
        ab[d] = b[d] - a[d];
        ac[d] = cc[d] - a[d];
        ap[d] = p[d] - a[d];
        bp[d] = p[d] - b[d];
        cp[d] = p[d] - cc[d];
    }
    d1 = dot3(ab, ap);
    d2 = dot3(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        memcpy(c, a, 3 * sizeof *c);
        return R_VA;
    }
    d3 = dot3(ab, bp);
    d4 = dot3(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        memcpy(c, b, 3 * sizeof *c);
        return R_VB;
    }
    d5 = dot3(ab, cp);
    d6 = dot3(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        memcpy(c, cc, 3 * sizeof *c);
        return R_VC;
    }
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        v = d1 / (d1 - d3);
        for (int d = 0; d < 3; d++) c[d] = a[d] + v * ab[d];
        return edge_region(0, v);
    }
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        w = d2 / (d2 - d6);
        for (int d = 0; d < 3; d++) c[d] = a[d] + w * ac[d];
        return edge_region(2, 1.0 - w);
    }
    va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int d = 0; d < 3; d++) c[d] = b[d] + w * (cc[d] - b[d]);
        return edge_region(1, w);
    }
    denom = va + vb + vc;
    if (!(denom > 0.0)) { /* degenerate triangle: nearest of its edges */
        double best = INFINITY;
        int reg = R_VA;
        for (int k = 0; k < 3; k++) {
            const double *s = tri + 3 * k, *e = tri + 3 * ((k + 1) % 3);
            double t = segment_t(p, s, e), q[3], d2q;
            for (int d = 0; d < 3; d++) q[d] = s[d] + t * (e[d] - s[d]);
            d2q = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                (q[2] - p[2]) * (q[2] - p[2]);
            if (d2q < best) {
                best = d2q;
                reg = edge_region(k, t);
                memcpy(c, q, sizeof q);
            }
        }
        return reg;
    }
    v = vb / denom;
    w = vc / denom;
    for (int d = 0; d < 3; d++) c[d] = a[d] + ab[d] * v + ac[d] * w;
    /* barycentric (1 - v - w, v, w): snap to an edge when one is ~0 */
    if (v <= SNAP) return edge_region(2, 1.0 - w);
    if (w <= SNAP) return edge_region(0, v);
    if (1.0 - v - w <= SNAP) return edge_region(1, w);
    return R_FACE;
}

static double box_dist2(const bvh_node *n, const double p[3])
{
    double s = 0.0;
    for (int d = 0; d < 3; d++) {
        double e = p[d] < n->lo[d] ? n->lo[d] - p[d] : p[d] > n->hi[d] ? p[d] - n->hi[d] : 0.0;
        s += e * e;
    }
    return s;
}

typedef struct hit {
    double d2, c[3];
    size_t slot;
    int region;
} hit;

/* Nearest point among triangles closer than sqrt(bound2); h->d2 = bound2
 * if there is none. */
static void nearest(const mesh_index *ix, const double p[3], double bound2, hit *h)
{
    struct {
        uint32_t node;
        double d2;
    } stack[MAX_DEPTH + 2];
    int top = 0;
    h->d2 = bound2;
    memcpy(h->c, p, sizeof h->c);
    h->slot = 0;
    h->region = R_FACE;
    if (ix->nt == 0) return;
    stack[top].node = 0;
    stack[top++].d2 = box_dist2(&ix->node[0], p);
    while (top > 0) {
        const bvh_node *n;
        top--;
        if (stack[top].d2 >= h->d2) continue;
        n = &ix->node[stack[top].node];
        if (n->count) {
            for (uint32_t s = n->first; s < n->first + n->count; s++) {
                double c[3], d2;
                int reg = closest_on_triangle(p, ix->tri + 9 * (size_t)s, c);
                d2 = (c[0] - p[0]) * (c[0] - p[0]) + (c[1] - p[1]) * (c[1] - p[1]) +
                    (c[2] - p[2]) * (c[2] - p[2]);
                if (d2 < h->d2) {
                    h->d2 = d2;
                    h->slot = s;
                    h->region = reg;
                    memcpy(h->c, c, sizeof c);
                }
            }
        } else {
            uint32_t l = (uint32_t)(n - ix->node) + 1, r = n->first;
            double dl = box_dist2(&ix->node[l], p), dr = box_dist2(&ix->node[r], p);
            /* push the farther child first: the nearer one is searched first */
            if (dl < dr) {
                stack[top].node = r;
                stack[top++].d2 = dr;
                stack[top].node = l;
                stack[top++].d2 = dl;
            } else {
                stack[top].node = l;
                stack[top++].d2 = dl;
                stack[top].node = r;
                stack[top++].d2 = dr;
            }
        }
    }
}

static const mesh_index *need_index(const mesh *m)
{
    if (!m->index)
        sl_fatal("mesh distance query without an index (call mesh_validate or "
                 "mesh_index_build after changing the mesh)");
    return m->index;
}

double mesh_closest_point(const mesh *m, const double p[3], double c[3], size_t *tri)
{
    const mesh_index *ix = need_index(m);
    hit h;
    nearest(ix, p, INFINITY, &h);
    if (c) memcpy(c, h.c, sizeof h.c);
    if (tri) *tri = ix->nt ? ix->id[h.slot] : 0;
    return sqrt(h.d2);
}

double mesh_closest_point_within(const mesh *m, const double p[3], double dmax, double c[3],
                                 size_t *tri)
{
    const mesh_index *ix = need_index(m);
    hit h;
    nearest(ix, p, dmax * dmax, &h);
    if (!(h.d2 < dmax * dmax)) return INFINITY;
    if (c) memcpy(c, h.c, sizeof h.c);
    if (tri) *tri = ix->id[h.slot];
    return sqrt(h.d2);
}

/* Signed distance from the hit h of a nearest search. */
static double signed_of_hit(const mesh_index *ix, const double p[3], const hit *h)
{
    const double *n;
    double dp[3], d;
    switch (h->region) {
    case R_FACE:
        n = ix->fn + 3 * h->slot;
        break;
    case R_VA:
    case R_VB:
    case R_VC:
        n = ix->vn + 3 * (size_t)ix->corner[3 * h->slot + (h->region - R_VA)];
        break;
    default:
        n = ix->en + 3 * (size_t)ix->edge[3 * h->slot + (h->region - R_AB)];
        break;
    }
    for (int k = 0; k < 3; k++) dp[k] = p[k] - h->c[k];
    d = sqrt(h->d2);
    return dot3(dp, n) < 0.0 ? -d : d;
}

double mesh_signed_distance(const mesh *m, const double p[3])
{
    const mesh_index *ix = need_index(m);
    hit h;
    if (ix->nt == 0) return INFINITY;
    nearest(ix, p, INFINITY, &h);
    return signed_of_hit(ix, p, &h);
}

/* Cell of p in the sign grid, or (size_t)-1 outside it. */
static size_t grid_cell(const mesh_index *ix, const double p[3])
{
    size_t c[3];
    if (isinf(ix->gcell)) return 0; /* the one-cell grid of absurd coordinates */
    for (int d = 0; d < 3; d++) {
        double f = floor((p[d] - ix->glo[d]) / ix->gcell);
        if (!(f >= 0.0 && f < (double)ix->gn[d])) return (size_t)-1;
        c[d] = (size_t)f;
    }
    return c[0] + ix->gn[0] * (c[1] + ix->gn[1] * c[2]);
}

double mesh_signed_distance_bounded(const mesh *m, const double p[3], double dmax)
{
    const mesh_index *ix = need_index(m);
    size_t c;
    hit h;
    if (ix->nt == 0) return INFINITY;
    nearest(ix, p, dmax * dmax, &h);
    if (h.d2 < dmax * dmax) return signed_of_hit(ix, p, &h);
    c = grid_cell(ix, p);
    if (c == (size_t)-1) return dmax; /* outside the bounding box */
    if (ix->gsign[c]) return ix->gsign[c] * dmax;
    return mesh_signed_distance(m, p); /* near the surface: exact and cheap */
}

/* ---- the sign grid ----------------------------------------------------------- */

#define GRID_MIN_CELLS 32768.0
#define GRID_MAX_CELLS 8388608.0
#define GRID_MARGIN    2
#define GRID_MAX_WORK  64.0 /* lattice points per cell beyond which there is no grid */

/* Mark the cells that triangle j may touch: the cell of every point of a
 * barycentric lattice no coarser than a cell, and their 26 neighbours (a
 * point of the triangle is within one lattice step of a lattice point). */
/* Lattice steps per edge for triangle tri: its longest edge / cell. */
static long lattice_steps(const mesh_index *ix, const double *tri)
{
    double emax = 0.0;
    for (int k = 0; k < 3; k++) {
        const double *a = tri + 3 * k, *b = tri + 3 * ((k + 1) % 3);
        double e = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                        (a[2] - b[2]) * (a[2] - b[2]));
        emax = fmax(emax, e);
    }
    emax = ceil(emax / ix->gcell);
    return emax < 1.0 ? 1 : (long)emax; /* <= the grid's diagonal in cells */
}

static void mark_triangle(mesh_index *ix, const double *tri)
{
    long n = lattice_steps(ix, tri);
    for (long i = 0; i <= n; i++)
        for (long j = 0; i + j <= n; j++) {
            double u = (double)i / (double)n, v = (double)j / (double)n, q[3];
            long c[3];
            for (int d = 0; d < 3; d++) {
                q[d] = tri[d] + u * (tri[3 + d] - tri[d]) + v * (tri[6 + d] - tri[d]);
                c[d] = (long)floor((q[d] - ix->glo[d]) / ix->gcell);
            }
            for (long dz = -1; dz <= 1; dz++)
                for (long dy = -1; dy <= 1; dy++)
                    for (long dx = -1; dx <= 1; dx++) {
                        long x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
                        if (x < 0 || y < 0 || z < 0 || x >= (long)ix->gn[0] ||
                            y >= (long)ix->gn[1] || z >= (long)ix->gn[2])
                            continue;
                        ix->gsign[(size_t)x + ix->gn[0] * ((size_t)y + ix->gn[1] * (size_t)z)] = 0;
                    }
        }
}

/* Give each 6-connected region of untouched cells the sign of the exact
 * distance at one of its cell centres: no surface separates its cells. */
static void label_regions(mesh_index *ix)
{
    size_t nc = ix->gn[0] * ix->gn[1] * ix->gn[2], *stack;
    const size_t step[3] = {1, ix->gn[0], ix->gn[0] * ix->gn[1]};
    stack = sl_malloc(nc * sizeof *stack, "a sign grid");
    for (size_t seed = 0; seed < nc; seed++) {
        size_t top = 0,
               q[3] = {seed % ix->gn[0], seed / ix->gn[0] % ix->gn[1],
                       seed / (ix->gn[0] * ix->gn[1])};
        double p[3];
        int8_t sign;
        hit h;
        if (ix->gsign[seed] != 2) continue; /* surface, or labelled already */
        for (int d = 0; d < 3; d++) p[d] = ix->glo[d] + ((double)q[d] + 0.5) * ix->gcell;
        nearest(ix, p, INFINITY, &h);
        sign = signed_of_hit(ix, p, &h) < 0.0 ? -1 : 1;
        ix->gsign[seed] = sign;
        stack[top++] = seed;
        while (top) {
            size_t c = stack[--top],
                   cc[3] = {c % ix->gn[0], c / ix->gn[0] % ix->gn[1], c / (ix->gn[0] * ix->gn[1])};
            for (int d = 0; d < 3; d++)
                for (int s = -1; s <= 1; s += 2) {
                    size_t o;
                    if ((s < 0 && cc[d] == 0) || (s > 0 && cc[d] + 1 == ix->gn[d])) continue;
                    o = s < 0 ? c - step[d] : c + step[d];
                    if (ix->gsign[o] != 2) continue;
                    ix->gsign[o] = sign;
                    stack[top++] = o;
                }
        }
    }
    free(stack);
}

static void build_sign_grid(mesh_index *ix, const mesh *m)
{
    double lo[3], hi[3], emax = 0.0, target = 8.0 * (double)m->nt, nc, work = 0.0;
    if (target < GRID_MIN_CELLS) target = GRID_MIN_CELLS;
    if (target > GRID_MAX_CELLS) target = GRID_MAX_CELLS;
    mesh_bounds(m, lo, hi);
    for (int d = 0; d < 3; d++) emax = fmax(emax, hi[d] - lo[d]);
    ix->gcell = emax > 0.0 ? emax / cbrt(target) : 1.0;
    if (!isfinite(emax) || !isfinite(ix->gcell) || !(ix->gcell > 0.0)) {
        /* absurd coordinates: one cell the surface touches, exact queries */
        for (int d = 0; d < 3; d++) {
            ix->gn[d] = 1;
            ix->glo[d] = -INFINITY;
        }
        ix->gcell = INFINITY;
        ix->gsign = sl_calloc(1, 1, "a sign grid");
        return;
    }
    nc = 1.0;
    for (int d = 0; d < 3; d++) {
        ix->gn[d] = (size_t)ceil((hi[d] - lo[d]) / ix->gcell) + 2 * GRID_MARGIN;
        ix->glo[d] = lo[d] - GRID_MARGIN * ix->gcell;
        nc *= (double)ix->gn[d];
    }
    ix->gsign = sl_malloc((size_t)nc, "a sign grid");
    memset(ix->gsign, 2, (size_t)nc); /* 2: untouched, not labelled yet */
    if (ix->nt == 0) {
        memset(ix->gsign, 1, (size_t)nc);
        return;
    }
    /* Many huge triangles (a hostile or very odd mesh) would make the marking
     * slow: then no grid, and bounded queries are exact ones. */
    for (size_t s = 0; s < ix->nt; s++) {
        double n = (double)lattice_steps(ix, ix->tri + 9 * s);
        work += 0.5 * (n + 1.0) * (n + 2.0);
    }
    if (work > GRID_MAX_WORK * nc) {
        memset(ix->gsign, 0, (size_t)nc);
        return;
    }
    for (size_t s = 0; s < ix->nt; s++) mark_triangle(ix, ix->tri + 9 * s);
    label_regions(ix);
}

int mesh_inside(const mesh *m, const double p[3])
{
    const mesh_index *ix = need_index(m);
    size_t c;
    if (ix->nt == 0) return 0;
    c = grid_cell(ix, p);
    if (c == (size_t)-1) return 0;
    if (ix->gsign[c]) return ix->gsign[c] < 0;
    return mesh_signed_distance(m, p) < 0.0;
}
