/* test_vectors.c: the test vectors of LANGUAGE.md §7.1-7.5. Each expression
 * is evaluated in a fresh runtime as `debug(EXPR)`, so the comparison uses
 * the repr of §3.14 exactly as the table gives it. Exact doubles that the
 * table states in full are checked through value text (FORMATS.md §1). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "runtime.h"

typedef struct Vector {
    int number;             /* row number in §7 */
    const char *expr;       /* Flitter expression */
    const char *repr;       /* expected debug() repr, or NULL */
    const char *text;       /* expected value text, or NULL */
} Vector;

static const Vector vectors[] = {
    {1, "10m", "0.01", "0.01"},
    {2, "90deg;90°", "0.25;0.25", NULL},
    {3, "30deg", "0.0833333333", "0.08333333333333334"},
    {4, "1_000k", "1000000", NULL},
    {5, "1:30", "90", NULL},
    {6, "001:01:01.100", "3661.1", NULL},
    {7, "\"\\x41\\u00e9\"", "'Aé'", NULL},
    {8, ":foo", ":foo", ":foo"},
    {9, "\"x\";1;:y;!node", "'x';1;:y;(!node)", NULL},
    {9, "concat(\"x\";1;:y;!node)", "'x1ynode'", NULL},
    {9, "len(\"x\";1;:y;!node)", "4", NULL},
    {10, "true;false;null", "1;0", NULL},
    {11, "2**3**2", "64", NULL},
    {12, "-2**2", "-4", NULL},
    {15, "(1;2;3;4) + (1;-1)", "2;1;4;3", NULL},
    {16, "(1;2;3)*(2;3)", "2;6;6", NULL},
    {17, "(-7 // 2);(-7 % 2);(7 % -2)", "-4;1;-1", NULL},
    {18, "(5 % 0);(1/0);(-1/0);(0/0)", "nan;inf;-inf;nan", NULL},
    {19, "(-8)**(1/3)", "nan", NULL},
    {20, "\"a\" + 1", "null", NULL},
    {21, "0.1+0.2", "0.3", "0.30000000000000004"},
    {22, "1/3", "0.333333333", NULL},
    {23, "((1;2) == (1;2));((1;2) != (1;2))", "1;0", NULL},
    {23, "1;2 == 1;2", "1;0;2", NULL},
    {24, "((1;2) < (1;2;0));(null < 0);(1 < null)", "1;1;0", NULL},
    {25, "\"a\" < 1", "null", NULL},
    {25, "\"abc\" < \"abd\"", "1", NULL},
    {26, "(nan == nan);(nan > 1)", "1;1", NULL},
    {27, "(0 == null);(null == null);(!a == !a)", "0;1;1", NULL},
    {28, "(3 in (1;2;3;4));((2;3) in ..5);(null in 5)", "1;1;1", NULL},
    {29, "(not (0;0));(\"\" or 5);(0 and 7)", "1;5;0", NULL},
    {30, "(1 xor 0);(1 xor 2);(0 xor 0)", "1;0;0", NULL},
    {31, "(5 if 0);(1 if 1)", "1", NULL},
    {32, "-0", "0", NULL},
    {32, "concat(-0)", "'-0'", NULL},
    {32, "0.5*-0", "0", NULL},
    {33, "..5", "0;1;2;3;4", NULL},
    {34, "1..0|-0.25", "1;0.75;0.5;0.25", NULL},
    {35, "0.1..0.5|0.1", "0.1;0.2;0.3;0.4", "0.1;0.2;0.30000000000000004;0.4"},
    {36, "(..2.5);(0..1|0);(..0)", "0;1;2", NULL},
    {37, "(10;20;30)[-1];(10;20;30)[1.7]", "30;20", NULL},
    {38, "5[..3]", "5;5;5", NULL},
    {39, "(1;2;3)[null]", "null", NULL},
    {40, "hypot(3;4);hypot(3, 4);hypot()", "5;5", NULL},
    {41, "sin(0.25);cos(0.5);sin(0.5)", "1;-1;0", NULL},
    {41, "concat(sin(0.5))", "'-0'", NULL},
    {42, "cos(1/3);sin(0.125)", "-0.5;0.707106781", NULL},
    {43, "polar(0.25)", "0;1", NULL},
    {43, "concat(polar(0.25)[0])", "'-0'", NULL},
    {44, "angle(0;1);angle(1, 1);length(3;4;6;8)", "0.25;0.125;5;10", NULL},
    {45, "round(2.5);round(-2.5);round(1.2345, 2);round(0.125, 2)", "3;-3;1.23;0.13", NULL},
    {47, "sum(1;2;3;4, 2);sum(1;2;3;4;5, 2);sum(1;2;3, 0.5)", "4;6;9;6", NULL},
    {48, "mean(1;2;3);mean(null);mean(1;2;3, 5)", "2;0;1;2;3;0;0", NULL},
    {49, "accumulate(1;2;3);accumulate(1;2;3;4, 2)", "1;3;6;1;2;4;6", NULL},
    {50, "product(1;2;3;4, 2);product(null)", "3;8;1", NULL},
    {51, "clamp(-1;5, 0, 3);clamp(nan, 0, 1);clamp(0.5, nan, 1)", "0;3;0;nan", NULL},
    {52, "zip(1;2, 10;20;30)", "1;10;2;20;1;30", NULL},
    {52, "zip(1;2;3, \"a\";\"b\")", "1;'a';2;'b';3;'a'", NULL},
    {53, "max(3, 1;5, 2);max(1;5;3);min(1, \"a\")", "3;5", NULL},
    {54, "min(nan;1);min(1;nan)", "nan;1", NULL},
    {55, "minindex(3;1;2);maxindex(1, 5, 3)", "1;1", NULL},
    {56, "sort(3;1;2)", "1;2;3", NULL},
    {56, "sort(\"b\";\"a\";\"c\")", "'a';'b';'c'", NULL},
    {57, "count(1;2, 1;1;2)", "2;1", NULL},
    {57, "count(\"a\";:a, \"a\";\"a\";:a)", "2;1", NULL},
    {58, "normalize(3;4);normalize(0;0)", "0.6;0.8", NULL},
    {59, "dot(1;2;3, 4;5;6);cross(1;0;0, 0;1;0)", "32;0;0;1", NULL},
    {60, "map(0.25, 10, 20);fract(-0.25);floor(-0.5)", "12.5;0.75;-1", NULL},
    {61, "impulse(0.1);sharkfin(0.25);triangle(0.25)", "0.784;0.707106781;0.5", NULL},
    {62, "square(0.5);sawtooth(1.25);bounce(0.5)", "1;0.25;1", NULL},
    {63, "quad(0.25);cubic(0.75);snap(0.125);linear(2;-1;0.5)", "0.125;0.9375;0.25;1;0;0.5", NULL},
    {64, "hsv(0;1;1);hsv(1/3);hsl(0.5;1;0.5);hsl(1.25;1;0.5)", "1;0;0;0;1;0;0;1;1;0.5;1;0", NULL},
    {65, "colortemp(6503.5)", "1.04233145;0.983839545;1.03543351", NULL},
    {66, "oklch(0.5;0;0)", "0.125033337;0.125006761;0.124909312", NULL},
    {67, "quaternion(0;0;1, 0.25)", "0.707106781;0;0;0.707106781", NULL},
    {67, "qmul(quaternion(0;0;1,0.25), 1;0;0)", "0;1;0", NULL},
    {68, "chr(72;105);ord(\"AB\");chr(ord(\"héllo\")[1..3])", "'Hi';65;66;'él'", NULL},
    {69, "split(\"a,b,,\", \",\");split(\"a\\nb\\n\");concat(1;\"a\";:b)", "'a';'b';'a';'b';'1ab'", NULL},
    {70, "len(\"abc\");len(null);len(1;\"a\";!n)", "1;0;3", NULL},
    {71, "(sin;cos)(0.25)", "1;0", NULL},
    {71, "concat((sin;cos)(0.25))", "'1-0'", NULL},
    {72, "sqrt(4, 5)", "null", NULL},
    {73, "uniform()[0]", NULL, "0.11377270426292592"},
    {74, "uniform(:x)[0;1;2]", NULL, "0.5012199625101028;0.8455173988858942;0.1393270459400855"},
    {75, "uniform(:x)[-1]", NULL, "0.7565468999279326"},
    {76, "uniform(1)[0];uniform(1.5)[0]", NULL, "0.3236437711805903;0.3236437711805903"},
    {77, "uniform(:x;-0.5)[0] == uniform(:x;-1)[0]", "1", NULL},
    {78, "beta(1)[0;1]", NULL, "0.3236437711805903;0.6619503345041775"},
    {79, "normal(1)[0;1]", "-1.50110779;-0.0538430951", NULL},
    {80, "normal()[0;1;2;3]", "1.50032773;1.44779901;1.69169514;0.837380376", NULL},
    {81, "beta(:q)[0;1;2]", "0.475603294;0.515468558;0.314542472", NULL},
    {82, "shuffle(uniform(:a), ..6)", "3;0;1;5;4;2", NULL},
    {83, "uniform(:x)", "null", NULL},
    {83, "len(uniform(:x));(uniform(:x);5)", "0;5", NULL},
    {84, "noise(:s, 0.5);noise(:s, 0.5, 0.25);noise(null, 1.3)", NULL,
     "0.6390421355507776;0.5816501773837107;0.4902465961370626"},
    {85, "noise(:s, 0.3, 0.6, 0.9);noise(:s, 0.3, 0.6, 0.9, 1.2)", "-0.427225357;-0.413527839", NULL},
    {86, "noise(:s, 1;2, 3)", "-0.232062298;-0.0979359928", NULL},
    {87, "octnoise(:s, 3, 0.5, 0.3, 0.7);octnoise(:s, 0, 0.5, 1)", "0.0101296387", NULL},
};

