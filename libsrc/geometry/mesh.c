/* mesh: the triangle mesh type, transforms, topology and validation
 * (see mesh.h). */
#include "geometry/mesh.h"

#include "core/sl_mem.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NONE32 UINT32_MAX

/* ---- the type ------------------------------------------------------------ */

void mesh_init(mesh *m) { memset(m, 0, sizeof *m); }

void mesh_free(mesh *m)
{
    mesh_index_free(m->index);
    free(m->v);
    free(m->t);
    mesh_init(m);
}

void mesh_touch(mesh *m)
{
    mesh_index_free(m->index);
    m->index = NULL;
}

void mesh_copy(mesh *dst, const mesh *src)
{
    mesh_init(dst);
    dst->nv = dst->cap_v = src->nv;
    dst->nt = dst->cap_t = src->nt;
    dst->v = sl_malloc(3 * src->nv * sizeof *dst->v, "mesh vertices");
    dst->t = sl_malloc(3 * src->nt * sizeof *dst->t, "mesh triangles");
    if (src->nv) memcpy(dst->v, src->v, 3 * src->nv * sizeof *dst->v);
    if (src->nt) memcpy(dst->t, src->t, 3 * src->nt * sizeof *dst->t);
}

uint32_t mesh_add_vertex(mesh *m, double x, double y, double z)
{
    if (m->nv >= MESH_MAX_VERTICES) sl_fatal("mesh: more than %zu vertices", MESH_MAX_VERTICES);
    if (m->nv == m->cap_v) {
        m->cap_v = m->cap_v ? 2 * m->cap_v : 64;
        m->v = sl_realloc(m->v, 3 * m->cap_v * sizeof *m->v, "mesh vertices");
    }
    m->v[3 * m->nv] = x;
    m->v[3 * m->nv + 1] = y;
    m->v[3 * m->nv + 2] = z;
    mesh_touch(m);
    return (uint32_t)m->nv++;
}

void mesh_add_triangle(mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->nt == m->cap_t) {
        m->cap_t = m->cap_t ? 2 * m->cap_t : 64;
        m->t = sl_realloc(m->t, 3 * m->cap_t * sizeof *m->t, "mesh triangles");
    }
    m->t[3 * m->nt] = a;
    m->t[3 * m->nt + 1] = b;
    m->t[3 * m->nt + 2] = c;
    m->nt++;
    mesh_touch(m);
}

/* ---- transforms ------------------------------------------------------------ */

