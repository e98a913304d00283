/* case: dictionaries -> run controls, parameters and particles (see case.h). */
#include "case/case.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "core/sl_progress.h"
#include "dictionary/dict.h"
#include "effects/gravity.h"
#include "effects/moving_boundary.h"
#include "effects/particle_shifting.h"
#include "geometry/mesh.h"
#include "boundary/bnd_methods.h"
#include "parallel/par.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* eta (in % of rho0) above which a warning asks whether it is a mistake */
#define CASE_ETA_WARN 10.0
/* |gravity| (m/s^2) above which a warning asks about units (cm/s^2?) */
#define CASE_GRAVITY_WARN 100.0

/* ---- error helpers: every failure names file, line and key ---- */

static void need(int status, const sl_err *err) { dict_need(status, err); }

static dict *read_dict(const sl_case *c, const char *rel)
{
    sl_err err;
    size_t len = strlen(c->dir) + strlen(rel) + 2;
    char *path = sl_malloc(len, "path");
    snprintf(path, len, "%s/%s", c->dir, rel);
    dict *d = dict_read_file(path, &err);
    free(path);
    if (!d) sl_fatal("%s", err.msg);
    return d;
}

/* read_dict, the first time a file is read: keys written twice are reported
 * (once: read_periodic reads boundaryProperties again). */
static dict *read_case_file(const sl_case *c, const char *rel)
{
    dict *d = read_dict(c, rel);
    dict_warn_duplicates(d);
    return d;
}

static void set_where(case_where *w, const dict_entry *e)
{
    snprintf(w->text, sizeof w->text, "%s:%d", dict_entry_file(e), dict_entry_line(e));
}

/* "<file>:<line>: keyword '<key>': <why>" as a warning: legal, but almost
 * surely not what the user meant. */
static void warn_value(const dict *d, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void warn_value(const dict *d, const char *key, const char *fmt, ...)
{
    char why[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    const dict_entry *e = dict_lookup(d, key);
    sl_warning("%s:%d: keyword '%s': %s", dict_entry_file(e), dict_entry_line(e), key, why);
}

/* Stop with "<file>:<line>: keyword '<key>': <why>". */
static void bad_value(const dict *d, const char *key, const char *why)
{
    dict_fatal(d, key, "%s", why);
}

static double positive(const dict *d, const char *key, double v)
{
    return dict_need_positive(d, key, v);
}

static int choose(const dict *d, const char *key, const char *word, const char *const *choices)
{
    for (int i = 0; choices[i]; i++)
        if (strcmp(word, choices[i]) == 0) return i;
    char why[512];
    size_t off = (size_t)snprintf(why, sizeof why, "'%s' is not one of:", word);
    for (int i = 0; choices[i] && off < sizeof why; i++)
        off += (size_t)snprintf(why + off, sizeof why - off, " %s", choices[i]);
    bad_value(d, key, why);
    return -1;
}

/* ---- system/controlDict ---- */

static const char *const control_keys[] = {"application",     "startFrom",
                                           "startTime",       "endTime",
                                           "writeInterval",   "writeControl",
                                           "writeFormat",     "writeCompression",
                                           "timePrecision",   "purgeWrite",
                                           "numberOfThreads", "writeBoundary",
                                           "functions",       NULL};

static void read_controls(sl_case *c)
{
    static const char *const start_choices[] = {"startTime", "latestTime", NULL};
    static const char *const format_choices[] = {"binary", "ascii", NULL};
    static const char *const write_choices[] = {"adjustableRunTime", "runTime", NULL};
    dict *d = read_case_file(c, "system/controlDict");
    case_controls *k = &c->ctl;
    sl_err err;
    const char *w;
    long l;
    dict_warn_unknown(d, control_keys);
    need(dict_get_word_or(d, "startFrom", "startTime", &w, &err), &err);
    k->start_from = choose(d, "startFrom", w, start_choices) ? CASE_LATEST_TIME : CASE_START_TIME;
    need(dict_get_scalar_or(d, "startTime", 0.0, &k->start_time, &err), &err);
    need(dict_get_scalar(d, "endTime", &k->end_time, &err), &err);
    if (!(k->end_time > k->start_time)) bad_value(d, "endTime", "must be larger than startTime");
    need(dict_get_scalar(d, "writeInterval", &k->write_interval, &err), &err);
    positive(d, "writeInterval", k->write_interval);
    need(dict_get_word_or(d, "writeControl", "adjustableRunTime", &w, &err), &err);
    k->write_control =
        choose(d, "writeControl", w, write_choices) ? CASE_RUN_TIME : CASE_ADJUSTABLE_RUN_TIME;
    need(dict_get_word_or(d, "writeFormat", "binary", &w, &err), &err);
    k->ascii = choose(d, "writeFormat", w, format_choices);
    need(dict_get_bool_or(d, "writeCompression", 1, &k->compress, &err), &err);
    need(dict_get_int_or(d, "timePrecision", 6, &l, &err), &err);
    if (l < 1 || l > 17) bad_value(d, "timePrecision", "must be between 1 and 17 digits");
    k->time_precision = (int)l;
    need(dict_get_int_or(d, "purgeWrite", 0, &l, &err), &err);
    if (l < 0) bad_value(d, "purgeWrite", "must be 0 (keep all) or a positive count");
    k->purge_write = (int)l;
    need(dict_get_int_or(d, "numberOfThreads", 0, &l, &err), &err);
    if (l < 0 || l > 4096)
        bad_value(d, "numberOfThreads", "must be 0 (all cores) or a thread count from 1 to 4096");
    k->nthreads = (int)l;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (cores > 0 && l > cores)
        warn_value(d, "numberOfThreads",
                   "%ld threads on a machine with %ld cores run slower "
                   "than %ld (0 uses all cores)",
                   l, cores, cores);
    need(dict_get_bool_or(d, "writeBoundary", 1, &k->write_boundary, &err), &err);
    dict_free(d);
}

/* ---- system/timeStepDict: the controller's parameters (timestep/) ---- */

static void read_timestep(sl_case *c)
{
    dict *d = read_case_file(c, "system/timeStepDict");
    ts_read(d, &c->ts);
    dict_free(d);
}

/* ---- constant/fluidProperties ---- */

/* The keys of constant/fluidProperties besides the effects' own entries
 * (effects/: eff_fluid_effects). */
static const char *const fluid_keys[] = {"rho0",           "particleSpacing",
                                         "gravity",        "eta",
                                         "minIterations",  "maxIterations",
                                         "fluidRegions",   "emitters",
                                         "initialPacking", "kernelSupport",
                                         "pressureSource", "pressureForce",
                                         "kernel",         NULL};

/* fluid_keys and the names of the effects of constant/fluidProperties. */
static const char **fluid_and_effect_keys(void)
{
    size_t nf = 0, ne = 0;
    while (fluid_keys[nf]) nf++;
    while (eff_fluid_effects[ne]) ne++;
    const char **k = sl_malloc((nf + ne + 1) * sizeof *k, "keys");
    for (size_t i = 0; i < nf; i++) k[i] = fluid_keys[i];
    for (size_t i = 0; i < ne; i++) k[nf + i] = eff_fluid_effects[i]->name;
    k[nf + ne] = NULL;
    return k;
}

static void read_shape_geometry(sl_case *c, const dict *s, geo_shape *g, geo_kind kind, int region);

static const char *const region_keys[] = {
    "type", "min",   "max",    "centre",    "radius",   "point1",        "point2",
    "file", "scale", "rotate", "translate", "velocity", "velocityField", NULL};

/* A region's velocityField { }: an initial velocity field added to its
 * uniform velocity, for the verification cases (doc/verification.md):
 *   taylorGreen   u = U sin(k x) cos(k y), v = -U cos(k x) sin(k y),
 *                 k = 2 pi / L, x and y from 0 (a periodic box of period L)
 *   standingWave  the linear standing wave eta = A cos(k x') sin(w t) at
 *                 t = 0 (flat surface, largest velocity): u = -A w cosh(k z')
 *                 sin(k x') / sinh(k H), w = A w sinh(k z') cos(k x') /
 *                 sinh(k H), k = pi / L, w^2 = g k tanh(k H), x' and z'
 *                 from the region's min, H its height (a box)
 * with U or A the amplitude and L the length. */
static void read_velocity_field(const dict *r, case_region *g)
{
    static const char *const types[] = {"taylorGreen", "standingWave", NULL};
    static const char *const keys[] = {"type", "amplitude", "length", NULL};
    sl_err err;
    const char *w;
    const dict *v = dict_sub(r, "velocityField");
    if (!v)
        dict_fatal(r, "velocityField",
                   "must be a dictionary { type taylorGreen; amplitude ..; length ..; }");
    dict_warn_unknown(v, keys);
    need(dict_get_word(v, "type", &w, &err), &err);
    g->field = 1 + choose(v, "type", w, types);
    need(dict_get_scalar(v, "amplitude", &g->field_amplitude, &err), &err);
    need(dict_get_scalar(v, "length", &g->field_length, &err), &err);
    dict_need_positive(v, "length", g->field_length);
    if (g->field == CASE_FIELD_STANDING_WAVE && g->shape.kind != GEO_BOX)
        dict_fatal(v, "type", "standingWave needs a region of type box");
}

/* Region g's velocity field at (x, y, z), added to v. */
static void field_at(const case_region *g, const double gravity[3], double x, double y, double z,
                     double v[3])
{
    const double pi = 3.14159265358979323846, A = g->field_amplitude;
    if (g->field == CASE_FIELD_TAYLOR_GREEN) {
        const double k = 2.0 * pi / g->field_length;
        v[0] += A * sin(k * x) * cos(k * y);
        v[1] -= A * cos(k * x) * sin(k * y);
    } else if (g->field == CASE_FIELD_STANDING_WAVE) {
        const double k = pi / g->field_length, H = g->shape.hi[2] - g->shape.lo[2];
        const double gm =
            sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);
        const double w = sqrt(gm * k * tanh(k * H)), c = A * w / sinh(k * H);
        const double xr = x - g->shape.lo[0], zr = z - g->shape.lo[2];
        v[0] -= c * cosh(k * zr) * sin(k * xr);
        v[2] += c * sinh(k * zr) * cos(k * xr);
    }
}

/* Add region g's velocity field to fluid particles [from, n) (the loops as
 * they were before field_at: the same bits for a case built on the lattice). */
static void apply_velocity_field(const case_region *g, const double gravity[3], sl_fluid *f,
                                 size_t from)
{
    const double pi = 3.14159265358979323846, A = g->field_amplitude;
    if (g->field == CASE_FIELD_TAYLOR_GREEN) {
        const double k = 2.0 * pi / g->field_length;
        for (size_t i = from; i < f->n; i++) {
            f->vx[i] += A * sin(k * f->x[i]) * cos(k * f->y[i]);
            f->vy[i] -= A * cos(k * f->x[i]) * sin(k * f->y[i]);
        }
    } else if (g->field == CASE_FIELD_STANDING_WAVE) {
        const double k = pi / g->field_length, H = g->shape.hi[2] - g->shape.lo[2];
        const double gm =
            sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);
        const double w = sqrt(gm * k * tanh(k * H)), c = A * w / sinh(k * H);
        for (size_t i = from; i < f->n; i++) {
            const double x = f->x[i] - g->shape.lo[0], z = f->z[i] - g->shape.lo[2];
            f->vx[i] -= c * cosh(k * z) * sin(k * x);
            f->vz[i] += c * sinh(k * z) * cos(k * x);
        }
    }
}

