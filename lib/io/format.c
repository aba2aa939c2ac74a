/* format.c: every textual form of a Flitter value (format.h).
 *
 * Implements FORMATS.md §1 (value text: shortest round-trip numbers, quoted
 * strings with C-like escapes, `(!kind)` nodes, `(func NAME)` functions),
 * §2 (state dumps: a `# frame N time T` header and `KEY = VALUE` lines sorted
 * by the bytes of the key text, `_`-prefixed string keys omitted) and §3
 * (node-tree dumps), plus LANGUAGE.md §3.13 string conversion ("%.9g"
 * numbers, symbol names, node kinds, function names) and §3.14 debug repr
 * (Python-style quoted strings, node representations in parentheses).
 *
 * Shortest round-trip digits: for a digit count p, printf's correctly
 * rounded "%.*e" and its neighbouring p-digit decimal on the other side of
 * x are read back with strtod; the smallest p that works is found by
 * bisection, giving the shortest digit string that reads back exactly, and
 * the closest such string to x (the same digits as Python's repr()).
 * That literal route costs about 2-3 us a number (printf's digits); for
 * |x| from 2^-30 to 2^53 the exact route finds the same digits in about
 * 0.2 us with 128-bit integer arithmetic (no printf, no strtod), trying the
 * same candidates in the same order; test_format compares the two.
 */
#include "format.h"

#include "mem.h"
#include "utf8.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ */
/* Numbers                                                             */
/* ------------------------------------------------------------------ */

/* The significant digits d1 d2 ... dn (d1 != 0) and decimal exponent of a
 * finite non-zero |x| written as d1.d2...dn × 10^exp. */
typedef struct {
    char digits[24];
    int ndigits;
    int exp;        /* decimal exponent of the first digit */
} Decimal;

/* Read "d.ddd…e±X" (from "%.*e") into [d]. */
static void decimal_parse(Decimal *d, const char *s)
{
    d->ndigits = 0;
    for (; *s && *s != 'e'; s++)
        if (*s >= '0' && *s <= '9')
            d->digits[d->ndigits++] = *s;
    d->exp = (*s == 'e') ? atoi(s + 1) : 0;
}

/* True when the decimal [d] (sign [neg]) reads back to exactly [x]. */
static bool decimal_reads_back(const Decimal *d, bool neg, double x)
{
    char text[48];
    int n = 0;
    if (neg)
        text[n++] = '-';
    text[n++] = d->digits[0];
    text[n++] = '.';
    for (int i = 1; i < d->ndigits; i++)
        text[n++] = d->digits[i];
    snprintf(text + n, sizeof text - (size_t)n, "e%d", d->exp);
    double y = strtod(text, NULL);
    return memcmp(&x, &y, sizeof x) == 0;
}

/* [d] moved by one unit in its last digit (+1 or -1), renormalised. */
static Decimal decimal_step(const Decimal *d, int dir)
{
    Decimal r = *d;
    int i = r.ndigits - 1;
    if (dir > 0) {
        while (i >= 0 && r.digits[i] == '9')
            r.digits[i--] = '0';
        if (i >= 0) {
            r.digits[i]++;
        } else {            /* 9.99 → 10.0 */
            memmove(r.digits + 1, r.digits, (size_t)r.ndigits);
            r.digits[0] = '1';
            r.exp++;        /* keep the digit count: drop the last zero */
        }
    } else {
        while (i >= 0 && r.digits[i] == '0')
            r.digits[i--] = '9';
        if (i >= 0)
            r.digits[i]--;
        if (r.digits[0] == '0') {   /* 1.00e+X → 9.99e+(X-1) */
            memset(r.digits, '9', (size_t)r.ndigits);
            r.exp--;
        }
    }
    return r;
}

