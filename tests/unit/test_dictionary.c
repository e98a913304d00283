/*
 * test_dictionary: unit tests of the OpenFOAM dictionary parser
 * (libsrc/dictionary).  Reads the files under tests/data/dictionary/, so it
 * must run from the repository root.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/sl_mem.h"
#include "dictionary/dict.h"
#include "hostile_table.h"

#define VALID "tests/data/dictionary/valid/"
#define BAD   "tests/data/dictionary/bad/"

/* ---- helpers --------------------------------------------------------------- */

static void assert_has(const char *text, const char *part)
{
    if (!text || !strstr(text, part))
        fail_msg("expected '%s' in '%s'", part, text ? text : "(null)");
}

static dict *read_ok(const char *path)
{
    sl_err err = {{0}};
    dict *d = dict_read_file(path, &err);
    if (!d) fail_msg("%s should parse: %s", path, err.msg);
    return d;
}

static double scalar(const dict *d, const char *key)
{
    sl_err err = {{0}};
    double v = -12345.0;
    if (dict_get_scalar(d, key, &v, &err)) fail_msg("%s: %s", key, err.msg);
    return v;
}

static long integer(const dict *d, const char *key)
{
    sl_err err = {{0}};
    long v = -12345;
    if (dict_get_int(d, key, &v, &err)) fail_msg("%s: %s", key, err.msg);
    return v;
}

static const char *word(const dict *d, const char *key)
{
    sl_err err = {{0}};
    const char *v = NULL;
    if (dict_get_word(d, key, &v, &err)) fail_msg("%s: %s", key, err.msg);
    return v;
}

static void assert_vector(const dict *d, const char *key, double x, double y, double z)
{
    sl_err err = {{0}};
    double v[3] = {-1, -1, -1};
    if (dict_get_vector(d, key, v, &err)) fail_msg("%s: %s", key, err.msg);
    assert_true(v[0] == x && v[1] == y && v[2] == z);
}

static void assert_text(const dict *d, const char *key, const char *expected)
{
    char *text = dict_entry_value_text(dict_lookup(d, key));
    assert_non_null(text);
    assert_string_equal(text, expected);
    free(text);
}

static void assert_scalar_error(const dict *d, const char *key, const char *part)
{
    sl_err err = {{0}};
    double v = 0.0;
    assert_int_not_equal(dict_get_scalar(d, key, &v, &err), 0);
    assert_has(err.msg, part);
}

/* Runs fn with stderr redirected; returns what it printed (caller frees). */
static char *capture_stderr(int (*fn)(const dict *, const char *const *), const dict *d,
                            const char *const *valid, int *result)
{
    FILE *tmp = tmpfile();
    int saved = dup(2);
    long n;
    char *text;
    assert_non_null(tmp);
    fflush(stderr);
    dup2(fileno(tmp), 2);
    *result = fn(d, valid);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    n = ftell(tmp);
    text = calloc(1, (size_t)n + 1);
    rewind(tmp);
    assert_int_equal(fread(text, 1, (size_t)n, tmp), (size_t)n);
    fclose(tmp);
    return text;
}

/* ---- valid files ------------------------------------------------------------- */

static void test_header(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    const dict *h = dict_sub(d, "FoamFile");
    (void)state;
    assert_non_null(h);
    assert_string_equal(dict_name(d), "fluidProperties");
    assert_string_equal(dict_file(d), VALID "fluidProperties");
    assert_string_equal(dict_name(h), "FoamFile");
    assert_true(scalar(h, "version") == 2.0);
    assert_string_equal(word(h, "format"), "ascii");
    assert_string_equal(word(d, "FoamFile/object"), "fluidProperties");
    assert_string_equal(dict_entry_key(dict_entry_at(d, 0)), "FoamFile");
    assert_int_equal(dict_entry_line(dict_entry_at(d, 0)), 5);
    dict_free(d);
}

