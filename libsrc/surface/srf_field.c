/*
 * srf_field: the colour field of the particles on a grid, its smoothing,
 * and the interpolation of particle fields to the surface's vertices (see
 * surface.h).
 *
 * The particles are binned once into cells of size h, layer by layer in z
 * (cz, then cy, then cx; a stable counting sort, so each cell keeps the
 * input order).  The scatter gives each thread a block of SRF_PLANES grid
 * planes and has it visit the particles of the cell layers that reach
 * them: its writes are its own, and each grid value is the sum over the
 * particles in the same order whatever the thread count.
 */
#include "surface/surface.h"

#include "core/sl_mem.h"
#include "kernel/kernel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Grid planes per work unit of the scatter. */
#define SRF_PLANES 4

/* Particles binned into cells of size h (positions copied in cell order). */
typedef struct srf_cells {
    double lo[3], size;
    int nc[3];
    size_t *start;     /* cell c: [start[c], start[c + 1]) */
    size_t *order;     /* order[s] = input index of sorted particle s */
    double *x, *y, *z; /* sorted copies */
} srf_cells;

static int clampi(long v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : (int)v; }

static void cells_build(srf_cells *c, const srf_particles *in, double h)
{
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const double *p[3] = {in->x, in->y, in->z};
    for (int d = 0; d < 3; d++) c->lo[d] = INFINITY;
    for (size_t i = 0; i < in->n; i++)
        for (int d = 0; d < 3; d++) {
            if (p[d][i] < c->lo[d]) c->lo[d] = p[d][i];
            if (p[d][i] > hi[d]) hi[d] = p[d][i];
        }
    c->size = h;
    for (int d = 0; d < 3; d++) c->nc[d] = (int)floor((hi[d] - c->lo[d]) / h) + 1;
    size_t ncell = (size_t)c->nc[0] * (size_t)c->nc[1] * (size_t)c->nc[2];
    size_t *cell = sl_malloc((in->n ? in->n : 1) * sizeof *cell, "surface cells");
    c->start = sl_calloc(ncell + 1, sizeof *c->start, "surface cell starts");
    for (size_t i = 0; i < in->n; i++) {
        int q[3];
        for (int d = 0; d < 3; d++)
            q[d] = clampi((long)floor((p[d][i] - c->lo[d]) / h), 0, c->nc[d] - 1);
        cell[i] =
            ((size_t)q[2] * (size_t)c->nc[1] + (size_t)q[1]) * (size_t)c->nc[0] + (size_t)q[0];
        c->start[cell[i] + 1]++;
    }
    for (size_t k = 0; k < ncell; k++) c->start[k + 1] += c->start[k];
    size_t *fill = sl_malloc((ncell + 1) * sizeof *fill, "surface cell fill");
    memcpy(fill, c->start, (ncell + 1) * sizeof *fill);
    c->order = sl_malloc((in->n ? in->n : 1) * sizeof *c->order, "surface order");
    c->x = sl_malloc((in->n ? in->n : 1) * sizeof(double), "surface positions");
    c->y = sl_malloc((in->n ? in->n : 1) * sizeof(double), "surface positions");
    c->z = sl_malloc((in->n ? in->n : 1) * sizeof(double), "surface positions");
    for (size_t i = 0; i < in->n; i++) {
        size_t s = fill[cell[i]]++;
        c->order[s] = i;
        c->x[s] = in->x[i];
        c->y[s] = in->y[i];
        c->z[s] = in->z[i];
    }
    free(fill);
    free(cell);
}

static void cells_free(srf_cells *c)
{
    free(c->start);
    free(c->order);
    free(c->x);
    free(c->y);
    free(c->z);
}

/* The first and last grid index within h of coordinate v along axis d. */
static void grid_range(const srf_grid *g, int d, double v, double h, int *a, int *b)
{
    *a = clampi((long)ceil((v - h - g->lo[d]) / g->dx), 0, g->nc[d] - 1);
    *b = clampi((long)floor((v + h - g->lo[d]) / g->dx), 0, g->nc[d] - 1);
}