/* Whether some [prec]-digit decimal reads back to [x] (finite, non-zero);
 * if so it is stored in *[out]. Such a decimal lies in the interval of
 * values that round to x, so it is either the correctly rounded one or its
 * neighbour on the other side of x (the interval is asymmetric at powers of
 * two). The property is monotone in [prec]. */
static bool probe_digits(double x, int prec, Decimal *out)
{
    bool neg = signbit(x);
    char text[48];
    snprintf(text, sizeof text, "%.*e", prec - 1, fabs(x));
    Decimal d;
    decimal_parse(&d, text);
    if (decimal_reads_back(&d, neg, x)) {
        *out = d;
        return true;
    }
    Decimal up = decimal_step(&d, +1), down = decimal_step(&d, -1);
    if (decimal_reads_back(&up, neg, x)) {
        *out = up;
        return true;
    }
    if (decimal_reads_back(&down, neg, x)) {
        *out = down;
        return true;
    }
    return false;
}

/* Shortest round-trip digits of finite non-zero [x] (the literal route:
 * printf and strtod, for any x): 17 digits always
 * suffice; most computed values need 16 or 17, so those are tried first and
 * shorter forms are found by bisection. */
static void shortest_decimal_literal(Decimal *out, double x)
{
    if (probe_digits(x, 15, out)) {
        int lo = 1, hi = 15;        /* hi works, *out holds its digits */
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            Decimal d;
            if (probe_digits(x, mid, &d)) {
                hi = mid;
                *out = d;
            } else {
                lo = mid + 1;
            }
        }
    } else if (!probe_digits(x, 16, out)) {
        char text[48];
        snprintf(text, sizeof text, "%.16e", fabs(x));
        decimal_parse(out, text);
    }
    while (out->ndigits > 1 && out->digits[out->ndigits - 1] == '0')
        out->ndigits--;
}

#ifdef __SIZEOF_INT128__
/* {===== the exact route: the same digits without printf
 *
 * For x = m 2^q with 2^-30 <= |x| < 2^53 (m < 2^53 an integer), the value
 * X = |x| 10^k, k = 16 - e (e the decimal exponent of |x|: X has 17 digits
 * before its point), is N / 2^r with N = m 5^k and r = -(q + k): both fit
 * in 128 bits (k <= 26, so N < 2^114; r <= 62, so a candidate shifted
 * by r is below 2^123). A candidate of n digits is
 * C 10^(17-n) in X's units, so whether it lies in x's round-trip interval
 * is an integer comparison with the interval's half-width, 5^k / 2^(r+1)
 * (half that below x when m = 2^52: the double below is nearer), ties
 * going to the even m as strtod's rounding does. The digits, the order of
 * the candidates tried (the correctly rounded one, then one unit up, one
 * down) and the bisection over digit counts are those of the literal
 * route, which test_format checks the two against. */

typedef unsigned __int128 U128;

/* X's parts: N, r >= 0 (X = N / 2^r), the half-width's numerator H =
 * 5^k 2^(-r before clamping) (the interval is (X - H/2^(r+1), X + H/2^(r+1))
 * above, half that below when [pow2]), [m_even]. */
typedef struct {
    U128 n;
    int r;
    U128 h;
    bool pow2, m_even;
    int e;           /* the decimal exponent of |x| */
} Exact;

/* 10^j for j in 0..17 and 5^k for k in 0..26: all below 2^64. */
static const uint64_t POW10[18] = {
    UINT64_C(1), UINT64_C(10), UINT64_C(100), UINT64_C(1000), UINT64_C(10000), UINT64_C(100000),
    UINT64_C(1000000), UINT64_C(10000000), UINT64_C(100000000), UINT64_C(1000000000),
    UINT64_C(10000000000), UINT64_C(100000000000), UINT64_C(1000000000000), UINT64_C(10000000000000),
    UINT64_C(100000000000000), UINT64_C(1000000000000000), UINT64_C(10000000000000000),
    UINT64_C(100000000000000000)};
