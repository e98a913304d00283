/*
 * mesh: triangle meshes as boundary bodies and fluid regions (paper Sec. 3.4).
 *
 * A mesh is indexed: vertex i has coordinates v[3i], v[3i+1], v[3i+2] and
 * triangle j the vertex indices t[3j], t[3j+1], t[3j+2].  The normal of a
 * triangle (a, b, c) is (b - a) x (c - a); a closed mesh is oriented so that
 * normals point out of the volume it encloses (positive signed volume).
 *
 * Life cycle: read (OBJ, STL) or make (box, sphere, cylinder) -> transform
 * (scale, rotate, translate) -> mesh_validate (drops degenerate triangles,
 * checks closedness, repairs orientation, builds the distance index) ->
 * queries (mesh_signed_distance, msample_surface).  Every change to the
 * geometry discards the distance index.
 *
 * Nothing here exits on bad input: readers and checks return nonzero and
 * fill an sl_err naming the file and the line (OBJ, ascii STL) or the byte
 * offset (binary STL).  Only running out of memory is fatal (sl_mem).
 * Files:  mesh.c (type, transforms, topology, validation),  mesh_io.c
 * (readers, writer),  mesh_make.c (primitives),  mesh_distance.c (index,
 * signed distance).
 */
#ifndef SL_MESH_H
#define SL_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "core/sl_log.h"

typedef struct mesh_index mesh_index; /* distance acceleration, mesh_distance.c */

typedef struct mesh {
    size_t nv, nt;       /* vertices, triangles */
    size_t cap_v, cap_t; /* allocated vertices, triangles */
    double *v;           /* 3 * nv coordinates */
    uint32_t *t;         /* 3 * nt vertex indices */
    mesh_index *index;   /* NULL until built; dropped by every change */
} mesh;

/* Largest coordinate mesh_validate accepts. */
#define MESH_MAX_COORD 1e100

/* Largest vertex count (indices are 32-bit; UINT32_MAX marks "none"). */
#define MESH_MAX_VERTICES ((size_t)UINT32_MAX - 1)

/* ---- the type ----------------------------------------------------------- */

void mesh_init(mesh *m);
void mesh_free(mesh *m);                    /* and re-initialise */
void mesh_copy(mesh *dst, const mesh *src); /* dst is overwritten (not freed) */
/* Append; the caller keeps nv <= MESH_MAX_VERTICES and indices < nv. */
uint32_t mesh_add_vertex(mesh *m, double x, double y, double z);
void mesh_add_triangle(mesh *m, uint32_t a, uint32_t b, uint32_t c);
/* Drop the distance index (done by every function that changes m). */
void mesh_touch(mesh *m);

/* ---- reading and writing (mesh_io.c) -----------------------------------
 * Readers initialise m themselves (free earlier contents first); on failure
 * m is left empty.  Messages:
 *   "<file>:<line>: vertex index 9 out of range (1..8 defined so far)"
 *   "<file>: byte 80: binary STL declares 12 triangles (684 bytes) ..."  */

/* By extension: .obj or .stl (any letter case). */
int mesh_read(const char *path, mesh *m, sl_err *err);
/* OBJ: `v x y z [w]` and `f i j k ...` (i, i/t, i//n, i/t/n; negative
 * indices count back from the last vertex read); polygons become fans
 * (i, j, k), (i, k, l), ...; every other statement is ignored (unknown
 * ones with a warning).  Lines continued with a backslash are not joined. */
int mesh_read_obj(const char *path, mesh *m, sl_err *err);
/* STL, ascii or binary: binary when the size is 84 + 50 n for the count n
 * at byte 80, whatever the header says.  The triangle soup is welded
 * (mesh_weld with 1e-6 of the bounding-box diagonal); stored facet normals
 * are ignored (orientation comes from the vertex order). */
int mesh_read_stl(const char *path, mesh *m, sl_err *err);
/* Writes v/f lines (full double precision) atomically; `comment` (may be
 * NULL) becomes a leading # line. */
int mesh_write_obj(const mesh *m, const char *path, const char *comment, sl_err *err);

/* Merge vertices closer than tol (> 0): each vertex maps to the first
 * earlier kept vertex within tol.  Returns the number of vertices removed;
 * triangles that lose a corner are left for mesh_validate to drop. */
size_t mesh_weld(mesh *m, double tol);

/* ---- transforms ----------------------------------------------------------
 * Return nonzero with err filled on non-finite or zero factors.  Scaling by
 * factors whose product is negative mirrors the mesh; triangles are then
 * reversed so that normals keep pointing outward. */

int mesh_scale(mesh *m, const double s[3], sl_err *err); /* about the origin */
int mesh_scale_uniform(mesh *m, double s, sl_err *err);
/* Rotation by Euler angles in degrees about the fixed x, y and z axes
 * through the origin, applied in that order: p' = Rz(c) Ry(b) Rx(a) p. */
int mesh_rotate(mesh *m, const double deg[3], sl_err *err);
int mesh_translate(mesh *m, const double d[3], sl_err *err);

void mesh_bounds(const mesh *m, double lo[3], double hi[3]); /* zeros if nv == 0 */
double mesh_area(const mesh *m);
double mesh_volume(const mesh *m); /* signed: > 0 for outward normals */
/* Unit normal of triangle j (zero vector if degenerate) and its area. */
double mesh_triangle_normal(const mesh *m, size_t j, double n[3]);

