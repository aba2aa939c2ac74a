/* files.c: the helpers the file built-ins share (files.h): Python's number
 * parsing rules for text fields, file names relative to the running script,
 * strict UTF-8 reading with universal newlines, string lists.
 */
#include "files.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "context.h"
#include "fileio.h"
#include "format.h"
#include "mem.h"
#include "utf8.h"

/* Python's str.isspace() for a code point (Unicode White_Space plus the
 * ASCII separators 0x1c-0x1f). */
bool py_space(uint32_t c)
{
    return (c >= 0x09 && c <= 0x0d) || (c >= 0x1c && c <= 0x20) || c == 0x85 ||
           c == 0xa0 || c == 0x1680 || (c >= 0x2000 && c <= 0x200a) ||
           c == 0x2028 || c == 0x2029 || c == 0x202f || c == 0x205f || c == 0x3000;
}

/* Trim Python whitespace from both ends of [*s, *s + *n). */
void py_strip(const char **s, size_t *n)
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
bool py_drop_underscores(const char *s, size_t n, char *out, size_t cap)
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
bool py_parse_float(const char *s, size_t n, double *out)
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
bool py_parse_int(const char *s, size_t n, int64_t *out)
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
bool file_name(Eval *ev, const Vec *v, Buf *name)
{
    fmt_str(name, v, eval_symtab(ev));
    return memchr(buf_cstr(name), '\0', name->len) == NULL;
}

/* [name] made relative to the script's directory unless absolute. */
void resolve_path(Eval *ev, const char *name, Buf *path)
{
    if (name[0] != '/') {
        buf_puts(path, eval_script_dir(ev));
        buf_putc(path, '/');
    }
    buf_puts(path, name);
}

/* After a failed file_read_regular(): an execution error when the file was
 * over the size limit or not a regular file (a missing or unreadable file
 * stays a silent null). */
Vec *read_failed(Eval *ev, const Builtin *bi)
{
    if (errno == EFBIG)
        return bi_error(ev, bi, "file too large (over %zu bytes)", FILE_READ_MAX);
    if (errno == EINVAL)
        return bi_error(ev, bi, "not a regular file");
    return NULL;
}

/* An object vector of the [n] strings in [items] (null when [n] is 0). */
Vec *string_vector(Str **items, size_t n)
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

void strlist_push(StrList *l, Str *s)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? l->cap * 2 : 16;
        Str **grown = realloc(l->v, l->cap * sizeof *grown);
        if (!grown)
            mem_oom();
        l->v = grown;
    }
    l->v[l->n++] = s;
}

void strlist_free(StrList *l)
{
    for (size_t i = 0; i < l->n; i++)
        str_release(l->v[i]);
    free(l->v);
    l->v = NULL;
    l->n = l->cap = 0;
}
