/*
 * fo_list: reads the `functions` dictionary, decides when each object is
 * due, and owns the output files postProcessing/<name>/<startTime>/<type>.dat
 * (see fo.h).  The types are plugged in through the table below; nothing
 * else here knows what a type computes.
 */
#include "functionObjects/fo.h"
#include "functionObjects/fo_type.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "io/time_dir.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const fo_type *const fo_types[] = {&fo_type_density_error, &fo_type_probes,
                                          &fo_type_water_gauges,  &fo_type_energy,
                                          &fo_type_power,         NULL};

static const char *const common_keys[] = {"type", "writeControl", "writeInterval", "enabled", NULL};

/* Rows remembered for rolling back (the solver redoes up to two steps
 * after a shock). */
#define FO_RING 8

typedef struct fo_object {
    char *name;
    const fo_type *type;
    void *state;
    int on_write_time; /* writeControl writeTime */
    long interval;     /* writeInterval */
    long nwrites;      /* write times seen (writeTime control) */
    char *dir, *path;
    FILE *dat;
    int failed;
    double row_time[FO_RING]; /* the last rows: time and file offset */
    off_t row_at[FO_RING];
    size_t nrows; /* rows written (the ring holds the last FO_RING) */
} fo_object;

struct fo_list {
    fo_object *obj;
    size_t n, cap;
    char *case_dir;
    int precision;
    int post;  /* post-processing: every call executes, every call is a write time */
    int serve; /* fo_serve: no files; the collective objects only */
    char tname[64];
    fo_index ix;
    int started;      /* files open (first call or fo_start) */
    double last_time; /* of the last call */
    double *box;      /* fo_wants_region's boxes */
    size_t box_cap;
};

/* ---- reading ---- */

static const fo_type *find_type(const char *name)
{
    for (size_t i = 0; fo_types[i]; i++)
        if (!strcmp(fo_types[i]->name, name)) return fo_types[i];
    return NULL;
}

static void type_list(char *buf, size_t len)
{
    size_t off = 0;
    buf[0] = '\0';
    for (size_t i = 0; fo_types[i] && off < len; i++)
        off += (size_t)snprintf(buf + off, len - off, "%s%s", i ? ", " : "", fo_types[i]->name);
}

static void warn_unknown(const dict *d, const fo_type *t)
{
    size_t nc = 0, nt = 0;
    while (common_keys[nc]) nc++;
    while (t->keys && t->keys[nt]) nt++;
    const char **keys = sl_malloc((nc + nt + 1) * sizeof *keys, "keys");
    memcpy(keys, common_keys, nc * sizeof *keys);
    if (nt) memcpy(keys + nc, t->keys, nt * sizeof *keys);
    keys[nc + nt] = NULL;
    dict_warn_unknown(d, keys);
    free(keys);
}

static fo_list *list_new(const char *case_dir, int precision)
{
    fo_list *l = sl_calloc(1, sizeof *l, "function objects");
    l->case_dir = sl_strdup(case_dir);
    l->precision = precision;
    return l;
}

/* One object from its dictionary d; `force` ignores `enabled`. */
static void read_object(fo_list *l, const dict *d, const char *name, int force)
{
    static const char *const controls[] = {"timeStep", "writeTime", NULL};
    sl_err err;
    const char *w;
    int enabled;
    long interval;
    char valid[256];
    if (!*name || strchr(name, '/') || !strcmp(name, ".") || !strcmp(name, ".."))
        sl_fatal("%s: function object name '%s' cannot name a folder", dict_file(d), name);
    fo_need(dict_get_word(d, "type", &w, &err), &err);
    const fo_type *t = find_type(w);
    if (!t) {
        char why[512];
        type_list(valid, sizeof valid);
        snprintf(why, sizeof why, "unknown type '%s'; valid types: %s", w, valid);
        fo_bad_key(d, "type", why);
    }
    warn_unknown(d, t);
    fo_need(dict_get_bool_or(d, "enabled", 1, &enabled, &err), &err);
    if (!enabled && !force) return;
    fo_need(dict_get_word_or(d, "writeControl", "timeStep", &w, &err), &err);
    int control = -1;
    for (int i = 0; controls[i]; i++)
        if (!strcmp(w, controls[i])) control = i;
    if (control < 0) {
        char why[256];
        snprintf(why, sizeof why, "'%s' is not one of: timeStep writeTime", w);
        fo_bad_key(d, "writeControl", why);
    }
    fo_need(dict_get_int_or(d, "writeInterval", 1, &interval, &err), &err);
    if (interval < 1) fo_bad_key(d, "writeInterval", "must be a whole number of at least 1");
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 4;
        l->obj = sl_realloc(l->obj, l->cap * sizeof *l->obj, "function objects");
    }
    fo_object *o = &l->obj[l->n++];
    memset(o, 0, sizeof *o);
    o->name = sl_strdup(name);
    o->type = t;
    o->on_write_time = control == 1;
    o->interval = interval;
    o->state = t->read(d);
}

