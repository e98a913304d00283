/*
 * ce_setup: reads system/compareExperimentDict, which says which column of
 * the experiment goes with which column of the run and how to judge them:
 *
 *   experiment                  // optional
 *   {
 *       normalised  on;         // columns t* = t sqrt(g/H), p* = p/(rho g H),
 *       length      0.3;        // h* = h/H; then H (m), rho (kg/m^3), g (m/s^2)
 *       density     1000;       // are required
 *       gravity     9.81;
 *       timeShift   0;          // s added to the experiment's times
 *   }
 *   filter      0.01;           // s: moving-average width for pressures
 *   groups
 *   {
 *       heights                 // one plot, one table
 *       {
 *           quantity        height;         // or pressure
 *           functionObject  gauges;         // postProcessing/gauges/<startTime>/<type>.dat
 *           title           "Water heights";
 *           threshold       0.01;           // m (height) or Pa (pressure)
 *           window          (0 2);          // s: errors and peaks (default: all)
 *           plateau         (0.5 1);        // s, pressure only (optional)
 *           summary         yes;            // counted in summary.dat (default
 *                                           // yes; no: e.g. a second reference)
 *           H1 { data H1_m; column height_0; }          // any other keyword:
 *           P2 { data median; column pressure_1;        // a series, which may
 *                band (p2.5 p97.5); window (0 1); }     // override the above
 *       }
 *   }
 */
#include "ce.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "dictionary/dict.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const top_keys[] = {"experiment", "filter", "groups", NULL};
static const char *const exp_keys[] = {"normalised", "length",    "density",
                                       "gravity",    "timeShift", NULL};
static const char *const group_keys[] = {"quantity", "functionObject", "title",   "threshold",
                                         "window",   "plateau",        "summary", NULL};
static const char *const entry_keys[] = {"data",   "column",  "band", "threshold",
                                         "window", "plateau", NULL};

static void need(int status, const sl_err *err) { dict_need(status, err); }

/* Stops with file:line, keyword and the dictionary it sits in. */
static void bad(const dict *d, const char *key, const char *why)
{
    dict_fatal(d, key, "in '%s': %s", dict_name(d), why);
}

/* Warns about the plain (non-dictionary) entries of d not in valid; with
 * series_ok, sub-dictionaries are series and fine. */
static void warn_unknown(const dict *d, const char *const *valid, int series_ok)
{
    for (size_t i = 0; i < dict_size(d); i++) {
        const dict_entry *e = dict_entry_at(d, i);
        const char *key = dict_entry_key(e);
        int known = !strcmp(key, "FoamFile") || (series_ok && dict_entry_dict(e));
        for (size_t k = 0; valid[k] && !known; k++) known = !strcmp(key, valid[k]);
        if (known) continue;
        const char *near = dict_nearest(key, valid);
        sl_warning("%s:%d: unknown keyword '%s' in '%s'%s%s%s", dict_entry_file(e),
                   dict_entry_line(e), key, dict_name(d), near ? "; did you mean '" : "",
                   near ? near : "", near ? "'?" : "");
    }
}

static char *word(const dict *d, const char *key)
{
    const char *w;
    sl_err err;
    need(dict_get_word(d, key, &w, &err), &err);
    return sl_strdup(w);
}

/* (a b) with b > a into out; 0 if the key is absent. */
static int interval(const dict *d, const char *key, double out[2])
{
    double *v;
    size_t n;
    sl_err err;
    if (!dict_has(d, key)) return 0;
    need(dict_get_scalar_list(d, key, &v, &n, &err), &err);
    if (n != 2 || !(v[1] > v[0])) {
        free(v);
        bad(d, key, "must be (start end) in s with end > start");
    }
    out[0] = v[0];
    out[1] = v[1];
    free(v);
    return 1;
}

static void read_entry(ce_entry *e, const dict *d, const dict *g, ce_kind kind)
{
    sl_err err;
    memset(e, 0, sizeof *e);
    warn_unknown(d, entry_keys, 0);
    e->name = sl_strdup(dict_name(d));
    e->data = word(d, "data");
    e->column = word(d, "column");
    if (dict_has(d, "band")) {
        char **w;
        size_t n;
        need(dict_get_word_list(d, "band", &w, &n, &err), &err);
        if (n != 2) {
            dict_free_word_list(w, n);
            bad(d, "band", "must name two columns: (lower upper)");
        }
        e->band[0] = sl_strdup(w[0]);
        e->band[1] = sl_strdup(w[1]);
        dict_free_word_list(w, n);
    }
    /* Threshold, window and plateau: the series' own, else the group's. */
    const dict *src = dict_has(d, "threshold") ? d : g;
    if (!dict_has(src, "threshold"))
        sl_fatal("%s: missing keyword 'threshold' in '%s' (or its group '%s'): the %s above "
                 "which the %s has arrived",
                 dict_file(d), dict_name(d), dict_name(g),
                 kind == CE_HEIGHT ? "height (m)" : "pressure (Pa)",
                 kind == CE_HEIGHT ? "front" : "load");
    need(dict_get_scalar(src, "threshold", &e->threshold, &err), &err);
    e->window[0] = -INFINITY;
    e->window[1] = INFINITY;
    if (!interval(d, "window", e->window)) interval(g, "window", e->window);
    e->plateau[0] = e->plateau[1] = NAN;
    if (!interval(d, "plateau", e->plateau)) interval(g, "plateau", e->plateau);
    if (kind == CE_HEIGHT && isfinite(e->plateau[0]))
        bad(dict_has(d, "plateau") ? d : g, "plateau", "only pressures have a plateau");
    if (kind == CE_HEIGHT && e->band[0]) bad(d, "band", "only pressures have a band");
}

