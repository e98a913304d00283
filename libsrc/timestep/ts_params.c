/*
 * ts_params: the constants of Ihmsen et al. 2010, eq. (16)-(27), their
 * defaults, system/timeStepDict reading and validation (see timestep.h).
 *
 * Invariants after ts_read / ts_validate: every constant positive; the
 * increase constants do not exceed the matching decrease constants, so no
 * observation can ask for an increase and a decrease at once;
 * eta_avg < delta_shock < eta_max (Sec. 3.3, after eq. 27).
 */
#include "timestep/timestep.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define TS_MAX_ITERATIONS 1000

void ts_params_default(ts_params *p)
{
    memset(p, 0, sizeof *p);
    p->mode = TS_ADAPTIVE;
    p->delta_t = 0.0;              /* adaptive: estimated by ts_initial */
    p->delta_t_min = 0.0;          /* none */
    p->delta_t_max = 0.0;          /* none */
    p->iterations = 3;             /* Sec. 3.3: "we limit the number of iterations to three" */
    p->initial_cfl = 0.25;         /* Sec. 3.3: dt = 0.25 h / v0max */
    p->eta_max_factor = 10.0;      /* Sec. 3.3: eta_max = 10 eta_avg */
    p->delta_shock_factor = 5.5;   /* midway in (eta_avg, eta_max), eq. (25) */
    p->increase_factor = 1.002;    /* +0.2 % */
    p->decrease_factor = 0.998;    /* -0.2 % */
    p->increase_force = 0.19;      /* eq. (16) */
    p->increase_max_density = 4.5; /* eq. (17) */
    p->increase_avg_density = 0.9; /* eq. (18) */
    p->increase_velocity = 0.39;   /* eq. (19) */
    p->decrease_force = 0.2;       /* eq. (20) */
    p->decrease_max_density = 5.5; /* eq. (21) */
    p->decrease_avg_density = 1.0; /* eq. (22) */
    p->decrease_velocity = 0.4;    /* eq. (23) */
    p->shock_force = 0.2;          /* eq. (24) */
    p->shock_velocity = 0.25;      /* eq. (24) */
    p->shock_velocity_cfl = 0.45;  /* eq. (27) */
    p->shock_max_ratio = 0.5;      /* not in the paper, see timestep.h */
    p->controller = TS_IHMSEN2010; /* the paper's */
    p->target_iterations = 8;      /* controller cost: doc/timestep-cost.md */
    p->cost_increase_factor = 1.01;
    p->cost_decrease_factor = 0.98;
    p->cost_max_density = 8;
}

/* ---- the keys: one list for reading, writing, checking and tests ---- */

/* name, field, 1 if 0 is allowed (it means "none" or "estimate") */
#define TS_SCALARS(X)                                \
    X("deltaT", delta_t, 1)                          \
    X("deltaTMin", delta_t_min, 1)                   \
    X("deltaTMax", delta_t_max, 1)                   \
    X("initialCFL", initial_cfl, 0)                  \
    X("etaMaxFactor", eta_max_factor, 0)             \
    X("deltaShockFactor", delta_shock_factor, 0)     \
    X("increaseFactor", increase_factor, 0)          \
    X("decreaseFactor", decrease_factor, 0)          \
    X("increaseForce", increase_force, 0)            \
    X("increaseMaxDensity", increase_max_density, 0) \
    X("increaseAvgDensity", increase_avg_density, 0) \
    X("increaseVelocity", increase_velocity, 0)      \
    X("decreaseForce", decrease_force, 0)            \
    X("decreaseMaxDensity", decrease_max_density, 0) \
    X("decreaseAvgDensity", decrease_avg_density, 0) \
    X("decreaseVelocity", decrease_velocity, 0)      \
    X("shockForce", shock_force, 0)                  \
    X("shockVelocity", shock_velocity, 0)            \
    X("shockVelocityCFL", shock_velocity_cfl, 0)     \
    X("shockMaxRatio", shock_max_ratio, 0)           \
    X("targetIterations", target_iterations, 0)      \
    X("costIncreaseFactor", cost_increase_factor, 0) \
    X("costDecreaseFactor", cost_decrease_factor, 0) \
    X("costMaxDensity", cost_max_density, 0)

typedef struct ts_scalar_key {
    const char *name;
    size_t off;
    int zero_ok;
} ts_scalar_key;

#define TS_KEY_ENTRY(name, field, zero_ok) {name, offsetof(ts_params, field), zero_ok},
#define TS_KEY_NAME(name, field, zero_ok)  name,

static const ts_scalar_key scalar_keys[] = {TS_SCALARS(TS_KEY_ENTRY)};
static const char *const key_names[] = {"mode", "controller", "iterations",
                                        TS_SCALARS(TS_KEY_NAME) NULL};
