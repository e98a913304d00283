/*
 * app: the frame of every Sluice program, in the habit of OpenFOAM's
 * argList and timeSelector.  A program declares its options in a table;
 * the frame parses argv against it and gives
 *   - `-help`: the usage line, the options (with their defaults), then the
 *     description, all generated from the table;
 *   - checked values: `-jobs abc` stops with "Error: sweepCase: -jobs:
 *     'abc' is not an integer" and exit status 2, before anything is done; ranges
 *     (min, max) are checked the same way;
 *   - unknown options refused with the nearest declared one ("did you mean
 *     -latestTime?"), missing arguments and options given twice refused;
 *   - one spelling per option, camelCase as OpenFOAM; old spellings listed
 *     in `aliases` still work and print a one-line warning;
 *   - the shared `-case` (APP_CASE) and `-time`/`-latestTime` (APP_TIMES,
 *     with app_times: OpenFOAM's time selection);
 *   - the hidden `-completionWords`: one line per option, "-name kind
 *     [glob]", then "@args kind", that etc/bash_completion asks for.
 *
 * A program (ten lines; designated initializers, so that -Wextra is quiet
 * and the kind defaults to APP_NONE, a switch):
 *
 *   static const app_option options[] = {
 *       APP_CASE,
 *       APP_TIMES,
 *       {.name = "jobs", .kind = APP_INT, .help = "cases run at a time", .def = "4",
 *        .min = 1, .max = 4096},
 *       {.name = "dryRun", .help = "only print what would be removed", .aliases = "dry-run n"},
 *       APP_END};
 *   static const app_info info = {.name = "cleanCase", .what = "Removes the results ...",
 *                                 .options = options, .args = "[<case>]", .max_args = 1};
 *   int main(int argc, char **argv) {
 *       app a;
 *       app_parse(&a, &info, argc, argv);
 *       int dry = app_found(&a, "dryRun");
 *       long jobs = app_int(&a, "jobs", 4);
 *       const char *dir = a.nargs ? a.args[0] : app_case(&a);
 *       ...
 *       app_free(&a);
 *   }
 *
 * Looking up a name the table does not declare is a programming error,
 * reported as such (so a typo fails on the first run, not silently).
 * Errors of the command line exit with status 2; sl_fatal's are 1.
 */
#ifndef SL_APP_H
#define SL_APP_H

#include <stddef.h>
#include <stdio.h>

#include "io/time_dir.h"

typedef enum app_kind {
    APP_NONE,   /* a switch: -force */
    APP_INT,    /* a whole number (strtol, all of it, within long) */
    APP_DOUBLE, /* a finite number */
    APP_STRING, /* any word */
    APP_PATH,   /* a file (completes file names) */
    APP_DIR     /* a folder (completes folder names) */
} app_kind;

typedef struct app_option {
    const char *name; /* camelCase, without the '-' */
    app_kind kind;
    const char *arg;     /* the argument in -help ("<N>"); NULL: from the kind */
    const char *help;    /* what it does; '\n' starts a new line of help */
    const char *def;     /* the default as -help shows it ("5"); NULL: none shown */
    const char *aliases; /* old spellings, space-separated ("dry-run n"): a warning */
    double min, max;     /* APP_INT, APP_DOUBLE: the range, checked when min < max */
    int above_min;       /* the value must be above min, not equal to it */
    int repeat;          /* may be given more than once (app_count, app_value_at) */
    const char *glob;    /* APP_PATH: what bash completes ("*.png"); NULL: any file */
} app_option;

/* The shared options.  APP_TIMES is two entries, -time and -latestTime. */
#define APP_CASE                                                                              \
    {                                                                                         \
        "case", APP_DIR, "<dir>", "the case", "the current directory", NULL, 0, 0, 0, 0, NULL \
    }