void case_initial_velocity(const sl_case *c, sl_fluid *f)
{
    for (size_t i = 0; i < f->n; i++) {
        const case_region *g = NULL;
        for (size_t r = 0; r < c->nregions && !g; r++)
            if (f->id[i] >= c->regions[r].id0 && f->id[i] < c->regions[r].id1) g = &c->regions[r];
        double v[3] = {0, 0, 0};
        if (g) {
            v[0] = g->velocity[0];
            v[1] = g->velocity[1];
            v[2] = g->velocity[2];
            field_at(g, c->prm.gravity, f->x[i], f->y[i], f->z[i], v);
        }
        f->vx[i] = v[0];
        f->vy[i] = v[1];
        f->vz[i] = v[2];
    }
}

static void read_region(sl_case *c, const dict *r, const dict_entry *at)
{
    static const char *const types[] = {"box", "sphere", "cylinder", "mesh", NULL};
    static const geo_kind kinds[] = {GEO_BOX, GEO_SPHERE, GEO_CYLINDER, GEO_MESH};
    static const double zero[3] = {0, 0, 0};
    sl_err err;
    const char *w;
    case_region *g;
    dict_warn_unknown(r, region_keys);
    need(dict_get_word(r, "type", &w, &err), &err);
    int kind = choose(r, "type", w, types);
    c->regions = sl_realloc(c->regions, (c->nregions + 1) * sizeof *c->regions, "fluid regions");
    g = &c->regions[c->nregions++];
    memset(g, 0, sizeof *g);
    snprintf(g->name, sizeof g->name, "%s", dict_name(r));
    set_where(&g->where, at);
    read_shape_geometry(c, r, &g->shape, kinds[kind], 1);
    need(dict_get_vector_or(r, "velocity", zero, g->velocity, &err), &err);
    if (dict_has(r, "velocityField")) read_velocity_field(r, g);
}

static const char *const emitter_keys[] = {"type",  "centre",    "direction", "size", "radius",
                                           "speed", "startTime", "endTime",   NULL};

static void read_emitter(sl_case *c, const dict *e, const dict_entry *at)
{
    static const char *const types[] = {"rectangle", "disc", NULL};
    sl_err err;
    const char *w;
    emt_emitter *m;
    dict_warn_unknown(e, emitter_keys);
    need(dict_get_word(e, "type", &w, &err), &err);
    int disc = choose(e, "type", w, types);
    c->emitters = sl_realloc(c->emitters, (c->nemitters + 1) * sizeof *c->emitters, "emitters");
    c->emitter_where =
        sl_realloc(c->emitter_where, (c->nemitters + 1) * sizeof *c->emitter_where, "emitters");
    set_where(&c->emitter_where[c->nemitters], at);
    m = &c->emitters[c->nemitters++];
    memset(m, 0, sizeof *m);
    snprintf(m->name, sizeof m->name, "%s", dict_name(e));
    m->disc = disc;
    need(dict_get_vector(e, "centre", m->centre, &err), &err);
    need(dict_get_vector(e, "direction", m->dir, &err), &err);
    if (!(m->dir[0] * m->dir[0] + m->dir[1] * m->dir[1] + m->dir[2] * m->dir[2] > 0.0))
        bad_value(e, "direction", "must not be the zero vector");
    if (disc) {
        need(dict_get_scalar(e, "radius", &m->radius, &err), &err);
        positive(e, "radius", m->radius);
    } else {
        double *sz = NULL;
        size_t n = 0;
        need(dict_get_scalar_list(e, "size", &sz, &n, &err), &err);
        if (n != 2 || !(sz[0] > 0.0) || !(sz[1] > 0.0)) {
            free(sz);
            bad_value(e, "size", "must be two positive widths (a b)");
        }
        m->size[0] = sz[0];
        m->size[1] = sz[1];
        free(sz);
    }
    need(dict_get_scalar(e, "speed", &m->speed, &err), &err);
    positive(e, "speed", m->speed);
    need(dict_get_scalar_or(e, "startTime", 0.0, &m->t0, &err), &err);
    need(dict_get_scalar_or(e, "endTime", INFINITY, &m->t1, &err), &err);
    if (!(m->t1 > m->t0)) {
        char why[160];
        snprintf(why, sizeof why,
                 "must be larger than the emitter's startTime (%g s): it would "
                 "never emit",
                 m->t0);
        bad_value(e, "endTime", why);
    }
    if (m->t0 >= c->ctl.end_time)
        warn_value(e, "startTime",
                   "%g s is at or after the run's endTime (%g s in "
                   "system/controlDict): emitter '%s' never emits",
                   m->t0, c->ctl.end_time, dict_name(e));
    m->rho0 = c->prm.rho0;
    if (emt_setup(m, c->prm.r0) == 0)
        bad_value(e, disc ? "radius" : "size",
                  "the opening holds no particle at this particleSpacing");
}

