/* app_help: -help and -completionWords, generated from a program's option
 * table (see app.h).  -help is the usage line, the options in the table's
 * order (each with its default), the old spellings, then the description. */
#include "app/app.h"

#include <stdio.h>
#include <string.h>

/* The longest "-name <arg>" column shown; longer ones put the help below. */
enum { APP_HELP_COLUMN = 24 };
/* Lines of help are kept within this many columns where the default is added. */
enum { APP_HELP_WIDTH = 80 };

static const char *app_kind_arg(app_kind k)
{
    switch (k) {
    case APP_NONE:
        return "";
    case APP_INT:
        return "<N>";
    case APP_DOUBLE:
        return "<x>";
    case APP_STRING:
        return "<word>";
    case APP_PATH:
        return "<file>";
    case APP_DIR:
        return "<dir>";
    }
    return "";
}

static const char *app_kind_word(app_kind k)
{
    switch (k) {
    case APP_NONE:
        return "none";
    case APP_INT:
        return "int";
    case APP_DOUBLE:
        return "double";
    case APP_STRING:
        return "string";
    case APP_PATH:
        return "path";
    case APP_DIR:
        return "dir";
    }
    return "none";
}

/* "-name <arg>" of option o. */
static void app_synopsis(const app_option *o, char *buf, size_t len)
{
    const char *arg = o->arg ? o->arg : app_kind_arg(o->kind);
    snprintf(buf, len, "-%s%s%s", o->name, *arg ? " " : "", arg);
}

/* Text with every line indented; the first one follows what is printed. */
static void app_lines(FILE *out, const char *text, int indent, int first)
{
    for (const char *p = text; *p;) {
        size_t n = strcspn(p, "\n");
        if (!first) fprintf(out, "%*s", indent, "");
        fprintf(out, "%.*s\n", (int)n, p);
        first = 0;
        p += n;
        if (*p) p++;
    }
}

static void app_help_option(FILE *out, const app_option *o, int col)
{
    char syn[128], help[2048];
    app_synopsis(o, syn, sizeof syn);
    const char *text = o->help ? o->help : "", *last = strrchr(text, '\n');
    size_t width = (size_t)col + 4 + strlen(last ? last + 1 : text);
    if (o->def && width + strlen(o->def) + 12 > APP_HELP_WIDTH)
        snprintf(help, sizeof help, "%s\n(default: %s)", text, o->def);
    else if (o->def) snprintf(help, sizeof help, "%s (default: %s)", text, o->def);
    else snprintf(help, sizeof help, "%s", text);
    if ((int)strlen(syn) > col) {
        fprintf(out, "  %s\n", syn);
        app_lines(out, help, col + 4, 0);
    } else {
        fprintf(out, "  %-*s  ", col, syn);
        app_lines(out, help, col + 4, 1);
    }
}

static void app_help_aliases(FILE *out, const app_info *info)
{
    int any = 0;
    for (const app_option *o = info->options; o && o->name; o++) {
        if (!o->aliases) continue;
        if (!any++) fputs("\nOld spellings, still accepted with a warning:\n", out);
        fputs("  ", out);
        for (const char *p = o->aliases; *p;) {
            size_t n = strcspn(p, " ");
            fprintf(out, "%s-%.*s", p == o->aliases ? "" : ", ", (int)n, p);
            p += n;
            p += strspn(p, " ");
        }
        fprintf(out, ": use -%s\n", o->name);
    }
}

void app_print_help(const app_info *info, FILE *out)
{
    static const app_option help = {"help", APP_NONE, NULL, "print this help", NULL, NULL, 0, 0,
                                    0,      0,        NULL};
    int col = 6;
    char syn[128];
    for (const app_option *o = info->options; o && o->name; o++) {
        app_synopsis(o, syn, sizeof syn);
        int n = (int)strlen(syn);
        if (n > col && n <= APP_HELP_COLUMN) col = n;
    }
    fprintf(out, "Usage: %s [options]%s%s\n\nOptions:\n", info->name, info->args ? " " : "",
            info->args ? info->args : "");
    for (const app_option *o = info->options; o && o->name; o++) app_help_option(out, o, col);
    app_help_option(out, &help, col);
    app_help_aliases(out, info);
    if (info->what) {
        fputc('\n', out);
        app_lines(out, info->what, 2, 0);
    }
    if (info->notes) {
        fputc('\n', out);
        app_lines(out, info->notes, 0, 0);
    }
}

void app_print_completion(const app_info *info, FILE *out)
{
    for (const app_option *o = info->options; o && o->name; o++)
        fprintf(out, "-%s %s%s%s\n", o->name, app_kind_word(o->kind), o->glob ? " " : "",
                o->glob ? o->glob : "");
    fputs("-help none\n", out);
    if (info->max_args != 0)
        fprintf(out, "@args %s\n",
                app_kind_word(info->args_kind == APP_NONE ? APP_PATH : info->args_kind));
}
