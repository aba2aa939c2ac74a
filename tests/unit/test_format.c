/* test_format.c: value text, str, repr, node-tree dumps and state dumps
 * (FORMATS.md §1-3, LANGUAGE.md §3.13-3.14), checked against the examples
 * of the specs and the layout of the golden files. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "buf.h"
#include "format.h"
#include "node.h"
#include "pool.h"
#include "state.h"
#include "value.h"

/* ------------------------------------------------------------------ */
/* Helpers                                                             */
/* ------------------------------------------------------------------ */

static void check_double(double x, const char *want)
{
    Buf b = BUF_INIT;
    fmt_double(&b, x);
    if (strcmp(buf_cstr(&b), want) != 0)
        fail_msg("fmt_double(%.17g) = \"%s\", want \"%s\"", x, buf_cstr(&b), want);
    /* whatever is printed (bar the special values) reads back exactly */
    if (isfinite(x) && x != 0) {
        double y = strtod(buf_cstr(&b), NULL);
        assert_memory_equal(&x, &y, sizeof x);
    }
    buf_free(&b);
}

static void check_g9(double x, const char *want)
{
    Buf b = BUF_INIT;
    fmt_g9(&b, x);
    if (strcmp(buf_cstr(&b), want) != 0)
        fail_msg("fmt_g9(%.17g) = \"%s\", want \"%s\"", x, buf_cstr(&b), want);
    buf_free(&b);
}

typedef void (*Formatter)(Buf *, const Vec *, const SymTab *);

/* Format [v] with [f], compare with [want], release [v]. */
static void check_fmt(Formatter f, Vec *v, const SymTab *st, const char *want)
{
    Buf b = BUF_INIT;
    f(&b, v, st);
    if (strcmp(buf_cstr(&b), want) != 0)
        fail_msg("got \"%s\", want \"%s\"", buf_cstr(&b), want);
    buf_free(&b);
    vec_release(v);
}

static Vec *nums(int n, ...)
{
    va_list ap;
    va_start(ap, n);
    Vec *v = vec_new_num((uint32_t)n);
    for (int i = 0; i < n; i++)
        vec_nums(v)[i] = va_arg(ap, double);
    va_end(ap);
    return v;
}

/* Compose [n] parts (consumed). */
static Vec *compose(int n, ...)
{
    Vec *parts[16];
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++)
        parts[i] = va_arg(ap, Vec *);
    va_end(ap);
    Vec *v = vec_compose(parts, (size_t)n);
    for (int i = 0; i < n; i++)
        vec_release(parts[i]);
    return v;
}

static Vec *str(const char *s)
{
    return vec_str(s, strlen(s));
}

static Node *node(const char *kind)
{
    Str *k = str_from(kind);
    Node *n = node_new(k);
    str_release(k);
    return n;
}

static void set_attr(Node *n, const char *name, Vec *value)
{
    Str *s = str_from(name);
    node_set_attr(n, s, value);
    str_release(s);
}

static void add_tag(Node *n, const char *tag)
{
    Str *s = str_from(tag);
    node_add_tag(n, s);
    str_release(s);
}

/* A one-element vector holding a fresh node of [kind]. */
static Vec *node_vec(const char *kind)
{
    return vec_node_take(node(kind));
}

/* A user function value named [name]. */
static Vec *user_func(const char *name)
{
    Func *f = pool_calloc(sizeof *f);   /* func_release returns it to the pool */
    f->refs = 1;
    f->name = str_from(name);
    return vec_func_take(f);
}

/* ------------------------------------------------------------------ */
/* Buf                                                                 */
/* ------------------------------------------------------------------ */

