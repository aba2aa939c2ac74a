/* file.c: the dynamic file and debugging built-ins debug, read, read_bytes,
 * csv, glob and srt (LANGUAGE.md §5.12), exported as bi_file_table.
 *
 * Relative file names are taken from the directory of the running script
 * (eval_script_dir). Following the reference:
 *   - read() decodes strict UTF-8 with universal newlines ("\r\n" and "\r"
 *     become "\n"); a missing or undecodable file gives null.
 *   - csv() parses with the rules of Python's csv module (excel dialect:
 *     ',' separators, '"' quoting with "" for a quote, records ending at
 *     "\n", "\r\n" or "\r", a blank line being an empty record); each cell
 *     that Python's float() accepts becomes a number, trailing empty cells
 *     are dropped, and row floor(row) is returned.
 *   - srt() splits the text on blank lines ("\n\n") into sections of an
 *     index line, a `START --> END` line (`H:M:S,mmm`) and text lines; any
 *     malformed section (including the empty one after a trailing blank
 *     line) makes the whole file unreadable, so the result is null.
 *   - glob() matches a relative pattern (`*`, `?`, `[...]`, `**` for any
 *     depth of directories; wildcards also match names starting with '.')
 *     and returns the sorted absolute, symlink-resolved paths.
 * sample() is not provided: it reads pixels of a rendered window.
 * Files are read afresh on every call (the reference caches them until they
 * change, which gives the same results).
 */
#include <dirent.h>
#include <errno.h>
#include <fnmatch.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "builtins.h"
#include "buf.h"
#include "context.h"
#include "format.h"
#include "fileio.h"
#include "utf8.h"

/* ------------------------------------------------------------------ */
/* Helpers                                                             */
/* ------------------------------------------------------------------ */

/* Python's str.isspace() for a code point (Unicode White_Space plus the
 * ASCII separators 0x1c-0x1f). */
static bool py_space(uint32_t c)
{
    return (c >= 0x09 && c <= 0x0d) || (c >= 0x1c && c <= 0x20) || c == 0x85 ||
           c == 0xa0 || c == 0x1680 || (c >= 0x2000 && c <= 0x200a) ||
           c == 0x2028 || c == 0x2029 || c == 0x202f || c == 0x205f || c == 0x3000;
}

/* Trim Python whitespace from both ends of [*s, *s + *n). */
static void py_strip(const char **s, size_t *n)
{
    const unsigned char *p = (const unsigned char *)*s;
    size_t a = 0, b = *n;
    uint32_t cp;
    while (a < b) {
        size_t len = utf8_decode_strict(p + a, b - a, &cp);
        if (!len || !py_space(cp))
            break;
        a += len;
    }
    while (b > a) {
        /* step back to the start of the last code point */
        size_t k = b - 1;
        while (k > a && (p[k] & 0xc0) == 0x80 && b - k < 4)
            k--;
        size_t len = utf8_decode_strict(p + k, b - k, &cp);
        if (len != b - k || !py_space(cp))
            break;
        b = k;
    }
    *s += a;
    *n = b - a;
}

/* Copy [s, s+n) to [out] (capacity [cap]) without the underscores Python
 * allows between digits; false when an underscore is misplaced, the text
 * holds a NUL or it does not fit. */
static bool py_drop_underscores(const char *s, size_t n, char *out, size_t cap)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (c == '\0')
            return false;
        if (c == '_') {
            if (i == 0 || i + 1 >= n || !(s[i - 1] >= '0' && s[i - 1] <= '9') ||
                !(s[i + 1] >= '0' && s[i + 1] <= '9'))
                return false;
            continue;
        }
        if (k + 1 >= cap)
            return false;
        out[k++] = c;
    }
    out[k] = '\0';
    return true;
}

/* Python float(text): decimal or inf/infinity/nan (any case, signed),
 * surrounding whitespace and digit-separating underscores allowed. */
