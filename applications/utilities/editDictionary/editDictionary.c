/*
 * editDictionary: query and edit an OpenFOAM-syntax dictionary file, in the
 * habit of OpenFOAM's foamDictionary.  Edits change only the bytes of one
 * value (or add or remove one entry's lines), so comments, layout, #include
 * and $var elsewhere stay as they were; see libsrc/dictedit.
 *
 *   editDictionary [-entry a/b [-value | -set v | -remove]] [-keywords] [-expand] <file>
 */
#include "app/app.h"
#include "core/sl_log.h"
#include "dictedit/dictedit.h"
#include "dictionary/dict.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct options {
    const char *file, *entry, *set;
    int value, remove, keywords, expand;
} options;

static const app_option table[] = {
    {.name = "expand", .help = "print it with #include and $var resolved (OpenFOAM layout)"},
    {.name = "entry",
     .kind = APP_STRING,
     .arg = "<a/b>",
     .help = "select the entry 'b' of sub-dictionary 'a': print it as written\n"
             "(with -expand: resolved)"},
    {.name = "value", .help = "with -entry: print only its value, as the solver reads it"},
    {.name = "set",
     .kind = APP_STRING,
     .arg = "<value>",
     .help = "with -entry: set its value in place (OpenFOAM syntax, e.g. 0.5,\n"
             "'(0 0 -9.81)', '{ a 1; }'); a missing entry is added at the end\n"
             "of its dictionary, which must exist.  An entry written in an\n"
             "#include'd file is changed in that file."},
    {.name = "remove", .help = "with -entry: remove it (its whole line when alone on it)"},
    {.name = "keywords", .help = "list the keywords of the dictionary, or of -entry"},
    APP_END};

static const app_info info = {
    .name = "editDictionary",
    .what = "Prints or edits a dictionary file (OpenFOAM syntax) in place; <file> alone\n"
            "prints the file as written, after checking that it reads.  Edits go\n"
            "through a temp file and a rename and are checked by reading the result;\n"
            "errors name the file and line and exit with status 1.",
    .options = table,
    .args = "<file>",
    .min_args = 1,
    .max_args = 1,
    .args_kind = APP_PATH};

static options parse_args(int argc, char **argv)
{
    app a;
    options o = {0};
    app_parse(&a, &info, argc, argv);
    o.file = a.args[0];
    o.entry = app_string(&a, "entry", NULL);
    o.set = app_string(&a, "set", NULL);
    o.value = app_found(&a, "value");
    o.remove = app_found(&a, "remove");
    o.keywords = app_found(&a, "keywords");
    o.expand = app_found(&a, "expand");
    if ((o.value || o.set || o.remove) && !o.entry)
        app_error(&a, "-value, -set and -remove need -entry");
    if ((o.value != 0) + (o.set != NULL) + (o.remove != 0) + (o.keywords != 0) > 1)
        app_error(&a, "use one of -value, -set, -remove, -keywords");
    app_free(&a);
    return o;
}

static void set_entry(const options *o)
{
    sl_err err;
    dedit_change ch;
    if (dedit_set(o->file, o->entry, o->set, &ch, &err)) sl_fatal("%s", err.msg);
    if (strcmp(ch.file, o->file) != 0)
        printf("%s: '%s' is written in the included file %s: %s it there (line %d)\n", o->file,
               o->entry, ch.file, ch.added ? "added" : "changed", ch.line);
    else
        printf("%s:%d: %s '%s' = %s\n", ch.file, ch.line, ch.added ? "added" : "set", o->entry,
               o->set);
}

static void remove_entry(const options *o)
{
    sl_err err;
    dedit_change ch;
    if (dedit_remove(o->file, o->entry, &ch, &err)) sl_fatal("%s", err.msg);
    if (strcmp(ch.file, o->file) != 0)
        printf("%s: '%s' is written in the included file %s: removed it there (line %d)\n", o->file,
               o->entry, ch.file, ch.line);
    else
        printf("%s:%d: removed '%s'%s\n", ch.file, ch.line, o->entry,
               ch.removed > 1 ? " (every definition of it)" : "");
}

static void print_keywords(const dict *d, const dict_entry *e, const char *entry)
{
    if (e && !dict_entry_dict(e))
        sl_fatal("%s:%d: '%s' is not a dictionary: it has no keywords", dict_entry_file(e),
                 dict_entry_line(e), entry);
    if (e) d = dict_entry_dict(e);
    for (size_t i = 0; i < dict_size(d); i++) puts(dict_entry_key(dict_entry_at(d, i)));
}

static void print_value(const dict_entry *e)
{
    if (dict_entry_dict(e)) {
        puts("{");
        dedit_print_dict(stdout, dict_entry_dict(e), 1);
        puts("}");
    } else {
        char *v = dict_entry_value_text(e);
        puts(v);
        free(v);
    }
}

/* The entry as written: key, then its raw value text. */
static void print_entry_raw(const dict_entry *e)
{
    sl_err err;
    char *raw = dedit_raw_value(e, &err);
    const char *key = dict_entry_key(e);
    int w = (int)strlen(key);
    if (!raw) sl_fatal("%s", err.msg);
    if (raw[0] == '{') printf("%s\n%s\n", key, raw);
    else printf("%s%*s%s;\n", key, w < 16 ? 16 - w : 1, "", raw);
    free(raw);
}

static void print_file(const char *file)
{
    sl_err err;
    size_t n;
    char *text = dedit_read_text(file, &n, &err);
    if (!text) sl_fatal("%s", err.msg);
    fwrite(text, 1, n, stdout);
    free(text);
}

int main(int argc, char **argv)
{
    options o = parse_args(argc, argv);
    const dict_entry *e = NULL;
    sl_err err;
    dict *d;
    if (o.set) set_entry(&o);
    else if (o.remove) remove_entry(&o);
    if (o.set || o.remove) return 0;

    if (!(d = dict_read_file(o.file, &err))) sl_fatal("%s", err.msg);
    if (o.entry && !(e = dedit_lookup(d, o.entry, &err))) sl_fatal("%s", err.msg);
    if (o.keywords) print_keywords(d, e, o.entry);
    else if (o.value) print_value(e);
    else if (e && o.expand) dedit_print_entry(stdout, e, 0);
    else if (e) print_entry_raw(e);
    else if (o.expand) dedit_print_dict(stdout, d, 0);
    else print_file(o.file);
    dict_free(d);
    return 0;
}