/* ---- topology ----------------------------------------------------------- */

typedef struct mesh_topology {
    size_t ne;        /* distinct undirected edges */
    uint32_t *ev;     /* 2 * ne: end vertices, ev[2e] <= ev[2e+1] */
    uint32_t *et;     /* 2 * ne: first two triangles using it (UINT32_MAX: none) */
    uint32_t *ecount; /* ne: number of triangles using it */
    uint32_t *tedge;  /* 3 * nt: edge from corner k to corner (k+1) % 3 of triangle j */
} mesh_topology;

void mesh_topology_build(const mesh *m, mesh_topology *tp);
void mesh_topology_free(mesh_topology *tp);

/* ---- validation ---------------------------------------------------------- */

enum {
    MESH_REQUIRE_CLOSED = 1, /* error unless every edge has exactly two triangles */
    MESH_QUIET = 2,          /* no warnings for repairs (they are still reported) */
    MESH_WARN_OPEN = 4       /* warn when not closed ("<name>: mesh is not closed: ...: it is
                                sampled as an open sheet ..."): for obstacles, where a glass
                                open at the top as a container is not */
};

typedef struct mesh_report {
    size_t degenerate;   /* triangles dropped: repeated corner or area ~ 0 */
    size_t unused;       /* vertices dropped: no triangle uses them */
    size_t open_edges;   /* edges used by one triangle */
    size_t nonmanifold;  /* edges used by more than two triangles */
    size_t reoriented;   /* triangles flipped to agree with their neighbours */
    int inverted;        /* 1: the whole mesh was flipped (volume was < 0) */
    int closed;          /* 1: every edge has two triangles */
    double area, volume; /* after the repairs */
} mesh_report;

/* Drop degenerate triangles (area below 1e-24 of the squared bounding-box
 * diagonal, or height below 1e-10 of the longest edge) and unused vertices,
 * make neighbouring triangles agree in orientation (each connected piece
 * keeps the orientation of most of its triangles), flip a closed mesh whose
 * volume is negative, then build the distance index.  `name` (file or
 * body name) starts every message.  Errors: non-finite coordinates or
 * beyond MESH_MAX_COORD, no
 * triangle left, a non-orientable piece, and with MESH_REQUIRE_CLOSED open or
 * non-manifold edges ("<name>: mesh is not closed: 4 edges are used by one
 * triangle only, e.g. (0 0 1)-(1 0 1)").  rep may be NULL. */
int mesh_validate(mesh *m, const char *name, unsigned flags, mesh_report *rep, sl_err *err);

/* ---- primitives (mesh_make.c) ---------------------------------------------
 * Closed and outward, with the distance index built; m is initialised by
 * the call.  Errors on non-finite
 * or non-positive sizes and on levels/segment counts out of range. */

/* 12 triangles. */
int mesh_make_box(mesh *m, const double lo[3], const double hi[3], sl_err *err);
/* Icosahedron subdivided `level` times (0..9: 20 * 4^level triangles),
 * vertices on the sphere. */
int mesh_make_sphere(mesh *m, const double centre[3], double radius, int level, sl_err *err);
/* Axis from the centre of the bottom cap a to that of the top cap b,
 * nseg (3..1000000) segments around, caps as fans about their centres. */
int mesh_make_cylinder(mesh *m, const double a[3], const double b[3], double radius, int nseg,
                       sl_err *err);

/* ---- distance (mesh_distance.c) ----------------------------------------- */

/* Bounding-volume hierarchy plus angle-weighted pseudo-normals (Baerentzen
 * and Aanaes 2005) of faces, edges and vertices.  Built by mesh_validate. */
void mesh_index_build(mesh *m);
void mesh_index_free(mesh_index *ix); /* NULL is fine */
/* Exact distance to the surface, negative inside.  The sign is that of
 * (p - c) . n for the closest point c and the pseudo-normal n of the face,
 * edge or vertex it lies on, which is exact for closed, consistently
 * oriented meshes.  The index must exist (fatal otherwise).  Thread-safe.
 * Cost: a few microseconds near the surface, but deep inside a round body
 * every triangle is nearly equally far and the search visits many of them:
 * fill with mesh_signed_distance_bounded. */
double mesh_signed_distance(const mesh *m, const double p[3]);
/* The same where |d| < dmax; elsewhere a value of the right sign with
 * magnitude >= dmax (usually exactly dmax).  Made for filling: far from the
 * surface it costs a few box tests instead of an exact search (a coarse
 * grid of cells the surface does not touch knows their sign). */
double mesh_signed_distance_bounded(const mesh *m, const double p[3], double dmax);
/* Unsigned distance; c (may be NULL) receives the closest point and *tri
 * (may be NULL) its triangle.  The index must exist. */
double mesh_closest_point(const mesh *m, const double p[3], double c[3], size_t *tri);
/* The same among points closer than dmax: INFINITY (c, tri untouched) if
 * there is none.  Much faster when dmax is small. */
double mesh_closest_point_within(const mesh *m, const double p[3], double dmax, double c[3],
                                 size_t *tri);
/* 1 if p is inside a closed mesh (d < 0; fast, through the sign grid). */
int mesh_inside(const mesh *m, const double p[3]);

#endif