static bool py_parse_float(const char *s, size_t n, double *out)
{
    char tmp[512];
    py_strip(&s, &n);
    if (n == 0 || !py_drop_underscores(s, n, tmp, sizeof tmp))
        return false;
    const char *p = tmp;
    if (*p == '+' || *p == '-')
        p++;
    if (!strcasecmp(p, "inf") || !strcasecmp(p, "infinity") || !strcasecmp(p, "nan")) {
        double v = (p[0] == 'n' || p[0] == 'N') ? NAN : INFINITY;
        *out = tmp[0] == '-' ? -v : v;
        return true;
    }
    size_t digits = 0;
    while (*p >= '0' && *p <= '9') {
        p++;
        digits++;
    }
    if (*p == '.') {
        p++;
        while (*p >= '0' && *p <= '9') {
            p++;
            digits++;
        }
    }
    if (!digits)
        return false;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            p++;
        if (!(*p >= '0' && *p <= '9'))
            return false;
        while (*p >= '0' && *p <= '9')
            p++;
    }
    if (*p)
        return false;
    *out = strtod(tmp, NULL);
    return true;
}

/* Python int(text) for values that fit in 64 bits. */
static bool py_parse_int(const char *s, size_t n, int64_t *out)
{
    char tmp[128];
    py_strip(&s, &n);
    if (n == 0 || !py_drop_underscores(s, n, tmp, sizeof tmp))
        return false;
    const char *p = tmp;
    bool neg = false;
    if (*p == '+' || *p == '-')
        neg = *p++ == '-';
    if (!*p)
        return false;
    uint64_t v = 0;
    for (; *p; p++) {
        if (!(*p >= '0' && *p <= '9'))
            return false;
        unsigned d = (unsigned)(*p - '0');
        if (v > (UINT64_C(1) << 63) / 10 || v * 10 + d > (UINT64_C(1) << 63))
            return false;
        v = v * 10 + d;
    }
    if (!neg && v > INT64_MAX)
        return false;
    *out = neg ? (int64_t)(0 - v) : (int64_t)v;
    return true;
}

/* The file name str([v]) in [name]; false when it holds a NUL byte. */
static bool file_name(Eval *ev, const Vec *v, Buf *name)
{
    fmt_str(name, v, eval_symtab(ev));
    return memchr(buf_cstr(name), '\0', name->len) == NULL;
}

/* [name] made relative to the script's directory unless absolute. */
static void resolve_path(Eval *ev, const char *name, Buf *path)
{
    if (name[0] != '/') {
        buf_puts(path, eval_script_dir(ev));
        buf_putc(path, '/');
    }
    buf_puts(path, name);
}

/* After a failed file_read(): an execution error when the file was over
 * the size limit (a missing or unreadable file stays a silent null). */
static Vec *read_failed(Eval *ev, const Builtin *bi)
{
    if (errno == EFBIG)
        return bi_error(ev, bi, "file too large (over %zu bytes)", FILE_READ_MAX);
    return NULL;
}

/* Read [path] as strict UTF-8 text with universal newlines into [out]
 * (errno EFBIG when over FILE_READ_MAX). */
static bool read_text_file(const char *path, Buf *out)
{
    Buf raw = BUF_INIT;
    errno = 0;
    bool ok = file_read(path, &raw) && utf8_all_valid(buf_cstr(&raw), raw.len);
    if (ok) {
        const char *s = buf_cstr(&raw);
        for (size_t i = 0; i < raw.len; i++) {
            if (s[i] == '\r') {
                buf_putc(out, '\n');
                if (i + 1 < raw.len && s[i + 1] == '\n')
                    i++;
            } else {
                buf_putc(out, s[i]);
            }
        }
        if (!out->data)
            buf_add(out, "", 0);
    }
    buf_free(&raw);
    return ok;
}

/* An object vector of the [n] strings in [items] (null when [n] is 0). */
static Vec *string_vector(Str **items, size_t n)
{
    if (n == 0 || n > UINT32_MAX)
        return NULL;
    Vec *r = vec_new_obj((uint32_t)n);
    Elem *e = vec_elems(r);
    for (size_t i = 0; i < n; i++) {
        e[i].kind = EL_STR;
        e[i].str = str_retain(items[i]);
    }
    return r;
}

/* A growable list of strings. */
typedef struct {
    Str **v;
    size_t n, cap;
} StrList;

static void strlist_push(StrList *l, Str *s)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? l->cap * 2 : 16;
        Str **grown = realloc(l->v, l->cap * sizeof *grown);
        if (!grown)
            abort();
        l->v = grown;
    }
    l->v[l->n++] = s;
}

static void strlist_free(StrList *l)
{
    for (size_t i = 0; i < l->n; i++)
        str_release(l->v[i]);
    free(l->v);
    l->v = NULL;
    l->n = l->cap = 0;
}