static int all_finite(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

static void flip_triangle(mesh *m, size_t j)
{
    uint32_t tmp = m->t[3 * j + 1];
    m->t[3 * j + 1] = m->t[3 * j + 2];
    m->t[3 * j + 2] = tmp;
}

int mesh_scale(mesh *m, const double s[3], sl_err *err)
{
    static const char axis[] = "xyz";
    for (int d = 0; d < 3; d++)
        if (!isfinite(s[d]) || s[d] == 0.0) {
            sl_err_set(err, "mesh scale factor along %c is %g: expected a finite, nonzero number",
                       axis[d], s[d]);
            return 1;
        }
    for (size_t i = 0; i < m->nv; i++)
        for (int d = 0; d < 3; d++) m->v[3 * i + d] *= s[d];
    if (s[0] * s[1] * s[2] < 0.0)
        for (size_t j = 0; j < m->nt; j++) flip_triangle(m, j);
    mesh_touch(m);
    return 0;
}

int mesh_scale_uniform(mesh *m, double s, sl_err *err)
{
    double v[3] = {s, s, s};
    return mesh_scale(m, v, err);
}

int mesh_rotate(mesh *m, const double deg[3], sl_err *err)
{
    double c[3], s[3], r[3][3];
    if (!all_finite(deg, 3)) {
        sl_err_set(err, "mesh rotation (%g %g %g): expected finite angles in degrees", deg[0],
                   deg[1], deg[2]);
        return 1;
    }
    for (int d = 0; d < 3; d++) {
        c[d] = cos(deg[d] * M_PI / 180.0);
        s[d] = sin(deg[d] * M_PI / 180.0);
    }
    /* R = Rz(c) Ry(b) Rx(a) */
    r[0][0] = c[2] * c[1];
    r[0][1] = c[2] * s[1] * s[0] - s[2] * c[0];
    r[0][2] = c[2] * s[1] * c[0] + s[2] * s[0];
    r[1][0] = s[2] * c[1];
    r[1][1] = s[2] * s[1] * s[0] + c[2] * c[0];
    r[1][2] = s[2] * s[1] * c[0] - c[2] * s[0];
    r[2][0] = -s[1];
    r[2][1] = c[1] * s[0];
    r[2][2] = c[1] * c[0];
    for (size_t i = 0; i < m->nv; i++) {
        double *p = m->v + 3 * i, q[3];
        for (int a = 0; a < 3; a++) q[a] = r[a][0] * p[0] + r[a][1] * p[1] + r[a][2] * p[2];
        memcpy(p, q, sizeof q);
    }
    mesh_touch(m);
    return 0;
}

int mesh_translate(mesh *m, const double d[3], sl_err *err)
{
    if (!all_finite(d, 3)) {
        sl_err_set(err, "mesh translation (%g %g %g): expected finite numbers", d[0], d[1], d[2]);
        return 1;
    }
    for (size_t i = 0; i < m->nv; i++)
        for (int a = 0; a < 3; a++) m->v[3 * i + a] += d[a];
    mesh_touch(m);
    return 0;
}

void mesh_bounds(const mesh *m, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) lo[d] = hi[d] = m->nv ? m->v[d] : 0.0;
    for (size_t i = 1; i < m->nv; i++)
        for (int d = 0; d < 3; d++) {
            double x = m->v[3 * i + d];
            if (x < lo[d]) lo[d] = x;
            if (x > hi[d]) hi[d] = x;
        }
}

/* Twice-area vector (b - a) x (c - a) of triangle j. */
static void cross_of(const mesh *m, size_t j, double n[3])
{
    const double *a = m->v + 3 * m->t[3 * j], *b = m->v + 3 * m->t[3 * j + 1],
                 *c = m->v + 3 * m->t[3 * j + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
}

double mesh_triangle_normal(const mesh *m, size_t j, double n[3])
{
    double len;
    cross_of(m, j, n);
    len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int d = 0; d < 3; d++) n[d] = len > 0.0 ? n[d] / len : 0.0;
    return 0.5 * len;
}

double mesh_area(const mesh *m)
{
    double s = 0.0, n[3];
    for (size_t j = 0; j < m->nt; j++) s += mesh_triangle_normal(m, j, n);
    return s;
}

/* Sum of the signed volumes of the tetrahedra (c, a, b, c') about the
 * bounding-box centre c, which keeps the round-off small far from 0. */
double mesh_volume(const mesh *m)
{
    double lo[3], hi[3], c[3], s = 0.0;
    mesh_bounds(m, lo, hi);
    for (int d = 0; d < 3; d++) c[d] = 0.5 * (lo[d] + hi[d]);
    for (size_t j = 0; j < m->nt; j++) {
        const double *p[3];
        double a[3][3];
        for (int k = 0; k < 3; k++) {
            p[k] = m->v + 3 * m->t[3 * j + k];
            for (int d = 0; d < 3; d++) a[k][d] = p[k][d] - c[d];
        }
        s += a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
            a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
            a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    }
    return s / 6.0;
}

/* ---- topology -------------------------------------------------------------- */

typedef struct half_edge {
    uint64_t key; /* (min vertex << 32) | max vertex */
    size_t he;    /* 3 * triangle + corner */
} half_edge;

static int cmp_half_edge(const void *pa, const void *pb)
{
    const half_edge *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->he > b->he) - (a->he < b->he);
}