static void test_scalars_and_words(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    (void)state;
    assert_true(scalar(d, "nu") == 1e-06);
    assert_true(scalar(d, "gamma") == 7.0);
    assert_true(scalar(d, "negative") == -2500.0);
    assert_true(scalar(d, "dot") == 0.5);
    assert_true(scalar(d, "nParticles") == 12000.0);
    assert_int_equal(integer(d, "nParticles"), 12000);
    assert_int_equal(integer(d, "negInt"), -42);
    assert_string_equal(word(d, "model"), "taitEquation");
    assert_string_equal(word(d, "title"), "dam break \"2D\" test");
    assert_string_equal(word(d, "winPath"), "a\\b");
    assert_text(d, "div(phi,U)", "Gauss linear");
    assert_text(d, "multi", "1 2 3");
    assert_text(d, "title", "\"dam break \\\"2D\\\" test\"");
    dict_free(d);
}

static void test_bools(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    sl_err err = {{0}};
    int b = -1;
    (void)state;
    assert_int_equal(dict_get_bool(d, "active", &b, &err), 0);
    assert_int_equal(b, 1);
    assert_int_equal(dict_get_bool(d, "verbose", &b, &err), 0);
    assert_int_equal(b, 0);
    assert_int_equal(dict_get_bool(d, "flagTrue", &b, &err), 0);
    assert_int_equal(b, 1);
    assert_int_equal(dict_get_bool(d, "flagZero", &b, &err), 0);
    assert_int_equal(b, 0);
    dict_free(d);
}

static void test_vectors_and_lists(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    sl_err err = {{0}};
    double *v = NULL;
    char **w = NULL;
    size_t n = 0;
    (void)state;
    assert_vector(d, "gravity", 0, 0, -9.81);
    assert_vector(d, "origin", 1.5, -2, 0.25);
    assert_int_equal(dict_get_scalar_list(d, "levels", &v, &n, &err), 0);
    assert_int_equal(n, 4);
    assert_true(v[0] == 1 && v[1] == 2 && v[2] == 3 && v[3] == 4.5);
    free(v);
    assert_int_equal(dict_get_scalar_list(d, "counted", &v, &n, &err), 0);
    assert_int_equal(n, 4);
    assert_true(v[0] == 10 && v[3] == 40);
    free(v);
    assert_int_equal(dict_get_scalar_list(d, "emptyList", &v, &n, &err), 0);
    assert_int_equal(n, 0);
    free(v);
    assert_int_equal(dict_get_word_list(d, "names", &w, &n, &err), 0);
    assert_int_equal(n, 3);
    assert_string_equal(w[0], "inlet");
    assert_string_equal(w[2], "side wall");
    dict_free_word_list(w, n);
    assert_text(d, "gravity", "(0 0 -9.81)");
    assert_text(d, "origin", "3(1.5 -2 0.25)");
    assert_text(d, "vertices", "((0 0 0) (1 0 0) (1 1 0))");
    assert_text(d, "boundary", "(walls { type wall; } lid { type movingWall; })");
    dict_free(d);
}

static void test_nested_and_scoped(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    const dict *s = dict_sub(d, "solver");
    (void)state;
    assert_non_null(s);
    assert_string_equal(dict_name(s), "solver");
    assert_string_equal(dict_file(s), VALID "fluidProperties");
    assert_string_equal(word(s, "type"), "pcisph");
    assert_true(scalar(s, "tolerance") == 1e-4);
    assert_int_equal(integer(s, "maxIter"), 50);
    assert_true(scalar(d, "solver/limits/maxDt") == 1e-3);
    assert_int_equal(integer(d, "solver/limits/deeper/level"), 3);
    assert_true(dict_has(d, "solver/limits"));
    assert_false(dict_has(d, "solver/nope"));
    assert_false(dict_has(d, "rho0/x"));
    assert_null(dict_sub(d, "rho0"));
    assert_null(dict_entry_dict(dict_lookup(d, "rho0")));
    assert_int_equal(dict_size(dict_sub(s, "limits")), 3);
    assert_int_equal(dict_entry_line(dict_lookup(s, "maxIter")), 40);
    assert_text(d, "solver/limits", "{ minDt 1e-7; maxDt 1e-3; deeper { level 3; } }");
    dict_free(d);
}

static void test_duplicate_keeps_position(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    const dict_entry *e = dict_entry_at(d, 1);
    size_t count = 0;
    (void)state;
    assert_string_equal(dict_entry_key(e), "rho0");
    assert_true(scalar(d, "rho0") == 998.2);
    assert_int_equal(dict_entry_line(e), 60);
    for (size_t i = 0; i < dict_size(d); i++)
        count += strcmp(dict_entry_key(dict_entry_at(d, i)), "rho0") == 0;
    assert_int_equal(count, 1);
    assert_null(dict_entry_at(d, dict_size(d)));
    dict_free(d);
}