/* Add particle (px, py, pz)'s share vol W to the planes [k0, k1) of g. */
static void scatter_one(srf_grid *g, const krn_kernel *k, double vol, double px, double py,
                        double pz, int k0, int k1)
{
    const double h = k->h, h2 = h * h, dx = g->dx;
    int i0, i1, j0, j1, z0, z1;
    grid_range(g, 0, px, h, &i0, &i1);
    grid_range(g, 1, py, h, &j0, &j1);
    grid_range(g, 2, pz, h, &z0, &z1);
    if (z0 < k0) z0 = k0;
    if (z1 > k1 - 1) z1 = k1 - 1;
    for (int kk = z0; kk <= z1; kk++) {
        const double dz = g->lo[2] + kk * dx - pz;
        for (int j = j0; j <= j1; j++) {
            const double dy = g->lo[1] + j * dx - py, r2yz = dy * dy + dz * dz;
            if (r2yz >= h2) continue;
            float *row = g->f + ((size_t)kk * (size_t)g->nc[1] + (size_t)j) * (size_t)g->nc[0];
            for (int i = i0; i <= i1; i++) {
                const double ddx = g->lo[0] + i * dx - px;
                row[i] += (float)(vol * krn_w(k, sqrt(ddx * ddx + r2yz)));
            }
        }
    }
}

/* Raise the planes [k0, k1) of g to the ball of particle (px, py, pz):
 * f = max(f, iso (2 - d / rb)), which is above iso within rb. */
static void ball_one(srf_grid *g, double rb, double iso, double px, double py, double pz, int k0,
                     int k1)
{
    int i0, i1, j0, j1, z0, z1;
    const double reach = 2 * rb, dx = g->dx;
    grid_range(g, 0, px, reach, &i0, &i1);
    grid_range(g, 1, py, reach, &j0, &j1);
    grid_range(g, 2, pz, reach, &z0, &z1);
    if (z0 < k0) z0 = k0;
    if (z1 > k1 - 1) z1 = k1 - 1;
    for (int kk = z0; kk <= z1; kk++)
        for (int j = j0; j <= j1; j++) {
            const double dy = g->lo[1] + j * dx - py, dz = g->lo[2] + kk * dx - pz;
            float *row = g->f + ((size_t)kk * (size_t)g->nc[1] + (size_t)j) * (size_t)g->nc[0];
            for (int i = i0; i <= i1; i++) {
                const double ddx = g->lo[0] + i * dx - px;
                const float b = (float)(iso * (2 - sqrt(ddx * ddx + dy * dy + dz * dz) / rb));
                if (b > row[i]) row[i] = b;
            }
        }
}

/* The trilinear interpolation of g at (x, y, z) (inside the grid). */
static double grid_at(const srf_grid *g, double x, double y, double z)
{
    const double q[3] = {(x - g->lo[0]) / g->dx, (y - g->lo[1]) / g->dx, (z - g->lo[2]) / g->dx};
    int c[3];
    double t[3];
    for (int d = 0; d < 3; d++) {
        c[d] = clampi((long)floor(q[d]), 0, g->nc[d] - 2);
        t[d] = q[d] - c[d];
    }
    double v = 0;
    for (int k = 0; k < 8; k++) {
        const int di = k & 1, dj = k >> 1 & 1, dk = k >> 2 & 1;
        const double w = (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dk ? t[2] : 1 - t[2]);
        v += w *
            (double)g->f[((size_t)(c[2] + dk) * (size_t)g->nc[1] + (size_t)(c[1] + dj)) *
                             (size_t)g->nc[0] +
                         (size_t)(c[0] + di)];
    }
    return v;
}

