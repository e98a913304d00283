/*
 * dictedit_internal: text helpers shared by the files of libsrc/dictedit.
 * Offsets are byte offsets into a NUL-terminated file text of n bytes.
 */
#ifndef DICTEDIT_INTERNAL_H
#define DICTEDIT_INTERNAL_H

#include <stddef.h>
#include <stdio.h>

#include "dictedit/dictedit.h"

/* OpenFOAM writes values from column 17: keys padded to 16 characters. */
#define DEDIT_KEY_WIDTH 16

long dedit_line_start(const char *s, long i);
/* Offset of the '\n' ending the line of i (n at the end of the text). */
long dedit_line_end(const char *s, size_t n, long i);
/* Offset of 1-based line and byte column (as dict_entry_line/col give). */
long dedit_offset(const char *s, size_t n, int line, int col);
/* 1 if s[from, to) holds only spaces and tabs. */
int dedit_is_blank(const char *s, long from, long to);
/* First offset at or after i that is not white space or a comment. */
long dedit_skip_blank(const char *s, size_t n, long i);
/* 1 if from i to the end of its line there is only blank and comments. */
int dedit_tail_is_comment(const char *s, size_t n, long i);
/* Just after the ';' closing a value that ends at value_end (value_end if
 * none follows, as after a { } dictionary). */
long dedit_entry_end(const char *s, size_t n, long value_end);

/* Keys that are not one OpenFOAM word are written as "strings". */
int dedit_key_needs_quotes(const char *key);
/* Writes the key (quoted if needed); returns the characters written. */
int dedit_write_key(FILE *out, const char *key);

#endif
