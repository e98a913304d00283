/*
 * dictedit_inside: dedit_set for the copies of a case that sweepCase and
 * stableTimeStep make -- refused when the entry lives in a file outside the
 * copy (an #include of a shared file, a symlink), which the edit would
 * change for every case at once (see dictedit.h).
 */
#include "dictedit/dictedit.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

/* The file a dedit_set of `path` in `file` would change: where the entry
 * (or the nearest dictionary above it, which a new entry is added to) is
 * written; NULL with err filled if file does not read. */
static char *dedit_owner(const char *file, const char *path, sl_err *err)
{
    dict *d = dict_read_file(file, err);
    if (!d) return NULL;
    char *parent = sl_strdup(path), *slash;
    const dict_entry *e = dict_lookup(d, path);
    while (!e && (slash = strrchr(parent, '/'))) {
        *slash = '\0';
        e = dict_lookup(d, parent);
    }
    char *owner = sl_strdup(e ? dict_entry_file(e) : file);
    free(parent);
    dict_free(d);
    return owner;
}

int dedit_set_inside(const char *root, const char *file, const char *path, const char *value,
                     dedit_change *ch, sl_err *err)
{
    char rr[PATH_MAX], ro[PATH_MAX], *owner = dedit_owner(file, path, err);
    if (!owner) return 1;
    if (!realpath(root, rr) || !realpath(owner, ro)) {
        sl_err_set(err, "cannot resolve '%s' or '%s': %s", root, owner, strerror(errno));
        free(owner);
        return 1;
    }
    size_t n = strlen(rr);
    if (strncmp(ro, rr, n) != 0 || ro[n] != '/') {
        sl_err_set(err,
                   "'%s' of %s is written in %s, outside %s (an #include of a shared file, "
                   "or a symlink): setting it would change that file for every case; copy "
                   "it into the case",
                   path, file, owner, root);
        free(owner);
        return 1;
    }
    free(owner);
    return dedit_set(file, path, value, ch, err);
}