/* initialPacking cubic | relaxed | { type relaxed; steps ..; tolerance ..; jitter ..; } */
static void read_packing(sl_case *c, const dict *d)
{
    static const char *const types[] = {"cubic", "relaxed", NULL};
    static const char *const keys[] = {"type", "steps", "tolerance", "jitter", NULL};
    case_packing *k = &c->packing;
    sl_err err;
    const char *w;
    long l;
    k->steps = CASE_RELAX_STEPS;
    k->jitter = CASE_RELAX_JITTER;
    k->tolerance = 0.0;
    if (!dict_has(d, "initialPacking")) return;
    set_where(&k->where, dict_lookup(d, "initialPacking"));
    const dict *p = dict_sub(d, "initialPacking");
    if (!p) {
        if (dict_get_word(d, "initialPacking", &w, &err))
            bad_value(d, "initialPacking",
                      "must be cubic, relaxed or { type relaxed; steps ..; jitter ..; }");
        k->relaxed = choose(d, "initialPacking", w, types);
        return;
    }
    dict_warn_unknown(p, keys);
    need(dict_get_word(p, "type", &w, &err), &err);
    k->relaxed = choose(p, "type", w, types);
    need(dict_get_int_or(p, "steps", CASE_RELAX_STEPS, &l, &err), &err);
    if (l < 1 || l > 100000) bad_value(p, "steps", "must be between 1 and 100000 (default 300)");
    k->steps = l;
    if (dict_has(p, "tolerance")) {
        need(dict_get_scalar(p, "tolerance", &k->tolerance, &err), &err);
        if (!(k->tolerance > 0.0 && k->tolerance < 1.0))
            bad_value(p, "tolerance",
                      "must be the largest displacement per step that ends the relaxation, a "
                      "fraction of particleSpacing above 0 and below 1 (e.g. 1e-4; leave it out "
                      "for a fixed number of steps)");
    }
    need(dict_get_scalar_or(p, "jitter", CASE_RELAX_JITTER, &k->jitter, &err), &err);
    if (!(k->jitter >= 0.0 && k->jitter <= 0.3))
        bad_value(p, "jitter",
                  "must be a fraction of particleSpacing between 0 and 0.3 (default 0.1): a "
                  "particle must stay inside its cube of the lattice, r0 / 2 from the walls");
}

/* pressureSource: what the pressure update corrects (solver/pcisph.h):
 *   pressureSource density;       the predicted density error (the paper's, default)
 *   pressureSource divergence;    the predicted density change over the step (DFSPH's
 *                                 divergence source), warm-started
 *   pressureSource mixed;         the divergence source plus densityWeight (0.05) of the
 *                                 density error
 *   pressureSource { type divergence; warmStart off; gradientCorrection on; }
 *   pressureSource { type divergence; ...; meanPressure 0; }   the pressures not clamped,
 *                                 their mean held at 0 Pa (a box periodic along every axis)
 *   pressureSource { type mixed; relaxation 0.5; }   p += 0.5 delta rho_err* (any type;
 *                                 default 1, eq. 3)
 * and densityWeight in the dictionary of type mixed. */
static void read_source(const dict *d, pcs_params *p, case_where *mean_where)
{
    static const char *const types[] = {"density", "divergence", "mixed", NULL};
    static const char *const keys[] = {
        "type",         "densityWeight", "warmStart", "gradientCorrection",
        "meanPressure", "relaxation",    NULL};
    sl_err err;
    const char *w;
    p->source = PCS_SOURCE_DENSITY;
    p->warm_start = 1;
    p->grad_correction = 0;
    if (!dict_has(d, "pressureSource")) return;
    const dict *q = dict_sub(d, "pressureSource");
    if (!q) {
        if (dict_get_word(d, "pressureSource", &w, &err))
            bad_value(d, "pressureSource",
                      "must be density, divergence, mixed or { type divergence; warmStart on; "
                      "gradientCorrection off; }");
        p->source = choose(d, "pressureSource", w, types);
    } else {
        dict_warn_unknown(q, keys);
        need(dict_get_word(q, "type", &w, &err), &err);
        p->source = choose(q, "type", w, types);
        if (dict_has(q, "densityWeight") && p->source != PCS_SOURCE_MIXED)
            bad_value(q, "densityWeight", "is the weight of type mixed only");
        need(dict_get_scalar_or(q, "relaxation", 1.0, &p->relaxation, &err), &err);
        if (!(p->relaxation > 0.0 && p->relaxation <= 1.0))
            bad_value(q, "relaxation",
                      "must be omega of p += omega delta rho_err, above 0 and at most 1 (default "
                      "1, the paper's eq. 3; 0.5 as IISPH's relaxed Jacobi)");
        if (p->source == PCS_SOURCE_DENSITY && dict_size(q) > 1 + (size_t)dict_has(q, "relaxation"))
            bad_value(q, "type",
                      "density takes no options but relaxation (warmStart and gradientCorrection "
                      "are those of divergence and mixed)");
        need(dict_get_bool_or(q, "warmStart", 1, &p->warm_start, &err), &err);
        need(dict_get_bool_or(q, "gradientCorrection", 0, &p->grad_correction, &err), &err);
        if (dict_has(q, "meanPressure")) {
            if (p->source != PCS_SOURCE_DIVERGENCE)
                bad_value(q, "meanPressure",
                          "is an option of type divergence only (the mixed source's density "
                          "error fixes the pressure level)");
            need(dict_get_scalar(q, "meanPressure", &p->mean_pressure, &err), &err);
            if (!(fabs(p->mean_pressure) <= 1e9))
                bad_value(q, "meanPressure",
                          "must be the fluid's mean pressure in Pa (e.g. 0), at most 1e9 in size");
            p->hold_mean = 1;
            set_where(mean_where, dict_lookup(q, "meanPressure"));
        }
    }
    if (p->source == PCS_SOURCE_MIXED) {
        p->source_mix = CASE_SOURCE_MIX;
        if (q)
            need(dict_get_scalar_or(q, "densityWeight", CASE_SOURCE_MIX, &p->source_mix, &err),
                 &err);
        if (!(p->source_mix > 0.0 && p->source_mix < 1.0))
            bad_value(q, "densityWeight",
                      "must be the density error's weight in the source, above 0 (divergence) "
                      "and below 1 (density)");
    }
}