/* ------------------------------------------------------------------ */
/* debug, read, read_bytes                                             */
/* ------------------------------------------------------------------ */

static Vec *bi_debug(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)bi; (void)nargs;
    Buf b = BUF_INIT;
    fmt_repr(&b, args[0], eval_symtab(ev));
    eval_debug(ev, buf_cstr(&b));
    buf_free(&b);
    return vec_retain(args[0]);
}

static Vec *bi_read(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    Buf name = BUF_INIT, path = BUF_INIT, text = BUF_INIT;
    Vec *r = NULL;
    if (!file_name(ev, args[0], &name)) {
        r = bi_error(ev, bi, "embedded null byte");
    } else if (name.len > 0) {
        resolve_path(ev, buf_cstr(&name), &path);
        if (read_text_file(buf_cstr(&path), &text))
            r = vec_str(buf_cstr(&text), text.len);
        else
            r = read_failed(ev, bi);
    }
    buf_free(&name);
    buf_free(&path);
    buf_free(&text);
    return r;
}

static Vec *bi_read_bytes(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    Buf name = BUF_INIT, path = BUF_INIT, data = BUF_INIT;
    Vec *r = NULL;
    if (!file_name(ev, args[0], &name)) {
        r = bi_error(ev, bi, "embedded null byte");
    } else if (name.len > 0) {
        resolve_path(ev, buf_cstr(&name), &path);
        if (!file_read(buf_cstr(&path), &data)) {
            r = read_failed(ev, bi);
        } else if (data.len > 0 && data.len <= UINT32_MAX) {
            r = vec_new_num((uint32_t)data.len);
            double *out = vec_nums(r);
            const unsigned char *s = (const unsigned char *)data.data;
            for (size_t i = 0; i < data.len; i++)
                out[i] = s[i];
        }
    }
    buf_free(&name);
    buf_free(&path);
    buf_free(&data);
    return r;
}

/* ------------------------------------------------------------------ */
/* csv                                                                 */
/* ------------------------------------------------------------------ */

typedef enum {
    CSV_START_RECORD, CSV_START_FIELD, CSV_IN_FIELD, CSV_IN_QUOTED_FIELD,
    CSV_QUOTE_IN_QUOTED_FIELD, CSV_EAT_CRNL
} CsvState;

/* Parser of one CSV record at a time (Python's csv.reader state machine). */
typedef struct {
    const char *s;      /* file contents */
    size_t n, pos;      /* length and read position */
    CsvState state;
    Buf field;          /* the field being read */
    StrList fields;     /* the record's fields so far */
} Csv;

#define CSV_EOL (-1)

static void csv_save_field(Csv *c)
{
    strlist_push(&c->fields, str_new(buf_cstr(&c->field), c->field.len));
    buf_reset(&c->field);
}

static void csv_char(Csv *c, int ch)
{
    bool eol = ch == CSV_EOL, nl = ch == '\n' || ch == '\r';
    switch (c->state) {
    case CSV_START_RECORD:
        if (eol)
            break;
        if (nl) {
            c->state = CSV_EAT_CRNL;
            break;
        }
        c->state = CSV_START_FIELD;
        /* fall through */
    case CSV_START_FIELD:
        if (nl || eol) {
            csv_save_field(c);
            c->state = eol ? CSV_START_RECORD : CSV_EAT_CRNL;
        } else if (ch == '"') {
            c->state = CSV_IN_QUOTED_FIELD;
        } else if (ch == ',') {
            csv_save_field(c);
        } else {
            buf_putc(&c->field, (char)ch);
            c->state = CSV_IN_FIELD;
        }
        break;
    case CSV_IN_FIELD:
        if (nl || eol) {
            csv_save_field(c);
            c->state = eol ? CSV_START_RECORD : CSV_EAT_CRNL;
        } else if (ch == ',') {
            csv_save_field(c);
            c->state = CSV_START_FIELD;
        } else {
            buf_putc(&c->field, (char)ch);
        }
        break;
    case CSV_IN_QUOTED_FIELD:
        if (eol)
            break;
        if (ch == '"')
            c->state = CSV_QUOTE_IN_QUOTED_FIELD;
        else
            buf_putc(&c->field, (char)ch);
        break;
    case CSV_QUOTE_IN_QUOTED_FIELD:
        if (ch == '"') {
            buf_putc(&c->field, '"');
            c->state = CSV_IN_QUOTED_FIELD;
        } else if (ch == ',') {
            csv_save_field(c);
            c->state = CSV_START_FIELD;
        } else if (nl || eol) {
            csv_save_field(c);
            c->state = eol ? CSV_START_RECORD : CSV_EAT_CRNL;
        } else {
            buf_putc(&c->field, (char)ch);
            c->state = CSV_IN_FIELD;
        }
        break;
    case CSV_EAT_CRNL:
        if (eol)
            c->state = CSV_START_RECORD;
        break;
    }
}