static void test_spans(void **state)
{
    const char *text = "a  1.5 ;\nlist (1\n  2);\nsub { x 1; }\nq \"s\";";
    sl_err err = {{0}};
    dict *d = dict_parse_string(text, "spans", &err);
    long b = 0, e = 0;
    (void)state;
    assert_non_null(d);
    assert_int_equal(dict_entry_span(dict_lookup(d, "a"), &b, &e), 0);
    assert_int_equal(e - b, 3);
    assert_memory_equal(text + b, "1.5", 3);
    dict_entry_span(dict_lookup(d, "list"), &b, &e);
    assert_memory_equal(text + b, "(1\n  2)", (size_t)(e - b));
    dict_entry_span(dict_lookup(d, "sub"), &b, &e);
    assert_memory_equal(text + b, "{ x 1; }", (size_t)(e - b));
    assert_int_equal(e - b, 8);
    dict_entry_span(dict_lookup(d, "q"), &b, &e);
    assert_memory_equal(text + b, "\"s\"", 3);
    assert_int_equal(e - b, 3);
    assert_int_equal(dict_entry_col(dict_lookup(d, "sub")), 1);
    assert_int_equal(dict_entry_line(dict_lookup(d, "sub")), 4);
    dict_free(d);
}

static void test_macros(void **state)
{
    dict *d = read_ok(VALID "macros");
    const dict *body = dict_sub(d, "body");
    (void)state;
    assert_true(scalar(d, "useX") == 2.5);
    assert_true(scalar(d, "useBraced") == 2.5);
    assert_int_equal(integer(d, "useScoped"), 1);
    assert_int_equal(integer(d, "useRoot"), 7);
    assert_text(d, "useSlash", "(1 2 3)");
    assert_non_null(body);
    assert_string_equal(word(body, "type"), "wall"); /* merged by $defaults */
    assert_true(scalar(body, "friction") == 0.5);
    assert_string_equal(dict_entry_key(dict_entry_at(body, 1)), "friction");
    assert_true(scalar(body, "localX") == 2.5);
    assert_string_equal(word(body, "parentName"), "water");
    assert_true(scalar(body, "nested/own") == 10);
    assert_true(scalar(body, "nested/up") == 2.5);
    assert_true(scalar(body, "nested/fromRoot") == 2.5);
    assert_non_null(dict_sub(d, "copy"));
    assert_string_equal(dict_name(dict_sub(d, "copy")), "copy");
    assert_true(scalar(d, "copy/friction") == 0.3);
    assert_text(d, "list", "(1 2.5 3)");
    assert_vector(d, "vec", 2.5, 0, 1);
    /* The original is untouched by the copy. */
    assert_true(scalar(d, "defaults/friction") == 0.3);
    dict_free(d);
}

static void test_include(void **state)
{
    dict *d = read_ok(VALID "withInclude");
    const dict_entry *e;
    (void)state;
    assert_int_equal(integer(d, "before"), 1);
    assert_int_equal(integer(d, "fromInclude"), 42);
    assert_int_equal(integer(d, "after"), 42);
    assert_text(d, "fromMore", "(4 5 6)");
    assert_int_equal(integer(d, "nested/before"), 2);
    assert_string_equal(word(d, "nested/inNested"), "yes");
    /* The included header was dropped: FoamFile is the main file's. */
    assert_string_equal(word(d, "FoamFile/object"), "withInclude");
    e = dict_lookup(d, "fromInclude");
    assert_string_equal(dict_entry_file(e), VALID "include/common.inc");
    assert_int_equal(dict_entry_line(e), 9);
    e = dict_lookup(d, "fromMore");
    assert_string_equal(dict_entry_file(e), VALID "include/more.inc");
    assert_int_equal(dict_entry_line(e), 1);
    dict_free(d);
}

