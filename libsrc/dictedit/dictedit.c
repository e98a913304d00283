/*
 * dictedit: setting, adding and removing entries of dictionary files in
 * place (see dictedit.h).
 *
 * Every edit is one splice -- bytes [begin, end) of one file replaced by new
 * text -- found from the parsed tree (dict_entry_span, key line and column)
 * and checked by parsing the edited text: the entry must then be where the
 * splice put it and nothing else may have moved, which also refuses values
 * that are not one value ("1; b 2", unbalanced brackets).
 *
 * Entries that are copies made by $-macros (`a $b;` then a/x, or `$b;`
 * merged into a dictionary) have their span in the original definition:
 * editing there would change every copy, so such entries are refused.
 */
#include "dictedit/dictedit_internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/sl_mem.h"
#include "io/atomic_file.h"

/* One file's text and the replacement of bytes [begin, end) of it. */
typedef struct dedit_splice {
    const char *file; /* as the parser named it */
    char *text;
    size_t n;
    long begin, end;
    char *with;
} dedit_splice;

/* What the entry must look like after the edit (present = 0: gone or
 * anything, only readability is checked). */
typedef struct dedit_expect {
    const char *path;
    int present;
    long begin, end; /* span of the value in the edited file */
} dedit_expect;

static void dedit_splice_free(dedit_splice *sp)
{
    free(sp->text);
    free(sp->with);
    sp->text = sp->with = NULL;
}

static int dedit_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
        sa.st_ino == sb.st_ino;
}

static char *dedit_strndup(const char *s, size_t n)
{
    char *c = sl_malloc(n + 1, "text");
    memcpy(c, s, n);
    c[n] = '\0';
    return c;
}

/* Replaces every occurrence of `from` in err by `to` (temp file names in
 * parser messages become the name of the file being edited). */
static void dedit_err_rename(sl_err *err, const char *from, const char *to)
{
    char out[SL_ERR_LEN];
    size_t o = 0, lf = strlen(from), lt = strlen(to);
    for (const char *s = err->msg; *s && o + 1 < sizeof out;) {
        if (lf && strncmp(s, from, lf) == 0 && o + lt + 1 < sizeof out) {
            memcpy(out + o, to, lt);
            o += lt;
            s += lf;
        } else {
            out[o++] = *s++;
        }
    }
    out[o] = '\0';
    memcpy(err->msg, out, o + 1);
}

/* ---- lookups with helpful errors -------------------------------------------- */

/* "a, b, c" (at most a few), for messages. */
static void dedit_key_list(const dict *d, char *buf, size_t len)
{
    size_t n = dict_size(d), o = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < n && o + 1 < len; i++) {
        const char *k = dict_entry_key(dict_entry_at(d, i));
        if (!strcmp(k, "FoamFile")) continue;
        int w = snprintf(buf + o, len - o, "%s%s", o ? ", " : "", k);
        if (w < 0 || (size_t)w >= len - o) {
            snprintf(buf + (o < len - 5 ? o : len - 5), 5, ", ..");
            return;
        }
        o += (size_t)w;
    }
}

static const char *dedit_nearest_key(const dict *d, const char *key)
{
    size_t n = dict_size(d);
    const char **keys = sl_malloc((n + 1) * sizeof *keys, "keys");
    const char *near;
    for (size_t i = 0; i < n; i++) keys[i] = dict_entry_key(dict_entry_at(d, i));
    keys[n] = NULL;
    near = dict_nearest(key, keys);
    free(keys);
    return near;
}

