/*
 * dict: the dictionary tree -- construction, copying, freeing, lookups and
 * the accessors of the public API.  Parsing is in dict_parse.c, the lexer in
 * dict_lex.c, the typed getters in dict_get.c.
 */
#include "dictionary/dict_internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

/* ---- growable text ------------------------------------------------------- */

void dict_buf_puts(dict_buf *b, const char *s, size_t len)
{
    if (b->n + len + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 64;
        while (cap < b->n + len + 1) cap *= 2;
        b->s = sl_realloc(b->s, cap, "dictionary text");
        b->cap = cap;
    }
    memcpy(b->s + b->n, s, len);
    b->n += len;
    b->s[b->n] = '\0';
}

void dict_buf_putc(dict_buf *b, char c) { dict_buf_puts(b, &c, 1); }

char *dict_buf_take(dict_buf *b)
{
    char *s = b->s ? b->s : sl_strdup("");
    b->s = NULL;
    b->n = b->cap = 0;
    return s;
}

/* ---- construction -------------------------------------------------------- */

dict *dict_new(const char *name, const char *file, dict *parent)
{
    dict *d = sl_calloc(1, sizeof *d, "a dictionary");
    d->name = sl_strdup(name);
    d->file = file;
    d->parent = parent;
    return d;
}

dict *dict_root(dict *d)
{
    while (d->parent) d = d->parent;
    return d;
}

/* Returns a copy of `name` that lives as long as the tree containing d. */
const char *dict_intern_file(dict *d, const char *name)
{
    dict *root = dict_root(d);
    dict_files *f;
    if (!root->files) root->files = sl_calloc(1, sizeof *root->files, "file names");
    f = root->files;
    for (size_t i = 0; i < f->n; i++)
        if (strcmp(f->names[i], name) == 0) return f->names[i];
    if (f->n == f->cap) {
        f->cap = f->cap ? 2 * f->cap : 4;
        f->names = sl_realloc(f->names, f->cap * sizeof *f->names, "file names");
    }
    f->names[f->n] = sl_strdup(name);
    return f->names[f->n++];
}

dict_entry *dict_entry_new(char *key, const char *file, int line, int col)
{
    dict_entry *e = sl_calloc(1, sizeof *e, "a dictionary entry");
    e->key = key;
    e->file = file;
    e->line = line;
    e->col = col;
    return e;
}

void dict_tokens_free(dict_token *t, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        free(t[i].text);
        dict_free(t[i].sub);
    }
    free(t);
}

void dict_entry_free(dict_entry *e)
{
    if (!e) return;
    free(e->key);
    dict_free(e->sub);
    dict_tokens_free(e->tok, e->ntok);
    free(e);
}

void dict_free(dict *d)
{
    if (!d) return;
    for (size_t i = 0; i < d->n; i++) dict_entry_free(d->entries[i]);
    free(d->entries);
    free(d->index);
    free(d->name);
    if (d->files) {
        for (size_t i = 0; i < d->files->n; i++) free(d->files->names[i]);
        free(d->files->names);
        free(d->files);
    }
    free(d);
}

/* ---- the key index --------------------------------------------------------
 * Small dictionaries are searched linearly; from DICT_INDEX_MIN entries on a
 * hash index keeps reading a file with many keys linear in its size. */

#define DICT_INDEX_MIN 16

static size_t dict_hash(const char *key, size_t len)
{
    uint64_t h = 1469598103934665603u; /* FNV-1a */
    for (size_t i = 0; i < len; i++) h = (h ^ (unsigned char)key[i]) * 1099511628211u;
    return (size_t)h;
}

static void dict_index_put(dict *d, size_t i)
{
    size_t mask = d->index_cap - 1;
    size_t h = dict_hash(d->entries[i]->key, strlen(d->entries[i]->key)) & mask;
    while (d->index[h]) h = (h + 1) & mask;
    d->index[h] = i + 1;
}

static void dict_index_rebuild(dict *d)
{
    free(d->index);
    d->index_cap = 4 * DICT_INDEX_MIN;
    while (d->index_cap < 2 * d->n) d->index_cap *= 2;
    d->index = sl_calloc(d->index_cap, sizeof *d->index, "a dictionary index");
    for (size_t i = 0; i < d->n; i++) dict_index_put(d, i);
}

static int dict_key_is(const dict_entry *e, const char *key, size_t len)
{
    return strncmp(e->key, key, len) == 0 && e->key[len] == '\0';
}

/* Position of the entry with the first `len` characters of key, or d->n. */
static size_t dict_find_pos(const dict *d, const char *key, size_t len)
{
    if (d->index) {
        size_t mask = d->index_cap - 1, h = dict_hash(key, len) & mask;
        for (; d->index[h]; h = (h + 1) & mask)
            if (dict_key_is(d->entries[d->index[h] - 1], key, len)) return d->index[h] - 1;
        return d->n;
    }
    for (size_t i = 0; i < d->n; i++)
        if (dict_key_is(d->entries[i], key, len)) return i;
    return d->n;
}

dict_entry *dict_find_local(const dict *d, const char *key, size_t len)
{
    size_t i = dict_find_pos(d, key, len);
    return i < d->n ? d->entries[i] : NULL;
}

/* OpenFOAM's default: a later definition replaces the value of an earlier
 * one; the entry keeps the earlier position so that output order is stable. */
