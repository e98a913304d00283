/*
 * test_timestep: unit tests of the time-step controller (libsrc/timestep),
 * Ihmsen et al. 2010, Sec. 3.3: increase (16)-(19), decrease (20)-(23),
 * shock detection (25)-(27) with the step of (24), the initial step, limits,
 * rollback, reading and validation.  Reads etc/caseDicts/timeStepDict, so it
 * must run from the repository root.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dictionary/dict.h"
#include "timestep/timestep.h"

/* The observations below give (err_avg, err_max, vmax, fmax) positionally;
 * converged and iterating stay 0 unless a test sets them. */
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

#define ETC "etc/caseDicts/timeStepDict"

/* A typical set-up: h = 2 r0 = 0.02 m, eta_avg = 1 %, dt = 1 ms. */
#define H   0.02
#define ETA 0.01
#define DT  1e-3

#define SHOCKS (TS_C25 | TS_C26 | TS_C27)

/* ---- helpers --------------------------------------------------------------- */

static void assert_has(const char *text, const char *part)
{
    if (!text || !strstr(text, part))
        fail_msg("expected '%s' in '%s'", part, text ? text : "(null)");
}

/* |a - b| <= tol (this cmocka has no assert_double_equal) */
#define assert_near(a, b, tol) near_at((a), (b), (tol), #a, __LINE__)

static void near_at(double a, double b, double tol, const char *what, int line)
{
    if (!(fabs(a - b) <= tol)) fail_msg("line %d: %s = %.17g, expected %.17g", line, what, a, b);
}

static ts_params defaults(void)
{
    ts_params p;
    ts_params_default(&p);
    return p;
}

/* A quiet step: all of (16)-(19) hold, nothing else. */
static ts_obs calm(void)
{
    ts_obs o = {.err_avg = 0.1 * ETA, .err_max = 1.0 * ETA, .vmax = 1.0, .fmax = 10.0};
    return o;
}

/* Fmax with sqrt(h / Fmax) = k dt, and vmax with h / vmax = k dt. */
static double force_for(double k) { return H / (k * DT * k * DT); }
static double speed_for(double k) { return H / (k * DT); }

static ts_state fresh(double dt)
{
    ts_state s;
    ts_init(&s, dt);
    return s;
}

static ts_action step(const ts_params *p, ts_state *s, ts_obs o, unsigned *c)
{
    return ts_update(p, s, ETA, H, &o, c);
}

static int rejects(const ts_params *p, double eta_avg, const char *key)
{
    sl_err err = {{0}};
    char want[64];
    if (!ts_validate(p, eta_avg, &err)) return 0;
    snprintf(want, sizeof want, "keyword '%s'", key);
    assert_has(err.msg, want);
    return 1;
}

static dict *parse(const char *text)
{
    sl_err err = {{0}};
    dict *d = dict_parse_string(text, "timeStepDict", &err);
    if (!d) fail_msg("should parse: %s", err.msg);
    return d;
}

/* ---- defaults ---------------------------------------------------------------- */

static void test_defaults_are_the_papers(void **state)
{
    (void)state;
    ts_params p = defaults();
    assert_int_equal(p.mode, TS_ADAPTIVE);
    assert_true(p.delta_t == 0.0 && p.delta_t_min == 0.0 && p.delta_t_max == 0.0);
    assert_int_equal(p.iterations, 3);          /* Sec. 3.3 */
    assert_true(p.initial_cfl == 0.25);         /* Sec. 3.3 */
    assert_true(p.eta_max_factor == 10.0);      /* Sec. 3.3 */
    assert_true(p.increase_factor == 1.002);    /* +0.2 % */
    assert_true(p.decrease_factor == 0.998);    /* -0.2 % */
    assert_true(p.increase_force == 0.19);      /* (16) */
    assert_true(p.increase_max_density == 4.5); /* (17) */
    assert_true(p.increase_avg_density == 0.9); /* (18) */
    assert_true(p.increase_velocity == 0.39);   /* (19) */
    assert_true(p.decrease_force == 0.2);       /* (20) */
    assert_true(p.decrease_max_density == 5.5); /* (21) */
    assert_true(p.decrease_avg_density == 1.0); /* (22) */
    assert_true(p.decrease_velocity == 0.4);    /* (23) */
    assert_true(p.shock_force == 0.2);          /* (24) */
    assert_true(p.shock_velocity == 0.25);      /* (24) */
    assert_true(p.shock_velocity_cfl == 0.45);  /* (27) */
    /* eta_avg < delta_shock < eta_max */
    assert_true(p.delta_shock_factor > 1.0 && p.delta_shock_factor < p.eta_max_factor);
    assert_true(p.shock_max_ratio > 0.0 && p.shock_max_ratio < 1.0);
    sl_err err = {{0}};
    assert_int_equal(ts_validate(&p, ETA, &err), 0);
}