const dict_entry *dedit_lookup(const dict *d, const char *path, sl_err *err)
{
    const dict_entry *e = dict_lookup(d, path);
    const dict *scope = d;
    char *p, *part, keys[512];
    if (e) return e;
    /* Walk down to the first part that is missing, to say where. */
    p = sl_strdup(path);
    part = p;
    for (;;) {
        char *slash = strchr(part, '/');
        if (slash) *slash = '\0';
        const dict_entry *x = dict_lookup(scope, part);
        if (!x || !slash) {
            const char *near = dedit_nearest_key(scope, part);
            dedit_key_list(scope, keys, sizeof keys);
            if (scope == d)
                sl_err_set(err, "%s: no entry '%s'%s%s%s (keywords: %s)", dict_file(d), path,
                           near ? "; did you mean '" : "", near ? near : "", near ? "'?" : "",
                           keys);
            else
                sl_err_set(err,
                           "%s: no entry '%s': dictionary '%.*s' has no keyword '%s'%s%s%s "
                           "(keywords: %s)",
                           dict_file(d), path, (int)(part - p - 1), p, part,
                           near ? "; did you mean '" : "", near ? near : "", near ? "'?" : "",
                           keys);
            break;
        }
        if (!dict_entry_dict(x)) {
            sl_err_set(err, "%s: no entry '%s': '%s' (%s:%d) is not a dictionary", dict_file(d),
                       path, p, dict_entry_file(x), dict_entry_line(x));
            break;
        }
        scope = dict_entry_dict(x);
        *slash = '/';
        part = slash + 1;
    }
    free(p);
    return NULL;
}

/* ---- where an entry is written ------------------------------------------------ */

/* Reads the file holding e's value into sp (text, n, file). */
static int dedit_load(dedit_splice *sp, const dict_entry *e, sl_err *err)
{
    long b, en;
    sp->file = dict_entry_file(e);
    sp->text = dedit_read_text(sp->file, &sp->n, err);
    if (!sp->text) return 1;
    dict_entry_span(e, &b, &en);
    if (b < 0 || en <= b || (size_t)en > sp->n) {
        sl_err_set(err, "%s:%d: the file changed while it was being edited", sp->file,
                   dict_entry_line(e));
        return 1;
    }
    return 0;
}

/* 1 if e is written inside the braces of the dictionary entry `in`. */
static int dedit_inside(const dict_entry *in, const dict_entry *e)
{
    long ib, ie, b, en;
    dict_entry_span(in, &ib, &ie);
    dict_entry_span(e, &b, &en);
    return !strcmp(dict_entry_file(in), dict_entry_file(e)) && b > ib && en < ie;
}

static int dedit_copy_error(const char *path, const dict_entry *e, sl_err *err)
{
    sl_err_set(err,
               "'%s' is a copy made by a $-macro of the entry written at %s:%d: edit it "
               "there, or set the dictionary holding it as a whole",
               path, dict_entry_file(e), dict_entry_line(e));
    return 1;
}

/* 1 if a dictionary entry of d that is not one of e's ancestors (nor a copy
 * of one, with the same span) holds e's text: e is then a copy that a
 * `$sub;` merge made of an entry of that dictionary. */
static int dedit_held_elsewhere(const dict *d, const dict_entry *e, const dict_entry *const *anc,
                                size_t nanc)
{
    long b, en, db, de, ab, ae;
    dict_entry_span(e, &b, &en);
    for (size_t i = 0; i < dict_size(d); i++) {
        const dict_entry *x = dict_entry_at(d, i);
        int ancestor = 0;
        if (x == e || !dict_entry_dict(x)) continue;
        dict_entry_span(x, &db, &de);
        for (size_t k = 0; k < nanc && !ancestor; k++) {
            dict_entry_span(anc[k], &ab, &ae);
            ancestor = ab == db && ae == de && !strcmp(dict_entry_file(anc[k]), dict_entry_file(x));
        }
        if (!ancestor && !strcmp(dict_entry_file(x), dict_entry_file(e)) && db <= b && en <= de &&
            (db != b || de != en))
            return 1;
        if (dedit_held_elsewhere(dict_entry_dict(x), e, anc, nanc)) return 1;
    }
    return 0;
}

/* 0 if e (found at path in d) is written where its span says, so that a
 * splice there edits this entry only. */
static int dedit_check_origin(const dict *d, const char *path, const dict_entry *e, sl_err *err)
{
    const dict_entry **anc = sl_malloc((strlen(path) + 1) * sizeof *anc, "entries");
    size_t nanc = 0;
    char *p = sl_strdup(path);
    int rc = 0;
    if (strcmp(dict_entry_key(e), path) != 0) { /* not an exact key "a/b" */
        for (char *slash = strchr(p, '/'); slash && !rc; slash = strchr(slash + 1, '/')) {
            *slash = '\0';
            const dict_entry *a = dict_lookup(d, p);
            char *raw = a ? dedit_raw_value(a, err) : NULL;
            if (a && !raw) rc = 1;
            else if (raw && raw[0] != '{') rc = dedit_copy_error(path, e, err); /* `a $b;` */
            free(raw);
            *slash = '/';
            if (!a || !dict_entry_dict(a)) break;
            anc[nanc++] = a;
        }
    }
    if (!rc && dedit_held_elsewhere(d, e, anc, nanc)) rc = dedit_copy_error(path, e, err);
    free(p);
    free(anc);
    return rc;
}

