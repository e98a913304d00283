/* verifyCase: the exact answers and the error norms of each kind (see vc.h). */
#include "vc.h"

#include <math.h>
#include <string.h>

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <stdlib.h>

const char *const vc_kind_names[] = {"hydrostatic", "translatingTank", "poiseuille",
                                     "taylorGreen", "standingWave",    NULL};

static const char *const keys[] = {"exact", "nu", "amplitude", "length", "from", "tolerance", NULL};

static double need_scalar(const dict *d, const char *key, double def, int required)
{
    sl_err err;
    double v;
    if (required) dict_need(dict_get_scalar(d, key, &v, &err), &err);
    else dict_need(dict_get_scalar_or(d, key, def, &v, &err), &err);
    return v;
}

/* The first container of the case: its walls and its motion. */
static void find_container(vc_setup *s, const sl_case *c, const dict *d)
{
    for (size_t i = 0; i < c->nshapes; i++)
        if (c->shapes[i].kind == GEO_CONTAINER) {
            memcpy(s->lo, c->shapes[i].lo, sizeof s->lo);
            memcpy(s->hi, c->shapes[i].hi, sizeof s->hi);
            s->motion = c->motions && c->motions[i].type != MOT_NONE ? &c->motions[i] : NULL;
            return;
        }
    dict_fatal(d, "exact", "needs a case with a container (constant/boundaryProperties)");
}

void vc_read(vc_setup *s, const sl_case *c)
{
    sl_err err;
    char path[4096];
    snprintf(path, sizeof path, "%s/system/verifyDict", c->dir);
    dict *d = dict_read_file(path, &err);
    if (!d) sl_fatal("%s (verifyCase needs system/verifyDict naming the exact answer)", err.msg);
    dict_warn_unknown(d, keys);
    const char *w;
    dict_need(dict_get_word(d, "exact", &w, &err), &err);
    int k = 0;
    while (vc_kind_names[k] && strcmp(vc_kind_names[k], w)) k++;
    if (!vc_kind_names[k])
        dict_fatal(d, "exact",
                   "unknown answer '%s' (did you mean '%s'?); known: hydrostatic "
                   "translatingTank poiseuille taylorGreen standingWave",
                   w, dict_nearest(w, vc_kind_names));
    memset(s, 0, sizeof *s);
    s->kind = (vc_kind)k;
    const int viscous = s->kind == VC_POISEUILLE || s->kind == VC_TAYLOR_GREEN;
    s->nu = need_scalar(d, "nu", 0.0, viscous);
    /* the Poiseuille profile needs a viscosity; the Taylor-Green vortex
     * without one is steady (its losses are then the method's own) */
    if (s->kind == VC_POISEUILLE) dict_need_positive(d, "nu", s->nu);
    else if (!(s->nu >= 0.0)) dict_fatal(d, "nu", "must be zero or positive");
    const int amp = s->kind == VC_TAYLOR_GREEN || s->kind == VC_WAVE;
    s->amplitude = need_scalar(d, "amplitude", 0.0, amp);
    if (amp) dict_need_positive(d, "amplitude", s->amplitude);
    s->length = need_scalar(d, "length", 0.0, s->kind == VC_TAYLOR_GREEN);
    if (s->kind == VC_TAYLOR_GREEN || dict_has(d, "length"))
        dict_need_positive(d, "length", s->length);
    s->from = need_scalar(d, "from", 0.0, 0);
    s->tolerance = need_scalar(d, "tolerance", -1.0, 0);
    if (dict_has(d, "tolerance")) dict_need_positive(d, "tolerance", s->tolerance);
    s->rho0 = c->prm.rho0;
    s->r0 = c->prm.r0;
    s->support = c->prm.support * c->prm.r0;
    memcpy(s->g, c->prm.gravity, sizeof s->g);
    s->gmag = sqrt(s->g[0] * s->g[0] + s->g[1] * s->g[1] + s->g[2] * s->g[2]);
    find_container(s, c, d);
    const int still = s->kind == VC_HYDROSTATIC || s->kind == VC_TRANSLATING || s->kind == VC_WAVE;
    if (still && (s->g[0] != 0.0 || s->g[1] != 0.0 || !(s->g[2] < 0.0)))
        dict_fatal(d, "exact", "'%s' needs gravity (0 0 -g) in constant/fluidProperties", w);
    if (s->kind == VC_POISEUILLE && (!(s->g[0] > 0.0) || s->g[1] != 0.0 || s->g[2] != 0.0))
        dict_fatal(d, "exact",
                   "'poiseuille' needs a driving gravity (g 0 0), g > 0, in "
                   "constant/fluidProperties (the flow along x between plates at z min and max)");
    if (s->kind == VC_TRANSLATING && !s->motion)
        dict_fatal(d, "exact", "'translatingTank' needs a container with a motion { }");
    dict_free(d);
}

