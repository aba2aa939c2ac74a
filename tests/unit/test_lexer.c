/* test_lexer.c: unit tests of the re2c lexer (grammar/lexer.re) and the
 * indentation filter (lib/syntax/indent.c): token kinds and spans, number, time
 * code and string conversions, comments, continuations, hashbang, keywords,
 * and NL -> NL/INDENT/DEDENT on token arrays and on lexed text
 * (LANGUAGE.md §1, test vectors §7.1).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "lexer.h"

/* {=====================================================================
 * Helpers
 * ===================================================================== */

#define MAX_TOKENS 64

typedef struct Lexed {
    Token t[MAX_TOKENS];
    int n;
    Lexer lx;
} Lexed;

/* Lex all of [src] (up to TK_END, an error, or MAX_TOKENS tokens). */
static void lex_all(Lexed *out, const char *src)
{
    lex_init(&out->lx, src, strlen(src));
    out->n = 0;
    while (out->n < MAX_TOKENS) {
        int k = lex_next(&out->lx, &out->t[out->n++]);
        if (k == TK_END || k == TK_FLP_error)
            break;
    }
}

static void lexed_free(Lexed *l)
{
    for (int i = 0; i < l->n; i++)
        token_clear(&l->t[i]);
    lex_free(&l->lx);
}

/* The kinds of the tokens of [src], ending with TK_END or TK_FLP_error,
 * compared with the list after [src] (terminated by -1). */
static void check_kinds(const char *src, ...)
{
    Lexed l;
    lex_all(&l, src);
    va_list ap;
    va_start(ap, src);
    int i = 0;
    for (;; i++) {
        int want = va_arg(ap, int);
        if (want == -1)
            break;
        if (i >= l.n || l.t[i].kind != want) {
            print_error("source %s: token %d is %d, expected %d\n", src, i,
                        i < l.n ? l.t[i].kind : -1, want);
            fail();
        }
    }
    va_end(ap);
    assert_int_equal(i, l.n);
    lexed_free(&l);
}

/* The single NUMBER/TIMECODE value of [src] (one token then NL). */
static double value_of(const char *src, int kind)
{
    Lexed l;
    lex_all(&l, src);
    assert_int_equal(l.t[0].kind, kind);
    assert_int_equal(l.t[1].kind, TK_NL);
    double v = l.t[0].num;
    lexed_free(&l);
    return v;
}

static double number(const char *src) { return value_of(src, TK_NUMBER); }
static double timecode(const char *src) { return value_of(src, TK_TIMECODE); }

/* The decoded text of the single STRING token of [src]. */
static void check_string(const char *src, const char *want, size_t want_len)
{
    Lexed l;
    lex_all(&l, src);
    assert_int_equal(l.t[0].kind, TK_STRING);
    assert_non_null(l.t[0].str);
    assert_int_equal(l.t[0].str->len, want_len);
    assert_memory_equal(l.t[0].str->bytes, want, want_len);
    lexed_free(&l);
}

/* The first error message of lexing [src]. */
static void check_error(const char *src, const char *message)
{
    Lexed l;
    lex_all(&l, src);
    assert_int_equal(l.t[l.n - 1].kind, TK_FLP_error);
    assert_string_equal(lex_message(&l.lx), message);
    lexed_free(&l);
}

/* }===================================================================== */

/* {=====================================================================
 * Tokens and positions
 * ===================================================================== */

static void test_spans(void **state)
{
    (void)state;
    Lexed l;
    lex_all(&l, "let x' = 1.5\n!foo #bar :baz\n");
    static const struct { int kind; unsigned start, end; } want[] = {
        {TK_LET, 0, 3}, {TK_NAME, 4, 6}, {TK_ASSIGN, 7, 8},
        {TK_NUMBER, 9, 12}, {TK_NL, 12, 13}, {TK_NODE, 13, 17},
        {TK_TAG, 18, 22}, {TK_SYMBOL, 23, 27}, {TK_NL, 27, 28},
        {TK_END, 27, 27},
    };
    assert_int_equal(l.n, (int)(sizeof want / sizeof want[0]));
    for (int i = 0; i < l.n; i++) {
        assert_int_equal(l.t[i].kind, want[i].kind);
        assert_int_equal(l.t[i].start, want[i].start);
        assert_int_equal(l.t[i].end, want[i].end);
    }
    Token t;
    assert_int_equal(lex_next(&l.lx, &t), TK_YYEOF);
    assert_int_equal(lex_next(&l.lx, &t), TK_YYEOF);
    lexed_free(&l);
}