/* The annotated file lists every key, each with the compiled default. */
static void test_defaults_match_etc(void **state)
{
    (void)state;
    sl_err err = {{0}};
    ts_params p = defaults(), r;
    dict *d = dict_read_file(ETC, &err);
    if (!d) fail_msg("%s: %s", ETC, err.msg);
    size_t nkeys = 0;
    for (size_t i = 0; i < dict_size(d); i++) {
        const char *key = dict_entry_key(dict_entry_at(d, i));
        double file, compiled;
        if (!strcmp(key, "FoamFile")) continue;
        nkeys++;
        if (!strcmp(key, "mode") || !strcmp(key, "controller")) {
            const char *w = NULL;
            assert_int_equal(dict_get_word(d, key, &w, &err), 0);
            assert_string_equal(
                w, !strcmp(key, "mode") ? ts_mode_name(p.mode) : ts_controller_name(p.controller));
            continue;
        }
        if (ts_param_value(&p, key, &compiled)) fail_msg("%s: unknown key '%s'", ETC, key);
        if (dict_get_scalar(d, key, &file, &err)) fail_msg("%s", err.msg);
        if (file != compiled)
            fail_msg("%s: %s is %.17g, compiled default %.17g", ETC, key, file, compiled);
    }
    size_t nknown = 0;
    for (const char *const *k = ts_keys(); *k; k++, nknown++)
        if (!dict_has(d, *k)) fail_msg("%s lacks the key '%s'", ETC, *k);
    assert_int_equal(nkeys, nknown);
    /* and ts_read of the file gives the defaults */
    ts_read(d, &r);
    assert_int_equal(r.mode, p.mode);
    assert_int_equal(r.controller, p.controller);
    for (const char *const *k = ts_keys(); *k; k++) {
        double a, b;
        if (!strcmp(*k, "mode") || !strcmp(*k, "controller")) continue;
        assert_int_equal(ts_param_value(&r, *k, &a), 0);
        assert_int_equal(ts_param_value(&p, *k, &b), 0);
        assert_true(a == b);
    }
    dict_free(d);
}

/* ---- increase and decrease --------------------------------------------------- */

static void test_increase_needs_all(void **state)
{
    (void)state;
    ts_params p = defaults();
    unsigned c;
    ts_state s = fresh(DT);
    assert_int_equal(step(&p, &s, calm(), &c), TS_INCREASE);
    assert_int_equal(c, TS_INCREASE_ALL);
    assert_true(s.dt == DT * 1.002);

    /* Each criterion failing alone, in the band between increase and
     * decrease, keeps the step. */
    struct {
        unsigned fails;
        ts_obs o;
    } rows[] = {
        {TS_C16, {0.1 * ETA, 1.0 * ETA, 1.0, force_for(1.0 / 0.195)}},  /* 0.19 < 0.195 < 0.2 */
        {TS_C17, {0.1 * ETA, 5.0 * ETA, 1.0, 10.0}},                    /* 4.5 <= 5 <= 5.5 */
        {TS_C17, {0.1 * ETA, 4.5 * ETA, 1.0, 10.0}},                    /* (17) is strict */
        {TS_C18, {0.95 * ETA, 1.0 * ETA, 1.0, 10.0}},                   /* 0.9 <= 0.95 < 1 */
        {TS_C18, {0.9 * ETA, 1.0 * ETA, 1.0, 10.0}},                    /* (18) is strict */
        {TS_C19, {0.1 * ETA, 1.0 * ETA, speed_for(1.0 / 0.395), 10.0}}, /* 0.39 < 0.395 < 0.4 */
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        s = fresh(DT);
        ts_action a = step(&p, &s, rows[i].o, &c);
        if (a != TS_KEEP || s.dt != DT || c != (TS_INCREASE_ALL & ~rows[i].fails))
            fail_msg("row %zu: action %s, dt %.17g, criteria %#x", i, ts_action_name(a), s.dt, c);
    }
}

static void test_decrease_on_any(void **state)
{
    (void)state;
    ts_params p = defaults();
    struct {
        unsigned holds;
        ts_obs o;
    } rows[] = {
        {TS_C20, {0.1 * ETA, 1.0 * ETA, 1.0, force_for(4.0)}},         /* 0.2 * 4 dt < dt */
        {TS_C21, {0.1 * ETA, 6.0 * ETA, 1.0, 10.0}},                   /* 6 > 5.5 */
        {TS_C22, {1.0 * ETA, 1.0 * ETA, 1.0, 10.0}},                   /* (22) is >= */
        {TS_C23, {0.1 * ETA, 1.0 * ETA, speed_for(1.0 / 0.42), 10.0}}, /* 0.4 < 0.42 < 0.45 */
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        unsigned c;
        ts_state s = fresh(DT);
        ts_action a = step(&p, &s, rows[i].o, &c);
        if (a != TS_DECREASE || s.dt != DT * 0.998 || !(c & rows[i].holds) ||
            (c & TS_DECREASE_ANY) != rows[i].holds || (c & SHOCKS))
            fail_msg("row %zu: action %s, dt %.17g, criteria %#x", i, ts_action_name(a), s.dt, c);
    }
    /* A decrease criterion wins over an otherwise calm step. */
    ts_state s = fresh(DT);
    ts_obs o = calm();
    o.err_max = 5.6 * ETA;
    assert_int_equal(step(&p, &s, o, NULL), TS_DECREASE);
}

