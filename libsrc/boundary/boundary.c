/* boundary: calibration, masses and world collision (see boundary.h). */
#include "boundary/boundary.h"

#include <math.h>
#include <stdlib.h>

#include "core/sl_mem.h"

/* Sum of W over a square lattice (spacing r0, |i|,|j| <= 4) in the plane
 * z = 0, seen from (0, 0, zq). */
static double wall_sum(const krn_kernel *k, double r0, double zq)
{
    double s = 0.0;
    for (int i = -4; i <= 4; i++)
        for (int j = -4; j <= 4; j++)
            s += krn_w(k, sqrt((i * i + j * j) * r0 * r0 + zq * zq));
    return s;
}

/* Sum of W over a cubic fluid lattice filling z >= r0, seen from (0,0,zq). */
static double fluid_sum(const krn_kernel *k, double r0, double zq)
{
    double s = 0.0;
    for (int i = -4; i <= 4; i++)
        for (int j = -4; j <= 4; j++)
            for (int l = 1; l <= 6; l++) {
                double dz = l * r0 - zq;
                s += krn_w(k, sqrt((i * i + j * j) * r0 * r0 + dz * dz));
            }
    return s;
}

bnd_calibration bnd_calibrate(const krn_kernel *k, double r0, double mfluid, double rho0)
{
    bnd_calibration c;
    double v_proto = 1.0 / wall_sum(k, r0, 0.0);
    double fluid_first = mfluid * fluid_sum(k, r0, r0);
    double wall_seen = wall_sum(k, r0, r0);
    c.gamma = (rho0 - fluid_first) / (rho0 * v_proto * wall_seen);
    c.fluid_sum = mfluid * fluid_sum(k, r0, 0.0);
    /* prototype wall particle: sum_k m_k W_0k = gamma rho0 */
    c.c_static = (rho0 - c.fluid_sum) / (c.gamma * rho0);
    return c;
}

void bnd_set_mass(const nbr_grid *g, const krn_kernel *k, const bnd_calibration *c,
                  double rho0, sl_boundary *b)
{
    nbr_list bb;
    nbr_list_init(&bb);
    nbr_build_bb(g, b, &bb);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        double s = 0.0;
        for (uint32_t q = bb.start[i]; q < bb.start[i + 1]; q++) {
            uint32_t j = bb.idx[q];
            double dx = b->x[i] - b->x[j], dy = b->y[i] - b->y[j], dz = b->z[i] - b->z[j];
            s += krn_w(k, sqrt(dx * dx + dy * dy + dz * dz));
        }
        b->mass[i] = c->gamma * rho0 / s; /* s > 0: the list holds the particle itself */
    }
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        double s = 0.0;
        for (uint32_t q = bb.start[i]; q < bb.start[i + 1]; q++) {
            uint32_t j = bb.idx[q];
            double dx = b->x[i] - b->x[j], dy = b->y[i] - b->y[j], dz = b->z[i] - b->z[j];
            s += b->mass[j] * krn_w(k, sqrt(dx * dx + dy * dy + dz * dz));
        }
        b->rho_static[i] = c->c_static * s;
    }
    nbr_list_free(&bb);
}

size_t bnd_collide(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                   size_t n, double *x, double *y, double *z,
                   double *vx, double *vy, double *vz)
{
    size_t hits = 0;
#pragma omp parallel for schedule(static) reduction(+ : hits)
    for (size_t i = 0; i < n; i++) {
        double ncx = 0, ncy = 0, ncz = 0, sw = 0, swd = 0, wvx = 0, wvy = 0, wvz = 0;
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
            uint32_t j = fb->idx[q];
            double dx = x[i] - b->x[j], dy = y[i] - b->y[j], dz = z[i] - b->z[j];
            double d = sqrt(dx * dx + dy * dy + dz * dz);
            double w = d < r0 ? (r0 - d) / r0 : 0.0; /* eq. (10) */
            ncx += w * b->nx[j];                      /* eq. (9) */
            ncy += w * b->ny[j];
            ncz += w * b->nz[j];
            sw += w;
            swd += w * (r0 - d);
            wvx += w * b->vx[j]; /* the wall's velocity, same weights */
            wvy += w * b->vy[j];
            wvz += w * b->vz[j];
        }
        double len = sqrt(ncx * ncx + ncy * ncy + ncz * ncz);
        if (sw <= 0.0 || len <= 1e-12) continue;
        double s = swd / (sw * len); /* eq. (11) */
        x[i] += s * ncx;
        y[i] += s * ncy;
        z[i] += s * ncz;
        hits++;
        if (vx) { /* eq. (12) relative to the wall: keep epsilon times the tangential velocity */
            double ux = ncx / len, uy = ncy / len, uz = ncz / len;
            wvx /= sw;
            wvy /= sw;
            wvz /= sw;
            double rx = vx[i] - wvx, ry = vy[i] - wvy, rz = vz[i] - wvz;
            double vn = rx * ux + ry * uy + rz * uz;
            vx[i] = wvx + epsilon * (rx - vn * ux);
            vy[i] = wvy + epsilon * (ry - vn * uy);
            vz[i] = wvz + epsilon * (rz - vn * uz);
        }
    }
    return hits;
}