static void test_operators(void **state)
{
    (void)state;
    check_kinds("( ) [ ] ; , = | $ @ .. + - * / // % ** == != < > <= >= <<",
                TK_LPAREN, TK_RPAREN, TK_LBRACKET, TK_RBRACKET, TK_SEMI,
                TK_COMMA, TK_ASSIGN, TK_PIPE, TK_DOLLAR, TK_AT, TK_DOTDOT,
                TK_PLUS, TK_MINUS, TK_STAR, TK_SLASH, TK_DSLASH, TK_PERCENT,
                TK_POW, TK_EQ, TK_NE, TK_LT, TK_GT, TK_LE, TK_GE, TK_APPEND,
                TK_NL, TK_END, -1);
    /* longest match without spaces */
    check_kinds("a**b//c<<d<=e!=f", TK_NAME, TK_POW, TK_NAME, TK_DSLASH,
                TK_NAME, TK_APPEND, TK_NAME, TK_LE, TK_NAME, TK_NE, TK_NAME,
                TK_NL, TK_END, -1);
    check_kinds("..5", TK_DOTDOT, TK_NUMBER, TK_NL, TK_END, -1);
    check_kinds("1..5|.5", TK_NUMBER, TK_DOTDOT, TK_NUMBER, TK_PIPE,
                TK_NUMBER, TK_NL, TK_END, -1);
}

static void test_names(void **state)
{
    (void)state;
    check_kinds("café x' x''' _ \xe6\xb0\xb4 Hafnarfj\xc3\xb6r\xc3\xb0ur x2",
                TK_NAME, TK_NAME, TK_NAME, TK_NAME, TK_NAME, TK_NAME,
                TK_NAME, TK_NL, TK_END, -1);
    /* a prime only at the end: x'y is x' then y */
    Lexed l;
    lex_all(&l, "x'y");
    assert_int_equal(l.t[0].kind, TK_NAME);
    assert_int_equal(l.t[0].end, 2);
    assert_int_equal(l.t[1].kind, TK_NAME);
    lexed_free(&l);
    /* 2x is a number and a name */
    check_kinds("2x", TK_NUMBER, TK_NAME, TK_NL, TK_END, -1);
}

static void test_nodes_tags_symbols(void **state)
{
    (void)state;
    check_kinds("!foo' #_b :c\xc3\xa9", TK_NODE, TK_TAG, TK_SYMBOL, TK_NL,
                TK_END, -1);
    /* '!=' is the operator; '!' before a non-letter is an error */
    check_kinds("a!=b", TK_NAME, TK_NE, TK_NAME, TK_NL, TK_END, -1);
    check_error("! x", "unexpected character '!'");
    check_error("# x", "unexpected character '#'");
    check_error(": x", "unexpected character ':'");
}

static void test_keywords(void **state)
{
    (void)state;
    check_kinds("let stable func import from for in if elif else where or xor and not",
                TK_LET, TK_STABLE, TK_FUNC, TK_IMPORT, TK_FROM, TK_FOR, TK_IN,
                TK_IF, TK_ELIF, TK_ELSE, TK_WHERE, TK_OR, TK_XOR, TK_AND,
                TK_NOT, TK_NL, TK_END, -1);
    check_kinds("lets let' Let _let", TK_NAME, TK_NAME, TK_NAME, TK_NAME,
                TK_NL, TK_END, -1);
    assert_int_equal(lex_keyword("where", 5), TK_WHERE);
    assert_int_equal(lex_keyword("wher", 4), -1);
}

