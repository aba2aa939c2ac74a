/* files.h: what the file built-ins (read.c, csv.c, glob.c; LANGUAGE.md
 * §5.12) share: Python-compatible number parsing of text fields, file names
 * relative to the running script, bounded strict-UTF-8 text reading, lists
 * of strings, and the csv/glob functions listed in read.c's bi_file_table.
 * Internal to lib/builtins.
 */
#ifndef FL_FILES_H
#define FL_FILES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "buf.h"
#include "builtins.h"
#include "value.h"

/* A growable list of strings (each entry one reference). */
typedef struct {
    Str **v;
    size_t n, cap;
} StrList;

/* Append [s] to [l] (consumes [s]); aborts when out of memory. */
void strlist_push(StrList *l, Str *s);
/* Release every string of [l] and empty it. */
void strlist_free(StrList *l);
/* An object vector of the [n] strings in [items] (null when [n] is 0). */
Vec *string_vector(Str **items, size_t n);

/* Python's str.isspace() for code point [c]. */
bool py_space(uint32_t c);
/* Narrow [*s, *n] to drop Python-whitespace at both ends. */
void py_strip(const char **s, size_t *n);
/* Copy [s, n] to [out] (capacity [cap]) without digit-separating
 * underscores, as Python's number parsers accept them; false when an
 * underscore is misplaced or [out] is too small. */
bool py_drop_underscores(const char *s, size_t n, char *out, size_t cap);
/* Python float(text): true with *out set, false when [s, n] is not a
 * number Python would accept. */
bool py_parse_float(const char *s, size_t n, double *out);
/* Python int(text) for values that fit in 64 bits. */
bool py_parse_int(const char *s, size_t n, int64_t *out);

/* The file name str([v]) in [name]; false when it holds a NUL byte. */
bool file_name(Eval *ev, const Vec *v, Buf *name);
/* [name] made relative to the script's directory unless absolute. */
void resolve_path(Eval *ev, const char *name, Buf *path);
/* After a failed file_read_regular(): an execution error when the file was
 * over the size limit or not a regular file (a missing or unreadable file
 * stays a silent null). */
Vec *read_failed(Eval *ev, const Builtin *bi);
/* csv()'s rows of a file's bytes, parsed as they are asked for (csv.c). */
typedef struct CsvRows CsvRows;
/* Free [r] (NULL is a no-op): the rows kept and the parser. */
void csv_rows_free(CsvRows *r);
/* The bytes of the regular file [path] (file_read_regular's; filememo.c):
 * from the runtime's memo [m] while the file is unchanged, else read now
 * (into the memo, or, when [m] is NULL or the file too large to keep,
 * into [scratch], which the caller frees). *[data] and *[len] are
 * borrowed until the next call on [m] or until [scratch] is freed. With
 * [rows] (may be NULL): in *[rows] the memo's slot for csv()'s rows of
 * the bytes when they come from [m] (NULL otherwise), a slot the caller
 * fills and the memo frees (csv_rows_free) with the bytes, once the file
 * changed. False, with errno as file_read_regular's, when the file cannot
 * be read. */
bool file_memo_bytes(FileMemo *m, const char *path, Buf *scratch, const char **data, size_t *len,
                     CsvRows ***rows);
/* read()'s string of the file [path] (strict UTF-8, universal newlines), a new
 * reference: from [m] while the file is unchanged (the same vector each
 * time), else read now; NULL with *[ok] false when the file cannot be
 * read (errno as file_read_regular's) or is not strict UTF-8 (errno 0).
 * [m] NULL: read afresh. */
Vec *file_memo_text(FileMemo *m, const char *path, bool *ok);

/* csv(filename, row_number) (csv.c). */
Vec *bi_csv(Eval *ev, const Builtin *bi, int nargs, Vec *const *args);
/* glob(pattern) (glob.c). */
Vec *bi_glob(Eval *ev, const Builtin *bi, int nargs, Vec *const *args);

#endif
