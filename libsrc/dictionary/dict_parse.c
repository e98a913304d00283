/*
 * dict_parse: reads dictionary files and strings into a tree -- entries,
 * sub-dictionaries, #include directives and `$sub;` merges.  Primitive
 * values (`key 1 (2 3);`) are read by dict_value.c.
 */
#include "dictionary/dict_internal.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/sl_mem.h"

int dict_parse_error(const dict_lexer *lx, int line, int col, const char *fmt, ...)
{
    /* The message ends up in an sl_err of SL_ERR_LEN bytes anyway. */
    char msg[SL_ERR_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sl_err_set(lx->err, "%s:%d:%d: %s", lx->file, line, col, msg);
    return -1;
}

/* A key written twice in one file and dictionary is most likely a
 * copy-paste mistake: the later line is marked for dict_warn_duplicates.
 * Overriding what an #include or a `$sub;` merge brought in is the usual
 * OpenFOAM idiom and is not marked. */
void dict_parse_add(const dict_lexer *lx, dict *d, dict_entry *e)
{
    /* An included file's header describes that file, not the including one. */
    if (lx->is_include && d == lx->top && strcmp(e->key, "FoamFile") == 0) {
        dict_entry_free(e);
        return;
    }
    const dict_entry *old = dict_find_local(d, e->key, strlen(e->key));
    if (old && !old->copied && old->file == e->file && old->line != e->line)
        e->prev_line = old->line; /* (one line twice: a file #include'd twice) */
    dict_insert(d, e);
}

/* ---- files --------------------------------------------------------------- */

/* Whole file in a NUL-terminated buffer; NULL with *errnum set on failure. */
static char *dict_parse_slurp(const char *path, size_t *len, int *errnum)
{
    struct stat st;
    /* a dictionary is a regular file: a device or a pipe (/dev/zero) could
     * be read forever */
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        *errnum = S_ISDIR(st.st_mode) ? EISDIR : EINVAL;
        return NULL;
    }
    FILE *f = fopen(path, "rb");
    size_t n = 0, cap = 4096;
    char *buf;
    if (!f) {
        *errnum = errno;
        return NULL;
    }
    buf = sl_malloc(cap, "a dictionary file");
    for (;;) {
        size_t got;
        if (cap - n < 2) buf = sl_realloc(buf, cap *= 2, "a dictionary file");
        got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0) break;
    }
    if (ferror(f)) {
        *errnum = errno ? errno : EIO; /* e.g. EISDIR for a directory */
        fclose(f);
        free(buf);
        return NULL;
    }
    fclose(f);
    buf[n] = '\0';
    *len = n;
    return buf;
}

/* NUL bytes would silently end C strings: reject binary files up front. */
static int dict_parse_check_nul(const char *text, size_t len, const char *file, sl_err *err)
{
    const char *nul = memchr(text, '\0', len);
    int line, col;
    if (!nul) return 0;
    dict_lex_locate(text, (size_t)(nul - text), &line, &col);
    sl_err_set(err, "%s:%d:%d: invalid character 0x00 (binary or corrupt file?)", file, line, col);
    return -1;
}

/* Folder of path for relative #include, NULL for the cwd. */
static char *dict_parse_dirname(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t n;
    char *dir;
    if (!slash) return NULL;
    n = slash == path ? 1 : (size_t)(slash - path);
    dir = sl_malloc(n + 1, "a folder name");
    memcpy(dir, path, n);
    dir[n] = '\0';
    return dir;
}

static char *dict_parse_join(const char *dir, const char *rel)
{
    dict_buf b = {0};
    if (!dir || rel[0] == '/') return sl_strdup(rel);
    dict_buf_puts(&b, dir, strlen(dir));
    if (dir[strlen(dir) - 1] != '/') dict_buf_putc(&b, '/');
    dict_buf_puts(&b, rel, strlen(rel));
    return dict_buf_take(&b);
}

static const char *dict_parse_basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* ---- the include stack ---------------------------------------------------- */

static void dict_parse_push(dict_parser *p, const char *real)
{
    if (p->nstack == p->capstack) {
        p->capstack = p->capstack ? 2 * p->capstack : 8;
        p->stack = sl_realloc(p->stack, p->capstack * sizeof *p->stack, "include stack");
    }
    p->stack[p->nstack++] = real;
}

static int dict_parse_on_stack(const dict_parser *p, const char *real)
{
    for (size_t i = 0; i < p->nstack; i++)
        if (p->stack[i] && strcmp(p->stack[i], real) == 0) return 1;
    return 0;
}

/* Appends where the file with the error was included from, so that the
 * user can tell which of several includes of one file went wrong. */
static void dict_parse_note_include(dict_parser *p, const dict_lexer *from, int line, int col)
{
    char msg[SL_ERR_LEN];
    if (!p->err) return;
    memcpy(msg, p->err->msg, sizeof msg);
    msg[sizeof msg - 1] = '\0';
    sl_err_set(p->err, "%s (included from %s:%d:%d)", msg, from->file, line, col);
}

