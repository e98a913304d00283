/* dict_fatal: the one way a reader stops on a bad entry (see dict.h). */
#include "dictionary/dict.h"

#include <stdarg.h>
#include <stdio.h>

void dict_need(int status, const sl_err *err)
{
    if (status) sl_fatal("%s", err->msg);
}

void dict_fatal(const dict *d, const char *key, const char *fmt, ...)
{
    char why[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    const dict_entry *e = dict_lookup(d, key);
    if (e) sl_fatal("%s:%d: keyword '%s': %s", dict_entry_file(e), dict_entry_line(e), key, why);
    sl_fatal("%s: keyword '%s' (not set: the default): %s", dict_file(d), key, why);
}

double dict_need_positive(const dict *d, const char *key, double v)
{
    if (!(v > 0.0)) dict_fatal(d, key, "must be a positive number");
    return v;
}
