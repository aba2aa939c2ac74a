/* define_value.c: the value a script receives for a defined name's text,
 * read part by part as Flitter's `keyvalue` reads it (define_value.h).
 *
 * Flitter reads a part with Python's float() and int(), not with its own
 * lexer, so the grammar here is Python's: float() takes a sign, `inf`,
 * `infinity` and `nan` in any case, and `_` between two digits; both
 * ignore blanks around the text. glibc's strtod, like Python's, rounds
 * correctly, so every number is the one Flitter reads.
 */
#include "define_value.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"

/* Python's blanks for float() and int(): the ASCII ones (with the
 * information separators 0x1c-0x1f); of the others only U+0085 and
 * U+00A0, which are the two that a short UTF-8 sequence can spell. */
static size_t blank_len(const char *s, size_t len)
{
    unsigned char c = (unsigned char)s[0];
    if (c == ' ' || (c >= '\t' && c <= '\r') || (c >= 0x1c && c <= 0x1f)) return 1;
    if (len >= 2 && c == 0xc2 && ((unsigned char)s[1] == 0x85 || (unsigned char)s[1] == 0xa0))
        return 2;
    return 0;
}

static size_t blank_before(const char *s, size_t len)
{
    unsigned char c = (unsigned char)s[len - 1];
    if (c == ' ' || (c >= '\t' && c <= '\r') || (c >= 0x1c && c <= 0x1f)) return 1;
    if (len >= 2 && (unsigned char)s[len - 2] == 0xc2 && (c == 0x85 || c == 0xa0)) return 2;
    return 0;
}

/* [s, s+len) without the blanks around it. */
static void strip(const char **s, size_t *len)
{
    size_t k;
    while (*len && (k = blank_len(*s, *len)) != 0) {
        *s += k;
        *len -= k;
    }
    while (*len && (k = blank_before(*s, *len)) != 0) *len -= k;
}

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

/* Python's digitpart, `digit (["_"] digit)*`, at s[*i]: copies its digits
 * (without the `_`) to out[*o]; false when there is none or a `_` is not
 * between two digits. */
static bool digitpart(const char *s, size_t len, size_t *i, char *out, size_t *o)
{
    if (*i >= len || !is_digit(s[*i])) return false;
    out[(*o)++] = s[(*i)++];
    while (*i < len) {
        if (is_digit(s[*i])) {
            out[(*o)++] = s[(*i)++];
        } else if (s[*i] == '_' && *i + 1 < len && is_digit(s[*i + 1])) {
            (*i)++;
        } else {
            break;
        }
    }
    return true;
}

static bool word_at(const char *s, size_t len, const char *word)
{
    size_t n = strlen(word);
    if (len != n) return false;
    for (size_t k = 0; k < n; k++) {
        char c = s[k];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != word[k]) return false;
    }
    return true;
}

bool define_float(const char *s, size_t len, double *out)
{
    strip(&s, &len);
    if (len == 0) return false;
    bool neg = false;
    size_t i = 0;
    if (s[0] == '+' || s[0] == '-') {
        neg = s[0] == '-';
        i = 1;
    }
    if (word_at(s + i, len - i, "inf") || word_at(s + i, len - i, "infinity")) {
        *out = neg ? -INFINITY : INFINITY;
        return true;
    }
    if (word_at(s + i, len - i, "nan")) {
        *out = neg ? -NAN : NAN;
        return true;
    }
    /* the cleaned text for strtod: sign, digits, '.', 'e', sign, digits */
    char *clean = malloc(len + 2);
    if (!clean) mem_oom();
    size_t o = 0;
    if (neg) clean[o++] = '-';
    bool whole = digitpart(s, len, &i, clean, &o), frac = false;
    if (i < len && s[i] == '.') {
        clean[o++] = s[i++];
        frac = digitpart(s, len, &i, clean, &o);
    }
    bool ok = whole || frac;
    if (ok && i < len && (s[i] == 'e' || s[i] == 'E')) {
        clean[o++] = 'e';
        i++;
        if (i < len && (s[i] == '+' || s[i] == '-')) clean[o++] = s[i++];
        ok = digitpart(s, len, &i, clean, &o);
    }
    ok = ok && i == len;
    if (ok) {
        clean[o] = '\0';
        *out = strtod(clean, NULL);
    }
    free(clean);
    return ok;
}