static void test_directives(void **state)
{
    (void)state;
    /* %pragma / %include at the start of a statement ... */
    check_kinds("%pragma tempo 110\n%include 'x'\n", TK_PRAGMA, TK_NAME,
                TK_NUMBER, TK_NL, TK_INCLUDE, TK_STRING, TK_NL, TK_END, -1);
    check_kinds("!a << %include 'x'", TK_NODE, TK_APPEND, TK_INCLUDE,
                TK_STRING, TK_NL, TK_END, -1);
    /* ... elsewhere '%' and a name (modulo) */
    check_kinds("a %include", TK_NAME, TK_PERCENT, TK_NAME, TK_NL, TK_END, -1);
    check_kinds("a%pragma", TK_NAME, TK_PERCENT, TK_NAME, TK_NL, TK_END, -1);
}

static void test_hashbang(void **state)
{
    (void)state;
    Lexed l;
    lex_all(&l, "#!/usr/bin/env flitter\n  x\n");
    assert_int_equal(l.t[0].kind, TK_HASHBANG);
    assert_int_equal(l.t[0].start, 0);
    assert_int_equal(l.t[0].end, 23);
    assert_int_equal(l.t[1].kind, TK_NAME);     /* no NL: not measured */
    assert_int_equal(l.t[1].start, 25);
    lexed_free(&l);
    check_kinds("#!x\r\n%pragma fps 30", TK_HASHBANG, TK_PRAGMA, TK_NAME,
                TK_NUMBER, TK_NL, TK_END, -1);
}

static void test_comments_and_newlines(void **state)
{
    (void)state;
    Lexed l;
    /* one NL for line ends, blank lines and comment-only lines; its
     * indentation is that of the next real line */
    lex_all(&l, "x -- c\n\n   -- d\n\t\n  y\r\nz");
    assert_int_equal(l.t[0].kind, TK_NAME);
    assert_int_equal(l.t[1].kind, TK_NL);
    assert_int_equal(l.t[1].start, 2);
    assert_int_equal(l.t[1].indent, 2);
    assert_int_equal(l.t[2].kind, TK_NAME);
    assert_int_equal(l.t[3].kind, TK_NL);
    assert_int_equal(l.t[3].indent, 0);
    assert_int_equal(l.t[4].kind, TK_NAME);
    assert_int_equal(l.t[5].kind, TK_NL);        /* the appended '\n' */
    assert_int_equal(l.t[6].kind, TK_END);
    assert_int_equal(l.t[6].start, 24);          /* end of the last token */
    lexed_free(&l);
    /* x--1 is x then a comment */
    check_kinds("x--1", TK_NAME, TK_NL, TK_END, -1);
    check_kinds("x - -1", TK_NAME, TK_MINUS, TK_MINUS, TK_NUMBER, TK_NL,
                TK_END, -1);
    /* tabs count 8 columns wherever they are */
    lex_all(&l, "a\n\t b\n \tc\n");
    assert_int_equal(l.t[1].indent, 9);
    assert_int_equal(l.t[3].indent, 9);
    lexed_free(&l);
    /* a lone CR is not a line end */
    check_error("a\rb", "unexpected character '\\x0d'");
}

static void test_continuation(void **state)
{
    (void)state;
    check_kinds("x \\\n    + 1", TK_NAME, TK_PLUS, TK_NUMBER, TK_NL, TK_END, -1);
    /* only backslash + LF */
    check_error("x \\ \n", "unexpected character '\\'");
    check_error("x \\\r\n", "unexpected character '\\'");
}

/* }===================================================================== */

/* {=====================================================================
 * Conversions
 * ===================================================================== */

