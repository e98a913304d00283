/* Tests of the application frame (libsrc/app) on a table of its own, in
 * this process: values and their checks, repeated options, old spellings,
 * "--", the usage errors (run in a child, whose stderr and exit status are
 * kept), the generated -help, and io's time selection (tdir_select) that
 * -time and -latestTime use.  test_tools.c checks the same on the programs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "app/app.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static const app_option options[] = {
    APP_CASE,
    APP_TIMES,
    {.name = "jobs", .kind = APP_INT, .help = "runs at a time", .def = "4", .min = 1, .max = 64},
    {.name = "refresh",
     .kind = APP_DOUBLE,
     .arg = "<s>",
     .help = "seconds",
     .min = 0,
     .max = INFINITY,
     .above_min = 1},
    {.name = "func", .kind = APP_STRING, .help = "a function\nrepeat for more", .repeat = 1},
    {.name = "dryRun", .help = "only say", .aliases = "dry-run n"},
    APP_END};

static const app_info info = {.name = "testApp",
                              .what = "A program of the tests.",
                              .options = options,
                              .args = "[<file>...]",
                              .max_args = -1};

/* argv from a string of words (no quoting). */
static int split(char *line, char **argv, int max)
{
    int n = 0;
    argv[n++] = "testApp";
    for (char *w = strtok(line, " "); w && n < max - 1; w = strtok(NULL, " ")) argv[n++] = w;
    argv[n] = NULL;
    return n;
}

static void parse(app *a, const char *words)
{
    static char line[512];
    static char *argv[64];
    snprintf(line, sizeof line, "%s", words);
    app_parse(a, &info, split(line, argv, 64), argv);
}

/* Runs app_parse in a child: its exit status, and stderr + stdout in out. */
static int parse_in_child(const char *words, char *out, size_t len)
{
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        dup2(fd[1], STDERR_FILENO);
        dup2(fd[1], STDOUT_FILENO);
        close(fd[0]);
        app a;
        parse(&a, words);
        exit(99); /* parsed without stopping */
    }
    close(fd[1]);
    size_t n = 0;
    ssize_t r;
    while (n + 1 < len && (r = read(fd[0], out + n, len - 1 - n)) > 0) n += (size_t)r;
    out[n] = '\0';
    close(fd[0]);
    int status;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void test_values(void **state)
{
    (void)state;
    app a;
    parse(&a, "-jobs 8 -case there -func a x -refresh 0.5 -func b -- -notAnOption");
    assert_int_equal(app_int(&a, "jobs", 4), 8);
    assert_string_equal(app_case(&a), "there");
    assert_true(app_double(&a, "refresh", 5) == 0.5);
    assert_int_equal(app_count(&a, "func"), 2);
    assert_string_equal(app_value_at(&a, "func", 0), "a");
    assert_string_equal(app_value_at(&a, "func", 1), "b");
    assert_false(app_found(&a, "dryRun"));
    assert_false(app_found(&a, "latestTime"));
    assert_int_equal(a.nargs, 2);
    assert_string_equal(a.args[0], "x");
    assert_string_equal(a.args[1], "-notAnOption"); /* after "--" */
    app_free(&a);
    parse(&a, "");
    assert_int_equal(app_int(&a, "jobs", 4), 4);
    assert_string_equal(app_case(&a), ".");
    assert_null(app_string(&a, "time", NULL));
    app_free(&a);
}

static void test_old_spelling(void **state)
{
    (void)state;
    char out[4096];
    assert_int_equal(parse_in_child("-dry-run", out, sizeof out), 99);
    assert_string_equal(out, "Warning: testApp: -dry-run is an old spelling: use -dryRun\n");
    assert_int_equal(parse_in_child("-dryRun", out, sizeof out), 99);
    assert_string_equal(out, "");
}

static void test_usage_errors(void **state)
{
    (void)state;
    static const char *const bad[][2] = {
        {"-jobs four", "testApp: -jobs: 'four' is not an integer\n"},
        {"-jobs 4.5", "testApp: -jobs: '4.5' is not an integer\n"},
        {"-jobs 99999999999999999999", "is not an integer"},
        {"-jobs 65", "testApp: -jobs: '65' must be from 1 to 64\n"},
        {"-refresh 0", "testApp: -refresh: '0' must be above 0\n"},
        {"-refresh -1", "testApp: -refresh: '-1' must be above 0\n"},
        {"-refresh inf", "testApp: -refresh: 'inf' is not a number\n"},
        {"-refresh", "testApp: -refresh needs an argument <s>\n"},
        {"-jbos 2", "testApp: unknown option '-jbos'; did you mean -jobs?\n"},
        {"-xyzzyq", "testApp: unknown option '-xyzzyq'\n"},
        {"-jobs 2 -jobs 3", "testApp: -jobs is given twice\n"},
        {"-time 1 -latestTime", "testApp: give -time or -latestTime, not both\n"},
    };
    char out[4096];
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        int rc = parse_in_child(bad[i][0], out, sizeof out);
        if (rc != 2 || !strstr(out, bad[i][1]) ||
            !strstr(out, "Usage: testApp [options] [<file>...]\n"))
            fail_msg("'%s': status %d, output\n%s", bad[i][0], rc, out);
    }
}

