/*
 * dict_get: typed getters (scalar, integer, word, switch, vector, lists)
 * with messages that name the file, line, column and keyword, so that a
 * user can fix a case file without reading the solver's source.
 */
#include "dictionary/dict_internal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/sl_mem.h"

/* The entry of key, or NULL with the "missing required keyword" message. */
static const dict_entry *dict_get_entry(const dict *d, const char *key, sl_err *err)
{
    const dict_entry *e = dict_lookup(d, key);
    if (!e)
        sl_err_set(err, "%s: missing required keyword '%s' in dictionary '%s'",
                   d ? d->file : "(null)", key ? key : "(null)", d ? d->name : "(null)");
    return e;
}

/* "<file>:<line>:<col>: keyword '<key>': <what>, found '<text>'", located at
 * token t (NULL: the entry).  Long values are shortened. */
static int dict_get_bad(const dict_entry *e, const dict_token *t, const char *what, sl_err *err)
{
    char *text;
    if (!t && e->sub) {
        sl_err_set(err, "%s:%d:%d: keyword '%s': %s, found a dictionary", e->file, e->line, e->col,
                   e->key, what);
        return -1;
    }
    if (t && t->kind == DICT_TOK_DICT) {
        sl_err_set(err, "%s:%d:%d: keyword '%s': %s, found a dictionary", t->file, t->line, t->col,
                   e->key, what);
        return -1;
    }
    text = t ? sl_strdup(t->text) : dict_entry_value_text(e);
    sl_err_set(err, "%s:%d:%d: keyword '%s': %s, found '%.80s%s'", t ? t->file : e->file,
               t ? t->line : e->line, t ? t->col : e->col, e->key, what, text,
               strlen(text) > 80 ? "..." : "");
    free(text);
    return -1;
}

/* The single word of a one-token value, NULL otherwise. */
static const dict_token *dict_get_single(const dict_entry *e)
{
    return !e->sub && e->ntok == 1 && e->tok[0].kind == DICT_TOK_WORD ? &e->tok[0] : NULL;
}

/* [+-] digits [. digits] [e [+-] digits], with at least one mantissa digit. */
static int dict_get_is_decimal(const char *s)
{
    size_t digits = 0;
    if (*s == '+' || *s == '-') s++;
    for (; *s >= '0' && *s <= '9'; s++) digits++;
    if (*s == '.')
        for (s++; *s >= '0' && *s <= '9'; s++) digits++;
    if (!digits) return 0;
    if (*s == 'e' || *s == 'E') {
        s++;
        if (*s == '+' || *s == '-') s++;
        if (!(*s >= '0' && *s <= '9')) return 0;
        while (*s >= '0' && *s <= '9') s++;
    }
    return *s == '\0';
}

static int dict_get_is_nonfinite_word(const char *s)
{
    if (*s == '+' || *s == '-') s++;
    return strcasecmp(s, "nan") == 0 || strcasecmp(s, "inf") == 0 || strcasecmp(s, "infinity") == 0;
}

/* Parses the number of token t into *out; -1 with err filled otherwise. */
static int dict_get_number(const dict_entry *e, const dict_token *t, double *out, sl_err *err)
{
    double v;
    if (!t || t->kind != DICT_TOK_WORD) return dict_get_bad(e, t, "expected a number", err);
    if (dict_get_is_nonfinite_word(t->text)) return dict_get_bad(e, t, "not a finite number", err);
    if (!dict_get_is_decimal(t->text)) return dict_get_bad(e, t, "expected a number", err);
    v = strtod(t->text, NULL);
    if (!isfinite(v)) return dict_get_bad(e, t, "not a finite number", err);
    *out = v;
    return 0;
}

int dict_get_scalar(const dict *d, const char *key, double *out, sl_err *err)
{
    const dict_entry *e = dict_get_entry(d, key, err);
    const dict_token *t;
    if (!e) return -1;
    t = dict_get_single(e);
    if (!t) return dict_get_bad(e, NULL, "expected a number", err);
    return dict_get_number(e, t, out, err);
}

int dict_get_int(const dict *d, const char *key, long *out, sl_err *err)
{
    const dict_entry *e = dict_get_entry(d, key, err);
    const dict_token *t;
    const char *s;
    long v;
    if (!e) return -1;
    if (!(t = dict_get_single(e))) return dict_get_bad(e, NULL, "expected an integer", err);
    s = t->text + (t->text[0] == '+' || t->text[0] == '-');
    if (!*s || strspn(s, "0123456789") != strlen(s))
        return dict_get_bad(e, t, "expected an integer", err);
    errno = 0;
    v = strtol(t->text, NULL, 10);
    if (errno == ERANGE) return dict_get_bad(e, t, "integer out of range", err);
    *out = v;
    return 0;
}

int dict_get_word(const dict *d, const char *key, const char **out, sl_err *err)
{
    const dict_entry *e = dict_get_entry(d, key, err);
    if (!e) return -1;
    if (e->sub || e->ntok != 1 ||
        (e->tok[0].kind != DICT_TOK_WORD && e->tok[0].kind != DICT_TOK_STRING))
        return dict_get_bad(e, NULL, "expected a word", err);
    *out = e->tok[0].text;
    return 0;
}

int dict_get_bool(const dict *d, const char *key, int *out, sl_err *err)
{
    static const char *const yes[] = {"on", "yes", "true", "1", "y"};
    static const char *const no[] = {"off", "no", "false", "0", "n"};
    const dict_entry *e = dict_get_entry(d, key, err);
    const dict_token *t;
    if (!e) return -1;
    if ((t = dict_get_single(e)))
        for (size_t i = 0; i < sizeof yes / sizeof *yes; i++) {
            if (strcasecmp(t->text, yes[i]) == 0) return *out = 1, 0;
            if (strcasecmp(t->text, no[i]) == 0) return *out = 0, 0;
        }
    return dict_get_bad(e, t, "expected on/off, yes/no, true/false or 1/0", err);
}