static void test_numbers(void **state)
{
    (void)state;
    assert_true(number("10m") == 0.01);
    assert_true(number("30deg") == 0.08333333333333334);
    assert_true(number("30deg") != 30.0 / 360);
    assert_true(number("90deg") == 0.25);
    assert_true(number("90\xc2\xb0") == 0.25);
    assert_true(number("1_000k") == 1000000.0);
    assert_true(number("1.1k") == 1100.0);
    assert_true(number("5\xc2\xb5") == 5 * 1e-6);
    assert_true(number("5u") == 5 * 1e-6);
    assert_true(number("2p") == 2 * 1e-12);
    assert_true(number("3n") == 3 * 1e-9);
    assert_true(number("3n") != 3e-9);          /* a multiplication */
    assert_true(number("4M") == 4e6);
    assert_true(number("4G") == 4e9);
    assert_true(number("4T") == 4e12);
    assert_true(number(".5") == 0.5);
    assert_true(number("1.234_5") == 1.2345);
    assert_true(number("1e1_0") == 1e10);
    assert_true(number("2.5E-3") == 0.0025);
    assert_true(number("1e3m") == 1.0);
    assert_true(isinf(number("1e400")));
    assert_true(number("1e-400") == 0.0);
    assert_true(number("0.1") == 0.1);
    /* greedy: 2max is 2m then ax; 3d is 3 then d; 10deg one token */
    check_kinds("2max", TK_NUMBER, TK_NAME, TK_NL, TK_END, -1);
    check_kinds("10degrees", TK_NUMBER, TK_NAME, TK_NL, TK_END, -1);
    check_kinds("10deg", TK_NUMBER, TK_NL, TK_END, -1);
    /* 1. is not a number */
    check_kinds("1.", TK_NUMBER, TK_FLP_error, -1);
    /* badly placed underscores fail the conversion */
    check_error("1_", "invalid number '1_'");
    check_error("1__0", "invalid number '1__0'");
    check_error("1_.5", "invalid number '1_.5'");
    check_error("1_e3", "invalid number '1_e3'");
    check_error("1_k", "invalid number '1_k'");
}

static void test_timecodes(void **state)
{
    (void)state;
    assert_true(timecode("1:30") == 90.0);
    assert_true(timecode("001:01:01.100") == 3661.1);
    assert_true(timecode("02:05.3") == 125.3);
    assert_true(timecode("1:1:1") == 3661.0);
    assert_true(timecode("0:0") == 0.0);
    /* same order of operations as the reference: (s + 60m) + 3600h */
    assert_true(timecode("1:00:00.1") == (0.1 + 0.0) + 3600.0);
    /* 3600 * hours is exact before its one rounding */
    assert_true(timecode("99999999999999999:0:0") == 359999999999999996400.0);
    /* 0:60 is 0:6 then 0; 60:00 is 60 then a stray ':' */
    check_kinds("0:60", TK_TIMECODE, TK_NUMBER, TK_NL, TK_END, -1);
    check_kinds("60:00", TK_NUMBER, TK_FLP_error, -1);
    check_kinds("0:0:0:0", TK_TIMECODE, TK_FLP_error, -1);
    /* time codes take no exponent or suffix */
    check_kinds("1:30e3", TK_TIMECODE, TK_NAME, TK_NL, TK_END, -1);
}

static void test_strings(void **state)
{
    (void)state;
    check_string("\"\\x41\\u00e9\"", "A\xc3\xa9", 3);
    check_string("'a\\'b'", "a'b", 3);
    check_string("\"a\\\"b\"", "a\"b", 3);
    check_string("''", "", 0);
    check_string("'\\\\\\n\\t\\r\\a\\b\\f\\v'", "\\\n\t\r\a\b\f\v", 8);
    check_string("'\\101\\0\\7x\\1234'", "A\0\axS4", 6);
    check_string("'\\5234'", "\xc5\x93" "4", 3);
    check_string("'\\q\\%'", "\\q\\%", 4);
    check_string("'\\U0001F600'", "\xf0\x9f\x98\x80", 4);
    check_string("'caf\xc3\xa9'", "caf\xc3\xa9", 5);
    check_string("'''a\nb''c'd'''", "a\nb''c'd", 8);
    check_string("\"\"\"x\"\"y\"\"\"", "x\"\"y", 4);
    check_string("'''a\r\nb'''", "a\nb", 3);
    check_string("'''a\\\r\nb'''", "ab", 2);   /* \ CR LF: continuation */
    check_kinds("'''a\\\nb'''", TK_STRING, TK_FLP_error, -1);  /* '' then ' */
    /* escaped quote does not end the string */
    check_kinds("'\\'' x", TK_STRING, TK_NAME, TK_NL, TK_END, -1);
    /* a triple-quoted string ends at the first run of three quotes */
    check_kinds("'''a''''", TK_STRING, TK_FLP_error, -1);
    check_error("\"abc", "unterminated string");
    check_error("'ab\ncd'", "unterminated string");
    check_error("'ab\\\ncd'", "unterminated string");
    check_error("'\\x4'", "truncated \\xXX escape in string");
    check_error("'\\u12g4'", "truncated \\uXXXX escape in string");
    check_error("'\\U00110000'", "illegal Unicode character in \\U escape");
    check_error("'\\N{BULLET}'", "unsupported \\N{...} escape in string");
}

