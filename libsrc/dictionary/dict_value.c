/*
 * dict_value: reads the value of a primitive entry, `key tok tok ... ;`,
 * checking that brackets balance, expanding $variables, reading
 * dictionaries inside lists and catching a forgotten ';' (a value that
 * runs on to the next line outside any bracket).
 */
#include "dictionary/dict_internal.h"

#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

typedef struct dict_value_bracket {
    char c;
    int line, col;
} dict_value_bracket;

/* The value being read. */
typedef struct dict_value {
    dict_parser *p;
    dict_lexer *lx;
    dict *scope;
    const char *key;
    dict_token *tok;
    size_t ntok, captok;
    dict_value_bracket *br; /* open brackets, innermost last */
    size_t nbr, capbr;
    int prev_line, prev_col; /* just after the previous token */
    long end;                /* byte offset just after the previous token */
    dict *whole;             /* `key $dict;`: a copy of that dictionary */
} dict_value;

static void dict_value_free(dict_value *v)
{
    dict_tokens_free(v->tok, v->ntok);
    free(v->br);
    dict_free(v->whole);
}

/* Appends a token (taking ownership of text and sub) at the current place. */
static void dict_value_push(dict_value *v, dict_token t)
{
    if (v->ntok == v->captok) {
        v->captok = v->captok ? 2 * v->captok : 8;
        v->tok = sl_realloc(v->tok, v->captok * sizeof *v->tok, "dictionary tokens");
    }
    v->tok[v->ntok++] = t;
}

static dict_token dict_value_here(const dict_value *v, dict_tok_kind kind, char *text)
{
    dict_token t = {kind, text, NULL, v->lx->file, v->lx->tok.line, v->lx->tok.col};
    return t;
}

static int dict_value_missing_semicolon(const dict_value *v)
{
    return dict_parse_error(v->lx, v->prev_line, v->prev_col,
                            "missing ';' after the value of keyword '%s'", v->key);
}

static int dict_value_unclosed(const dict_value *v)
{
    const dict_value_bracket *b = &v->br[v->nbr - 1];
    return dict_parse_error(v->lx, b->line, b->col,
                            "unbalanced '%c' in the value of keyword '%s': no matching '%c'", b->c,
                            v->key, b->c == '(' ? ')' : ']');
}

static int dict_value_too_deep(const dict_value *v, size_t extra)
{
    if (v->p->depth + v->nbr + extra <= DICT_MAX_DEPTH) return 0;
    return dict_parse_error(v->lx, v->lx->tok.line, v->lx->tok.col,
                            "dictionaries and lists nested deeper than %d levels", DICT_MAX_DEPTH);
}

static int dict_value_open(dict_value *v)
{
    const dict_lx_tok *t = &v->lx->tok;
    char text[2] = {t->punct, '\0'};
    if (dict_value_too_deep(v, 1)) return -1;
    if (v->nbr == v->capbr) {
        v->capbr = v->capbr ? 2 * v->capbr : 8;
        v->br = sl_realloc(v->br, v->capbr * sizeof *v->br, "brackets");
    }
    v->br[v->nbr].c = t->punct;
    v->br[v->nbr].line = t->line;
    v->br[v->nbr++].col = t->col;
    dict_value_push(v, dict_value_here(v, DICT_TOK_PUNCT, sl_strdup(text)));
    return 0;
}

static int dict_value_close(dict_value *v)
{
    const dict_lx_tok *t = &v->lx->tok;
    char text[2] = {t->punct, '\0'};
    char want = t->punct == ')' ? '(' : '[';
    if (v->nbr == 0)
        return dict_parse_error(v->lx, t->line, t->col,
                                "unbalanced '%c' in the value of keyword '%s'", t->punct, v->key);
    if (v->br[v->nbr - 1].c != want)
        return dict_parse_error(v->lx, t->line, t->col,
                                "mismatched '%c' in the value of keyword '%s' ('%c' opened "
                                "at line %d)",
                                t->punct, v->key, v->br[v->nbr - 1].c, v->br[v->nbr - 1].line);
    v->nbr--;
    dict_value_push(v, dict_value_here(v, DICT_TOK_PUNCT, sl_strdup(text)));
    return 0;
}

/* `( name { ... } ... )`: a dictionary as a list element. */
static int dict_value_subdict(dict_value *v)
{
    dict_parser *p = v->p;
    dict_token t = dict_value_here(v, DICT_TOK_DICT, NULL);
    size_t saved = p->depth;
    int rc;
    if (dict_value_too_deep(v, 1)) return -1;
    t.sub = dict_new(v->key, v->lx->file, v->scope);
    p->depth += v->nbr + 1;
    rc = dict_parse_body(p, v->lx, t.sub, t.line, t.col);
    p->depth = saved;
    if (rc) {
        dict_free(t.sub);
        return -1;
    }
    dict_value_push(v, t);
    return 0;
}

/* $var naming a dictionary: the whole value (`key $sub;`) or a list
 * element; 1 when the value is complete (the ';' is the current token). */