static void read_fluid(sl_case *c)
{
    static const double g0[3] = {0, 0, -9.81};
    dict *d = read_case_file(c, "constant/fluidProperties");
    pcs_params *p = &c->prm;
    sl_err err;
    long l;
    double eta;
    const char **keys = fluid_and_effect_keys();
    dict_warn_unknown(d, keys);
    free(keys);
    need(dict_get_scalar(d, "rho0", &p->rho0, &err), &err);
    if (!(p->rho0 >= 1e-3 && p->rho0 <= 1e5))
        bad_value(d, "rho0", "must be a liquid's rest density in kg/m^3 (between 1e-3 and 1e5)");
    need(dict_get_scalar(d, "particleSpacing", &p->r0, &err), &err);
    positive(d, "particleSpacing", p->r0);
    const char *kname;
    need(dict_get_word_or(d, "kernel", "cubicSpline", &kname, &err), &err);
    p->kernel = krn_type_of(kname);
    if (p->kernel < 0)
        bad_value(d, "kernel",
                  "must be cubicSpline (Monaghan 1992, the paper's) or wendlandC2 (Wendland 1995)");
    need(dict_get_scalar_or(d, "kernelSupport", 2.0, &p->support, &err), &err);
    if (!(p->support >= 2.0 && p->support <= 4.0))
        bad_value(d, "kernelSupport",
                  "must be the kernel's support radius in particle spacings, between 2 (the "
                  "paper's) and 4");
    need(dict_get_vector_or(d, "gravity", g0, p->gravity, &err), &err);
    double gn = sqrt(p->gravity[0] * p->gravity[0] + p->gravity[1] * p->gravity[1] +
                     p->gravity[2] * p->gravity[2]);
    if (gn > CASE_GRAVITY_WARN)
        warn_value(d, "gravity",
                   "|g| = %g m/s^2 is above %g m/s^2 (the Earth's is 9.81): "
                   "wrong units (cm/s^2)?",
                   gn, CASE_GRAVITY_WARN);
    need(dict_get_scalar_or(d, "eta", 1.0, &eta, &err), &err);
    if (!(eta > 0.0 && eta < 100.0))
        bad_value(d, "eta", "must be a percentage above 0 and below 100 (the paper uses 1)");
    if (eta > CASE_ETA_WARN)
        warn_value(d, "eta",
                   "%g %% of rho0 lets the fluid compress by that much (the paper "
                   "uses 1 %%; above %g %% it is no longer a liquid): is it a percentage?",
                   eta, CASE_ETA_WARN);
    p->eta = eta / 100.0;
    need(dict_get_int_or(d, "minIterations", 3, &l, &err), &err);
    if (l < 1 || l > 1000)
        bad_value(d, "minIterations", "must be between 1 and 1000 (the paper uses 3)");
    p->min_iter = (int)l;
    need(dict_get_int_or(d, "maxIterations", 100, &l, &err), &err);
    if (l < p->min_iter || l > 100000) {
        char why[128];
        snprintf(why, sizeof why, "must be between minIterations (%d) and 100000", p->min_iter);
        bad_value(d, "maxIterations", why);
    }
    p->max_iter = (int)l;
    read_source(d, p, &c->mean_where);
    /* pressureForce symmetric;  eq. (6) as the paper (default)
     * pressureForce corrected;  eq. (6) times the kernel gradient correction
     *                           L_i (Bonet & Lok 1999) where the neighbourhood
     *                           is isotropic: there a linear pressure's force
     *                           is its gradient on any packing
     * pressureForce correctedConservative;  each pair's term times
     *                           (L_i + L_j) / 2: momentum conserved
     * (the order of PCS_FORCE_*) */
    static const char *const forces[] = {"symmetric", "corrected", "correctedConservative", NULL};
    const char *fname;
    need(dict_get_word_or(d, "pressureForce", "symmetric", &fname, &err), &err);
    p->force_correction = choose(d, "pressureForce", fname, forces);
    if (p->source != PCS_SOURCE_DENSITY && p->warm_start) {
        /* a packing 2 % closer than the lattice: a margin for the
         * compression (eta) and the local disorder a run reaches; at 2.4
         * r0 the mixed source stops at omega 1 and runs at 0.5
         * (doc/verification.md, "The mixed source: a period that does not
         * move with the step") */
        const double dl = p->relaxation * pcs_delta_lambda_max(p->kernel, p->support, 0.98);
        if (dl > 2.0)
            warn_value(d, "pressureSource",
                       "warm-started at kernelSupport %g, one pressure update grows the largest "
                       "modes of a packing 2 %% closer than the lattice (relaxation times delta "
                       "lambda %.2f > 2), which the warm start carries from step to step: the "
                       "run may stop \"not converging\"; relaxation 0.5 keeps them damped "
                       "(pressureSource { type ...; relaxation 0.5; }, IISPH's relaxed Jacobi)",
                       p->support, dl);
    }
    /* the effects of the fluid, in the order they act: gravity first */
    void *g = eff_gravity_new(p->gravity);
    if (g) eff_add(&c->effects, &eff_gravity, g);
    const eff_setup su = {p->r0, pcs_support(p), p->rho0, p->gravity};
    eff_read_fluid(&c->effects, d, &su);
    if (dict_has(d, "emitters")) {
        const dict *em = dict_sub(d, "emitters");
        if (!em) bad_value(d, "emitters", "must be a dictionary of emitters");
        for (size_t i = 0; i < dict_size(em); i++) {
            const dict_entry *e = dict_entry_at(em, i);
            if (!dict_entry_dict(e))
                sl_fatal("%s:%d: emitter '%s' must be a dictionary", dict_entry_file(e),
                         dict_entry_line(e), dict_entry_key(e));
            read_emitter(c, dict_entry_dict(e), e);
        }
    }
    read_packing(c, d);
    const dict *regions = dict_sub(d, "fluidRegions");
    if (!regions && c->nemitters == 0)
        bad_value(d, "fluidRegions", "a dictionary of fluid regions (or emitters) is required");
    for (size_t i = 0; regions && i < dict_size(regions); i++) {
        const dict *r = dict_entry_dict(dict_entry_at(regions, i));
        if (!r) {
            const dict_entry *e = dict_entry_at(regions, i);
            sl_fatal("%s:%d: fluid region '%s' must be a dictionary", dict_entry_file(e),
                     dict_entry_line(e), dict_entry_key(e));
        }
        read_region(c, r, dict_entry_at(regions, i));
    }
    if (c->nregions == 0 && c->nemitters == 0)
        bad_value(d, "fluidRegions", "names no fluid region (and there is no emitter)");
    dict_free(d);
}

/* ---- constant/boundaryProperties ---- */

static const char *const boundary_keys[] = {"method",   "epsilon",  "restitution", "massFactor",
                                            "geometry", "periodic", NULL};
static const char *const shape_keys[] = {
    "type",  "min",   "max",  "centre", "radius", "open",      "point1", "point2", "origin",
    "edge1", "edge2", "file", "scale",  "rotate", "translate", "side",   "motion", NULL};

static unsigned read_open_faces(const dict *s)
{
    static const char *const faces[] = {"xMin", "xMax", "yMin", "yMax", "zMin", "zMax", NULL};
    unsigned mask = 0;
    char **words = NULL;
    size_t n = 0;
    sl_err err;
    if (!dict_has(s, "open")) return 0;
    need(dict_get_word_list(s, "open", &words, &n, &err), &err);
    for (size_t i = 0; i < n; i++) {
        mask |= 1u << choose(s, "open", words[i], faces);
        free(words[i]);
    }
    free(words);
    return mask;
}

/* A mesh body: file, optional scale / rotate / translate, side. */
static void read_mesh(sl_case *c, const dict *s, geo_shape *g, int region)
{
    static const char *const sides[] = {"obstacle", "container", NULL};
    static const double zero[3] = {0, 0, 0};
    sl_err err;
    const char *file, *side;
    double rot[3], tr[3];
    need(dict_get_word(s, "file", &file, &err), &err);
    size_t len = strlen(c->dir) + strlen(file) + 16;
    char *path = sl_malloc(len, "path");
    snprintf(path, len, "%s/constant/%s", c->dir, file); /* meshes live in constant/ */
    g->mesh = sl_malloc(sizeof *g->mesh, "mesh");
    mesh_init(g->mesh);
    if (mesh_read(path, g->mesh, &err))
        sl_fatal("%s (geometry '%s' in %s)", err.msg, g->name, dict_file(s));
    if (dict_has(s, "scale")) {
        double sc[3];
        const dict_entry *e = dict_lookup(s, "scale");
        char *txt = dict_entry_value_text(e);
        int vec = txt && txt[0] == '(';
        free(txt);
        if (vec) need(dict_get_vector(s, "scale", sc, &err), &err);
        else {
            need(dict_get_scalar(s, "scale", &sc[0], &err), &err);
            sc[1] = sc[2] = sc[0];
        }
        if (mesh_scale(g->mesh, sc, &err)) bad_value(s, "scale", err.msg);
    }
    need(dict_get_vector_or(s, "rotate", zero, rot, &err), &err);
    need(dict_get_vector_or(s, "translate", zero, tr, &err), &err);
    if (mesh_rotate(g->mesh, rot, &err)) bad_value(s, "rotate", err.msg);
    if (mesh_translate(g->mesh, tr, &err)) bad_value(s, "translate", err.msg);
    need(dict_get_word_or(s, "side", "obstacle", &side, &err), &err);
    g->mesh_container = region ? 0 : choose(s, "side", side, sides);
    mesh_report rep;
    unsigned check = region ? MESH_REQUIRE_CLOSED : g->mesh_container ? 0 : MESH_WARN_OPEN;
    if (mesh_validate(g->mesh, path, check, &rep, &err))
        sl_fatal("%s (geometry '%s' in %s)", err.msg, g->name, dict_file(s));
    g->dbound = 2.0 * c->prm.r0;
    free(path);
}