void mesh_topology_build(const mesh *m, mesh_topology *tp)
{
    size_t nh = 3 * m->nt, ne = 0;
    half_edge *h = sl_malloc(nh * sizeof *h, "mesh edges");
    for (size_t i = 0; i < nh; i++) {
        uint32_t a = m->t[i], b = m->t[i - i % 3 + (i % 3 + 1) % 3];
        if (a > b) {
            uint32_t s = a;
            a = b;
            b = s;
        }
        h[i].key = (uint64_t)a << 32 | b;
        h[i].he = i;
    }
    qsort(h, nh, sizeof *h, cmp_half_edge);
    for (size_t i = 0; i < nh; i++) ne += i == 0 || h[i].key != h[i - 1].key;
    tp->ne = ne;
    tp->ev = sl_malloc(2 * ne * sizeof *tp->ev, "mesh edges");
    tp->et = sl_malloc(2 * ne * sizeof *tp->et, "mesh edges");
    tp->ecount = sl_malloc(ne * sizeof *tp->ecount, "mesh edges");
    tp->tedge = sl_malloc(nh * sizeof *tp->tedge, "mesh edges");
    for (size_t i = 0, e = (size_t)-1; i < nh; i++) {
        if (i == 0 || h[i].key != h[i - 1].key) {
            e++;
            tp->ev[2 * e] = (uint32_t)(h[i].key >> 32);
            tp->ev[2 * e + 1] = (uint32_t)h[i].key;
            tp->et[2 * e] = tp->et[2 * e + 1] = NONE32;
            tp->ecount[e] = 0;
        }
        if (tp->ecount[e] < 2) tp->et[2 * e + tp->ecount[e]] = (uint32_t)(h[i].he / 3);
        if (tp->ecount[e] < UINT32_MAX) tp->ecount[e]++;
        tp->tedge[h[i].he] = (uint32_t)e;
    }
    free(h);
}

void mesh_topology_free(mesh_topology *tp)
{
    free(tp->ev);
    free(tp->et);
    free(tp->ecount);
    free(tp->tedge);
    memset(tp, 0, sizeof *tp);
}

/* ---- validation ------------------------------------------------------------- */

static int check_input(const mesh *m, const char *name, sl_err *err)
{
    for (size_t i = 0; i < m->nv; i++) {
        const double *x = m->v + 3 * i;
        if (!all_finite(x, 3)) {
            sl_err_set(err, "%s: vertex %zu has a non-finite coordinate", name, i + 1);
            return 1;
        }
        /* squares of larger numbers overflow in the distance computations */
        if (fabs(x[0]) > MESH_MAX_COORD || fabs(x[1]) > MESH_MAX_COORD ||
            fabs(x[2]) > MESH_MAX_COORD) {
            sl_err_set(err, "%s: vertex %zu at (%g %g %g) is beyond %g (wrong units?)", name, i + 1,
                       x[0], x[1], x[2], MESH_MAX_COORD);
            return 1;
        }
    }
    for (size_t i = 0; i < 3 * m->nt; i++)
        if (m->t[i] >= m->nv) {
            sl_err_set(err, "%s: triangle %zu uses vertex %lu, but there are only %zu", name,
                       i / 3 + 1, (unsigned long)m->t[i] + 1, m->nv);
            return 1;
        }
    return 0;
}

static int is_degenerate(const mesh *m, size_t j, double diag2)
{
    const uint32_t *t = m->t + 3 * j;
    double n[3], area2, emax2 = 0.0;
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return 1;
    for (int k = 0; k < 3; k++) {
        const double *a = m->v + 3 * t[k], *b = m->v + 3 * t[(k + 1) % 3];
        double e2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
            (a[2] - b[2]) * (a[2] - b[2]);
        if (e2 > emax2) emax2 = e2;
    }
    cross_of(m, j, n);
    area2 = 0.25 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]); /* squared area */
    /* area < 1e-24 diag^2, or height = 2 area / emax < 1e-10 emax */
    return area2 < 1e-48 * diag2 * diag2 || 4.0 * area2 < 1e-20 * emax2 * emax2;
}

