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

/* Entries used as $variables elsewhere are the user's macros (a resolution
 * knob, say) and are not reported. */
int dict_warn_unknown(const dict *d, const char *const *valid)
{
    int unknown = 0;
    for (size_t i = 0; d && i < d->n; i++) {
        const dict_entry *e = d->entries[i];
        const char *near;
        if (dict_check_known(e->key, valid) || e->referenced) continue;
        unknown++;
        near = dict_nearest(e->key, valid);
        if (near)
            sl_warning("%s:%d: unknown keyword '%s' in dictionary '%s'; did you mean '%s'?",
                       e->file, e->line, e->key, d->name, near);
        else
            sl_warning("%s:%d: unknown keyword '%s' in dictionary '%s'", e->file, e->line,
                       e->key, d->name);
    }
    return unknown;
}