static void test_parse_string(void **state)
{
    sl_err err = {{0}};
    dict *d = dict_parse_string("a 1;\n#include \"" VALID "include/more.inc\"\n", "inline", &err);
    (void)state;
    assert_non_null(d);
    assert_string_equal(dict_name(d), "inline");
    assert_string_equal(dict_file(d), "inline");
    assert_text(d, "fromMore", "(4 5 6)");
    dict_free(d);
    assert_null(dict_parse_string("a 1", "inline", &err));
    assert_has(err.msg, "inline:1:4: missing ';'");
    assert_null(dict_parse_string(NULL, "x", &err));
    dict_free(NULL);
}

/* ---- malformed files --------------------------------------------------------- */

struct bad_case {
    const char *file;  /* under bad/ */
    const char *where; /* file the error is in, if not `file` */
    int line;
    const char *part; /* keyword, directive, ... */
};

static const struct bad_case bad_cases[] = {
    {"unbalanced_brace", NULL, 3, "'solver'"},
    {"unbalanced_paren", NULL, 2, "'gravity'"},
    {"missing_semicolon", NULL, 2, "missing ';' after the value of keyword 'rho0'"},
    {"missing_semicolon_brace", NULL, 4, "keyword 'type'"},
    {"missing_semicolon_eof", NULL, 3, "keyword 'b'"},
    {"unterminated_string", NULL, 3, "unterminated string"},
    {"unterminated_comment", NULL, 2, "unterminated block comment"},
    {"unexpected_brace", NULL, 4, "unexpected '}'"},
    {"empty_key", NULL, 3, "empty keyword"},
    {"brace_without_key", NULL, 3, "empty keyword"},
    {"no_value", NULL, 3, "keyword 'rho0' has no value"},
    {"no_value_eof", NULL, 3, "keyword 'rho0' has no value"},
    {"include_missing", NULL, 2, "cannot open file '" BAD "include/nope': No such file"},
    {"loop_a", "loop_b", 3, "#include loop"},
    {"undefined_var", NULL, 3, "undefined variable '$nope'"},
    {"undefined_braced_var", NULL, 2, "'$later'"},
    {"unknown_directive", NULL, 2, "'#inputMode'"},
    {"include_etc", NULL, 2, "'#includeEtc' is not supported"},
    {"include_no_name", NULL, 2, "expected a file name after '#include'"},
    {"binary_nul", NULL, 3, "invalid character 0x00"},
    {"invalid_char", NULL, 3, "invalid character 0x01"},
    {"mismatched_bracket", NULL, 2, "keyword 'v'"},
    {"extra_paren", NULL, 2, "unbalanced ')' in the value of keyword 'v'"},
    {"dict_var_in_value", NULL, 3, "'$d' is a dictionary"},
    {"merge_not_dict", NULL, 5, "'$x'"},
    {"unterminated_var", NULL, 3, "unterminated '${'"},
    {"list_without_key", NULL, 3, "unexpected '('"},
    {"unbalanced_word", NULL, 2, "'div(phi,U'"},
    {"dict_var_missing_semicolon", NULL, 3, "missing ';' after the value of keyword 'b'"},
    {"deep_nesting", NULL, 258, "nested deeper than 256"},
};

static void test_bad_files(void **state)
{
    (void)state;
    assert_true(sizeof bad_cases / sizeof *bad_cases >= 15);
    for (size_t i = 0; i < sizeof bad_cases / sizeof *bad_cases; i++) {
        const struct bad_case *c = &bad_cases[i];
        char path[256], where[300];
        sl_err err = {{0}};
        dict *d;
        snprintf(path, sizeof path, BAD "%s", c->file);
        d = dict_read_file(path, &err);
        if (d) fail_msg("%s was accepted", path);
        snprintf(where, sizeof where, BAD "%s:%d:", c->where ? c->where : c->file, c->line);
        assert_has(err.msg, where);
        assert_has(err.msg, c->part);
        hostile_record("dictionary syntax (any case file)", c->file, err.msg);
    }
}

/* An error in an included file also says where it was included from. */
static void test_include_chain_in_message(void **state)
{
    sl_err err = {{0}};
    (void)state;
    assert_null(dict_read_file(BAD "loop_a", &err));
    assert_has(err.msg, BAD "loop_b:3:1: #include loop: '" BAD "loop_a' is already being read");
    assert_has(err.msg, "(included from " BAD "loop_a:2:1)");
}