/* ---- anisotropic kernels (Yu & Turk 2013, Sec. 3.2-3.3) ----------------
 * Per particle, the weighted covariance of its neighbours within
 * ra = anisotropyRadius h, w = 1 - (r / ra)^3 (their eq. 6), gives principal
 * axes R and variances s1 >= s2 >= s3.  With at least minNeighbours
 * neighbours the kernel is stretched along the axes by factors
 * proportional to s1, max(s2, s1 / k), max(s3, s1 / k) (k = maxStretch,
 * eq. 7), scaled to a product of 1 so that the kernel keeps its volume and
 * its integral; with fewer it stays the isotropic one.  In the bulk the
 * covariance is isotropic and so is the kernel; at a flat free surface the
 * half-ball of neighbours flattens it across the surface and widens it
 * along it, which smooths the lattice's terraces without the volume loss of
 * a wider isotropic kernel.  The centres are not smoothed (their eq. 5):
 * that moves a flat free surface inwards by most of the neighbourhood's
 * mean offset. */

typedef struct srf_aniso {
    double *g;    /* 6 per particle: G = R diag(1 / (h s)) R^T as xx yy zz xy xz yz */
    double *ext;  /* 3 per particle: half-extent of the support along x, y, z */
    double reach; /* the largest half-extent (for the scatter's blocks) */
} srf_aniso;

/* Eigenvalues d and eigenvectors (columns of v) of the symmetric a, by
 * cyclic Jacobi rotations. */
static void jacobi3(double a[3][3], double d[3], double v[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) v[i][j] = i == j;
    for (int sweep = 0; sweep < 50; sweep++) {
        const double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        if (off <= 1e-30 * (fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2])) || off == 0) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0) continue;
                const double th = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                const double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
                const double c = 1 / sqrt(t * t + 1), sn = t * c;
                for (int k = 0; k < 3; k++) { /* a = J^T a J */
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - sn * akq;
                    a[k][q] = sn * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - sn * aqk;
                    a[q][k] = sn * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - sn * vkq;
                    v[k][q] = sn * vkp + c * vkq;
                }
            }
    }
    for (int i = 0; i < 3; i++) d[i] = a[i][i];
}

/* G and the support's extents of sorted particle s. */
static void aniso_one(const srf_cells *c, size_t s, double h, const srf_params *prm, double *g,
                      double *ext)
{
    const double ra = prm->anisotropy_radius * h, ra2 = ra * ra;
    const double q[3] = {c->x[s], c->y[s], c->z[s]};
    const int reach = (int)ceil(ra / c->size);
    int lo[3], hi[3];
    double w = 0, m[3] = {0, 0, 0}, cv[3][3] = {{0}};
    long nb = 0;
    for (int d = 0; d < 3; d++) {
        const int cd = clampi((long)floor((q[d] - c->lo[d]) / c->size), 0, c->nc[d] - 1);
        lo[d] = clampi(cd - reach, 0, c->nc[d] - 1);
        hi[d] = clampi(cd + reach, 0, c->nc[d] - 1);
    }
    /* two sweeps: the weighted mean, then the covariance about it */
    for (int pass = 0; pass < 2; pass++) {
        for (int cz = lo[2]; cz <= hi[2]; cz++)
            for (int cy = lo[1]; cy <= hi[1]; cy++) {
                const size_t row = ((size_t)cz * (size_t)c->nc[1] + (size_t)cy) * (size_t)c->nc[0];
                for (size_t t = c->start[row + (size_t)lo[0]];
                     t < c->start[row + (size_t)hi[0] + 1]; t++) {
                    const double r[3] = {c->x[t] - q[0], c->y[t] - q[1], c->z[t] - q[2]};
                    const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
                    if (r2 >= ra2) continue;
                    const double rr = sqrt(r2) / ra, wt = 1 - rr * rr * rr;
                    if (pass == 0) {
                        w += wt;
                        nb++;
                        for (int d = 0; d < 3; d++) m[d] += wt * r[d];
                        continue;
                    }
                    for (int i = 0; i < 3; i++)
                        for (int j = 0; j < 3; j++) cv[i][j] += wt * (r[i] - m[i]) * (r[j] - m[j]);
                }
            }
        if (pass == 0)
            for (int d = 0; d < 3; d++) m[d] /= w;
    }
    double sc[3] = {1, 1, 1}, v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    if (nb - 1 >= prm->min_neighbours) { /* nb counts the particle itself */
        double ev[3];
        jacobi3(cv, ev, v);
        double big = fmax(ev[0], fmax(ev[1], ev[2]));
        if (big > 0) {
            for (int k = 0; k < 3; k++) sc[k] = fmax(ev[k], big / prm->max_stretch);
            const double norm = cbrt(sc[0] * sc[1] * sc[2]);
            for (int k = 0; k < 3; k++) sc[k] /= norm;
        }
    }
    /* G = V diag(1 / (h s)) V^T; the support is the ellipsoid |G r| < 1 */
    double G[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            G[i][j] = 0;
            for (int k = 0; k < 3; k++) G[i][j] += v[i][k] * v[j][k] / (h * sc[k]);
        }
    g[0] = G[0][0];
    g[1] = G[1][1];
    g[2] = G[2][2];
    g[3] = G[0][1];
    g[4] = G[0][2];
    g[5] = G[1][2];
    for (int d = 0; d < 3; d++) { /* bounding box of the ellipsoid V diag(h s) */
        double e = 0;
        for (int k = 0; k < 3; k++) e += (v[d][k] * h * sc[k]) * (v[d][k] * h * sc[k]);
        ext[d] = sqrt(e);
    }
}