/* Without a shock the step never changes by more than 0.2 %. */
static void test_change_bounded(void **state)
{
    (void)state;
    ts_params p = defaults();
    const double errs[] = {0.0, 0.5, 0.9, 1.0, 3.0, 4.5, 5.0, 5.5, 6.0, 9.0, 11.0};
    const double ks[] = {0.1, 0.19, 0.2, 0.3, 0.39, 0.4, 0.45, 0.5, 2.0, 100.0};
    long n = 0, unchanged = 0, up = 0, down = 0;
    for (size_t a = 0; a < 11; a++)
        for (size_t m = 0; m < 11; m++)
            for (size_t v = 0; v < 10; v++)
                for (size_t f = 0; f < 10; f++) {
                    ts_obs o = {errs[a] * ETA, errs[m] * ETA, speed_for(1.0 / ks[v]),
                                force_for(1.0 / ks[f])};
                    ts_state s = fresh(DT);
                    unsigned c;
                    ts_action act = step(&p, &s, o, &c);
                    assert_false((c & TS_INCREASE_ALL) == TS_INCREASE_ALL && (c & TS_DECREASE_ANY));
                    if (act == TS_SHOCK) continue;
                    n++;
                    if (act == TS_KEEP && s.dt == DT) unchanged++;
                    else if (act == TS_INCREASE && s.dt == DT * 1.002) up++;
                    else if (act == TS_DECREASE && s.dt == DT * 0.998) down++;
                    else fail_msg("%s to %.17g (criteria %#x)", ts_action_name(act), s.dt, c);
                }
    assert_true(n > 1000 && unchanged > 0 && up > 0 && down > 0);
}

/* ---- shocks ------------------------------------------------------------------ */

static void test_shock_25_uses_previous_step(void **state)
{
    (void)state;
    ts_params p = defaults(); /* delta_shock = 5.5 eta */
    unsigned c;
    ts_obs o = calm();
    ts_state s = fresh(DT);
    /* Without history there is no (25): 6.1 eta is a decrease by (21). */
    o.err_max = 6.1 * ETA;
    assert_int_equal(step(&p, &s, o, &c), TS_DECREASE);
    assert_int_equal(c & SHOCKS, 0);
    /* 0.5 -> 5.0 -> 9.0 eta: rises of 4.5 and 4, none above 5.5 (8.5 from
     * the first would be): (25) compares with the previous step only. */
    s = fresh(DT);
    o.err_max = 0.5 * ETA;
    step(&p, &s, o, &c);
    assert_true(s.prev_err_max == 0.5 * ETA);
    o.err_max = 5.0 * ETA;
    step(&p, &s, o, &c);
    assert_true(s.prev_err_max == 5.0 * ETA);
    o.err_max = 9.0 * ETA;
    assert_int_equal(step(&p, &s, o, &c), TS_DECREASE);
    assert_int_equal(c & SHOCKS, 0);
    /* 2 -> 7.6 eta: a rise of 5.6 eta > 5.5 eta. No force nor speed: (24)
     * has no finite term, the step halves (shockMaxRatio). */
    o.err_max = 2.0 * ETA;
    step(&p, &s, o, &c);
    double dt = s.dt;
    o = (ts_obs){0.1 * ETA, 7.6 * ETA, 0.0, 0.0};
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_int_equal(c & SHOCKS, TS_C25);
    assert_true(c & TS_LIMIT_RATIO);
    assert_true(s.dt == 0.5 * dt);
    assert_int_equal(s.count.shock, 1);
}

static void test_shock_26_force_branch(void **state)
{
    (void)state;
    ts_params p = defaults();
    unsigned c;
    ts_state s = fresh(DT);
    ts_obs o = calm();
    o.err_max = 9.0 * ETA;
    step(&p, &s, o, &c);
    /* 9 -> 10.5 eta: above eta_max, rise 1.5.  Large force: (24) by force. */
    s.dt = DT;
    o.err_max = 10.5 * ETA;
    o.fmax = force_for(1.5);
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_int_equal(c & SHOCKS, TS_C26);
    assert_true(c & TS_C24_FORCE);
    assert_false(c & (TS_C24_VELOCITY | TS_LIMIT_RATIO));
    assert_near(s.dt, 0.2 * sqrt(H / o.fmax), 1e-18); /* eq. (24) */
    assert_near(s.dt, 0.3 * DT, 1e-15);
}

static void test_shock_27_velocity_branch(void **state)
{
    (void)state;
    ts_params p = defaults();
    unsigned c;
    ts_state s = fresh(DT);
    ts_obs o = calm();
    o.vmax = speed_for(1.0 / 0.6); /* 0.45 h/v = 0.75 dt < dt */
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_int_equal(c & SHOCKS, TS_C27);
    assert_true(c & TS_C24_VELOCITY);
    assert_false(c & (TS_C24_FORCE | TS_LIMIT_RATIO));
    assert_near(s.dt, 0.25 * H / o.vmax, 1e-18); /* eq. (24) */
    /* Zero force: the force term is infinite, not a division by zero. */
    s = fresh(DT);
    o.fmax = 0.0;
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_near(s.dt, 0.25 * H / o.vmax, 1e-18);
}

/* (24) alone would not shrink the step: shockMaxRatio does. */
static void test_shock_ratio_limit(void **state)
{
    (void)state;
    ts_params p = defaults();
    unsigned c;
    ts_state s = fresh(DT);
    ts_obs o = calm(); /* (24) gives min(0.2*4.47, 0.25*20) ms */
    o.err_max = 11.0 * ETA;
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_true(c & TS_LIMIT_RATIO);
    assert_true(s.dt == 0.5 * DT);
    /* A non-finite observation is a shock too. */
    s = fresh(DT);
    o = calm();
    o.err_max = (double)NAN;
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_true(c & TS_NONFINITE);
    assert_true(s.dt == 0.5 * DT);
}