/* Variables out of reach are undefined, not a crash. */
static void test_var_scopes(void **state)
{
    static const char *const bad[] = {
        "a $../x;",   /* no parent of the top level */
        "x 1; a $:;", /* nothing after the scope */
        "x 1; s { a $../../x; }",
        "x 1; s { y 2; } a $s/x;", /* x is not inside s */
        "x 1; a $x/y;",            /* x is not a dictionary */
        "s { y 2; } t { a $y; }",  /* y is in s, not an enclosing scope */
    };
    sl_err err = {{0}};
    dict *d;
    (void)state;
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        d = dict_parse_string(bad[i], "vars", &err);
        if (d) fail_msg("'%s' was accepted", bad[i]);
        assert_has(err.msg, "vars:1:");
        assert_has(err.msg, "undefined variable");
    }
    d = dict_parse_string("x 1; s { x 2; t { a $../x; b $:x; c $x; } }", "vars", &err);
    assert_non_null(d);
    assert_int_equal(integer(d, "s/t/a"), 2);
    assert_int_equal(integer(d, "s/t/b"), 1);
    assert_int_equal(integer(d, "s/t/c"), 2);
    dict_free(d);
}

static void test_missing_file(void **state)
{
    sl_err err = {{0}};
    (void)state;
    assert_null(dict_read_file(BAD "doesNotExist", &err));
    assert_string_equal(err.msg,
                        "cannot open file '" BAD "doesNotExist': No such file or directory");
    assert_null(dict_read_file("tests/data/dictionary", &err));
    assert_has(err.msg, "cannot open file 'tests/data/dictionary': Is a directory");
}

/* #include chains deeper than DICT_MAX_INCLUDE are refused. */
static void test_include_depth(void **state)
{
    char dir[] = "/tmp/test_dictionary_XXXXXX", path[128];
    sl_err err = {{0}};
    const int n = DICT_MAX_INCLUDE + 2;
    (void)state;
    assert_non_null(mkdtemp(dir));
    for (int i = 0; i < n; i++) {
        FILE *f;
        snprintf(path, sizeof path, "%s/f%d", dir, i);
        f = fopen(path, "w");
        assert_non_null(f);
        fprintf(f, "k%d %d;\n", i, i);
        if (i + 1 < n) fprintf(f, "#include \"f%d\"\n", i + 1);
        fclose(f);
    }
    snprintf(path, sizeof path, "%s/f%d", dir, 1);
    dict *d = dict_read_file(path, &err); /* 32 levels of #include: fine */
    assert_non_null(d);
    assert_int_equal(dict_size(d), (size_t)n - 1);
    dict_free(d);
    snprintf(path, sizeof path, "%s/f0", dir);
    assert_null(dict_read_file(path, &err));
    assert_has(err.msg, "nested deeper than 32");
    for (int i = 0; i < n; i++) {
        snprintf(path, sizeof path, "%s/f%d", dir, i);
        remove(path);
    }
    rmdir(dir);
}

/* No fixed buffers: a 1 MB word, a 1 MB string and a 100000-element list. */
static void test_long_tokens(void **state)
{
    const size_t big = 1u << 20, count = 100000;
    char *text = sl_malloc(2 * big + 8 * count + 64, "test text");
    size_t n = 0;
    sl_err err = {{0}};
    double *v;
    size_t nv;
    dict *d;
    (void)state;
    n += (size_t)sprintf(text + n, "w ");
    memset(text + n, 'x', big);
    n += big;
    n += (size_t)sprintf(text + n, ";\ns \"");
    memset(text + n, 'y', big);
    n += big;
    n += (size_t)sprintf(text + n, "\";\nl (");
    for (size_t i = 0; i < count; i++) n += (size_t)sprintf(text + n, "%zu ", i % 10);
    sprintf(text + n, ");\n");
    d = dict_parse_string(text, "long", &err);
    assert_non_null(d);
    assert_int_equal(strlen(word(d, "w")), big);
    assert_int_equal(strlen(word(d, "s")), big);
    assert_int_equal(dict_get_scalar_list(d, "l", &v, &nv, &err), 0);
    assert_int_equal(nv, count);
    assert_true(v[count - 1] == 9.0);
    free(v);
    dict_free(d);
    free(text);
}

