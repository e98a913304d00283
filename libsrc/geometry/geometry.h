/*
 * geometry: the shapes a case is built from, their sampling with boundary
 * particles (paper Sec. 3.2 and 3.4) and the filling of fluid regions.
 *
 * Convention (documented in the README): the surface of a shape is the
 * physical wall.  Boundary particles sit r0/2 behind it, on the solid side,
 * and fluid particles are placed on a lattice whose first layer is r0/2 in
 * front of it.  A fluid particle resting against a wall is then exactly r0
 * from the boundary particles, the contact distance of the paper's
 * penetration test ||x_i - x_b|| < r0, and a tank of inner height H filled
 * with n = H / r0 layers holds a water column of height H.
 * Normals point from the solid into the fluid.
 */
#ifndef SL_GEOMETRY_H
#define SL_GEOMETRY_H

#include <stddef.h>
#include <stdint.h>

#include "particles/particles.h"

typedef enum { GEO_CONTAINER, GEO_BOX, GEO_SPHERE, GEO_CYLINDER, GEO_PLANE, GEO_MESH } geo_kind;

struct mesh;

/* Faces of a box, for the container's `open` list. */
enum { GEO_XMIN = 1, GEO_XMAX = 2, GEO_YMIN = 4, GEO_YMAX = 8, GEO_ZMIN = 16, GEO_ZMAX = 32 };

typedef struct geo_shape {
    geo_kind kind;
    char name[64];
    double lo[3], hi[3];            /* container (inner walls) and box */
    double centre[3];               /* sphere */
    double radius;                  /* sphere, cylinder */
    double p1[3], p2[3];            /* cylinder: axis end points (solid, capped) */
    double origin[3], e1[3], e2[3]; /* plane: rectangle origin + s e1 + t e2, s, t in [0, 1];
                                       the fluid is on the side of e1 x e2 */
    unsigned open_faces;            /* container: faces left open (GEO_XMIN | ...) */
    struct mesh *mesh;              /* mesh: validated, with its distance index */
    int mesh_container;             /* mesh: fluid inside (1) or outside (0) */
    double dbound;                  /* mesh: distances beyond this need only their sign */
} geo_shape;

/* Signed distance from p to the solid: positive in the fluid space,
 * negative inside the solid.  Open container faces count as closed here
 * (fluid does not fill the space beyond them). */
double geo_solid_distance(const geo_shape *s, const double p[3]);

/* Sample the shape with boundary particles of spacing close to r0 placed
 * r0/2 behind its surface; appends to b with body index `body`. Returns
 * the number of particles added, or 0 when the shape is too small to
 * sample (the caller reports that). */
size_t geo_sample(const geo_shape *s, double r0, uint32_t body, sl_boundary *b);

/* Fill the box [lo, hi] with a cubic lattice of spacing r0 (first layer at
 * lo + r0/2), keeping points at least r0/2 from every shape's solid, with
 * initial velocity v.  Returns the number of particles added. */
size_t geo_fill_box(const double lo[3], const double hi[3], double r0, const double v[3],
                    const geo_shape *shapes, size_t nshapes, sl_fluid *f);

/* Fill the inside of a region shape (box, sphere, cylinder, mesh) with a
 * cubic lattice of spacing r0 anchored at the shape's bounds, keeping
 * points at least r0/2 inside the region and r0/2 away from every solid.
 * *outside (may be NULL) receives the number of lattice points dropped
 * because they lie beyond the walls of a box container (not merely within
 * r0/2 of them): fluid the region asks for that would be lost. */
size_t geo_fill_region(const geo_shape *region, double r0, const double v[3],
                       const geo_shape *shapes, size_t nshapes, sl_fluid *f, size_t *outside);


/* Axis-aligned bounds of a shape's boundary particles (for the grid). */
void geo_bounds(const geo_shape *s, double r0, double lo[3], double hi[3]);

#endif
