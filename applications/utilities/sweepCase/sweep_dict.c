/*
 * sweep_dict: reads a sweep dictionary (syntax in sweep.h) into the list
 * of points and their case names.
 */
#include "sweep.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "case/case.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "dictionary/dict.h"

static const char *const sweep_keys[] = {"baseCase", "combine", "parameters", "results", NULL};

/* ---- values -------------------------------------------------------------------- */

/* Splits the text of a list "(a (1 2) \"b c\")" into its top-level
 * elements; a value that is not a list is one element. */
static char **sweep_split(const char *text, size_t *n)
{
    char **out = NULL;
    size_t len = strlen(text), i = 0, end = len;
    *n = 0;
    while (i < len && isdigit((unsigned char)text[i])) i++; /* "3(...)" */
    if (i < len && text[i] == '(' && text[len - 1] == ')') {
        i++;
        end = len - 1;
    } else {
        i = 0;
    }
    while (i < end) {
        size_t from;
        int depth = 0, quoted = 0;
        while (i < end && isspace((unsigned char)text[i])) i++;
        if (i >= end) break;
        from = i;
        for (; i < end; i++) {
            char c = text[i];
            if (quoted) {
                if (c == '\\' && i + 1 < end) i++;
                else if (c == '"') quoted = 0;
            } else if (c == '"') {
                quoted = 1;
            } else if (c == '(' || c == '[' || c == '{') {
                depth++;
            } else if (c == ')' || c == ']' || c == '}') {
                depth--;
            } else if (depth == 0 && isspace((unsigned char)c)) {
                break;
            }
        }
        out = sl_realloc(out, (*n + 1) * sizeof *out, "sweep values");
        out[*n] = sl_malloc(i - from + 1, "a sweep value");
        memcpy(out[*n], text + from, i - from);
        out[*n][i - from] = '\0';
        ++*n;
    }
    return out;
}

/* Keeps [A-Za-z0-9.+-], turns runs of anything else into one '_'. */
static void sweep_safe(const char *in, char *out, size_t len)
{
    size_t o = 0;
    for (const char *c = in; *c && o + 1 < len; c++) {
        if (isalnum((unsigned char)*c) || strchr(".+-", *c)) out[o++] = *c;
        else if (o > 0 && out[o - 1] != '_') out[o++] = '_';
    }
    while (o > 0 && out[o - 1] == '_') o--;
    if (o == 0) out[o++] = 'v';
    out[o] = '\0';
}

/* ---- parameters ------------------------------------------------------------------- */

/* Splits key into the file of the base case it starts with and the entry. */
static void sweep_locate(const sweep *s, sweep_param *p)
{
    for (char *slash = strchr(p->key, '/'); slash; slash = strchr(slash + 1, '/')) {
        *slash = '\0';
        char *path = cf_join(s->base, p->key);
        int file = cf_is_file(path);
        free(path);
        if (file && slash[1]) {
            p->file = sl_strdup(p->key);
            p->entry = sl_strdup(slash + 1);
        }
        *slash = '/';
        if (file) break;
    }
    if (!p->file)
        sl_fatal("%s:%d: parameter '%s' names no file of the base case %s: write it as "
                 "\"<file>/<entry>\", e.g. \"constant/fluidProperties/eta\"",
                 s->path, p->line, p->key, s->base);
}

/* The top-level keys the solver reads from `file` of a case, or NULL. */
static const char *const *sweep_known_keys(const char *file)
{
    for (const dict_key_home *h = case_key_homes(); h->where; h++)
        if (!strcmp(h->where, file)) return h->keys;
    return NULL;
}

static int sweep_in(const char *key, const char *const *keys)
{
    for (size_t i = 0; keys && keys[i]; i++)
        if (!strcmp(key, keys[i])) return 1;
    return 0;
}

/* The keys of d (may be NULL) and `known` (may be NULL), NULL-terminated;
 * free() the array. */
static const char **sweep_candidates(const dict *d, const char *const *known)
{
    size_t nk = 0, nd = dict_size(d), n = 0;
    while (known && known[nk]) nk++;
    const char **c = sl_malloc((nk + nd + 1) * sizeof *c, "sweep keys");
    for (size_t i = 0; i < nk; i++) c[n++] = known[i];
    for (size_t i = 0; i < nd; i++) c[n++] = dict_entry_key(dict_entry_at(d, i));
    c[n] = NULL;
    return c;
}

/* An entry that is not in the base case: a key the solver knows (left at
 * its default there) is added to each case; a misspelt one would give a
 * sweep of identical points, so it stops the sweep before anything runs,
 * naming the nearest key of the file (or of its dictionary). */