/* Reads the file at `path` into d as if its text stood where the
 * #include is (from, line, col: the directive, for messages). */
static int dict_parse_include(dict_parser *p, const dict_lexer *from, int line, int col, dict *d,
                              const char *path, int optional)
{
    dict_lexer lx;
    size_t len = 0;
    int errnum = 0, rc;
    char *real = realpath(path, NULL), *text, *dir;
    if (real && dict_parse_on_stack(p, real)) {
        free(real);
        return dict_parse_error(from, line, col, "#include loop: '%s' is already being read", path);
    }
    if (p->nstack > DICT_MAX_INCLUDE) {
        free(real);
        return dict_parse_error(from, line, col, "#include of '%s' nested deeper than %d levels",
                                path, DICT_MAX_INCLUDE);
    }
    text = dict_parse_slurp(path, &len, &errnum);
    if (!text) {
        free(real);
        if (optional && errnum == ENOENT) return 0;
        return dict_parse_error(from, line, col, "cannot open file '%s': %s", path,
                                strerror(errnum));
    }
    dict_lex_init(&lx, text, len, dict_intern_file(d, path), p->err);
    lx.dir = dir = dict_parse_dirname(path);
    lx.top = d;
    lx.is_include = 1;
    rc = dict_parse_check_nul(text, len, lx.file, p->err);
    dict_parse_push(p, real);
    if (!rc) rc = dict_parse_body(p, &lx, d, 0, 0);
    if (rc) dict_parse_note_include(p, from, line, col);
    p->nstack--;
    dict_lex_done(&lx);
    free(dir);
    free(text);
    free(real);
    return rc;
}

/* ---- directives and merges ----------------------------------------------- */

/* 0 for #include, 1 for #includeIfPresent, -1 (err filled) for the rest. */
static int dict_parse_include_kind(const dict_lexer *lx)
{
    const dict_lx_tok *t = &lx->tok;
    if (strcmp(t->text, "#include") == 0) return 0;
    if (strcmp(t->text, "#includeIfPresent") == 0 || strcmp(t->text, "#sinclude") == 0) return 1;
    if (strncmp(t->text, "#include", 8) == 0)
        return dict_parse_error(lx, t->line, t->col, "directive '%s' is not supported", t->text);
    return dict_parse_error(lx, t->line, t->col, "unknown directive '%s'", t->text);
}

static int dict_parse_directive(dict_parser *p, dict_lexer *lx, dict *d)
{
    int line = lx->tok.line, col = lx->tok.col, optional, rc;
    char *name, *path;
    if ((optional = dict_parse_include_kind(lx)) < 0) return -1;
    name = dict_lex_take(lx);
    if (dict_lex_next(lx)) {
        free(name);
        return -1;
    }
    /* The file name must follow on the same line, or a forgotten name would
     * swallow the next keyword. */
    if ((lx->tok.kind != DICT_LX_STRING && lx->tok.kind != DICT_LX_WORD) || lx->tok.line != line) {
        rc = dict_parse_error(lx, line, col, "expected a file name after '%s'", name);
        free(name);
        return rc;
    }
    free(name);
    path = dict_parse_join(lx->dir, lx->tok.text);
    rc = dict_parse_include(p, lx, line, col, d, path, optional);
    free(path);
    return rc;
}

/* A bare `$sub;` copies the entries of dictionary sub into d. */
static int dict_parse_merge(dict_parser *p, dict_lexer *lx, dict *d)
{
    const dict_lx_tok *t = &lx->tok;
    const dict_entry *e = dict_var_lookup(d, t->text);
    if (!e) return dict_parse_error(lx, t->line, t->col, "undefined variable '$%s'", t->text);
    if (!e->sub)
        return dict_parse_error(lx, t->line, t->col,
                                "cannot merge '$%s' into dictionary '%s': not a dictionary",
                                t->text, d->name);
    if (p->depth + dict_height(e->sub) > DICT_MAX_DEPTH)
        return dict_parse_error(lx, t->line, t->col,
                                "'$%s' nests dictionaries deeper than %d levels", t->text,
                                DICT_MAX_DEPTH);
    dict_merge(d, e->sub);
    return 0;
}

/* ---- entries ------------------------------------------------------------- */

static int dict_parse_subdict(dict_parser *p, dict_lexer *lx, dict *d, char *key, int line, int col)
{
    dict_entry *e = dict_entry_new(key, lx->file, line, col);
    int open_line = lx->tok.line, open_col = lx->tok.col, rc;
    e->begin = lx->tok.begin;
    if (p->depth + 1 > DICT_MAX_DEPTH) {
        dict_entry_free(e);
        return dict_parse_error(lx, open_line, open_col,
                                "dictionaries and lists nested deeper than %d levels",
                                DICT_MAX_DEPTH);
    }
    e->sub = dict_new(key, lx->file, d);
    p->depth++;
    rc = dict_parse_body(p, lx, e->sub, open_line, open_col);
    p->depth--;
    if (rc) {
        dict_entry_free(e);
        return -1;
    }
    e->end = lx->tok.end;
    dict_parse_add(lx, d, e);
    return 0;
}