/* Many keys (the hashed lookup) with duplicates that keep their position. */
static void test_many_keys(void **state)
{
    const size_t keys = 5000;
    char *text = sl_malloc(keys * 40, "test text"), key[32];
    size_t n = 0;
    sl_err err = {{0}};
    dict *d;
    (void)state;
    for (size_t i = 0; i < keys; i++) n += (size_t)sprintf(text + n, "k%zu %zu;\n", i, i);
    for (size_t i = 0; i < keys; i += 7) n += (size_t)sprintf(text + n, "k%zu -1;\n", i);
    d = dict_parse_string(text, "many", &err);
    assert_non_null(d);
    assert_int_equal(dict_size(d), keys);
    for (size_t i = 0; i < keys; i++) {
        snprintf(key, sizeof key, "k%zu", i);
        assert_string_equal(dict_entry_key(dict_entry_at(d, i)), key);
        assert_int_equal(integer(d, key), i % 7 ? (long)i : -1);
    }
    assert_false(dict_has(d, "k5000"));
    dict_free(d);
    free(text);
}

/* ---- getters ------------------------------------------------------------------ */

static void test_missing_key(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    sl_err err = {{0}};
    double v;
    int b;
    (void)state;
    assert_int_not_equal(dict_get_scalar(d, "rho", &v, &err), 0);
    assert_string_equal(err.msg,
                        VALID "fluidProperties: missing required keyword 'rho' in "
                              "dictionary 'fluidProperties'");
    assert_int_not_equal(dict_get_bool(dict_sub(d, "solver"), "fast", &b, &err), 0);
    assert_string_equal(err.msg,
                        VALID "fluidProperties: missing required keyword 'fast' in "
                              "dictionary 'solver'");
    dict_free(d);
}

static void test_bad_types(void **state)
{
    dict *d = read_ok(VALID "badValues");
    sl_err err = {{0}};
    long l;
    int b;
    double vec[3], *list;
    char **words;
    size_t n = 7;
    (void)state;
    assert_scalar_error(d, "word",
                        VALID "badValues:2:13: keyword 'word': expected a number, "
                              "found 'abc'");
    assert_scalar_error(d, "hexV", "keyword 'hexV': expected a number, found '0x10'");
    assert_scalar_error(d, "twoNum", ":9:1: keyword 'twoNum': expected a number, found '1 2'");
    assert_scalar_error(d, "sub", "keyword 'sub': expected a number, found a dictionary");
    assert_scalar_error(d, "strNum", "found '\"1.5\"'");
    assert_int_not_equal(dict_get_int(d, "half", &l, &err), 0);
    assert_has(err.msg, ":6:13: keyword 'half': expected an integer, found '1.5'");
    assert_int_not_equal(dict_get_int(d, "bigInt", &l, &err), 0);
    assert_has(err.msg, "integer out of range");
    assert_int_not_equal(dict_get_bool(d, "maybe", &b, &err), 0);
    assert_has(err.msg, "keyword 'maybe': expected on/off");
    assert_int_not_equal(dict_get_vector(d, "shortVec", vec, &err), 0);
    assert_has(err.msg, ":10:1: keyword 'shortVec': expected a vector (x y z), found '(1 2)'");
    assert_int_not_equal(dict_get_vector(d, "wordVec", vec, &err), 0);
    assert_has(err.msg, ":11:16: keyword 'wordVec': expected a number, found 'a'");
    assert_int_not_equal(dict_get_vector(d, "notList", vec, &err), 0);
    assert_has(err.msg, "expected a vector (x y z), found '5'");
    assert_int_not_equal(dict_get_scalar_list(d, "badCount", &list, &n, &err), 0);
    assert_null(list);
    assert_int_equal(n, 0);
    assert_has(err.msg, "keyword 'badCount': list size 3 does not match its 2 elements");
    assert_int_not_equal(dict_get_scalar_list(d, "nestedList", &list, &n, &err), 0);
    assert_has(err.msg, "expected a number, found '('");
    assert_int_not_equal(dict_get_word_list(d, "sub", &words, &n, &err), 0);
    assert_null(words);
    assert_has(err.msg, "keyword 'sub': expected a list of words, found a dictionary");
    assert_int_not_equal(dict_get_word_list(d, "nestedList", &words, &n, &err), 0);
    assert_has(err.msg, ":17:14: keyword 'nestedList': expected a word in the list, found '('");
    assert_int_not_equal(dict_get_word(d, "twoNum", &(const char *){0}, &err), 0);
    assert_has(err.msg, "expected a word");
    dict_free(d);
}