static const uint64_t POW5[27] = {
    UINT64_C(1), UINT64_C(5), UINT64_C(25), UINT64_C(125), UINT64_C(625), UINT64_C(3125),
    UINT64_C(15625), UINT64_C(78125), UINT64_C(390625), UINT64_C(1953125), UINT64_C(9765625),
    UINT64_C(48828125), UINT64_C(244140625), UINT64_C(1220703125), UINT64_C(6103515625),
    UINT64_C(30517578125), UINT64_C(152587890625), UINT64_C(762939453125), UINT64_C(3814697265625),
    UINT64_C(19073486328125), UINT64_C(95367431640625), UINT64_C(476837158203125),
    UINT64_C(2384185791015625), UINT64_C(11920928955078125), UINT64_C(59604644775390625),
    UINT64_C(298023223876953125), UINT64_C(1490116119384765625)};

/* Set up [ex] for |x|; false outside the route's range. */
static bool exact_of(double x, Exact *ex)
{
    double a = fabs(x);
    if (!(a >= 0x1p-30 && a < 0x1p53))
        return false;
    int be;
    double f = frexp(a, &be);                 /* a = f 2^be, f in [0.5, 1) */
    uint64_t m = (uint64_t)ldexp(f, 53);      /* exact: 53 bits */
    int q = be - 53;
    int e = (int)floor(log10(a));
    for (int tries = 0; tries < 3; tries++) {
        int k = 16 - e;
        if (k < 0 || k > 26)
            return false;
        U128 five = POW5[k];
        U128 n = (U128)m * five;
        int r = -(q + k);
        U128 h = five;
        if (r < 0) {
            if (r < -8)
                return false;
            n <<= -r;
            h <<= -r;
            r = 0;
        }
        if (r > 62)
            return false;
        U128 whole = n >> r;                   /* floor(X) */
        if (whole >= POW10[17]) {
            e++;
            continue;
        }
        if (whole < POW10[16]) {
            e--;
            continue;
        }
        ex->n = n;
        ex->r = r;
        ex->h = h;
        ex->pow2 = m == (UINT64_C(1) << 52);
        ex->m_even = (m & 1) == 0;
        ex->e = e;
        return true;
    }
    return false;
}

/* X rounded to a multiple of 10^j (j in 0..16), halves to even, in units
 * of 10^j: printf's correctly rounded digits. */
static U128 exact_round(const Exact *ex, int j)
{
    /* X = whole + frac / 2^r, whole < 10^17, frac < 2^62 */
    uint64_t whole = (uint64_t)(ex->n >> ex->r);
    uint64_t frac = (uint64_t)(ex->n - ((U128)whole << ex->r));
    uint64_t p = POW10[j];
    uint64_t c = whole / p, b = whole % p;
    bool up;
    if (j == 0) {
        /* the fraction against one half */
        if (ex->r == 0)
            up = false;
        else {
            uint64_t half = UINT64_C(1) << (ex->r - 1);
            up = frac > half || (frac == half && (c & 1));
        }
    } else {
        uint64_t half = p / 2;
        up = b > half || (b == half && (frac > 0 || (c & 1)));
    }
    return c + (up ? 1 : 0);
}

/* Whether C 10^j (X's units) reads back to x. */
static bool exact_reads_back(const Exact *ex, U128 c, int j)
{
    U128 v = (c * POW10[j]) << ex->r;         /* < 2^61 2^62 */
    bool below = v < ex->n;
    U128 d = below ? ex->n - v : v - ex->n;
    /* |C 10^j - X| against H / 2^(r+1), or H / 2^(r+2) below a power of two */
    U128 lhs = d << (below && ex->pow2 ? 2 : 1);
    return lhs < ex->h || (lhs == ex->h && ex->m_even);
}