/* The shape part of a geometry or fluid-region entry. */
static void read_shape_geometry(sl_case *c, const dict *s, geo_shape *g, geo_kind kind, int region)
{
    sl_err err;
    snprintf(g->name, sizeof g->name, "%s", dict_name(s));
    g->kind = kind;
    if (g->kind == GEO_MESH) {
        read_mesh(c, s, g, region);
        return;
    }
    if (g->kind == GEO_CYLINDER) {
        need(dict_get_vector(s, "point1", g->p1, &err), &err);
        need(dict_get_vector(s, "point2", g->p2, &err), &err);
        need(dict_get_scalar(s, "radius", &g->radius, &err), &err);
        positive(s, "radius", g->radius);
        double l2 = 0;
        for (int k = 0; k < 3; k++) l2 += (g->p2[k] - g->p1[k]) * (g->p2[k] - g->p1[k]);
        if (!(l2 > 0)) bad_value(s, "point2", "must differ from point1");
        return;
    }
    if (g->kind == GEO_PLANE) {
        need(dict_get_vector(s, "origin", g->origin, &err), &err);
        need(dict_get_vector(s, "edge1", g->e1, &err), &err);
        need(dict_get_vector(s, "edge2", g->e2, &err), &err);
        double n[3] = {g->e1[1] * g->e2[2] - g->e1[2] * g->e2[1],
                       g->e1[2] * g->e2[0] - g->e1[0] * g->e2[2],
                       g->e1[0] * g->e2[1] - g->e1[1] * g->e2[0]};
        if (!(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 0))
            bad_value(s, "edge2", "must not be parallel to edge1 (or zero)");
        return;
    }
    if (g->kind == GEO_SPHERE) {
        need(dict_get_vector(s, "centre", g->centre, &err), &err);
        need(dict_get_scalar(s, "radius", &g->radius, &err), &err);
        positive(s, "radius", g->radius);
        return;
    }
    need(dict_get_vector(s, "min", g->lo, &err), &err);
    need(dict_get_vector(s, "max", g->hi, &err), &err);
    for (int k = 0; k < 3; k++)
        if (!(g->hi[k] > g->lo[k]))
            bad_value(s, "max", "must be larger than min in every component");
    if (g->kind == GEO_CONTAINER) g->open_faces = read_open_faces(s);
}

static void read_shape(sl_case *c, const dict *s)
{
    static const char *const types[] = {"container", "box",  "sphere", "cylinder",
                                        "plane",     "mesh", NULL};
    static const geo_kind kinds[] = {GEO_CONTAINER, GEO_BOX,   GEO_SPHERE,
                                     GEO_CYLINDER,  GEO_PLANE, GEO_MESH};
    sl_err err;
    const char *w;
    dict_warn_unknown(s, shape_keys);
    need(dict_get_word(s, "type", &w, &err), &err);
    int kind = choose(s, "type", w, types);
    c->shapes = sl_realloc(c->shapes, (c->nshapes + 1) * sizeof *c->shapes, "geometry");
    c->motions = sl_realloc(c->motions, (c->nshapes + 1) * sizeof *c->motions, "geometry");
    memset(&c->motions[c->nshapes], 0, sizeof *c->motions);
    if (dict_has(s, "motion")) {
        const dict *m = dict_sub(s, "motion");
        if (!m)
            bad_value(s, "motion", "must be a dictionary { type cosine|oscillating|table; ... }");
        mot_read(&c->motions[c->nshapes], m, c->dir);
    }
    geo_shape *g = &c->shapes[c->nshapes++];
    memset(g, 0, sizeof *g);
    read_shape_geometry(c, s, g, kinds[kind], 0);
}

static void read_boundary(sl_case *c)
{
    dict *d = read_case_file(c, "constant/boundaryProperties");
    sl_err err;
    const char *w;
    dict_warn_unknown(d, boundary_keys);
    need(dict_get_word_or(d, "method", c->prm.method->name, &w, &err), &err);
    const char *const *methods = bnd_method_names();
    c->prm.method = bnd_method_find(methods[choose(d, "method", w, methods)]);
    if (c->prm.source != PCS_SOURCE_DENSITY && c->prm.method == &harada2007_method)
        bad_value(d, "method",
                  "harada2007's wall weight has no divergence term: pressureSource divergence "
                  "and mixed (constant/fluidProperties) need ihmsen2010 or becker2009");
    if (c->prm.force_correction && strcmp(c->prm.method->name, "ihmsen2010") != 0)
        bad_value(d, "method",
                  "pressureForce corrected and correctedConservative (constant/fluidProperties) "
                  "need ihmsen2010: their "
                  "correction is taken over the boundary particles, which only ihmsen2010's "
                  "pressure force sums as the fluid's (eq. 13)");
    need(dict_get_scalar_or(d, "restitution", 0.0, &c->prm.restitution, &err), &err);
    if (!(c->prm.restitution >= 0.0 && c->prm.restitution <= 1.0))
        bad_value(d, "restitution", "must be in [0, 1]");
    need(dict_get_scalar_or(d, "massFactor", 1.0, &c->prm.mass_factor, &err), &err);
    if (!(c->prm.mass_factor > 0.0 && c->prm.mass_factor <= 10.0))
        bad_value(d, "massFactor", "must be in (0, 10]");
    need(dict_get_scalar_or(d, "epsilon", 1.0, &c->prm.epsilon, &err), &err);
    if (!(c->prm.epsilon >= 0.0 && c->prm.epsilon <= 1.0))
        bad_value(d, "epsilon", "must be in [0, 1]");
    const dict *geo = dict_sub(d, "geometry");
    if (!geo) bad_value(d, "geometry", "a dictionary of boundary shapes is required");
    for (size_t i = 0; i < dict_size(geo); i++) {
        const dict_entry *e = dict_entry_at(geo, i);
        if (!dict_entry_dict(e))
            sl_fatal("%s:%d: geometry entry '%s' must be a dictionary", dict_entry_file(e),
                     dict_entry_line(e), dict_entry_key(e));
        read_shape(c, dict_entry_dict(e));
    }
    dict_free(d);
}

/* The period along axis a: the extent of the first container, whose
 * faces across a must be open; every other shape inside it. */
static void periodic_extent(sl_case *c, const dict *d, int a)
{
    const char *ax = (const char *[]){"x", "y", "z"}[a];
    const unsigned faces = (unsigned)(3u << (2 * a));
    const geo_shape *box = NULL;
    char why[512];
    for (size_t s = 0; s < c->nshapes && !box; s++)
        if (c->shapes[s].kind == GEO_CONTAINER) box = &c->shapes[s];
    if (!box)
        bad_value(d, "periodic",
                  "needs a container (with open faces across the periodic axis) "
                  "to give the period");
    if ((box->open_faces & faces) != faces) {
        snprintf(why, sizeof why,
                 "axis %s: container '%s' has walls across it; open both faces "
                 "(open (%sMin %sMax);) to make %s periodic",
                 ax, box->name, ax, ax, ax);
        bad_value(d, "periodic", why);
    }
    const double lo = box->lo[a], hi = box->hi[a], len = hi - lo, r0 = c->prm.r0;
    const double k = len / r0;
    if (fabs(k - round(k)) > 1e-6 * fmax(k, 1.0)) {
        snprintf(why, sizeof why,
                 "axis %s: the period (container '%s', %g m) must be a whole "
                 "number of particle spacings (%g m), here %.6g; make it %g or %g m",
                 ax, box->name, len, r0, k, floor(k) * r0, ceil(k) * r0);
        bad_value(d, "periodic", why);
    }
    if (len < 4.0 * r0 * (1.0 - 1e-9)) {
        snprintf(why, sizeof why,
                 "axis %s: the period (%g m) must be at least the support "
                 "diameter 2 h = 4 particleSpacing (%g m)",
                 ax, len, 4.0 * r0);
        bad_value(d, "periodic", why);
    }
    const double tol = 1e-9 * len;
    for (size_t s = 0; s < c->nshapes; s++) {
        double slo[3], shi[3];
        if (&c->shapes[s] == box) continue;
        geo_bounds(&c->shapes[s], 0.0, slo, shi);
        if (c->shapes[s].kind == GEO_PLANE) {
            slo[a] += r0;
            shi[a] -= r0;
        } /* geo_bounds pads planes */
        if (c->shapes[s].kind == GEO_CONTAINER && (c->shapes[s].open_faces & faces) == faces &&
            fabs(slo[a] - lo) <= tol && fabs(shi[a] - hi) <= tol)
            continue;
        if (slo[a] < lo - tol || shi[a] > hi + tol) {
            snprintf(why, sizeof why,
                     "axis %s: geometry '%s' (%g to %g) crosses the periodic "
                     "face of container '%s' (%g to %g); keep it inside the period",
                     ax, c->shapes[s].name, slo[a], shi[a], box->name, lo, hi);
            bad_value(d, "periodic", why);
        }
    }
    for (size_t r = 0; r < c->nregions; r++) {
        double rlo[3], rhi[3];
        geo_bounds(&c->regions[r].shape, 0.0, rlo, rhi);
        if (rlo[a] < lo - tol || rhi[a] > hi + tol)
            sl_fatal("%s/constant/fluidProperties: fluid region '%s' (%g to %g along %s) must lie "
                     "inside the period %g to %g of 'periodic' in constant/boundaryProperties",
                     c->dir, c->regions[r].name, rlo[a], rhi[a], ax, lo, hi);
    }
    c->prm.periodic.lo[a] = lo;
    c->prm.periodic.hi[a] = hi;
}