static void test_bad_input(void **state)
{
    (void)state;
    check_error("a & b", "unexpected character '&'");
    check_error("a \xe2\x82\xac", "unexpected character '\xe2\x82\xac'");
    /* an embedded NUL is an error, not the end */
    Lexed l;
    lex_init(&l.lx, "a\0b", 3);
    Token t;
    assert_int_equal(lex_next(&l.lx, &t), TK_NAME);
    assert_int_equal(lex_next(&l.lx, &t), TK_FLP_error);
    assert_int_equal(t.start, 1);
    l.n = 0;
    lexed_free(&l);
    /* the empty file is one newline */
    check_kinds("", TK_NL, TK_END, -1);
}

/* }===================================================================== */

/* {=====================================================================
 * Indentation filter
 * ===================================================================== */

#define T(k) {.kind = (k)}
#define NLI(n) {.kind = TK_NL, .indent = (n)}

/* Run [n] tokens through a fresh filter; compare the output kinds with
 * [want] (terminated by -1). [fail_at] >= 0: feeding token [fail_at] must
 * fail. */
static void check_filter(const Token *in, int n, const int *want, int fail_at)
{
    Indenter ind;
    indent_init(&ind);
    int out = 0;
    for (int i = 0; i < n; i++) {
        Token t = in[i];
        bool ok = indent_feed(&ind, &t);
        if (i == fail_at) {
            assert_false(ok);
            break;
        }
        assert_true(ok);
        Token o;
        while (indent_pop(&ind, &o)) {
            if (want[out] == -1 || o.kind != want[out]) {
                print_error("output token %d is %d, expected %d\n", out,
                            o.kind, want[out]);
                fail();
            }
            out++;
        }
    }
    assert_int_equal(want[out], -1);
    indent_free(&ind);
}

static void test_indent_blocks(void **state)
{
    (void)state;
    const Token in[] = {
        T(TK_NAME), NLI(4), T(TK_NAME), NLI(8), T(TK_NAME), NLI(4),
        T(TK_NAME), NLI(0), T(TK_NAME), NLI(8), T(TK_NAME), NLI(0), T(TK_END),
    };
    const int want[] = {
        TK_NAME, TK_NL, TK_INDENT, TK_NAME, TK_NL, TK_INDENT, TK_NAME,
        TK_NL, TK_DEDENT, TK_NAME, TK_NL, TK_DEDENT, TK_NAME, TK_NL,
        TK_INDENT, TK_NAME, TK_NL, TK_DEDENT, TK_END, -1,
    };
    check_filter(in, (int)(sizeof in / sizeof in[0]), want, -1);
}

