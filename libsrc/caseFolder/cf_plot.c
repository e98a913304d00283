/*
 * cf_plot: the one gnuplot runner (Debian's gnuplot-nox) of the tools --
 * a pipe to a new gnuplot for those that draw from inline data (plotSweep,
 * monitorCase), a script file run in its folder for those that leave the
 * script beside the data to run again (densityError, compareExperiment,
 * monitorCase -script) --
 * both started by sl_proc, so a missing gnuplot is one message; plus the
 * PNG terminal available (pngcairo, else libgd's png) and string quoting.
 */
#include "caseFolder/caseFolder.h"

#include "core/sl_proc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char cf_plot_missing[] =
    "gnuplot is not installed (Debian: apt-get install gnuplot-nox)";

/* The pipes open now and their gnuplots (a tool draws one plot at a time). */
enum { CF_PLOT_MAX = 4 };
static struct {
    FILE *f;
    pid_t pid;
} cf_plots[CF_PLOT_MAX];

/* Starting failed: "not installed" when gnuplot is not found. */
static void cf_plot_start_error(sl_err *err)
{
    if (strstr(err->msg, "cannot run gnuplot:")) sl_err_set(err, "%s", cf_plot_missing);
}

const char *cf_plot_png_terminal(void)
{
    static const char *term;
    if (!term) {
        const char *argv[] = {"gnuplot", "-e", "set terminal pngcairo", NULL};
        sl_proc p = {.argv = argv, .input = "/dev/null", .log = "/dev/null"};
        int status;
        term = sl_proc_run(&p, &status, NULL) == 0 && sl_proc_ok(status) ? "pngcairo" : "png";
    }
    return term;
}

FILE *cf_plot_open(sl_err *err)
{
    const char *argv[] = {"gnuplot", NULL};
    sl_proc p = {.argv = argv, .pipe_input = 1};
    FILE *f = NULL;
    int k = 0;
    while (k < CF_PLOT_MAX && cf_plots[k].f) k++;
    if (k == CF_PLOT_MAX) {
        sl_err_set(err, "more than %d gnuplots at once", CF_PLOT_MAX);
        return NULL;
    }
    pid_t pid = sl_proc_start(&p, &f, err);
    if (pid < 0) {
        cf_plot_start_error(err);
        return NULL;
    }
    cf_plots[k].f = f;
    cf_plots[k].pid = pid;
    return f;
}

int cf_plot_close(FILE *p, sl_err *err)
{
    int k = 0, status = 0;
    while (k < CF_PLOT_MAX && cf_plots[k].f != p) k++;
    if (k == CF_PLOT_MAX) {
        sl_err_set(err, "cf_plot_close: not a gnuplot pipe");
        return 1;
    }
    int bad = fclose(p) != 0;
    bad |= sl_proc_wait(cf_plots[k].pid, &status, 0, err) < 0 || !sl_proc_ok(status);
    cf_plots[k].f = NULL;
    if (bad) sl_err_set(err, "gnuplot failed (its messages are above)");
    return bad;
}

int cf_plot_script(const char *dir, const char *script, const char *const *args, sl_err *err)
{
    const char *argv[16] = {"gnuplot"};
    size_t n = 1;
    if (args) argv[n++] = "-c";
    argv[n++] = script;
    for (size_t i = 0; args && args[i]; i++) {
        if (n + 1 >= sizeof argv / sizeof *argv) {
            sl_err_set(err, "gnuplot %s: too many arguments", script);
            return 1;
        }
        argv[n++] = args[i];
    }
    argv[n] = NULL;
    sl_proc p = {.argv = argv, .dir = dir, .input = "/dev/null"};
    int status;
    if (sl_proc_run(&p, &status, err)) {
        cf_plot_start_error(err);
        return 1;
    }
    if (!sl_proc_ok(status)) {
        char why[64];
        sl_proc_describe(status, why, sizeof why);
        sl_err_set(err, "gnuplot failed on %s%s%s (%s)", dir ? dir : "", dir ? "/" : "", script,
                   why);
        return 1;
    }
    return 0;
}

void cf_plot_string(FILE *p, const char *s)
{
    fputc('\'', p);
    for (; *s; s++) {
        if (*s == '\'') fputc('\'', p); /* '' inside '...' */
        if (*s != '\n') fputc(*s, p);
    }
    fputc('\'', p);
}