/* [c] (n digits, or 10^n after a carry) at 10^j into [out]. */
static void exact_digits(Decimal *out, U128 c, int n, int e)
{
    char t[40];
    int len = 0;
    do {
        t[len++] = (char)('0' + (int)(c % 10));
        c /= 10;
    } while (c);
    out->ndigits = n;
    out->exp = e + (len - n);
    for (int i = 0; i < n; i++)
        out->digits[i] = i < len ? t[len - 1 - i] : '0';
}

/* probe_digits by the exact route: [n] in 1..16. */
static bool exact_probe(const Exact *ex, int n, Decimal *out)
{
    int j = 17 - n, e = ex->e;
    U128 c = exact_round(ex, j), lowest = POW10[n - 1];
    if (c == lowest * 10) {
        /* rounded up to 10.00…0: the literal route's 1.00…0 a decade up,
         * whose neighbours are a unit of its own last digit away */
        c = lowest;
        j++;
        e++;
    }
    if (exact_reads_back(ex, c, j)) {
        exact_digits(out, c, n, e);
        return true;
    }
    if (exact_reads_back(ex, c + 1, j)) {
        exact_digits(out, c + 1, n, e);
        return true;
    }
    /* one unit down; from 1.00…0 that is 9.99…9 a decade lower (the
     * literal route's decimal_step): the next digit's unit, 10^(j-1) */
    if (c > lowest) {
        if (exact_reads_back(ex, c - 1, j)) {
            exact_digits(out, c - 1, n, e);
            return true;
        }
    } else if (exact_reads_back(ex, c * 10 - 1, j - 1)) {
        exact_digits(out, c * 10 - 1, n, e - 1);
        return true;
    }
    return false;
}

/* shortest_decimal_literal's digits by the exact route; false outside its
 * range. */
static bool shortest_decimal_exact(Decimal *out, double x)
{
    Exact ex;
    if (!exact_of(x, &ex))
        return false;
    if (exact_probe(&ex, 15, out)) {
        int lo = 1, hi = 15;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            Decimal d;
            if (exact_probe(&ex, mid, &d)) {
                hi = mid;
                *out = d;
            } else {
                lo = mid + 1;
            }
        }
    } else if (!exact_probe(&ex, 16, out)) {
        exact_digits(out, exact_round(&ex, 0), 17, ex.e);
    }
    while (out->ndigits > 1 && out->digits[out->ndigits - 1] == '0')
        out->ndigits--;
    return true;
}

/* }===== */
#endif

/* Shortest round-trip digits of finite non-zero [x]: the exact route where
 * it reaches, else the literal one ([literal]: always the literal one). */
static void shortest_decimal(Decimal *out, double x, bool literal)
{
#ifdef __SIZEOF_INT128__
    if (!literal && shortest_decimal_exact(out, x))
        return;
#else
    (void)literal;
#endif
    shortest_decimal_literal(out, x);
}

void fmt_double_route(Buf *b, double x, bool literal)
{
    if (x == 0) {
        buf_putc(b, '0');
        return;
    }
    if (isnan(x)) {
        buf_puts(b, "nan");
        return;
    }
    if (isinf(x)) {
        buf_puts(b, x < 0 ? "-inf" : "inf");
        return;
    }
    if (fabs(x) < 0x1p53 && x == (double)(int64_t)x) {
        /* an integer below 2^53: every integer there is a double, so no
         * shorter decimal than its own digits reads back to it, and it is
         * below 1e16, so it is written without an exponent */
        char t[24];
        size_t i = sizeof t;
        uint64_t u = (uint64_t)(x < 0 ? -x : x);
        do {
            t[--i] = (char)('0' + u % 10);
            u /= 10;
        } while (u);
        if (x < 0)
            t[--i] = '-';
        buf_add(b, t + i, sizeof t - i);
        return;
    }
    Decimal d;
    shortest_decimal(&d, x, literal);
    if (signbit(x))
        buf_putc(b, '-');
    int e = d.exp, n = d.ndigits;
    if (e >= 16 || e < -4) {
        buf_putc(b, d.digits[0]);
        if (n > 1) {
            buf_putc(b, '.');
            buf_add(b, d.digits + 1, (size_t)n - 1);
        }
        buf_printf(b, "e%c%02d", e < 0 ? '-' : '+', e < 0 ? -e : e);
    } else if (e >= 0) {
        if (n <= e + 1) {
            buf_add(b, d.digits, (size_t)n);
            for (int i = n; i <= e; i++)
                buf_putc(b, '0');
        } else {
            buf_add(b, d.digits, (size_t)e + 1);
            buf_putc(b, '.');
            buf_add(b, d.digits + e + 1, (size_t)(n - e - 1));
        }
    } else {
        buf_puts(b, "0.");
        for (int i = -1; i > e; i--)
            buf_putc(b, '0');
        buf_add(b, d.digits, (size_t)n);
    }
}