static size_t drop_degenerate(mesh *m)
{
    double lo[3], hi[3], diag2 = 0.0;
    size_t kept = 0, nt = m->nt;
    mesh_bounds(m, lo, hi);
    for (int d = 0; d < 3; d++) diag2 += (hi[d] - lo[d]) * (hi[d] - lo[d]);
    for (size_t j = 0; j < nt; j++) {
        if (is_degenerate(m, j, diag2)) continue;
        memmove(m->t + 3 * kept, m->t + 3 * j, 3 * sizeof *m->t);
        kept++;
    }
    m->nt = kept;
    return nt - kept;
}

static size_t drop_unused(mesh *m)
{
    uint32_t *map = sl_malloc((m->nv ? m->nv : 1) * sizeof *map, "a vertex map");
    size_t kept = 0, nv = m->nv;
    for (size_t i = 0; i < nv; i++) map[i] = NONE32;
    for (size_t i = 0; i < 3 * m->nt; i++) map[m->t[i]] = 0;
    for (size_t i = 0; i < nv; i++) {
        if (map[i] == NONE32) continue;
        memmove(m->v + 3 * kept, m->v + 3 * i, 3 * sizeof *m->v);
        map[i] = (uint32_t)kept++;
    }
    for (size_t i = 0; i < 3 * m->nt; i++) m->t[i] = map[m->t[i]];
    m->nv = kept;
    free(map);
    return nv - kept;
}

/* 1 if triangle j runs along edge e from ev[0] to ev[1]. */
static int runs_forward(const mesh *m, const mesh_topology *tp, size_t j, size_t e)
{
    for (int k = 0; k < 3; k++)
        if (tp->tedge[3 * j + k] == e) return m->t[3 * j + k] == tp->ev[2 * e];
    return 0;
}

/* Breadth-first over manifold edges: flip[j] = 1 for triangles that must
 * turn to agree with the first triangle of their piece; then each piece
 * keeps the orientation of most of its triangles.  Returns the number of
 * triangles flipped, or (size_t)-1 with *bad set for a non-orientable
 * piece. */
static size_t make_consistent(mesh *m, const mesh_topology *tp, size_t *bad)
{
    size_t nt = m->nt, flipped = 0;
    uint8_t *flip = sl_malloc(nt, "orientation flags");
    uint8_t *seen = sl_calloc(nt, 1, "orientation flags");
    uint32_t *queue = sl_malloc(nt * sizeof *queue, "a triangle queue");
    for (size_t seed = 0; seed < nt; seed++) {
        size_t head = 0, tail = 0, nflip = 0;
        if (seen[seed]) continue;
        seen[seed] = 1;
        flip[seed] = 0;
        queue[tail++] = (uint32_t)seed;
        while (head < tail) {
            size_t j = queue[head++];
            for (int k = 0; k < 3; k++) {
                size_t e = tp->tedge[3 * j + k], o;
                int same;
                if (tp->ecount[e] != 2) continue;
                o = tp->et[2 * e] == j ? tp->et[2 * e + 1] : tp->et[2 * e];
                if (o == j) continue;
                same = runs_forward(m, tp, j, e) == runs_forward(m, tp, o, e);
                if (!seen[o]) {
                    seen[o] = 1;
                    flip[o] = (uint8_t)(flip[j] ^ same);
                    queue[tail++] = (uint32_t)o;
                } else if (flip[o] != (flip[j] ^ same)) {
                    *bad = o;
                    free(flip);
                    free(seen);
                    free(queue);
                    return (size_t)-1;
                }
            }
        }
        for (size_t q = 0; q < tail; q++) nflip += flip[queue[q]];
        for (size_t q = 0; q < tail; q++) {
            size_t j = queue[q];
            if (flip[j] != (2 * nflip > tail)) {
                flip_triangle(m, j);
                flipped++;
            }
        }
    }
    free(flip);
    free(seen);
    free(queue);
    return flipped;
}