#define NSCALARS (sizeof scalar_keys / sizeof scalar_keys[0])

static double *field(ts_params *p, size_t i) { return (double *)((char *)p + scalar_keys[i].off); }

static double cfield(const ts_params *p, size_t i)
{
    return *(const double *)((const char *)p + scalar_keys[i].off);
}

const char *const *ts_keys(void) { return key_names; }

const char *ts_mode_name(ts_mode m) { return m == TS_CONSTANT ? "constant" : "adaptive"; }

const char *ts_controller_name(ts_controller c) { return c == TS_COST ? "cost" : "ihmsen2010"; }

int ts_param_value(const ts_params *p, const char *key, double *value)
{
    if (strcmp(key, "iterations") == 0) {
        *value = p->iterations;
        return 0;
    }
    for (size_t i = 0; i < NSCALARS; i++)
        if (strcmp(key, scalar_keys[i].name) == 0) {
            *value = cfield(p, i);
            return 0;
        }
    return -1;
}

void ts_write(const ts_params *p, FILE *f)
{
    fprintf(f, "%-19s %s;\n", "mode", ts_mode_name(p->mode));
    fprintf(f, "%-19s %s;\n", "controller", ts_controller_name(p->controller));
    fprintf(f, "%-19s %d;\n", "iterations", p->iterations);
    for (size_t i = 0; i < NSCALARS; i++)
        fprintf(f, "%-19s %.15g;\n", scalar_keys[i].name, cfield(p, i));
}

/* ---- checks ---- */

/* Returns the offending key (why filled) or NULL. */
static const char *reject(char *why, size_t len, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static const char *reject(char *why, size_t len, const char *key, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, len, fmt, ap);
    va_end(ap);
    return key;
}

/* Each increase constant must not exceed its decrease constant. */
static const char *check_pairs(const ts_params *p, char *why, size_t len)
{
    static const struct {
        const char *up, *down;
        size_t up_off, down_off;
        const char *eqs;
    } pairs[] = {
        {"increaseForce", "decreaseForce", offsetof(ts_params, increase_force),
         offsetof(ts_params, decrease_force), "(16) and (20)"},
        {"increaseMaxDensity", "decreaseMaxDensity", offsetof(ts_params, increase_max_density),
         offsetof(ts_params, decrease_max_density), "(17) and (21)"},
        {"increaseAvgDensity", "decreaseAvgDensity", offsetof(ts_params, increase_avg_density),
         offsetof(ts_params, decrease_avg_density), "(18) and (22)"},
        {"increaseVelocity", "decreaseVelocity", offsetof(ts_params, increase_velocity),
         offsetof(ts_params, decrease_velocity), "(19) and (23)"},
    };
    for (size_t i = 0; i < sizeof pairs / sizeof pairs[0]; i++) {
        double up = *(const double *)((const char *)p + pairs[i].up_off);
        double down = *(const double *)((const char *)p + pairs[i].down_off);
        if (up > down)
            return reject(why, len, pairs[i].up,
                          "%g exceeds %s %g: a step could be increased and decreased at once "
                          "(eq. %s)",
                          up, pairs[i].down, down, pairs[i].eqs);
    }
    return NULL;
}