/* Read the next record into c->fields; false at the end of the data. */
static bool csv_next(Csv *c)
{
    strlist_free(&c->fields);
    buf_reset(&c->field);
    c->state = CSV_START_RECORD;
    do {
        if (c->pos >= c->n) {
            if (c->field.len != 0 || c->state == CSV_IN_QUOTED_FIELD) {
                csv_save_field(c);
                return true;
            }
            return false;
        }
        /* One line: up to and including "\n", "\r\n" or "\r". */
        size_t start = c->pos, end = start;
        while (end < c->n && c->s[end] != '\n' && c->s[end] != '\r')
            end++;
        if (end < c->n)
            end += (c->s[end] == '\r' && end + 1 < c->n && c->s[end + 1] == '\n') ? 2 : 1;
        /* Python decodes as it reads: undecodable text ends the file. */
        if (!utf8_all_valid(c->s + start, end - start))
            return false;
        for (size_t i = start; i < end; i++)
            csv_char(c, (unsigned char)c->s[i]);
        csv_char(c, CSV_EOL);
        c->pos = end;
    } while (c->state != CSV_START_RECORD);
    return true;
}

/* The record's cells: numbers where float() accepts them, else strings;
 * trailing empty strings dropped. */
static Vec *csv_row_value(const StrList *fields)
{
    size_t n = fields->n;
    while (n > 0 && fields->v[n - 1]->len == 0)
        n--;
    if (n == 0 || n > UINT32_MAX)
        return NULL;
    Vec *r = vec_new_obj((uint32_t)n);
    Elem *e = vec_elems(r);
    for (size_t i = 0; i < n; i++) {
        Str *s = fields->v[i];
        double x;
        if (py_parse_float(s->bytes, s->len, &x)) {
            e[i].kind = EL_NUM;
            e[i].num = x;
        } else {
            e[i].kind = EL_STR;
            e[i].str = str_retain(s);
        }
    }
    return vec_normalize_take(r);
}

/* The row number argument as Python's `match(1, int)` takes it: *[ok]
 * false means null; a message in *[err] means an error. */
static int64_t csv_row_number(const Vec *v, const SymTab *st, bool *ok, const char **err)
{
    int64_t row = 0;
    *ok = false;
    *err = NULL;
    if (vec_is_scalar(v)) {
        double f = vec_scalar(v);
        if (st && symtab_name(st, f))
            return 0;
        if (isnan(f)) {
            *err = "cannot convert float NaN to integer";
            return 0;
        }
        if (isinf(f)) {
            *err = "cannot convert float infinity to integer";
            return 0;
        }
        f = floor(f);
        /* rows beyond 2^62 cannot exist; clamp to stay in range */
        if (f > 4611686018427387904.0)
            f = 4611686018427387904.0;
        if (f < -4611686018427387904.0)
            f = -4611686018427387904.0;
        row = (int64_t)f;
        *ok = true;
    } else if (vec_is_obj(v) && v->len == 1 && vec_celems(v)[0].kind == EL_STR) {
        const Str *s = vec_celems(v)[0].str;
        *ok = py_parse_int(s->bytes, s->len, &row);
    }
    return row;
}