/* ---- writing and checking ------------------------------------------------------- */

static char *dedit_spliced(const dedit_splice *sp, size_t *len)
{
    size_t w = strlen(sp->with), n = (size_t)sp->begin + w + (sp->n - (size_t)sp->end);
    char *s = sl_malloc(n + 1, "a dictionary file");
    memcpy(s, sp->text, (size_t)sp->begin);
    memcpy(s + sp->begin, sp->with, w);
    memcpy(s + (size_t)sp->begin + w, sp->text + sp->end, sp->n - (size_t)sp->end);
    s[n] = '\0';
    *len = n;
    return s;
}

/* Writes text to path atomically, keeping its permissions. */
static int dedit_write(const char *path, const char *text, size_t n, afile *a, int commit,
                       sl_err *err)
{
    struct stat st;
    FILE *f = afile_open(a, path, err);
    if (!f) return 1;
    if (stat(path, &st) == 0) (void)fchmod(fileno(f), st.st_mode & 07777);
    if (fwrite(text, 1, n, f) != n || fflush(f) != 0) {
        sl_err_set(err, "cannot write '%s': %s", path, strerror(errno));
        afile_abort(a);
        return 1;
    }
    return commit ? afile_commit(a, err) : 0;
}

/* The edited dictionary d (the value file read as `file`) against ex. */
static int dedit_verify(const dict *d, const char *file, const dedit_expect *ex, const char *value,
                        sl_err *err)
{
    const dict_entry *e;
    long b, en;
    if (!ex->present) return 0;
    e = dict_lookup(d, ex->path);
    if (e) dict_entry_span(e, &b, &en);
    if (e && dedit_same_file(dict_entry_file(e), file) && b == ex->begin && en == ex->end) return 0;
    if (e) {
        char *v = dict_entry_value_text(e);
        sl_err_set(err, "'%s' is not one value for '%s': the entry would read '%s'", value,
                   ex->path, v);
        free(v);
    } else {
        sl_err_set(err, "'%s' is not one value for '%s': the entry would be lost", value, ex->path);
    }
    return 1;
}

/* Applies sp to its file: for the top file the edited text is parsed from
 * the temp file before the rename; an included file is replaced first, the
 * top file parsed again, and the old text put back if that fails. */
static int dedit_apply(const char *top, dedit_splice *sp, const dedit_expect *ex, const char *value,
                       sl_err *err)
{
    size_t n;
    char *text = dedit_spliced(sp, &n), *real = realpath(sp->file, NULL);
    int rc;
    sl_err perr;
    afile a;
    dict *d;
    if (!real) {
        sl_err_set(err, "cannot edit '%s': %s", sp->file, strerror(errno));
        free(text);
        return 1;
    }
    if (dedit_same_file(top, real)) {
        rc = dedit_write(real, text, n, &a, 0, err);
        if (!rc) {
            d = dict_read_file(a.tmp, &perr);
            if (!d) {
                dedit_err_rename(&perr, a.tmp, top);
                sl_err_set(err, "the edit would make %s unreadable: %s", top, perr.msg);
                rc = 1;
            } else {
                rc = dedit_verify(d, a.tmp, ex, value, err);
            }
            dict_free(d);
            if (rc) afile_abort(&a);
            else rc = afile_commit(&a, err);
        }
    } else {
        rc = dedit_write(real, text, n, &a, 1, err);
        if (!rc) {
            d = dict_read_file(top, &perr);
            if (!d)
                sl_err_set(err, "the edit of %s would make %s unreadable: %s", sp->file, top,
                           perr.msg);
            rc = d ? dedit_verify(d, real, ex, value, err) : 1;
            dict_free(d);
            if (rc) {
                sl_err undo;
                if (dedit_write(real, sp->text, sp->n, &a, 1, &undo))
                    sl_err_set(err, "%s; and putting back the old text failed: %s", err->msg,
                               undo.msg);
            }
        }
    }
    free(real);
    free(text);
    return rc;
}