static void sweep_check_missing(const sweep *s, const sweep_param *p, const dict *d,
                                const char *path)
{
    const char *slash = strrchr(p->entry, '/'), *last = slash ? slash + 1 : p->entry;
    char *parent = sl_strdup(p->entry);
    parent[slash ? slash - p->entry : 0] = '\0';
    const dict *in = slash ? dict_sub(d, parent) : d;
    const char *const *known = slash ? NULL : sweep_known_keys(p->file);
    const char **cand = sweep_candidates(in, known);
    const char *near = dict_nearest(last, cand);
    if (known && sweep_in(last, known))
        sl_info("%s:%d: '%s' is not in %s (the default is used there): it is added to each case",
                s->path, p->line, p->entry, path);
    else if (known || near)
        sl_fatal("%s:%d: parameter '%s': '%s' is not a keyword of %s%s%s%s%s%s (nothing was run)",
                 s->path, p->line, p->key, last, p->file, slash ? "/" : "", slash ? parent : "",
                 near ? "; did you mean '" : "", near ? near : "", near ? "'?" : "");
    else
        sl_warning("%s:%d: '%s' is not in %s: it will be added to each case", s->path, p->line,
                   p->entry, path);
    free(cand);
    free(parent);
}

static void sweep_check_entry(const sweep *s, const sweep_param *p)
{
    char *path = cf_join(s->base, p->file);
    sl_err err;
    dict *d = dict_read_file(path, &err);
    if (!d) sl_fatal("%s", err.msg);
    if (!dict_lookup(d, p->entry)) sweep_check_missing(s, p, d, path);
    dict_free(d);
    free(path);
}

static void sweep_read_param(sweep *s, const dict_entry *e, sweep_param *p)
{
    char *text = dict_entry_value_text(e);
    p->key = sl_strdup(dict_entry_key(e));
    p->line = dict_entry_line(e);
    if (dict_entry_dict(e))
        sl_fatal("%s:%d: parameter '%s': expected a list of values, found a dictionary", s->path,
                 p->line, p->key);
    p->value = sweep_split(text, &p->nvalue);
    free(text);
    if (p->nvalue == 0) sl_fatal("%s:%d: parameter '%s' has no values", s->path, p->line, p->key);
    sweep_locate(s, p);
    sweep_check_entry(s, p);
}

static int sweep_label_taken(const sweep *s, size_t upto, const char *label)
{
    for (size_t i = 0; i < upto; i++)
        if (!strcmp(s->param[i].label, label)) return 1;
    return 0;
}

/* The last part of the entry ("alpha"), else the whole entry path, else
 * file and entry, whichever is first unique. */
static void sweep_label(sweep *s, size_t k)
{
    sweep_param *p = &s->param[k];
    const char *last = strrchr(p->entry, '/');
    char buf[512];
    sweep_safe(last ? last + 1 : p->entry, buf, sizeof buf);
    if (sweep_label_taken(s, k, buf)) sweep_safe(p->entry, buf, sizeof buf);
    if (sweep_label_taken(s, k, buf)) sweep_safe(p->key, buf, sizeof buf);
    p->label = sl_strdup(buf);
}

static void sweep_read_params(sweep *s, const dict *d)
{
    const dict *pd = dict_sub(d, "parameters");
    if (!pd)
        sl_fatal("%s: missing required dictionary 'parameters' (\"<file>/<entry>\" (values);)",
                 s->path);
    s->nparam = dict_size(pd);
    if (s->nparam == 0) sl_fatal("%s: 'parameters' is empty", s->path);
    s->param = sl_calloc(s->nparam, sizeof *s->param, "sweep parameters");
    for (size_t k = 0; k < s->nparam; k++) {
        sweep_read_param(s, dict_entry_at(pd, k), &s->param[k]);
        sweep_label(s, k);
    }
}

/* ---- results ------------------------------------------------------------------------- */

static void sweep_read_results(sweep *s, const dict *d)
{
    char **list;
    size_t n;
    sl_err err;
    if (!dict_has(d, "results")) return;
    if (dict_get_word_list(d, "results", &list, &n, &err)) sl_fatal("%s", err.msg);
    s->result = sl_calloc(n ? n : 1, sizeof *s->result, "sweep results");
    s->nresult = n;
    for (size_t i = 0; i < n; i++) {
        char *colon = strrchr(list[i], ':');
        if (!colon || colon == list[i] || !colon[1])
            sl_fatal("%s:%d: results: '%s' is not <file>:<column>", s->path,
                     dict_entry_line(dict_lookup(d, "results")), list[i]);
        s->result[i].file = sl_strdup(list[i]);
        s->result[i].file[colon - list[i]] = '\0';
        s->result[i].column = sl_strdup(colon + 1);
    }
    for (size_t i = 0; i < n; i++) { /* label: the column, made unique by its file */
        char buf[512];
        int dup = 0;
        for (size_t j = 0; j < n; j++)
            dup |= j != i && !strcmp(s->result[j].column, s->result[i].column);
        if (dup) snprintf(buf, sizeof buf, "%s:%s", s->result[i].file, s->result[i].column);
        s->result[i].label = sl_strdup(dup ? buf : s->result[i].column);
    }
    dict_free_word_list(list, n);
}

/* ---- points --------------------------------------------------------------------------- */