/* periodic (x y);: the axes, and the period of each from the geometry. */
static void read_periodic(sl_case *c, const char *rel)
{
    static const char *const axes[] = {"x", "y", "z", NULL};
    dict *d = read_dict(c, rel);
    char **words = NULL;
    size_t n = 0;
    sl_err err;
    if (!dict_has(d, "periodic")) {
        dict_free(d);
        return;
    }
    need(dict_get_word_list(d, "periodic", &words, &n, &err), &err);
    for (size_t i = 0; i < n; i++) {
        c->prm.periodic.axes |= 1u << choose(d, "periodic", words[i], axes);
        free(words[i]);
    }
    free(words);
    if (!c->prm.periodic.axes) bad_value(d, "periodic", "names no axis (x, y or z)");
    for (int a = 0; a < 3; a++)
        if (c->prm.periodic.axes & (1u << a)) periodic_extent(c, d, a);
    dict_free(d);
}

const dict_key_home *case_key_homes(void)
{
    static const char *fluid[64];
    static dict_key_home homes[5];
    if (homes[0].where) return homes;
    const char **k = fluid_and_effect_keys();
    size_t n = 0;
    while (k[n] && n + 1 < sizeof fluid / sizeof *fluid) {
        fluid[n] = k[n];
        n++;
    }
    fluid[n] = NULL;
    free(k);
    homes[0] = (dict_key_home){"system/controlDict", control_keys};
    homes[1] = (dict_key_home){"system/timeStepDict", ts_keys()};
    homes[2] = (dict_key_home){"constant/fluidProperties", fluid};
    homes[3] = (dict_key_home){"constant/boundaryProperties", boundary_keys};
    homes[4] = (dict_key_home){NULL, NULL};
    return homes;
}

void case_read(sl_case *c, const char *dir)
{
    /* `eta` in controlDict is reported as belonging in fluidProperties */
    dict_warn_set_homes(case_key_homes());
    memset(c, 0, sizeof *c);
    pcs_params_default(&c->prm);
    eff_set_init(&c->effects);
    c->dir = sl_strdup(dir);
    prt_fluid_init(&c->fluid);
    prt_boundary_init(&c->boundary);
    read_controls(c);
    read_timestep(c);
    read_fluid(c);
    read_boundary(c);
    read_periodic(c, "constant/boundaryProperties");
    const eff_instance *shift = eff_find(&c->effects, eff_particle_shifting.name);
    if (shift && c->prm.periodic.axes != 7u) /* no free-surface treatment (particle_shifting.h) */
        sl_fatal("%s: particleShifting: only in a box periodic along every axis (periodic (x y "
                 "z); in constant/boundaryProperties): it has no free-surface treatment yet",
                 eff_particle_shifting_where(shift->state));
    if (c->prm.hold_mean && c->prm.periodic.axes != 7u) /* a free surface fixes the level */
        sl_fatal("%s: keyword 'meanPressure': only in a box periodic along every axis "
                 "(periodic (x y z); in constant/boundaryProperties): at a free surface the "
                 "pressure is 0, and negative pressures would pull the surface together",
                 c->mean_where.text);
    void *moving = eff_moving_boundary_new(c->motions, c->nshapes);
    if (moving) eff_add(&c->effects, &eff_moving_boundary, moving);
    sl_err err;
    if (ts_validate(&c->ts, c->prm.eta, &err))
        sl_fatal("%s/system/timeStepDict: %s (with eta = %g %% in constant/fluidProperties)",
                 c->dir, err.msg, 100 * c->prm.eta);
    if (ts_is_cost(&c->ts)) /* to eta on average, minIterations..maxIterations */
        c->prm.stop_max = c->ts.cost_max_density * c->prm.eta;
    else if (c->ts.mode == TS_ADAPTIVE) /* Sec. 3.3: exactly `iterations` per step */
        c->prm.min_iter = c->prm.max_iter = c->ts.iterations;
}

/* ---- building the world ---- */

static void grow_bounds(double lo[3], double hi[3], const double a[3], const double b[3])
{
    for (int k = 0; k < 3; k++) {
        if (a[k] < lo[k]) lo[k] = a[k];
        if (b[k] > hi[k]) hi[k] = b[k];
    }
}

/* Particles a box of extent e needs: its volume (fluid) or its surface
 * (boundary) over the spacing; infinite when it overflows. */
static double estimate(const double lo[3], const double hi[3], double r0, int surface)
{
    double a = (hi[0] - lo[0]) / r0, b = (hi[1] - lo[1]) / r0, c = (hi[2] - lo[2]) / r0;
    double n = surface ? 2.0 * (a * b + b * c + c * a) : a * b * c;
    return isfinite(n) ? n : HUGE_VAL;
}

/* Stop before allocating when a shape or region would need more particles
 * than memory holds (about 0.5 KiB each): wrong units or a typo. */
static void check_size(const sl_case *c, const char *file, const char *what, const char *name,
                       double n)
{
    const double limit = (double)sysconf(_SC_PHYS_PAGES) * (double)sysconf(_SC_PAGESIZE) / 512.0;
    if (n > limit)
        sl_fatal("%s/%s: %s '%s' needs too many particles (about %.3g at particleSpacing %g; this "
                 "machine's memory holds about %.3g): is particleSpacing or the size in the "
                 "wrong units?",
                 c->dir, file, what, name, n, c->prm.r0, limit);
}

/* "Sampling geometry 'glass' (2 of 5 parts)": what a long build is doing
 * (sl_progress: in place on a terminal, every 10 s in a log). */
static void build_status(sl_progress *p, const char *what, const char *name, size_t k, size_t n)
{
    char text[256];
    snprintf(text, sizeof text, "%s '%s' (%zu of %zu parts)", what, name, k + 1, n);
    sl_progress_update(p, (double)k, text);
}

/* The names of the box containers ("'tank'", "'tank', 'table'"). */
static const char *container_names(const sl_case *c)
{
    static char buf[256];
    size_t off = 0;
    buf[0] = 0;
    for (size_t s = 0; s < c->nshapes && off < sizeof buf; s++) {
        const geo_shape *g = &c->shapes[s];
        if (g->kind == GEO_CONTAINER)
            off +=
                (size_t)snprintf(buf + off, sizeof buf - off, "%s'%s'", off ? ", " : "", g->name);
    }
    return buf;
}

/* 1 if p, outside the box container g, lies beyond open faces only and
 * the jet (or gravity) carries it in through them: a tank filled from
 * above its open top. */
