/* app: parsing a command line against a program's option table (see app.h). */
#include "app/app.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "dictionary/dict.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the table ---------------------------------------------------------------------- */

static size_t app_noptions(const app_info *info)
{
    size_t n = 0;
    while (info->options && info->options[n].name) n++;
    return n;
}

/* Whether word is one of the space-separated aliases. */
static int app_is_alias(const char *aliases, const char *word)
{
    size_t n = strlen(word);
    for (const char *p = aliases; p && *p;) {
        size_t len = strcspn(p, " ");
        if (len == n && !strncmp(p, word, n)) return 1;
        p += len;
        p += strspn(p, " ");
    }
    return 0;
}

/* Index of the option spelt `word` (its name, else an alias: *alias set), -1. */
static int app_lookup(const app_info *info, const char *word, int *alias)
{
    size_t n = app_noptions(info);
    *alias = 0;
    for (size_t i = 0; i < n; i++)
        if (!strcmp(info->options[i].name, word)) return (int)i;
    for (size_t i = 0; i < n; i++)
        if (app_is_alias(info->options[i].aliases, word)) {
            *alias = 1;
            return (int)i;
        }
    return -1;
}

/* Index of a declared option; an undeclared name is the program's bug. */
static int app_declared(const app *a, const char *name)
{
    int alias, i = app_lookup(a->info, name, &alias);
    if (i < 0 || alias)
        sl_fatal("%s: the program asks for option -%s, which its table does not declare (a bug)",
                 a->info->name, name);
    return i;
}

/* ---- errors ------------------------------------------------------------------------- */

static void app_usage_line(const app_info *info, FILE *out)
{
    fprintf(out, "Usage: %s [options]%s%s\n", info->name, info->args ? " " : "",
            info->args ? info->args : "");
}

static void app_verror(const app_info *info, const char *fmt, va_list ap)
    __attribute__((format(printf, 2, 0), noreturn));
static void app_verror(const app_info *info, const char *fmt, va_list ap)
{
    fflush(stdout);
    fprintf(stderr, "Error: %s: ", info->name);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    app_usage_line(info, stderr);
    fprintf(stderr, "Run '%s -help' for the options.\n", info->name);
    exit(2);
}

static void app_fail(const app_info *info, const char *fmt, ...)
    __attribute__((format(printf, 2, 3), noreturn));
static void app_fail(const app_info *info, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    app_verror(info, fmt, ap);
}

void app_error(const app *a, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    app_verror(a->info, fmt, ap);
}

/* ---- values ------------------------------------------------------------------------- */

int app_parse_long(const char *s, long *v)
{
    char *end;
    errno = 0;
    *v = strtol(s, &end, 10);
    return end == s || *end || errno != 0;
}

int app_parse_double(const char *s, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(s, &end);
    return end == s || *end || errno == ERANGE || !isfinite(*v);
}

/* Stops unless value suits option o (a number of its kind, in its range). */
static void app_check_value(const app_info *info, const app_option *o, const char *value)
{
    double x;
    long l;
    if (o->kind == APP_INT) {
        if (app_parse_long(value, &l))
            app_fail(info, "-%s: '%s' is not an integer", o->name, value);
        x = (double)l;
    } else if (o->kind == APP_DOUBLE) {
        if (app_parse_double(value, &x))
            app_fail(info, "-%s: '%s' is not a number", o->name, value);
    } else {
        if (!*value && o->kind != APP_STRING) app_fail(info, "-%s: an empty name", o->name);
        return;
    }
    if (!(o->min < o->max)) return;
    if (o->above_min && !(x > o->min))
        app_fail(info, "-%s: '%s' must be above %g", o->name, value, o->min);
    if (x < o->min || x > o->max) {
        if (isinf(o->max)) app_fail(info, "-%s: '%s' must be at least %g", o->name, value, o->min);
        app_fail(info, "-%s: '%s' must be from %g to %g", o->name, value, o->min, o->max);
    }
}

/* ---- parsing ------------------------------------------------------------------------ */

/* "did you mean -x?" for an unknown option, from the names declared. */
static void app_unknown(const app_info *info, const char *arg)
{
    size_t n = app_noptions(info);
    const char **names = sl_malloc((n + 2) * sizeof *names, "option names");
    for (size_t i = 0; i < n; i++) names[i] = info->options[i].name;
    names[n] = "help";
    names[n + 1] = NULL;
    const char *near = dict_nearest(arg + 1, names);
    if (near) app_fail(info, "unknown option '%s'; did you mean -%s?", arg, near);
    app_fail(info, "unknown option '%s'", arg);
}

static void app_add(app *a, int opt, const char *value)
{
    a->given = sl_realloc(a->given, (a->ngiven + 1) * sizeof *a->given, "options");
    a->given[a->ngiven].opt = opt;
    a->given[a->ngiven++].value = value;
}