static const char *check(const ts_params *p, double eta_avg, char *why, size_t len)
{
    if (!(eta_avg > 0.0)) return reject(why, len, "eta", "eta_avg = %g must be positive", eta_avg);
    for (size_t i = 0; i < NSCALARS; i++) {
        double v = cfield(p, i);
        if (!(v >= 0.0)) return reject(why, len, scalar_keys[i].name, "%g must not be negative", v);
        if (v == 0.0 && !scalar_keys[i].zero_ok)
            return reject(why, len, scalar_keys[i].name, "must be positive");
    }
    if (p->mode == TS_CONSTANT && !(p->delta_t > 0.0))
        return reject(why, len, "deltaT", "must be positive in constant mode");
    if (p->delta_t_min > 0.0 && p->delta_t_max > 0.0 && !(p->delta_t_min < p->delta_t_max))
        return reject(why, len, "deltaTMin", "%g must be smaller than deltaTMax %g", p->delta_t_min,
                      p->delta_t_max);
    if (p->delta_t > 0.0 && p->delta_t < p->delta_t_min)
        return reject(why, len, "deltaT", "%g is below deltaTMin %g", p->delta_t, p->delta_t_min);
    if (p->delta_t > 0.0 && p->delta_t_max > 0.0 && p->delta_t > p->delta_t_max)
        return reject(why, len, "deltaT", "%g is above deltaTMax %g", p->delta_t, p->delta_t_max);
    if (p->iterations < 1 || p->iterations > TS_MAX_ITERATIONS)
        return reject(why, len, "iterations", "%d must be between 1 and %d", p->iterations,
                      TS_MAX_ITERATIONS);
    if (!(p->eta_max_factor > 1.0))
        return reject(why, len, "etaMaxFactor", "%g must be larger than 1 (eta_max > eta_avg)",
                      p->eta_max_factor);
    double shock = ts_delta_shock(p, eta_avg), eta_max = ts_eta_max(p, eta_avg);
    if (!(shock > eta_avg && shock < eta_max)) /* Sec. 3.3: eta_avg < delta_shock < eta_max */
        return reject(why, len, "deltaShockFactor",
                      "%g must lie strictly between 1 and etaMaxFactor %g "
                      "(eta_avg < delta_shock < eta_max, eq. 25)",
                      p->delta_shock_factor, p->eta_max_factor);
    if (!(p->increase_factor > 1.0))
        return reject(why, len, "increaseFactor", "%g must be larger than 1", p->increase_factor);
    if (!(p->decrease_factor < 1.0))
        return reject(why, len, "decreaseFactor", "%g must be smaller than 1", p->decrease_factor);
    if (!(p->cost_increase_factor > 1.0))
        return reject(why, len, "costIncreaseFactor", "%g must be larger than 1",
                      p->cost_increase_factor);
    if (!(p->cost_decrease_factor < 1.0))
        return reject(why, len, "costDecreaseFactor", "%g must be smaller than 1",
                      p->cost_decrease_factor);
    if (!(p->target_iterations >= 1.0 && p->target_iterations <= TS_MAX_ITERATIONS))
        return reject(why, len, "targetIterations", "%g must be between 1 and %d",
                      p->target_iterations, TS_MAX_ITERATIONS);
    if (p->controller == TS_COST &&
        !(p->cost_max_density >= 1.0 && p->cost_max_density < p->eta_max_factor))
        return reject(why, len, "costMaxDensity",
                      "%g must be at least 1 and below etaMaxFactor %g (a step the iterations "
                      "end at rho_err_max > eta_max would be a shock, eq. 26)",
                      p->cost_max_density, p->eta_max_factor);
    if (!(p->shock_max_ratio < 1.0))
        return reject(why, len, "shockMaxRatio",
                      "%g must be smaller than 1 (a shock must shrink "
                      "the step, or the rolled-back steps repeat)",
                      p->shock_max_ratio);
    return check_pairs(p, why, len);
}

int ts_validate(const ts_params *p, double eta_avg, sl_err *err)
{
    char why[512];
    const char *key = check(p, eta_avg, why, sizeof why);
    if (!key) return 0;
    sl_err_set(err, "keyword '%s': %s", key, why);
    return 1;
}

/* ---- reading ---- */

static void need(int status, const sl_err *err) { dict_need(status, err); }

static void bad_value(const dict *d, const char *key, const char *why)
{
    dict_fatal(d, key, "%s", why);
}

void ts_read(const dict *d, ts_params *p)
{
    sl_err err;
    const char *w;
    long it;
    char why[512];
    ts_params_default(p);
    dict_warn_unknown(d, key_names);
    need(dict_get_word_or(d, "mode", ts_mode_name(p->mode), &w, &err), &err);
    if (strcmp(w, "constant") == 0) p->mode = TS_CONSTANT;
    else if (strcmp(w, "adaptive") == 0) p->mode = TS_ADAPTIVE;
    else {
        snprintf(why, sizeof why, "'%s' is not one of: constant adaptive", w);
        bad_value(d, "mode", why);
    }
    need(dict_get_word_or(d, "controller", ts_controller_name(p->controller), &w, &err), &err);
    if (strcmp(w, "cost") == 0) p->controller = TS_COST;
    else if (strcmp(w, "ihmsen2010") == 0) p->controller = TS_IHMSEN2010;
    else {
        snprintf(why, sizeof why, "'%s' is not one of: ihmsen2010 cost", w);
        bad_value(d, "controller", why);
    }
    if (p->mode == TS_CONSTANT) need(dict_get_scalar(d, "deltaT", &p->delta_t, &err), &err);
    for (size_t i = 0; i < NSCALARS; i++)
        need(dict_get_scalar_or(d, scalar_keys[i].name, *field(p, i), field(p, i), &err), &err);
    need(dict_get_int_or(d, "iterations", p->iterations, &it, &err), &err);
    if (it < 1 || it > TS_MAX_ITERATIONS) {
        snprintf(why, sizeof why, "%ld must be between 1 and %d", it, TS_MAX_ITERATIONS);
        bad_value(d, "iterations", why);
    }
    p->iterations = (int)it;
    /* Every check is relative to eta_avg, so eta_avg = 1 decides them all. */
    const char *key = check(p, 1.0, why, sizeof why);
    if (key) bad_value(d, key, why);
}