void fmt_double(Buf *b, double x) { fmt_double_route(b, x, false); }

void fmt_g9(Buf *b, double x)
{
    if (isnan(x)) {
        buf_puts(b, "nan");
        return;
    }
    buf_printf(b, "%.9g", x);
}

/* A number in value text: 0, nan, inf, :symbol or shortest digits. */
static void value_number(Buf *b, double x, const SymTab *st)
{
    if (x != 0 && st) {
        const Str *name = symtab_name(st, x);
        if (name) {
            buf_putc(b, ':');
            buf_add(b, name->bytes, name->len);
            return;
        }
    }
    fmt_double(b, x);
}

/* A number in str(): symbol name or "%.9g". */
static void str_number(Buf *b, double x, const SymTab *st)
{
    const Str *name = st ? symtab_name(st, x) : NULL;
    if (name)
        buf_add(b, name->bytes, name->len);
    else
        fmt_g9(b, x);
}

/* A number in repr(): :symbol or "%.9g"; [zero_special] prints either zero
 * as `0` (numeric vectors). */
static void repr_number(Buf *b, double x, const SymTab *st, bool zero_special)
{
    if (zero_special && x == 0) {
        buf_putc(b, '0');
        return;
    }
    const Str *name = st ? symtab_name(st, x) : NULL;
    if (name) {
        buf_putc(b, ':');
        buf_add(b, name->bytes, name->len);
    } else {
        fmt_g9(b, x);
    }
}

/* ------------------------------------------------------------------ */
/* Strings                                                             */
/* ------------------------------------------------------------------ */

/* A string in value text (FORMATS.md §1). */
void fmt_quoted(Buf *b, const Str *s)
{
    buf_putc(b, '"');
    for (uint32_t i = 0; i < s->len; i++) {
        unsigned char c = (unsigned char)s->bytes[i];
        switch (c) {
        case '"': buf_puts(b, "\\\""); break;
        case '\\': buf_puts(b, "\\\\"); break;
        case '\n': buf_puts(b, "\\n"); break;
        case '\r': buf_puts(b, "\\r"); break;
        case '\t': buf_puts(b, "\\t"); break;
        default:
            if (c < 0x20 || c == 0x7f)
                buf_printf(b, "\\x%02x", c);
            else
                buf_putc(b, (char)c);
        }
    }
    buf_putc(b, '"');
}

/* Python's str.isprintable() for one code point. Exact for Latin-1 and the
 * common format/separator characters; unassigned code points beyond those
 * listed here are treated as printable (an approximation of Python's
 * Unicode database, relevant only to debug output). */