/* The option at argv[*i]; takes its argument too. */
static void app_option_arg(app *a, int argc, char **argv, int *i)
{
    const app_info *info = a->info;
    const char *arg = argv[*i];
    int alias, k = app_lookup(info, arg + 1, &alias);
    if (k < 0) app_unknown(info, arg);
    const app_option *o = &info->options[k];
    if (alias)
        fprintf(stderr, "Warning: %s: %s is an old spelling: use -%s\n", info->name, arg, o->name);
    for (size_t g = 0; g < a->ngiven; g++)
        if (a->given[g].opt == k && !o->repeat) app_fail(info, "-%s is given twice", o->name);
    const char *value = NULL;
    if (o->kind != APP_NONE) {
        if (*i + 1 >= argc)
            app_fail(info, "-%s needs an argument %s", o->name, o->arg ? o->arg : "");
        value = argv[++*i];
        app_check_value(info, o, value);
    }
    app_add(a, k, value);
}

/* The words after which everything is an argument: "--". */
static int app_is_option(const char *s) { return s[0] == '-' && s[1] != '\0'; }

void app_parse(app *a, const app_info *info, int argc, char **argv)
{
    int rest = 0;
    memset(a, 0, sizeof *a);
    a->info = info;
    a->args = sl_malloc(((size_t)argc + 1) * sizeof *a->args, "arguments");
    for (int i = 1; i < argc; i++) {
        const char *s = argv[i];
        if (!rest && (!strcmp(s, "-help") || !strcmp(s, "--help"))) {
            app_print_help(info, stdout);
            exit(0);
        } else if (!rest && !strcmp(s, "-completionWords")) {
            app_print_completion(info, stdout);
            exit(0);
        } else if (!rest && !strcmp(s, "--")) {
            rest = 1;
        } else if (!rest && app_is_option(s)) {
            app_option_arg(a, argc, argv, &i);
        } else {
            a->args[a->nargs++] = s;
        }
    }
    if (a->nargs < (size_t)info->min_args)
        app_fail(info, "missing argument%s: %s", info->min_args - (int)a->nargs > 1 ? "s" : "",
                 info->args ? info->args : "");
    if (info->max_args >= 0 && a->nargs > (size_t)info->max_args)
        app_fail(info, "unexpected argument '%s'", a->args[info->max_args]);
    int dummy;
    if (app_lookup(info, "time", &dummy) >= 0 && app_lookup(info, "latestTime", &dummy) >= 0 &&
        app_found(a, "time") && app_found(a, "latestTime"))
        app_fail(info, "give -time or -latestTime, not both");
}

void app_free(app *a)
{
    free(a->given);
    free((void *)a->args);
    memset(a, 0, sizeof *a);
}

/* ---- looking up --------------------------------------------------------------------- */

size_t app_count(const app *a, const char *name)
{
    int k = app_declared(a, name);
    size_t n = 0;
    for (size_t g = 0; g < a->ngiven; g++) n += a->given[g].opt == k;
    return n;
}

int app_found(const app *a, const char *name) { return app_count(a, name) > 0; }

const char *app_value_at(const app *a, const char *name, size_t i)
{
    int k = app_declared(a, name);
    for (size_t g = 0; g < a->ngiven; g++)
        if (a->given[g].opt == k && i-- == 0) return a->given[g].value;
    return NULL;
}

const char *app_string(const app *a, const char *name, const char *def)
{
    size_t n = app_count(a, name);
    const char *v = n ? app_value_at(a, name, n - 1) : NULL;
    return v ? v : def;
}

long app_int(const app *a, const char *name, long def)
{
    const char *v = app_string(a, name, NULL);
    long x;
    if (!v) return def;
    if (a->info->options[app_declared(a, name)].kind != APP_INT || app_parse_long(v, &x))
        sl_fatal("%s: option -%s is not declared APP_INT (a bug)", a->info->name, name);
    return x;
}

double app_double(const app *a, const char *name, double def)
{
    const char *v = app_string(a, name, NULL);
    double x;
    if (!v) return def;
    if (app_parse_double(v, &x)) app_error(a, "-%s: '%s' is not a number", name, v);
    return x;
}

const char *app_case(const app *a) { return app_string(a, "case", "."); }

const char *app_case_or_arg(const app *a)
{
    if (a->nargs && app_found(a, "case"))
        app_error(a, "give the case as -case or as the argument, not both");
    return a->nargs ? a->args[0] : app_case(a);
}

void app_times(const app *a, const char *case_dir, const char *marker, int with_first,
               tdir_list *out)
{
    sl_err err;
    if (tdir_list_read(case_dir, marker, out, &err)) sl_fatal("%s", err.msg);
    if (tdir_select(out, app_string(a, "time", NULL), app_found(a, "latestTime"), with_first, &err))
        app_error(a, "%s", err.msg);
}