static void flip_all(mesh *m)
{
    for (size_t j = 0; j < m->nt; j++) flip_triangle(m, j);
}

/* The error for a mesh that must be closed: count and one example edge. */
static void closed_error(const mesh *m, const mesh_topology *tp, const char *name,
                         const mesh_report *r, sl_err *err)
{
    size_t e = 0;
    const double *a, *b;
    while (e + 1 < tp->ne && (r->open_edges ? tp->ecount[e] != 1 : tp->ecount[e] <= 2)) e++;
    a = m->v + 3 * tp->ev[2 * e];
    b = m->v + 3 * tp->ev[2 * e + 1];
    if (r->open_edges)
        sl_err_set(err,
                   "%s: mesh is not closed: %zu edges are used by one triangle only, "
                   "e.g. (%g %g %g)-(%g %g %g)",
                   name, r->open_edges, a[0], a[1], a[2], b[0], b[1], b[2]);
    else
        sl_err_set(err,
                   "%s: mesh is not manifold: %zu edges are shared by more than two "
                   "triangles, e.g. (%g %g %g)-(%g %g %g)",
                   name, r->nonmanifold, a[0], a[1], a[2], b[0], b[1], b[2]);
}

int mesh_validate(mesh *m, const char *name, unsigned flags, mesh_report *rep, sl_err *err)
{
    mesh_report r;
    mesh_topology tp;
    size_t bad = 0;
    int quiet = (flags & MESH_QUIET) != 0;
    memset(&r, 0, sizeof r);
    mesh_touch(m);
    if (check_input(m, name, err)) return 1;
    r.degenerate = drop_degenerate(m);
    r.unused = drop_unused(m);
    if (m->nt == 0) {
        sl_err_set(err, "%s: mesh has no triangles%s", name,
                   r.degenerate ? " (all of them are degenerate)" : "");
        return 1;
    }
    if (r.degenerate && !quiet)
        sl_warning("%s: dropped %zu degenerate triangles (zero area)", name, r.degenerate);
    mesh_topology_build(m, &tp);
    for (size_t e = 0; e < tp.ne; e++) {
        r.open_edges += tp.ecount[e] == 1;
        r.nonmanifold += tp.ecount[e] > 2;
    }
    r.closed = r.open_edges == 0 && r.nonmanifold == 0;
    if ((flags & MESH_REQUIRE_CLOSED) && !r.closed) {
        closed_error(m, &tp, name, &r, err);
        mesh_topology_free(&tp);
        return 1;
    }
    if (!r.closed && (flags & MESH_WARN_OPEN)) { /* an open obstacle: legal, but say so */
        sl_err open;
        closed_error(m, &tp, name, &r, &open);
        sl_warning("%s: it is sampled as an open sheet, and inside and outside are not defined "
                   "near its holes (close the mesh for a solid body)",
                   open.msg);
    }
    r.reoriented = make_consistent(m, &tp, &bad);
    mesh_topology_free(&tp);
    if (r.reoriented == (size_t)-1) {
        sl_err_set(err,
                   "%s: mesh is not orientable: triangle %zu cannot agree with all its "
                   "neighbours (Moebius strip?)",
                   name, bad + 1);
        return 1;
    }
    if (r.reoriented && !quiet)
        sl_warning("%s: flipped %zu triangles to agree in orientation with their neighbours", name,
                   r.reoriented);
    r.volume = mesh_volume(m);
    if (r.closed && r.volume < 0.0) {
        flip_all(m);
        r.volume = -r.volume;
        r.inverted = 1;
        if (!quiet)
            sl_warning("%s: mesh is inside out (negative volume); flipped every triangle", name);
    }
    r.area = mesh_area(m);
    mesh_index_build(m);
    if (rep) *rep = r;
    return 0;
}