double vc_poiseuille(double g, double nu, double d, double z, double t)
{
    double u = 0.5 * g / nu * z * (d - z);
    const double pi = 3.14159265358979323846;
    for (int n = 1; n < 400; n += 2) {
        double e = exp(-(double)(n * n) * pi * pi * nu * t / (d * d));
        if (e < 1e-17) break;
        u -= 4.0 * g * d * d / (nu * pi * pi * pi * n * n * n) * sin(n * pi * z / d) * e;
    }
    return u;
}

double vc_wave_period(double g, double L, double H)
{
    const double pi = 3.14159265358979323846, k = pi / L;
    return 2.0 * pi / sqrt(g * k * tanh(k * H));
}

double vc_wave_length(const vc_setup *s)
{
    return s->length > 0.0 ? s->length : s->hi[0] - s->lo[0];
}

/* The exact velocity of particle i at time t. */
static void exact_velocity(const vc_setup *s, double x, double y, double z, double t, double v[3])
{
    const double pi = 3.14159265358979323846;
    v[0] = v[1] = v[2] = 0.0;
    if (s->kind == VC_TRANSLATING) {
        double d[3], angle, omega;
        mot_eval(s->motion, t, d, &angle, v, &omega);
    } else if (s->kind == VC_POISEUILLE) {
        v[0] = vc_poiseuille(s->g[0], s->nu, s->hi[2] - s->lo[2], z - s->lo[2], t);
    } else if (s->kind == VC_TAYLOR_GREEN) {
        const double k = 2.0 * pi / s->length, f = s->amplitude * exp(-2.0 * s->nu * k * k * t);
        v[0] = f * sin(k * x) * cos(k * y);
        v[1] = -f * cos(k * x) * sin(k * y);
    }
}

/* The pressure profile's error: the pressures averaged over layers of
 * thickness r0 (the lattice's) against rho0 g (H - z) at the layers' mean
 * heights, rms over the layers, over rho0 g H.  Particle noise averages
 * out; what is left is the error of the pressure field. */
static double profile_error(const vc_setup *s, const sl_fluid *f)
{
    const double H = s->depth, pg = s->rho0 * s->gmag;
    const size_t nb = (size_t)ceil(1.5 * H / s->r0) + 2;
    double *sum = sl_calloc(3 * nb, sizeof *sum, "layers"), *sz = sum + nb, *cnt = sz + nb;
    for (size_t i = 0; i < f->n; i++) {
        double q = (f->z[i] - s->lo[2]) / s->r0;
        size_t b = q <= 0.0 ? 0 : (size_t)q;
        if (b >= nb) b = nb - 1;
        sum[b] += f->p[i];
        sz[b] += f->z[i] - s->lo[2];
        cnt[b] += 1.0;
    }
    double e = 0.0, m = 0.0;
    for (size_t b = 0; b < nb; b++) {
        if (cnt[b] == 0.0) continue;
        const double z = sz[b] / cnt[b], ex = z < H ? pg * (H - z) : 0.0;
        const double d = sum[b] / cnt[b] - ex;
        e += d * d;
        m += 1.0;
    }
    free(sum);
    return m > 0.0 ? sqrt(e / m) / (pg * H) : (double)NAN;
}

/* The pressure gradient's error: the least-squares slope of p against z
 * over the particles whose kernel reaches neither the floor nor above the
 * highest particle (h above the one, h below the other), over -rho0 g,
 * less 1.  The profile error mixes the gradient with the pressure's level
 * (the free surface's); this is the gradient alone. */
static double gradient_error(const vc_setup *s, const sl_fluid *f, double top)
{
    const double lo = s->lo[2] + s->support, hi = top - s->support;
    double n = 0.0, sz = 0.0, sp = 0.0, szz = 0.0, szp = 0.0;
    for (size_t i = 0; i < f->n; i++) {
        const double z = f->z[i];
        if (!(z > lo && z < hi)) continue;
        n += 1.0;
        sz += z;
        sp += f->p[i];
        szz += z * z;
        szp += z * f->p[i];
    }
    const double var = szz - sz * sz / n;
    if (!(n >= 3.0 && var > 0.0)) return (double)NAN;
    const double slope = (szp - sz * sp / n) / var;
    return -slope / (s->rho0 * s->gmag) - 1.0;
}

