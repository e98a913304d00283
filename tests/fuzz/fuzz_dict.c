/*
 * fuzz_dict: libFuzzer target for the dictionary parser (libsrc/dictionary).
 *
 * Each input is parsed twice: as a string (dict_parse_string, text up to
 * the first NUL) and byte for byte from a file (dict_read_file, which must
 * reject NUL bytes).  A parsed tree is then walked with every getter, so
 * that lookups, macros and value rendering see hostile trees too.
 *
 * Beyond "no crash, no leak, no undefined behaviour" (the sanitizers) the
 * target checks the parser's contract: a failure always fills the error
 * message, success never does harm to it, spans are ordered, and the two
 * entry points agree on inputs without NUL bytes.
 *
 * Run it in a scratch folder holding the files that #include may name
 * (run_fuzz copies tests/data/dictionary/valid there): the input file is
 * written to the cwd so that #include resolves the same way for both entry
 * points.  Build and run with `make fuzz`.
 */
#include "dictionary/dict.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *const valid_keys[] = {
    "rho0", "particleSpacing", "gravity", "eta", "fluidRegions", "type", "min", "max", NULL};

static void check(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_dict: contract violated: %s\n", what);
        abort();
    }
}

static void check_err(const sl_err *err)
{
    check(memchr(err->msg, '\0', sizeof err->msg) != NULL, "error message not terminated");
    check(err->msg[0] != '\0', "failure with an empty error message");
}

/* Every getter on every key; recursion into sub-dictionaries. */
static void walk(const dict *d)
{
    for (size_t i = 0; i < dict_size(d); i++) {
        const dict_entry *e = dict_entry_at(d, i);
        const char *key = dict_entry_key(e), *w;
        sl_err err;
        double v[3], s;
        long l, b, en;
        int flag;
        size_t n;
        double *list;
        char **words;
        check(key != NULL && dict_entry_file(e) != NULL, "entry without key or file");
        check(dict_entry_line(e) >= 1 && dict_entry_col(e) >= 1, "line/col below 1");
        check(dict_lookup(d, key) != NULL, "an entry's own key is not found");
        if (dict_entry_span(e, &b, &en) == 0) check(b <= en, "span end before begin");
        char *text = dict_entry_value_text(e);
        check(text != NULL, "no value text");
        free(text);
        (void)dict_nearest(key, valid_keys);
        if (dict_get_scalar(d, key, &s, &err)) check_err(&err);
        if (dict_get_int(d, key, &l, &err)) check_err(&err);
        if (dict_get_word(d, key, &w, &err)) check_err(&err);
        if (dict_get_bool(d, key, &flag, &err)) check_err(&err);
        if (dict_get_vector(d, key, v, &err)) check_err(&err);
        if (dict_get_scalar_list(d, key, &list, &n, &err) == 0) free(list);
        else check_err(&err);
        if (dict_get_word_list(d, key, &words, &n, &err) == 0) dict_free_word_list(words, n);
        else check_err(&err);
        const dict *sub = dict_entry_dict(e);
        if (sub) {
            check(dict_sub(d, key) != NULL, "dict_sub disagrees with dict_entry_dict");
            (void)dict_name(sub);
            walk(sub);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[64];
    sl_err err;
    char *text = malloc(size + 1);
    memcpy(text, data, size);
    text[size] = '\0';
    err.msg[0] = '\0';
    dict *a = dict_parse_string(text, "fuzz", &err);
    if (a) walk(a);
    else check_err(&err);
    free(text);

    /* in the cwd, so that #include resolves as for the string */
    if (!path[0]) snprintf(path, sizeof path, "fuzz_input.%ld", (long)getpid());
    FILE *f = fopen(path, "wb");
    check(f != NULL, "cannot write the temporary input file");
    fwrite(data, 1, size, f);
    fclose(f);
    err.msg[0] = '\0';
    dict *b = dict_read_file(path, &err);
    if (b) walk(b);
    else check_err(&err);
    if (memchr(data, '\0', size)) check(b == NULL, "a file with a NUL byte was accepted");
    else check(!a == !b, "dict_parse_string and dict_read_file disagree");
    dict_free(a);
    dict_free(b);
    return 0;
}
