/* read.c: the file and debugging built-ins debug, read, read_bytes and srt
 * (LANGUAGE.md §5.12), and bi_file_table, the family's table (csv and glob
 * are in csv.c and glob.c).
 *
 * Relative file names are taken from the directory of the running script
 * (eval_script_dir). Following the reference:
 *   - read() decodes strict UTF-8 with universal newlines ("\r\n" and "\r"
 *     become "\n"); a missing or undecodable file gives null.
 *   - srt() splits the text on blank lines ("\n\n") into sections of an
 *     index line, a `START --> END` line (`H:M:S,mmm`) and text lines; any
 *     malformed section (including the empty one after a trailing blank
 *     line) makes the whole file unreadable, so the result is null.
 * sample() is not provided: it reads pixels of a rendered window.
 * A runtime keeps the files read until they change, as the reference
 * does (filememo.c): the results are those of reading them afresh.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "context.h"
#include "fileio.h"
#include "files.h"
#include "format.h"
#include "utf8.h"

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
    Buf name = BUF_INIT, path = BUF_INIT;
    Vec *r = NULL;
    if (!file_name(ev, args[0], &name)) {
        r = bi_error(ev, bi, "embedded null byte");
    } else if (name.len > 0) {
        resolve_path(ev, buf_cstr(&name), &path);
        bool ok;
        r = file_memo_text(eval_file_memo(ev), buf_cstr(&path), &ok);
        if (!ok)
            r = read_failed(ev, bi);
    }
    buf_free(&name);
    buf_free(&path);
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
        const char *bytes;
        size_t len;
        if (!file_memo_bytes(eval_file_memo(ev), buf_cstr(&path), &data, &bytes, &len, NULL)) {
            r = read_failed(ev, bi);
        } else if (len > 0 && len <= UINT32_MAX) {
            r = vec_new_num((uint32_t)len);
            double *out = vec_nums(r);
            const unsigned char *s = (const unsigned char *)bytes;
            for (size_t i = 0; i < len; i++)
                out[i] = s[i];
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
    Buf name = BUF_INIT, path = BUF_INIT;
    Vec *r = NULL;
    if (!file_name(ev, args[0], &name)) {
        r = bi_error(ev, bi, "embedded null byte");
    } else {
        resolve_path(ev, buf_cstr(&name), &path);
        StrList lines = {NULL, 0, 0};
        bool ok;
        Vec *text = file_memo_text(eval_file_memo(ev), buf_cstr(&path), &ok);
        if (ok) {
            const Str *s = vec_celems(text)[0].str;
            if (srt_collect(s->bytes, s->len, t, &lines))
                r = string_vector(lines.v, lines.n);
        } else {
            r = read_failed(ev, bi);
        }
        vec_release(text);
        strlist_free(&lines);
    }
    buf_free(&name);
    buf_free(&path);
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