static void test_buf(void **s)
{
    (void)s;
    Buf b = BUF_INIT;
    assert_string_equal(buf_cstr(&b), "");
    buf_puts(&b, "abc");
    buf_putc(&b, '-');
    buf_printf(&b, "%d/%s", 42, "x");
    assert_string_equal(buf_cstr(&b), "abc-42/x");
    assert_int_equal(b.len, 8);
    /* a long printf goes through the growth path */
    char big[1000];
    memset(big, 'q', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    buf_printf(&b, "%s!", big);
    assert_int_equal(b.len, 8 + 999 + 1);
    assert_int_equal(buf_cstr(&b)[b.len - 1], '!');
    buf_add(&b, "\0z", 2);          /* embedded NUL kept */
    assert_int_equal(b.len, 1010);
    buf_reset(&b);
    assert_string_equal(buf_cstr(&b), "");
    buf_free(&b);
    assert_null(b.data);
}

/* ------------------------------------------------------------------ */
/* Numbers                                                             */
/* ------------------------------------------------------------------ */

static void test_fmt_double_spec(void **s)
{
    (void)s;
    /* FORMATS.md §1 */
    check_double(3, "3");
    check_double(-0.5, "-0.5");
    check_double(0.0001, "0.0001");
    check_double(1000000000000000.0, "1000000000000000");
    check_double(1.9833333333333312, "1.9833333333333312");
    check_double(1e16, "1e+16");
    check_double(1e-5, "1e-05");
    check_double(-1.2345678901234568e+17, "-1.2345678901234568e+17");
    check_double(5e-324, "5e-324");
    volatile double a = 0.1, b = 0.2;
    check_double(a + b, "0.30000000000000004");
    /* special values */
    check_double(0.0, "0");
    check_double(-0.0, "0");
    check_double(NAN, "nan");
    check_double(-NAN, "nan");
    check_double(INFINITY, "inf");
    check_double(-INFINITY, "-inf");
    /* golden layouts (literals.tree, box3d.state) */
    check_double(4e-06, "4e-06");
    check_double(7.000000000000001e-09, "7.000000000000001e-09");
    check_double(2.5e-06, "2.5e-06");
    check_double(0.01, "0.01");
    check_double(3723.5, "3723.5");
    check_double(0.4833333333333333, "0.4833333333333333");
    check_double(-25.361382702164512, "-25.361382702164512");
}

static void test_fmt_double_edges(void **s)
{
    (void)s;
    check_double(1234567890123456.0, "1234567890123456");   /* exponent 15 */
    check_double(12345678901234568.0, "1.2345678901234568e+16");
    check_double(0.00012345, "0.00012345");                /* exponent -4 */
    check_double(0.000012345, "1.2345e-05");
    check_double(1e22, "1e+22");
    check_double(1e23, "1e+23");
    check_double(1e100, "1e+100");
    check_double(-1e-300, "-1e-300");
    check_double(1.7976931348623157e308, "1.7976931348623157e+308");
    check_double(2.2250738585072014e-308, "2.2250738585072014e-308");
    check_double(9007199254740993.0, "9007199254740992");
    check_double(1.0 / 3, "0.3333333333333333");
    check_double(2.0 / 3, "0.6666666666666666");
    check_double(100, "100");
    check_double(123.456, "123.456");
    check_double(0.1, "0.1");
    /* powers of two where the round-trip interval is asymmetric */
    check_double(ldexp(1, -1074), "5e-324");
    check_double(ldexp(1, 1023), "8.98846567431158e+307");
    check_double(ldexp(1, -1022), "2.2250738585072014e-308");
    check_double(ldexp(1, 60), "1.152921504606847e+18");
    /* a sweep: everything printed reads back (checked in check_double) */
    uint64_t u = UINT64_C(0x9e3779b97f4a7c15);
    for (int i = 0; i < 20000; i++) {
        u ^= u << 13;
        u ^= u >> 7;
        u ^= u << 17;
        double x;
        memcpy(&x, &u, sizeof x);
        if (!isfinite(x) || x == 0)
            continue;
        Buf b = BUF_INIT;
        fmt_double(&b, x);
        double y = strtod(buf_cstr(&b), NULL);
        assert_memory_equal(&x, &y, sizeof x);
        /* never longer than 17 significant digits, never a trailing .0 */
        assert_null(strstr(buf_cstr(&b), ".0e"));
        assert_false(b.len >= 2 && strcmp(buf_cstr(&b) + b.len - 2, ".0") == 0);
        buf_free(&b);
    }
}

/* Integers below 2^53 take a fast path (their own digits); it must write
 * what the shortest round-trip route writes: checked against "%.0f" (exact
 * for integers) and, around the ends of the path, by reading back. */
static void test_fmt_double_integers(void **s)
{
    (void)s;
    check_double(-0.0, "0");
    check_double(1, "1");
    check_double(-7, "-7");
    check_double(1000, "1000");
    check_double(1e15, "1000000000000000");
    check_double(-999999999999999.0, "-999999999999999");
    check_double(0x1p53 - 1, "9007199254740991");
    check_double(-(0x1p53 - 1), "-9007199254740991");
    check_double(0x1p53, "9007199254740992");        /* past the path */
    check_double(-0x1p53, "-9007199254740992");
    check_double(0.5, "0.5");                         /* not integers */
    check_double(4503599627370495.5, "4503599627370495.5");
    uint64_t u = UINT64_C(0x2545f4914f6cdd1d);
    for (int i = 0; i < 20000; i++) {
        u ^= u << 13;
        u ^= u >> 7;
        u ^= u << 17;
        /* magnitudes spread over 1 .. 2^53 */
        double x = (double)(int64_t)((u >> 11) >> (u & 63) % 53);
        if (u & 64)
            x = -x;
        char want[32];
        snprintf(want, sizeof want, "%.0f", x == 0 ? 0.0 : x);
        check_double(x, want);
    }
}

/* fmt_double's exact route (integer arithmetic for |x| from 2^-30 to 2^53)
 * writes what the literal route (printf's digits read back with strtod)
 * writes: at powers of two and ten and their neighbours (asymmetric
 * intervals, digits that round up to the next decade), at short decimals
 * (ties in the rounding of a probe), across the route's ends, and over a
 * sweep of bit patterns in its range. */
static void check_routes(double x)
{
    Buf a = BUF_INIT, b = BUF_INIT;
    fmt_double_route(&a, x, false);
    fmt_double_route(&b, x, true);
    if (strcmp(buf_cstr(&a), buf_cstr(&b)) != 0)
        fail_msg("fmt_double(%a): exact route \"%s\", literal \"%s\"", x, buf_cstr(&a), buf_cstr(&b));
    buf_free(&a);
    buf_free(&b);
}

static void test_fmt_double_routes(void **s)
{
    (void)s;
    /* a few by hand, through fmt_double (the exact route here) */
    check_double(nextafter(10, 0), "9.999999999999998");
    check_double(nextafter(1, 2), "1.0000000000000002");
    check_double(nextafter(1, 0), "0.9999999999999999");
    check_double(0.125, "0.125");
    check_double(ldexp(1, -30), "9.313225746154785e-10");
    check_double(nextafter(ldexp(1, -30), 0), "9.313225746154784e-10");   /* past the route: literal */
    check_double(4503599627370495.5, "4503599627370495.5");
    check_double(0.3, "0.3");
    check_double(1e-9, "1e-09");
    for (int k = -31; k <= 53; k++) {
        double p = ldexp(1, k);
        for (double x = nextafter(nextafter(p, 0), 0), i = 0; i < 5; i++, x = nextafter(x, INFINITY)) {
            check_routes(x);
            check_routes(-x);
        }
    }
    for (int k = -10; k <= 16; k++) {
        double p = pow(10, k);
        for (double x = nextafter(nextafter(p, 0), 0), i = 0; i < 5; i++, x = nextafter(x, INFINITY)) {
            check_routes(x);
            check_routes(x * 0.5);
            check_routes(x * 2.5);
        }
    }
    for (int i = 1; i < 4000; i++) {
        check_routes(i / 1000.0);
        check_routes(i / 8.0 + 0.0625);
        check_routes(i * 0.1);
        check_routes(i * 1e-9);
        check_routes(1.0 / i);
    }
    uint64_t u = UINT64_C(0x853c49e6748fea9b);
    for (int i = 0; i < 20000; i++) {
        u ^= u << 13;
        u ^= u >> 7;
        u ^= u << 17;
        /* any mantissa, exponents from 2^-31 to 2^53 */
        uint64_t bits = (u & UINT64_C(0x800fffffffffffff)) | (uint64_t)(1023 - 31 + (int)((u >> 52) % 85)) << 52;
        double x;
        memcpy(&x, &bits, sizeof x);
        check_routes(x);
    }
}

static void test_fmt_g9(void **s)
{
    (void)s;
    /* LANGUAGE.md §3.13 */
    check_g9(1e9, "1e+09");
    check_g9(123456789, "123456789");
    check_g9(1234567890, "1.23456789e+09");
    volatile double a = 0.1, b = 0.2;
    check_g9(a + b, "0.3");
    check_g9(1.0 / 3, "0.333333333");
    check_g9(1e-5, "1e-05");
    check_g9(0.0001, "0.0001");
    check_g9(123456789.5, "123456790");
    check_g9(INFINITY, "inf");
    check_g9(-INFINITY, "-inf");
    check_g9(NAN, "nan");
    check_g9(-NAN, "nan");
    check_g9(-0.0, "-0");
    check_g9(0.0, "0");
    check_g9(0.5, "0.5");
    check_g9(-2.5, "-2.5");
    check_g9(1e100, "1e+100");
}

/* ------------------------------------------------------------------ */
/* Value text                                                          */
/* ------------------------------------------------------------------ */

static void test_fmt_value_numbers(void **s)
{
    (void)s;
    SymTab *st = symtab_new();
    double sym = symtab_add(st, "sym", 3);
    double other = symtab_add(st, "other", 5);
    check_fmt(fmt_value, NULL, st, "null");
    check_fmt(fmt_value, vec_stream(STREAM_UNIFORM, 1), st, "null");
    check_fmt(fmt_value, nums(3, 2.0, 4.0, 6.0), st, "2;4;6");
    check_fmt(fmt_value, nums(3, 1.0, -0.0, 0.5), st, "1;0;0.5");
    check_fmt(fmt_value, nums(2, sym, 1e16), st, ":sym;1e+16");
    check_fmt(fmt_value, nums(2, other, sym), st, ":other;:sym");
    check_fmt(fmt_value, nums(3, NAN, INFINITY, -INFINITY), st, "nan;inf;-inf");
    /* without a symbol table the symbol is an ordinary (huge) number */
    check_fmt(fmt_value, nums(1, symbol_value("foo", 3)), NULL,
              "-1.6737404350843107e+308");
    symtab_free(st);
}

static void test_fmt_value_strings(void **s)
{
    (void)s;
    check_fmt(fmt_value, str("tab\there"), NULL, "\"tab\\there\"");
    check_fmt(fmt_value, str("quote\"inside"), NULL, "\"quote\\\"inside\"");
    check_fmt(fmt_value, str("back\\slash"), NULL, "\"back\\\\slash\"");
    check_fmt(fmt_value, str("a\nb\rc"), NULL, "\"a\\nb\\rc\"");
    check_fmt(fmt_value, str("\x01\x1f\x7f"), NULL, "\"\\x01\\x1f\\x7f\"");
    check_fmt(fmt_value, str("uni\xc3\xa9"), NULL, "\"uni\xc3\xa9\"");
    check_fmt(fmt_value, str("single"), NULL, "\"single\"");
    check_fmt(fmt_value, str("it's"), NULL, "\"it's\"");
    check_fmt(fmt_value, str(""), NULL, "\"\"");
    check_fmt(fmt_value, vec_str("a\0b", 3), NULL, "\"a\\x00b\"");
    check_fmt(fmt_value, compose(3, str("n"), nums(1, 0.0), str("m")), NULL, "\"n\";0;\"m\"");
}

static void test_fmt_value_objects(void **s)
{
    (void)s;
    SymTab *st = symtab_new();
    double sym = symtab_add(st, "sym", 3);
    check_fmt(fmt_value, compose(2, node_vec("a"), node_vec("b")), st, "(!a);(!b)");
    check_fmt(fmt_value, compose(3, str("title"), nums(1, sym), node_vec("x")), st,
              "\"title\";:sym;(!x)");
    check_fmt(fmt_value, compose(2, user_func("f"), nums(1, 1.5)), st, "(func f);1.5");
    /* a node with content still prints as (!kind) inside a vector */
    Node *n = node("box");
    add_tag(n, "t");
    set_attr(n, "size", nums(1, 2.0));
    Node *child = node("inner");
    node_append(n, child);  /* children are not printed either */
    node_release(child);
    check_fmt(fmt_value, vec_node_take(n), st, "(!box)");
    symtab_free(st);
}

/* ------------------------------------------------------------------ */
/* str and repr                                                        */
/* ------------------------------------------------------------------ */

static void test_fmt_str(void **s)
{
    (void)s;
    SymTab *st = symtab_new();
    double b = symtab_add(st, "b", 1);
    double foo = symtab_add(st, "foo", 3);
    check_fmt(fmt_str, NULL, st, "");
    check_fmt(fmt_str, vec_stream(STREAM_NORMAL, 7), st, "");
    check_fmt(fmt_str, nums(1, foo), st, "foo");
    check_fmt(fmt_str, str("hello"), st, "hello");
    check_fmt(fmt_str, compose(3, nums(1, 1.0), str("a"), nums(1, b)), st, "1ab");
    check_fmt(fmt_str, nums(2, 1.0, -0.0), st, "1-0");
    check_fmt(fmt_str, nums(1, -0.0), st, "-0");
    check_fmt(fmt_str, nums(3, 1.0 / 3, 1e9, NAN), st, "0.3333333331e+09nan");
    check_fmt(fmt_str, compose(3, node_vec("window"), str("-"), user_func("fn")), st,
              "window-fn");
    check_fmt(fmt_str, str("tab\there"), st, "tab\there");
    symtab_free(st);
}

static void test_fmt_repr(void **s)
{
    (void)s;
    SymTab *st = symtab_new();
    double y = symtab_add(st, "y", 1);
    /* LANGUAGE.md §3.14 examples */
    check_fmt(fmt_repr, compose(4, str("x"), nums(1, 1.0), nums(1, y), node_vec("node")), st,
              "'x';1;:y;(!node)");
    check_fmt(fmt_repr, nums(3, 1.0, -0.0, 0.5), st, "1;0;0.5");
    check_fmt(fmt_repr, NULL, st, "null");
    /* no zero special case inside object vectors */
    check_fmt(fmt_repr, compose(2, str("a"), nums(1, -0.0)), st, "'a';-0");
    check_fmt(fmt_repr, nums(2, NAN, 1.0 / 3), st, "nan;0.333333333");
    check_fmt(fmt_repr, compose(2, user_func("go"), nums(1, 2.0)), st,
              "(<Function: go>);2");
    symtab_free(st);
}

static void test_repr_strings(void **s)
{
    (void)s;
    check_fmt(fmt_repr, str("plain"), NULL, "'plain'");
    check_fmt(fmt_repr, str("it's"), NULL, "\"it's\"");
    check_fmt(fmt_repr, str("say \"hi\""), NULL, "'say \"hi\"'");
    check_fmt(fmt_repr, str("both ' and \""), NULL, "'both \\' and \"'");
    check_fmt(fmt_repr, str("back\\slash"), NULL, "'back\\\\slash'");
    check_fmt(fmt_repr, str("a\nb\rc\td"), NULL, "'a\\nb\\rc\\td'");
    check_fmt(fmt_repr, str("\x01\x7f"), NULL, "'\\x01\\x7f'");
    check_fmt(fmt_repr, str("caf\xc3\xa9"), NULL, "'caf\xc3\xa9'");
    check_fmt(fmt_repr, str("\xc2\xa0\xc2\x85"), NULL, "'\\xa0\\x85'");
    check_fmt(fmt_repr, str("\xe2\x80\xa8|\xef\xbb\xbf"), NULL, "'\\u2028|\\ufeff'");
    check_fmt(fmt_repr, str("\xf4\x8f\xbf\xbd"), NULL, "'\\U0010fffd'");
    check_fmt(fmt_repr, str("\xe2\x82\xac\xf0\x9f\x98\x80"), NULL,
              "'\xe2\x82\xac\xf0\x9f\x98\x80'");
    check_fmt(fmt_repr, str(""), NULL, "''");
}

static void test_repr_nodes(void **s)
{
    (void)s;
    SymTab *st = symtab_new();
    double sym = symtab_add(st, "sym", 3);
    /* §3.12: `!a #z #b y=1 x=2 y=3` with child `!c` */
    Node *a = node("a");
    add_tag(a, "z");
    add_tag(a, "b");
    set_attr(a, "y", nums(1, 1.0));
    set_attr(a, "x", nums(1, 2.0));
    set_attr(a, "y", nums(1, 3.0));
    Node *c = node("c");
    set_attr(c, "s", compose(2, str("q"), nums(1, sym)));
    Node *d = node("d");
    node_append(c, d);
    node_append(a, c);
    node_release(c);
    node_release(d);
    check_fmt(fmt_repr, compose(2, nums(1, 1.0), vec_node_take(a)), st,
              "1;(!a #b #z y=3 x=2\n !c s='q';:sym\n  !d)");
    symtab_free(st);
}

/* ------------------------------------------------------------------ */
/* Tree dump                                                           */
/* ------------------------------------------------------------------ */

static void test_fmt_tree(void **s)
{
    (void)s;
    SymTab *st = symtab_new();
    double sym = symtab_add(st, "sym", 3);
    /* the example of FORMATS.md §3 */
    Node *root = node("root");
    Node *window = node("window");
    add_tag(window, "b");
    add_tag(window, "a");
    add_tag(window, "a");
    set_attr(window, "size", nums(3, 2.0, 4.0, 6.0));
    set_attr(window, "title", compose(2, str("hi\tthere"), nums(1, sym)));
    Node *canvas = node("canvas");
    set_attr(canvas, "z", nums(1, 1.0 / 3));
    set_attr(canvas, "y", nums(1, 1e16));
    set_attr(canvas, "w", nums(1, 1e-5));
    set_attr(canvas, "gone", nums(1, 1.0));
    set_attr(canvas, "gone", NULL);     /* deleted again */
    node_append(window, canvas);
    Node *other = node("other");
    Node *item = node("item");
    set_attr(item, "id", nums(1, 0.0));
    set_attr(item, "v", nums(1, -0.0));
    set_attr(item, "name", compose(2, str("n"), nums(1, 0.0)));
    node_append(other, item);
    node_append(root, window);
    node_append(root, other);
    node_release(window);
    node_release(canvas);
    node_release(other);
    node_release(item);

    Buf b = BUF_INIT;
    fmt_tree(&b, root, st);
    assert_string_equal(buf_cstr(&b),
                        "!root\n"
                        " !window #a #b size=2;4;6 title=\"hi\\tthere\";:sym\n"
                        "  !canvas z=0.3333333333333333 y=1e+16 w=1e-05\n"
                        " !other\n"
                        "  !item id=0 v=0 name=\"n\";0\n");
    buf_free(&b);

    /* nodes.tree: a node-valued attribute and a bare root */
    Node *w = node("w");
    set_attr(w, "v", compose(2, node_vec("a"), node_vec("b")));
    Node *r2 = node("root");
    node_append(r2, w);
    node_release(w);
    fmt_tree(&b, r2, st);
    assert_string_equal(buf_cstr(&b), "!root\n !w v=(!a);(!b)\n");
    buf_reset(&b);
    Node *empty = node("root");
    fmt_tree(&b, empty, st);
    assert_string_equal(buf_cstr(&b), "!root\n");
    buf_free(&b);
    node_release(empty);
    node_release(r2);
    node_release(root);
    symtab_free(st);
}

static void test_fmt_tree_deep(void **s)
{
    (void)s;
    /* a deep chain is written without deep C recursion */
    enum { DEPTH = 3000 };
    Node *leaf = node("n");
    for (int i = 0; i < DEPTH; i++) {
        Node *parent = node("n");
        node_append(parent, leaf);
        node_release(leaf);
        leaf = parent;
    }
    Buf b = BUF_INIT;
    fmt_tree(&b, leaf, NULL);
    /* lines of 2 + depth bytes for depth 0..DEPTH */
    size_t want = 0;
    for (size_t d = 0; d <= DEPTH; d++)
        want += d + 3;
    assert_int_equal(b.len, want);
    buf_free(&b);
    node_release(leaf);
}

/* ------------------------------------------------------------------ */
/* State dump                                                          */
/* ------------------------------------------------------------------ */

static void put(StateDict *sd, Vec *key, Vec *value)
{
    state_set(sd, key, value);
    vec_release(key);
    vec_release(value);
}

static void test_fmt_state_dump(void **s)
{
    (void)s;
    SymTab *st = symtab_new();
    double box = symtab_add(st, "box", 3);
    double vel = symtab_add(st, "velocity", 8);
    double dish = symtab_add(st, "dish", 4);
    StateDict *sd = state_new();
    put(sd, nums(2, box, 1.0), nums(2, -5.008663227767952, 77.93580382577103));
    put(sd, nums(3, box, 1.0, vel), nums(1, -8.901815295556256));
    put(sd, nums(3, box, 19.0, vel), nums(2, 33.18110192538167, 0.880930470592179));
    put(sd, nums(1, box), nums(1, 0.0));
    put(sd, nums(2, box, 10.0), nums(1, 0.2089224327728833));
    put(sd, nums(3, dish, 10.0, vel), nums(2, 0.708631961664684, -0.01348675833188967));
    put(sd, str("_counter"), nums(1, 12.0));                   /* left out */
    put(sd, compose(2, str("_x"), nums(1, 1.0)), str("kept")); /* not a single string */
    put(sd, str("beat"), nums(1, 4e-06));
    put(sd, str("a\tb"), compose(2, str("v"), node_vec("n")));
    put(sd, nums(1, 0.0), str("pos"));  /* 0 and -0 are different keys with */
    put(sd, nums(1, -0.0), str("neg")); /* the same text: ordered by value */

    Buf b = BUF_INIT;
    fmt_state_dump(&b, sd, 29, 0.4833333333333333, st);
    assert_string_equal(buf_cstr(&b),
                        "# frame 29 time 0.4833333333333333\n"
                        "\"_x\";1 = \"kept\"\n"
                        "\"a\\tb\" = \"v\";(!n)\n"
                        "\"beat\" = 4e-06\n"
                        "0 = \"neg\"\n"
                        "0 = \"pos\"\n"
                        ":box = 0\n"
                        ":box;1 = -5.008663227767952;77.93580382577103\n"
                        ":box;10 = 0.2089224327728833\n"
                        ":box;19;:velocity = 33.18110192538167;0.880930470592179\n"
                        ":box;1;:velocity = -8.901815295556256\n"
                        ":dish;10;:velocity = 0.708631961664684;-0.01348675833188967\n");
    buf_reset(&b);

    /* an empty dictionary: the header only; time 0 prints as 0 */
    StateDict *empty = state_new();
    fmt_state_dump(&b, empty, 0, 0.0, st);
    assert_string_equal(buf_cstr(&b), "# frame 0 time 0\n");
    buf_free(&b);
    state_free(empty);
    state_free(sd);
    symtab_free(st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_buf),
        cmocka_unit_test(test_fmt_double_spec),
        cmocka_unit_test(test_fmt_double_edges),
        cmocka_unit_test(test_fmt_double_integers),
        cmocka_unit_test(test_fmt_double_routes),
        cmocka_unit_test(test_fmt_g9),
        cmocka_unit_test(test_fmt_value_numbers),
        cmocka_unit_test(test_fmt_value_strings),
        cmocka_unit_test(test_fmt_value_objects),
        cmocka_unit_test(test_fmt_str),
        cmocka_unit_test(test_fmt_repr),
        cmocka_unit_test(test_repr_strings),
        cmocka_unit_test(test_repr_nodes),
        cmocka_unit_test(test_fmt_tree),
        cmocka_unit_test(test_fmt_tree_deep),
        cmocka_unit_test(test_fmt_state_dump),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