static void test_nonfinite(void **state)
{
    dict *d = read_ok(VALID "badValues");
    (void)state;
    assert_scalar_error(d, "nanV", ":3:13: keyword 'nanV': not a finite number, found 'nan'");
    assert_scalar_error(d, "infV", "not a finite number");
    assert_scalar_error(d, "huge", "keyword 'huge': not a finite number, found '1e999'");
    dict_free(d);
}

static void test_optional(void **state)
{
    dict *d = read_ok(VALID "fluidProperties");
    const double def[3] = {1, 2, 3};
    sl_err err = {{0}};
    double s = 0, v[3] = {0};
    long l = 0;
    int b = 0;
    const char *w = NULL;
    (void)state;
    assert_int_equal(dict_get_scalar_or(d, "none", 3.5, &s, &err), 0);
    assert_true(s == 3.5);
    assert_int_equal(dict_get_scalar_or(d, "rho0", 3.5, &s, &err), 0);
    assert_true(s == 998.2);
    assert_int_equal(dict_get_int_or(d, "none", 7, &l, &err), 0);
    assert_int_equal(l, 7);
    assert_int_equal(dict_get_word_or(d, "none", "dflt", &w, &err), 0);
    assert_string_equal(w, "dflt");
    assert_int_equal(dict_get_bool_or(d, "none", 1, &b, &err), 0);
    assert_int_equal(b, 1);
    assert_int_equal(dict_get_vector_or(d, "none", def, v, &err), 0);
    assert_true(v[0] == 1 && v[1] == 2 && v[2] == 3);
    assert_int_equal(dict_get_vector_or(d, "gravity", def, v, &err), 0);
    assert_true(v[2] == -9.81);
    /* Present but malformed is still an error. */
    assert_int_not_equal(dict_get_int_or(d, "nu", 7, &l, &err), 0);
    assert_has(err.msg, "keyword 'nu': expected an integer");
    assert_int_not_equal(dict_get_bool_or(d, "model", 0, &b, &err), 0);
    assert_int_not_equal(dict_get_scalar_or(d, "solver", 0, &s, &err), 0);
    assert_int_not_equal(dict_get_word_or(d, "gravity", "x", &w, &err), 0);
    assert_int_not_equal(dict_get_vector_or(d, "levels", def, v, &err), 0);
    dict_free(d);
}

/* ---- unknown keywords ------------------------------------------------------------ */

static void test_nearest(void **state)
{
    const char *const valid[] = {"rho0", "nu", "gamma", "solver", NULL};
    (void)state;
    assert_string_equal(dict_nearest("rh0", valid), "rho0");
    assert_string_equal(dict_nearest("gama", valid), "gamma");
    assert_string_equal(dict_nearest("slover", valid), "solver");
    assert_null(dict_nearest("temperature", valid));
    assert_int_equal(dict_edit_distance("kitten", "sitting"), 3);
    assert_int_equal(dict_edit_distance("", "abc"), 3);
}

static void test_warn_unknown(void **state)
{
    sl_err err = {{0}};
    dict *d = dict_parse_string("FoamFile { version 2.0; }\nrh0 1;\nnu 2;\ntemperature 3;\n",
                                "props", &err);
    const char *const valid[] = {"rho0", "nu", NULL};
    int count = -1;
    char *out;
    (void)state;
    assert_non_null(d);
    out = capture_stderr(dict_warn_unknown, d, valid, &count);
    assert_int_equal(count, 2);
    assert_has(out, "props:2: unknown keyword 'rh0' in dictionary 'props'; did you mean 'rho0'?");
    assert_has(out, "props:4: unknown keyword 'temperature' in dictionary 'props'\n");
    assert_null(strstr(out, "'nu'"));
    assert_null(strstr(out, "FoamFile"));
    free(out);
    dict_free(d);
}

static int warn_duplicates(const dict *d, const char *const *valid)
{
    (void)valid;
    return dict_warn_duplicates(d);
}