static void aniso_build(const srf_cells *c, size_t n, double h, const srf_params *prm, srf_aniso *a)
{
    a->g = sl_malloc((n ? n : 1) * 6 * sizeof *a->g, "surface kernels");
    a->ext = sl_malloc((n ? n : 1) * 3 * sizeof *a->ext, "surface kernels");
#pragma omp parallel for schedule(dynamic, 256)
    for (size_t s = 0; s < n; s++) aniso_one(c, s, h, prm, a->g + 6 * s, a->ext + 3 * s);
    a->reach = h;
    for (size_t s = 0; s < 3 * n; s++) a->reach = fmax(a->reach, a->ext[s]);
}

/* Add the anisotropic kernel of particle (px, py, pz) to planes [k0, k1). */
static void scatter_aniso(srf_grid *g, const krn_kernel *k, double vol, double px, double py,
                          double pz, const double *G, const double *ext, int k0, int k1)
{
    const double dx = g->dx, h = k->h;
    int i0, i1, j0, j1, z0, z1;
    i0 = clampi((long)ceil((px - ext[0] - g->lo[0]) / dx), 0, g->nc[0] - 1);
    i1 = clampi((long)floor((px + ext[0] - g->lo[0]) / dx), 0, g->nc[0] - 1);
    j0 = clampi((long)ceil((py - ext[1] - g->lo[1]) / dx), 0, g->nc[1] - 1);
    j1 = clampi((long)floor((py + ext[1] - g->lo[1]) / dx), 0, g->nc[1] - 1);
    z0 = clampi((long)ceil((pz - ext[2] - g->lo[2]) / dx), k0, k1 - 1);
    z1 = clampi((long)floor((pz + ext[2] - g->lo[2]) / dx), k0, k1 - 1);
    if (pz + ext[2] < g->lo[2] + k0 * dx || pz - ext[2] > g->lo[2] + (k1 - 1) * dx) return;
    for (int kk = z0; kk <= z1; kk++) {
        const double rz = g->lo[2] + kk * dx - pz;
        for (int j = j0; j <= j1; j++) {
            const double ry = g->lo[1] + j * dx - py;
            float *row = g->f + ((size_t)kk * (size_t)g->nc[1] + (size_t)j) * (size_t)g->nc[0];
            for (int i = i0; i <= i1; i++) {
                const double rx = g->lo[0] + i * dx - px;
                const double ux = G[0] * rx + G[3] * ry + G[4] * rz;
                const double uy = G[3] * rx + G[1] * ry + G[5] * rz;
                const double uz = G[4] * rx + G[5] * ry + G[2] * rz;
                const double q2 = ux * ux + uy * uy + uz * uz;
                if (q2 < 1) row[i] += (float)(vol * krn_w(k, h * sqrt(q2)));
            }
        }
    }
}