/* ---- snapshot and rollback ------------------------------------------------- */

static const ts_obs sequence[] = {
    {0.1 * ETA, 1.0 * ETA, 1.0, 10.0},    {0.5 * ETA, 3.0 * ETA, 2.0, 50.0},
    {0.95 * ETA, 5.0 * ETA, 3.0, 100.0},  {1.1 * ETA, 5.8 * ETA, 4.0, 800.0},
    {0.3 * ETA, 9.5 * ETA, 5.0, 900.0},   {0.1 * ETA, 1.0 * ETA, 1.0, 10.0},
    {0.1 * ETA, 12.0 * ETA, 9.0, 5000.0}, {0.1 * ETA, 1.0 * ETA, 1.0, 10.0},
};
#define NSEQ (sizeof sequence / sizeof sequence[0])

static void run(const ts_params *p, ts_state *s, ts_action *a, unsigned *c, double *dt)
{
    for (size_t i = 0; i < NSEQ; i++) {
        a[i] = step(p, s, sequence[i], &c[i]);
        dt[i] = s->dt;
    }
}

static void assert_same_state(const ts_state *a, const ts_state *b)
{
    assert_true(a->dt == b->dt && a->prev_err_max == b->prev_err_max);
    assert_int_equal(a->have_prev, b->have_prev);
    assert_int_equal(a->count.steps, b->count.steps);
    assert_int_equal(a->count.keep, b->count.keep);
    assert_int_equal(a->count.increase, b->count.increase);
    assert_int_equal(a->count.decrease, b->count.decrease);
    assert_int_equal(a->count.shock, b->count.shock);
    assert_true(a->count.dt_min == b->count.dt_min && a->count.dt_max == b->count.dt_max);
}

static void test_snapshot_restore(void **state)
{
    (void)state;
    ts_params p = defaults();
    ts_state s = fresh(DT);
    ts_action a1[NSEQ], a2[NSEQ];
    unsigned c1[NSEQ], c2[NSEQ];
    double dt1[NSEQ], dt2[NSEQ];
    step(&p, &s, sequence[1], NULL); /* some history */
    ts_state snap = s;
    run(&p, &s, a1, c1, dt1);
    ts_state end1 = s;
    s = snap;
    run(&p, &s, a2, c2, dt2);
    int shocks = 0;
    for (size_t i = 0; i < NSEQ; i++) {
        assert_int_equal(a1[i], a2[i]);
        assert_int_equal(c1[i], c2[i]);
        assert_true(dt1[i] == dt2[i]);
        shocks += a1[i] == TS_SHOCK;
    }
    assert_true(shocks > 0); /* the sequence exercises the history */
    assert_same_state(&s, &end1);
}

/* The solver's use: snapshot per step, on a shock go two steps back. */
static void test_rollback(void **state)
{
    (void)state;
    ts_params p = defaults();
    unsigned c;
    ts_state s = fresh(DT);
    step(&p, &s, calm(), NULL);
    ts_obs o = calm();
    o.err_max = 3.0 * ETA;
    ts_state two_back = s; /* start of step t - dt */
    step(&p, &s, o, NULL);
    step(&p, &s, calm(), NULL);
    o = calm();
    o.vmax = speed_for(1.0 / 0.6);
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    double dt_new = s.dt;
    ts_rollback(&s, &two_back);
    assert_true(s.dt == dt_new);                          /* the new step */
    assert_true(s.prev_err_max == two_back.prev_err_max); /* history of that time */
    assert_int_equal(s.have_prev, two_back.have_prev);
    assert_int_equal(s.count.shock, 1); /* the run's counts */
    assert_int_equal(s.count.steps, two_back.count.steps + 3);
    /* Resuming behaves as from the snapshot with the new step. */
    ts_state ref = two_back;
    ref.dt = dt_new;
    o = calm();
    o.err_max = 1.0 * ETA + 5.6 * ETA; /* rise from 1 eta (snapshot's last) */
    unsigned c1, c2;
    ts_action a1 = step(&p, &s, o, &c1), a2 = step(&p, &ref, o, &c2);
    assert_int_equal(a1, a2);
    assert_int_equal(c1, c2);
    assert_true(c1 & TS_C25);
    assert_true(s.dt == ref.dt);
}

/* ---- initial step -------------------------------------------------------------- */

