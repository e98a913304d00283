/* geometry: shapes, boundary sampling and fluid filling (see geometry.h). */
#include "geometry/geometry.h"

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

double geo_solid_distance(const geo_shape *s, const double p[3])
{
    switch (s->kind) {
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
                        if (!(open & fmin)) { nrm[d] -= sign; on_closed = 1; }
                    }
                    if (idx[d] == n[d]) {
                        on_any = 1;
                        if (!(open & fmax)) { nrm[d] += sign; on_closed = 1; }
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
        prt_boundary_push(b, c[0] + radius * nx, c[1] + radius * ny, c[2] + radius * z,
                          nx, ny, z, body);
    }
    return n;
}

size_t geo_sample(const geo_shape *s, double r0, uint32_t body, sl_boundary *b)
{
    const double half = 0.5 * r0;
    double lo[3], hi[3];
    switch (s->kind) {
    case GEO_CONTAINER:
        for (int d = 0; d < 3; d++) { lo[d] = s->lo[d] - half; hi[d] = s->hi[d] + half; }
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
    }
    return 0;
}

void geo_bounds(const geo_shape *s, double r0, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) {
        if (s->kind == GEO_SPHERE) {
            lo[d] = s->centre[d] - s->radius;
            hi[d] = s->centre[d] + s->radius;
        } else {
            lo[d] = s->lo[d] - r0;
            hi[d] = s->hi[d] + r0;
        }
    }
}

size_t geo_fill_box(const double lo[3], const double hi[3], double r0, const double v[3],
                    const geo_shape *shapes, size_t nshapes, sl_fluid *f)
{
    long n[3];
    size_t added = 0;
    const double keep = 0.5 * r0 * (1.0 - 1e-9);
    for (int d = 0; d < 3; d++) n[d] = (long)floor((hi[d] - lo[d]) / r0 + 1e-9);
    for (long k = 0; k < n[2]; k++)
        for (long j = 0; j < n[1]; j++)
            for (long i = 0; i < n[0]; i++) {
                double p[3] = {lo[0] + ((double)i + 0.5) * r0, lo[1] + ((double)j + 0.5) * r0,
                               lo[2] + ((double)k + 0.5) * r0};
                int ok = 1;
                for (size_t s = 0; s < nshapes && ok; s++)
                    if (geo_solid_distance(&shapes[s], p) < keep) ok = 0;
                if (!ok) continue;
                prt_fluid_push(f, p[0], p[1], p[2], v[0], v[1], v[2]);
                added++;
            }
    return added;
}
