/*
 * dict_text: renders entry values back to text in OpenFOAM syntax, for logs
 * and tools ("1 2 3", "(0 0 -9.81)", "\"a \\\"b\\\"\"", "{ a 1; }").
 */
#include "dictionary/dict_internal.h"

#include <string.h>

static void dict_text_dict(dict_buf *b, const dict *d);

static void dict_text_string(dict_buf *b, const char *s)
{
    dict_buf_putc(b, '"');
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') dict_buf_putc(b, '\\');
        dict_buf_putc(b, *s);
    }
    dict_buf_putc(b, '"');
}

static int dict_text_is(const dict_token *t, const char *chars)
{
    return t->kind == DICT_TOK_PUNCT && strchr(chars, t->text[0]);
}

/* A list size written against its list: "3(1 2 3)". */
static int dict_text_is_count(const dict_token *t, const dict_token *next)
{
    return t->kind == DICT_TOK_WORD && strspn(t->text, "0123456789") == strlen(t->text) &&
        dict_text_is(next, "(");
}

/* Single spaces between tokens, none just inside brackets. */
static void dict_text_tokens(dict_buf *b, const dict_token *t, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (i > 0 && !dict_text_is(&t[i - 1], "([") && !dict_text_is(&t[i], ")]") &&
            !dict_text_is_count(&t[i - 1], &t[i]))
            dict_buf_putc(b, ' ');
        if (t[i].kind == DICT_TOK_DICT) dict_text_dict(b, t[i].sub);
        else if (t[i].kind == DICT_TOK_STRING) dict_text_string(b, t[i].text);
        else dict_buf_puts(b, t[i].text, strlen(t[i].text));
    }
}

static void dict_text_dict(dict_buf *b, const dict *d)
{
    dict_buf_putc(b, '{');
    for (size_t i = 0; i < d->n; i++) {
        const dict_entry *e = d->entries[i];
        dict_buf_putc(b, ' ');
        dict_buf_puts(b, e->key, strlen(e->key));
        dict_buf_putc(b, ' ');
        if (e->sub) {
            dict_text_dict(b, e->sub);
        } else {
            dict_text_tokens(b, e->tok, e->ntok);
            dict_buf_putc(b, ';');
        }
    }
    dict_buf_puts(b, " }", 2);
}

char *dict_entry_value_text(const dict_entry *e)
{
    dict_buf b = {0};
    if (!e) return NULL;
    if (e->sub) dict_text_dict(&b, e->sub);
    else dict_text_tokens(&b, e->tok, e->ntok);
    return dict_buf_take(&b);
}
