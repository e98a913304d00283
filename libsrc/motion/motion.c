/* motion: prescribed rigid body motion (see motion.h). */
#include "motion/motion.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void mot_fail(const dict *d, const char *key, const char *why)
{
    dict_fatal(d, key, "%s", why);
}

static void need(int rc, const sl_err *err) { dict_need(rc, err); }

static void read_axis(mot_motion *m, const dict *d)
{
    static const double zaxis[3] = {0, 0, 1}, origin[3] = {0, 0, 0};
    sl_err err;
    need(dict_get_vector_or(d, "axis", zaxis, m->axis, &err), &err);
    need(dict_get_vector_or(d, "centre", origin, m->centre, &err), &err);
    double n = sqrt(m->axis[0] * m->axis[0] + m->axis[1] * m->axis[1] + m->axis[2] * m->axis[2]);
    if (!(n > 0.0)) mot_fail(d, "axis", "must not be the zero vector");
    for (int k = 0; k < 3; k++) m->axis[k] /= n;
}

/* Rows "t dx dy dz angle" of a text file ('#' comments). */
static void read_table(mot_motion *m, const dict *d, const char *case_dir)
{
    sl_err err;
    const char *name;
    need(dict_get_word(d, "file", &name, &err), &err);
    size_t len = strlen(case_dir) + strlen(name) + 2;
    char *path = sl_malloc(len, "path");
    snprintf(path, len, "%s/%s", case_dir, name);
    FILE *f = fopen(path, "r");
    if (!f) sl_fatal("%s: cannot open motion table '%s': %s", dict_file(d), path, strerror(errno));
    char line[1024];
    size_t cap = 0;
    int lineno = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *s = line;
        while (*s == ' ' || *s == '\t') s++;
        if (*s == '#' || *s == '\n' || *s == '\0') continue;
        double v[5];
        char *end = s;
        for (int k = 0; k < 5; k++) {
            v[k] = strtod(end, &end);
            if (!isfinite(v[k])) sl_fatal("%s:%d: motion table: not a finite number", path, lineno);
        }
        if (end == s) sl_fatal("%s:%d: motion table: expected 't dx dy dz angle'", path, lineno);
        if (m->nrows && !(v[0] > m->t[m->nrows - 1]))
            sl_fatal("%s:%d: motion table: times must increase", path, lineno);
        if (m->nrows == cap) {
            cap = cap ? 2 * cap : 64;
            m->t = sl_realloc(m->t, cap * sizeof *m->t, "motion table");
            for (int k = 0; k < 4; k++)
                m->col[k] = sl_realloc(m->col[k], cap * sizeof(double), "motion table");
        }
        m->t[m->nrows] = v[0];
        for (int k = 0; k < 4; k++) m->col[k][m->nrows] = k == 3 ? v[4] * M_PI / 180.0 : v[k + 1];
        m->nrows++;
    }
    fclose(f);
    if (m->nrows < 2) sl_fatal("%s: motion table needs at least 2 rows", path);
    free(path);
    const gsl_interp_type *type = m->nrows >= 5 ? gsl_interp_akima : gsl_interp_linear;
    for (int k = 0; k < 4; k++) {
        m->spline[k] = gsl_spline_alloc(type, m->nrows);
        m->acc[k] = gsl_interp_accel_alloc();
        gsl_spline_init(m->spline[k], m->t, m->col[k], m->nrows);
    }
}

void mot_read(mot_motion *m, const dict *d, const char *case_dir)
{
    static const char *const keys[] = {"type", "peakVelocity", "period", "amplitude",
                                       "axis", "centre",       "file",   NULL};
    sl_err err;
    const char *type;
    memset(m, 0, sizeof *m);
    dict_warn_unknown(d, keys);
    need(dict_get_word(d, "type", &type, &err), &err);
    if (!strcmp(type, "cosine")) {
        m->type = MOT_COSINE;
        need(dict_get_vector(d, "peakVelocity", m->peak_velocity, &err), &err);
        need(dict_get_scalar(d, "period", &m->period, &err), &err);
        if (!(m->period > 0.0)) mot_fail(d, "period", "must be positive");
    } else if (!strcmp(type, "oscillating")) {
        m->type = MOT_OSCILLATING;
        need(dict_get_scalar(d, "amplitude", &m->amplitude, &err), &err);
        need(dict_get_scalar(d, "period", &m->period, &err), &err);
        if (!(m->period > 0.0)) mot_fail(d, "period", "must be positive");
        m->amplitude *= M_PI / 180.0;
        read_axis(m, d);
    } else if (!strcmp(type, "table")) {
        m->type = MOT_TABLE;
        read_axis(m, d);
        read_table(m, d, case_dir);
    } else {
        mot_fail(d, "type", "is not one of: cosine oscillating table");
    }
}