static int dict_parse_entry(dict_parser *p, dict_lexer *lx, dict *d)
{
    int line = lx->tok.line, col = lx->tok.col, rc;
    char *key = dict_lex_take(lx);
    const dict_lx_tok *t = &lx->tok;
    if (!key[0]) {
        free(key);
        return dict_parse_error(lx, line, col, "empty keyword");
    }
    if (dict_lex_next(lx)) {
        free(key);
        return -1;
    }
    if (t->kind == DICT_LX_PUNCT && t->punct == '{')
        return dict_parse_subdict(p, lx, d, key, line, col);
    if (t->kind == DICT_LX_EOF ||
        (t->kind == DICT_LX_PUNCT && (t->punct == ';' || t->punct == '}'))) {
        rc = dict_parse_error(lx, line, col, "keyword '%s' has no value", key);
        free(key);
        return rc;
    }
    return dict_value_parse(p, lx, d, key, line, col);
}

/* Punctuation where a keyword is expected: 1 at the closing '}', 0 to go
 * on, -1 on error. */
static int dict_parse_punct(const dict_lexer *lx, int open_line)
{
    const dict_lx_tok *t = &lx->tok;
    if (t->punct == ';') return 0; /* stray ';' (e.g. after '}') is harmless */
    if (t->punct == '}') {
        if (open_line) return 1;
        return dict_parse_error(lx, t->line, t->col, "unexpected '}' (unbalanced braces)");
    }
    if (t->punct == '{')
        return dict_parse_error(lx, t->line, t->col, "unexpected '{': empty keyword");
    return dict_parse_error(lx, t->line, t->col, "unexpected '%c': expected a keyword", t->punct);
}

int dict_parse_body(dict_parser *p, dict_lexer *lx, dict *d, int open_line, int open_col)
{
    for (;;) {
        int rc = 0;
        if (dict_lex_next(lx)) return -1;
        switch (lx->tok.kind) {
        case DICT_LX_EOF:
            if (!open_line) return 0;
            return dict_parse_error(lx, open_line, open_col,
                                    "unbalanced braces: '{' of dictionary '%s' is not closed "
                                    "before the end of the file",
                                    d->name);
        case DICT_LX_PUNCT:
            rc = dict_parse_punct(lx, open_line);
            if (rc) return rc > 0 ? 0 : -1;
            break;
        case DICT_LX_DIRECTIVE:
            rc = dict_parse_directive(p, lx, d);
            break;
        case DICT_LX_VAR:
            rc = dict_parse_merge(p, lx, d);
            break;
        default:
            rc = dict_parse_entry(p, lx, d);
            break;
        }
        if (rc) return -1;
    }
}

/* ---- entry points ---------------------------------------------------------- */

static dict *dict_parse_text(const char *text, size_t len, const char *file, const char *dir,
                             const char *real, sl_err *err)
{
    dict *root = dict_new(dict_parse_basename(file), NULL, NULL);
    dict_parser p = {.err = err};
    dict_lexer lx;
    int rc;
    root->file = dict_intern_file(root, file);
    dict_lex_init(&lx, text, len, root->file, err);
    lx.dir = dir;
    lx.top = root;
    dict_parse_push(&p, real);
    rc = dict_parse_check_nul(text, len, root->file, err);
    if (!rc) rc = dict_parse_body(&p, &lx, root, 0, 0);
    dict_lex_done(&lx);
    free(p.stack);
    if (rc) {
        dict_free(root);
        return NULL;
    }
    return root;
}

dict *dict_read_file(const char *path, sl_err *err)
{
    size_t len = 0;
    int errnum = 0;
    char *text, *real, *dir;
    dict *d;
    if (!path) {
        sl_err_set(err, "cannot open file '(null)': no file name given");
        return NULL;
    }
    text = dict_parse_slurp(path, &len, &errnum);
    if (!text) {
        sl_err_set(err, "cannot open file '%s': %s", path, strerror(errnum));
        return NULL;
    }
    real = realpath(path, NULL);
    dir = dict_parse_dirname(path);
    d = dict_parse_text(text, len, path, dir, real, err);
    free(dir);
    free(real);
    free(text);
    return d;
}

dict *dict_parse_string(const char *text, const char *name, sl_err *err)
{
    if (!name) name = "<string>";
    if (!text) {
        sl_err_set(err, "%s: no text to parse", name);
        return NULL;
    }
    return dict_parse_text(text, strlen(text), name, NULL, NULL, err);
}