static void sweep_points(sweep *s)
{
    size_t np = s->nparam;
    if (s->zip) {
        s->npoint = s->param[0].nvalue;
        for (size_t k = 1; k < np; k++)
            if (s->param[k].nvalue != s->npoint)
                sl_fatal("%s:%d: combine zip needs lists of one length: '%s' has %zu values, "
                         "'%s' %zu",
                         s->path, s->param[k].line, s->param[0].key, s->npoint, s->param[k].key,
                         s->param[k].nvalue);
    } else {
        s->npoint = 1;
        for (size_t k = 0; k < np; k++) s->npoint *= s->param[k].nvalue;
    }
    s->choice = sl_malloc(s->npoint * np * sizeof *s->choice, "sweep points");
    for (size_t i = 0; i < s->npoint; i++) {
        size_t rest = i;
        for (size_t k = np; k-- > 0;) { /* the last parameter varies fastest */
            size_t nv = s->param[k].nvalue;
            s->choice[i * np + k] = s->zip ? i : rest % nv;
            rest /= nv;
        }
    }
}

/* "eta_0.5-mode_adaptive"; a repeated name gets "-<point number>". */
static void sweep_names(sweep *s)
{
    s->name = sl_calloc(s->npoint, sizeof *s->name, "case names");
    for (size_t i = 0; i < s->npoint; i++) {
        char buf[1024] = "", part[512];
        size_t o = 0;
        for (size_t k = 0; k < s->nparam; k++) {
            sweep_safe(sweep_value(s, i, k), part, sizeof part);
            int w =
                snprintf(buf + o, sizeof buf - o, "%s%s_%s", k ? "-" : "", s->param[k].label, part);
            if (w > 0) o = o + (size_t)w < sizeof buf ? o + (size_t)w : sizeof buf - 1;
        }
        for (size_t j = 0; j < i; j++)
            if (!strcmp(s->name[j], buf)) {
                snprintf(part, sizeof part, "-%zu", i);
                if (o + strlen(part) < sizeof buf) strcat(buf, part);
                break;
            }
        s->name[i] = sl_strdup(buf);
    }
}

/* ---- the dictionary ------------------------------------------------------------------------- */

static void sweep_read_application(sweep *s)
{
    char *ctl = cf_join(s->base, "system/controlDict");
    const char *app;
    sl_err err;
    dict *d = dict_read_file(ctl, &err);
    if (!d) sl_fatal("%s", err.msg);
    if (dict_get_word_or(d, "application", "pcisph", &app, &err)) sl_fatal("%s", err.msg);
    s->application = sl_strdup(app);
    dict_free(d);
    free(ctl);
}

void sweep_read(sweep *s, const char *path)
{
    const char *base, *combine;
    sl_err err;
    dict *d;
    memset(s, 0, sizeof *s);
    if (!(d = dict_read_file(path, &err))) sl_fatal("%s", err.msg);
    dict_warn_unknown(d, sweep_keys);
    s->path = sl_strdup(path);
    const char *slash = strrchr(path, '/');
    s->dir = slash ? sl_strdup(path) : sl_strdup(".");
    if (slash) s->dir[slash == path ? 1 : slash - path] = '\0';
    if (dict_get_word(d, "baseCase", &base, &err)) sl_fatal("%s", err.msg);
    s->base = base[0] == '/' ? sl_strdup(base) : cf_join(s->dir, base);
    if (!cf_is_case(s->base))
        sl_fatal("%s:%d: baseCase '%s' is not a case (no %s/system/controlDict)", path,
                 dict_entry_line(dict_lookup(d, "baseCase")), base, s->base);
    s->cases = cf_join(s->dir, "cases");
    if (dict_get_word_or(d, "combine", "product", &combine, &err)) sl_fatal("%s", err.msg);
    if (strcmp(combine, "product") && strcmp(combine, "zip"))
        sl_fatal("%s:%d: combine '%s': expected product or zip", path,
                 dict_entry_line(dict_lookup(d, "combine")), combine);
    s->zip = !strcmp(combine, "zip");
    sweep_read_application(s);
    sweep_read_params(s, d);
    sweep_read_results(s, d);
    sweep_points(s);
    sweep_names(s);
    dict_free(d);
}

void sweep_free(sweep *s)
{
    for (size_t k = 0; k < s->nparam; k++) {
        sweep_param *p = &s->param[k];
        for (size_t v = 0; v < p->nvalue; v++) free(p->value[v]);
        free(p->value);
        free(p->key);
        free(p->file);
        free(p->entry);
        free(p->label);
    }
    for (size_t i = 0; i < s->nresult; i++) {
        free(s->result[i].file);
        free(s->result[i].column);
        free(s->result[i].label);
    }
    for (size_t i = 0; i < s->npoint; i++) free(s->name[i]);
    free(s->param);
    free(s->result);
    free(s->choice);
    free(s->name);
    free(s->path);
    free(s->dir);
    free(s->base);
    free(s->cases);
    free(s->application);
    memset(s, 0, sizeof *s);
}

const char *sweep_value(const sweep *s, size_t point, size_t param)
{
    return s->param[param].value[s->choice[point * s->nparam + param]];
}

char *sweep_case_dir(const sweep *s, size_t point) { return cf_join(s->cases, s->name[point]); }