void mot_free(mot_motion *m)
{
    for (int k = 0; k < 4; k++) {
        if (m->spline[k]) gsl_spline_free(m->spline[k]);
        if (m->acc[k]) gsl_interp_accel_free(m->acc[k]);
        free(m->col[k]);
    }
    free(m->t);
    memset(m, 0, sizeof *m);
}

int mot_translates_across(const mot_motion *m, unsigned axes)
{
    switch (m->type) {
    case MOT_NONE:
        return 1;
    case MOT_COSINE:
        for (int k = 0; k < 3; k++)
            if (axes & (1u << k) && m->peak_velocity[k] != 0.0) return 0;
        return 1;
    case MOT_OSCILLATING:
        return m->amplitude == 0.0;
    case MOT_TABLE:
        for (size_t i = 0; i < m->nrows; i++) {
            if (m->col[3][i] != 0.0) return 0;
            for (int k = 0; k < 3; k++)
                if (axes & (1u << k) && m->col[k][i] != 0.0) return 0;
        }
        return 1;
    }
    return 0;
}

void mot_eval(const mot_motion *m, double t, double d[3], double *angle, double v[3], double *omega)
{
    d[0] = d[1] = d[2] = v[0] = v[1] = v[2] = 0.0;
    *angle = *omega = 0.0;
    switch (m->type) {
    case MOT_NONE:
        return;
    case MOT_COSINE: {
        const double w = 2.0 * M_PI / m->period;
        for (int k = 0; k < 3; k++) {
            d[k] = m->peak_velocity[k] / w * sin(w * t);
            v[k] = m->peak_velocity[k] * cos(w * t);
        }
        return;
    }
    case MOT_OSCILLATING: {
        const double w = 2.0 * M_PI / m->period;
        *angle = m->amplitude * sin(w * t);
        *omega = m->amplitude * w * cos(w * t);
        return;
    }
    case MOT_TABLE: {
        const double tc = t < m->t[0] ? m->t[0] : t > m->t[m->nrows - 1] ? m->t[m->nrows - 1] : t;
        const int inside = t >= m->t[0] && t <= m->t[m->nrows - 1];
        double val[4], rate[4];
        for (int k = 0; k < 4; k++) {
            val[k] = gsl_spline_eval(m->spline[k], tc, m->acc[k]);
            rate[k] = inside ? gsl_spline_eval_deriv(m->spline[k], tc, m->acc[k]) : 0.0;
        }
        for (int k = 0; k < 3; k++) {
            d[k] = val[k];
            v[k] = rate[k];
        }
        *angle = val[3];
        *omega = rate[3];
        return;
    }
    }
}

/* Rodrigues' rotation of v by angle a about unit axis k. */
static void rotate(const double k[3], double a, const double v[3], double out[3])
{
    const double c = cos(a), s = sin(a), kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    const double cx = k[1] * v[2] - k[2] * v[1], cy = k[2] * v[0] - k[0] * v[2],
                 cz = k[0] * v[1] - k[1] * v[0];
    out[0] = v[0] * c + cx * s + k[0] * kv * (1.0 - c);
    out[1] = v[1] * c + cy * s + k[1] * kv * (1.0 - c);
    out[2] = v[2] * c + cz * s + k[2] * kv * (1.0 - c);
}

void mot_apply(const mot_motion *m, uint32_t body, double t, sl_boundary *b)
{
    double d[3], v[3], a, w;
    mot_eval(m, t, d, &a, v, &w);
    const double *c = m->centre, *k = m->axis;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < b->n; i++) {
        if (b->body[i] != body) continue;
        double r0[3] = {b->x0[i] - c[0], b->y0[i] - c[1], b->z0[i] - c[2]}, r[3],
               n0[3] = {b->nx0[i], b->ny0[i], b->nz0[i]}, n[3];
        rotate(k, a, r0, r);
        rotate(k, a, n0, n);
        b->x[i] = c[0] + r[0] + d[0];
        b->y[i] = c[1] + r[1] + d[1];
        b->z[i] = c[2] + r[2] + d[2];
        b->nx[i] = n[0];
        b->ny[i] = n[1];
        b->nz[i] = n[2];
        /* v + omega k x r */
        b->vx[i] = v[0] + w * (k[1] * r[2] - k[2] * r[1]);
        b->vy[i] = v[1] + w * (k[2] * r[0] - k[0] * r[2]);
        b->vz[i] = v[2] + w * (k[0] * r[1] - k[1] * r[0]);
    }
}
