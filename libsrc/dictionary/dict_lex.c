/*
 * dict_lex: splits OpenFOAM dictionary text into tokens (words, numbers,
 * "strings", $variables, #directives and the punctuation { } ( ) [ ] ;),
 * skipping comments and tracking line, column and byte offset of each token
 * for error messages and in-place editing.
 */
#include "dictionary/dict_internal.h"

#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

void dict_lex_init(dict_lexer *lx, const char *text, size_t len, const char *file, sl_err *err)
{
    memset(lx, 0, sizeof *lx);
    lx->text = text;
    lx->len = len;
    lx->line = 1;
    lx->col = 1;
    lx->file = file;
    lx->err = err;
    /* A UTF-8 byte-order mark is not content; offsets stay file offsets. */
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) lx->pos = 3;
}

void dict_lex_done(dict_lexer *lx)
{
    free(lx->tok.text);
    lx->tok.text = NULL;
}

char *dict_lex_take(dict_lexer *lx)
{
    char *s = lx->tok.text;
    lx->tok.text = NULL;
    return s;
}

void dict_lex_locate(const char *text, size_t offset, int *line, int *col)
{
    *line = 1;
    *col = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n') {
            ++*line;
            *col = 1;
        } else {
            ++*col;
        }
    }
}

/* The character `ahead` places on, or -1 at the end of the text. */
static int dict_lex_peek(const dict_lexer *lx, size_t ahead)
{
    size_t i = lx->pos + ahead;
    return i < lx->len ? (unsigned char)lx->text[i] : -1;
}

static void dict_lex_advance(dict_lexer *lx)
{
    if (lx->text[lx->pos] == '\n') {
        lx->line++;
        lx->col = 1;
    } else {
        lx->col++;
    }
    lx->pos++;
}