/* ---- set --------------------------------------------------------------------- */

static char *dedit_trim(const char *v)
{
    size_t n;
    while (*v && strchr(" \t\r\n", *v)) v++;
    n = strlen(v);
    while (n && strchr(" \t\r\n", v[n - 1])) n--;
    return dedit_strndup(v, n);
}

/* Replace the value of the existing entry e. */
static int dedit_replace(const char *top, const char *path, const dict_entry *e, const char *value,
                         dedit_change *ch, sl_err *err)
{
    dedit_splice sp = {0};
    dedit_expect ex = {path, 1, 0, 0};
    int rc;
    if (dedit_load(&sp, e, err)) return 1;
    dict_entry_span(e, &sp.begin, &sp.end);
    long after = dedit_entry_end(sp.text, sp.n, sp.end); /* after ';' if there is one */
    int had_semicolon = after != sp.end, is_dict = value[0] == '{';
    if (had_semicolon && is_dict) { /* `key 1;` -> `key { ... }` */
        sp.end = after;
        sp.with = sl_strdup(value);
    } else if (!had_semicolon && !is_dict) { /* `key { ... }` -> `key 1;` */
        size_t n = strlen(value) + 2;
        sp.with = sl_malloc(n, "a value");
        snprintf(sp.with, n, "%s;", value);
    } else {
        sp.with = sl_strdup(value);
    }
    ex.begin = sp.begin;
    ex.end = sp.begin + (long)strlen(value);
    rc = dedit_apply(top, &sp, &ex, value, err);
    if (!rc) {
        snprintf(ch->file, sizeof ch->file, "%s", sp.file);
        ch->line = dict_entry_line(e);
        ch->added = 0;
    }
    dedit_splice_free(&sp);
    return rc;
}

/* Indentation of the line of e's key, and the column offset of its value
 * from its key (0 if the value is not on the key's line). */
static void dedit_layout(const dedit_splice *sp, const dict_entry *e, char *indent, size_t len,
                         int *value_col)
{
    long k = dedit_offset(sp->text, sp->n, dict_entry_line(e), dict_entry_col(e));
    long ls = dedit_line_start(sp->text, k), b, en;
    size_t w = (size_t)(k - ls) < len - 1 ? (size_t)(k - ls) : len - 1;
    memcpy(indent, sp->text + ls, w);
    indent[w] = '\0';
    if (!dedit_is_blank(indent, 0, (long)w)) indent[0] = '\0';
    dict_entry_span(e, &b, &en);
    *value_col = dedit_line_end(sp->text, sp->n, k) > b ? (int)(b - k) : 0;
}

/* The text of a new entry: prefix (line break, indentation), key, padding
 * to value_col (< 0: one space), value, `;` and `end`; *value_at is where
 * the value starts in it. */
static char *dedit_new_entry(const char *prefix, const char *key, int value_col, const char *value,
                             const char *end, long *value_at)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    int w;
    if (!f) sl_fatal("out of memory writing a dictionary entry");
    fputs(prefix, f);
    w = dedit_write_key(f, key);
    if (value_col < 0) value_col = w + 1;
    else if (value_col <= w) value_col = w < DEDIT_KEY_WIDTH ? DEDIT_KEY_WIDTH : w + 1;
    fprintf(f, "%*s", value_col - w, "");
    fflush(f);
    *value_at = (long)len;
    fprintf(f, "%s%s%s", value, value[0] == '{' ? "" : ";", end);
    fclose(f);
    return buf;
}

/* The last entry of scope written in `file` (by position in the file). */
static const dict_entry *dedit_last_in(const dict *scope, const char *file)
{
    const dict_entry *last = NULL;
    long lb = -1, b, en;
    for (size_t i = 0; i < dict_size(scope); i++) {
        const dict_entry *e = dict_entry_at(scope, i);
        dict_entry_span(e, &b, &en);
        if (dedit_same_file(dict_entry_file(e), file) && b > lb) {
            last = e;
            lb = b;
        }
    }
    return last;
}