void srf_colour_field(const srf_particles *in, const srf_params *prm, srf_grid *g)
{
    srf_cells c;
    krn_kernel k;
    srf_aniso an = {NULL, NULL, 0};
    const double h = prm->kernel_radius * in->r0, iso = prm->iso_value;
    const double vol = in->r0 * in->r0 * in->r0;
    /* a ball narrower than the grid step might hold no grid point (a grid
     * point lies within sqrt(3)/2 dx of any particle); 2 ball <= h keeps it
     * within the scatter's reach */
    double ball = prm->droplet_radius * in->r0;
    if (ball > 0 && ball < g->dx) ball = g->dx;
    if (2 * ball > h) ball = h / 2;
    const size_t npts = (size_t)g->nc[0] * (size_t)g->nc[1] * (size_t)g->nc[2];
    krn_init(&k, h);
    cells_build(&c, in, h);
    if (prm->anisotropic) aniso_build(&c, in->n, h, prm, &an);
    const double reach = prm->anisotropic ? an.reach : h;
    memset(g->f, 0, npts * sizeof *g->f);
    const long nblocks = (g->nc[2] + SRF_PLANES - 1) / SRF_PLANES;
    const size_t per_layer = (size_t)c.nc[0] * (size_t)c.nc[1];
#pragma omp parallel for schedule(dynamic, 1)
    for (long b = 0; b < nblocks; b++) {
        const int k0 = (int)(b * SRF_PLANES);
        const int k1 = k0 + SRF_PLANES < g->nc[2] ? k0 + SRF_PLANES : g->nc[2];
        const double zlo = g->lo[2] + k0 * g->dx - reach, zhi = g->lo[2] + (k1 - 1) * g->dx + reach;
        const int c0 = clampi((long)floor((zlo - c.lo[2]) / h), 0, c.nc[2] - 1);
        const int c1 = clampi((long)floor((zhi - c.lo[2]) / h), 0, c.nc[2] - 1);
        const size_t s0 = c.start[(size_t)c0 * per_layer],
                     s1 = c.start[(size_t)(c1 + 1) * per_layer];
        if (an.g)
            for (size_t s = s0; s < s1; s++)
                scatter_aniso(g, &k, vol, c.x[s], c.y[s], c.z[s], an.g + 6 * s, an.ext + 3 * s, k0,
                              k1);
        else
            for (size_t s = s0; s < s1; s++)
                scatter_one(g, &k, vol, c.x[s], c.y[s], c.z[s], k0, k1);
    }
    free(an.g);
    free(an.ext);
    if (ball > 0) { /* the particles the field leaves out, and their balls */
        unsigned char *lone = sl_malloc(in->n ? in->n : 1, "surface lone particles");
#pragma omp parallel for schedule(static)
        for (size_t s = 0; s < in->n; s++) lone[s] = grid_at(g, c.x[s], c.y[s], c.z[s]) <= iso;
#pragma omp parallel for schedule(dynamic, 1)
        for (long b = 0; b < nblocks; b++) {
            const int k0 = (int)(b * SRF_PLANES);
            const int k1 = k0 + SRF_PLANES < g->nc[2] ? k0 + SRF_PLANES : g->nc[2];
            const double zlo = g->lo[2] + k0 * g->dx - h, zhi = g->lo[2] + (k1 - 1) * g->dx + h;
            const int c0 = clampi((long)floor((zlo - c.lo[2]) / h), 0, c.nc[2] - 1);
            const int c1 = clampi((long)floor((zhi - c.lo[2]) / h), 0, c.nc[2] - 1);
            for (size_t s = c.start[(size_t)c0 * per_layer];
                 s < c.start[(size_t)(c1 + 1) * per_layer]; s++)
                if (lone[s]) ball_one(g, ball, iso, c.x[s], c.y[s], c.z[s], k0, k1);
        }
        free(lone);
    }
    cells_free(&c);
}