#define APP_TIMES                                                                          \
    {"time",                                                                               \
     APP_STRING,                                                                           \
     "<times>",                                                                            \
     "only these times: times and ranges, comma-separated,\n"                              \
     "e.g. 0.5  0.5:1  :0.2  0.8:  0,0.5:1 (inclusive)",                                   \
     NULL,                                                                                 \
     NULL,                                                                                 \
     0,                                                                                    \
     0,                                                                                    \
     0,                                                                                    \
     0,                                                                                    \
     NULL},                                                                                \
    {                                                                                      \
        "latestTime", APP_NONE, NULL, "only the latest time", NULL, NULL, 0, 0, 0, 0, NULL \
    }
/* -jobs <N> (runs at a time, default the cores) and -threads <T> of the
 * programs that run the solver several times (sweepCase, stableTimeStep). */
#define APP_JOBS(what)                                                                         \
    {                                                                                          \
        .name = "jobs", .kind = APP_INT, .help = what, .def = "the number of cores", .min = 1, \
        .max = 4096                                                                            \
    }
#define APP_THREADS(what, def_)                                                                \
    {                                                                                          \
        .name = "threads", .kind = APP_INT, .arg = "<T>", .help = what, .def = def_, .min = 1, \
        .max = 4096                                                                            \
    }
#define APP_END                                                  \
    {                                                            \
        NULL, APP_NONE, NULL, NULL, NULL, NULL, 0, 0, 0, 0, NULL \
    }

typedef struct app_info {
    const char *name;          /* the program, as the user types it */
    const char *what;          /* the description (paragraphs; -help prints it last) */
    const app_option *options; /* ends with APP_END; -help is added by the frame */
    const char *args;          /* the arguments in the usage line ("<source> <new case>") */
    int min_args, max_args;    /* how many arguments (max_args < 0: any number) */
    app_kind args_kind;        /* what bash completes for them (APP_NONE: files) */
    const char *notes;         /* printed after the description (syntax, examples) */
} app_info;

typedef struct app_given {
    int opt;           /* index in the table */
    const char *value; /* its argument (NULL for a switch) */
} app_given;

typedef struct app {
    const app_info *info;
    app_given *given; /* in command-line order */
    size_t ngiven;
    const char **args; /* the arguments that are not options */
    size_t nargs;
} app;

/* Parse argv against info.  Exits 0 after -help or -completionWords, 2
 * (with a one-line message and the usage line on stderr) on a bad command
 * line.  -time with -latestTime is refused when both are declared. */
void app_parse(app *a, const app_info *info, int argc, char **argv);
void app_free(app *a);

/* Whether the option was given (a switch, or an option with a value). */
int app_found(const app *a, const char *name);
/* The value of an option given once (the last if it may repeat), or def. */
const char *app_string(const app *a, const char *name, const char *def);
long app_int(const app *a, const char *name, long def);
double app_double(const app *a, const char *name, double def);
/* A repeatable option: how often it was given, and the i-th value. */
size_t app_count(const app *a, const char *name);
const char *app_value_at(const app *a, const char *name, size_t i);

/* -case, or the current directory ".". */
const char *app_case(const app *a);
/* The case of a program that also takes it as its one argument (listTimes,
 * cleanCase): the argument, else -case, else "."; both is an error. */
const char *app_case_or_arg(const app *a);

/* The time directories of case_dir holding `marker` (e.g. "fluid.vtu")
 * that -time / -latestTime select (all without them); the first one (the
 * initial state) is left out unless with_first.  Stops (sl_fatal) on a
 * malformed -time.  The list may be empty.  Free with tdir_list_free. */
void app_times(const app *a, const char *case_dir, const char *marker, int with_first,
               tdir_list *out);

/* A command-line error found by the program itself (e.g. two options that
 * exclude each other): "Error: <program>: <message>", the usage line, exit 2. */
void app_error(const app *a, const char *fmt, ...) __attribute__((format(printf, 2, 3), noreturn));

/* The help text and the completion words, as -help and -completionWords
 * print them (for tests). */
void app_print_help(const app_info *info, FILE *out);
void app_print_completion(const app_info *info, FILE *out);

/* A whole number or a finite number filling s; 0 on success. */
int app_parse_long(const char *s, long *v);
int app_parse_double(const char *s, double *v);

#endif
