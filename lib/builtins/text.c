/* text.c: the text built-ins chr, ord, split and concat (LANGUAGE.md
 * §5.11), exported as bi_text_table.
 *
 * Text is taken from any value with the string conversion of §3.13
 * (fmt_str). Strings are UTF-8; code points are decoded as in fnv1a_utf8
 * (an invalid byte counts as the code point of its value). measure_text is
 * left out: its result depends on a renderer's font metrics.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "config.h"
#include "builtins.h"
#include "buf.h"
#include "context.h"
#include "format.h"
#include "utf8.h"

/* The string in [b] as a one-string vector, or null with an error when it
 * is longer than MAX_STRING; frees [b]. */
static Vec *string_result(Eval *ev, const Builtin *bi, Buf *b)
{
    Vec *r = b->len > MAX_STRING ? bi_error(ev, bi, "string too long (over %zu bytes)", MAX_STRING)
                                 : vec_str(buf_cstr(b), b->len);
    buf_free(b);
    return r;
}

/* chr(ordinals): one string of the code points floor(o_i). */
static Vec *bi_chr(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    const Vec *o = args[0];
    if (!vec_is_num(o))
        return NULL;
    Buf b = BUF_INIT;
    const double *x = vec_cnums(o);
    for (uint32_t i = 0; i < o->len; i++) {
        double f = floor(x[i]);
        /* The reference converts with a C (int) cast; out-of-range values
         * (and NaN) become INT_MIN there, which is not a code point either.
         * Lone surrogates cannot be held in a UTF-8 string. */
        if (!(f >= 0 && f <= 0x10ffff) || (f >= 0xd800 && f <= 0xdfff)) {
            buf_free(&b);
            return bi_error(ev, bi, "chr() arg not in range(0x110000)");
        }
        utf8_put(&b, (uint32_t)f);
    }
    return string_result(ev, bi, &b);
}

/* ord(text): the code points of str(text); null for an empty string. */
static Vec *bi_ord(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)bi; (void)nargs;
    Buf b = BUF_INIT;
    fmt_str(&b, args[0], eval_symtab(ev));
    const unsigned char *s = (const unsigned char *)buf_cstr(&b);
    size_t n = b.len, count = 0;
    for (size_t i = 0; i < n; count++) {
        uint32_t c;
        i += utf8_decode(s + i, n - i, &c);
    }
    Vec *r = NULL;
    if (count > 0 && count <= UINT32_MAX) {
        r = vec_new_num((uint32_t)count);
        double *out = vec_nums(r);
        size_t k = 0;
        for (size_t i = 0; i < n;) {
            uint32_t c;
            i += utf8_decode(s + i, n - i, &c);
            out[k++] = c;
        }
    }
    buf_free(&b);
    return r;
}

/* split(text, separator="\n"): pieces of str(text) between occurrences of
 * str(separator), trailing empty pieces dropped. */
static Vec *bi_split(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    const Vec *text = args[0];
    const Vec *sepv = nargs > 1 ? args[1] : NULL;
    if (vec_len(text) == 0 || (nargs > 1 && vec_len(sepv) == 0))
        return NULL;
    const SymTab *st = eval_symtab(ev);
    Buf tb = BUF_INIT, sb = BUF_INIT;
    fmt_str(&tb, text, st);
    if (nargs > 1)
        fmt_str(&sb, sepv, st);
    else
        buf_putc(&sb, '\n');
    if (sb.len == 0) {
        buf_free(&tb);
        buf_free(&sb);
        return bi_error(ev, bi, "empty separator");
    }
    const char *t = buf_cstr(&tb), *sep = buf_cstr(&sb);
    size_t tn = tb.len, sn = sb.len;

    /* Count the pieces, and the end of the last non-empty one. */
    size_t pieces = 0, keep = 0;
    for (size_t pos = 0;;) {
        const char *hit = memmem(t + pos, tn - pos, sep, sn);
        size_t end = hit ? (size_t)(hit - t) : tn;
        pieces++;
        if (end > pos)
            keep = pieces;
        if (!hit)
            break;
        pos = end + sn;
    }
    Vec *r = NULL;
    if (keep == 0) {
        /* The reference pops trailing empty strings off an emptied list. */
        r = bi_error(ev, bi, "list index out of range");
    } else if (keep <= UINT32_MAX) {
        r = vec_new_obj((uint32_t)keep);
        Elem *e = vec_elems(r);
        size_t pos = 0;
        for (size_t k = 0; k < keep; k++) {
            const char *hit = memmem(t + pos, tn - pos, sep, sn);
            size_t end = hit ? (size_t)(hit - t) : tn;
            e[k].kind = EL_STR;
            e[k].str = str_new(t + pos, end - pos);
            pos = end + sn;
        }
    }
    buf_free(&tb);
    buf_free(&sb);
    return r;
}

/* concat(text): one string str(text); null for an empty vector. */
static Vec *bi_concat(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)nargs;
    if (vec_len(args[0]) == 0)
        return NULL;
    Buf b = BUF_INIT;
    fmt_str(&b, args[0], eval_symtab(ev));
    return string_result(ev, bi, &b);
}

const Builtin bi_text_table[] = {
    {"chr", "chrv", 1, 1, {"ordinals"}, bi_chr, 0},
    {"ord", "ordv", 1, 1, {"text"}, bi_ord, 0},
    {"split", "split", 1, 2, {"text", "separator"}, bi_split, 0},
    {"concat", "concat", 1, 1, {"text"}, bi_concat, 0},
    {NULL, NULL, 0, 0, {NULL}, NULL, 0},
};