static void test_initial_step(void **state)
{
    (void)state;
    ts_params p = defaults();
    char rule[256];
    /* Moving fluid, no gravity: the paper's 0.25 h / v0max. */
    assert_near(ts_initial(&p, H, 2.0, 0.0, 0.0, rule, sizeof rule), 0.25 * H / 2.0, 1e-18);
    assert_has(rule, "eq. (14)");
    /* Fast fluid with gravity: still the paper's rule (the smallest). */
    assert_near(ts_initial(&p, H, 10.0, 9.81, 0.5, rule, sizeof rule), 0.25 * H / 10.0, 1e-18);
    assert_has(rule, "eq. (14)");
    /* At rest: the free-fall speed over the fluid's height. */
    double v = sqrt(2.0 * 9.81 * 0.5);
    assert_near(ts_initial(&p, H, 0.0, 9.81, 0.5, rule, sizeof rule), 0.25 * H / v, 1e-18);
    assert_has(rule, "free fall");
    assert_has(rule, "at rest");
    /* At rest, no height: eq. (16) with F = |g|. */
    assert_near(ts_initial(&p, H, 0.0, 9.81, 0.0, rule, sizeof rule), 0.19 * sqrt(H / 9.81), 1e-18);
    assert_has(rule, "eq. (16)");
    /* Slow fluid: gravity bounds the paper's (huge) step. */
    assert_near(ts_initial(&p, H, 1e-6, 9.81, 0.0, rule, sizeof rule), 0.19 * sqrt(H / 9.81),
                1e-18);
    /* At rest without gravity: no time scale. */
    assert_true(ts_initial(&p, H, 0.0, 0.0, 0.5, rule, sizeof rule) == 0.0);
    assert_has(rule, "no time scale");
    p.delta_t_max = 2e-3;
    assert_true(ts_initial(&p, H, 0.0, 0.0, 0.5, rule, sizeof rule) == 2e-3);
    /* Limits. */
    p.delta_t_max = 1e-4;
    assert_true(ts_initial(&p, H, 0.0, 9.81, 0.5, rule, sizeof rule) == 1e-4);
    assert_has(rule, "deltaTMax");
    p.delta_t_max = 0.0;
    p.delta_t_min = 0.01;
    assert_true(ts_initial(&p, H, 0.0, 9.81, 0.5, rule, sizeof rule) == 0.01);
    assert_has(rule, "deltaTMin");
    /* deltaT given. */
    p = defaults();
    p.delta_t = 3e-4;
    assert_true(ts_initial(&p, H, 2.0, 9.81, 0.5, rule, sizeof rule) == 3e-4);
    p.mode = TS_CONSTANT;
    assert_true(ts_initial(&p, H, 2.0, 9.81, 0.5, rule, sizeof rule) == 3e-4);
    assert_has(rule, "constant");
}

/* ---- limits and constant mode ------------------------------------------------- */

static void test_limits(void **state)
{
    (void)state;
    ts_params p = defaults();
    unsigned c;
    p.delta_t_max = 1.001 * DT;
    ts_state s = fresh(DT);
    assert_int_equal(step(&p, &s, calm(), &c), TS_INCREASE);
    assert_true(s.dt == p.delta_t_max);
    assert_true(c & TS_LIMIT_MAX);
    assert_int_equal(step(&p, &s, calm(), &c), TS_KEEP);
    assert_true(s.dt == p.delta_t_max);
    assert_true(c & TS_LIMIT_MAX);
}

static void test_too_small(void **state)
{
    (void)state;
    ts_params p = defaults();
    unsigned c;
    ts_obs o = calm();
    o.err_max = 6.0 * ETA; /* (21): decrease */
    p.delta_t_min = 0.9985 * DT;
    ts_state s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_TOO_SMALL);
    assert_true(c & TS_C21);
    assert_true(s.dt < p.delta_t_min);
    p.delta_t_min = 0.997 * DT;
    s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_DECREASE);
    /* a shock below deltaTMin */
    p.delta_t_min = 0.6 * DT;
    s = fresh(DT);
    o.err_max = 11.0 * ETA;
    assert_int_equal(step(&p, &s, o, &c), TS_TOO_SMALL);
    assert_true(c & TS_C26);
    assert_string_equal(ts_action_name(TS_TOO_SMALL), "tooSmall");
}

static void test_constant_mode(void **state)
{
    (void)state;
    ts_params pa = defaults(), pc = defaults();
    pc.mode = TS_CONSTANT;
    pc.delta_t = DT;
    ts_state base = fresh(DT);
    for (size_t i = 0; i < NSEQ; i++) {
        unsigned ca, cc;
        ts_state sa = base, sc = base; /* same dt and history */
        step(&pa, &sa, sequence[i], &ca);
        ts_action a = step(&pc, &sc, sequence[i], &cc);
        assert_int_equal(a, TS_KEEP);
        assert_true(sc.dt == DT);
        /* the same criteria, without the flags of how the step would change */
        unsigned how = TS_C24_FORCE | TS_C24_VELOCITY | TS_LIMIT_RATIO | TS_LIMIT_MAX;
        assert_int_equal(cc, ca & ~how);
        base = sc;
    }
    assert_int_equal(base.count.keep, (long)NSEQ);
    assert_int_equal(base.count.shock + base.count.increase + base.count.decrease, 0);
}

/* The actions that end a run, and why. */
static void test_run_ending_actions(void **state)
{
    (void)state;
    ts_params pc = defaults(), pa = defaults();
    pc.mode = TS_CONSTANT;
    pc.delta_t = DT;
    unsigned c;
    ts_state s = fresh(DT);
    ts_obs o = calm();
    o.err_avg = 11.0 * ETA; /* constant mode: the average beyond eta_max */
    assert_int_equal(step(&pc, &s, o, &c), TS_NOT_CONVERGING);
    o = calm();
    o.err_avg = 1.5 * ETA; /* iterating to convergence and not reaching eta */
    o.iterating = 1;
    s = fresh(DT);
    assert_int_equal(step(&pc, &s, o, &c), TS_NOT_CONVERGING);
    o.converged = 1; /* ... or reaching it */
    s = fresh(DT);
    assert_int_equal(step(&pc, &s, o, &c), TS_KEEP);
    o = calm();
    o.vmax = (double)INFINITY; /* constant mode has no shock to go back from */
    s = fresh(DT);
    assert_int_equal(step(&pc, &s, o, &c), TS_DIVERGED);
    s = fresh(1e-14); /* adaptive: a shock that leaves no step */
    o = calm();
    o.err_max = 11.0 * ETA;
    assert_int_equal(step(&pa, &s, o, &c), TS_SHOCK_STORM);
    const ts_action ends[] = {TS_TOO_SMALL, TS_DIVERGED, TS_NOT_CONVERGING, TS_SHOCK_STORM};
    for (size_t k = 0; k < 4; k++) assert_non_null(ts_failure(ends[k]));
    const ts_action goes_on[] = {TS_KEEP, TS_INCREASE, TS_DECREASE, TS_SHOCK};
    for (size_t k = 0; k < 4; k++) assert_null(ts_failure(goes_on[k]));
}