static void test_indent_end_closes(void **state)
{
    (void)state;
    const Token in[] = {
        T(TK_NAME), NLI(2), T(TK_NAME), NLI(5), T(TK_NAME), T(TK_END),
    };
    const int want[] = {
        TK_NAME, TK_NL, TK_INDENT, TK_NAME, TK_NL, TK_INDENT, TK_NAME,
        TK_DEDENT, TK_DEDENT, TK_END, -1,
    };
    check_filter(in, (int)(sizeof in / sizeof in[0]), want, -1);
    /* two levels closed by one newline */
    const Token in2[] = {
        T(TK_NAME), NLI(2), T(TK_NAME), NLI(5), T(TK_NAME), NLI(0), T(TK_END),
    };
    const int want2[] = {
        TK_NAME, TK_NL, TK_INDENT, TK_NAME, TK_NL, TK_INDENT, TK_NAME,
        TK_NL, TK_DEDENT, TK_DEDENT, TK_END, -1,
    };
    check_filter(in2, (int)(sizeof in2 / sizeof in2[0]), want2, -1);
}

static void test_indent_bad_dedent(void **state)
{
    (void)state;
    const Token in[] = {
        T(TK_NAME), NLI(4), T(TK_NAME), NLI(2), T(TK_NAME), T(TK_END),
    };
    const int want[] = {TK_NAME, TK_NL, TK_INDENT, TK_NAME, -1};
    check_filter(in, (int)(sizeof in / sizeof in[0]), want, 3);
}

static void test_indent_parens(void **state)
{
    (void)state;
    /* newlines inside ( ) vanish, also nested; [ ] do not hide them */
    const Token in[] = {
        T(TK_NAME), T(TK_LPAREN), NLI(4), T(TK_LPAREN), NLI(0), T(TK_RPAREN),
        NLI(9), T(TK_RPAREN), NLI(0), T(TK_LBRACKET), NLI(4), T(TK_RBRACKET),
        NLI(0), T(TK_END),
    };
    const int want[] = {
        TK_NAME, TK_LPAREN, TK_LPAREN, TK_RPAREN, TK_RPAREN, TK_NL,
        TK_LBRACKET, TK_NL, TK_INDENT, TK_RBRACKET, TK_NL, TK_DEDENT,
        TK_END, -1,
    };
    check_filter(in, (int)(sizeof in / sizeof in[0]), want, -1);
    /* a stray ')' does not make the depth negative */
    const Token in2[] = {T(TK_RPAREN), NLI(0), T(TK_END)};
    const int want2[] = {TK_RPAREN, TK_NL, TK_END, -1};
    check_filter(in2, 3, want2, -1);
}

/* Lexer then filter on real text: tabs, comments, blank lines. */
static void test_indent_text(void **state)
{
    (void)state;
    const char *src = "a\n\tb\n        c\n  -- comment\n\n\t d\ne\n";
    const int want[] = {
        TK_NAME, TK_NL, TK_INDENT, TK_NAME, TK_NL, TK_NAME, TK_NL,
        TK_INDENT, TK_NAME, TK_NL, TK_DEDENT, TK_DEDENT, TK_NAME, TK_NL,
        TK_END, -1,
    };
    Lexer lx;
    Indenter ind;
    lex_init(&lx, src, strlen(src));
    indent_init(&ind);
    int out = 0;
    for (;;) {
        Token t, o;
        int k = lex_next(&lx, &t);
        assert_true(k != TK_FLP_error);
        assert_true(indent_feed(&ind, &t));
        while (indent_pop(&ind, &o))
            assert_int_equal(o.kind, want[out++]);
        if (k == TK_END)
            break;
    }
    assert_int_equal(want[out], -1);
    indent_free(&ind);
    lex_free(&lx);
}

/* }===================================================================== */

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spans),
        cmocka_unit_test(test_operators),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_nodes_tags_symbols),
        cmocka_unit_test(test_keywords),
        cmocka_unit_test(test_directives),
        cmocka_unit_test(test_hashbang),
        cmocka_unit_test(test_comments_and_newlines),
        cmocka_unit_test(test_continuation),
        cmocka_unit_test(test_numbers),
        cmocka_unit_test(test_timecodes),
        cmocka_unit_test(test_strings),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_indent_blocks),
        cmocka_unit_test(test_indent_end_closes),
        cmocka_unit_test(test_indent_bad_dedent),
        cmocka_unit_test(test_indent_parens),
        cmocka_unit_test(test_indent_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