/* One pass of [1 2 1]/4 along axis d from src into dst (outside: 0). */
static void smooth_axis(const srf_grid *g, const float *src, float *dst, int d)
{
    const size_t nx = (size_t)g->nc[0], nxy = nx * (size_t)g->nc[1];
    const size_t stride = d == 0 ? 1 : d == 1 ? nx : nxy;
    const int n = g->nc[d];
#pragma omp parallel for schedule(static)
    for (long kk = 0; kk < g->nc[2]; kk++)
        for (size_t j = 0; j < (size_t)g->nc[1]; j++)
            for (size_t i = 0; i < nx; i++) {
                const size_t at = (size_t)kk * nxy + j * nx + i;
                const int q = d == 0 ? (int)i : d == 1 ? (int)j : (int)kk;
                const float a = q > 0 ? src[at - stride] : 0.0f;
                const float b = q < n - 1 ? src[at + stride] : 0.0f;
                dst[at] = 0.25f * a + 0.5f * src[at] + 0.25f * b;
            }
}

void srf_smooth(srf_grid *g, int passes)
{
    if (passes <= 0) return;
    const size_t npts = (size_t)g->nc[0] * (size_t)g->nc[1] * (size_t)g->nc[2];
    float *tmp = sl_malloc(npts * sizeof *tmp, "surface smoothing");
    for (int p = 0; p < passes; p++)
        for (int d = 0; d < 3; d++) {
            smooth_axis(g, g->f, tmp, d);
            float *t = g->f;
            g->f = tmp;
            tmp = t;
        }
    free(tmp);
}

void srf_interpolate(const srf_particles *in, double h, srf_mesh *m)
{
    if (!in->vx && !in->p) return;
    srf_cells c;
    krn_kernel k;
    krn_init(&k, h);
    cells_build(&c, in, h);
    const size_t nv = m->nv ? m->nv : 1;
    if (in->vx) {
        m->vx = sl_malloc(nv * sizeof(double), "surface velocity");
        m->vy = sl_malloc(nv * sizeof(double), "surface velocity");
        m->vz = sl_malloc(nv * sizeof(double), "surface velocity");
    }
    if (in->p) m->p = sl_malloc(nv * sizeof(double), "surface pressure");
    const double h2 = h * h;
#pragma omp parallel for schedule(dynamic, 256)
    for (size_t v = 0; v < m->nv; v++) {
        const double q[3] = {m->x[v], m->y[v], m->z[v]};
        int lo[3], hi[3];
        double w = 0, a[4] = {0, 0, 0, 0};
        for (int d = 0; d < 3; d++) {
            lo[d] = clampi((long)floor((q[d] - h - c.lo[d]) / h), 0, c.nc[d] - 1);
            hi[d] = clampi((long)floor((q[d] + h - c.lo[d]) / h), 0, c.nc[d] - 1);
        }
        for (int cz = lo[2]; cz <= hi[2]; cz++)
            for (int cy = lo[1]; cy <= hi[1]; cy++) {
                const size_t row = ((size_t)cz * (size_t)c.nc[1] + (size_t)cy) * (size_t)c.nc[0];
                for (size_t s = c.start[row + (size_t)lo[0]]; s < c.start[row + (size_t)hi[0] + 1];
                     s++) {
                    const double ddx = c.x[s] - q[0], ddy = c.y[s] - q[1], ddz = c.z[s] - q[2];
                    const double r2 = ddx * ddx + ddy * ddy + ddz * ddz;
                    if (r2 >= h2) continue;
                    const double wj = krn_w(&k, sqrt(r2));
                    const size_t j = c.order[s];
                    w += wj;
                    if (in->vx) {
                        a[0] += wj * in->vx[j];
                        a[1] += wj * in->vy[j];
                        a[2] += wj * in->vz[j];
                    }
                    if (in->p) a[3] += wj * in->p[j];
                }
            }
        const double inv = w > 0 ? 1.0 / w : 0.0;
        if (in->vx) {
            m->vx[v] = a[0] * inv;
            m->vy[v] = a[1] * inv;
            m->vz[v] = a[2] * inv;
        }
        if (in->p) m->p[v] = a[3] * inv;
    }
    cells_free(&c);
}