/* -help: usage, every option with its argument, default and help lines,
 * -help itself, the old spellings, then the description; exit 0. */
static void test_help(void **state)
{
    (void)state;
    char out[8192];
    assert_int_equal(parse_in_child("-jobs x -help", out, sizeof out), 2); /* -jobs x first */
    assert_int_equal(parse_in_child("-help", out, sizeof out), 0);
    const char *want[] = {
        "Usage: testApp [options] [<file>...]\n\nOptions:\n",
        "\n  -case <dir>    the case (default: the current directory)\n",
        "\n  -time <times>  only these times",
        "\n  -latestTime    only the latest time\n",
        "\n  -jobs <N>      runs at a time (default: 4)\n",
        "\n  -refresh <s>   seconds\n",
        "\n  -func <word>   a function\n                 repeat for more\n",
        "\n  -dryRun        only say\n",
        "\n  -help          print this help\n",
        "\nOld spellings, still accepted with a warning:\n  -dry-run, -n: use -dryRun\n",
        "\n\n  A program of the tests.\n"};
    for (size_t i = 0; i < sizeof want / sizeof *want; i++)
        if (!strstr(out, want[i])) fail_msg("-help lacks '%s':\n%s", want[i], out);
    assert_int_equal(parse_in_child("-completionWords", out, sizeof out), 0);
    assert_string_equal(out,
                        "-case dir\n-time string\n-latestTime none\n-jobs int\n"
                        "-refresh double\n-func string\n-dryRun none\n-help none\n@args path\n");
}

/* ---- tdir_select -------------------------------------------------------------- */

static void make_list(tdir_list *l, const double *t, size_t n)
{
    l->n = n;
    l->time = malloc(n * sizeof *l->time);
    l->name = malloc(n * sizeof *l->name);
    for (size_t i = 0; i < n; i++) {
        char buf[32];
        l->time[i] = t[i];
        tdir_name(t[i], 6, buf, sizeof buf);
        l->name[i] = strdup(buf);
    }
}

/* The names left, space-separated. */
static const char *selected(const char *spec, int latest, int with_first)
{
    static const double t[] = {0, 0.1, 0.2, 0.30000000000000004, 1, 2.5};
    static char out[1100];
    tdir_list l;
    sl_err err;
    make_list(&l, t, sizeof t / sizeof *t);
    if (tdir_select(&l, spec, latest, with_first, &err)) {
        snprintf(out, sizeof out, "error: %s", err.msg);
    } else {
        out[0] = '\0';
        for (size_t i = 0; i < l.n; i++) {
            strcat(out, i ? " " : "");
            strcat(out, l.name[i]);
        }
    }
    tdir_list_free(&l);
    return out;
}

static void test_time_selection(void **state)
{
    (void)state;
    assert_string_equal(selected(NULL, 0, 1), "0 0.1 0.2 0.3 1 2.5");
    assert_string_equal(selected(NULL, 0, 0),
                        "0.1 0.2 0.3 1 2.5"); /* listTimes without -withZero */
    assert_string_equal(selected(NULL, 1, 1), "2.5");
    assert_string_equal(selected("0.3", 0, 1), "0.3"); /* within 1e-9 (1 + |t|) */
    assert_string_equal(selected("0.1:0.3", 0, 1), "0.1 0.2 0.3");
    assert_string_equal(selected(":0.1", 0, 1), "0 0.1");
    assert_string_equal(selected(":0.1", 0, 0), "0.1");
    assert_string_equal(selected("1:", 0, 1), "1 2.5");
    assert_string_equal(selected("0, 0.2 ,2:", 0, 1), "0 0.2 2.5");
    assert_string_equal(selected("0.1:0.3", 1, 1), "0.3"); /* latest of the selection */
    assert_string_equal(selected("7", 0, 1), "");
    assert_non_null(strstr(selected("0.1,x", 0, 1), "error: -time '0.1,x': expected times"));
    assert_non_null(strstr(selected("", 0, 1), "error: -time '': expected"));
    assert_non_null(strstr(selected("1:2:3", 0, 1), "error:"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_values),         cmocka_unit_test(test_old_spelling),
        cmocka_unit_test(test_usage_errors),   cmocka_unit_test(test_help),
        cmocka_unit_test(test_time_selection),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