/* Where a new entry of the dictionary `parent` goes: on its own line before
 * the closing brace, or before the brace of a one-line `name { a 1; }`. */
static void dedit_place_in_dict(dedit_splice *sp, const dict_entry *parent, const char *indent,
                                int value_col, const char *key, const char *value, long *value_at)
{
    long pb, close, ls;
    dict_entry_span(parent, &pb, &close);
    close--; /* the '}' */
    ls = dedit_line_start(sp->text, close);
    if (ls > pb && dedit_is_blank(sp->text, ls, close)) {
        sp->begin = sp->end = ls;
        sp->with = dedit_new_entry(indent, key, value_col, value, "\n", value_at);
    } else {
        int space = close > 0 && sp->text[close - 1] == ' ';
        sp->begin = sp->end = close;
        sp->with = dedit_new_entry(space ? "" : " ", key, -1, value, " ", value_at);
    }
}

/* Where a new top-level entry goes: on the line after the last top-level
 * entry written in the file, or at the end of a file holding none. */
static void dedit_place_at_top(dedit_splice *sp, const dict_entry *last, const char *indent,
                               int value_col, const char *key, const char *value, long *value_at)
{
    char prefix[300];
    long at = (long)sp->n;
    if (last) {
        long b, en;
        dict_entry_span(last, &b, &en);
        at = dedit_line_end(sp->text, sp->n, dedit_entry_end(sp->text, sp->n, en));
        if ((size_t)at < sp->n) at++;
    }
    snprintf(prefix, sizeof prefix, "%s%s", at > 0 && sp->text[at - 1] != '\n' ? "\n" : "", indent);
    sp->begin = sp->end = at;
    sp->with = dedit_new_entry(prefix, key, value_col, value, "\n", value_at);
}

/* Add `key value;` at the end of the dictionary `parent` (NULL: the top
 * level of the file `top`). */
static int dedit_add(const char *top, const dict *d, const char *path, const char *key,
                     const dict_entry *parent, const char *value, dedit_change *ch, sl_err *err)
{
    dedit_splice sp = {0};
    dedit_expect ex = {path, 1, 0, 0};
    const dict *scope = parent ? dict_entry_dict(parent) : d;
    const dict_entry *last;
    char indent[256] = "";
    int value_col = DEDIT_KEY_WIDTH, rc;
    long value_at = 0;
    if (parent) {
        if (dedit_load(&sp, parent, err)) return 1;
    } else {
        sp.file = top;
        if (!(sp.text = dedit_read_text(top, &sp.n, err))) return 1;
    }
    last = dedit_last_in(scope, sp.file);
    if (last && parent && !dedit_inside(parent, last)) last = NULL;
    if (last) {
        dedit_layout(&sp, last, indent, sizeof indent, &value_col);
    } else if (parent) { /* an empty dictionary: one level in from its key */
        dedit_layout(&sp, parent, indent, sizeof indent - 4, &value_col);
        strcat(indent, "    ");
        value_col = DEDIT_KEY_WIDTH;
    }
    if (parent) dedit_place_in_dict(&sp, parent, indent, value_col, key, value, &value_at);
    else dedit_place_at_top(&sp, last, indent, value_col, key, value, &value_at);
    ex.begin = sp.begin + value_at;
    ex.end = ex.begin + (long)strlen(value);
    rc = dedit_apply(top, &sp, &ex, value, err);
    if (!rc) {
        snprintf(ch->file, sizeof ch->file, "%s", sp.file);
        ch->added = 1;
        ch->line = 1;
        for (long i = 0; i < sp.begin; i++) ch->line += sp.text[i] == '\n';
        for (long i = 0; i < value_at; i++) ch->line += sp.with[i] == '\n';
    }
    dedit_splice_free(&sp);
    return rc;
}

/* The dictionary entry a new entry `path` goes into (*parent NULL: the top
 * level); 0, or nonzero with err filled if it is missing or not a
 * dictionary written in place. */