static Vec *bi_csv(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    bool ok;
    const char *err;
    int64_t row = csv_row_number(args[1], eval_symtab(ev), &ok, &err);
    if (err)
        return bi_error(ev, bi, "%s", err);
    if (!ok || !vec_truthy(args[0]))
        return NULL;
    Buf name = BUF_INIT, path = BUF_INIT, data = BUF_INIT;
    Vec *r = NULL;
    if (!file_name(ev, args[0], &name)) {
        r = bi_error(ev, bi, "embedded null byte");
    } else if (row >= 0) {
        resolve_path(ev, buf_cstr(&name), &path);
        if (file_read(buf_cstr(&path), &data)) {
            Csv c = {buf_cstr(&data), data.len, 0, CSV_START_RECORD, BUF_INIT, {NULL, 0, 0}};
            int64_t k = 0;
            while (csv_next(&c)) {
                if (k++ == row) {
                    r = csv_row_value(&c.fields);
                    break;
                }
            }
            strlist_free(&c.fields);
            buf_free(&c.field);
        } else {
            r = read_failed(ev, bi);
        }
    }
    buf_free(&name);
    buf_free(&path);
    buf_free(&data);
    return r;
}

/* ------------------------------------------------------------------ */
/* srt                                                                 */
/* ------------------------------------------------------------------ */

/* Python str.splitlines() boundaries at [s] (< [n]): the length of the line
 * break there, or 0. */
static size_t line_break(const char *s, size_t i, size_t n)
{
    unsigned char c = (unsigned char)s[i];
    if (c == '\r')
        return (i + 1 < n && s[i + 1] == '\n') ? 2 : 1;
    if (c == '\n' || c == 0x0b || c == 0x0c || (c >= 0x1c && c <= 0x1e))
        return 1;
    uint32_t cp;
    size_t len = utf8_decode_strict((const unsigned char *)s + i, n - i, &cp);
    if (len > 1 && (cp == 0x85 || cp == 0x2028 || cp == 0x2029))
        return len;
    return 0;
}

/* decode_timestamp of the reference: `H:M:S[,mmm]` (any number of
 * colon-separated parts, each a Python int) in seconds. */
static bool srt_timestamp(const char *s, size_t n, double *out)
{
    const char *comma = memchr(s, ',', n);
    size_t tn = comma ? (size_t)(comma - s) : n;
    double fsec = 0;
    int64_t isec = 0;
    bool is_float = comma != NULL;
    if (comma) {
        int64_t ms;
        if (!py_parse_int(comma + 1, n - tn - 1, &ms))
            return false;
        fsec = (double)ms / 1000;
    }
    int64_t mult = 1;
    size_t end = tn;
    for (;;) {
        size_t start = end;
        while (start > 0 && s[start - 1] != ':')
            start--;
        int64_t part;
        if (!py_parse_int(s + start, end - start, &part))
            return false;
        int64_t term;
        if (__builtin_mul_overflow(part, mult, &term))
            return false;
        if (is_float) {
            fsec += (double)term;
        } else if (__builtin_add_overflow(isec, term, &isec)) {
            return false;
        }
        if (start == 0)
            break;
        end = start - 1;
        if (__builtin_mul_overflow(mult, 60, &mult))
            return false;
    }
    *out = is_float ? fsec : (double)isec;
    return true;
}

/* Append to [lines] the text lines of the subtitles in [text] that are
 * active at time [t]; false when the file is malformed. */
static bool srt_collect(const char *text, size_t n, double t, StrList *lines)
{
    size_t pos = 0;
    for (;;) {
        const char *hit = memmem(text + pos, n - pos, "\n\n", 2);
        size_t end = hit ? (size_t)(hit - text) : n;
        /* splitlines() of the section [pos, end) */
        size_t starts[3] = {0}, ends[3] = {0}, count = 0, i = pos;
        StrList sect = {NULL, 0, 0};
        while (i < end) {
            size_t ls = i, br = 0;
            while (i < end && !(br = line_break(text, i, end)))
                i++;
            if (count < 2) {
                starts[count] = ls;
                ends[count] = i;
            } else {
                strlist_push(&sect, str_new(text + ls, i - ls));
            }
            count++;
            i += br;
        }
        double start, stop;
        int64_t index;
        bool ok = count >= 2 && py_parse_int(text + starts[0], ends[0] - starts[0], &index);
        if (ok) {
            const char *tc = text + starts[1];
            size_t tn = ends[1] - starts[1];
            const char *arrow = memmem(tc, tn, " --> ", 5);
            ok = arrow && !memmem(arrow + 5, tn - (size_t)(arrow - tc) - 5, " --> ", 5) &&
                 srt_timestamp(tc, (size_t)(arrow - tc), &start) &&
                 srt_timestamp(arrow + 5, tn - (size_t)(arrow - tc) - 5, &stop);
        }
        if (ok && start <= t && t < stop) {
            for (size_t k = 0; k < sect.n; k++)
                strlist_push(lines, str_retain(sect.v[k]));
        }
        strlist_free(&sect);
        if (!ok)
            return false;
        if (!hit)
            return true;
        pos = end + 2;
    }
}

