/* mesh_sample: boundary particles on a triangle mesh: offset surface,
 * feature lines, Poisson-disk faces (see mesh_sample.h for the method). */
#include "core/sl_morton.h"
#include "geometry/mesh_sample.h"

#include "core/sl_mem.h"
#include "geometry/mesh_grid.h"
#include "geometry/mesh_progress.h"

#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FEATURE_SPACING 0.6  /* feature particles closer than this * r0 are skipped */
#define MAX_OFFSET      3.0  /* a vertex moves at most this * r0/2 (sharp spikes) */
#define REGULARISE      1e-4 /* weight of the pseudo-normal in the vertex offset */
#define MAX_PARTICLES   4e9  /* beyond 32-bit particle ids: surely a unit error */
#define RELAX_RANGE     1.25 /* relaxation: particles closer than this * r0 repel */
#define RELAX_GAIN      0.2  /* relaxation: fraction of the overlap removed per sweep */
#define RELAX_STEP      0.2  /* relaxation: largest move per sweep, * r0 */
#define RELAX_SKIN      0.3  /* relaxation: neighbour-list margin, * r0 */

typedef struct sampler {
    const mesh *m;
    double r0, cos_crease;
    double sign; /* +1 obstacle, -1 container */
    mesh_topology tp;
    double *fn;      /* 3 per triangle: unit normal into the fluid */
    double *angle;   /* 3 per triangle: interior angle at each corner */
    double *off;     /* 3 per vertex: offset position r0/2 behind the wall */
    double *vn;      /* 3 per vertex: angle-weighted pseudo-normal */
    double *cn;      /* 9 per triangle: smoothed corner normals */
    uint8_t *feat;   /* per edge: 1 if sampled as a line */
    uint32_t *fdeg;  /* per vertex: feature edges at it */
    size_t *fstart;  /* per vertex + 1: CSR into fedge */
    uint32_t *fedge; /* feature edges by vertex */
    mgrid grid;      /* accepted particles */
    double *nrm;     /* 3 per accepted particle */
    size_t ncap;
} sampler;

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void normalise(double *a)
{
    double l = sqrt(dot3(a, a));
    if (l > 0.0)
        for (int d = 0; d < 3; d++) a[d] /= l;
}

msample_params msample_defaults(double r0, msample_side side)
{
    msample_params p = {.r0 = r0,
                        .side = side,
                        .min_spacing = 0.8,
                        .crease_angle = 30.0,
                        .darts = 10.0,
                        .relax = 20,
                        .seed = 1};
    return p;
}

/* Accept x unless a particle lies within r; returns 1 if accepted. */
static int accept(sampler *s, const double x[3], const double n[3], double r)
{
    size_t id;
    if (mgrid_nearest_within(&s->grid, x, r, MGRID_NONE, NULL) != MGRID_NONE) return 0;
    id = mgrid_insert(&s->grid, x);
    if (id == s->ncap) {
        s->ncap = s->ncap ? 2 * s->ncap : 1024;
        s->nrm = sl_realloc(s->nrm, 3 * s->ncap * sizeof *s->nrm, "sample normals");
    }
    memcpy(s->nrm + 3 * id, n, 3 * sizeof *n);
    normalise(s->nrm + 3 * id);
    return 1;
}

/* ---- normals, angles and the offset surface -------------------------------- */

static void face_data(sampler *s)
{
    const double sign = s->sign;
    const mesh *m = s->m;
    s->fn = sl_malloc(3 * m->nt * sizeof *s->fn, "face normals");
    s->angle = sl_malloc(3 * m->nt * sizeof *s->angle, "corner angles");
    for (size_t j = 0; j < m->nt; j++) {
        mesh_triangle_normal(m, j, s->fn + 3 * j);
        for (int d = 0; d < 3; d++) s->fn[3 * j + d] *= sign;
        for (int k = 0; k < 3; k++) {
            const double *a = m->v + 3 * m->t[3 * j + k];
            const double *b = m->v + 3 * m->t[3 * j + (k + 1) % 3];
            const double *c = m->v + 3 * m->t[3 * j + (k + 2) % 3];
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double x[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                           u[0] * w[1] - u[1] * w[0]};
            s->angle[3 * j + k] = atan2(sqrt(dot3(x, x)), dot3(u, w));
        }
    }
}

/* Solve A d = b for symmetric A (6 entries xx yy zz xy xz yz); 0 if singular. */
static int solve_sym3(const double a[6], const double b[3], double d[3])
{
    double c00 = a[1] * a[2] - a[5] * a[5], c01 = a[4] * a[5] - a[3] * a[2],
           c02 = a[3] * a[5] - a[4] * a[1], c11 = a[0] * a[2] - a[4] * a[4],
           c12 = a[3] * a[4] - a[0] * a[5], c22 = a[0] * a[1] - a[3] * a[3];
    double det = a[0] * c00 + a[3] * c01 + a[4] * c02;
    if (!(fabs(det) > 0.0)) return 0;
    d[0] = (c00 * b[0] + c01 * b[1] + c02 * b[2]) / det;
    d[1] = (c01 * b[0] + c11 * b[1] + c12 * b[2]) / det;
    d[2] = (c02 * b[0] + c12 * b[1] + c22 * b[2]) / det;
    return isfinite(d[0]) && isfinite(d[1]) && isfinite(d[2]);
}

