/* fo_util: key reading with file/line errors and value writing shared by
 * the function-object types (see fo_type.h). */
#include "functionObjects/fo_type.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void fo_bad_key(const dict *d, const char *key, const char *why)
{
    const dict_entry *e = dict_lookup(d, key);
    if (e)
        sl_fatal("%s:%d: keyword '%s' in function object '%s': %s", dict_entry_file(e),
                 dict_entry_line(e), key, dict_name(d), why);
    sl_fatal("%s: keyword '%s' in function object '%s': %s", dict_file(d), key, dict_name(d), why);
}

void fo_need(int status, const sl_err *err)
{
    if (status) sl_fatal("%s", err->msg);
}

static const char *skip_space(const char *s)
{
    while (isspace((unsigned char)*s)) s++;
    return s;
}

/* An optional list size before '(' ("3(...)"); returns -1 if there is none. */
static long list_size(const char **s)
{
    const char *p = *s;
    if (!isdigit((unsigned char)*p)) return -1;
    long n = strtol(p, (char **)&p, 10);
    *s = p;
    return n;
}

/* Parses "((x y z) ...)" (or with list sizes) into a malloc'd array;
 * returns NULL with *why set on a syntax error. */
static double *parse_points(const char *text, int dim, size_t *n, const char **why)
{
    const char *s = skip_space(text);
    size_t cap = 8;
    double *pts = sl_malloc(cap * (size_t)dim * sizeof *pts, "points");
    long want = list_size(&s);
    *n = 0;
    *why = "expected a list of points, e.g. ((0.5 0.3 0.1) (1.0 0.3 0.1))";
    if (*s++ != '(') goto bad;
    for (;;) {
        s = skip_space(s);
        if (*s == ')') break;
        long inner = list_size(&s);
        if (*s++ != '(' || (inner >= 0 && inner != dim)) goto bad;
        if (*n == cap) {
            cap *= 2;
            pts = sl_realloc(pts, cap * (size_t)dim * sizeof *pts, "points");
        }
        for (int k = 0; k < dim; k++) {
            char *end;
            double v = strtod(s, &end);
            if (end == s) {
                *why = dim == 3 ? "every point must be (x y z)" : "every location must be (x y)";
                goto bad;
            }
            if (!isfinite(v)) {
                *why = "coordinates must be finite numbers";
                goto bad;
            }
            pts[*n * (size_t)dim + (size_t)k] = v;
            s = end;
        }
        s = skip_space(s);
        if (*s++ != ')') {
            *why = dim == 3 ? "every point must be (x y z)" : "every location must be (x y)";
            goto bad;
        }
        (*n)++;
    }
    s = skip_space(s + 1);
    if (*s) goto bad;
    if (want >= 0 && (size_t)want != *n) {
        *why = "the list size does not match the number of points";
        goto bad;
    }
    if (*n == 0) {
        *why = "needs at least one point";
        goto bad;
    }
    return pts;
bad:
    free(pts);
    return NULL;
}

void fo_get_points(const dict *d, const char *key, int dim, double **out, size_t *n)
{
    const dict_entry *e = dict_lookup(d, key);
    if (!e)
        sl_fatal("%s: missing required keyword '%s' in function object '%s'", dict_file(d), key,
                 dict_name(d));
    char *text = dict_entry_value_text(e);
    const char *why = NULL;
    *out = parse_points(text ? text : "", dim, n, &why);
    free(text);
    if (!*out) fo_bad_key(d, key, why);
}

void fo_put(FILE *f, double v)
{
    if (!f) return;
    if (isnan(v)) fputs("\tnan", f);
    else fprintf(f, "\t%.10g", v);
}
