/*
 * dictedit: in-place editing of OpenFOAM-syntax dictionary files, shared by
 * editDictionary and sweepCase.
 *
 * An edit changes only the bytes of one value (dict_entry_span of the
 * parsed entry), so comments, layout, #include directives and $variables
 * elsewhere stay byte-for-byte as they were.  When the entry is written in
 * an #include'd file, that file is the one edited.  Every edit is checked by
 * parsing the result before (top file) or right after (included file, undone
 * on failure) it replaces the file, through a temp file and a rename, so a
 * dictionary is never left half-written or unreadable.
 *
 * Entry paths are scoped "a/b/c" as in dict_lookup(); an exact key
 * containing '/' wins.  Errors name the file (and line where there is one).
 */
#ifndef DICTEDIT_H
#define DICTEDIT_H

#include <stdio.h>

#include "core/sl_log.h"
#include "dictionary/dict.h"

/* What an edit did, for the caller to report. */
typedef struct dedit_change {
    char file[4096]; /* the file changed (an #include'd one, possibly) */
    int line;        /* line of the entry's key in that file */
    int added;       /* dedit_set: 1 if the entry was new */
    int removed;     /* dedit_remove: definitions removed (a key repeats) */
} dedit_change;

/* Set entry `path` of the dictionary file `file` to the value text `value`
 * (OpenFOAM syntax: "0.5", "(0 0 -9.81)", "\"a b\"", "{ a 1; }").  A missing
 * entry is added at the end of its dictionary, which must exist.  The value
 * must be one value: "1; b 2" is refused.  0, or nonzero with err filled. */
int dedit_set(const char *file, const char *path, const char *value, dedit_change *ch, sl_err *err);

/* dedit_set on `file` (a path inside the folder `root`, e.g. a case or a
 * clone of one), refused when the change would land outside root: when the
 * entry (or, for a new one, the dictionary it is added to) is written in an
 * #include'd file, or through a symlink, outside root -- it would change a
 * shared file for every case.  The error names the entry, the file holding
 * it and root. */
int dedit_set_inside(const char *root, const char *file, const char *path, const char *value,
                     dedit_change *ch, sl_err *err);

/* Remove entry `path` (every definition of it, with the lines it stands on
 * when nothing else is on them).  0, or nonzero with err filled; a missing
 * entry is an error naming it. */
int dedit_remove(const char *file, const char *path, dedit_change *ch, sl_err *err);

/* The entry at `path` of d, or NULL with err filled: "<file>: no entry 'a/b'
 * (dictionary 'a' has: x, y)" with a "did you mean" when one is close. */
const dict_entry *dedit_lookup(const dict *d, const char *path, sl_err *err);

/* The value of e as written in its file ("$var", "{ ... }" with comments),
 * or NULL with err filled.  The caller frees the result. */
char *dedit_raw_value(const dict_entry *e, sl_err *err);

/* Print d (or one entry) in OpenFOAM layout, with #include and $var resolved:
 * keys padded to 16 columns, four spaces per level. */
void dedit_print_dict(FILE *out, const dict *d, int level);
void dedit_print_entry(FILE *out, const dict_entry *e, int level);

/* Whole file in a NUL-terminated buffer, or NULL with err filled. */
char *dedit_read_text(const char *file, size_t *len, sl_err *err);

#endif
