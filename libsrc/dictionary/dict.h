/*
 * dict: reader for OpenFOAM-syntax dictionary files (case set-up files).
 *
 * A dictionary is an ordered list of entries `key value;` or `key { ... }`.
 * Supported: the FoamFile header (kept as an ordinary entry), // and block
 * comments, lists `( ... )` (nested, optionally count-prefixed `3(1 2 3)`),
 * "strings" with \" escapes, #include / #includeIfPresent (relative to the
 * including file's folder), $var / ${var} / $a/b / $:a/b / $../x macros,
 * `key $sub;` (copy a dictionary) and `$sub;` (merge its entries).  A
 * repeated key replaces the earlier value but keeps the earlier position
 * (dict_warn_duplicates() reports it when both are written in one file).
 *
 * Every error is returned through an sl_err as "file:line:col: message";
 * nothing here exits or prints except the dict_warn_*() checks.  A parsed tree is
 * immutable, owned by the top-level dict and released with dict_free().
 * Pointers returned by lookups and dict_get_word() stay valid until then.
 */
#ifndef DICT_H
#define DICT_H

#include <stddef.h>

#include "core/sl_log.h"

typedef struct dict dict;             /* ordered entries; may be nested */
typedef struct dict_entry dict_entry; /* one `key value;` or `key {...}` */

/* Limits that turn hostile input into an error instead of a stack overflow. */
#define DICT_MAX_DEPTH   256 /* nesting of dictionaries and lists */
#define DICT_MAX_INCLUDE 32  /* nesting of #include */

/* ---- reading ----------------------------------------------------------- */

/* NULL and err filled on any error (including "cannot open file"). */
dict *dict_read_file(const char *path, sl_err *err);
/* `name` is used in messages; #include paths are relative to the cwd. */
dict *dict_parse_string(const char *text, const char *name, sl_err *err);
/* Frees a top-level dict and everything in it (NULL is fine). */
void dict_free(dict *d);

const char *dict_file(const dict *d); /* file it came from (for messages) */
/* Basename of the file for the top level, the key for sub-dictionaries. */
const char *dict_name(const dict *d);

/* ---- structure --------------------------------------------------------- */

/* `key` may be a scoped path "a/b/c" (searched in d only, not outward). */
const dict_entry *dict_lookup(const dict *d, const char *key);
int dict_has(const dict *d, const char *key);
const dict *dict_sub(const dict *d, const char *key); /* NULL if not a dict */
size_t dict_size(const dict *d);
const dict_entry *dict_entry_at(const dict *d, size_t i);
const char *dict_entry_key(const dict_entry *e);
int dict_entry_line(const dict_entry *e);
int dict_entry_col(const dict_entry *e);
const char *dict_entry_file(const dict_entry *e);
const dict *dict_entry_dict(const dict_entry *e); /* NULL if not a dict */
/* Byte offsets [*begin, *end) of the value text in dict_entry_file(e): from
 * the first value character to just after the last one (for a dictionary
 * the braces included; for `key $var;` the `$var`).  Returns 0 (-1 for NULL). */
int dict_entry_span(const dict_entry *e, long *begin, long *end);
/* Value as text: tokens separated by single spaces, except just inside
 * brackets and after a list size: "1 2 3", "(0 0 -9.81)", "3(1 2 3)",
 * "{ a 1; }".  NULL if e is NULL.  The caller frees the result. */
char *dict_entry_value_text(const dict_entry *e);

/* ---- typed getters ------------------------------------------------------
 * Return 0 on success, nonzero with err filled on failure:
 *   "<file>: missing required keyword '<key>' in dictionary '<name>'"
 *   "<file>:<line>:<col>: keyword '<key>': expected a number, found 'abc'"
 * Numbers must be finite ('nan', 'inf', '1e999' are "not a finite number").
 * On failure the outputs are left unchanged (lists: set to NULL / 0). */