/* Python's int() of a part of a time code: `[sign] digitpart` within
 * blanks. Exact up to 15 digits (every hour or minute count a clock can
 * hold); beyond that the count is rounded to a double first, where Python
 * would keep it exact until the sum. */
static bool define_int(const char *s, size_t len, double *out)
{
    strip(&s, &len);
    size_t i = 0;
    if (len && (s[0] == '+' || s[0] == '-')) i = 1;
    char *digits = malloc(len + 2);
    if (!digits) mem_oom();
    size_t o = 0;
    if (len && s[0] == '-') digits[o++] = '-';
    bool ok = digitpart(s, len, &i, digits, &o) && i == len;
    if (ok) {
        digits[o] = '\0';
        *out = strtod(digits, NULL);
    }
    free(digits);
    return ok;
}

/* Flitter's number rule: the first suffix the part ends with decides (its
 * multiplier applied to the float() of the rest, which must read); a part
 * without one is float() of the whole. */
static bool define_number(const char *s, size_t len, double *out)
{
    static const struct { const char *suffix; double mult; } suffixes[] = {
        {"\xc2\xb0", 1.0 / 360}, {"deg", 1.0 / 360}, {"p", 1e-12}, {"n", 1e-9},
        {"u", 1e-6}, {"\xc2\xb5", 1e-6}, {"m", 1e-3}, {"k", 1e3}, {"M", 1e6},
        {"G", 1e9}, {"T", 1e12},
    };
    for (size_t k = 0; k < sizeof suffixes / sizeof suffixes[0]; k++) {
        size_t n = strlen(suffixes[k].suffix);
        if (len >= n && memcmp(s + len - n, suffixes[k].suffix, n) == 0) {
            double x;
            if (!define_float(s, len - n, &x)) return false;
            *out = x * suffixes[k].mult;
            return true;
        }
    }
    return define_float(s, len, out);
}

/* A time code `[[H:]M:]S`: S by float(), M and H by int(), summed as
 * S + 60*M + 3600*H in that order. */
static bool define_timecode(const char *s, size_t len, double *out)
{
    size_t colon[3], nc = 0;
    for (size_t k = 0; k < len; k++) {
        if (s[k] != ':') continue;
        if (nc == 2) return false;
        colon[nc++] = k;
    }
    double sec, m, h;
    size_t last = nc ? colon[nc - 1] + 1 : 0;
    if (!define_float(s + last, len - last, &sec)) return false;
    if (nc >= 1) {
        size_t from = nc == 2 ? colon[0] + 1 : 0;
        if (!define_int(s + from, colon[nc - 1] - from, &m)) return false;
        sec += 60 * m;
    }
    if (nc == 2) {
        if (!define_int(s, colon[0], &h)) return false;
        sec += 3600 * h;
    }
    *out = sec;
    return true;
}

Vec *define_value(SymTab *st, const char *text, size_t len)
{
    size_t nparts = 1;
    for (size_t k = 0; k < len; k++) nparts += text[k] == ';';
    Vec **parts = malloc(nparts * sizeof *parts);
    if (!parts) mem_oom();
    size_t np = 0, i = 0;
    for (;;) {
        size_t j = i;
        while (j < len && text[j] != ';') j++;
        const char *p = text + i;
        size_t n = j - i;
        double x;
        if (n >= 1 && p[0] == ':') parts[np++] = vec_num1(symtab_add(st, p + 1, n - 1));
        else if (define_number(p, n, &x) || define_timecode(p, n, &x)) parts[np++] = vec_num1(x);
        else parts[np++] = vec_str(p, n);
        if (j == len) break;
        i = j + 1;
    }
    Vec *v = vec_compose(parts, np);
    for (size_t k = 0; k < np; k++) vec_release(parts[k]);
    free(parts);
    return v;
}