static const dict *entry_dict(const dict_entry *e)
{
    const dict *d = dict_entry_dict(e);
    if (!d)
        sl_fatal("%s:%d: function object '%s' must be a dictionary { type ...; }",
                 dict_entry_file(e), dict_entry_line(e), dict_entry_key(e));
    return d;
}

static fo_list *finish(fo_list *l)
{
    if (l->n == 0) {
        fo_free(l);
        return NULL;
    }
    return l;
}

fo_list *fo_read_dict(const dict *functions, const char *case_dir, int time_precision)
{
    if (!functions) return NULL;
    fo_list *l = list_new(case_dir, time_precision);
    for (size_t i = 0; i < dict_size(functions); i++) {
        const dict_entry *e = dict_entry_at(functions, i);
        if (!strcmp(dict_entry_key(e), "FoamFile")) continue;
        read_object(l, entry_dict(e), dict_entry_key(e), 0);
    }
    return finish(l);
}

/* The controlDict and its functions sub-dictionary (NULL if absent). */
static dict *read_control(const sl_case *c, const dict **functions)
{
    sl_err err;
    size_t len = strlen(c->dir) + 32;
    char *path = sl_malloc(len, "path");
    snprintf(path, len, "%s/system/controlDict", c->dir);
    dict *d = dict_read_file(path, &err);
    free(path);
    if (!d) sl_fatal("%s", err.msg);
    *functions = dict_sub(d, "functions");
    if (!*functions && dict_has(d, "functions")) {
        const dict_entry *e = dict_lookup(d, "functions");
        sl_fatal("%s:%d: keyword 'functions' must be a dictionary of function objects",
                 dict_entry_file(e), dict_entry_line(e));
    }
    return d;
}

fo_list *fo_read(const sl_case *c)
{
    const dict *functions;
    dict *d = read_control(c, &functions);
    fo_list *l = fo_read_dict(functions, c->dir, c->ctl.time_precision);
    dict_free(d);
    return l;
}

fo_list *fo_select(const sl_case *c, const char *const *names, size_t n)
{
    const dict *functions;
    dict *d = read_control(c, &functions);
    fo_list *l = list_new(c->dir, c->ctl.time_precision);
    l->post = 1;
    if (n == 0) {
        if (!functions || dict_size(functions) == 0)
            sl_fatal("%s/system/controlDict names no function objects; choose one with -func",
                     c->dir);
        for (size_t i = 0; i < dict_size(functions); i++) {
            const dict_entry *e = dict_entry_at(functions, i);
            read_object(l, entry_dict(e), dict_entry_key(e), 0);
        }
    }
    for (size_t i = 0; i < n; i++) {
        const dict_entry *e = functions ? dict_lookup(functions, names[i]) : NULL;
        if (e) {
            read_object(l, entry_dict(e), names[i], 1);
            continue;
        }
        if (!find_type(names[i])) {
            char valid[256];
            type_list(valid, sizeof valid);
            sl_fatal("'%s' is neither a function object of %s/system/controlDict nor a type "
                     "(valid types: %s)",
                     names[i], c->dir, valid);
        }
        /* A type with its defaults: an empty dictionary naming only the type. */
        char text[128], src[128];
        sl_err err;
        snprintf(text, sizeof text, "type %s;", names[i]);
        snprintf(src, sizeof src, "-func %s", names[i]);
        dict *def = dict_parse_string(text, src, &err);
        if (!def) sl_fatal("%s", err.msg);
        read_object(l, def, names[i], 1);
        dict_free(def);
    }
    dict_free(d);
    if (l->n == 0) sl_fatal("no enabled function object to run in %s/system/controlDict", c->dir);
    return l;
}