/* ---- reading and validation ---------------------------------------------------- */

static void test_read_overrides(void **state)
{
    (void)state;
    ts_params p;
    dict *d = parse("mode constant; deltaT 0.002; increaseForce 0.18; iterations 5;\n"
                    "deltaShockFactor 3; etaMaxFactor 8; deltaTMax 0.01; shockMaxRatio 0.3;");
    ts_read(d, &p);
    dict_free(d);
    assert_int_equal(p.mode, TS_CONSTANT);
    assert_true(p.delta_t == 0.002 && p.increase_force == 0.18 && p.delta_shock_factor == 3.0);
    assert_true(p.eta_max_factor == 8.0 && p.delta_t_max == 0.01 && p.shock_max_ratio == 0.3);
    assert_int_equal(p.iterations, 5);
    assert_true(p.decrease_force == 0.2); /* untouched: the default */
    d = parse("mode adaptive;");
    ts_read(d, &p);
    dict_free(d);
    assert_int_equal(p.mode, TS_ADAPTIVE);
    assert_true(p.delta_t == 0.0);
    /* ts_write then ts_read gives the same parameters. */
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    ts_params q = defaults(), r;
    q.controller = TS_COST;
    q.target_iterations = 6.5;
    q.increase_velocity = 0.37;
    q.delta_t_min = 1e-7;
    ts_write(&q, f);
    fclose(f);
    d = parse(text);
    free(text);
    ts_read(d, &r);
    dict_free(d);
    assert_int_equal(r.controller, q.controller);
    for (const char *const *k = ts_keys(); *k; k++) {
        double a, b;
        if (!strcmp(*k, "mode") || !strcmp(*k, "controller")) continue;
        ts_param_value(&q, *k, &a);
        ts_param_value(&r, *k, &b);
        if (a != b) fail_msg("%s: wrote %.17g, read %.17g", *k, a, b);
    }
}

static void test_validate_rejects(void **state)
{
    (void)state;
    ts_params p;
#define BAD(field, value, key)                                                          \
    do {                                                                                \
        p = defaults();                                                                 \
        p.field = value;                                                                \
        if (!rejects(&p, ETA, key)) fail_msg("%s = %g accepted", key, (double)(value)); \
    } while (0)
    BAD(increase_force, -0.19, "increaseForce");
    BAD(shock_force, 0.0, "shockForce");
    BAD(decrease_max_density, -1.0, "decreaseMaxDensity");
    BAD(delta_t_min, -1e-3, "deltaTMin");
    BAD(initial_cfl, 0.0, "initialCFL");
    BAD(delta_shock_factor, 0.5, "deltaShockFactor");  /* below eta_avg */
    BAD(delta_shock_factor, 1.0, "deltaShockFactor");  /* strictly */
    BAD(delta_shock_factor, 10.0, "deltaShockFactor"); /* strictly */
    BAD(delta_shock_factor, 12.0, "deltaShockFactor"); /* above eta_max */
    BAD(eta_max_factor, 4.0, "deltaShockFactor");      /* 5.5 > eta_max */
    BAD(eta_max_factor, 1.0, "etaMaxFactor");
    BAD(increase_factor, 0.99, "increaseFactor");
    BAD(decrease_factor, 1.0, "decreaseFactor");
    BAD(shock_max_ratio, 1.0, "shockMaxRatio");
    BAD(shock_max_ratio, 0.0, "shockMaxRatio");
    BAD(iterations, 0, "iterations");
    BAD(increase_force, 0.25, "increaseForce");       /* > decreaseForce */
    BAD(increase_velocity, 0.41, "increaseVelocity"); /* > decreaseVelocity */
    BAD(increase_avg_density, 1.1, "increaseAvgDensity");
    BAD(increase_max_density, 6.0, "increaseMaxDensity");
    BAD(delta_t, (double)NAN, "deltaT");
    BAD(mode, TS_CONSTANT, "deltaT"); /* constant mode needs deltaT */
    BAD(target_iterations, 0.5, "targetIterations");
    BAD(target_iterations, 2000.0, "targetIterations");
    BAD(cost_increase_factor, 1.0, "costIncreaseFactor");
    BAD(cost_decrease_factor, 1.0, "costDecreaseFactor");
#undef BAD
#define BAD(field, value, key)                                                          \
    do {                                                                                \
        p = defaults();                                                                 \
        p.controller = TS_COST;                                                         \
        p.field = value;                                                                \
        if (!rejects(&p, ETA, key)) fail_msg("%s = %g accepted", key, (double)(value)); \
    } while (0)
    BAD(cost_max_density, 10.0, "costMaxDensity"); /* = etaMaxFactor: a shock */
    BAD(cost_max_density, 0.5, "costMaxDensity");
    p = defaults(); /* checked with controller cost only */
    p.cost_max_density = 10.0;
    assert_false(rejects(&p, ETA, "costMaxDensity"));
#undef BAD
    p = defaults();
    p.delta_t_min = 1e-3;
    p.delta_t_max = 1e-3;
    assert_true(rejects(&p, ETA, "deltaTMin"));
    p.delta_t_max = 1e-2;
    p.delta_t = 1e-4;
    assert_true(rejects(&p, ETA, "deltaT"));
    p.delta_t = 1e-1;
    assert_true(rejects(&p, ETA, "deltaT"));
    p.delta_t = 5e-3;
    assert_false(rejects(&p, ETA, "deltaT"));
    p = defaults();
    assert_true(rejects(&p, 0.0, "eta"));
    assert_true(rejects(&p, -0.01, "eta"));
    p.delta_shock_factor = 9.99;
    assert_false(rejects(&p, ETA, "deltaShockFactor"));
    p.delta_shock_factor = 1.01;
    assert_false(rejects(&p, ETA, "deltaShockFactor"));
}