static bool py_printable(uint32_t c)
{
    static const uint32_t ranges[][2] = {
        {0x0000, 0x001f}, {0x007f, 0x00a0}, {0x00ad, 0x00ad},
        {0x0378, 0x0379}, {0x0380, 0x0383}, {0x038b, 0x038b},
        {0x038d, 0x038d}, {0x03a2, 0x03a2},
        {0x0600, 0x0605}, {0x061c, 0x061c}, {0x06dd, 0x06dd},
        {0x070f, 0x070f}, {0x0890, 0x0891}, {0x08e2, 0x08e2},
        {0x1680, 0x1680}, {0x180e, 0x180e},
        {0x2000, 0x200f}, {0x2028, 0x202f}, {0x205f, 0x2064},
        {0x2065, 0x206f}, {0x3000, 0x3000},
        {0xd800, 0xf8ff}, {0xfdd0, 0xfdef}, {0xfeff, 0xfeff},
        {0xfff0, 0xfffb}, {0xfffe, 0xffff},
        {0x110bd, 0x110bd}, {0x110cd, 0x110cd}, {0x13430, 0x1343f},
        {0x1bca0, 0x1bca3}, {0x1d173, 0x1d17a},
        {0x323b0, 0xe00ff}, {0xe01f0, 0x10ffff},
    };
    for (size_t i = 0; i < sizeof ranges / sizeof ranges[0]; i++)
        if (c >= ranges[i][0] && c <= ranges[i][1])
            return false;
    if ((c & 0xfffe) == 0xfffe)   /* per-plane noncharacters */
        return false;
    return true;
}

/* A string as Python's repr() writes it (LANGUAGE.md §3.14). */
static void repr_string(Buf *b, const Str *s)
{
    bool has_single = memchr(s->bytes, '\'', s->len) != NULL;
    bool has_double = memchr(s->bytes, '"', s->len) != NULL;
    char quote = (has_single && !has_double) ? '"' : '\'';
    buf_putc(b, quote);
    const unsigned char *p = (const unsigned char *)s->bytes;
    size_t n = s->len;
    for (size_t i = 0; i < n;) {
        uint32_t c;
        size_t len = utf8_decode(p + i, n - i, &c);
        if (c == (uint32_t)quote || c == '\\') {
            buf_putc(b, '\\');
            buf_putc(b, (char)c);
        } else if (c == '\n') {
            buf_puts(b, "\\n");
        } else if (c == '\r') {
            buf_puts(b, "\\r");
        } else if (c == '\t') {
            buf_puts(b, "\\t");
        } else if (len == 1 && c >= 0x80) {
            buf_printf(b, "\\x%02x", (unsigned)c);   /* invalid UTF-8 byte */
        } else if (!py_printable(c)) {
            if (c < 0x100)
                buf_printf(b, "\\x%02x", (unsigned)c);
            else if (c < 0x10000)
                buf_printf(b, "\\u%04x", (unsigned)c);
            else
                buf_printf(b, "\\U%08x", (unsigned)c);
        } else {
            buf_add(b, (const char *)p + i, len);
        }
        i += len;
    }
    buf_putc(b, quote);
}

/* ------------------------------------------------------------------ */
/* Vectors                                                             */
/* ------------------------------------------------------------------ */

void fmt_value(Buf *b, const Vec *v, const SymTab *st)
{
    uint32_t n = vec_len(v);
    if (n == 0) {
        buf_puts(b, "null");
        return;
    }
    if (v->kind == VEC_NUM) {
        const double *x = vec_cnums(v);
        for (uint32_t i = 0; i < n; i++) {
            if (i)
                buf_putc(b, ';');
            value_number(b, x[i], st);
        }
        return;
    }
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < n; i++) {
        if (i)
            buf_putc(b, ';');
        switch (e[i].kind) {
        case EL_NUM:
            value_number(b, e[i].num, st);
            break;
        case EL_STR:
            fmt_quoted(b, e[i].str);
            break;
        case EL_NODE:
            buf_puts(b, "(!");
            buf_add(b, e[i].node->kind->bytes, e[i].node->kind->len);
            buf_putc(b, ')');
            break;
        case EL_FUNC:
            buf_puts(b, "(func ");
            buf_puts(b, func_name(e[i].func));
            buf_putc(b, ')');
            break;
        }
    }
}