int dict_get_scalar(const dict *d, const char *key, double *out, sl_err *err);
int dict_get_int(const dict *d, const char *key, long *out, sl_err *err);
/* A word or a "string"; *out points into the dictionary. */
int dict_get_word(const dict *d, const char *key, const char **out, sl_err *err);
/* on/off yes/no true/false 1/0 (any letter case). */
int dict_get_bool(const dict *d, const char *key, int *out, sl_err *err);
int dict_get_vector(const dict *d, const char *key, double out[3], sl_err *err);
/* (1 2 3) or 3(1 2 3); *out is malloc'd (even when *n is 0), free() it. */
int dict_get_scalar_list(const dict *d, const char *key, double **out, size_t *n, sl_err *err);
/* (a "b c") or 2(a b); free with dict_free_word_list(). */
int dict_get_word_list(const dict *d, const char *key, char ***out, size_t *n, sl_err *err);
void dict_free_word_list(char **list, size_t n);

/* Optional variants: missing key -> *out = def, return 0; present but
 * malformed -> error as above. */
int dict_get_scalar_or(const dict *d, const char *key, double def, double *out, sl_err *err);
int dict_get_int_or(const dict *d, const char *key, long def, long *out, sl_err *err);
int dict_get_word_or(const dict *d, const char *key, const char *def, const char **out,
                     sl_err *err);
int dict_get_bool_or(const dict *d, const char *key, int def, int *out, sl_err *err);
int dict_get_vector_or(const dict *d, const char *key, const double def[3], double out[3],
                       sl_err *err);

/* ---- checking ------------------------------------------------------------
 * For each entry of d whose key is not in the NULL-terminated `valid` (and
 * is not "FoamFile") print a warning
 *   "<file>:<line>: unknown keyword '<key>' in dictionary '<name>'; did you
 *    mean '<nearest>'?"  (the suggestion only when one is close).
 * After DICT_WARN_MAX such lines the rest are counted in one line
 *   "<file>: ... and 1499990 more unknown keywords in dictionary '<name>'".
 * Returns the number of unknown keys. */
#define DICT_WARN_MAX 10
int dict_warn_unknown(const dict *d, const char *const *valid);
/* Where a key belongs instead: `where` (e.g. "constant/fluidProperties")
 * and its NULL-terminated keys; an array of them ends with where == NULL. */
typedef struct dict_key_home {
    const char *where;
    const char *const *keys;
} dict_key_home;
/* From now on, an unknown key of a top-level dictionary that is valid in one
 * of `homes` (kept, not copied; NULL: none) is reported as
 *   "<file>:<line>: unknown keyword 'eta' in dictionary 'controlDict': it
 *    belongs in constant/fluidProperties (ignored here)".
 * The case reader registers its files' keys. */
void dict_warn_set_homes(const dict_key_home *homes);
/* For each key written twice in one file and dictionary (d and every
 * dictionary below it; not an override of an #include'd or $merged entry):
 *   "<file>:<line>: keyword 'eta' in dictionary 'fluidProperties' is set
 *    twice, at lines 4 and 9: the value of line 9 is used"
 * (at most DICT_WARN_MAX lines, then a count).  Returns the number. */
int dict_warn_duplicates(const dict *d);
/* Nearest valid keyword by Levenshtein distance, NULL if none is within
 * max(2, strlen(key)/2). */
const char *dict_nearest(const char *key, const char *const *valid);
/* Levenshtein edit distance between a and b. */
size_t dict_edit_distance(const char *a, const char *b);

/* ---- stopping on a bad entry ---------------------------------------------
 * The one error path of every reader of case files: stop the program with
 *   "<file>:<line>: keyword '<key>': <why>"
 * (or "<file>: keyword '<key>' (not set: the default): <why>" when the key is
 * absent).  dict_need() stops with err's message when status is non-zero. */
void dict_fatal(const dict *d, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 3, 4), noreturn));
void dict_need(int status, const sl_err *err);
/* v if v > 0, else stop: "must be a positive number". */
double dict_need_positive(const dict *d, const char *key, double v);

#endif