/* Least squares A d = b (A = sum of w n n^T, b = -h sum of w n) by iterated
 * Tikhonov regularisation towards d = h0 n: exact where the face normals
 * fix d (box corners and edges get the exact mitre), d = h0 n along
 * directions they leave free (flat parts, the length of an edge). */
static int offset_solve(const double a[6], double eps, const double b[3], double h0,
                        const double n[3], double d[3])
{
    double r[6] = {a[0] + eps, a[1] + eps, a[2] + eps, a[3], a[4], a[5]}, rhs[3], delta[3];
    for (int k = 0; k < 3; k++) rhs[k] = b[k] + eps * h0 * n[k];
    if (!solve_sym3(r, rhs, d)) return 0;
    for (int it = 0; it < 6; it++) {
        rhs[0] = b[0] - (a[0] * d[0] + a[3] * d[1] + a[4] * d[2]);
        rhs[1] = b[1] - (a[3] * d[0] + a[1] * d[1] + a[5] * d[2]);
        rhs[2] = b[2] - (a[4] * d[0] + a[5] * d[1] + a[2] * d[2]);
        if (!solve_sym3(r, rhs, delta)) return 0;
        for (int k = 0; k < 3; k++) d[k] += delta[k];
    }
    return isfinite(d[0]) && isfinite(d[1]) && isfinite(d[2]);
}

/* Each vertex moves by d with d . n_f ~ -r0/2 for its faces f (least
 * squares, angle-weighted, nudged towards -r0/2 along the pseudo-normal
 * where the faces do not fix d).  Returns the number of clamped vertices. */
static size_t offset_vertices(sampler *s)
{
    const mesh *m = s->m;
    const double h = 0.5 * s->r0;
    double *a = sl_calloc(7 * m->nv, sizeof *a, "vertex offsets"); /* A (6), W */
    size_t clamped = 0;
    s->vn = sl_calloc(3 * m->nv, sizeof *s->vn, "vertex normals");
    s->off = sl_malloc(3 * m->nv * sizeof *s->off, "offset vertices");
    for (size_t j = 0; j < m->nt; j++)
        for (int k = 0; k < 3; k++) {
            size_t v = m->t[3 * j + k];
            const double *n = s->fn + 3 * j;
            double w = s->angle[3 * j + k], *q = a + 7 * v;
            q[0] += w * n[0] * n[0];
            q[1] += w * n[1] * n[1];
            q[2] += w * n[2] * n[2];
            q[3] += w * n[0] * n[1];
            q[4] += w * n[0] * n[2];
            q[5] += w * n[1] * n[2];
            q[6] += w;
            for (int d = 0; d < 3; d++) s->vn[3 * v + d] += w * n[d];
        }
    for (size_t v = 0; v < m->nv; v++) {
        double *q = a + 7 * v, nv[3], rhs[3], d[3] = {0, 0, 0}, len;
        const double eps = REGULARISE * q[6];
        memcpy(nv, s->vn + 3 * v, sizeof nv);
        for (int k = 0; k < 3; k++) rhs[k] = -h * (nv[k]);
        normalise(nv);
        if (!offset_solve(q, eps, rhs, -h, nv, d))
            for (int k = 0; k < 3; k++) d[k] = -h * nv[k];
        len = sqrt(dot3(d, d));
        if (len > MAX_OFFSET * h) {
            for (int k = 0; k < 3; k++) d[k] *= MAX_OFFSET * h / len;
            clamped++;
        }
        for (int k = 0; k < 3; k++) s->off[3 * v + k] = m->v[3 * v + k] + d[k];
    }
    free(a);
    return clamped;
}

/* Why triangles turned over: at an open rim, finer than r0 (next to a
 * sharp edge the offset of a small triangle folds), or in a part thinner
 * than r0 (the rest). */
typedef struct turned_count {
    size_t rim, fine, thin;
} turned_count;

static double max_edge2(const double *a, const double *b, const double *c)
{
    double m = 0.0;
    const double *p[4] = {a, b, c, a};
    for (int k = 0; k < 3; k++) {
        double d[3] = {p[k + 1][0] - p[k][0], p[k + 1][1] - p[k][1], p[k + 1][2] - p[k][2]};
        double l2 = dot3(d, d);
        if (l2 > m) m = l2;
    }
    return m;
}