/* ---- controller cost ------------------------------------------------------------ */

static ts_params cost_params(void)
{
    ts_params p = defaults();
    p.controller = TS_COST;
    return p;
}

/* A step that reached eta with k iterations, far from (16) and (19). */
static ts_obs cost_obs(int k)
{
    ts_obs o = calm();
    o.converged = o.iterating = 1;
    o.iterations = k;
    return o;
}

/* Fewer iterations than the target: dt grows by costIncreaseFactor; more:
 * it shrinks by costDecreaseFactor; exactly the target: kept. */
static void test_cost_steers_by_iterations(void **state)
{
    (void)state;
    ts_params p = cost_params();
    assert_true(p.target_iterations == 8.0 && p.cost_increase_factor == 1.01 &&
                p.cost_decrease_factor == 0.98 && p.cost_max_density == 8.0);
    unsigned c;
    ts_state s = fresh(DT);
    assert_int_equal(step(&p, &s, cost_obs(3), &c), TS_INCREASE);
    assert_near(s.dt, 1.01 * DT, 1e-18);
    assert_true(c & TS_COST_FEWER);
    s = fresh(DT);
    assert_int_equal(step(&p, &s, cost_obs(12), &c), TS_DECREASE);
    assert_near(s.dt, 0.98 * DT, 1e-18);
    assert_true(c & TS_COST_MORE);
    s = fresh(DT);
    assert_int_equal(step(&p, &s, cost_obs(8), &c), TS_KEEP);
    assert_true(s.dt == DT);
    /* the paper's 3-iteration rule would decrease here ((22) avg >= eta):
     * the cost controller only looks at what the iterations reached */
    ts_obs o = cost_obs(3);
    o.err_avg = ETA;
    s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_INCREASE);
    assert_true(c & TS_C22);
    /* the same observation, the paper's controller: decrease */
    ts_params q = defaults();
    s = fresh(DT);
    assert_int_equal(step(&q, &s, o, &c), TS_DECREASE);
    /* steering settles: k(dt) = 16 dt / DT iterations (more for a larger
     * step) brings dt up to the steps that need the target, 0.4375-0.5 DT */
    s = fresh(0.1 * DT);
    for (int i = 0; i < 1000; i++) step(&p, &s, cost_obs((int)ceil(16.0 * s.dt / DT)), &c);
    assert_true(s.dt > 0.43 * DT && s.dt <= 0.5 * DT);
}

/* The next step never exceeds (19) increaseVelocity h / vmax, (16)
 * increaseForce sqrt(h / Fmax) or deltaTMax. */
static void test_cost_limits(void **state)
{
    (void)state;
    ts_params p = cost_params();
    unsigned c;
    ts_obs o = cost_obs(3);
    o.vmax = speed_for(1.0 / 0.39 * 1.005); /* 0.39 h / vmax = 1.005 dt: below 1.01 dt */
    ts_state s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_INCREASE);
    assert_near(s.dt, 1.005 * DT, 1e-15);
    assert_true(c & TS_COST_LIMIT);
    o = cost_obs(3);
    o.fmax = force_for(0.5 / 0.19); /* 0.19 sqrt(h / Fmax) = 0.5 dt: a cut to half */
    s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_DECREASE);
    assert_near(s.dt, 0.5 * DT, 1e-15);
    p.delta_t_max = DT;
    s = fresh(DT);
    assert_int_equal(step(&p, &s, cost_obs(3), &c), TS_KEEP);
    assert_true(s.dt == DT && (c & TS_COST_LIMIT));
    p.delta_t_max = 0.0;
    p.delta_t_min = 0.99 * DT; /* costDecreaseFactor 0.98 goes below it */
    s = fresh(DT);
    assert_int_equal(step(&p, &s, cost_obs(20), &c), TS_TOO_SMALL);
}

/* A step whose average stayed above eta is a shock (back two steps, eq. 24);
 * one whose largest stayed above costMaxDensity eta is kept with a 5-fold
 * decrease; (25)-(27) are shocks as in the paper. */
