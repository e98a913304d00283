/*
 * dictedit_text: reading dictionary text and finding places in it (line
 * starts, comments, the ';' after a value) for the editor in dictedit.c,
 * and printing a parsed tree in OpenFOAM layout.
 */
#include "dictedit/dictedit_internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "core/sl_mem.h"

char *dedit_read_text(const char *file, size_t *len, sl_err *err)
{
    FILE *f = fopen(file, "rb");
    size_t n = 0, cap = 4096, got;
    char *s;
    if (!f) {
        sl_err_set(err, "cannot open file '%s': %s", file, strerror(errno));
        return NULL;
    }
    s = sl_malloc(cap, "a dictionary file");
    while ((got = fread(s + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (cap - n < 2) s = sl_realloc(s, cap *= 2, "a dictionary file");
    }
    if (ferror(f)) {
        sl_err_set(err, "cannot read file '%s': %s", file, strerror(errno ? errno : EIO));
        fclose(f);
        free(s);
        return NULL;
    }
    fclose(f);
    s[n] = '\0';
    if (len) *len = n;
    return s;
}

/* ---- places in the text ---------------------------------------------------- */

long dedit_line_start(const char *s, long i)
{
    while (i > 0 && s[i - 1] != '\n') i--;
    return i;
}

long dedit_line_end(const char *s, size_t n, long i)
{
    while ((size_t)i < n && s[i] != '\n') i++;
    return i;
}

long dedit_offset(const char *s, size_t n, int line, int col)
{
    long i = 0;
    for (int l = 1; l < line && (size_t)i < n; i++)
        if (s[i] == '\n') l++;
    i += col - 1;
    return (size_t)i <= n ? i : (long)n;
}

int dedit_is_blank(const char *s, long from, long to)
{
    for (long i = from; i < to; i++)
        if (s[i] != ' ' && s[i] != '\t' && s[i] != '\r') return 0;
    return 1;
}

/* Just after a comment starting at i, or i if none starts there. */
static long dedit_skip_comment(const char *s, size_t n, long i)
{
    if ((size_t)i + 1 >= n || s[i] != '/') return i;
    if (s[i + 1] == '/') return dedit_line_end(s, n, i);
    if (s[i + 1] == '*') {
        const char *e = strstr(s + i + 2, "*/");
        return e ? (long)(e - s) + 2 : (long)n;
    }
    return i;
}

long dedit_skip_blank(const char *s, size_t n, long i)
{
    for (;;) {
        long j = i;
        while ((size_t)j < n && strchr(" \t\r\n\f\v", s[j])) j++;
        j = dedit_skip_comment(s, n, j);
        if (j == i) return i;
        i = j;
    }
}

int dedit_tail_is_comment(const char *s, size_t n, long i)
{
    long eol = dedit_line_end(s, n, i);
    while (i < eol) {
        long j = i;
        while (j < eol && (s[j] == ' ' || s[j] == '\t' || s[j] == '\r')) j++;
        if (j == eol) return 1;
        i = dedit_skip_comment(s, n, j);
        if (i == j) return 0;  /* not a comment */
        if (i > eol) return 0; /* a block comment running onto the next lines */
    }
    return 1;
}

long dedit_entry_end(const char *s, size_t n, long value_end)
{
    long j = dedit_skip_blank(s, n, value_end);
    if ((size_t)j < n && s[j] == ';') return j + 1;
    return value_end;
}

char *dedit_raw_value(const dict_entry *e, sl_err *err)
{
    long b, en;
    size_t n;
    char *text, *v;
    if (dict_entry_span(e, &b, &en) != 0) {
        sl_err_set(err, "no entry");
        return NULL;
    }
    text = dedit_read_text(dict_entry_file(e), &n, err);
    if (!text) return NULL;
    if (b < 0 || en < b || (size_t)en > n) {
        sl_err_set(err, "%s: the text of '%s' has changed since it was read", dict_entry_file(e),
                   dict_entry_key(e));
        free(text);
        return NULL;
    }
    v = sl_malloc((size_t)(en - b) + 1, "a value");
    memcpy(v, text + b, (size_t)(en - b));
    v[en - b] = '\0';
    free(text);
    return v;
}

/* ---- printing ---------------------------------------------------------------- */

int dedit_key_needs_quotes(const char *key)
{
    int depth = 0;
    if (!*key || *key == '$' || *key == '#') return 1;
    for (const char *c = key; *c; c++) {
        if (strchr(" \t\r\n{};\"[]", *c) || (unsigned char)*c < 0x20 || (unsigned char)*c >= 0x7f)
            return 1;
        if (c[0] == '/' && (c[1] == '/' || c[1] == '*')) return 1;
        if (*c == '(') depth++;
        if (*c == ')' && --depth < 0) return 1;
    }
    return depth != 0;
}

int dedit_write_key(FILE *out, const char *key)
{
    int n = 2;
    if (!dedit_key_needs_quotes(key)) return fputs(key, out) < 0 ? 0 : (int)strlen(key);
    fputc('"', out);
    for (const char *c = key; *c; c++, n++) {
        if (*c == '"' || *c == '\\') {
            fputc('\\', out);
            n++;
        }
        fputc(*c, out);
    }
    fputc('"', out);
    return n;
}

static void dedit_indent(FILE *out, int level)
{
    for (int i = 0; i < level; i++) fputs("    ", out);
}

void dedit_print_entry(FILE *out, const dict_entry *e, int level)
{
    const dict *sub = dict_entry_dict(e);
    int len;
    dedit_indent(out, level);
    len = dedit_write_key(out, dict_entry_key(e));
    if (sub) {
        fputc('\n', out);
        dedit_indent(out, level);
        fputs("{\n", out);
        dedit_print_dict(out, sub, level + 1);
        dedit_indent(out, level);
        fputs("}\n", out);
    } else {
        char *v = dict_entry_value_text(e);
        fprintf(out, "%*s%s;\n", len < DEDIT_KEY_WIDTH ? DEDIT_KEY_WIDTH - len : 1, "", v);
        free(v);
    }
}

void dedit_print_dict(FILE *out, const dict *d, int level)
{
    for (size_t i = 0; i < dict_size(d); i++) {
        if (level == 0 && i > 0) fputc('\n', out);
        dedit_print_entry(out, dict_entry_at(d, i), level);
    }
}