/* Evaluate [expr] in a fresh runtime; return (malloc'd) the debug line or
 * the value text, without the trailing newline. */
static char *evaluate(const char *expr, bool repr)
{
    char *dbg = NULL, *log = NULL;
    size_t dlen, llen;
    FILE *d = open_memstream(&dbg, &dlen), *l = open_memstream(&log, &llen);
    fl_options o = fl_default_options();
    RtStreams streams = {l, d};
    rt_log_to_files(&o, &streams);
    fl_runtime *rt = fl_new(&o);
    Buf out = BUF_INIT, err = BUF_INIT, text = BUF_INIT;
    if (repr) buf_printf(&text, "debug(%s)\n", expr);
    else buf_printf(&text, "%s\n", expr);
    int rc = rt_eval(rt, text.data, text.len, &out, &err);
    fl_free(rt);
    fclose(d);
    fclose(l);
    char *result;
    if (rc != 0) result = strdup(buf_cstr(&err));
    else result = strdup(repr ? dbg : buf_cstr(&out));
    size_t n = strlen(result);
    if (n && result[n - 1] == '\n') result[n - 1] = '\0';
    if (repr && !*result && rc == 0) {   /* debug(null) prints "null" */
        free(result);
        result = strdup("(nothing printed)");
    }
    buf_free(&out);
    buf_free(&err);
    buf_free(&text);
    free(dbg);
    free(log);
    return result;
}