void fmt_str(Buf *b, const Vec *v, const SymTab *st)
{
    uint32_t n = vec_len(v);
    if (n == 0)
        return;
    if (v->kind == VEC_NUM) {
        const double *x = vec_cnums(v);
        for (uint32_t i = 0; i < n; i++)
            str_number(b, x[i], st);
        return;
    }
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < n; i++) {
        switch (e[i].kind) {
        case EL_NUM:
            str_number(b, e[i].num, st);
            break;
        case EL_STR:
            buf_add(b, e[i].str->bytes, e[i].str->len);
            break;
        case EL_NODE:
            buf_add(b, e[i].node->kind->bytes, e[i].node->kind->len);
            break;
        case EL_FUNC:
            buf_puts(b, func_name(e[i].func));
            break;
        }
    }
}

/* One node line (without indentation or newline): `!kind #tags name=VAL`,
 * attribute values written by value text ([repr] false) or repr ([repr]
 * true). */
static void node_line(Buf *b, const Node *nd, const SymTab *st, bool repr)
{
    buf_putc(b, '!');
    buf_add(b, nd->kind->bytes, nd->kind->len);
    for (uint32_t i = 0; i < nd->ntags; i++) {
        buf_puts(b, " #");
        buf_add(b, nd->tags[i]->bytes, nd->tags[i]->len);
    }
    for (uint32_t i = 0; i < nd->nattrs; i++) {
        buf_putc(b, ' ');
        buf_add(b, nd->attrs[i].name->bytes, nd->attrs[i].name->len);
        buf_putc(b, '=');
        if (repr)
            fmt_repr(b, nd->attrs[i].value, st);
        else
            fmt_value(b, nd->attrs[i].value, st);
    }
}

/* [root] and its descendants, depth-first, one line each indented one space
 * per depth; lines separated by '\n' and, when [trailing_newline], each
 * terminated by one. Iterative so that deep trees cannot exhaust the stack. */
static void node_lines(Buf *b, const Node *root, const SymTab *st, bool repr,
                       bool trailing_newline)
{
    typedef struct { const Node *node; uint32_t next; } Frame;
    size_t cap = 16, depth = 0;
    Frame *stack = malloc(cap * sizeof *stack);
    if (!stack)
        mem_oom();
    node_line(b, root, st, repr);
    if (trailing_newline)
        buf_putc(b, '\n');
    stack[0] = (Frame){root, 0};
    for (;;) {
        Frame *f = &stack[depth];
        if (f->next >= f->node->nchildren) {
            if (depth == 0)
                break;
            depth--;
            continue;
        }
        const Node *child = f->node->children[f->next++];
        if (!trailing_newline)
            buf_putc(b, '\n');
        for (size_t i = 0; i <= depth; i++)
            buf_putc(b, ' ');
        node_line(b, child, st, repr);
        if (trailing_newline)
            buf_putc(b, '\n');
        if (++depth == cap) {
            cap *= 2;
            Frame *grown = realloc(stack, cap * sizeof *stack);
            if (!grown)
                mem_oom();
            stack = grown;
        }
        stack[depth] = (Frame){child, 0};
    }
    free(stack);
}

void fmt_repr(Buf *b, const Vec *v, const SymTab *st)
{
    uint32_t n = vec_len(v);
    if (n == 0) {
        buf_puts(b, "null");
        return;
    }
    if (v->kind == VEC_NUM) {
        const double *x = vec_cnums(v);
        for (uint32_t i = 0; i < n; i++) {
            if (i)
                buf_putc(b, ';');
            repr_number(b, x[i], st, true);
        }
        return;
    }
    const Elem *e = vec_celems(v);
    for (uint32_t i = 0; i < n; i++) {
        if (i)
            buf_putc(b, ';');
        switch (e[i].kind) {
        case EL_NUM:
            repr_number(b, e[i].num, st, false);
            break;
        case EL_STR:
            repr_string(b, e[i].str);
            break;
        case EL_NODE:
            buf_putc(b, '(');
            node_lines(b, e[i].node, st, true, false);
            buf_putc(b, ')');
            break;
        case EL_FUNC:
            /* The reference prints the host repr of a builtin (with an
             * address); a stable stand-in is used here. */
            if (e[i].func->bi)
                buf_printf(b, "(<cyfunction %s>)", func_name(e[i].func));
            else
                buf_printf(b, "(<Function: %s>)", func_name(e[i].func));
            break;
        }
    }
}

