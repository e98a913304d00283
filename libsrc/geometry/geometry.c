/* geometry: shapes, boundary sampling and fluid filling (see geometry.h). */
#include "geometry/geometry.h"
#include "geometry/mesh.h"
#include "geometry/mesh_progress.h"
#include "geometry/mesh_sample.h"
#include "core/sl_log.h"

#include <math.h>

static double box_outside_distance(const double lo[3], const double hi[3], const double p[3])
{
    double out2 = 0.0, in = -INFINITY;
    for (int d = 0; d < 3; d++) {
        double a = lo[d] - p[d], b = p[d] - hi[d];
        double m = a > b ? a : b; /* > 0 outside along d */
        if (m > 0) out2 += m * m;
        if (m > in) in = m;
    }
    return out2 > 0 ? sqrt(out2) : in; /* in <= 0: minus the depth */
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Capped cylinder: distance outside (> 0) or minus the depth inside. */
static double cylinder_distance(const geo_shape *s, const double p[3])
{
    double ax[3] = {s->p2[0] - s->p1[0], s->p2[1] - s->p1[1], s->p2[2] - s->p1[2]};
    double len = sqrt(dot3(ax, ax));
    double w[3] = {p[0] - s->p1[0], p[1] - s->p1[1], p[2] - s->p1[2]};
    double u = dot3(w, ax) / len; /* along the axis */
    double r2 = dot3(w, w) - u * u;
    double radial = sqrt(r2 > 0 ? r2 : 0) - s->radius;
    double axial = fabs(u - 0.5 * len) - 0.5 * len;
    if (radial > 0 && axial > 0) return sqrt(radial * radial + axial * axial);
    return radial > axial ? radial : axial;
}

/* Plane rectangle: signed distance along the normal where the point
 * projects into the rectangle, else +infinity (no solid there). */
static double plane_distance(const geo_shape *s, const double p[3])
{
    double n[3], w[3] = {p[0] - s->origin[0], p[1] - s->origin[1], p[2] - s->origin[2]};
    cross3(s->e1, s->e2, n);
    double nl = sqrt(dot3(n, n));
    double a = dot3(w, s->e1) / dot3(s->e1, s->e1), b = dot3(w, s->e2) / dot3(s->e2, s->e2);
    if (a < 0 || a > 1 || b < 0 || b > 1) return INFINITY;
    return dot3(w, n) / nl;
}

double geo_solid_distance(const geo_shape *s, const double p[3])
{
    switch (s->kind) {
    case GEO_CYLINDER:
        return cylinder_distance(s, p);
    case GEO_PLANE:
        return plane_distance(s, p);
    case GEO_MESH: {
        double d = mesh_signed_distance_bounded(s->mesh, p, s->dbound);
        return s->mesh_container ? -d : d;
    }
    case GEO_CONTAINER:
        return -box_outside_distance(s->lo, s->hi, p);
    case GEO_BOX:
        return box_outside_distance(s->lo, s->hi, p);
    case GEO_SPHERE: {
        double dx = p[0] - s->centre[0], dy = p[1] - s->centre[1], dz = p[2] - s->centre[2];
        return sqrt(dx * dx + dy * dy + dz * dz) - s->radius;
    }
    }
    return INFINITY;
}

/* Sample the surface of the box [lo, hi] on a grid of about r0 spacing;
 * sign = +1 gives outward normals, -1 inward.  Faces in `open` are left
 * out (their edge particles still belong to the neighbouring faces). */
static size_t sample_box_surface(const double lo[3], const double hi[3], double r0, double sign,
                                 unsigned open, uint32_t body, sl_boundary *b)
{
    int n[3];
    double step[3];
    size_t added = 0;
    for (int d = 0; d < 3; d++) {
        double len = hi[d] - lo[d];
        n[d] = (int)lround(len / r0);
        if (n[d] < 1) n[d] = 1;
        step[d] = len / n[d];
    }
    for (int k = 0; k <= n[2]; k++)
        for (int j = 0; j <= n[1]; j++)
            for (int i = 0; i <= n[0]; i++) {
                int idx[3] = {i, j, k};
                double nrm[3] = {0, 0, 0};
                int on_closed = 0, on_any = 0;
                for (int d = 0; d < 3; d++) {
                    unsigned fmin = 1u << (2 * d), fmax = 1u << (2 * d + 1);
                    if (idx[d] == 0) {
                        on_any = 1;
                        if (!(open & fmin)) {
                            nrm[d] -= sign;
                            on_closed = 1;
                        }
                    }
                    if (idx[d] == n[d]) {
                        on_any = 1;
                        if (!(open & fmax)) {
                            nrm[d] += sign;
                            on_closed = 1;
                        }
                    }
                }
                if (!on_any || !on_closed) continue;
                double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
                prt_boundary_push(b, lo[0] + i * step[0], lo[1] + j * step[1], lo[2] + k * step[2],
                                  nrm[0] / len, nrm[1] / len, nrm[2] / len, body);
                added++;
            }
    return added;
}

/* Fibonacci lattice: near-uniform points on a sphere. */
static size_t sample_sphere(const double c[3], double radius, double r0, uint32_t body,
                            sl_boundary *b)
{
    size_t n = (size_t)lround(4.0 * M_PI * radius * radius / (r0 * r0));
    const double golden = M_PI * (3.0 - sqrt(5.0));
    if (n < 4) return 0;
    for (size_t i = 0; i < n; i++) {
        double z = 1.0 - (2.0 * (double)i + 1.0) / (double)n;
        double rr = sqrt(1.0 - z * z);
        double phi = golden * (double)i;
        double nx = rr * cos(phi), ny = rr * sin(phi);
        prt_boundary_push(b, c[0] + radius * nx, c[1] + radius * ny, c[2] + radius * z, nx, ny, z,
                          body);
    }
    return n;
}

/* Lateral surface and caps of a capped cylinder of radius R between a and
 * b (already moved r0/2 inside), rings spaced about r0, outward normals. */
static size_t sample_cylinder(const double a[3], const double bb[3], double R, double r0,
                              uint32_t body, sl_boundary *b)
{
    double ax[3] = {bb[0] - a[0], bb[1] - a[1], bb[2] - a[2]}, u[3], v[3];
    double len = sqrt(dot3(ax, ax));
    for (int k = 0; k < 3; k++) ax[k] /= len;
    double ref[3] = {fabs(ax[0]) < 0.9 ? 1.0 : 0.0, fabs(ax[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    double d = dot3(ref, ax);
    for (int k = 0; k < 3; k++) u[k] = ref[k] - d * ax[k];
    double ul = sqrt(dot3(u, u));
    for (int k = 0; k < 3; k++) u[k] /= ul;
    cross3(ax, u, v);
    size_t added = 0;
    long nz = lround(len / r0);
    if (nz < 1) nz = 1;
    long nphi = lround(2.0 * M_PI * R / r0);
    if (nphi < 3) nphi = 3;
    for (long iz = 0; iz <= nz; iz++) { /* side rings, staggered */
        double z = len * (double)iz / (double)nz;
        for (long ip = 0; ip < nphi; ip++) {
            double phi = 2.0 * M_PI * ((double)ip + 0.5 * (double)(iz % 2)) / (double)nphi;
            double n[3], c = cos(phi), sn = sin(phi);
            for (int k = 0; k < 3; k++) n[k] = c * u[k] + sn * v[k];
            prt_boundary_push(b, a[0] + z * ax[0] + R * n[0], a[1] + z * ax[1] + R * n[1],
                              a[2] + z * ax[2] + R * n[2], n[0], n[1], n[2], body);
            added++;
        }
    }
    long nr = lround(R / r0); /* caps: rings inside the rim */
    for (int cap = 0; cap < 2; cap++) {
        const double *o = cap ? bb : a, sgn = cap ? 1.0 : -1.0;
        prt_boundary_push(b, o[0], o[1], o[2], sgn * ax[0], sgn * ax[1], sgn * ax[2], body);
        added++;
        for (long ir = 1; ir < nr; ir++) {
            double rr = R * (double)ir / (double)nr;
            long m = lround(2.0 * M_PI * rr / r0);
            for (long ip = 0; ip < m; ip++) {
                double phi = 2.0 * M_PI * (double)ip / (double)m, c = cos(phi), sn = sin(phi);
                prt_boundary_push(b, o[0] + rr * (c * u[0] + sn * v[0]),
                                  o[1] + rr * (c * u[1] + sn * v[1]),
                                  o[2] + rr * (c * u[2] + sn * v[2]), sgn * ax[0], sgn * ax[1],
                                  sgn * ax[2], body);
                added++;
            }
        }
    }
    return added;
}

/* A plane rectangle, grid spacing about r0, r0/2 behind the surface. */
static size_t sample_plane(const geo_shape *s, double r0, uint32_t body, sl_boundary *b)
{
    double n[3];
    cross3(s->e1, s->e2, n);
    double nl = sqrt(dot3(n, n));
    for (int k = 0; k < 3; k++) n[k] /= nl;
    long na = lround(sqrt(dot3(s->e1, s->e1)) / r0), nb = lround(sqrt(dot3(s->e2, s->e2)) / r0);
    if (na < 1) na = 1;
    if (nb < 1) nb = 1;
    size_t added = 0;
    for (long i = 0; i <= na; i++)
        for (long j = 0; j <= nb; j++) {
            double a = (double)i / (double)na, c = (double)j / (double)nb, p[3];
            for (int k = 0; k < 3; k++)
                p[k] = s->origin[k] + a * s->e1[k] + c * s->e2[k] - 0.5 * r0 * n[k];
            prt_boundary_push(b, p[0], p[1], p[2], n[0], n[1], n[2], body);
            added++;
        }
    return added;
}

size_t geo_sample(const geo_shape *s, double r0, uint32_t body, sl_boundary *b)
{
    const double half = 0.5 * r0;
    double lo[3], hi[3];
    switch (s->kind) {
    case GEO_CONTAINER:
        for (int d = 0; d < 3; d++) {
            lo[d] = s->lo[d] - half;
            hi[d] = s->hi[d] + half;
        }
        return sample_box_surface(lo, hi, r0, -1.0, s->open_faces, body, b);
    case GEO_BOX:
        for (int d = 0; d < 3; d++) {
            lo[d] = s->lo[d] + half;
            hi[d] = s->hi[d] - half;
            if (hi[d] < lo[d]) { lo[d] = hi[d] = 0.5 * (s->lo[d] + s->hi[d]); }
        }
        return sample_box_surface(lo, hi, r0, 1.0, 0, body, b);
    case GEO_SPHERE:
        if (s->radius - half < r0) return 0;
        return sample_sphere(s->centre, s->radius - half, r0, body, b);
    case GEO_CYLINDER: {
        double ax[3] = {s->p2[0] - s->p1[0], s->p2[1] - s->p1[1], s->p2[2] - s->p1[2]};
        double len = sqrt(dot3(ax, ax)), a[3], c[3];
        if (s->radius - half < r0 || len - r0 < r0) return 0;
        for (int k = 0; k < 3; k++) {
            a[k] = s->p1[k] + half * ax[k] / len;
            c[k] = s->p2[k] - half * ax[k] / len;
        }
        return sample_cylinder(a, c, s->radius - half, r0, body, b);
    }
    case GEO_PLANE:
        return sample_plane(s, r0, body, b);
    case GEO_MESH: {
        msample_params mp =
            msample_defaults(r0, s->mesh_container ? MSAMPLE_CONTAINER : MSAMPLE_OBSTACLE);
        size_t added = 0;
        sl_err err;
        if (msample_surface(s->mesh, &mp, body, b, &added, &err)) sl_fatal("%s", err.msg);
        return added;
    }
    }
    return 0;
}

void geo_bounds(const geo_shape *s, double r0, double lo[3], double hi[3])
{
    if (s->kind == GEO_MESH) {
        mesh_bounds(s->mesh, lo, hi);
        for (int d = 0; d < 3; d++) {
            lo[d] -= r0;
            hi[d] += r0;
        }
        return;
    }
    for (int d = 0; d < 3; d++) {
        if (s->kind == GEO_CYLINDER) {
            lo[d] = fmin(s->p1[d], s->p2[d]) - s->radius;
            hi[d] = fmax(s->p1[d], s->p2[d]) + s->radius;
        } else if (s->kind == GEO_PLANE) {
            double c[4] = {s->origin[d], s->origin[d] + s->e1[d], s->origin[d] + s->e2[d],
                           s->origin[d] + s->e1[d] + s->e2[d]};
            lo[d] = fmin(fmin(c[0], c[1]), fmin(c[2], c[3])) - r0;
            hi[d] = fmax(fmax(c[0], c[1]), fmax(c[2], c[3])) + r0;
        } else if (s->kind == GEO_SPHERE) {
            lo[d] = s->centre[d] - s->radius;
            hi[d] = s->centre[d] + s->radius;
        } else {
            lo[d] = s->lo[d] - r0;
            hi[d] = s->hi[d] + r0;
        }
    }
}


/* 1 if p lies beyond the walls of a box container: a region point dropped
 * there is fluid the user asked for that is lost.  (A mesh container is
 * not counted: a box region over a glass is the way to fill the glass.) */
static int beyond_container(const geo_shape *s, double d)
{
    return d < 0.0 && s->kind == GEO_CONTAINER;
}

/* The lattice of spacing r0 over [lo, hi] (first point at lo + r0/2),
 * keeping points at least r0/2 inside `region` and r0/2 from every solid;
 * *outside (may be NULL) counts the points dropped beyond a container. */
static size_t fill_lattice(const geo_shape *region, const double lo[3], const double hi[3],
                           double r0, const double v[3], const geo_shape *shapes, size_t nshapes,
                           sl_fluid *f, size_t *outside)
{
    long n[3];
    size_t added = 0, beyond = 0;
    const double keep = 0.5 * r0 * (1.0 - 1e-9);
    for (int d = 0; d < 3; d++) n[d] = (long)floor((hi[d] - lo[d]) / r0 + 1e-9);
    const size_t row = n[0] > 0 ? (size_t)n[0] : 0, plane = row * (n[1] > 0 ? (size_t)n[1] : 0);
    mesh_progress mp;
    mesh_progress_start(&mp, plane * (n[2] > 0 ? (size_t)n[2] : 0),
                        "filling '%s' (%ld x %ld x %ld lattice points)",
                        region->name[0] ? region->name : "a box", n[0], n[1], n[2]);
    for (long k = 0; k < n[2]; k++)
        for (long j = 0; j < n[1]; j++) {
            mesh_progress_at(&mp, (size_t)k * plane + (size_t)j * row);
            for (long i = 0; i < n[0]; i++) {
                double p[3] = {lo[0] + ((double)i + 0.5) * r0, lo[1] + ((double)j + 0.5) * r0,
                               lo[2] + ((double)k + 0.5) * r0};
                if (geo_solid_distance(region, p) > -keep) continue; /* outside the region */
                int ok = 1;
                for (size_t s = 0; s < nshapes; s++) {
                    double d = geo_solid_distance(&shapes[s], p);
                    if (d >= keep) continue;
                    ok = 0;
                    if (beyond_container(&shapes[s], d)) {
                        beyond++;
                        break;
                    }
                    if (!outside) break;
                }
                if (!ok) continue;
                prt_fluid_push(f, p[0], p[1], p[2], v[0], v[1], v[2]);
                added++;
            }
        }
    mesh_progress_end(&mp);
    if (outside) *outside = beyond;
    return added;
}

size_t geo_fill_box(const double lo[3], const double hi[3], double r0, const double v[3],
                    const geo_shape *shapes, size_t nshapes, sl_fluid *f)
{
    geo_shape box = {.kind = GEO_BOX};
    for (int d = 0; d < 3; d++) {
        box.lo[d] = lo[d];
        box.hi[d] = hi[d];
    }
    return fill_lattice(&box, lo, hi, r0, v, shapes, nshapes, f, NULL);
}

size_t geo_fill_region(const geo_shape *region, double r0, const double v[3],
                       const geo_shape *shapes, size_t nshapes, sl_fluid *f, size_t *outside)
{
    double lo[3], hi[3];
    if (region->kind == GEO_BOX)
        return fill_lattice(region, region->lo, region->hi, r0, v, shapes, nshapes, f, outside);
    geo_bounds(region, 0.0, lo, hi);
    return fill_lattice(region, lo, hi, r0, v, shapes, nshapes, f, outside);
}
