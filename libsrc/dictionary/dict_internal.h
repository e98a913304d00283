/*
 * dict_internal: data structures and functions shared by the files of the
 * dictionary parser (tree, lexer, parser, macros, getters).  Not part of the
 * public API; include "dictionary/dict.h" instead.
 */
#ifndef DICT_INTERNAL_H
#define DICT_INTERNAL_H

#include <stddef.h>

#include "dictionary/dict.h"

/* ---- the tree ------------------------------------------------------------ */

typedef enum {
    DICT_TOK_WORD,   /* word or number, as written */
    DICT_TOK_STRING, /* "string", text without quotes and escapes */
    DICT_TOK_PUNCT,  /* one of ( ) [ ] */
    DICT_TOK_DICT    /* a { ... } inside a list */
} dict_tok_kind;

/* One token of a primitive value.  file/line/col are where it was written
 * (for a value copied by $var: where the original was written). */
typedef struct dict_token {
    dict_tok_kind kind;
    char *text; /* NULL for DICT_TOK_DICT */
    dict *sub;  /* DICT_TOK_DICT only */
    const char *file;
    int line, col;
} dict_token;

struct dict_entry {
    char *key;
    const char *file; /* interned in the top-level dict */
    int line, col;    /* of the key */
    long begin, end;  /* byte offsets of the value text in `file` */
    dict *sub;        /* non-NULL for a dictionary entry ... */
    dict_token *tok;  /* ... otherwise the value tokens */
    size_t ntok;
    int referenced; /* named by a $variable: a user's macro, not unknown */
    int copied;     /* made by $var or a `$sub;` merge, not written here */
    int prev_line;  /* > 0: the same key was written before in the same file
                         and dictionary, at this line (dict_warn_duplicates) */
};

/* File names referred to by entries and tokens, owned by the top level so
 * that every `const char *file` in the tree lives as long as the tree. */
typedef struct dict_files {
    char **names;
    size_t n, cap;
} dict_files;

struct dict {
    char *name;
    const char *file;
    dict *parent;         /* enclosing scope; NULL at the top level */
    dict_entry **entries; /* pointers so that entries never move */
    size_t n, cap;
    size_t *index;     /* hash of keys -> entry number + 1; large dicts only */
    size_t index_cap;  /* a power of two, at least twice n */
    dict_files *files; /* top level only */
};

dict *dict_new(const char *name, const char *file, dict *parent);
dict *dict_root(dict *d);
const char *dict_intern_file(dict *d, const char *name);
dict_entry *dict_entry_new(char *key, const char *file, int line, int col);
void dict_entry_free(dict_entry *e);
void dict_tokens_free(dict_token *t, size_t n);
/* Adds e to d; an entry with the same key is replaced in place. */
void dict_insert(dict *d, dict_entry *e);
/* Local lookup of the first `len` characters of key (no scoping). */
dict_entry *dict_find_local(const dict *d, const char *key, size_t len);
dict *dict_copy(const dict *src, const char *name, dict *parent);
dict_token *dict_tokens_copy(const dict_token *t, size_t n, dict *parent);
dict_entry *dict_entry_copy(const dict_entry *e, dict *parent);
/* Copies every entry of src into d (replacing keys that exist). */
void dict_merge(dict *d, const dict *src);
/* Levels of dictionaries and brackets below d / inside the tokens. */
size_t dict_height(const dict *d);
size_t dict_tokens_height(const dict_token *t, size_t n);

/* ---- growable text ------------------------------------------------------- */

typedef struct dict_buf {
    char *s;
    size_t n, cap;
} dict_buf;

void dict_buf_putc(dict_buf *b, char c);
void dict_buf_puts(dict_buf *b, const char *s, size_t len);
/* The text so far, NUL-terminated; ownership passes to the caller. */
char *dict_buf_take(dict_buf *b);

/* ---- the lexer ------------------------------------------------------------ */

typedef enum {
    DICT_LX_EOF,
    DICT_LX_WORD,
    DICT_LX_STRING,
    DICT_LX_VAR,       /* $name or ${name}: text is the name */
    DICT_LX_DIRECTIVE, /* #word: text includes the '#' */
    DICT_LX_PUNCT      /* { } ( ) [ ] ; */
} dict_lx_kind;

typedef struct dict_lx_tok {
    dict_lx_kind kind;
    char punct;      /* DICT_LX_PUNCT */
    char *text;      /* owned by the lexer until dict_lex_take() */
    int line, col;   /* of the first character */
    int end_line;    /* of the last character */
    int end_col;     /* just after the last character */
    long begin, end; /* byte offsets [begin, end) */
} dict_lx_tok;

/* One source text being read (the top file, a string or an #include). */
typedef struct dict_lexer {
    const char *text;
    size_t len, pos;
    int line, col;
    const char *file; /* interned name, for messages */
    const char *dir;  /* folder for relative #include; NULL = cwd */
    dict *top;        /* dict receiving this source's top-level entries */
    int is_include;   /* its FoamFile header is dropped */
    sl_err *err;
    dict_lx_tok tok; /* the current token */
} dict_lexer;

void dict_lex_init(dict_lexer *lx, const char *text, size_t len, const char *file, sl_err *err);
void dict_lex_done(dict_lexer *lx);
/* Reads the next token into lx->tok; 0 or -1 with lx->err filled. */
int dict_lex_next(dict_lexer *lx);
/* Takes ownership of the current token's text. */
char *dict_lex_take(dict_lexer *lx);
/* Line and column of byte `offset` of text. */
void dict_lex_locate(const char *text, size_t offset, int *line, int *col);

/* ---- the parser ----------------------------------------------------------- */

typedef struct dict_parser {
    sl_err *err;
    const char **stack; /* real paths of the files being read (NULL: a string) */
    size_t nstack, capstack;
    size_t depth; /* nesting level of the dictionary being filled */
} dict_parser;

/* Formats "file:line:col: message" into lx->err; returns -1. */
int dict_parse_error(const dict_lexer *lx, int line, int col, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Reads entries into d up to the '}' matching the '{' at open_line:open_col
 * (left as the current token), or to the end of the source if open_line is
 * 0.  0 or -1. */
int dict_parse_body(dict_parser *p, dict_lexer *lx, dict *d, int open_line, int open_col);
/* Inserts e into d (dropping the FoamFile header of an included file). */
void dict_parse_add(const dict_lexer *lx, dict *d, dict_entry *e);
/* Reads the value of `key` (the current token is its first token) up to its
 * ';' and adds the entry to d.  Takes ownership of key.  0 or -1. */
int dict_value_parse(dict_parser *p, dict_lexer *lx, dict *d, char *key, int line, int col);

/* ---- macros -------------------------------------------------------------- */

/* Resolves $name from `scope` with OpenFOAM rules; NULL if undefined. */
const dict_entry *dict_var_lookup(const dict *scope, const char *name);

#endif