static int dedit_parent_for_add(const dict *d, const char *file, const char *path,
                                const dict_entry **parent, sl_err *err)
{
    const char *slash = strrchr(path, '/');
    char *pp;
    int rc = 1;
    *parent = NULL;
    if (!slash) return 0;
    if (!slash[1]) {
        sl_err_set(err, "%s: empty keyword in '%s'", file, path);
        return 1;
    }
    pp = dedit_strndup(path, (size_t)(slash - path));
    if (!(*parent = dedit_lookup(d, pp, err))) {
        sl_err why = *err;
        sl_err_set(err, "cannot add '%s': its dictionary '%s' does not exist (%s)", path, pp,
                   why.msg);
    } else if (!dict_entry_dict(*parent)) {
        sl_err_set(err, "cannot add '%s' to %s: '%s' (line %d of %s) is not a dictionary", path,
                   file, pp, dict_entry_line(*parent), dict_entry_file(*parent));
    } else {
        rc = dedit_check_origin(d, pp, *parent, err);
    }
    free(pp);
    return rc;
}

int dedit_set(const char *file, const char *path, const char *value, dedit_change *ch, sl_err *err)
{
    dedit_change dummy;
    const dict_entry *e, *parent;
    char *v = dedit_trim(value);
    dict *d = dict_read_file(file, err);
    const char *slash = strrchr(path, '/');
    int rc = 1;
    if (!ch) ch = &dummy;
    memset(ch, 0, sizeof *ch);
    if (!d) {
        /* err filled by the parser */
    } else if (!*v) {
        sl_err_set(err, "%s: empty value for '%s'", file, path);
    } else if ((e = dict_lookup(d, path))) {
        rc = dedit_check_origin(d, path, e, err) || dedit_replace(file, path, e, v, ch, err);
    } else if (!dedit_parent_for_add(d, file, path, &parent, err)) {
        rc = dedit_add(file, d, path, slash ? slash + 1 : path, parent, v, ch, err);
    }
    free(v);
    dict_free(d);
    return rc;
}

/* ---- remove --------------------------------------------------------------------- */

/* Bytes to remove for e: its whole line(s) when nothing else stands on
 * them (a trailing comment goes with the entry), else just the entry. */
static void dedit_removal(dedit_splice *sp, const dict_entry *e)
{
    long b, en, k, end, ls;
    dict_entry_span(e, &b, &en);
    k = dedit_offset(sp->text, sp->n, dict_entry_line(e), dict_entry_col(e));
    end = dedit_entry_end(sp->text, sp->n, en);
    ls = dedit_line_start(sp->text, k);
    if (dedit_is_blank(sp->text, ls, k) && dedit_tail_is_comment(sp->text, sp->n, end)) {
        sp->begin = ls;
        sp->end = dedit_line_end(sp->text, sp->n, end);
        if ((size_t)sp->end < sp->n) sp->end++;
    } else {
        sp->begin = k;
        sp->end = end;
        while ((size_t)sp->end < sp->n && (sp->text[sp->end] == ' ' || sp->text[sp->end] == '\t'))
            sp->end++;
    }
    sp->with = sl_strdup("");
}

int dedit_remove(const char *file, const char *path, dedit_change *ch, sl_err *err)
{
    dedit_change dummy;
    const dedit_expect ex = {path, 0, 0, 0};
    if (!ch) ch = &dummy;
    memset(ch, 0, sizeof *ch);
    /* A repeated key is found once per pass (its last definition); the text
     * shrinks at every pass, so the loop ends. */
    for (;;) {
        dict *d = dict_read_file(file, err);
        const dict_entry *e;
        dedit_splice sp = {0};
        int rc;
        if (!d) return 1;
        e = ch->removed ? dict_lookup(d, path) : dedit_lookup(d, path, err);
        if (!e) {
            dict_free(d);
            return ch->removed ? 0 : 1;
        }
        rc = dedit_check_origin(d, path, e, err) || dedit_load(&sp, e, err);
        if (!rc) {
            dedit_removal(&sp, e);
            rc = dedit_apply(file, &sp, &ex, "", err);
        }
        if (!rc && !ch->removed++) {
            snprintf(ch->file, sizeof ch->file, "%s", sp.file);
            ch->line = dict_entry_line(e);
        }
        dedit_splice_free(&sp);
        dict_free(d);
        if (rc) return rc;
    }
}
