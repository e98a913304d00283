/*
 * cf_plot: driving gnuplot (Debian's gnuplot-nox) through a pipe for the
 * plotting tools (plotSweep, monitorCase): the PNG terminal available
 * (pngcairo, else libgd's png) and gnuplot string quoting.
 */
#include "casefiles/casefiles.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>

const char *cf_plot_png_terminal(void)
{
    static const char *term;
    if (!term) {
        int rc = system("gnuplot -e 'set terminal pngcairo' </dev/null >/dev/null 2>&1");
        term = rc == 0 ? "pngcairo" : "png";
    }
    return term;
}

FILE *cf_plot_open(sl_err *err)
{
    FILE *p;
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) {
        sl_err_set(err, "gnuplot is not installed (Debian: apt-get install gnuplot-nox)");
        return NULL;
    }
    fflush(stdout);
    if (!(p = popen("gnuplot", "w"))) sl_err_set(err, "cannot start gnuplot");
    return p;
}

int cf_plot_close(FILE *p, sl_err *err)
{
    int status = pclose(p);
    if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        sl_err_set(err, "gnuplot failed (its messages are above)");
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