static void classify_turned(const sampler *s, size_t j, turned_count *tc)
{
    const uint32_t *t = s->m->t + 3 * j;
    for (int k = 0; k < 3; k++)
        if (s->tp.ecount[s->tp.tedge[3 * j + k]] == 1) {
            tc->rim++;
            return;
        }
    const double *v = s->m->v;
    if (max_edge2(v + 3 * t[0], v + 3 * t[1], v + 3 * t[2]) < s->r0 * s->r0) tc->fine++;
    else tc->thin++;
}

/* Triangles whose offset turned over (normal reversed). */
static size_t count_turned(const sampler *s, turned_count *tc)
{
    size_t n = 0;
    memset(tc, 0, sizeof *tc);
    for (size_t j = 0; j < s->m->nt; j++) {
        const uint32_t *t = s->m->t + 3 * j;
        const double *a = s->off + 3 * t[0], *b = s->off + 3 * t[1], *c = s->off + 3 * t[2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double x[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                       u[0] * w[1] - u[1] * w[0]};
        if (s->sign * dot3(x, s->fn + 3 * j) < 0.0) { /* fn = sign * mesh normal */
            n++;
            classify_turned(s, j, tc);
        }
    }
    return n;
}

/* ---- features and smoothing groups ------------------------------------------ */

static void mark_features(sampler *s)
{
    const mesh_topology *tp = &s->tp;
    s->feat = sl_calloc(tp->ne ? tp->ne : 1, 1, "feature edges");
    for (size_t e = 0; e < tp->ne; e++) {
        if (tp->ecount[e] != 2) {
            s->feat[e] = 1;
            continue;
        }
        s->feat[e] = dot3(s->fn + 3 * (size_t)tp->et[2 * e],
                          s->fn + 3 * (size_t)tp->et[2 * e + 1]) < s->cos_crease;
    }
}

static size_t uf_find(size_t *parent, size_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void uf_union(size_t *parent, size_t a, size_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a != b) parent[a < b ? b : a] = a < b ? a : b;
}

/* Corner of triangle j at vertex v. */
static size_t corner_of(const mesh *m, size_t j, uint32_t v)
{
    for (int k = 0; k < 3; k++)
        if (m->t[3 * j + k] == v) return 3 * j + (size_t)k;
    return 3 * j;
}

/* Corners of triangles that meet across a smooth edge join one group; a
 * corner's normal is the angle-weighted sum over its group. */
static void corner_normals(sampler *s)
{
    const mesh *m = s->m;
    const mesh_topology *tp = &s->tp;
    size_t nc = 3 * m->nt;
    size_t *parent = sl_malloc(nc * sizeof *parent, "smoothing groups");
    double *sum = sl_calloc(3 * nc, sizeof *sum, "smoothing groups");
    for (size_t c = 0; c < nc; c++) parent[c] = c;
    for (size_t e = 0; e < tp->ne; e++) {
        size_t t1 = tp->et[2 * e], t2 = tp->et[2 * e + 1];
        if (s->feat[e]) continue;
        for (int k = 0; k < 2; k++) {
            uint32_t v = tp->ev[2 * e + k];
            uf_union(parent, corner_of(m, t1, v), corner_of(m, t2, v));
        }
    }
    for (size_t c = 0; c < nc; c++) {
        size_t r = uf_find(parent, c);
        for (int d = 0; d < 3; d++) sum[3 * r + d] += s->angle[c] * s->fn[3 * (c / 3) + d];
    }
    s->cn = sl_malloc(3 * nc * sizeof *s->cn, "corner normals");
    for (size_t c = 0; c < nc; c++) {
        size_t r = uf_find(parent, c);
        memcpy(s->cn + 3 * c, sum + 3 * r, 3 * sizeof *sum);
        normalise(s->cn + 3 * c);
    }
    free(parent);
    free(sum);
}

/* Feature edges by vertex (compressed rows). */
static void feature_adjacency(sampler *s)
{
    const mesh_topology *tp = &s->tp;
    size_t nv = s->m->nv;
    s->fdeg = sl_calloc(nv + 1, sizeof *s->fdeg, "feature adjacency");
    s->fstart = sl_calloc(nv + 1, sizeof *s->fstart, "feature adjacency");
    for (size_t e = 0; e < tp->ne; e++)
        if (s->feat[e]) {
            s->fdeg[tp->ev[2 * e]]++;
            s->fdeg[tp->ev[2 * e + 1]]++;
        }
    for (size_t v = 0; v < nv; v++) s->fstart[v + 1] = s->fstart[v] + s->fdeg[v];
    s->fedge =
        sl_malloc((s->fstart[nv] ? s->fstart[nv] : 1) * sizeof *s->fedge, "feature adjacency");
    memset(s->fdeg, 0, (nv + 1) * sizeof *s->fdeg);
    for (size_t e = 0; e < tp->ne; e++)
        if (s->feat[e])
            for (int k = 0; k < 2; k++) {
                uint32_t v = tp->ev[2 * e + k];
                s->fedge[s->fstart[v] + s->fdeg[v]++] = (uint32_t)e;
            }
}

static uint32_t other_end(const sampler *s, size_t e, uint32_t v)
{
    return s->tp.ev[2 * e] == v ? s->tp.ev[2 * e + 1] : s->tp.ev[2 * e];
}

/* A corner: the end of a feature line, a junction, or a sharp turn. */
static int is_corner(const sampler *s, uint32_t v)
{
    const double *x = s->m->v + 3 * (size_t)v;
    double a[3], b[3];
    uint32_t u, w;
    if (s->fdeg[v] == 0) return 0;
    if (s->fdeg[v] != 2) return 1;
    u = other_end(s, s->fedge[s->fstart[v]], v);
    w = other_end(s, s->fedge[s->fstart[v] + 1], v);
    for (int d = 0; d < 3; d++) {
        a[d] = x[d] - s->m->v[3 * (size_t)u + d];
        b[d] = s->m->v[3 * (size_t)w + d] - x[d];
    }
    normalise(a);
    normalise(b);
    return dot3(a, b) < s->cos_crease;
}

static void edge_normal(const sampler *s, size_t e, double n[3])
{
    const double *a = s->fn + 3 * (size_t)s->tp.et[2 * e];
    for (int d = 0; d < 3; d++) n[d] = a[d];
    if (s->tp.ecount[e] >= 2) {
        const double *b = s->fn + 3 * (size_t)s->tp.et[2 * e + 1];
        double sum[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
        if (dot3(sum, sum) > 1e-12) memcpy(n, sum, sizeof sum);
    }
}

/* A feature line: vertices path[0..n] joined by edges epath[0..n-1]. */
typedef struct polyline {
    uint32_t *v, *e;
    size_t n, cap;
} polyline;

static void poly_push(polyline *pl, uint32_t v, uint32_t e)
{
    if (pl->n + 1 >= pl->cap) {
        pl->cap = pl->cap ? 2 * pl->cap : 64;
        pl->v = sl_realloc(pl->v, pl->cap * sizeof *pl->v, "a feature line");
        pl->e = sl_realloc(pl->e, pl->cap * sizeof *pl->e, "a feature line");
    }
    pl->e[pl->n] = e;
    pl->v[++pl->n] = v;
}

static void poly_start(polyline *pl, uint32_t v)
{
    if (pl->cap == 0) {
        pl->cap = 64;
        pl->v = sl_malloc(pl->cap * sizeof *pl->v, "a feature line");
        pl->e = sl_malloc(pl->cap * sizeof *pl->e, "a feature line");
    }
    pl->n = 0;
    pl->v[0] = v;
}

/* round(L / r0) equal arc-length intervals; `closed`: the start point too. */
static void sample_polyline(sampler *s, const polyline *pl, int closed)
{
    double len = 0.0, step, next, done = 0.0;
    long n;
    for (size_t i = 0; i < pl->n; i++) {
        const double *a = s->off + 3 * (size_t)pl->v[i], *b = s->off + 3 * (size_t)pl->v[i + 1];
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        len += sqrt(dot3(d, d));
    }
    n = lround(len / s->r0);
    if (n < 1) n = 1;
    step = len / (double)n;
    next = closed ? 0.0 : step;
    for (size_t i = 0; i < pl->n && n > 0; i++) {
        const double *a = s->off + 3 * (size_t)pl->v[i], *b = s->off + 3 * (size_t)pl->v[i + 1];
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, l = sqrt(dot3(d, d));
        while (n > (closed ? 0 : 1) && next <= done + l + 1e-12 * len) {
            double t = l > 0.0 ? (next - done) / l : 0.0, x[3], nrm[3];
            if (t > 1.0) t = 1.0;
            for (int k = 0; k < 3; k++) x[k] = a[k] + t * d[k];
            edge_normal(s, pl->e[i], nrm);
            accept(s, x, nrm, FEATURE_SPACING * s->r0);
            next += step;
            n--;
        }
        done += l;
    }
}

/* Walk from v along feature edge e until a corner or back to the start. */
static void walk(sampler *s, uint8_t *used, uint32_t v, uint32_t e, polyline *pl)
{
    uint32_t start = v;
    poly_start(pl, v);
    for (;;) {
        uint32_t u = other_end(s, e, v), next = UINT32_MAX;
        used[e] = 1;
        poly_push(pl, u, e);
        if (u == start || is_corner(s, u)) return;
        for (size_t k = s->fstart[u]; k < s->fstart[u + 1]; k++)
            if (!used[s->fedge[k]]) next = s->fedge[k];
        if (next == UINT32_MAX) return;
        v = u;
        e = next;
    }
}

static void sample_features(sampler *s)
{
    const mesh *m = s->m;
    uint8_t *used = sl_calloc(s->tp.ne ? s->tp.ne : 1, 1, "feature flags");
    polyline pl = {0};
    for (uint32_t v = 0; v < m->nv; v++)
        if (is_corner(s, v)) {
            double n[3];
            memcpy(n, s->vn + 3 * (size_t)v, sizeof n);
            accept(s, s->off + 3 * (size_t)v, n, FEATURE_SPACING * s->r0);
        }
    for (uint32_t v = 0; v < m->nv; v++) {
        if (!is_corner(s, v)) continue;
        for (size_t k = s->fstart[v]; k < s->fstart[v + 1]; k++)
            if (!used[s->fedge[k]]) {
                walk(s, used, v, s->fedge[k], &pl);
                sample_polyline(s, &pl, 0);
            }
    }
    for (size_t e = 0; e < s->tp.ne; e++) /* closed loops without corners */
        if (s->feat[e] && !used[e]) {
            walk(s, used, s->tp.ev[2 * e], (uint32_t)e, &pl);
            sample_polyline(s, &pl, pl.v[pl.n] == pl.v[0]);
        }
    free(pl.v);
    free(pl.e);
    free(used);
}

/* ---- faces -------------------------------------------------------------------- */

static double offset_area(const sampler *s, size_t j)
{
    const uint32_t *t = s->m->t + 3 * j;
    const double *a = s->off + 3 * t[0], *b = s->off + 3 * t[1], *c = s->off + 3 * t[2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double x[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    return 0.5 * sqrt(dot3(x, x));
}

/* ---- spatial order ------------------------------------------------------------ */

typedef struct keyed {
    uint64_t key;
    size_t i;
} keyed;

static int cmp_keyed(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

/* perm[0..n) = the points x (3 per point) in Z-order inside [lo, hi]:
 * neighbours in space become neighbours in memory, which is what keeps the
 * grid and hierarchy queries below in cache. */
static void z_order(const double *x, size_t n, const double lo[3], const double hi[3], size_t *perm)
{
    keyed *k = sl_malloc((n ? n : 1) * sizeof *k, "a spatial order");
    for (size_t i = 0; i < n; i++) {
        uint64_t key = 0;
        for (int d = 0; d < 3; d++) {
            double f = hi[d] > lo[d] ? (x[3 * i + d] - lo[d]) / (hi[d] - lo[d]) : 0.0;
            f = f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f;
            key |= sl_morton_spread3((uint64_t)(f * 2097151.0)) << d;
        }
        k[i].key = key;
        k[i].i = i;
    }
    qsort(k, n, sizeof *k, cmp_keyed);
    for (size_t i = 0; i < n; i++) perm[i] = k[i].i;
    free(k);
}

/* ---- faces -------------------------------------------------------------------- */

/* Darts triangle by triangle in Z-order of their centroids, each getting
 * darts * area / r0^2 of them (the fraction rounded at random), so that
 * consecutive darts test nearby grid cells. */
static void sample_faces(sampler *s, const msample_params *p)
{
    const mesh *m = s->m;
    double *cen = sl_malloc(3 * m->nt * sizeof *cen, "triangle centroids"), lo[3], hi[3];
    size_t *order = sl_malloc(m->nt * sizeof *order, "a triangle order");
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (!rng) sl_fatal("out of memory allocating a random number generator");
    gsl_rng_set(rng, p->seed);
    mesh_bounds(m, lo, hi);
    for (int d = 0; d < 3; d++) {
        lo[d] -= s->r0;
        hi[d] += s->r0;
    }
    for (size_t j = 0; j < m->nt; j++)
        for (int d = 0; d < 3; d++)
            cen[3 * j + d] =
                (s->off[3 * (size_t)m->t[3 * j] + d] + s->off[3 * (size_t)m->t[3 * j + 1] + d] +
                 s->off[3 * (size_t)m->t[3 * j + 2] + d]) /
                3.0;
    z_order(cen, m->nt, lo, hi, order);
    mesh_progress mp;
    mesh_progress_start(&mp, m->nt, "sampling a mesh of %zu triangles", m->nt);
    for (size_t q = 0; q < m->nt; q++) {
        size_t j = order[q];
        mesh_progress_at(&mp, q);
        double expect = p->darts * offset_area(s, j) / (s->r0 * s->r0);
        double ndarts = floor(expect) + (gsl_rng_uniform(rng) < expect - floor(expect));
        for (double i = 0; i < ndarts; i++) {
            double r1 = sqrt(gsl_rng_uniform(rng)), r2 = gsl_rng_uniform(rng);
            double w[3] = {1.0 - r1, r1 * (1.0 - r2), r1 * r2}, x[3] = {0, 0, 0}, n[3] = {0, 0, 0};
            for (int k = 0; k < 3; k++)
                for (int d = 0; d < 3; d++) {
                    x[d] += w[k] * s->off[3 * (size_t)m->t[3 * j + k] + d];
                    n[d] += w[k] * s->cn[9 * j + 3 * k + d];
                }
            accept(s, x, n, p->min_spacing * s->r0);
        }
    }
    mesh_progress_end(&mp);
    gsl_rng_free(rng);
    free(order);
    free(cen);
}

/* ---- relaxation -------------------------------------------------------------- */

/* Neighbour lists (compressed rows) of the particles [nfixed, np) within
 * range + skin, kept until some particle has moved by skin / 2 (Verlet). */
typedef struct verlet {
    size_t *start; /* np - nfixed + 1 */
    uint32_t *nbr; /* neighbour ids */
    size_t cap;
    double *x0; /* positions when built */
} verlet;

typedef struct list_ctx {
    verlet *v;
    size_t self, n;
} list_ctx;

static void add_neighbour(void *ctx, size_t id, double d)
{
    list_ctx *c = ctx;
    (void)d;
    if (id == c->self) return;
    if (c->n == c->v->cap) {
        c->v->cap *= 2;
        c->v->nbr = sl_realloc(c->v->nbr, c->v->cap * sizeof *c->v->nbr, "neighbour lists");
    }
    c->v->nbr[c->n++] = (uint32_t)id;
}

static void verlet_build(verlet *v, const double *x, size_t nfixed, size_t np, double r)
{
    mgrid g;
    list_ctx c = {.v = v, .n = 0};
    mgrid_init(&g, r, np);
    for (size_t i = 0; i < np; i++) mgrid_insert(&g, x + 3 * i);
    for (size_t i = nfixed; i < np; i++) {
        v->start[i - nfixed] = c.n;
        c.self = i;
        mgrid_visit(&g, x + 3 * i, r, add_neighbour, &c);
    }
    v->start[np - nfixed] = c.n;
    memcpy(v->x0, x, 3 * np * sizeof *x);
    mgrid_free(&g);
}

static void barycentric(const double *a, const double *b, const double *c, const double *p,
                        double w[3])
{
    double v0[3], v1[3], v2[3], d00, d01, d11, d20, d21, den;
    for (int k = 0; k < 3; k++) {
        v0[k] = b[k] - a[k];
        v1[k] = c[k] - a[k];
        v2[k] = p[k] - a[k];
    }
    d00 = dot3(v0, v0);
    d01 = dot3(v0, v1);
    d11 = dot3(v1, v1);
    d20 = dot3(v2, v0);
    d21 = dot3(v2, v1);
    den = d00 * d11 - d01 * d01;
    if (!(den > 0.0)) {
        w[0] = w[1] = w[2] = 1.0 / 3.0;
        return;
    }
    w[1] = (d11 * d20 - d01 * d21) / den;
    w[2] = (d00 * d21 - d01 * d20) / den;
    w[0] = 1.0 - w[1] - w[2];
}

/* Sweeps of soft-sphere repulsion between the particles, each followed by
 * a projection back onto the offset surface; feature particles [0, nfixed)
 * stay put.  Jacobi sweeps, so the result does not depend on threads. */
static void relax(sampler *s, int sweeps, size_t nfixed, double *x, double *n, size_t np)
{
    const mesh *m = s->m;
    const double range = RELAX_RANGE * s->r0, maxstep = RELAX_STEP * s->r0;
    const double skin = RELAX_SKIN * s->r0;
    double *y = sl_malloc(3 * np * sizeof *y, "relaxed particles");
    verlet v = {.cap = 16 * (np - nfixed) + 16};
    int stale = 1;
    mesh off;
    if (np > UINT32_MAX)
        sl_fatal("mesh sampling: more than %lu particles", (unsigned long)UINT32_MAX);
    v.start = sl_malloc((np - nfixed + 1) * sizeof *v.start, "neighbour lists");
    v.nbr = sl_malloc(v.cap * sizeof *v.nbr, "neighbour lists");
    v.x0 = sl_malloc(3 * np * sizeof *v.x0, "neighbour lists");
    mesh_copy(&off, m);
    memcpy(off.v, s->off, 3 * m->nv * sizeof *off.v);
    mesh_index_build(&off);
    mesh_progress mp;
    mesh_progress_start(&mp, (size_t)sweeps * (np - nfixed),
                        "relaxing %zu boundary particles "
                        "(%d sweeps)",
                        np - nfixed, sweeps);
    for (int it = 0; it < sweeps; it++) {
        double moved2 = 0.0;
        mesh_progress_at(&mp, (size_t)it * (np - nfixed));
        if (stale) verlet_build(&v, x, nfixed, np, range + skin);
        memcpy(y, x, 3 * np * sizeof *y);
#pragma omp parallel for schedule(static) if (np - nfixed > 8192)
        for (size_t i = nfixed; i < np; i++) {
            const double *xi = x + 3 * i;
            double f[3] = {0, 0, 0}, q[3], len, w[3];
            size_t j;
            const uint32_t *t;
            for (size_t k = v.start[i - nfixed]; k < v.start[i - nfixed + 1]; k++) {
                const double *xj = x + 3 * (size_t)v.nbr[k];
                double e[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]}, d = sqrt(dot3(e, e));
                if (d >= range || d <= 0.0) continue; /* d = 0: no direction to push */
                for (int a = 0; a < 3; a++) f[a] += (range - d) / d * e[a];
            }
            len = RELAX_GAIN * sqrt(dot3(f, f));
            for (int a = 0; a < 3; a++)
                q[a] = xi[a] + RELAX_GAIN * f[a] * (len > maxstep ? maxstep / len : 1.0);
            /* xi was on the surface: its new closest point is within the move */
            len = sqrt((q[0] - xi[0]) * (q[0] - xi[0]) + (q[1] - xi[1]) * (q[1] - xi[1]) +
                       (q[2] - xi[2]) * (q[2] - xi[2]));
            if (isinf(
                    mesh_closest_point_within(&off, q, 1.001 * len + 1e-9 * s->r0, y + 3 * i, &j)))
                mesh_closest_point(&off, q, y + 3 * i, &j);
            t = m->t + 3 * j;
            barycentric(off.v + 3 * t[0], off.v + 3 * t[1], off.v + 3 * t[2], y + 3 * i, w);
            for (int d = 0; d < 3; d++)
                n[3 * i + d] = w[0] * s->cn[9 * j + d] + w[1] * s->cn[9 * j + 3 + d] +
                    w[2] * s->cn[9 * j + 6 + d];
            normalise(n + 3 * i);
        }
        memcpy(x, y, 3 * np * sizeof *y);
        for (size_t i = nfixed; i < np; i++) {
            double e[3] = {x[3 * i] - v.x0[3 * i], x[3 * i + 1] - v.x0[3 * i + 1],
                           x[3 * i + 2] - v.x0[3 * i + 2]};
            moved2 = fmax(moved2, dot3(e, e));
        }
        stale = 4.0 * moved2 > skin * skin;
    }
    mesh_progress_end(&mp);
    mesh_free(&off);
    free(v.start);
    free(v.nbr);
    free(v.x0);
    free(y);
}

/* Put the face particles [nfixed, np) in Z-order (the grid's hash is stale
 * afterwards; only its coordinates are used from here on). */
static void reorder(sampler *s, size_t nfixed, size_t np)
{
    size_t nf = np - nfixed, *perm = sl_malloc((nf ? nf : 1) * sizeof *perm, "a spatial order");
    double *tmp = sl_malloc(6 * (nf ? nf : 1) * sizeof *tmp, "a spatial order");
    double lo[3], hi[3];
    double *x = s->grid.x + 3 * nfixed, *n = s->nrm + 3 * nfixed;
    mesh_bounds(s->m, lo, hi);
    for (int d = 0; d < 3; d++) {
        lo[d] -= s->r0;
        hi[d] += s->r0;
    }
    z_order(x, nf, lo, hi, perm);
    for (size_t i = 0; i < nf; i++) {
        memcpy(tmp + 6 * i, x + 3 * perm[i], 3 * sizeof *tmp);
        memcpy(tmp + 6 * i + 3, n + 3 * perm[i], 3 * sizeof *tmp);
    }
    for (size_t i = 0; i < nf; i++) {
        memcpy(x + 3 * i, tmp + 6 * i, 3 * sizeof *tmp);
        memcpy(n + 3 * i, tmp + 6 * i + 3, 3 * sizeof *tmp);
    }
    free(tmp);
    free(perm);
}

/* ---- driver --------------------------------------------------------------------- */

static int check_params(const mesh *m, const msample_params *p, sl_err *err)
{
    double area;
    if (!(p->r0 > 0.0) || !isfinite(p->r0)) {
        sl_err_set(err, "mesh sampling: spacing r0 = %g, expected a finite number > 0", p->r0);
        return 1;
    }
    if (!(p->min_spacing > 0.0 && p->min_spacing < 2.0) || !(p->darts > 0.0 && p->darts < 1e4) ||
        !(p->crease_angle >= 0.0 && p->crease_angle <= 180.0) || p->relax < 0 || p->relax > 1000) {
        sl_err_set(err,
                   "mesh sampling: min_spacing %g (0..2), darts %g (0..1e4), "
                   "crease_angle %g (0..180 degrees) or relax %d (0..1000) out of range",
                   p->min_spacing, p->darts, p->crease_angle, p->relax);
        return 1;
    }
    for (size_t i = 0; i < 3 * m->nt; i++)
        if (m->t[i] >= m->nv) {
            sl_err_set(err,
                       "mesh sampling: triangle %zu uses vertex %lu of %zu (validate the "
                       "mesh first)",
                       i / 3 + 1, (unsigned long)m->t[i] + 1, m->nv);
            return 1;
        }
    area = mesh_area(m);
    if (m->nt == 0 || !(area > 0.0) || !isfinite(area)) {
        sl_err_set(err, "mesh sampling: the mesh has no area");
        return 1;
    }
    if (area / (p->r0 * p->r0) > MAX_PARTICLES) {
        sl_err_set(err,
                   "mesh sampling: area %g at spacing r0 = %g needs about %.3g particles "
                   "(more than %.0g): wrong units?",
                   area, p->r0, area / (p->r0 * p->r0), MAX_PARTICLES);
        return 1;
    }
    return 0;
}

static void free_sampler(sampler *s)
{
    mesh_topology_free(&s->tp);
    free(s->fn);
    free(s->angle);
    free(s->off);
    free(s->vn);
    free(s->cn);
    free(s->feat);
    free(s->fdeg);
    free(s->fstart);
    free(s->fedge);
    free(s->nrm);
    mgrid_free(&s->grid);
}

int msample_surface(const mesh *m, const msample_params *p, uint32_t body, sl_boundary *b,
                    size_t *added, sl_err *err)
{
    sampler s;
    size_t clamped, turned, nfixed, np;
    if (added) *added = 0;
    if (check_params(m, p, err)) return 1;
    memset(&s, 0, sizeof s);
    s.m = m;
    s.r0 = p->r0;
    s.cos_crease = cos(p->crease_angle * M_PI / 180.0);
    mesh_topology_build(m, &s.tp);
    s.sign = p->side == MSAMPLE_CONTAINER ? -1.0 : 1.0;
    face_data(&s);
    clamped = offset_vertices(&s);
    turned_count tc;
    turned = count_turned(&s, &tc);
    if (clamped || tc.thin || tc.rim)
        sl_warning("mesh sampling: offsetting by r0/2 = %g clamps %zu vertices at sharp spikes "
                   "and turns %zu triangles over (%zu at open rims, %zu in parts thinner than "
                   "r0, %zu finer than r0 next to sharp edges); the boundary particles there "
                   "follow the surface only roughly",
                   0.5 * p->r0, clamped, turned, tc.rim, tc.thin, tc.fine);
    else if (tc.fine)
        sl_info("mesh sampling: %zu triangles finer than r0 fold over next to sharp edges when "
                "offset by r0/2 = %g (the sampled offset surface keeps the edges)",
                tc.fine, 0.5 * p->r0);
    mark_features(&s);
    corner_normals(&s);
    feature_adjacency(&s);
    mgrid_init(&s.grid, p->min_spacing * p->r0, 1024);
    sample_features(&s);
    nfixed = s.grid.n;
    sample_faces(&s, p);
    np = s.grid.n;
    reorder(&s, nfixed, np);
    if (p->relax > 0) relax(&s, p->relax, nfixed, s.grid.x, s.nrm, np);
    for (size_t i = 0; i < np; i++) {
        const double *x = s.grid.x + 3 * i, *n = s.nrm + 3 * i;
        prt_boundary_push(b, x[0], x[1], x[2], n[0], n[1], n[2], body);
    }
    if (added) *added = np;
    free_sampler(&s);
    return 0;
}

/* ---- quality --------------------------------------------------------------------- */

msample_quality msample_spacing(size_t n, const double *x, const double *y, const double *z)
{
    msample_quality q = {n, 0.0, 0.0, 0.0};
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double diag = 0.0, sum = 0.0;
    mgrid g;
    if (n < 2) return q;
    for (size_t i = 0; i < n; i++) {
        double p[3] = {x[i], y[i], z[i]};
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], p[d]);
            hi[d] = fmax(hi[d], p[d]);
        }
    }
    for (int d = 0; d < 3; d++) diag += (hi[d] - lo[d]) * (hi[d] - lo[d]);
    diag = sqrt(diag);
    /* about the spacing of n points on a surface of size diag */
    mgrid_init(&g, diag > 0.0 ? diag / sqrt((double)n) : 1.0, n);
    for (size_t i = 0; i < n; i++) {
        double p[3] = {x[i], y[i], z[i]};
        mgrid_insert(&g, p);
    }
    q.min = INFINITY;
    for (size_t i = 0; i < n; i++) {
        double p[3] = {x[i], y[i], z[i]}, d = 0.0;
        mgrid_nearest(&g, p, i, &d);
        q.min = fmin(q.min, d);
        q.max = fmax(q.max, d);
        sum += d;
    }
    q.mean = sum / (double)n;
    mgrid_free(&g);
    return q;
}
