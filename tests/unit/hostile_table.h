/*
 * hostile_table: the record from which doc/hostile-inputs.md is generated.
 *
 * Every test that checks that an input is refused calls
 *
 *     hostile_record("class", "input", message);
 *
 * after the check passed: one row "class<TAB>input<TAB>message" is appended
 * to $SLUICE_HOSTILE_TSV (tests/run_tests sets it; default
 * tests/output/hostile_inputs.tsv).  `class` groups inputs of one kind
 * ("controlDict value", "mesh file", "restart file", ...), `input` says what
 * the user gave, and `message` is what the program printed: its first line
 * holding "Error:" (else "Warning:", else its first line) is kept.
 * tests/hostile_table turns the rows into the Markdown table (sorted, one
 * row per class and input, case paths shortened to <case>/); tests/run_tests
 * does it after a full passing run, so the table lists exactly what the
 * tests check.  Include after <cmocka.h> or on its own.
 */
#ifndef SL_TEST_HOSTILE_TABLE_H
#define SL_TEST_HOSTILE_TABLE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Tabs and line ends would break the row: write them as spaces. */
static inline void hostile_put_cell(FILE *f, const char *s, size_t n)
{
    for (size_t i = 0; i < n && s[i]; i++)
        fputc(s[i] == '\t' || s[i] == '\n' || s[i] == '\r' ? ' ' : s[i], f);
}

/* The line of `text` to show: the first holding `tag`, or NULL. */
static inline const char *hostile_line_with(const char *text, const char *tag, size_t *len)
{
    const char *at = strstr(text, tag);
    if (!at) return NULL;
    while (at > text && at[-1] != '\n') at--;
    const char *end = strchr(at, '\n');
    *len = end ? (size_t)(end - at) : strlen(at);
    return at;
}

/* A class for a row that has none: the case file the message names (the
 * text after "<case_dir>/" up to ':', a quote or a space; "mesh file" for
 * an .stl or .obj, "#include'd file" for a path with "../"), else "case". */
static inline const char *hostile_class_of(const char *message, const char *case_dir, char *buf,
                                           size_t len)
{
    size_t n = strlen(case_dir);
    const char *at = message;
    snprintf(buf, len, "case");
    while ((at = strstr(at, case_dir)) != NULL) {
        at += n;
        if (*at != '/') continue;
        at++;
        size_t k = strcspn(at, ": '\"\n");
        if (k > 0) snprintf(buf, len, "%.*s", (int)k, at);
        if (k > 4 && (!strncmp(at + k - 4, ".stl", 4) || !strncmp(at + k - 4, ".obj", 4)))
            snprintf(buf, len, "mesh file");
        else if (k > 0 && strstr(buf, "../")) snprintf(buf, len, "#include'd file");
        break;
    }
    return buf;
}

static inline void hostile_record(const char *cls, const char *input, const char *message)
{
    const char *path = getenv("SLUICE_HOSTILE_TSV");
    size_t len = 0;
    const char *line = hostile_line_with(message, "Error:", &len);
    if (!line) line = hostile_line_with(message, "Warning:", &len);
    if (!line) {
        line = message;
        len = strcspn(message, "\n");
    }
    if (!path) {
        mkdir("tests", 0777);
        mkdir("tests/output", 0777);
        path = "tests/output/hostile_inputs.tsv";
    }
    FILE *f = fopen(path, "a");
    if (!f) return; /* the table is a by-product: never fail a test for it */
    hostile_put_cell(f, cls, strlen(cls));
    fputc('\t', f);
    hostile_put_cell(f, input, strlen(input));
    fputc('\t', f);
    hostile_put_cell(f, line, len);
    fputc('\n', f);
    fclose(f);
}

#endif