static Vec *bi_srt(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    const Vec *tv = args[1];
    double t;
    if (vec_is_scalar(tv)) {
        t = vec_scalar(tv);
    } else if (vec_is_obj(tv) && tv->len == 1 && vec_celems(tv)[0].kind == EL_STR) {
        const Str *s = vec_celems(tv)[0].str;
        if (!py_parse_float(s->bytes, s->len, &t))
            return NULL;
    } else {
        return NULL;
    }
    if (!vec_truthy(args[0]))
        return NULL;
    Buf name = BUF_INIT, path = BUF_INIT, text = BUF_INIT;
    Vec *r = NULL;
    if (!file_name(ev, args[0], &name)) {
        r = bi_error(ev, bi, "embedded null byte");
    } else {
        resolve_path(ev, buf_cstr(&name), &path);
        StrList lines = {NULL, 0, 0};
        if (read_text_file(buf_cstr(&path), &text)) {
            if (srt_collect(buf_cstr(&text), text.len, t, &lines))
                r = string_vector(lines.v, lines.n);
        } else {
            r = read_failed(ev, bi);
        }
        strlist_free(&lines);
    }
    buf_free(&name);
    buf_free(&path);
    buf_free(&text);
    return r;
}

/* ------------------------------------------------------------------ */
/* glob                                                                */
/* ------------------------------------------------------------------ */

typedef struct {
    char **parts;       /* pattern components ("." and empty ones removed) */
    size_t nparts;
    bool dir_only;      /* pattern ended with '/' */
    StrList found;      /* matching paths (unresolved) */
} Glob;

static bool has_wildcard(const char *s)
{
    return strpbrk(s, "*?[") != NULL;
}

static bool is_dir(const char *path, bool follow)
{
    struct stat st;
    int rc = follow ? stat(path, &st) : lstat(path, &st);
    return rc == 0 && S_ISDIR(st.st_mode);
}

static void glob_select(Glob *g, const char *dir, size_t idx);

/* Match components from [idx] in [dir] and every directory below it
 * (symbolic links are not followed while descending). */
static void glob_recursive(Glob *g, const char *dir, size_t idx)
{
    glob_select(g, dir, idx);
    DIR *d = opendir(dir);
    if (!d)
        return;
    StrList subdirs = {NULL, 0, 0};
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
            continue;
        Buf child = BUF_INIT;
        buf_printf(&child, "%s/%s", dir, ent->d_name);
        if (is_dir(buf_cstr(&child), false))
            strlist_push(&subdirs, str_new(child.data, child.len));
        buf_free(&child);
    }
    closedir(d);
    for (size_t i = 0; i < subdirs.n; i++)
        glob_recursive(g, subdirs.v[i]->bytes, idx);
    strlist_free(&subdirs);
}

static void glob_select(Glob *g, const char *dir, size_t idx)
{
    if (idx == g->nparts) {
        if (!g->dir_only || is_dir(dir, true))
            strlist_push(&g->found, str_from(dir));
        return;
    }
    const char *part = g->parts[idx];
    bool last = idx + 1 == g->nparts;
    if (!strcmp(part, "**")) {
        while (idx + 1 < g->nparts && !strcmp(g->parts[idx + 1], "**"))
            idx++;
        if (idx + 1 == g->nparts) {     /* trailing "**": directories only */
            bool saved = g->dir_only;
            g->dir_only = true;
            glob_recursive(g, dir, idx + 1);
            g->dir_only = saved;
        } else {
            glob_recursive(g, dir, idx + 1);
        }
        return;
    }
    if (!has_wildcard(part)) {
        Buf child = BUF_INIT;
        buf_printf(&child, "%s/%s", dir, part);
        struct stat st;
        if (last ? stat(buf_cstr(&child), &st) == 0 : is_dir(buf_cstr(&child), true))
            glob_select(g, buf_cstr(&child), idx + 1);
        buf_free(&child);
        return;
    }
    DIR *d = opendir(dir);
    if (!d)
        return;
    StrList matches = {NULL, 0, 0};
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
            continue;
        if (fnmatch(part, ent->d_name, FNM_NOESCAPE) != 0)
            continue;
        Buf child = BUF_INIT;
        buf_printf(&child, "%s/%s", dir, ent->d_name);
        if (last || is_dir(buf_cstr(&child), true))
            strlist_push(&matches, str_new(child.data, child.len));
        buf_free(&child);
    }
    closedir(d);
    for (size_t i = 0; i < matches.n; i++)
        glob_select(g, matches.v[i]->bytes, idx + 1);
    strlist_free(&matches);
}

