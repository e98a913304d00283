/*
 * surface: the water as a surface, reconstructed from the particles of one
 * written time, for ParaView and for measurements (issue 19).
 *
 * Method (srf_field.c, srf_contour.c):
 *   1. A colour field on a uniform grid of spacing dx (default r0/2),
 *        c(x) = sum_j V_j W(|x - x_j|, h),  V_j = r0^3,
 *      the SPH estimate of the fraction of space the fluid fills (1 inside,
 *      1/2 on a flat free surface, 0 outside).  It is scattered particle
 *      by particle; each thread owns a block of grid planes, so every grid
 *      value is summed in the same particle order by one thread: the same
 *      field for any thread count.
 *      With kernel anisotropic, each particle's kernel is stretched along
 *      the principal axes of its neighbours (Yu & Turk 2013; srf_field.c).
 *      A particle where the sampled field (trilinear between the grid
 *      points) is not above iso -- a lone drop, a jet one particle thin, a
 *      pair whose narrow peak falls between grid points -- would lie
 *      outside the surface: it raises the field to a ball of radius
 *      rb = dropletRadius r0 around it, f = max(f, iso (2 - d / rb)), so it
 *      keeps a closed surface of its own (its volume underestimated, 0.52
 *      r0^3 for rb = r0 / 2, rather than lost).  rb is at least the grid
 *      step dx, so that a grid point lies inside every ball.  The other
 *      particles, the bulk and its surface, are left as the field has them.
 *   2. Optionally `smoothing` passes of the separable [1 2 1]/4 filter
 *      (symmetric: a flat surface stays where it is).
 *   3. The iso-surface c = isoValue (default 1/2) by marching cubes.  The
 *      case table is generated, not typed in: on each cube face the inside
 *      corners are cut off (the asymptotically ambiguous face is resolved
 *      as "inside corners apart"), and two cubes sharing a face see the same
 *      corners, so they cut it the same way: the surface has no cracks and,
 *      on a closed body of fluid, every edge is shared by exactly two
 *      triangles.  Triangles are oriented with the normal pointing out of
 *      the fluid.  Vertices are shared (one per crossed grid edge); they and
 *      the triangles are numbered plane by plane from counts, so the mesh
 *      is identical for any thread count.
 *   4. Velocity and pressure at each vertex by Shepard-normalised SPH
 *      interpolation, sum_j A_j W_j / sum_j W_j.
 *
 * Why written here rather than taken from VTK (vtkSPHInterpolator,
 * vtkFlyingEdges3D): the solver and its utilities build without VTK (it is
 * only a test and post-processing dependency through python3-vtk9), and
 * this library is ~1100 lines of C with no dependency.
 *
 * The library knows nothing of case folders: it takes positions and
 * fields, r0 and the parameters; system/surfaceDict is read by
 * srf_params_read.
 */
#ifndef SL_SURFACE_H
#define SL_SURFACE_H

#include <stddef.h>
#include <stdint.h>

#include "core/sl_log.h"
#include "dictionary/dict.h"

typedef struct srf_params {
    double grid_spacing;   /* gridSpacing: grid step in units of r0 (0.5) */
    double iso_value;      /* isoValue: the colour level of the surface (0.5) */
    double kernel_radius;  /* kernelRadius: the support h in units of r0 (2, the solver's) */
    int smoothing;         /* smoothing: passes of the [1 2 1]/4 filter (0) */
    double droplet_radius; /* dropletRadius: a lone particle's ball, units of r0 (0.5; 0: none) */
    int anisotropic;       /* kernel: isotropic (0) or anisotropic (1, Yu & Turk 2013) */
    double anisotropy_radius; /* anisotropyRadius: the covariance's neighbourhood, units of h (2) */
    double max_stretch;       /* maxStretch: largest ratio of the variances, k_r (4) */
    long min_neighbours;      /* minNeighbours: fewer: isotropic, N_eps (25) */
} srf_params;

/* The particles of one time: n positions and (optional, NULL) fields. */
typedef struct srf_particles {
    size_t n;
    const double *x, *y, *z;
    const double *vx, *vy, *vz; /* velocity, or NULL */
    const double *p;            /* pressure, or NULL */
    double r0;                  /* particle spacing */
} srf_particles;

/* A triangle mesh; tri[3 t + k] are vertex indices (0-based). */
typedef struct srf_mesh {
    size_t nv, nt;
    double *x, *y, *z;
    double *vx, *vy, *vz, *p; /* interpolated; NULL when the input had none */
    int64_t *tri;
    /* the grid it came from, for reports */
    int nc[3];
    double dx;
} srf_mesh;

/* The defaults of etc/caseDicts/surfaceDict. */
void srf_params_default(srf_params *p);
/* Read a surfaceDict (d may be NULL: the defaults).  Unknown keys are
 * warnings; a malformed or impossible value stops with file, line and key. */
void srf_params_read(const dict *d, srf_params *p);
/* The keys srf_params_read knows (NULL-terminated). */
extern const char *const srf_keys[];

/* Reconstruct the surface of the particles into m (which is overwritten;
 * free with srf_mesh_free).  Returns 0, or nonzero with err filled (no
 * particles, a grid too large for memory). */
int srf_reconstruct(const srf_particles *in, const srf_params *prm, srf_mesh *m, sl_err *err);
void srf_mesh_free(srf_mesh *m);

/* Measurements.  Area: sum of the triangles' areas.  Volume: by the
 * divergence theorem, sum (a . (b x c)) / 6, positive for a closed surface
 * oriented outwards. */
double srf_area(const srf_mesh *m);
double srf_volume(const srf_mesh *m);
/* Free-surface elevation: the highest z at which the vertical line through
 * (x, y) meets the surface (a triangle whose projection on the xy plane
 * holds the point, edges included); NAN if the line misses it. */
double srf_height_at(const srf_mesh *m, double x, double y);
/* Edges used by other than exactly two triangles (0 for a closed surface);
 * *nedges gets the number of distinct edges (NULL: not wanted). */
size_t srf_open_edges(const srf_mesh *m, size_t *nedges);

/* ---- inside the library (srf_field.c, srf_contour.c) ---- */

/* A uniform grid of values f[(k nc[1] + j) nc[0] + i] at lo + (i, j, k) dx. */
typedef struct srf_grid {
    double lo[3], dx;
    int nc[3];
    float *f;
} srf_grid;

/* Colour field of the particles on g (g->lo, dx, nc set; f allocated),
 * with isotropic or anisotropic kernels, raised to the droplet balls of the
 * particles where it is not above iso. */
void srf_colour_field(const srf_particles *in, const srf_params *prm, srf_grid *g);
/* passes of the [1 2 1]/4 filter along x, y and z. */
void srf_smooth(srf_grid *g, int passes);
/* Marching cubes of g at level iso into m (vertices and triangles only). */
void srf_contour(const srf_grid *g, double iso, srf_mesh *m);
/* Shepard interpolation of velocity and pressure at m's vertices. */
void srf_interpolate(const srf_particles *in, double h, srf_mesh *m);

#endif
