/* sl_log: messages and the fatal-error exit (see sl_log.h). */
#include "core/sl_log.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

static int quiet_, secondary_;
static void (*fatal_hook_)(void);

void sl_log_set_quiet(int quiet) { quiet_ = quiet; }

void sl_log_set_secondary(int rank) { secondary_ = rank; }

void sl_log_set_fatal_hook(void (*hook)(void)) { fatal_hook_ = hook; }

void sl_err_set(sl_err *e, const char *fmt, ...)
{
    va_list ap;
    if (!e) return;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
}

void sl_info(const char *fmt, ...)
{
    va_list ap;
    if (quiet_ || secondary_) return;
    va_start(ap, fmt);
    vfprintf(stdout, fmt, ap);
    va_end(ap);
    fputc('\n', stdout);
    fflush(stdout);
}

void sl_warning(const char *fmt, ...)
{
    va_list ap;
    if (secondary_) return;
    fflush(stdout);
    fputs("Warning: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

void sl_fatal_at(const char *src, int line, const char *fmt, ...)
{
    va_list ap;
    void (*hook)(void) = fatal_hook_;
    fflush(stdout);
    if (secondary_) fprintf(stderr, "rank %d: ", secondary_);
    fputs("Error: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
#ifdef SL_DEBUG
    fprintf(stderr, "  (raised at %s:%d)\n", src, line);
#else
    (void)src;
    (void)line;
#endif
    fatal_hook_ = NULL;
    if (hook) hook();
    exit(1);
}