void dict_insert(dict *d, dict_entry *e)
{
    size_t i = dict_find_pos(d, e->key, strlen(e->key));
    if (i < d->n) {
        dict_entry_free(d->entries[i]);
        d->entries[i] = e;
        return;
    }
    if (d->n == d->cap) {
        d->cap = d->cap ? 2 * d->cap : 8;
        d->entries = sl_realloc(d->entries, d->cap * sizeof *d->entries, "dictionary entries");
    }
    d->entries[d->n++] = e;
    if (d->index && 2 * d->n <= d->index_cap) dict_index_put(d, d->n - 1);
    else if (d->n >= DICT_INDEX_MIN) dict_index_rebuild(d);
}

/* ---- copying (for $var) -------------------------------------------------- */

dict_token *dict_tokens_copy(const dict_token *t, size_t n, dict *parent)
{
    dict_token *c = sl_calloc(n, sizeof *c, "dictionary tokens");
    for (size_t i = 0; i < n; i++) {
        c[i] = t[i];
        c[i].text = t[i].text ? sl_strdup(t[i].text) : NULL;
        c[i].sub = t[i].sub ? dict_copy(t[i].sub, t[i].sub->name, parent) : NULL;
    }
    return c;
}

dict_entry *dict_entry_copy(const dict_entry *e, dict *parent)
{
    dict_entry *c = dict_entry_new(sl_strdup(e->key), e->file, e->line, e->col);
    c->begin = e->begin;
    c->end = e->end;
    c->copied = 1;
    if (e->sub) c->sub = dict_copy(e->sub, e->key, parent);
    if (e->ntok) c->tok = dict_tokens_copy(e->tok, e->ntok, parent);
    c->ntok = e->ntok;
    return c;
}

dict *dict_copy(const dict *src, const char *name, dict *parent)
{
    dict *d = dict_new(name, src->file, parent);
    dict_merge(d, src);
    return d;
}

/* All copies are made before the first insertion: src may be an entry of d
 * (`s { s 1; } $s;`) that an inserted copy replaces and frees. */
void dict_merge(dict *d, const dict *src)
{
    size_t n = src->n;
    dict_entry **copy = sl_malloc(n * sizeof *copy, "dictionary entries");
    for (size_t i = 0; i < n; i++) copy[i] = dict_entry_copy(src->entries[i], d);
    for (size_t i = 0; i < n; i++) dict_insert(d, copy[i]);
    free(copy);
}

size_t dict_tokens_height(const dict_token *t, size_t n)
{
    size_t depth = 0, max = 0;
    for (size_t i = 0; i < n; i++) {
        size_t h = 0;
        if (t[i].kind == DICT_TOK_DICT) h = depth + dict_height(t[i].sub);
        else if (t[i].kind == DICT_TOK_PUNCT && (t[i].text[0] == '(' || t[i].text[0] == '['))
            h = ++depth;
        else if (t[i].kind == DICT_TOK_PUNCT && depth > 0) depth--;
        if (h > max) max = h;
    }
    return max;
}

size_t dict_height(const dict *d)
{
    size_t max = 0;
    for (size_t i = 0; i < d->n; i++) {
        const dict_entry *e = d->entries[i];
        size_t h = e->sub ? dict_height(e->sub) : dict_tokens_height(e->tok, e->ntok);
        if (h > max) max = h;
    }
    return max + 1;
}

/* ---- public accessors ---------------------------------------------------- */

const char *dict_file(const dict *d) { return d ? d->file : NULL; }
const char *dict_name(const dict *d) { return d ? d->name : NULL; }
size_t dict_size(const dict *d) { return d ? d->n : 0; }

const dict_entry *dict_entry_at(const dict *d, size_t i)
{
    return d && i < d->n ? d->entries[i] : NULL;
}

const char *dict_entry_key(const dict_entry *e) { return e ? e->key : NULL; }
int dict_entry_line(const dict_entry *e) { return e ? e->line : 0; }
int dict_entry_col(const dict_entry *e) { return e ? e->col : 0; }
const char *dict_entry_file(const dict_entry *e) { return e ? e->file : NULL; }
const dict *dict_entry_dict(const dict_entry *e) { return e ? e->sub : NULL; }

int dict_entry_span(const dict_entry *e, long *begin, long *end)
{
    if (!e) return -1;
    if (begin) *begin = e->begin;
    if (end) *end = e->end;
    return 0;
}

/* An exact key wins; otherwise "a/b/c" descends one dictionary per part. */
const dict_entry *dict_lookup(const dict *d, const char *key)
{
    const dict_entry *e;
    if (!d || !key) return NULL;
    e = dict_find_local(d, key, strlen(key));
    while (!e && d) {
        const char *slash = strchr(key, '/');
        if (!slash) return NULL;
        e = dict_find_local(d, key, (size_t)(slash - key));
        if (!e) return NULL;
        d = e->sub;
        key = slash + 1;
        e = d ? dict_find_local(d, key, strlen(key)) : NULL;
    }
    return e;
}

int dict_has(const dict *d, const char *key) { return dict_lookup(d, key) != NULL; }

const dict *dict_sub(const dict *d, const char *key)
{
    const dict_entry *e = dict_lookup(d, key);
    return e ? e->sub : NULL;
}