static void read_group(ce_group *g, const dict *d)
{
    sl_err err;
    const char *w;
    memset(g, 0, sizeof *g);
    warn_unknown(d, group_keys, 1);
    g->name = sl_strdup(dict_name(d));
    need(dict_get_word(d, "quantity", &w, &err), &err);
    if (!strcmp(w, "height")) g->kind = CE_HEIGHT;
    else if (!strcmp(w, "pressure")) g->kind = CE_PRESSURE;
    else bad(d, "quantity", "must be height or pressure");
    g->fo = word(d, "functionObject");
    if (strchr(g->fo, '/') || !strcmp(g->fo, ".") || !strcmp(g->fo, ".."))
        bad(d, "functionObject", "must be the name of a function object, not a path");
    need(dict_get_word_or(d, "title", g->name, &w, &err), &err);
    g->title = sl_strdup(w);
    need(dict_get_bool_or(d, "summary", 1, &g->summary, &err), &err);
    for (size_t i = 0; i < dict_size(d); i++)
        if (dict_entry_dict(dict_entry_at(d, i))) g->n++;
    if (g->n == 0)
        sl_fatal("%s: group '%s' has no series (e.g. H1 { data H1_m; column height_0; })",
                 dict_file(d), g->name);
    g->e = sl_calloc(g->n, sizeof *g->e, "series");
    for (size_t i = 0, k = 0; i < dict_size(d); i++) {
        const dict *sub = dict_entry_dict(dict_entry_at(d, i));
        if (sub) read_entry(&g->e[k++], sub, d, g->kind);
    }
}

static void read_experiment(ce_setup *s, const dict *d)
{
    sl_err err;
    if (!d) return;
    warn_unknown(d, exp_keys, 0);
    need(dict_get_bool_or(d, "normalised", 0, &s->normalised, &err), &err);
    need(dict_get_scalar_or(d, "timeShift", 0.0, &s->time_shift, &err), &err);
    if (!s->normalised) return;
    need(dict_get_scalar(d, "length", &s->H, &err), &err);
    need(dict_get_scalar(d, "density", &s->rho, &err), &err);
    need(dict_get_scalar(d, "gravity", &s->g, &err), &err);
    if (!(s->H > 0)) bad(d, "length", "must be positive");
    if (!(s->rho > 0)) bad(d, "density", "must be positive");
    if (!(s->g > 0)) bad(d, "gravity", "must be positive (|g|, m/s^2)");
}

void ce_setup_read(ce_setup *s, const char *path)
{
    sl_err err;
    memset(s, 0, sizeof *s);
    dict *d = dict_read_file(path, &err);
    if (!d) sl_fatal("%s", err.msg);
    s->path = sl_strdup(path);
    warn_unknown(d, top_keys, 0);
    if (dict_has(d, "experiment") && !dict_sub(d, "experiment"))
        bad(d, "experiment", "must be a dictionary { normalised ...; }");
    read_experiment(s, dict_sub(d, "experiment"));
    need(dict_get_scalar_or(d, "filter", 0.0, &s->filter, &err), &err);
    if (s->filter < 0) bad(d, "filter", "must be a width in s, >= 0 (0: no filter)");
    const dict *groups = dict_sub(d, "groups");
    if (!groups) sl_fatal("%s: missing dictionary 'groups' (what to compare)", path);
    for (size_t i = 0; i < dict_size(groups); i++)
        if (dict_entry_dict(dict_entry_at(groups, i))) s->ngrp++;
    if (s->ngrp == 0) sl_fatal("%s: 'groups' holds no group", path);
    s->grp = sl_calloc(s->ngrp, sizeof *s->grp, "groups");
    for (size_t i = 0, k = 0; i < dict_size(groups); i++) {
        const dict_entry *e = dict_entry_at(groups, i);
        if (dict_entry_dict(e)) read_group(&s->grp[k++], dict_entry_dict(e));
        else
            sl_warning("%s:%d: '%s' in 'groups' is not a group dictionary; ignored",
                       dict_entry_file(e), dict_entry_line(e), dict_entry_key(e));
    }
    dict_free(d);
}

void ce_setup_free(ce_setup *s)
{
    for (size_t i = 0; i < s->ngrp; i++) {
        ce_group *g = &s->grp[i];
        for (size_t k = 0; k < g->n; k++) {
            ce_entry *e = &g->e[k];
            free(e->name);
            free(e->data);
            free(e->band[0]);
            free(e->band[1]);
            free(e->column);
        }
        free(g->e);
        free(g->name);
        free(g->title);
        free(g->fo);
    }
    free(s->grp);
    free(s->path);
    memset(s, 0, sizeof *s);
}

double ce_time_scale(const ce_setup *s) { return s->normalised ? sqrt(s->H / s->g) : 1.0; }

double ce_value_scale(const ce_setup *s, ce_kind kind)
{
    if (!s->normalised) return 1.0;
    return kind == CE_HEIGHT ? s->H : s->rho * s->g * s->H;
}
