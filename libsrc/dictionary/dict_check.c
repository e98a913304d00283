/*
 * dict_check: warns about keywords a reader does not know, with a "did you
 * mean" suggestion, because a misspelt optional keyword is otherwise
 * silently ignored and the default used instead.
 */
#include "dictionary/dict_internal.h"

#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

size_t dict_edit_distance(const char *a, const char *b)
{
    size_t na = strlen(a), nb = strlen(b), result;
    /* Two rows of the classic dynamic programme. */
    size_t *prev = sl_malloc((nb + 1) * sizeof *prev, "edit distance");
    size_t *cur = sl_malloc((nb + 1) * sizeof *cur, "edit distance");
    for (size_t j = 0; j <= nb; j++) prev[j] = j;
    for (size_t i = 1; i <= na; i++) {
        cur[0] = i;
        for (size_t j = 1; j <= nb; j++) {
            size_t sub = prev[j - 1] + (a[i - 1] != b[j - 1]);
            size_t del = prev[j] + 1, ins = cur[j - 1] + 1;
            cur[j] = sub < del ? (sub < ins ? sub : ins) : (del < ins ? del : ins);
        }
        size_t *tmp = prev;
        prev = cur;
        cur = tmp;
    }
    result = prev[nb];
    free(prev);
    free(cur);
    return result;
}

const char *dict_nearest(const char *key, const char *const *valid)
{
    size_t len, limit, best_d = (size_t)-1;
    const char *best = NULL;
    if (!key || !valid) return NULL;
    len = strlen(key);
    limit = len / 2 > 2 ? len / 2 : 2;
    for (size_t i = 0; valid[i]; i++) {
        size_t dist = dict_edit_distance(key, valid[i]);
        if (dist < best_d) {
            best_d = dist;
            best = valid[i];
        }
    }
    return best_d <= limit ? best : NULL;
}

static int dict_check_known(const char *key, const char *const *valid)
{
    if (strcmp(key, "FoamFile") == 0) return 1;
    for (size_t i = 0; valid && valid[i]; i++)
        if (strcmp(key, valid[i]) == 0) return 1;
    return 0;
}

/* The other file a misplaced key belongs in (`eta` in controlDict), or NULL. */
static const char *dict_check_home(const char *key, const dict_key_home *homes)
{
    for (size_t h = 0; homes && homes[h].where; h++)
        if (dict_check_known(key, homes[h].keys) && strcmp(key, "FoamFile") != 0)
            return homes[h].where;
    return NULL;
}

static void dict_check_report(const dict *d, const dict_entry *e, const char *const *valid,
                              const dict_key_home *homes)
{
    const char *home = dict_check_home(e->key, homes);
    const char *near = home ? NULL : dict_nearest(e->key, valid);
    if (home)
        sl_warning("%s:%d: unknown keyword '%s' in dictionary '%s': it belongs in %s (ignored "
                   "here)",
                   e->file, e->line, e->key, d->name, home);
    else if (near)
        sl_warning("%s:%d: unknown keyword '%s' in dictionary '%s'; did you mean '%s'?", e->file,
                   e->line, e->key, d->name, near);
    else
        sl_warning("%s:%d: unknown keyword '%s' in dictionary '%s'", e->file, e->line, e->key,
                   d->name);
}

/* Entries used as $variables elsewhere are the user's macros (a resolution
 * knob, say) and are not reported.  After DICT_WARN_MAX lines the rest are
 * counted in one closing line, so that a file of a million stray keys does
 * not bury the log. */
static const dict_key_home *dict_check_homes;

void dict_warn_set_homes(const dict_key_home *homes) { dict_check_homes = homes; }

int dict_warn_unknown(const dict *d, const char *const *valid)
{
    const dict_key_home *homes = d && !d->parent ? dict_check_homes : NULL;
    int unknown = 0;
    const dict_entry *last = NULL;
    for (size_t i = 0; d && i < d->n; i++) {
        const dict_entry *e = d->entries[i];
        if (dict_check_known(e->key, valid) || e->referenced) continue;
        if (unknown++ < DICT_WARN_MAX) dict_check_report(d, e, valid, homes);
        last = e;
    }
    if (unknown > DICT_WARN_MAX)
        sl_warning("%s: ... and %d more unknown keywords in dictionary '%s' (the last at line "
                   "%d)",
                   d->file, unknown - DICT_WARN_MAX, d->name, last->line);
    return unknown;
}

/* Duplicates in d and below it; *shown counts the lines printed so far. */
static int dict_check_duplicates(const dict *d, int *shown)
{
    int n = 0;
    for (size_t i = 0; d && i < d->n; i++) {
        const dict_entry *e = d->entries[i];
        if (e->prev_line > 0) {
            n++;
            if ((*shown)++ < DICT_WARN_MAX)
                sl_warning("%s:%d: keyword '%s' in dictionary '%s' is set twice, at lines %d and "
                           "%d: the value of line %d is used",
                           e->file, e->line, e->key, d->name, e->prev_line, e->line, e->line);
        }
        if (e->sub) n += dict_check_duplicates(e->sub, shown);
    }
    return n;
}

int dict_warn_duplicates(const dict *d)
{
    int shown = 0, n = dict_check_duplicates(d, &shown);
    if (n > DICT_WARN_MAX)
        sl_warning("%s: ... and %d more keywords set twice", d ? d->file : "?", n - DICT_WARN_MAX);
    return n;
}