static int pours_in(const geo_shape *g, const double p[3], const double dir[3],
                    const double grav[3])
{
    for (int d = 0; d < 3; d++) {
        unsigned fmin = 1u << (2 * d), fmax = 1u << (2 * d + 1);
        if (p[d] < g->lo[d] && !((g->open_faces & fmin) && (dir[d] > 0 || grav[d] > 0))) return 0;
        if (p[d] > g->hi[d] && !((g->open_faces & fmax) && (dir[d] < 0 || grav[d] < 0))) return 0;
    }
    return 1;
}

/* An emitter must open into the fluid space: every point of its opening
 * inside the box containers (or pouring in through an open face) and
 * outside the solids; else its particles fall outside the tank forever, or
 * are born inside a wall.  A mesh container is not checked: a tap above a
 * glass pours into it. */
/* The first shape that excludes p from the fluid space (nshapes: none). */
static size_t excluding_shape(const sl_case *c, const emt_emitter *m, const double p[3])
{
    size_t s;
    for (s = 0; s < c->nshapes; s++) {
        const geo_shape *t = &c->shapes[s];
        if (t->kind == GEO_MESH && t->mesh_container) continue;
        if (geo_solid_distance(t, p) < 0.0 &&
            !(t->kind == GEO_CONTAINER && pours_in(t, p, m->dir, c->prm.gravity)))
            break;
    }
    return s;
}

static void check_emitter_place(const sl_case *c, size_t k)
{
    const emt_emitter *m = &c->emitters[k];
    for (int ahead = 0; ahead < 2; ahead++) /* the opening, then one spacing downstream */
        for (size_t q = 0; q < m->np; q++) {
            double p[3];
            for (int d = 0; d < 3; d++)
                p[d] = m->centre[d] + m->pu[q] * m->u[d] + m->pv[q] * m->v[d] +
                    ahead * c->prm.r0 * m->dir[d];
            size_t s = excluding_shape(c, m, p);
            if (s == c->nshapes) continue;
            const geo_shape *g = &c->shapes[s];
            int outside = g->kind == GEO_CONTAINER;
            if (ahead)
                sl_fatal("%s: emitter '%s' points %s geometry '%s': one particleSpacing "
                         "downstream, (%g %g %g) is %s; turn its direction into the fluid space",
                         c->emitter_where[k].text, m->name,
                         outside ? "out of the container" : "into the solid", g->name, p[0], p[1],
                         p[2], outside ? "beyond the walls" : "inside it");
            sl_fatal("%s: emitter '%s' opens %s geometry '%s': its point (%g %g %g) is %s; move "
                     "its centre (or make it smaller) so that the whole opening is in the fluid "
                     "space",
                     c->emitter_where[k].text, m->name,
                     outside ? "outside the container" : "inside the solid", g->name, p[0], p[1],
                     p[2], outside ? "beyond the walls" : "inside it");
        }
}

/* The volume an emitter delivers before endTime, against the containers'
 * volume: more than they hold is almost surely a wrong rate or time. */
static void check_emitter_volume(const sl_case *c, size_t k)
{
    const emt_emitter *m = &c->emitters[k];
    double t1 = fmin(m->t1, c->ctl.end_time), t0 = fmax(m->t0, c->ctl.start_time);
    double area = (double)m->np * c->prm.r0 * c->prm.r0, vol = area * m->speed * fmax(t1 - t0, 0.0);
    double tank = 0.0;
    for (size_t s = 0; s < c->nshapes; s++) {
        const geo_shape *g = &c->shapes[s];
        if (g->kind == GEO_CONTAINER)
            tank += (g->hi[0] - g->lo[0]) * (g->hi[1] - g->lo[1]) * (g->hi[2] - g->lo[2]);
    }
    if (tank > 0.0 && vol > tank)
        sl_warning("%s: emitter '%s' delivers %.3g m^3 by t = %g s (%zu particles a layer, %g m/s) "
                   "but the containers (%s) hold %.3g m^3: the fluid will overflow; check speed, "
                   "startTime and endTime",
                   c->emitter_where[k].text, m->name, vol, t1, m->np, m->speed, container_names(c),
                   tank);
}

/* The fluid's filter while a region is filled: every lattice point the
 * region makes is tested against the earlier regions (two regions over one
 * place would put two particles there, twice rho0, which PCISPH cannot
 * undo: overlapping regions are refused), then kept or not by the pass's
 * own filter (case_build_particles; NULL keeps every one).  The test sees
 * every point made, stored or not, so a rank that keeps a part of the case
 * refuses what the serial build refuses. */
typedef struct fill_filter {
    prt_filter f; /* c->fluid.filter while filling (f.ctx: this) */
    const sl_case *c;
    prt_filter *pass; /* the pass's filter (NULL: keep all) */
    size_t region;
    size_t *inside; /* per earlier region: points of this one inside it */
} fill_filter;

static int fill_keep(void *ctx, double x, double y, double z)
{
    fill_filter *k = ctx;
    const double p[3] = {x, y, z};
    for (size_t q = 0; q < k->region; q++)
        k->inside[q] += geo_solid_distance(&k->c->regions[q].shape, p) < 0.0;
    if (!k->pass) return 1;
    k->pass->made++;
    return k->pass->keep(k->pass->ctx, x, y, z);
}

/* After region r (n particles made): refused if some lie inside an earlier
 * region. */
static void check_overlap(const sl_case *c, size_t r, const size_t *inside, size_t n)
{
    for (size_t q = 0; q < r; q++)
        if (inside[q])
            sl_fatal("%s: fluid region '%s' overlaps fluid region '%s' (%s): %zu of its %zu "
                     "particles lie inside '%s', where they would double the density; make the "
                     "regions disjoint (or merge them)",
                     c->regions[r].where.text, c->regions[r].name, c->regions[q].name,
                     c->regions[q].where.text, inside[q], n, c->regions[q].name);
}

/* A body that lies wholly outside every box container meets no fluid:
 * almost surely a wrong translate, scale or unit. */
static void check_shape_place(const sl_case *c, size_t s, const double lo[3], const double hi[3])
{
    const geo_shape *g = &c->shapes[s];
    int containers = 0;
    if (g->kind == GEO_CONTAINER || (g->kind == GEO_MESH && g->mesh_container)) return;
    /* (bodies that move are left alone: they may come in later) */
    for (size_t t = 0; t < c->nshapes; t++) {
        const geo_shape *k = &c->shapes[t];
        if (k->kind != GEO_CONTAINER) continue;
        containers++;
        int apart = 0;
        for (int d = 0; d < 3; d++) apart |= lo[d] > k->hi[d] || hi[d] < k->lo[d];
        if (!apart) return;
    }
    if (containers)
        sl_warning("%s/constant/boundaryProperties: geometry '%s' (%g %g %g)-(%g %g %g) lies "
                   "wholly outside the container (%s): no fluid can reach it; wrong translate, "
                   "scale or units?",
                   c->dir, g->name, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], container_names(c));
}

void case_build_prepare(sl_case *c)
{
    const double r0 = c->prm.r0;
    for (size_t s = 0; s < c->nshapes; s++) {
        double lo[3], hi[3];
        if (c->shapes[s].kind == GEO_PLANE) continue; /* bounded by its edges */
        geo_bounds(&c->shapes[s], 0.0, lo, hi);
        check_size(c, "constant/boundaryProperties", "geometry", c->shapes[s].name,
                   estimate(lo, hi, r0, 1));
        if (c->motions[s].type == MOT_NONE) check_shape_place(c, s, lo, hi);
        if (c->shapes[s].kind == GEO_MESH) {
            double diag =
                sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
            if (diag < 2.0 * r0)
                sl_fatal(
                    "%s/constant/boundaryProperties: geometry '%s' is too small (%g m across) to "
                    "sample with particleSpacing %g: wrong scale?",
                    c->dir, c->shapes[s].name, diag, r0);
        }
    }
    for (size_t r = 0; r < c->nregions; r++) {
        double lo[3], hi[3];
        geo_bounds(&c->regions[r].shape, 0.0, lo, hi);
        check_size(c, "constant/fluidProperties", "fluid region", c->regions[r].name,
                   estimate(lo, hi, r0, 0));
    }
    for (size_t s = 0; s < c->nshapes; s++) {
        geo_shape *t = &c->shapes[s];
        /* A box thinner than 2 r0 would be sampled as one layer with
         * opposite normals on one plane, which cancel in eq. (9) and let
         * fluid through: it is made 2 r0 thick about its mid-plane. */
        for (int d = 0; t->kind == GEO_BOX && d < 3; d++)
            if (t->hi[d] - t->lo[d] < 2.0 * r0 * (1.0 - 1e-9)) {
                double mid = 0.5 * (t->lo[d] + t->hi[d]);
                sl_warning("%s/constant/boundaryProperties: box '%s' is %g m thick, less than two "
                           "particle spacings: treated as %g m thick",
                           c->dir, t->name, t->hi[d] - t->lo[d], 2.0 * r0);
                t->lo[d] = mid - r0;
                t->hi[d] = mid + r0;
            }
    }
    for (size_t e = 0; e < c->nemitters; e++) {
        check_emitter_place(c, e);
        check_emitter_volume(c, e);
    }
}