/* Finds the elements of a list value `( ... )` or `N( ... )`: tokens
 * [*first, *last) and the declared count (-1 if none). */
static int dict_get_list(const dict_entry *e, size_t *first, size_t *last, long *count)
{
    const dict_token *t = e->tok;
    size_t open = 0, depth = 0;
    char *end;
    if (e->sub || e->ntok < 2) return -1;
    *count = -1;
    if (t[0].kind == DICT_TOK_WORD) {
        *count = strtol(t[0].text, &end, 10);
        if (*end || *count < 0 || t[0].text[0] == '\0') return -1;
        open = 1;
    }
    if (t[open].kind != DICT_TOK_PUNCT || t[open].text[0] != '(') return -1;
    /* The '(' must close at the very last token. */
    for (size_t i = open; i < e->ntok; i++) {
        if (t[i].kind != DICT_TOK_PUNCT) continue;
        if (t[i].text[0] == '(' || t[i].text[0] == '[') depth++;
        else if (--depth == 0 && i != e->ntok - 1) return -1;
    }
    *first = open + 1;
    *last = e->ntok - 1;
    return 0;
}

/* The list elements of key after its shape and count were checked. */
static const dict_entry *dict_get_list_entry(const dict *d, const char *key, const char *what,
                                             size_t *first, size_t *last, sl_err *err)
{
    const dict_entry *e = dict_get_entry(d, key, err);
    long count;
    if (!e) return NULL;
    if (dict_get_list(e, first, last, &count)) {
        dict_get_bad(e, NULL, what, err);
        return NULL;
    }
    if (count >= 0 && (size_t)count != *last - *first) {
        sl_err_set(err, "%s:%d:%d: keyword '%s': list size %ld does not match its %zu elements",
                   e->file, e->line, e->col, e->key, count, *last - *first);
        return NULL;
    }
    return e;
}

int dict_get_scalar_list(const dict *d, const char *key, double **out, size_t *n, sl_err *err)
{
    size_t first, last;
    const dict_entry *e =
        dict_get_list_entry(d, key, "expected a list of numbers", &first, &last, err);
    double *v;
    *out = NULL;
    *n = 0;
    if (!e) return -1;
    v = sl_malloc((last - first) * sizeof *v, "a list of numbers");
    for (size_t i = first; i < last; i++)
        if (dict_get_number(e, &e->tok[i], &v[i - first], err)) {
            free(v);
            return -1;
        }
    *out = v;
    *n = last - first;
    return 0;
}

int dict_get_word_list(const dict *d, const char *key, char ***out, size_t *n, sl_err *err)
{
    size_t first, last;
    const dict_entry *e =
        dict_get_list_entry(d, key, "expected a list of words", &first, &last, err);
    char **v;
    *out = NULL;
    *n = 0;
    if (!e) return -1;
    for (size_t i = first; i < last; i++)
        if (e->tok[i].kind != DICT_TOK_WORD && e->tok[i].kind != DICT_TOK_STRING)
            return dict_get_bad(e, &e->tok[i], "expected a word in the list", err);
    v = sl_malloc((last - first) * sizeof *v, "a list of words");
    for (size_t i = first; i < last; i++) v[i - first] = sl_strdup(e->tok[i].text);
    *out = v;
    *n = last - first;
    return 0;
}

void dict_free_word_list(char **list, size_t n)
{
    if (!list) return;
    for (size_t i = 0; i < n; i++) free(list[i]);
    free(list);
}

int dict_get_vector(const dict *d, const char *key, double out[3], sl_err *err)
{
    const char *what = "expected a vector (x y z)";
    size_t first, last;
    const dict_entry *e = dict_get_list_entry(d, key, what, &first, &last, err);
    double v[3];
    if (!e) return -1;
    if (last - first != 3) return dict_get_bad(e, NULL, what, err);
    for (size_t i = 0; i < 3; i++)
        if (dict_get_number(e, &e->tok[first + i], &v[i], err)) return -1;
    memcpy(out, v, sizeof v);
    return 0;
}

/* ---- optional variants --------------------------------------------------- */

int dict_get_scalar_or(const dict *d, const char *key, double def, double *out, sl_err *err)
{
    if (!dict_lookup(d, key)) return *out = def, 0;
    return dict_get_scalar(d, key, out, err);
}

int dict_get_int_or(const dict *d, const char *key, long def, long *out, sl_err *err)
{
    if (!dict_lookup(d, key)) return *out = def, 0;
    return dict_get_int(d, key, out, err);
}

int dict_get_word_or(const dict *d, const char *key, const char *def, const char **out, sl_err *err)
{
    if (!dict_lookup(d, key)) return *out = def, 0;
    return dict_get_word(d, key, out, err);
}

int dict_get_bool_or(const dict *d, const char *key, int def, int *out, sl_err *err)
{
    if (!dict_lookup(d, key)) return *out = def, 0;
    return dict_get_bool(d, key, out, err);
}

int dict_get_vector_or(const dict *d, const char *key, const double def[3], double out[3],
                       sl_err *err)
{
    if (!dict_lookup(d, key)) {
        for (int i = 0; i < 3; i++) out[i] = def ? def[i] : 0.0;
        return 0;
    }
    return dict_get_vector(d, key, out, err);
}
