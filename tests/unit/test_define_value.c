/* test_define_value.c: the value a script receives for `-D NAME=VALUE`
 * (lib/io/define_value.c), part by part as Flitter's `keyvalue` reads it:
 * Python's float() with an optional SI or angle suffix, then a time code,
 * else the text (issue 59). Numbers are compared bit for bit with the
 * value each rule gives by hand. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "buf.h"
#include "define_value.h"
#include "format.h"
#include "value.h"

/* The value of [text] as value text (FORMATS.md §1), e.g. `-1;"a"`. */
static void check_text(const char *text, const char *want)
{
    SymTab *st = symtab_new();
    Vec *v = define_value(st, text, strlen(text));
    Buf b = BUF_INIT;
    fmt_value(&b, v, st);
    if (strcmp(buf_cstr(&b), want) != 0)
        fail_msg("define_value(\"%s\") = %s, want %s", text, buf_cstr(&b), want);
    buf_free(&b);
    vec_release(v);
    symtab_free(st);
}

/* [text] is one number, bit for bit [want]. */
static void check_number(const char *text, double want)
{
    SymTab *st = symtab_new();
    Vec *v = define_value(st, text, strlen(text));
    if (!vec_is_scalar(v)) fail_msg("define_value(\"%s\") is not one number", text);
    double got = vec_cnums(v)[0];
    if (memcmp(&got, &want, sizeof got) != 0)
        fail_msg("define_value(\"%s\") = %.17g, want %.17g", text, got, want);
    vec_release(v);
    symtab_free(st);
}

static void signs_and_python_floats(void **unused)
{
    (void)unused;
    check_number("-3", -3.0);
    check_number("+2.5", 2.5);
    check_number("-0.5", -0.5);
    check_number("-0", -0.0);
    check_number(".5", 0.5);
    check_number("5.", 5.0);
    check_number("1e5", 100000.0);
    check_number("1E+0_5", 100000.0);      /* `_` between digits, exponent too */
    check_number("1_000", 1000.0);
    check_number(" 7 ", 7.0);              /* blanks around */
    check_number("\t8\n", 8.0);
    check_number("inf", INFINITY);
    check_number("-iNf", -INFINITY);
    check_number("Infinity", INFINITY);
    check_number("1e400", INFINITY);
    check_number("0.1", 0.1);
    check_number("9007199254740993", 9007199254740992.0);   /* rounded to even */
    SymTab *st = symtab_new();
    Vec *v = define_value(st, "nan", 3);
    assert_true(vec_is_scalar(v) && isnan(vec_cnums(v)[0]));
    vec_release(v);
    symtab_free(st);
}

static void suffixes_multiply(void **unused)
{
    (void)unused;
    check_number("-10k", -10.0 * 1e3);
    check_number("1 k", 1.0 * 1e3);
    check_number("5m", 5.0 * 1e-3);
    check_number("1.5e-3m", 1.5e-3 * 1e-3);
    check_number("2M", 2.0 * 1e6);
    check_number("3G", 3.0 * 1e9);
    check_number("4T", 4.0 * 1e12);
    check_number("7p", 7.0 * 1e-12);
    check_number("8n", 8.0 * 1e-9);
    check_number("5u", 5.0 * 1e-6);
    check_number("5\xc2\xb5", 5.0 * 1e-6);
    check_number("5deg", 5.0 * (1.0 / 360));
    check_number("3\xc2\xb0", 3.0 * (1.0 / 360));
    /* the first suffix decides: "ok" is not o times 1000 but text */
    check_text("ok", "\"ok\"");
    /* "nan" ends in the suffix n, fails there, and reads as a time code */
    SymTab *st = symtab_new();
    Vec *v = define_value(st, "nan m", 5);
    assert_true(vec_is_scalar(v) && isnan(vec_cnums(v)[0]));
    vec_release(v);
    symtab_free(st);
}

static void time_codes(void **unused)
{
    (void)unused;
    check_number("1:30", 30.0 + 60 * 1.0);
    check_number("1:2:3.5", 3.5 + 60 * 2.0 + 3600 * 1.0);
    check_number("-1:30", 30.0 + 60 * -1.0);
    check_number("1:60", 60.0 + 60 * 1.0);   /* no range check on seconds */
    check_number("12:34.5e1", 34.5e1 + 60 * 12.0);
    check_number(" 1 : 2 ", 2.0 + 60 * 1.0);
    check_number("+1:+1:+1", 1.0 + 60 * 1.0 + 3600 * 1.0);
    check_number("1:00:00", 3600.0);
    check_text("1:2:3:4", "\"1:2:3:4\"");      /* four parts: text */
    check_text("1.5:2", "\"1.5:2\"");          /* minutes must be whole */
}

static void symbols_strings_and_parts(void **unused)
{
    (void)unused;
    check_text("", "\"\"");                    /* the empty string, not null */
    check_text("abc", "\"abc\"");
    check_text(":sym", ":sym");
    check_text(":", ":");
    check_text("-1;2", "-1;2");
    check_text("a;", "\"a\";\"\"");
    check_text("1;:x;two", "1;:x;\"two\"");
    check_text("1__0", "\"1__0\"");
    check_text("_1", "\"_1\"");
    check_text("1_", "\"1_\"");
    check_text("1._5", "\"1._5\"");
    check_text(".", "\".\"");
    check_text("1e", "\"1e\"");
    check_text("e5", "\"e5\"");
    check_text("--1", "\"--1\"");
    check_text("0x10", "\"0x10\"");
    check_text("1,5", "\"1,5\"");
    check_text(" x ", "\" x \"");             /* text keeps its blanks */
}

static void define_float_alone(void **unused)
{
    (void)unused;
    double x = 42;
    assert_false(define_float("", 0, &x));
    assert_false(define_float("  ", 2, &x));
    assert_false(define_float("+", 1, &x));
    assert_true(x == 42);
    assert_true(define_float("-2e-3", 5, &x) && x == -2e-3);
    /* only [len] bytes are read */
    assert_true(define_float("12345", 2, &x) && x == 12.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(signs_and_python_floats),
        cmocka_unit_test(suffixes_multiply),
        cmocka_unit_test(time_codes),
        cmocka_unit_test(symbols_strings_and_parts),
        cmocka_unit_test(define_float_alone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
