/*
 * editDictionary: query and edit an OpenFOAM-syntax dictionary file, in the
 * habit of OpenFOAM's foamDictionary.  Edits change only the bytes of one
 * value (or add or remove one entry's lines), so comments, layout, #include
 * and $var elsewhere stay as they were; see libsrc/dictedit.
 *
 *   editDictionary [-entry a/b [-value | -set v | -remove]] [-keywords] [-expand] <file>
 */
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

static void usage(int status)
{
    fprintf(status ? stderr : stdout,
            "Usage: editDictionary [options] <file>\n"
            "  Prints or edits a dictionary file (OpenFOAM syntax) in place.\n"
            "  <file> alone     print the file as written, after checking that it reads\n"
            "  -expand          print it with #include and $var resolved (OpenFOAM layout)\n"
            "  -entry <a/b>     select the entry 'b' of sub-dictionary 'a': print it as written\n"
            "                   (with -expand: resolved)\n"
            "  -value           with -entry: print only its value, as the solver reads it\n"
            "  -set <value>     with -entry: set its value in place (OpenFOAM syntax, e.g. 0.5,\n"
            "                   '(0 0 -9.81)', '{ a 1; }'); a missing entry is added at the end\n"
            "                   of its dictionary, which must exist.  An entry written in an\n"
            "                   #include'd file is changed in that file.\n"
            "  -remove          with -entry: remove it (its whole line when alone on it)\n"
            "  -keywords        list the keywords of the dictionary, or of -entry\n"
            "  -help            print this help\n"
            "  Edits go through a temp file and a rename and are checked by reading the\n"
            "  result; errors name the file and line and exit with status 1.\n");
    exit(status);
}

static const char *next_arg(int argc, char **argv, int *i)
{
    if (*i + 1 >= argc) {
        fprintf(stderr, "editDictionary: option '%s' needs an argument\n", argv[*i]);
        usage(2);
    }
    return argv[++*i];
}

static options parse_args(int argc, char **argv)
{
    options o = {0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-entry")) o.entry = next_arg(argc, argv, &i);
        else if (!strcmp(a, "-set")) o.set = next_arg(argc, argv, &i);
        else if (!strcmp(a, "-value")) o.value = 1;
        else if (!strcmp(a, "-remove")) o.remove = 1;
        else if (!strcmp(a, "-keywords")) o.keywords = 1;
        else if (!strcmp(a, "-expand")) o.expand = 1;
        else if (!strcmp(a, "-help") || !strcmp(a, "--help")) usage(0);
        else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "editDictionary: unknown option '%s'\n", a);
            usage(2);
        } else if (!o.file) o.file = a;
        else {
            fprintf(stderr, "editDictionary: more than one file ('%s', '%s')\n", o.file, a);
            usage(2);
        }
    }
    if (!o.file) {
        fprintf(stderr, "editDictionary: no file given\n");
        usage(2);
    }
    if ((o.value || o.set || o.remove) && !o.entry) {
        fprintf(stderr, "editDictionary: -value, -set and -remove need -entry\n");
        usage(2);
    }
    if ((o.value != 0) + (o.set != NULL) + (o.remove != 0) + (o.keywords != 0) > 1) {
        fprintf(stderr, "editDictionary: use one of -value, -set, -remove, -keywords\n");
        usage(2);
    }
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
        printf("%s: '%s' is written in the included file %s: removed it there (line %d)\n",
               o->file, o->entry, ch.file, ch.line);
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