static int dict_lex_is_space(int c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

/* Control characters, DEL and non-ASCII bytes are only allowed inside
 * strings and comments: anywhere else they mean a binary or corrupt file. */
static int dict_lex_is_invalid(int c)
{
    return c == 0 || (c < 0x20 && !dict_lex_is_space(c)) || c >= 0x7f;
}

static int dict_lex_error_at(dict_lexer *lx, int line, int col, const char *what)
{
    sl_err_set(lx->err, "%s:%d:%d: %s", lx->file, line, col, what);
    return -1;
}

static int dict_lex_invalid(dict_lexer *lx, int c)
{
    sl_err_set(lx->err, "%s:%d:%d: invalid character 0x%02x (binary or corrupt file?)", lx->file,
               lx->line, lx->col, (unsigned)c);
    return -1;
}

static int dict_lex_comment_start(const dict_lexer *lx)
{
    return dict_lex_peek(lx, 0) == '/' &&
        (dict_lex_peek(lx, 1) == '/' || dict_lex_peek(lx, 1) == '*');
}

static int dict_lex_block_comment(dict_lexer *lx)
{
    int line = lx->line, col = lx->col;
    dict_lex_advance(lx);
    dict_lex_advance(lx);
    for (;;) {
        int c = dict_lex_peek(lx, 0);
        if (c == -1) return dict_lex_error_at(lx, line, col, "unterminated block comment");
        if (c == 0) return dict_lex_invalid(lx, c);
        if (c == '*' && dict_lex_peek(lx, 1) == '/') break;
        dict_lex_advance(lx);
    }
    dict_lex_advance(lx);
    dict_lex_advance(lx);
    return 0;
}

static int dict_lex_skip(dict_lexer *lx)
{
    for (;;) {
        int c = dict_lex_peek(lx, 0);
        if (dict_lex_is_space(c)) {
            dict_lex_advance(lx);
        } else if (c == '/' && dict_lex_peek(lx, 1) == '/') {
            while (dict_lex_peek(lx, 0) != -1 && dict_lex_peek(lx, 0) != '\n') dict_lex_advance(lx);
        } else if (c == '/' && dict_lex_peek(lx, 1) == '*') {
            if (dict_lex_block_comment(lx)) return -1;
        } else {
            return 0;
        }
    }
}

/* Characters that can continue a word (brackets are handled by the caller). */
static int dict_lex_is_word_char(int c)
{
    return c != -1 && !dict_lex_is_space(c) && !dict_lex_is_invalid(c) && !strchr("{};\"[]()", c);
}

static int dict_lex_is_digit(int c) { return c >= '0' && c <= '9'; }

static int dict_lex_starts_number(const dict_lexer *lx)
{
    int c0 = dict_lex_peek(lx, 0), c1 = dict_lex_peek(lx, 1);
    if (dict_lex_is_digit(c0)) return 1;
    if (c0 == '.') return dict_lex_is_digit(c1);
    if (c0 == '+' || c0 == '-')
        return dict_lex_is_digit(c1) || (c1 == '.' && dict_lex_is_digit(dict_lex_peek(lx, 2)));
    return 0;
}

static char *dict_lex_copy(const dict_lexer *lx, size_t from)
{
    size_t n = lx->pos - from;
    char *s = sl_malloc(n + 1, "a dictionary token");
    memcpy(s, lx->text + from, n);
    s[n] = '\0';
    return s;
}

/* A number ends at '(' (count-prefixed list "3(1 2 3)"); any other word may
 * contain balanced parentheses like OpenFOAM's "div(phi,U)". */
static int dict_lex_word(dict_lexer *lx)
{
    size_t from = lx->pos;
    int numeric = dict_lex_starts_number(lx), depth = 0;
    for (;;) {
        int c = dict_lex_peek(lx, 0);
        if (c == '(' && !numeric) depth++;
        else if (c == ')' && depth > 0) depth--;
        else if (!dict_lex_is_word_char(c) || dict_lex_comment_start(lx)) break;
        dict_lex_advance(lx);
    }
    lx->tok.kind = DICT_LX_WORD;
    lx->tok.text = dict_lex_copy(lx, from);
    if (depth > 0) {
        sl_err_set(lx->err, "%s:%d:%d: unbalanced '(' in word '%s'", lx->file, lx->tok.line,
                   lx->tok.col, lx->tok.text);
        return -1;
    }
    return 0;
}

/* \" and \\ are escapes, backslash-newline continues the line; any other
 * backslash is kept (OpenFOAM keeps them for regular expressions). */
static int dict_lex_string(dict_lexer *lx)
{
    dict_buf b = {0};
    dict_lex_advance(lx);
    for (;;) {
        int c = dict_lex_peek(lx, 0), n = dict_lex_peek(lx, 1);
        if (c == -1 || c == '\n') {
            free(b.s);
            return dict_lex_error_at(lx, lx->tok.line, lx->tok.col, "unterminated string");
        }
        if (c == '"') break;
        if (c == 0 || (c < 0x20 && c != '\t' && c != '\r')) {
            free(b.s);
            return dict_lex_invalid(lx, c);
        }
        if (c == '\\' && (n == '"' || n == '\\' || n == '\n')) {
            dict_lex_advance(lx);
            if (n != '\n') dict_buf_putc(&b, (char)n);
        } else {
            dict_buf_putc(&b, (char)c);
        }
        dict_lex_advance(lx);
    }
    dict_lex_advance(lx);
    lx->tok.kind = DICT_LX_STRING;
    lx->tok.text = dict_buf_take(&b);
    return 0;
}

/* $name, $a/b, $:a/b, $../a or ${name}; the text is the name only. */
static int dict_lex_var(dict_lexer *lx)
{
    size_t from;
    int braced = dict_lex_peek(lx, 1) == '{';
    dict_lex_advance(lx);
    if (braced) dict_lex_advance(lx);
    from = lx->pos;
    while (dict_lex_is_word_char(dict_lex_peek(lx, 0)) && !dict_lex_comment_start(lx))
        dict_lex_advance(lx);
    lx->tok.kind = DICT_LX_VAR;
    lx->tok.text = dict_lex_copy(lx, from);
    if (braced && dict_lex_peek(lx, 0) != '}')
        return dict_lex_error_at(lx, lx->tok.line, lx->tok.col, "unterminated '${'");
    if (braced) dict_lex_advance(lx);
    if (lx->tok.text[0] == '\0')
        return dict_lex_error_at(lx, lx->tok.line, lx->tok.col,
                                 "expected a variable name after '$'");
    return 0;
}

static int dict_lex_directive(dict_lexer *lx)
{
    size_t from = lx->pos;
    dict_lex_advance(lx);
    while (dict_lex_is_word_char(dict_lex_peek(lx, 0)) && !dict_lex_comment_start(lx))
        dict_lex_advance(lx);
    lx->tok.kind = DICT_LX_DIRECTIVE;
    lx->tok.text = dict_lex_copy(lx, from);
    return 0;
}

static int dict_lex_dispatch(dict_lexer *lx)
{
    int c = dict_lex_peek(lx, 0);
    if (c == -1) {
        lx->tok.kind = DICT_LX_EOF;
        return 0;
    }
    if (strchr("{}()[];", c)) {
        lx->tok.kind = DICT_LX_PUNCT;
        lx->tok.punct = (char)c;
        dict_lex_advance(lx);
        return 0;
    }
    if (c == '"') return dict_lex_string(lx);
    if (c == '$') return dict_lex_var(lx);
    if (c == '#') return dict_lex_directive(lx);
    if (dict_lex_is_invalid(c)) return dict_lex_invalid(lx, c);
    return dict_lex_word(lx);
}

int dict_lex_next(dict_lexer *lx)
{
    dict_lx_tok *t = &lx->tok;
    free(t->text);
    memset(t, 0, sizeof *t);
    if (dict_lex_skip(lx)) return -1;
    t->line = t->end_line = lx->line;
    t->col = lx->col;
    t->begin = (long)lx->pos;
    if (dict_lex_dispatch(lx)) return -1;
    t->end = (long)lx->pos;
    /* No token ends with a newline, so the lexer's line is the last one. */
    t->end_line = lx->line;
    t->end_col = lx->col;
    return 0;
}