void vc_measure(const vc_setup *s, const sl_fluid *f, double t, vc_sample *out)
{
    const double H = s->depth, pg = s->rho0 * s->gmag;
    double sp = 0.0, sv = 0.0, su = 0.0, ke = 0.0, top = -INFINITY, pm = 0.0, mm = 0.0;
    double sd = 0.0, sd2 = 0.0; /* taylorGreen: p - exact p, and its square */
    const double kw = 3.14159265358979323846 / vc_wave_length(s);
    for (size_t i = 0; i < f->n; i++) {
        double v[3];
        exact_velocity(s, f->x[i], f->y[i], f->z[i], t, v);
        const double dx = f->vx[i] - v[0], dy = f->vy[i] - v[1], dz = f->vz[i] - v[2];
        sv += dx * dx + dy * dy + dz * dz;
        su += dx * dx;
        ke += 0.5 * (f->vx[i] * f->vx[i] + f->vy[i] * f->vy[i] + f->vz[i] * f->vz[i]);
        const double depth = H - (f->z[i] - s->lo[2]);
        const double dp = f->p[i] - pg * (depth > 0.0 ? depth : 0.0);
        sp += dp * dp;
        if (f->z[i] > top) top = f->z[i];
        if (s->kind == VC_TAYLOR_GREEN) { /* the vortex's shape, amplitude 1 */
            const double k = 2.0 * 3.14159265358979323846 / s->length;
            const double mu = sin(k * f->x[i]) * cos(k * f->y[i]),
                         mw = -cos(k * f->x[i]) * sin(k * f->y[i]);
            pm += f->vx[i] * mu + f->vy[i] * mw;
            mm += mu * mu + mw * mw;
            const double F = exp(-2.0 * s->nu * k * k * t), u = s->amplitude * F;
            const double d = f->p[i] -
                0.25 * s->rho0 * u * u * (cos(2.0 * k * f->x[i]) + cos(2.0 * k * f->y[i]));
            sd += d;
            sd2 += d * d;
        }
        if (s->kind == VC_WAVE) { /* the mode's velocity shape (case.c's standingWave) */
            const double x = f->x[i] - s->lo[0], z = f->z[i] - s->lo[2], sh = sinh(kw * H);
            const double mu = -cosh(kw * z) / sh * sin(kw * x),
                         mw = sinh(kw * z) / sh * cos(kw * x);
            pm += f->vx[i] * mu + f->vz[i] * mw;
            mm += mu * mu + mw * mw;
        }
    }
    const double n = f->n ? (double)f->n : 1.0;
    out->t = t;
    out->vrms = sqrt(sv / n);
    out->ke = ke / n;
    out->mode = mm > 0.0 ? pm / mm : (double)NAN;
    out->grad = (double)NAN;
    out->height = top + 0.5 * s->r0 - s->lo[2];
    out->perr =
        (s->kind == VC_HYDROSTATIC || s->kind == VC_TRANSLATING || s->kind == VC_WAVE) && H > 0.0
        ? sqrt(sp / n) / (pg * H)
        : (double)NAN;
    if (s->kind == VC_TAYLOR_GREEN) { /* up to a constant: the box fixes no pressure level */
        const double var = sd2 / n - (sd / n) * (sd / n);
        out->perr = sqrt(var > 0.0 ? var : 0.0) / (s->rho0 * s->amplitude * s->amplitude);
    }
    switch (s->kind) {
    case VC_HYDROSTATIC:
        out->err = profile_error(s, f);
        out->grad = gradient_error(s, f, top);
        break;
    case VC_TRANSLATING:
        out->err = out->vrms / sqrt(s->gmag * H);
        break;
    case VC_POISEUILLE: {
        const double d = s->hi[2] - s->lo[2], umax = s->g[0] * d * d / (8.0 * s->nu);
        out->err = sqrt(su / n) / umax;
        break;
    }
    case VC_TAYLOR_GREEN:
        out->err = out->vrms / s->amplitude;
        break;
    default:
        out->err = NAN;
        break;
    }
}
