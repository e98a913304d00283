/*
 * dict_var: resolves $variable names with OpenFOAM's scoping rules.
 *
 *   $name      name in the current dictionary, else in the enclosing ones
 *   $a/b       a found as above, then b inside dictionary a
 *   $:a/b $/a/b  from the top-level dictionary
 *   $../name   from the parent dictionary ($../../name: grandparent)
 *
 * Only entries defined before the reference are visible, as in OpenFOAM,
 * because the dictionary being read is not yet part of its parent.
 */
#include "dictionary/dict_internal.h"

#include <string.h>

/* Looks up the first `len` characters of name in scope, then, when outward
 * is set, in each enclosing dictionary. */
static const dict_entry *dict_var_find(const dict *scope, const char *name, size_t len, int outward)
{
    for (; scope; scope = outward ? scope->parent : NULL) {
        const dict_entry *e = dict_find_local(scope, name, len);
        if (e) return e;
    }
    return NULL;
}

/* Strips the leading scope of name; returns the dictionary to start from
 * (NULL past the top) and tells whether the search may go outward. */
static const dict *dict_var_start(const dict *scope, const char **name, int *outward)
{
    const char *s = *name;
    *outward = 1;
    if (*s == ':' || *s == '/') {
        while (scope->parent) scope = scope->parent;
        *outward = 0;
        s++;
    }
    while (scope && s[0] == '.' && s[1] == '.' && (s[2] == '/' || s[2] == '\0')) {
        scope = scope->parent;
        *outward = 0;
        s += s[2] ? 3 : 2;
    }
    *name = s;
    return scope;
}

const dict_entry *dict_var_lookup(const dict *scope, const char *name)
{
    int outward;
    const dict_entry *e;
    const char *slash;
    scope = dict_var_start(scope, &name, &outward);
    if (!scope || !*name) return NULL;
    slash = strchr(name, '/');
    e = dict_var_find(scope, name, slash ? (size_t)(slash - name) : strlen(name), outward);
    while (e && slash) {
        name = slash + 1;
        slash = strchr(name, '/');
        e = e->sub ? dict_find_local(e->sub, name, slash ? (size_t)(slash - name) : strlen(name))
                   : NULL;
    }
    if (e) ((dict_entry *)e)->referenced = 1; /* the tree is ours; marks a macro */
    return e;
}