static void test_section7(void **s)
{
    (void)s;
    int failures = 0;
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++) {
        const Vector *v = &vectors[i];
        for (int pass = 0; pass < 2; pass++) {
            const char *want = pass == 0 ? v->repr : v->text;
            if (!want) continue;
            char *got = evaluate(v->expr, pass == 0);
            if (strcmp(got, want) != 0) {
                print_error("§7 #%d %s: %s\n  expected %s\n  got      %s\n", v->number, v->expr,
                            pass == 0 ? "repr" : "value text", want, got);
                failures++;
            }
            free(got);
        }
    }
    assert_int_equal(failures, 0);
}

/* #13 and #14: a syntax error, and an unbound-name warning at load. */
static void test_errors(void **s)
{
    (void)s;
    char *got = evaluate("2**-1", false);
    assert_non_null(strstr(got, "<repl>:1:"));
    assert_non_null(strstr(got, "error"));
    free(got);
    char *log = NULL;
    size_t llen;
    FILE *l = open_memstream(&log, &llen);
    fl_options o = fl_default_options();
    RtStreams streams = {l, stdout};
    rt_log_to_files(&o, &streams);
    fl_runtime *rt = fl_new(&o);
    Buf out = BUF_INIT, err = BUF_INIT;
    const char *src = "x;y where x=1 y=2\n";
    assert_int_equal(rt_eval(rt, src, strlen(src), &out, &err), 0);
    assert_string_equal(buf_cstr(&out), "2\n");
    fl_free(rt);
    fclose(l);
    assert_non_null(strstr(log, "Unbound name 'x'"));
    free(log);
    buf_free(&out);
    buf_free(&err);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_section7),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
