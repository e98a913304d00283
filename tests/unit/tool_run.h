/*
 * tool_run: shared helpers of the tests that drive the programs in bin/:
 * run a formatted shell command keeping its output, and small file helpers.
 * Programs come from $SLUICE_BIN (tests/run_tests sets it), default bin/.
 * Include after <cmocka.h>.
 */
#ifndef SL_TEST_TOOL_RUN_H
#define SL_TEST_TOOL_RUN_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

static char output[1 << 16]; /* what the last run printed (stdout and stderr) */

static inline const char *bin_dir(void)
{
    const char *b = getenv("SLUICE_BIN");
    return b ? b : "bin";
}

/* Runs a shell command (formatted), keeps its output, returns its status. */
static int run(const char *fmt, ...) __attribute__((format(printf, 1, 2), unused));
static int run(const char *fmt, ...)
{
    char cmd[4096], full[4200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    snprintf(full, sizeof full, "( %s ) 2>&1", cmd);
    FILE *p = popen(full, "r");
    assert_non_null(p);
    size_t n = fread(output, 1, sizeof output - 1, p);
    output[n] = '\0';
    int status = pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

static inline char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
    s[n] = '\0';
    fclose(f);
    return s;
}

static inline void spit(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* The value of "group,series,metric" in a compareExperiment table.csv
 * (text csv); fails the test if absent. */
static inline double table_metric(const char *csv, const char *key)
{
    char pat[256];
    snprintf(pat, sizeof pat, "\n%s,", key);
    const char *at = strstr(csv, pat);
    if (!at) fail_msg("no metric '%s' in table.csv", key);
    at = strchr(at + strlen(pat), ','); /* skip the unit */
    assert_non_null(at);
    return strtod(at + 1, NULL);
}

static inline int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

#endif