/* ---- executing ---- */

static void open_object(fo_list *l, fo_object *o, const pcs_view *s)
{
    sl_err err;
    size_t len = strlen(l->case_dir) + strlen(o->name) + strlen(l->tname) + 32;
    o->dir = sl_malloc(len, "path");
    snprintf(o->dir, len, "%s/postProcessing/%s/%s", l->case_dir, o->name, l->tname);
    if (tdir_mkdirs(o->dir, &err)) sl_fatal("function object '%s': %s", o->name, err.msg);
    len += strlen(o->type->name) + 8;
    o->path = sl_malloc(len, "path");
    snprintf(o->path, len, "%s/%s.dat", o->dir, o->type->name);
    o->dat = fopen(o->path, "w");
    if (!o->dat)
        sl_fatal("function object '%s': cannot write '%s': %s", o->name, o->path, strerror(errno));
    fprintf(o->dat, "# %s: function object '%s' (Sluice)\n", o->type->name, o->name);
    o->type->header(o->state, s, o->dat);
    fputs("# Time", o->dat);
    o->type->columns(o->state, o->dat);
    fputc('\n', o->dat);
}

static int due(const fo_list *l, fo_object *o, long step, int write_time)
{
    if (l->post) return 1;
    if (o->on_write_time) return write_time && o->nwrites++ % o->interval == 0;
    return step % o->interval == 0;
}

/* A call at or before the time of the previous call is the solver going
 * back after a shock: drop the rows after that time (the state at that time
 * was recorded when it was first reached).  Deeper than the ring: keep all. */
static void roll_back_rows(fo_object *o, double time)
{
    size_t keep = o->nrows, first = o->nrows > FO_RING ? o->nrows - FO_RING : 0;
    while (keep > first && o->row_time[(keep - 1) % FO_RING] > time) keep--;
    if (keep == o->nrows || (keep == first && first > 0)) return;
    off_t at = o->row_at[keep % FO_RING];
    if (fflush(o->dat) != 0 || ftruncate(fileno(o->dat), at) != 0 ||
        fseeko(o->dat, at, SEEK_SET) != 0) {
        sl_warning("function object '%s': cannot roll back '%s': %s", o->name, o->path,
                   strerror(errno));
        return;
    }
    o->nrows = keep;
}

static void write_row(fo_object *o, const fo_call *call)
{
    if (!call->dat) { /* computed (collective), not written */
        o->type->execute(o->state, call);
        return;
    }
    size_t k = o->nrows++ % FO_RING;
    o->row_time[k] = call->time;
    o->row_at[k] = ftello(o->dat);
    fprintf(o->dat, "%.10g", call->time);
    o->type->execute(o->state, call);
    fputc('\n', o->dat);
}

static void open_all(fo_list *l, const pcs_view *s, double time)
{
    tdir_name(time, l->precision, l->tname, sizeof l->tname);
    for (size_t i = 0; i < l->n && !l->serve; i++)
        if (!l->obj[i].dat) open_object(l, &l->obj[i], s);
    l->started = 1;
    l->last_time = time;
}

void fo_serve(fo_list *l)
{
    if (l) l->serve = 1;
}

void fo_start(fo_list *l, const pcs_view *s, double time)
{
    if (l && !l->started) open_all(l, s, time);
}