static int str_ptr_cmp(const void *a, const void *b)
{
    return str_cmp(*(Str *const *)a, *(Str *const *)b);
}

/* Sort [l] by bytes and drop repeated entries. */
static void strlist_sort_unique(StrList *l)
{
    if (l->n < 2)
        return;
    qsort(l->v, l->n, sizeof *l->v, str_ptr_cmp);
    size_t k = 1;
    for (size_t i = 1; i < l->n; i++) {
        if (str_eq(l->v[i], l->v[k - 1]))
            str_release(l->v[i]);
        else
            l->v[k++] = l->v[i];
    }
    l->n = k;
}

static Vec *bi_glob(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    Buf pat = BUF_INIT;
    fmt_str(&pat, args[0], eval_symtab(ev));
    const char *p = buf_cstr(&pat);
    if (memchr(p, '\0', pat.len)) {
        buf_free(&pat);
        return bi_error(ev, bi, "embedded null byte");
    }
    if (p[0] == '/') {
        buf_free(&pat);
        return bi_error(ev, bi, "Non-relative patterns are unsupported");
    }
    /* Split into components, dropping empty and "." ones. */
    char *copy = strdup(p);
    if (!copy)
        abort();
    Glob g = {NULL, 0, pat.len > 0 && p[pat.len - 1] == '/', {NULL, 0, 0}};
    g.parts = malloc((pat.len / 2 + 1) * sizeof *g.parts);
    if (!g.parts)
        abort();
    char *save = NULL;
    for (char *tok = strtok_r(copy, "/", &save); tok; tok = strtok_r(NULL, "/", &save))
        if (strcmp(tok, ".") != 0)
            g.parts[g.nparts++] = tok;
    Vec *r = NULL;
    if (g.nparts == 0) {
        r = bi_error(ev, bi, "Unacceptable pattern: '%s'", p);
    } else {
        glob_select(&g, eval_script_dir(ev), 0);
        strlist_sort_unique(&g.found);
        StrList resolved = {NULL, 0, 0};
        for (size_t i = 0; i < g.found.n; i++) {
            char *real = realpath(g.found.v[i]->bytes, NULL);
            if (real) {
                strlist_push(&resolved, str_from(real));
                free(real);
            } else {
                /* a dangling link: made absolute without resolving */
                Buf abs = BUF_INIT;
                char cwd[PATH_MAX];
                if (g.found.v[i]->bytes[0] != '/' && getcwd(cwd, sizeof cwd))
                    buf_printf(&abs, "%s/", cwd);
                buf_puts(&abs, g.found.v[i]->bytes);
                strlist_push(&resolved, str_new(buf_cstr(&abs), abs.len));
                buf_free(&abs);
            }
        }
        if (resolved.n > 1)
            qsort(resolved.v, resolved.n, sizeof *resolved.v, str_ptr_cmp);
        r = string_vector(resolved.v, resolved.n);
        strlist_free(&resolved);
    }
    strlist_free(&g.found);
    free(g.parts);
    free(copy);
    buf_free(&pat);
    return r;
}

const Builtin bi_file_table[] = {
    {"debug", "debug", 1, 1, {"value"}, bi_debug, BI_DYNAMIC},
    {"read", "read_text", 1, 1, {"filename"}, bi_read, BI_DYNAMIC},
    {"read_bytes", "read_bytes", 1, 1, {"filename"}, bi_read_bytes, BI_DYNAMIC},
    {"csv", "read_csv", 2, 2, {"filename", "row_number"}, bi_csv, BI_DYNAMIC},
    {"glob", "glob", 1, 1, {"pattern"}, bi_glob, BI_DYNAMIC},
    {"srt", "read_srt", 2, 2, {"filename", "time"}, bi_srt, BI_DYNAMIC},
    {NULL, NULL, 0, 0, {NULL}, NULL, 0},
};