/* The regions filled: region r's particles made [id0, id1), those the
 * fluid's filter keeps stored. */
static void fill_regions(sl_case *c, prt_filter *fluid, sl_progress *prog, size_t nparts)
{
    const double r0 = c->prm.r0;
    fill_filter k = {.f = {fill_keep, NULL, 0}, .c = c, .pass = fluid};
    k.f.ctx = &k;
    k.inside = sl_calloc(c->nregions + 1, sizeof *k.inside, "region overlaps");
    c->fluid.filter = &k.f;
    for (size_t r = 0; r < c->nregions; r++) {
        const case_region *g = &c->regions[r];
        build_status(prog, "filling fluid region", g->name, c->nshapes + r, nparts);
        size_t lost = 0, from = c->fluid.n;
        const size_t id0 = k.f.made;
        k.region = r;
        memset(k.inside, 0, (c->nregions + 1) * sizeof *k.inside);
        size_t n =
            geo_fill_region(&g->shape, r0, g->velocity, c->shapes, c->nshapes, &c->fluid, &lost);
        if (lost)
            sl_fatal("%s: fluid region '%s' %s the container (%s): %zu of its particles would "
                     "lie beyond the walls and be dropped; make the region fit inside",
                     g->where.text, g->name, n ? "reaches outside" : "lies outside",
                     container_names(c), lost);
        if (n == 0)
            sl_fatal("%s/constant/fluidProperties: fluid region '%s' holds no particle "
                     "(outside the container, inside an obstacle, or smaller than "
                     "particleSpacing %g)",
                     c->dir, g->name, r0);
        check_overlap(c, r, k.inside, n);
        apply_velocity_field(g, c->prm.gravity, &c->fluid, from);
        c->regions[r].id0 = (uint32_t)id0;
        c->regions[r].id1 = (uint32_t)k.f.made;
    }
    c->fluid.filter = NULL;
    c->nfluid = k.f.made;
    free(k.inside);
}

void case_build_particles(sl_case *c, prt_filter *fluid, prt_filter *boundary, int what)
{
    const double r0 = c->prm.r0;
    sl_progress prog;
    const size_t nparts = c->nshapes + c->nregions;
    sl_progress_start(&prog, stderr, 0, (double)nparts, 10.0);
    if (what & CASE_BOUNDARY) {
        c->boundary.filter = boundary;
        const size_t made0 = boundary ? boundary->made : c->boundary.n;
        for (size_t s = 0; s < c->nshapes; s++) {
            const geo_shape *g = &c->shapes[s];
            build_status(&prog, "sampling geometry", g->name, s, nparts);
            const int all_open = g->kind == GEO_CONTAINER && g->open_faces == 63u;
            if (geo_sample(g, r0, (uint32_t)s, &c->boundary) == 0 &&
                !(all_open && c->prm.periodic.axes)) /* a periodic box without walls */
                sl_fatal("%s/constant/boundaryProperties: geometry '%s' is too small to sample "
                         "with particleSpacing %g",
                         c->dir, g->name, r0);
        }
        c->nboundary = boundary ? boundary->made - made0 : c->boundary.n;
        c->boundary.filter = NULL;
    }
    if (what & CASE_FLUID) fill_regions(c, fluid, &prog, nparts);
    sl_progress_end(&prog);
}

void case_build_finish(sl_case *c)
{
    const double r0 = c->prm.r0;
    for (int k = 0; k < 3; k++) {
        c->lo[k] = INFINITY;
        c->hi[k] = -INFINITY;
    }
    for (size_t s = 0; s < c->nshapes; s++) {
        double lo[3], hi[3];
        geo_bounds(&c->shapes[s], r0, lo, hi);
        grow_bounds(c->lo, c->hi, lo, hi);
    }
    for (size_t r = 0; r < c->nregions; r++) {
        double lo[3], hi[3];
        geo_bounds(&c->regions[r].shape, r0, lo, hi);
        grow_bounds(c->lo, c->hi, lo, hi);
    }
    for (size_t e = 0; e < c->nemitters; e++) {
        const emt_emitter *m = &c->emitters[e];
        double reach =
            m->disc ? m->radius : 0.5 * sqrt(m->size[0] * m->size[0] + m->size[1] * m->size[1]);
        double lo[3], hi[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = m->centre[k] - reach;
            hi[k] = m->centre[k] + reach;
        }
        grow_bounds(c->lo, c->hi, lo, hi);
    }
    if (c->nfluid > UINT32_MAX / 2 || c->nboundary > UINT32_MAX / 2)
        sl_fatal("%s: too many particles (%zu fluid, %zu boundary)", c->dir, c->nfluid,
                 c->nboundary);
    for (int k = 0; k < 3; k++) {
        c->lo[k] -= pcs_support(&c->prm);
        c->hi[k] += pcs_support(&c->prm);
    }
    for (int k = 0; k < 3; k++) /* room for the periodic images (h beyond the faces) */
        if (c->prm.periodic.axes & (1u << k)) {
            c->lo[k] = fmin(c->lo[k], c->prm.periodic.lo[k] - (pcs_support(&c->prm) + r0));
            c->hi[k] = fmax(c->hi[k], c->prm.periodic.hi[k] + (pcs_support(&c->prm) + r0));
        }
    void *emit = eff_emitter_new(c->emitters, c->nemitters, (uint32_t)c->nfluid);
    if (emit) eff_add(&c->effects, &eff_emitter, emit);
}

void case_build(sl_case *c)
{
    case_build_prepare(c);
    case_build_particles(c, NULL, NULL, CASE_FLUID | CASE_BOUNDARY);
    case_build_finish(c);
}

void case_free(sl_case *c)
{
    eff_set_free(&c->effects);
    prt_fluid_free(&c->fluid);
    prt_boundary_free(&c->boundary);
    for (size_t i = 0; i < c->nshapes; i++)
        if (c->shapes[i].mesh) {
            mesh_free(c->shapes[i].mesh);
            free(c->shapes[i].mesh);
        }
    for (size_t i = 0; i < c->nregions; i++)
        if (c->regions[i].shape.mesh) {
            mesh_free(c->regions[i].shape.mesh);
            free(c->regions[i].shape.mesh);
        }
    for (size_t i = 0; i < c->nemitters; i++) emt_free(&c->emitters[i]);
    free(c->emitters);
    free(c->emitter_where);
    for (size_t i = 0; i < c->nshapes; i++) mot_free(&c->motions[i]);
    free(c->motions);
    free(c->shapes);
    free(c->regions);
    free(c->dir);
    memset(c, 0, sizeof *c);
}

double case_wall_distance(const sl_case *c, const double p[3])
{
    double d = INFINITY;
    for (size_t k = 0; k < c->nshapes; k++) {
        const geo_shape *s = &c->shapes[k];
        if (s->kind == GEO_CONTAINER) {
            for (int a = 0; a < 3; a++) {
                if (!(s->open_faces & (1u << (2 * a))) && p[a] - s->lo[a] < d) d = p[a] - s->lo[a];
                if (!(s->open_faces & (1u << (2 * a + 1))) && s->hi[a] - p[a] < d)
                    d = s->hi[a] - p[a];
            }
        } else {
            double e = geo_solid_distance(s, p);
            if (e < d) d = e;
        }
    }
    return d;
}