static void test_cost_shocks(void **state)
{
    (void)state;
    ts_params p = cost_params();
    unsigned c;
    ts_obs o = cost_obs(50);
    o.err_avg = 1.2 * ETA;
    o.converged = 0;
    ts_state s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_true(c & TS_COST_ABOVE);
    assert_near(s.dt, 0.5 * DT, 1e-18); /* shockMaxRatio: (24) gives more here */
    o = cost_obs(50);
    o.err_max = 8.5 * ETA;
    o.converged = 0;
    s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_DECREASE);
    assert_true(c & TS_COST_SHORT);
    assert_near(s.dt, pow(0.98, 5) * DT, 1e-15);
    o = cost_obs(3);
    o.err_max = 1.0 * ETA;
    s = fresh(DT);
    step(&p, &s, o, &c);
    o.err_max = 7.0 * ETA; /* rose by 6 eta > deltaShockFactor 5.5 eta: (25) */
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    assert_true(c & TS_C25);
    o = cost_obs(3);
    o.vmax = speed_for(1.0 / 0.45 * 0.9); /* 0.45 h / vmax < dt: (27) */
    s = fresh(DT);
    assert_int_equal(step(&p, &s, o, &c), TS_SHOCK);
    /* the controller's state is its ts_state: a copy restores it exactly */
    s = fresh(DT);
    step(&p, &s, cost_obs(3), &c);
    ts_state snap = s;
    step(&p, &s, cost_obs(20), &c);
    s = snap;
    ts_state again = snap;
    assert_int_equal(step(&p, &s, cost_obs(20), &c), step(&p, &again, cost_obs(20), &c));
    assert_true(s.dt == again.dt);
    char buf[256];
    ts_criteria_text(&p, TS_COST_FEWER | TS_C22 | TS_COST_LIMIT, buf, sizeof buf);
    assert_string_equal(buf,
                        "cost: fewer iterations than targetIterations 8; cost: limited by "
                        "(16), (19) or deltaTMax");
}

/* controller: ihmsen2010 (default) or cost; anything else names the key. */
static void test_cost_read(void **state)
{
    (void)state;
    ts_params p;
    dict *d = parse("mode adaptive; controller cost; targetIterations 6;");
    ts_read(d, &p);
    dict_free(d);
    assert_int_equal(p.controller, TS_COST);
    assert_true(ts_is_cost(&p) && p.target_iterations == 6.0);
    d = parse("mode constant; deltaT 0.001; controller cost;");
    ts_read(d, &p);
    dict_free(d);
    assert_false(ts_is_cost(&p)); /* constant mode: the step is deltaT */
    d = parse("mode adaptive;");
    ts_read(d, &p);
    dict_free(d);
    assert_int_equal(p.controller, TS_IHMSEN2010);
    assert_string_equal(ts_controller_name(TS_COST), "cost");
    assert_string_equal(ts_controller_name(TS_IHMSEN2010), "ihmsen2010");
}

/* ---- text for the log ---------------------------------------------------------- */

static void test_text(void **state)
{
    (void)state;
    ts_params p = defaults();
    char buf[512];
    ts_criteria_text(&p, TS_C21 | TS_C16 | TS_C18 | TS_C19, buf, sizeof buf);
    assert_string_equal(buf, "(21) rho_err_max > 5.5 eta_avg");
    ts_criteria_text(&p, TS_INCREASE_ALL & ~TS_C17, buf, sizeof buf);
    assert_string_equal(buf, "not (17) rho_err_max < 4.5 eta_avg");
    ts_criteria_text(&p, TS_INCREASE_ALL, buf, sizeof buf);
    assert_string_equal(buf, "(16)-(19) all hold");
    ts_criteria_text(&p, TS_C26 | TS_C27 | TS_C21 | TS_C24_FORCE, buf, sizeof buf);
    assert_string_equal(buf,
                        "(26) rho_err_max > eta_max = 10 eta_avg; (27) 0.45 h/vmax < dt; "
                        "dt_new = 0.2 sqrt(h/Fmax) (24)");
    ts_criteria_text(&p, TS_C25 | TS_LIMIT_RATIO, buf, sizeof buf);
    assert_has(buf, "(25)");
    assert_has(buf, "shockMaxRatio");
    char tiny[8];
    ts_criteria_text(&p, TS_C20 | TS_C21 | TS_C22 | TS_C23, tiny, sizeof tiny);
    assert_int_equal(strlen(tiny), sizeof tiny - 1);
    assert_string_equal(ts_action_name(TS_SHOCK), "shock");
    assert_string_equal(ts_action_name(TS_INCREASE), "increase");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_are_the_papers),
        cmocka_unit_test(test_defaults_match_etc),
        cmocka_unit_test(test_increase_needs_all),
        cmocka_unit_test(test_decrease_on_any),
        cmocka_unit_test(test_change_bounded),
        cmocka_unit_test(test_shock_25_uses_previous_step),
        cmocka_unit_test(test_shock_26_force_branch),
        cmocka_unit_test(test_shock_27_velocity_branch),
        cmocka_unit_test(test_shock_ratio_limit),
        cmocka_unit_test(test_snapshot_restore),
        cmocka_unit_test(test_rollback),
        cmocka_unit_test(test_initial_step),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_too_small),
        cmocka_unit_test(test_constant_mode),
        cmocka_unit_test(test_run_ending_actions),
        cmocka_unit_test(test_read_overrides),
        cmocka_unit_test(test_validate_rejects),
        cmocka_unit_test(test_cost_steers_by_iterations),
        cmocka_unit_test(test_cost_limits),
        cmocka_unit_test(test_cost_shocks),
        cmocka_unit_test(test_cost_read),
        cmocka_unit_test(test_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