/* Issue 13, item 13: a key written twice in one file and dictionary is
 * reported with both lines; overriding a merged or #include'd entry is not. */
static void test_warn_duplicates(void **state)
{
    sl_err err = {{0}};
    int count = -1;
    (void)state;
    dict *d = dict_parse_string("a 1;\nb 2;\na 3;\ns { x 1;\n x 2; }\nbase { y 1; }\n"
                                "t { $base; y 2; }\n",
                                "props", &err);
    assert_non_null(d);
    char *out = capture_stderr(warn_duplicates, d, NULL, &count);
    assert_int_equal(count, 2);
    assert_has(out,
               "props:3: keyword 'a' in dictionary 'props' is set twice, at lines 1 and 3: "
               "the value of line 3 is used");
    assert_has(out, "props:5: keyword 'x' in dictionary 's' is set twice, at lines 4 and 5");
    assert_null(strstr(out, "'y'"));
    free(out);
    dict_free(d);
    /* an #include'd default overridden in the including file */
    FILE *f = fopen("tests/output/dict_defaults", "w");
    assert_non_null(f);
    fputs("eta 1;\n", f);
    fclose(f);
    f = fopen("tests/output/dict_main", "w");
    assert_non_null(f);
    fputs("#include \"dict_defaults\"\neta 2;\n", f);
    fclose(f);
    d = dict_read_file("tests/output/dict_main", &err);
    assert_non_null(d);
    out = capture_stderr(warn_duplicates, d, NULL, &count);
    assert_int_equal(count, 0);
    assert_string_equal(out, "");
    free(out);
    dict_free(d);
}

/* Item 15: after DICT_WARN_MAX lines the rest are one count; a key of
 * another file says where it belongs. */
static void test_warn_unknown_capped(void **state)
{
    sl_err err = {{0}};
    char text[4096] = "";
    int count = -1;
    (void)state;
    for (int i = 0; i < 25; i++)
        snprintf(text + strlen(text), sizeof text - strlen(text), "k%d 1;\n", i);
    strcat(text, "eta 1;\n");
    dict *d = dict_parse_string(text, "controlDict", &err);
    static const char *const valid[] = {"endTime", NULL};
    static const char *const fluid[] = {"eta", "rho0", NULL};
    const dict_key_home homes[] = {{"constant/fluidProperties", fluid}, {NULL, NULL}};
    assert_non_null(d);
    char *out = capture_stderr(dict_warn_unknown, d, valid, &count);
    assert_int_equal(count, 26);
    size_t lines = 0;
    for (const char *c = out; *c; c++) lines += *c == '\n';
    assert_int_equal(lines, DICT_WARN_MAX + 1);
    assert_has(out,
               "controlDict: ... and 16 more unknown keywords in dictionary 'controlDict' (the "
               "last at line 26)");
    free(out);
    /* the misplaced key, among the first ten */
    dict_free(d);
    d = dict_parse_string("eta 1;\n", "controlDict", &err);
    dict_warn_set_homes(homes);
    out = capture_stderr(dict_warn_unknown, d, valid, &count);
    dict_warn_set_homes(NULL);
    assert_has(out,
               "controlDict:1: unknown keyword 'eta' in dictionary 'controlDict': it belongs "
               "in constant/fluidProperties (ignored here)");
    free(out);
    dict_free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_header),
        cmocka_unit_test(test_scalars_and_words),
        cmocka_unit_test(test_bools),
        cmocka_unit_test(test_vectors_and_lists),
        cmocka_unit_test(test_nested_and_scoped),
        cmocka_unit_test(test_duplicate_keeps_position),
        cmocka_unit_test(test_spans),
        cmocka_unit_test(test_macros),
        cmocka_unit_test(test_include),
        cmocka_unit_test(test_parse_string),
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_include_chain_in_message),
        cmocka_unit_test(test_var_scopes),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_include_depth),
        cmocka_unit_test(test_long_tokens),
        cmocka_unit_test(test_many_keys),
        cmocka_unit_test(test_missing_key),
        cmocka_unit_test(test_bad_types),
        cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_optional),
        cmocka_unit_test(test_nearest),
        cmocka_unit_test(test_warn_unknown),
        cmocka_unit_test(test_warn_duplicates),
        cmocka_unit_test(test_warn_unknown_capped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