void fo_execute(fo_list *l, const pcs_view *s, double time, long step, int write_time)
{
    if (!l) return;
    if (!l->started) {
        open_all(l, s, time);
    } else if (time <= l->last_time) {
        for (size_t i = 0; i < l->n; i++)
            if (!l->obj[i].failed && l->obj[i].dat) roll_back_rows(&l->obj[i], time);
        l->last_time = time;
        return;
    }
    l->last_time = time;
    if (l->post) write_time = 1;
    tdir_name(time, l->precision, l->tname, sizeof l->tname);
    int ix_ready = 0;
    for (size_t i = 0; i < l->n; i++) {
        fo_object *o = &l->obj[i];
        /* a collective object runs on every rank alike, its file failed or not */
        if (o->type->collective ? 0 : o->failed || l->serve) continue;
        int row = due(l, o, step, write_time);
        if ((row || (write_time && o->type->at_write)) && (o->type->needs & FO_NEED_GRID) &&
            !ix_ready) {
            fo_index_update(&l->ix, s);
            ix_ready = 1;
        }
        FILE *dat = o->failed ? NULL : o->dat; /* NULL when serving */
        fo_call call = {s, &l->ix, time, l->tname, write_time, dat, o->dir};
        if (row) write_row(o, &call);
        if (write_time && o->type->at_write) o->type->at_write(o->state, &call);
        if (dat && (fflush(o->dat) != 0 || ferror(o->dat))) {
            sl_warning("function object '%s': cannot write '%s': %s; it writes no more", o->name,
                       o->path, strerror(errno));
            o->failed = 1;
        }
    }
}

/* Whether object o is due in a call at (step, write_time) after the start. */
static int wants(const fo_object *o, long step, int write_time)
{
    if (o->failed) return 0;
    if (write_time && o->type->at_write) return 1;
    return o->on_write_time ? write_time && o->nwrites % o->interval == 0 : step % o->interval == 0;
}

int fo_wants_region(fo_list *l, double time, long step, int write_time, const double **boxes,
                    size_t *nboxes)
{
    *boxes = NULL;
    *nboxes = 0;
    if (!l) return FO_READS_NOTHING;
    const int all = !l->started || l->post;
    if (l->started && time <= l->last_time) return FO_READS_NOTHING;
    size_t nb = 0;
    int any = 0;
    for (size_t i = 0; i < l->n; i++) {
        const fo_object *o = &l->obj[i];
        if (o->type->collective || !(all ? !o->failed : wants(o, step, write_time))) continue;
        if (!o->type->region) return FO_READS_ALL;
        any = 1;
        const size_t need = o->type->region(o->state, NULL, 0);
        if (nb + need > l->box_cap) {
            l->box_cap = 2 * (nb + need) + 16;
            l->box = sl_realloc(l->box, 6 * l->box_cap * sizeof *l->box, "query boxes");
        }
        nb += o->type->region(o->state, l->box + 6 * nb, need);
    }
    *boxes = l->box;
    *nboxes = nb;
    return any ? FO_READS_NEAR : FO_READS_NOTHING;
}

int fo_wants_state(const fo_list *l, double time, long step, int write_time)
{
    if (!l) return 0;
    if (!l->started) return 1;
    if (time <= l->last_time) return 0; /* going back after a shock: nothing executed */
    if (l->post) return 1;
    for (size_t i = 0; i < l->n; i++) {
        const fo_object *o = &l->obj[i];
        if (o->failed) continue;
        if (write_time && o->type->at_write) return 1;
        if (o->on_write_time ? write_time && o->nwrites % o->interval == 0
                             : step % o->interval == 0)
            return 1;
    }
    return 0;
}

unsigned fo_needs(const fo_list *l)
{
    unsigned u = 0;
    for (size_t i = 0; l && i < l->n; i++) u |= l->obj[i].type->needs;
    return u;
}

size_t fo_count(const fo_list *l) { return l ? l->n : 0; }
const char *fo_name(const fo_list *l, size_t i) { return l->obj[i].name; }
const char *fo_type_name(const fo_list *l, size_t i) { return l->obj[i].type->name; }
const char *fo_dat_path(const fo_list *l, size_t i) { return l->obj[i].path; }

void fo_free(fo_list *l)
{
    if (!l) return;
    for (size_t i = 0; i < l->n; i++) {
        fo_object *o = &l->obj[i];
        if (o->dat && fclose(o->dat) != 0 && !o->failed)
            sl_warning("function object '%s': could not finish '%s': %s", o->name, o->path,
                       strerror(errno));
        o->type->free(o->state);
        free(o->name);
        free(o->dir);
        free(o->path);
    }
    fo_index_free(&l->ix);
    free(l->box);
    free(l->obj);
    free(l->case_dir);
    free(l);
}