/* ---- the reference methods (paper Sec. 4.1) ---- */

const char *bnd_method_name(bnd_method m)
{
    switch (m) {
    case BND_IHMSEN2010: return "ihmsen2010";
    case BND_BECKER2009: return "becker2009";
    case BND_HARADA2007: return "harada2007";
    }
    return "?";
}

void bnd_wall_table_build(bnd_wall_table *t, const krn_kernel *k, double r0, double mass,
                          size_t n)
{
    const int reach = (int)ceil(k->h / r0) + 1, noff = 4;
    t->n = n;
    t->dmax = k->h;
    t->inv_step = (double)(n - 1) / t->dmax;
    t->z = sl_malloc(n * sizeof *t->z, "wall weight table");
    t->dz = sl_malloc(n * sizeof *t->dz, "wall weight table");
    for (size_t q = 0; q < n; q++) {
        double d = (double)q / t->inv_step, s = 0.0;
        for (int a = 0; a < noff; a++) /* average over in-plane lattice offsets */
            for (int c = 0; c < noff; c++)
                for (int i = -reach; i <= reach; i++)
                    for (int j = -reach; j <= reach; j++)
                        for (int l = 0; l <= reach; l++) {
                            double x = (i + (double)a / noff) * r0, y = (j + (double)c / noff) * r0;
                            double zz = d + l * r0;
                            s += krn_w(k, sqrt(x * x + y * y + zz * zz));
                        }
        t->z[q] = mass * s / (noff * noff);
    }
    for (size_t q = 0; q < n; q++) { /* central differences, one-sided at the ends */
        size_t a = q ? q - 1 : q, c = q + 1 < n ? q + 1 : q;
        t->dz[q] = (t->z[c] - t->z[a]) * t->inv_step / (double)(c - a);
    }
}

void bnd_wall_table_free(bnd_wall_table *t)
{
    free(t->z);
    free(t->dz);
    t->z = t->dz = NULL;
}

size_t bnd_collide_becker(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          double restitution, size_t n, double *x, double *y, double *z,
                          double *vx, double *vy, double *vz)
{
    size_t hits = 0;
#pragma omp parallel for schedule(static) reduction(+ : hits)
    for (size_t i = 0; i < n; i++) {
        int hit = 0;
        for (uint32_t q = fb->start[i]; q < fb->start[i + 1]; q++) {
            uint32_t j = fb->idx[q];
            double dx = x[i] - b->x[j], dy = y[i] - b->y[j], dz = z[i] - b->z[j];
            if (dx * dx + dy * dy + dz * dz >= r0 * r0) continue;
            double dn = dx * b->nx[j] + dy * b->ny[j] + dz * b->nz[j];
            if (dn >= r0) continue;
            double push = r0 - dn; /* eq. (8): back to the contact distance */
            x[i] += push * b->nx[j];
            y[i] += push * b->ny[j];
            z[i] += push * b->nz[j];
            hit = 1;
            if (vx) { /* eq. (7), relative to the wall */
                double rx = vx[i] - b->vx[j], ry = vy[i] - b->vy[j], rz = vz[i] - b->vz[j];
                double vn = rx * b->nx[j] + ry * b->ny[j] + rz * b->nz[j];
                double tx = rx - vn * b->nx[j], ty = ry - vn * b->ny[j], tz = rz - vn * b->nz[j];
                double nn = vn < 0.0 ? -restitution * vn : vn;
                vx[i] = b->vx[j] + epsilon * tx + nn * b->nx[j];
                vy[i] = b->vy[j] + epsilon * ty + nn * b->ny[j];
                vz[i] = b->vz[j] + epsilon * tz + nn * b->nz[j];
            }
        }
        hits += (size_t)hit;
    }
    return hits;
}

size_t bnd_collide_harada(const nbr_list *fb, const sl_boundary *b, double r0, double epsilon,
                          size_t n, double *x, double *y, double *z,
                          double *vx, double *vy, double *vz)
{
    size_t hits = 0;
#pragma omp parallel for schedule(static) reduction(+ : hits)
    for (size_t i = 0; i < n; i++) {
        double d;
        uint32_t j = bnd_nearest(fb, b, i, x[i], y[i], z[i], &d);
        if (j == UINT32_MAX || d >= r0) continue;
        double push = r0 - d;
        x[i] += push * b->nx[j];
        y[i] += push * b->ny[j];
        z[i] += push * b->nz[j];
        hits++;
        if (vx) { /* relative to the wall */
            double rx = vx[i] - b->vx[j], ry = vy[i] - b->vy[j], rz = vz[i] - b->vz[j];
            double vn = rx * b->nx[j] + ry * b->ny[j] + rz * b->nz[j];
            double keep = vn < 0.0 ? 0.0 : vn;
            double tx = rx - vn * b->nx[j], ty = ry - vn * b->ny[j], tz = rz - vn * b->nz[j];
            vx[i] = b->vx[j] + epsilon * tx + keep * b->nx[j];
            vy[i] = b->vy[j] + epsilon * ty + keep * b->ny[j];
            vz[i] = b->vz[j] + epsilon * tz + keep * b->nz[j];
        }
    }
    return hits;
}