static int dict_value_var_dict(dict_value *v, const dict_entry *e)
{
    dict_lexer *lx = v->lx;
    int line = lx->tok.line, col = lx->tok.col, rc;
    char *name;
    if (dict_value_too_deep(v, dict_height(e->sub))) return -1;
    if (v->nbr > 0) {
        dict_token t = dict_value_here(v, DICT_TOK_DICT, NULL);
        t.sub = dict_copy(e->sub, v->key, v->scope);
        dict_value_push(v, t);
        return 0;
    }
    name = dict_lex_take(lx);
    if (v->ntok == 0) {
        const dict_lx_tok *t = &lx->tok;
        v->end = t->end;
        v->prev_line = t->end_line;
        v->prev_col = t->end_col;
        if (dict_lex_next(lx)) {
            free(name);
            return -1;
        }
        if (t->kind == DICT_LX_PUNCT && t->punct == ';') {
            free(name);
            v->whole = dict_copy(e->sub, v->key, v->scope);
            return 1;
        }
        if (t->kind == DICT_LX_EOF || t->line > v->prev_line ||
            (t->kind == DICT_LX_PUNCT && t->punct == '}')) {
            free(name);
            return dict_value_missing_semicolon(v);
        }
    }
    rc = dict_parse_error(lx, line, col,
                          "'$%s' is a dictionary: it can only be the whole value of "
                          "keyword '%s' or a list element",
                          name, v->key);
    free(name);
    return rc;
}

static int dict_value_var(dict_value *v)
{
    const dict_lx_tok *t = &v->lx->tok;
    const dict_entry *e = dict_var_lookup(v->scope, t->text);
    dict_token *copy;
    if (!e)
        return dict_parse_error(v->lx, t->line, t->col,
                                "undefined variable '$%s' in the value of keyword '%s'", t->text,
                                v->key);
    if (e->sub) return dict_value_var_dict(v, e);
    if (dict_value_too_deep(v, dict_tokens_height(e->tok, e->ntok))) return -1;
    copy = dict_tokens_copy(e->tok, e->ntok, v->scope);
    for (size_t i = 0; i < e->ntok; i++) dict_value_push(v, copy[i]);
    free(copy); /* its contents now belong to v */
    return 0;
}

/* Adds the current token; -1 on error, 1 when the value is complete. */
static int dict_value_token(dict_value *v)
{
    const dict_lx_tok *t = &v->lx->tok;
    switch (t->kind) {
    case DICT_LX_WORD:
        dict_value_push(v, dict_value_here(v, DICT_TOK_WORD, dict_lex_take(v->lx)));
        return 0;
    case DICT_LX_STRING:
        dict_value_push(v, dict_value_here(v, DICT_TOK_STRING, dict_lex_take(v->lx)));
        return 0;
    case DICT_LX_VAR:
        return dict_value_var(v);
    case DICT_LX_DIRECTIVE:
        return dict_parse_error(v->lx, t->line, t->col,
                                "directive '%s' is not supported inside the value of keyword '%s'",
                                t->text, v->key);
    default:
        break;
    }
    if (t->punct == '(' || t->punct == '[') return dict_value_open(v);
    if (t->punct == ')' || t->punct == ']') return dict_value_close(v);
    if (v->nbr == 0) return dict_value_missing_semicolon(v); /* '{' or '}' */
    if (t->punct == '{') return dict_value_subdict(v);
    return dict_value_unclosed(v); /* '}' inside a list */
}

/* One step of the value loop: -1 error, 1 done, 0 go on. */
static int dict_value_step(dict_value *v)
{
    const dict_lx_tok *t = &v->lx->tok;
    int rc;
    if (t->kind == DICT_LX_EOF)
        return v->nbr ? dict_value_unclosed(v) : dict_value_missing_semicolon(v);
    if (t->kind == DICT_LX_PUNCT && t->punct == ';') return v->nbr ? dict_value_unclosed(v) : 1;
    /* Outside brackets a value stays on one line (a list may open on the
     * next); anything else is the next entry after a forgotten ';'. */
    if (v->nbr == 0 && v->ntok > 0 && t->line > v->prev_line &&
        !(t->kind == DICT_LX_PUNCT && (t->punct == '(' || t->punct == '[')))
        return dict_value_missing_semicolon(v);
    rc = dict_value_token(v);
    if (rc) return rc;
    v->prev_line = v->lx->tok.end_line;
    v->prev_col = v->lx->tok.end_col;
    v->end = v->lx->tok.end;
    return 0;
}

int dict_value_parse(dict_parser *p, dict_lexer *lx, dict *d, char *key, int line, int col)
{
    dict_value v = {.p = p, .lx = lx, .scope = d, .key = key};
    long begin = lx->tok.begin;
    dict_entry *e;
    int rc;
    while ((rc = dict_value_step(&v)) == 0)
        if (dict_lex_next(lx)) {
            rc = -1;
            break;
        }
    if (rc < 0) {
        dict_value_free(&v);
        free(key);
        return -1;
    }
    e = dict_entry_new(key, lx->file, line, col);
    e->begin = begin;
    e->end = v.end;
    e->sub = v.whole;
    if (!v.whole) {
        e->tok = v.tok;
        e->ntok = v.ntok;
    } else {
        dict_tokens_free(v.tok, v.ntok);
    }
    free(v.br);
    dict_parse_add(lx, d, e);
    return 0;
}