void fmt_tree(Buf *b, const Node *root, const SymTab *st)
{
    node_lines(b, root, st, false, true);
}

/* ------------------------------------------------------------------ */
/* State dump                                                          */
/* ------------------------------------------------------------------ */

/* One line's key and value texts: offsets into the dump's two texts
 * while they grow, pointers once they are complete. */
typedef struct {
    size_t key_at, key_len, value_at, value_len;
    const char *key, *value;
} DumpLine;

/* Order of two texts by their bytes (a prefix first). */
static int text_cmp(const char *a, size_t na, const char *b, size_t nb)
{
    size_t n = na < nb ? na : nb;
    int c = n ? memcmp(a, b, n) : 0;
    if (c)
        return c;
    return (na > nb) - (na < nb);
}

/* By key text; distinct keys with the same text (0 and -0) are ordered by
 * their value text so that dumps are deterministic. */
static int dump_line_cmp(const void *pa, const void *pb)
{
    const DumpLine *a = pa, *b = pb;
    int c = text_cmp(a->key, a->key_len, b->key, b->key_len);
    return c ? c : text_cmp(a->value, a->value_len, b->value, b->value_len);
}

/* A key left out of dumps: a single string starting with '_'. */
static bool key_is_internal(const Vec *key)
{
    if (!vec_is_obj(key) || key->len != 1)
        return false;
    const Elem *e = vec_celems(key);
    return e[0].kind == EL_STR && e[0].str->len > 0 && e[0].str->bytes[0] == '_';
}

void fmt_state_dump(Buf *b, const StateDict *sd, long frame, double time,
                    const SymTab *st)
{
    buf_printf(b, "# frame %ld time ", frame);
    value_number(b, time, st);
    buf_putc(b, '\n');
    size_t n = 0;
    StateEntry *entries = sd ? state_entries(sd, &n) : NULL;
    DumpLine *lines = n ? malloc(n * sizeof *lines) : NULL;
    if (n && !lines)
        mem_oom();
    /* every key's text into one buffer and every value's into another
     * (two allocations that grow, not two a line), then sorted by offset */
    Buf keys = BUF_INIT, values = BUF_INIT;
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (key_is_internal(entries[i].key) || vec_len(entries[i].value) == 0)
            continue;
        lines[m].key_at = keys.len;
        fmt_value(&keys, entries[i].key, st);
        lines[m].key_len = keys.len - lines[m].key_at;
        lines[m].value_at = values.len;
        fmt_value(&values, entries[i].value, st);
        lines[m].value_len = values.len - lines[m].value_at;
        m++;
    }
    const char *key_text = buf_cstr(&keys), *value_text = buf_cstr(&values);
    for (size_t i = 0; i < m; i++) {
        lines[i].key = key_text + lines[i].key_at;
        lines[i].value = value_text + lines[i].value_at;
    }
    if (m > 1)
        qsort(lines, m, sizeof *lines, dump_line_cmp);
    for (size_t i = 0; i < m; i++) {
        buf_add(b, lines[i].key, lines[i].key_len);
        buf_add(b, " = ", 3);
        buf_add(b, lines[i].value, lines[i].value_len);
        buf_putc(b, '\n');
    }
    buf_free(&keys);
    buf_free(&values);
    free(lines);
    free(entries);
}
